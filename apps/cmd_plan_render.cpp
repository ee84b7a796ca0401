// `floorcast plan render`: draw a plan to PNG or SVG (floorplans/render.hpp).
#include <algorithm>
#include <iostream>
#include <memory>
#include <vector>

#include "cli_common.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/render.hpp"

namespace floorcast::cli {
namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void register_plan_render(CLI::App& root) {
  CLI::App& plan = group(root, "plan", "Floor plans: inspect, validate, import, generate, render");
  auto* cmd = plan.add_subcommand(
      "render", "Draw a plan as PNG or SVG: walls black, glass blue, doors (open: swing arc, closed: orange "
                "leaf), obstacles grey, metre coordinates, scale bar, name");
  struct Options {
    std::string file;
    std::string output;
    std::string format;
    double px_per_m = 0.0;
    double margin_m = 1.5;
    bool no_obstacles = false;
    bool no_interior = false;
    bool no_coordinates = false;
  };
  auto opts = std::make_shared<Options>();
  cmd->add_option("FILE", opts->file, "Floor-plan JSON")->required();
  cmd->add_option("-o,--output", opts->output, "Output image: .png or .svg (- for standard output, with --format)")->required();
  cmd->add_option("--format", opts->format, "Image format when the output's extension does not say it (-o -)")
      ->check(CLI::IsMember({"png", "svg"}));
  CLI::Option* px_opt = cmd->add_option("--px-per-m", opts->px_per_m,
                  "Pixels per metre (default: automatic, the longer side ~2400 px, at most 80 px/m)")
      ->check(in_range(0.1, 1000.0));
  cmd->add_option("--margin-m", opts->margin_m, "Blank border around the plan, metres")->capture_default_str()->check(in_range(0.0, 1000.0));
  cmd->add_flag("--no-obstacles", opts->no_obstacles, "Leave out clutter obstacles");
  cmd->add_flag("--no-interior", opts->no_interior, "Do not tint the building interior");
  cmd->add_flag("--no-coordinates", opts->no_coordinates, "Leave out the metre coordinates along the left and bottom edges");
  cmd->callback([opts, px_opt] {
    const std::string ext = opts->format.empty() ? lower_extension(opts->output) : opts->format;
    if (opts->output == "-" && opts->format.empty()) throw InputError("-o -: give --format png or --format svg");
    if (ext != "png" && ext != "svg") {
      throw InputError(opts->output + ": unsupported image format \"" + ext + "\" (use .png or .svg)");
    }
    const FloorPlan p = load_floor_plan(opts->file);
    prepare_output_file(opts->output);
    RenderOptions ro;
    ro.margin_m = opts->margin_m;
    ro.draw_obstacles = !opts->no_obstacles;
    ro.draw_interior = !opts->no_interior;
    ro.draw_coordinates = !opts->no_coordinates;
    if (px_opt->count() > 0) {  // given: used as is (0 or less is refused), else automatic
      ro.px_per_m = opts->px_per_m;
    } else {
      const Eigen::Vector4d box = drawing_extent_m(p);
      const double extent = std::max({box[2] - box[0], box[3] - box[1], 1.0}) + 2.0 * ro.margin_m;
      ro.px_per_m = std::clamp(std::floor(2400.0 / extent), 4.0, 80.0);
    }
    if (ext == "svg") {
      write_text_file_atomic(opts->output, render_plan_svg(p, ro));
      message_stream(opts->output) << "wrote " << opts->output << " (" << ro.px_per_m << " px/m)\n";
      return;
    }
    const PlanImage img = render_plan(p, ro);
    write_png(opts->output, img.bgr);
    message_stream(opts->output) << "wrote " << opts->output << " (" << img.bgr.cols << " x " << img.bgr.rows << " px, " << ro.px_per_m
              << " px/m)\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_plan_render);
}  // namespace floorcast::cli
