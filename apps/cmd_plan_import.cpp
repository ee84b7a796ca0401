// `floorcast plan import SRC --format F [--level L] [--resolution M_PER_PX] -o plan.json`.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

struct ImportCliOptions {
  std::string source;
  std::string format;
  std::string output;
  std::string level;
  std::string building;
  std::string units;
  double scale = 0.0;
  double column_size_m = ImportOptions{}.default_column_size_m;
  double resolution_m_per_px = 0.0;
  double wall_thickness_m = 0.0;
  std::vector<double> png_origin_m;
  std::string name;
  double snap_tolerance_m = CleanupOptions{}.snap_tolerance_m;
  double angle_tolerance_deg = CleanupOptions{}.angle_tolerance_rad * 180.0 / 3.14159265358979323846;
  double door_width_m = ImportOptions{}.default_door_width_m;
  bool doors_closed = false;
  bool drop_bad_openings = false;
  bool include_outwall = false;
  std::vector<std::string> imdf_open_categories;
  std::vector<std::string> imdf_void_categories;
  std::string crs;
  bool unmapped_as_floor = false;
  bool infer_openings = false;
  bool strict = false;
  bool json = false;
};

void print_report(const ImportResult& r, const std::string& output, std::ostream& out) {
  const CleanupReport& c = r.cleanup;
  const PlanCounts counts = plan_counts(r.plan);
  out << "imported " << r.plan.name;
  if (!r.level_description.empty()) out << " (" << r.level_description << ")";
  out << " -> " << output << "\n";
  out << "source:";
  for (const auto& [what, n] : r.source_counts) out << " " << what << "=" << n;
  out << "\n";
  out << std::fixed << std::setprecision(3);
  out << "cleanup: walls " << c.input_walls << " -> " << c.output_walls << " (dropped degenerate "
            << c.dropped_degenerate_walls << ", merged away " << c.walls_merged_away << ", collinear groups merged "
            << c.collinear_groups_merged << ", duplicate length " << c.duplicate_length_m << " m, gaps closed "
            << c.gaps_closed << ")\n";
  out << "         endpoints snapped " << c.snapped_endpoints << ", onto walls " << c.endpoints_snapped_to_walls
            << "; openings re-attached " << c.openings_reattached << ", merged " << c.openings_merged << ", trimmed "
            << c.openings_trimmed << ", slid " << c.openings_slid << ", narrowed " << c.openings_narrowed
            << ", moved onto the axis " << c.openings_moved_to_axis << ", dropped " << c.openings_dropped << "\n";
  if (!r.repairs.empty()) {
    out << "repairs:";
    for (const auto& [what, n] : r.repairs) out << " " << what << "=" << n;
    out << "\n";
  }
  out << "plan: walls " << counts.walls << ", doors " << counts.doors << " (closed " << counts.doors_closed
            << "), windows " << counts.windows << ", rooms " << r.plan.rooms.size() << "\n";
  if (r.faithfulness.applicable) {
    out << "faithfulness: " << faithfulness_summary(r.faithfulness) << "\n";
    out << "  by kind (free share of the mapped area less walls):";
    for (const KindFaithfulness& k : r.faithfulness.kinds) {
      out << " " << k.kind << " " << std::setprecision(1) << 100.0 * k.free_share << "% of "
                << std::setprecision(0) << k.mapped_area_m2 << " m^2;";
    }
    out << std::setprecision(3) << "\n";
    if (!r.faithfulness.levels_without_spaces.empty()) {
      out << "  levels of the source without spaces:";
      for (const std::string& l : r.faithfulness.levels_without_spaces) out << " " << l << ";";
      out << "\n";
    }
  }
  for (const std::string& n : c.notes) out << "note: " << n << "\n";
  for (const std::string& n : r.notes) out << "note: " << n << "\n";
  for (const std::string& w : r.warnings) out << "warning: " << w << "\n";
}

void register_plan_import(CLI::App& root) {
  CLI::App& plan = group(root, "plan", "Floor plans: inspect, validate, import, generate, render");
  auto o = std::make_shared<ImportCliOptions>();
  auto* cmd = plan.add_subcommand(
      "import", "Import a floor plan from csv (PALMS segments), s3d (Structured3D annotation_3d.json), png "
                "(occupancy image), imdf (IMDF folder), osm (Simple Indoor Tagging XML) or geojson (OSM-derived "
                "GeoJSON); cleans it up and validates it");
  cmd->add_option("SRC", o->source, "Source file (imdf: folder; s3d: annotation_3d.json or its scene folder)")->required();
  cmd->add_option("--format,-f", o->format, "csv | s3d | png | imdf | osm | geojson")->required();
  cmd->add_option("-o,--output", o->output, "Output plan JSON (- for standard output; the report then goes to standard error)")->required();
  cmd->add_option("--level", o->level,
                  "Level to import: imdf ordinal (or level id), osm/geojson level value; csv/s3d/png: the plan's storey number");
  cmd->add_option("--building", o->building,
                  "imdf: building (id or name) whose level --level names by ordinal (archives with several buildings)");
  cmd->add_option("--units", o->units,
                  "csv/s3d: the source's length unit m, cm, mm, ft or in (default: m for csv, mm for s3d); skips the unit check")
      ->check(CLI::IsMember({"m", "cm", "mm", "ft", "in"}));
  cmd->add_option("--scale", o->scale, "csv/s3d: factor applied to the coordinates after --units; skips the unit check")
      ->check(above(0.0, 1e6));
  cmd->add_option("--column-size", o->column_size_m, "osm/geojson: side of columns mapped as nodes (m)")
      ->default_val(o->column_size_m)
      ->check(above(0.0, 10.0));
  cmd->add_option("--resolution", o->resolution_m_per_px, "png: metres per pixel (required for png)")->check(above(0.0, 10.0));
  cmd->add_option("--png-origin", o->png_origin_m, "png: world x y (m) of the image's bottom-left corner (default 0 0)")
      ->expected(2)
      ->check(in_range(-kMaxAbsCoordinateM, kMaxAbsCoordinateM));
  cmd->add_option("--thickness", o->wall_thickness_m,
                  "Wall thickness in metres (default 0.10; s3d 0.02; png measures it)")
      ->check(in_range(PlanLimits{}.min_thickness_m, PlanLimits{}.max_thickness_m));
  cmd->add_option("--name", o->name, "Plan name (default: from the source file name)");
  cmd->add_option("--snap-tolerance", o->snap_tolerance_m, "Clean-up: snap/merge tolerance in metres")
      ->default_val(o->snap_tolerance_m)
      ->check(in_range(0.0, 1.0));
  cmd->add_option("--angle-tolerance", o->angle_tolerance_deg, "Clean-up: collinearity tolerance in degrees")
      ->default_val(o->angle_tolerance_deg)
      ->check(in_range(0.0, 45.0));
  cmd->add_option("--door-width", o->door_width_m, "osm: width of doors without width=* (m)")
      ->default_val(o->door_width_m)
      ->check(in_range(PlanLimits{}.min_opening_width_m, PlanLimits{}.max_opening_width_m));
  cmd->add_flag("--doors-closed", o->doors_closed, "Import doors as closed (default: open)");
  cmd->add_flag("--drop-bad-openings", o->drop_bad_openings,
                "Drop doors/windows that fit on no wall (listed as notes) instead of failing");
  cmd->add_flag("--include-outwall", o->include_outwall, "s3d: also import the exterior (outwall) surfaces");
  cmd->add_option("--imdf-open-category", o->imdf_open_categories,
                  "imdf: unit category whose shared boundaries are open, repeatable (default: walkway)");
  cmd->add_flag("--unmapped-as-floor", o->unmapped_as_floor,
                "imdf/osm/geojson: regions enclosed by walls that no space covers (courtyards, atria) stay free floor "
                "(default: labelled \"unmapped\", not floor)");
  cmd->add_flag("--infer-openings", o->infer_openings,
                "imdf/osm/geojson: give each room without an opening in the source a door on the longest stretch of "
                "wall it shares with a corridor or hall (counted as openings_inferred)");
  cmd->add_flag("--strict", o->strict,
                "Refuse the import when the faithfulness check warns (free floor missing from the mapped spaces, free "
                "floor outside them, sealed spaces)");
  cmd->add_option("--imdf-void-category", o->imdf_void_categories,
                  "imdf: unit category that is no space (a void or building mass: walls around it, not floor), "
                  "repeatable (default: opentobelow column structure brick concrete drywall glass wood)");
  cmd->add_option("--crs", o->crs,
                  "imdf/osm/geojson: coordinate reference system of the positions (e.g. EPSG:32632 for UTM 32N metres); "
                  "overrides a GeoJSON crs member (default: the declared one, else WGS84 longitude/latitude)");
  cmd->add_flag("--json", o->json, "Print the import report as JSON");
  cmd->callback([o, cmd] {
    refuse_output_inside_inputs(o->output, {o->source});
    prepare_output_file(o->output);
    ImportOptions opts;
    if (!o->level.empty()) opts.level = o->level;
    if (!o->building.empty()) opts.building = o->building;
    // Given or not by the option count: an empty --units or --scale 0 is refused, not read as "not given".
    const bool units_given = cmd->count("--units") > 0, scale_given = cmd->count("--scale") > 0;
    if (units_given) opts.units = o->units;
    if (scale_given) opts.scale = o->scale;
    opts.default_column_size_m = o->column_size_m;
    const bool unit_format = o->format == "csv" || o->format == "s3d" || o->format == "structured3d";
    if ((units_given || scale_given) && !unit_format) {
      throw InputError("--units/--scale apply to csv and s3d sources (" + o->format +
                       " has its own units: png --resolution, imdf/osm/geojson their coordinate reference system, see --crs)");
    }
    if (cmd->count("--resolution") > 0) opts.resolution_m_per_px = o->resolution_m_per_px;
    if (cmd->count("--thickness") > 0) opts.wall_thickness_m = o->wall_thickness_m;
    if (o->png_origin_m.size() == 2) opts.png_origin_m = Vec2(o->png_origin_m[0], o->png_origin_m[1]);
    opts.name = o->name;
    opts.cleanup.snap_tolerance_m = o->snap_tolerance_m;
    opts.cleanup.angle_tolerance_rad = o->angle_tolerance_deg * 3.14159265358979323846 / 180.0;
    opts.cleanup.drop_unattachable_openings = o->drop_bad_openings;
    opts.default_door_width_m = o->door_width_m;
    opts.doors_closed = o->doors_closed;
    opts.s3d_include_outwall = o->include_outwall;
    opts.unmapped_is_floor = o->unmapped_as_floor;
    opts.strict = o->strict;
    opts.infer_openings = o->infer_openings;
    if (!o->imdf_open_categories.empty()) opts.imdf_open_unit_categories = o->imdf_open_categories;
    if (!o->imdf_void_categories.empty()) opts.imdf_void_unit_categories = o->imdf_void_categories;
    if (!o->crs.empty()) opts.crs = o->crs;
    const ImportFormat format = parse_import_format(o->format);
    const ImportResult r = import_floor_plan(o->source, format, opts);
    save_floor_plan(r.plan, o->output);
    if (o->json) {
      message_stream(o->output) << import_report_json(r, o->output).dump(2) << "\n";
    } else {
      print_report(r, o->output, message_stream(o->output));
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_plan_import);
}  // namespace floorcast::cli
