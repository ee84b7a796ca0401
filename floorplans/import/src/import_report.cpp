// The import report (`floorcast plan import --report FILE`) from field lists.
#include "floorcast/core/fields.hpp"
#include "floorcast/floorplans/faithfulness.hpp"
#include "floorcast/floorplans/import.hpp"

namespace floorcast {
namespace {

using OJson = nlohmann::ordered_json;

const FieldList<CleanupReport>& cleanup_fields() {
  using C = CleanupReport;
  constexpr int kMany = 1 << 30;
  static const FieldList<C> f =
      FieldList<C>("cleanup")
          .integer("input_walls", &C::input_walls, 0, kMany, "walls read")
          .integer("output_walls", &C::output_walls, 0, kMany, "walls written")
          .integer("dropped_degenerate_walls", &C::dropped_degenerate_walls, 0, kMany, "shorter than min_wall_length_m")
          .integer("snapped_endpoints", &C::snapped_endpoints, 0, kMany, "endpoints moved onto a nearby endpoint")
          .integer("endpoints_snapped_to_walls", &C::endpoints_snapped_to_walls, 0, kMany, "endpoints moved onto a wall")
          .integer("collinear_groups_merged", &C::collinear_groups_merged, 0, kMany, "runs of collinear walls merged")
          .integer("walls_merged_away", &C::walls_merged_away, 0, kMany, "walls absorbed into another")
          .number("duplicate_length_m", &C::duplicate_length_m, 0.0, 1e300, "wall length drawn more than once, m")
          .integer("gaps_closed", &C::gaps_closed, 0, kMany, "gaps closed along a line")
          .integer("openings_reattached", &C::openings_reattached, 0, kMany, "doors/windows moved to a merged wall")
          .integer("openings_merged", &C::openings_merged, 0, kMany, "duplicate doors/windows merged")
          .integer("openings_trimmed", &C::openings_trimmed, 0, kMany, "spans overshooting a wall end, shortened")
          .integer("openings_slid", &C::openings_slid, 0, kMany, "spans overrunning a wall end, slid inside")
          .integer("openings_narrowed", &C::openings_narrowed, 0, kMany, "openings wider than their wall, narrowed")
          .integer("openings_moved_to_axis", &C::openings_moved_to_axis, 0, kMany, "centres moved onto the wall axis")
          .integer("openings_dropped", &C::openings_dropped, 0, kMany, "unattachable openings dropped");
  return f;
}

const FieldList<KindFaithfulness>& kind_faithfulness_fields() {
  using K = KindFaithfulness;
  constexpr int kMany = 1 << 30;
  static const FieldList<K> f = FieldList<K>("faithfulness kind")
                                    .text("kind", &K::kind, "room kind")
                                    .integer("spaces", &K::spaces, 0, kMany, "spaces of the kind")
                                    .number("source_area_m2", &K::source_area_m2, 0.0, 1e300, "their areas as drawn, m^2")
                                    .number("mapped_area_m2", &K::mapped_area_m2, 0.0, 1e300, "their union, m^2")
                                    .number("wall_area_m2", &K::wall_area_m2, 0.0, 1e300, "of the union under walls, m^2")
                                    .number("free_area_m2", &K::free_area_m2, 0.0, 1e300, "free floor in them, m^2")
                                    .number("free_share", &K::free_share, 0.0, 1.0, "free / (mapped - wall)");
  return f;
}

const FieldList<FaithfulnessReport>& faithfulness_fields() {
  using F = FaithfulnessReport;
  constexpr int kMany = 1 << 30;
  static const FieldList<F> f =
      FieldList<F>("faithfulness")
          .flag("applicable", &F::applicable, "the plan has source spaces (else nothing else is written)")
          .number("resolution_m_per_px", &F::resolution_m_per_px, 0.0, 1e300, "raster of the check, m/px")
          .integer("spaces", &F::spaces, 0, kMany, "spaces of the source")
          .number("source_area_m2", &F::source_area_m2, 0.0, 1e300, "the spaces' areas as drawn (nested twice), m^2")
          .number("mapped_area_m2", &F::mapped_area_m2, 0.0, 1e300, "their union, m^2")
          .number("wall_area_m2", &F::wall_area_m2, 0.0, 1e300, "of the union under walls, glass, closed doors, m^2")
          .number("free_area_m2", &F::free_area_m2, 0.0, 1e300, "the plan's free floor, m^2")
          .number("free_in_mapped_m2", &F::free_in_mapped_m2, 0.0, 1e300, "free floor inside the spaces, m^2")
          .number("free_outside_mapped_m2", &F::free_outside_mapped_m2, 0.0, 1e300, "free floor no space covers, m^2")
          .number("free_share", &F::free_share, 0.0, 1.0, "free_in_mapped / (mapped - wall)")
          .number("unmapped_area_m2", &F::unmapped_area_m2, 0.0, 1e300, "enclosed regions no space covers, m^2")
          .integer("unmapped_regions", &F::unmapped_regions, 0, kMany, "their count")
          .list("kinds", &F::kinds, kind_faithfulness_fields())
          .integer("sealed_spaces", &F::sealed_spaces, 0, kMany, "spaces cut off from the main free region")
          .number("sealed_area_m2", &F::sealed_area_m2, 0.0, 1e300, "their area, m^2")
          .texts("sealed_ids", &F::sealed_ids, "their ids")
          .integer("unreachable_spaces", &F::unreachable_spaces, 0, kMany, "spaces outside the main free region")
          .number("unreachable_area_m2", &F::unreachable_area_m2, 0.0, 1e300, "their area, m^2")
          .texts("spaces_outside_free", &F::spaces_outside_free, "spaces less than half free")
          .texts("levels_without_spaces", &F::levels_without_spaces, "levels of the source with no space");
  return f;
}

OJson faithfulness_json(const FaithfulnessReport& f) {
  if (!f.applicable) return OJson{{"applicable", false}};
  return faithfulness_fields().write(f);
}

/// An ImportResult with where it was written (the report's first key).
struct Report {
  const ImportResult* result = nullptr;
  std::string output;
};

OJson counts_object(const std::vector<std::pair<std::string, int>>& counts) {
  OJson o = OJson::object();
  for (const auto& [what, n] : counts) o[what] = n;
  return o;
}

const FieldList<Report>& report_fields() {
  auto no_read = [](ParamReader&, Report&) {};  // the report is written, never read back
  static const FieldList<Report> f =
      FieldList<Report>("import report")
          .text("output", &Report::output, "the plan written")
          .custom("name", [](OJson& j, const Report& r) { j["name"] = r.result->plan.name; }, no_read, "text", "the plan's name")
          .custom("level", [](OJson& j, const Report& r) { j["level"] = r.result->level_description; }, no_read, "text",
                  "which level was imported")
          .custom("source", [](OJson& j, const Report& r) { j["source"] = counts_object(r.result->source_counts); },
                  no_read, "{what: count}", "what was read from the source")
          .custom("cleanup", [](OJson& j, const Report& r) { j["cleanup"] = cleanup_fields().write(r.result->cleanup); },
                  no_read, "object", "what the clean-up did")
          .custom("repairs", [](OJson& j, const Report& r) { j["repairs"] = counts_object(r.result->repairs); }, no_read,
                  "{what: count}", "what the importer repaired or skipped before the clean-up")
          .custom(
              "plan",
              [](OJson& j, const Report& r) {
                const PlanCounts c = plan_counts(r.result->plan);
                j["plan"] = {{"walls", c.walls},
                             {"doors", c.doors},
                             {"doors_closed", c.doors_closed},
                             {"windows", c.windows},
                             {"rooms", r.result->plan.rooms.size()}};
              },
              no_read, "object", "element counts of the plan written")
          .custom(
              "notes",
              [](OJson& j, const Report& r) {
                OJson notes = OJson::array();
                for (const std::string& n : r.result->cleanup.notes) notes.push_back(n);
                for (const std::string& n : r.result->notes) notes.push_back(n);
                j["notes"] = notes;
              },
              no_read, "texts", "one line per element dropped or repaired, with the reason")
          .custom("faithfulness", [](OJson& j, const Report& r) { j["faithfulness"] = faithfulness_json(r.result->faithfulness); },
                  no_read, "object", "the import against its source's spaces (free share per kind, sealed and unreachable spaces)")
          .custom("warnings", [](OJson& j, const Report& r) { j["warnings"] = r.result->warnings; }, no_read, "texts",
                  "faithfulness thresholds exceeded, one line each");
  return f;
}

}  // namespace

nlohmann::ordered_json import_report_json(const ImportResult& result, const std::string& output) {
  return report_fields().write(Report{&result, output});
}

}  // namespace floorcast
