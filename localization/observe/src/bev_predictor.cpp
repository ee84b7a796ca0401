#include "floorcast/observe/bev_predictor.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

constexpr std::uint64_t kStreamView = 0xbe71;
constexpr std::uint64_t kStreamElement = 0xbe72;

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// Mass of a log-normal around range_m (log sigma) in every bin; below the first edge counts to
/// bin 0, beyond the last is lost. sigma 0: all in bin_of(range).
std::vector<double> lognormal_bins(double range_m, double sigma, const BevDepthBins& bins) {
  std::vector<double> m(static_cast<std::size_t>(bins.count), 0.0);
  if (!(range_m > 0.0)) {
    m[0] = 1.0;
    return m;
  }
  if (!(sigma > 1e-9)) {
    const int d = bins.bin_of(range_m);
    if (d >= 0) m[static_cast<std::size_t>(d)] = 1.0;
    return m;
  }
  const double mu = std::log(range_m);
  double below = 0.0;
  for (int d = 0; d < bins.count; ++d) {
    const double hi = normal_cdf((std::log(bins.edge_m(d + 1)) - mu) / sigma);
    m[static_cast<std::size_t>(d)] = hi - below;
    below = hi;
  }
  return m;
}

struct Prediction {
  int cls;           ///< BEV class (semantic set)
  double range_m;    ///< predicted range
  double occluder_m; ///< range beyond which it is unseen, < 0 when seen
};

}  // namespace

const std::vector<std::string>& bev_predictor_presets() {
  static const std::vector<std::string> names = {"perfect", "structured3d_good", "structured3d_bad", "custom_good",
                                                 "custom_bad"};
  return names;
}

BevErrorModel bev_error_preset(const std::string& name) {
  BevErrorModel m;  // structured3d_good
  if (name == "structured3d_good") return m;
  if (name == "perfect") {
    m.depth_sigma_ln = m.depth_sigma_ln_per_m = m.view_scale_sigma_ln = m.element_offset_sigma_ln = 0.0;
    m.window_as_wall = m.wall_as_window = m.door_missed = m.closed_door_as_wall = m.furniture_as_wall = 0.0;
    m.occluded_spread = 0.0;
    m.peak_mass = 1.0;
    m.floor_mass = 0.0;
    return m;
  }
  if (name == "structured3d_bad") {
    // Fig. 5.2: views occluded by furniture, a door not recognised, walls in the wrong scale, a
    // painting seen as a window.
    m.depth_sigma_ln = 0.10;
    m.depth_sigma_ln_per_m = 0.03;
    m.view_scale_sigma_ln = 0.15;
    m.element_offset_sigma_ln = 0.10;
    m.window_as_wall = 0.10;
    m.wall_as_window = 0.05;
    m.door_missed = 0.5;
    m.closed_door_as_wall = 0.5;
    m.furniture_as_wall = 0.6;
    m.occluded_spread = 1.0;
    m.peak_mass = 0.8;
    m.floor_mass = 0.05;
    return m;
  }
  if (name == "custom_good") {
    // Fig. 5.3: real office images, layout and the window behind a window captured, but the
    // custom data's predictions are "more diffuse and less sharp" (sec. 5.1).
    m.depth_sigma_ln = 0.08;
    m.depth_sigma_ln_per_m = 0.02;
    m.view_scale_sigma_ln = 0.08;
    m.element_offset_sigma_ln = 0.05;
    m.window_as_wall = 0.05;
    m.wall_as_window = 0.02;
    m.door_missed = 0.2;
    m.closed_door_as_wall = 0.3;
    m.furniture_as_wall = 0.2;
    m.occluded_spread = 0.7;
    m.peak_mass = 0.8;
    m.floor_mass = 0.05;
    return m;
  }
  if (name == "custom_bad") {
    // Fig. 5.4: likelihood behind closed doors across all classes, likelihood spread over the
    // entire depth with few distinguishable peaks.
    m.depth_sigma_ln = 0.25;
    m.depth_sigma_ln_per_m = 0.05;
    m.view_scale_sigma_ln = 0.20;
    m.element_offset_sigma_ln = 0.15;
    m.window_as_wall = 0.20;
    m.wall_as_window = 0.10;
    m.door_missed = 0.5;
    m.closed_door_as_wall = 0.0;
    m.furniture_as_wall = 0.4;
    m.occluded_spread = 1.0;
    m.peak_mass = 0.6;
    m.floor_mass = 0.30;
    return m;
  }
  std::string known;
  for (const std::string& n : bev_predictor_presets()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("BEV predictor preset \"" + name + "\": unknown (known: " + known + ")");
}

std::vector<float> predict_bev_column(const std::vector<BevColumnElement>& elements, BevClasses classes,
                                      const BevDepthBins& bins, const BevErrorModel& model) {
  // What the network predicts along the ray, nearest first (semantic classes).
  std::vector<Prediction> preds;
  double occluder = -1.0;
  auto add = [&](int cls, double r) { preds.push_back({cls, r, occluder}); };
  for (const BevColumnElement& e : elements) {
    const double r = e.range_m * e.range_factor;
    bool stop = false;
    switch (e.truth) {
      case SemanticClass::kWall:
        add(e.as_window ? kBevWindow : kBevWall, r);
        stop = true;
        break;
      case SemanticClass::kWindow:
        add(e.as_wall ? kBevWall : kBevWindow, r);
        stop = e.as_wall;
        break;
      case SemanticClass::kDoorOpen:
        if (!e.missed) add(kBevDoor, r);
        break;
      case SemanticClass::kDoorClosed:
        if (e.as_wall) {
          add(kBevWall, r);
          stop = true;
          break;
        }
        if (!e.missed) add(kBevDoor, r);
        if (occluder < 0.0) occluder = r;
        break;
      case SemanticClass::kFurniture:
        if (e.as_wall) {
          add(kBevWall, r);
          stop = true;
        } else if (occluder < 0.0) {
          occluder = r;
        }
        break;
    }
    if (stop) break;
  }
  if (classes == BevClasses::kOccupancy) {
    // The no-semantics model: walls and windows one occupied class that stops the ray, no doors.
    std::vector<Prediction> occ;
    for (const Prediction& p : preds) {
      if (p.cls == kBevWall || p.cls == kBevWindow) {
        occ.push_back({kBevOccupied, p.range_m, p.occluder_m});
        break;
      }
    }
    preds = occ;
  }
  const int D = bins.count, C = bev_class_count(classes), empty = bev_empty_class(classes);
  std::vector<double> q(static_cast<std::size_t>(D) * C, 0.0);
  for (const Prediction& p : preds) {
    const bool unseen = p.occluder_m >= 0.0 && p.range_m > p.occluder_m;
    const double spread = unseen ? model.occluded_spread : 0.0;
    const double sigma = model.depth_sigma_ln + model.depth_sigma_ln_per_m * p.range_m;
    const std::vector<double> peak = lognormal_bins(p.range_m, sigma, bins);
    std::vector<double> m(static_cast<std::size_t>(D), 0.0);
    for (int d = 0; d < D; ++d) m[static_cast<std::size_t>(d)] = model.peak_mass * (1.0 - spread) * peak[static_cast<std::size_t>(d)];
    if (spread > 0.0) {
      const int first = bins.bin_of(p.occluder_m) + 1;
      if (first > 0 && first < D) {
        const double each = model.peak_mass * spread / (D - first);
        for (int d = first; d < D; ++d) m[static_cast<std::size_t>(d)] += each;
      }
    }
    // A farther element overwrites its share of a bin (render_bev_column's rule for one-hot masses).
    for (int d = 0; d < D; ++d) {
      const double md = std::min(1.0, m[static_cast<std::size_t>(d)]);
      if (md <= 0.0) continue;
      double* row = q.data() + static_cast<std::size_t>(d) * C;
      for (int c = 0; c < C; ++c) row[c] *= 1.0 - md;
      row[p.cls] += md;
    }
  }
  std::vector<float> out(static_cast<std::size_t>(D) * C);
  for (int d = 0; d < D; ++d) {
    double* row = q.data() + static_cast<std::size_t>(d) * C;
    double total = 0.0;
    for (int c = 0; c < C; ++c) total += c == empty ? 0.0 : row[c];
    row[empty] = std::max(0.0, 1.0 - total);
    for (int c = 0; c < C; ++c) {
      out[static_cast<std::size_t>(d) * C + c] =
          static_cast<float>((1.0 - model.floor_mass) * row[c] + model.floor_mass / C);
    }
  }
  return out;
}

BevPredictionResult predict_bev(const Scan& scan, const BevPredictorParams& params) {
  BevPredictionResult out;
  const BevDepthBins bins = params.bins();
  bins.check("BEV predictor");
  if (!(params.column_step_deg > 0.0) || params.column_step_deg > 180.0) {
    throw InputError("BEV predictor: column_step_deg must be in (0, 180]");
  }
  // Views that can give columns: their own BEV (then only those), else their column semantics.
  std::vector<int> brought, annotated;
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    if (!v.bev.empty()) brought.push_back(static_cast<int>(k));
    if (!v.column_semantics.empty()) annotated.push_back(static_cast<int>(k));
  }
  const bool byo = !brought.empty();
  const std::vector<int>& views = byo ? brought : annotated;
  if (views.empty()) {
    out.warnings.push_back("BEV predictor: no view has a BEV of its own or column semantics (simulate with column "
                           "semantics, or bring view BEVs): no BEV");
    return out;
  }
  if (byo && brought.size() < scan.views.size()) {
    out.warnings.push_back("BEV: " + std::to_string(brought.size()) + " of " + std::to_string(scan.views.size()) +
                           " views bring a BEV; only those are used");
  }
  const BevClasses byo_classes = byo ? scan.views[static_cast<std::size_t>(views.front())].bev.classes : BevClasses::kSemantic;
  for (const int k : views) {
    const BevPrediction& b = scan.views[static_cast<std::size_t>(k)].bev;
    if (byo && (b.classes != byo_classes || !(b.bins == bins))) {
      throw InputError("view " + std::to_string(k) + ": its BEV has another class set or other depth bins than " +
                       "the BEV predictor's (depth_bins " + std::to_string(bins.count) + ", " +
                       std::to_string(bins.min_m) + " .. " + std::to_string(bins.max_m) + " m)");
    }
  }

  // Equiangular columns, each from the seeing view with the nearest heading.
  struct Column {
    double azimuth = 0.0;
    int view = -1;
    double u = 0.0;  ///< image column (annotation) or relative azimuth (own BEV)
  };
  std::vector<Column> columns;
  const int n = std::max(1, static_cast<int>(std::lround(360.0 / params.column_step_deg)));
  std::vector<char> used(scan.views.size(), 0);
  for (int j = 0; j < n; ++j) {
    const double phi = 2.0 * kPi * j / n;
    Column best;
    double best_off = 1e9;
    for (const int k : views) {
      const DepthView& v = scan.views[static_cast<std::size_t>(k)];
      const CameraIntrinsics& K = v.intrinsics;
      const double rel = wrap_angle_rad(phi - view_heading_rad(v));
      const double left = std::atan(K.cx_px / K.fx_px), right = std::atan((K.cx_px - (K.width_px - 1)) / K.fx_px);
      if (rel > left + 1e-9 || rel < right - 1e-9) continue;
      if (std::abs(rel) < best_off) {
        best_off = std::abs(rel);
        best.azimuth = phi;
        best.view = k;
        best.u = byo ? rel : K.cx_px - K.fx_px * std::tan(rel);
      }
    }
    if (best.view >= 0) {
      columns.push_back(best);
      used[static_cast<std::size_t>(best.view)] = 1;
    }
  }
  for (std::size_t k = 0; k < used.size(); ++k) {
    if (used[k]) out.views_used.push_back(static_cast<int>(k));
  }
  if (byo) out.views_brought = out.views_used;
  out.columns = static_cast<int>(columns.size());
  if (columns.empty()) {
    out.warnings.push_back("BEV predictor: no column falls inside a view's field of view: no BEV");
    return out;
  }
  std::vector<double> azimuths;
  for (const Column& c : columns) azimuths.push_back(c.azimuth);

  if (byo) {
    BevPrediction b;
    b.classes = byo_classes;
    b.bins = bins;
    b.column_azimuth_rad = azimuths;
    const int C = b.num_classes(), D = bins.count;
    for (const Column& c : columns) {
      const BevPrediction& src = scan.views[static_cast<std::size_t>(c.view)].bev;
      int w_best = 0;
      for (int w = 1; w < src.num_columns(); ++w) {
        if (std::abs(src.column_azimuth_rad[static_cast<std::size_t>(w)] - c.u) <
            std::abs(src.column_azimuth_rad[static_cast<std::size_t>(w_best)] - c.u)) {
          w_best = w;
        }
      }
      const float* p = src.probabilities.data() + static_cast<std::size_t>(w_best) * D * C;
      b.probabilities.insert(b.probabilities.end(), p, p + static_cast<std::size_t>(D) * C);
    }
    out.bev.push_back(std::move(b));
    return out;
  }

  // The annotation's hits per column, linked into elements across neighbouring columns.
  std::uint64_t key = mix64(params.seed);
  std::vector<const std::vector<SemanticHit>*> hits(columns.size());
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const DepthView& v = scan.views[static_cast<std::size_t>(columns[j].view)];
    const int u = std::clamp(static_cast<int>(std::lround(columns[j].u)), 0, v.intrinsics.width_px - 1);
    hits[j] = &v.column_semantics[static_cast<std::size_t>(u)];
    for (const SemanticHit& h : *hits[j]) {
      std::uint64_t bits;
      std::memcpy(&bits, &h.range_m, sizeof bits);
      key = mix64(key ^ bits ^ (static_cast<std::uint64_t>(h.label) << 56));
    }
  }
  const BevErrorModel& m = params.error;
  std::vector<std::vector<int>> element(columns.size());
  int next_element = 0;
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const bool has_prev = j > 0 && std::abs(wrap_angle_rad(columns[j].azimuth - columns[j - 1].azimuth)) <
                                       1.5 * params.column_step_deg * kPi / 180.0;
    for (const SemanticHit& h : *hits[j]) {
      int id = -1;
      if (has_prev) {
        for (std::size_t i = 0; i < hits[j - 1]->size(); ++i) {
          const SemanticHit& p = (*hits[j - 1])[i];
          if (p.label == h.label && std::abs(p.range_m - h.range_m) <= 0.2 + 0.15 * h.range_m) {
            id = element[j - 1][i];
            break;
          }
        }
      }
      element[j].push_back(id >= 0 ? id : next_element++);
    }
  }
  // Decisions per element and per view.
  std::map<int, double> view_log_scale;
  for (const Column& c : columns) {
    if (!view_log_scale.count(c.view)) {
      view_log_scale[c.view] = m.view_scale_sigma_ln * CounterRng(key, kStreamView, static_cast<std::uint64_t>(c.view)).normal(0);
    }
  }
  struct Draws {
    double u_class, u_missed, offset;
  };
  std::vector<Draws> draws(static_cast<std::size_t>(next_element));
  for (int e = 0; e < next_element; ++e) {
    const CounterRng rng(key, kStreamElement, static_cast<std::uint64_t>(e));
    draws[static_cast<std::size_t>(e)] = {rng.uniform(0), rng.uniform(1), m.element_offset_sigma_ln * rng.normal(2)};
  }
  std::map<int, SemanticClass> element_class;
  for (std::size_t j = 0; j < columns.size(); ++j) {
    for (std::size_t i = 0; i < hits[j]->size(); ++i) element_class[element[j][i]] = (*hits[j])[i].label;
  }
  for (const auto& [e, cls] : element_class) {
    const Draws& d = draws[static_cast<std::size_t>(e)];
    switch (cls) {
      case SemanticClass::kWall: out.events["wall_as_window"] += d.u_class < m.wall_as_window; break;
      case SemanticClass::kWindow: out.events["window_as_wall"] += d.u_class < m.window_as_wall; break;
      case SemanticClass::kDoorOpen: out.events["door_missed"] += d.u_missed < m.door_missed; break;
      case SemanticClass::kDoorClosed:
        out.events["closed_door_as_wall"] += d.u_class < m.closed_door_as_wall;
        out.events["door_missed"] += d.u_class >= m.closed_door_as_wall && d.u_missed < m.door_missed;
        break;
      case SemanticClass::kFurniture: out.events["furniture_as_wall"] += d.u_class < m.furniture_as_wall; break;
    }
    out.events["elements"] += 1;
  }

  for (const BevClasses classes : {BevClasses::kSemantic, BevClasses::kOccupancy}) {
    BevPrediction b;
    b.classes = classes;
    b.bins = bins;
    b.column_azimuth_rad = azimuths;
    for (std::size_t j = 0; j < columns.size(); ++j) {
      std::vector<BevColumnElement> els;
      for (std::size_t i = 0; i < hits[j]->size(); ++i) {
        const SemanticHit& h = (*hits[j])[i];
        const Draws& d = draws[static_cast<std::size_t>(element[j][i])];
        BevColumnElement e;
        e.truth = h.label;
        e.range_m = h.range_m;
        e.range_factor = std::exp(view_log_scale[columns[j].view] + d.offset);
        switch (h.label) {
          case SemanticClass::kWall: e.as_window = d.u_class < m.wall_as_window; break;
          case SemanticClass::kWindow: e.as_wall = d.u_class < m.window_as_wall; break;
          case SemanticClass::kDoorOpen: e.missed = d.u_missed < m.door_missed; break;
          case SemanticClass::kDoorClosed:
            e.as_wall = d.u_class < m.closed_door_as_wall;
            e.missed = d.u_missed < m.door_missed;
            break;
          case SemanticClass::kFurniture: e.as_wall = d.u_class < m.furniture_as_wall; break;
        }
        els.push_back(e);
      }
      const std::vector<float> col = predict_bev_column(els, classes, bins, m);
      b.probabilities.insert(b.probabilities.end(), col.begin(), col.end());
    }
    out.bev.push_back(std::move(b));
  }
  return out;
}

}  // namespace floorcast
