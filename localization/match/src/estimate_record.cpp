#include "floorcast/match/estimate_record.hpp"

#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {

using OJson = nlohmann::ordered_json;
constexpr double kAny = 1e300;

const FieldList<HypothesisRecord>& hypothesis_fields() {
  using H = HypothesisRecord;
  static const FieldList<H> f = FieldList<H>("hypothesis")
                                    .number("x_m", &H::x_m, -kAny, kAny, "world x, m")
                                    .number("y_m", &H::y_m, -kAny, kAny, "world y, m")
                                    .number("yaw_deg", &H::yaw_deg, -kAny, kAny, "heading, deg (counter-clockwise from +x)")
                                    .number("score", &H::score, -kAny, kAny, "the matcher's score (higher is better)");
  return f;
}

/// A number, or null when absent.
OJson number_or_null(const std::optional<double>& v) { return v ? OJson(*v) : OJson(nullptr); }

}  // namespace

HypothesisRecord hypothesis_record(const PoseHypothesis& h) { return {h.x_m, h.y_m, h.yaw_rad * 180.0 / kPi, h.score}; }

const FieldList<EstimateRecord>& estimate_record_fields() {
  using E = EstimateRecord;
  auto best_part = [](const char* key, double HypothesisRecord::*m) {
    return std::make_pair(
        [key, m](OJson& j, const E& e) {
          j[key] = number_or_null(e.best ? std::optional<double>((*e.best).*m) : std::nullopt);
        },
        [key, m](ParamReader& r, E& e) {
          nlohmann::json v;
          r.read(key, v);
          if (v.is_null()) return;
          if (!v.is_number()) r.fail(key, "expected a number or null");
          if (!e.best) e.best = HypothesisRecord{};
          (*e.best).*m = v.get<double>();
        });
  };
  const auto x = best_part("x_m", &HypothesisRecord::x_m);
  const auto y = best_part("y_m", &HypothesisRecord::y_m);
  const auto yaw = best_part("yaw_deg", &HypothesisRecord::yaw_deg);
  static const FieldList<E> timings =
      FieldList<E>("timings")
          .number("precompute_s", &E::precompute_s, 0.0, kAny, "the matcher's per-plan precomputation, s")
          .number("match_s", &E::match_s, 0.0, kAny, "the match, wall s")
          .custom(
              "stages_s", [](OJson& j, const E& e) {
                OJson stages;  // null without stages (as estimate.json always had it)
                for (const auto& [k, v] : e.stages_s) stages[k] = v;
                j["stages_s"] = stages;
              },
              [](ParamReader& r, E& e) {
                nlohmann::json stages;
                r.read("stages_s", stages);
                for (auto it = stages.begin(); it != stages.end(); ++it) e.stages_s[it.key()] = it.value().get<double>();
              },
              "{stage: s}", "named stages of the match (CPU s where several threads ran)");
  static const FieldList<GridSpec> grid =
      FieldList<GridSpec>("grid")
          .custom(
              "origin_m", [](OJson& j, const GridSpec& g) { j["origin_m"] = {g.origin_x_m, g.origin_y_m}; },
              [](ParamReader& r, GridSpec& g) {
                std::vector<double> v;
                r.read("origin_m", v, -kAny, kAny);
                if (v.size() != 2) r.fail("origin_m", "expected [x, y]");
                g.origin_x_m = v[0];
                g.origin_y_m = v[1];
              },
              "[x, y]", "world position of the grid's corner, m")
          .number("resolution_m", &GridSpec::resolution_m_per_px, 0.0, kAny, "cell size, m")
          .custom(
              "size_px", [](OJson& j, const GridSpec& g) { j["size_px"] = {g.width_px, g.height_px}; },
              [](ParamReader& r, GridSpec& g) {
                std::vector<double> v;
                r.read("size_px", v, 0.0, 1e9);
                if (v.size() != 2) r.fail("size_px", "expected [width, height]");
                g.width_px = static_cast<int>(v[0]);
                g.height_px = static_cast<int>(v[1]);
              },
              "[width, height]", "cells");
  static const FieldList<E> grid_and_slices =
      FieldList<E>("grid").flatten(&E::grid, grid).custom(
          "slices", [](OJson& j, const E& e) { j["slices"] = e.slices ? OJson(*e.slices) : OJson(nullptr); },
          [](ParamReader& r, E& e) {
            nlohmann::json v;
            r.read("slices", v);
            if (v.is_number_integer()) e.slices = v.get<int>();
          },
          "integer or null", "orientation slices of the full posterior (null: only the modes and the heatmap computed)");
  static const FieldList<E> f =
      FieldList<E>("estimate")
          .text("status", &E::status, "ok, or \"not localized (no pose): \" and why")
          .custom("x_m", x.first, x.second, "number or null", "estimated world x, m (null: no pose)")
          .custom("y_m", y.first, y.second, "number or null", "estimated world y, m")
          .custom("yaw_deg", yaw.first, yaw.second, "number or null", "estimated heading, deg")
          .number("score", &E::score, -kAny, kAny, "the best score (0: empty posterior)")
          .list("top_k", &E::top_k, hypothesis_fields())
          .custom(
              "ground_truth",
              [](OJson& j, const E& e) {
                if (!e.ground_truth) return;
                OJson g = hypothesis_fields().write(*e.ground_truth);
                g.erase("score");
                j["ground_truth"] = g;
              },
              [](ParamReader& r, E& e) {
                if (!r.optional("ground_truth")) return;
                nlohmann::json g;
                r.read("ground_truth", g);
                HypothesisRecord h;
                h.x_m = g.at("x_m").get<double>();
                h.y_m = g.at("y_m").get<double>();
                h.yaw_deg = g.at("yaw_deg").get<double>();
                e.ground_truth = h;
              },
              "{x_m, y_m, yaw_deg}", "the true pose, when the observation knows it")
          .custom(
              "position_error_m", [](OJson& j, const E& e) { if (e.position_error_m) j["position_error_m"] = *e.position_error_m; },
              [](ParamReader& r, E& e) {
                if (!r.optional("position_error_m")) return;
                double v = 0.0;
                r.read("position_error_m", v, 0.0, kAny);
                e.position_error_m = v;
              },
              "number", "distance of the estimate to the truth, m")
          .custom(
              "yaw_error_deg", [](OJson& j, const E& e) { if (e.yaw_error_deg) j["yaw_error_deg"] = *e.yaw_error_deg; },
              [](ParamReader& r, E& e) {
                if (!r.optional("yaw_error_deg")) return;
                double v = 0.0;
                r.read("yaw_error_deg", v, 0.0, 180.0);
                e.yaw_error_deg = v;
              },
              "number", "heading error, deg")
          .custom(
              "counters",
              [](OJson& j, const E& e) {
                OJson c = OJson::object();
                for (const auto& [k, v] : e.counters) c[k] = v;
                j["counters"] = c;
              },
              [](ParamReader& r, E& e) {
                nlohmann::json c;
                r.read("counters", c);
                if (!c.is_object()) r.fail("counters", "expected an object of numbers");
                for (auto it = c.begin(); it != c.end(); ++it) {
                  if (!it.value().is_number()) r.fail("counters." + it.key(), "expected a number");
                  e.counters[it.key()] = it.value().get<double>();
                }
              },
              "{name: number}", "the matcher's counters (planes: hypotheses, triplets, abstained, ...)")
          .optional([](const E&) { return true; })
          .section("timings", [](auto& e) -> auto& { return e; }, timings)
          .text("matcher", &E::matcher, "the matcher's registry name")
          .json("parameters", &E::parameters, "every matcher parameter with its value")
          .number("precompute_mb", &E::precompute_mb, 0.0, kAny, "memory of the per-plan precomputation, MB")
          .text("plan", &E::plan, "the plan file")
          .text("observation", &E::observation, "the observation given")
          .text("observation_input", &E::observation_input, "what it was: observation JSON or a scan folder")
          .unsigned_integer("observation_segments", &E::observation_segments, "observed wall segments")
          .unsigned_integer("observation_planes", &E::observation_planes, "3D plane patches of the observation")
          .optional([](const E&) { return true; })
          .texts("notes", &E::notes, "what the command did that the user should know")
          .optional([](const E& e) { return !e.notes.empty(); })
          .section("grid", [](auto& e) -> auto& { return e; }, grid_and_slices)
          .text("posterior_output", &E::posterior_output, "what was written of the volume: none, npy, npz-f16, top-k");
  return f;
}

PosteriorGridRecord posterior_grid_record(const Posterior& posterior, const std::string& matcher) {
  PosteriorGridRecord g;
  g.slices = posterior.num_slices();
  g.grid = posterior.grid;
  for (double y : posterior.yaw_rad) g.yaw_deg.push_back(y * 180.0 / kPi);
  g.matcher = matcher;
  return g;
}

const FieldList<PosteriorGridRecord>& posterior_grid_record_fields() {
  using G = PosteriorGridRecord;
  auto constant = [](const char* key, OJson value) {
    return std::make_pair([key, value](OJson& j, const G&) { j[key] = value; }, [key](ParamReader& r, G&) {
      nlohmann::json v;
      r.read(key, v);
    });
  };
  const auto axes = constant("axes", {"yaw", "y", "x"});
  const auto centre = constant("cell_centre",
                               "posterior[s, row, col] is the observer at x = origin_m[0] + (col + 0.5) * resolution_m, "
                               "y = origin_m[1] + (row + 0.5) * resolution_m (row 0 = lowest y), heading yaw_deg[s]");
  const auto values = constant("values", "unnormalised scores >= 0, higher is better; all zero = no pose");
  static const FieldList<G> f =
      FieldList<G>("posterior grid")
          .text("file", &G::file, "the numpy file")
          .custom("axes", axes.first, axes.second, "[yaw, y, x]", "axes of the array")
          .custom(
              "shape", [](OJson& j, const G& g) { j["shape"] = {g.slices, g.grid.height_px, g.grid.width_px}; },
              [](ParamReader& r, G& g) {
                std::vector<double> v;
                r.read("shape", v, 0.0, 1e9);
                if (v.size() != 3) r.fail("shape", "expected [slices, rows, columns]");
                g.slices = static_cast<int>(v[0]);
                g.grid.height_px = static_cast<int>(v[1]);
                g.grid.width_px = static_cast<int>(v[2]);
              },
              "[slices, rows, columns]", "the array's shape")
          .text("dtype", &G::dtype, "float32, or float16 (npz-f16)")
          .text("top_k", &G::top_k, "top-k: what the arrays of posterior_top.npz hold")
          .optional([](const G& g) { return !g.top_k.empty(); })
          .custom(
              "origin_m", [](OJson& j, const G& g) { j["origin_m"] = {g.grid.origin_x_m, g.grid.origin_y_m}; },
              [](ParamReader& r, G& g) {
                std::vector<double> v;
                r.read("origin_m", v, -kAny, kAny);
                if (v.size() != 2) r.fail("origin_m", "expected [x, y]");
                g.grid.origin_x_m = v[0];
                g.grid.origin_y_m = v[1];
              },
              "[x, y]", "world position of cell (0, 0)'s corner, m")
          .number("resolution_m", [](auto& g) -> auto& { return g.grid.resolution_m_per_px; }, 0.0, kAny, "cell size, m")
          .series("yaw_deg", &G::yaw_deg, "heading of each slice, deg")
          .custom("cell_centre", centre.first, centre.second, "text", "how an index maps to a pose")
          .custom("values", values.first, values.second, "text", "what the values mean")
          .text("matcher", &G::matcher, "the matcher's registry name");
  return f;
}

}  // namespace floorcast
