// `floorcast plan generate`: procedural buildings (floorplans/generate.hpp).
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

void register_plan_generate(CLI::App& root) {
  CLI::App& plan = group(root, "plan", "Floor plans: inspect, validate, import, generate, render");
  auto* cmd = plan.add_subcommand(
      "generate",
      "Generate a building of an archetype (apartment, office, campus, angled: calibrated on real plans; "
      "office_repetitive, campus_repetitive, angled_repetitive: the hard case of identical rooms); the same seed "
      "always gives the same file");
  struct Options {
    std::string archetype;
    std::uint64_t seed = 1;
    std::string output;
    std::string rooms;
    std::string campus_layout;
    std::string campus_halls;
    bool no_furniture = false;
    double wall_thickness_m = 0.0;
  };
  auto opts = std::make_shared<Options>();
  cmd->add_option("--archetype,-a", opts->archetype, "apartment | office | campus | angled | office_repetitive | campus_repetitive | angled_repetitive")->required();
  cmd->add_option("--seed,-s", opts->seed, "Random seed (non-negative integer)")->capture_default_str();
  cmd->add_option("-o,--output", opts->output, "Output plan JSON (- for standard output)")->required();
  cmd->add_option("--rooms", opts->rooms,
                  "Also write the rooms (id, kind, polygon) as JSON to this file (for labelling and sampling)");
  cmd->add_option("--campus-layout", opts->campus_layout,
                  "campus only: blocks (parallel hallways, back-to-back inner blocks) | spine (one long corridor with "
                  "side wings, the large real teaching building's layout); default: the archetype's (CampusParams)")
      ->check(CLI::IsMember({"blocks", "spine"}));
  cmd->add_option("--campus-halls", opts->campus_halls,
                  "campus, spine layout only: varied (outlines and doors as measured on the large real teaching "
                  "building's halls, CampusParams::HallVariety) | orthogonal (the same without chamfered corners: "
                  "every side on the building's axes, the halls before chamfers) | plain (rectangles with two double "
                  "doors, the spine campus before that); default: varied")
      ->check(CLI::IsMember({"plain", "orthogonal", "varied"}));
  cmd->add_flag("--no-furniture", opts->no_furniture,
                "The same building with every obstacle (furniture, seating, stair flights, pillars) left out: e.g. to "
                "compare with imported real plans, which map none (BuildingStyle::furniture = false instead would "
                "draw a different building: furnishing draws random numbers)");
  cmd->add_option("--wall-thickness", opts->wall_thickness_m,
                  "Draw every wall (glass included) this many metres thick, as imports of sources that map no "
                  "thickness draw theirs (0.1 m): the same rooms, doors and windows, to compare like for like with "
                  "imported real plans; default: the archetype's thicknesses (BuildingStyle)")
      ->check(CLI::Range(0.01, 1.0));
  cmd->callback([opts] {
    const Archetype archetype = parse_archetype(opts->archetype);
    if (!opts->campus_layout.empty() && archetype != Archetype::kCampus) {
      throw InputError("--campus-layout applies to the campus archetype only (got " + opts->archetype + ")");
    }
    if (!opts->campus_halls.empty() && (archetype != Archetype::kCampus || opts->campus_layout == "blocks")) {
      throw InputError("--campus-halls applies to the campus archetype's spine layout only (got " + opts->archetype +
                       (opts->campus_layout.empty() ? "" : ", --campus-layout " + opts->campus_layout) + ")");
    }
    check_distinct_outputs({opts->output, opts->rooms});
    prepare_output_file(opts->output);
    if (!opts->rooms.empty()) prepare_output_file(opts->rooms);
    ArchetypeOverrides overrides;
    if (!opts->campus_layout.empty()) {
      overrides.campus_layout = opts->campus_layout == "spine" ? CampusLayout::kSpine : CampusLayout::kBlocks;
    }
    if (!opts->campus_halls.empty()) {
      overrides.campus_hall_variety = opts->campus_halls != "plain";
      overrides.campus_hall_chamfers = opts->campus_halls == "varied";
    }
    GeneratedBuilding b = generate_building(archetype, opts->seed, overrides);
    if (opts->no_furniture) b.plan.obstacles.clear();
    if (opts->wall_thickness_m > 0.0) {
      for (Wall& w : b.plan.walls) w.thickness_m = opts->wall_thickness_m;
    }
    save_floor_plan(b.plan, opts->output);
    if (!opts->rooms.empty()) {
      nlohmann::ordered_json j;
      j["plan"] = b.plan.name;
      j["archetype"] = archetype_name(archetype);
      j["seed"] = opts->seed;
      nlohmann::ordered_json rooms = nlohmann::ordered_json::array();
      for (const GeneratedRoom& r : b.rooms) {
        nlohmann::ordered_json room;
        room["id"] = r.id;
        room["kind"] = r.kind;
        nlohmann::ordered_json poly = nlohmann::ordered_json::array();
        for (const Vec2& p : r.polygon_m) poly.push_back({p.x(), p.y()});
        room["polygon"] = std::move(poly);
        rooms.push_back(std::move(room));
      }
      j["rooms"] = std::move(rooms);
      write_json(opts->rooms, j);
    }
    const PlanCounts c = plan_counts(b.plan);
    message_stream(opts->output == "-" ? opts->output : opts->rooms) << "wrote " << opts->output << ": " << archetype_name(archetype) << " (seed " << opts->seed << "), "
              << b.rooms.size() << " rooms, " << c.walls << " walls (" << c.glass_walls << " glass), " << c.doors
              << " doors (" << c.doors_closed << " closed), " << c.windows << " windows, " << c.obstacles
              << " obstacles\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_plan_generate);
}  // namespace floorcast::cli
