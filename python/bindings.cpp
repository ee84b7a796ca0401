// Python bindings of floorcast (pybind11 + numpy): load or generate a plan, simulate a scan (with
// colour views), bring your own depth, observe, run any matcher and get the posterior as a numpy
// array and the estimate as a dict, run a scenario. Arrays are copied in and out (no aliasing of
// C++ memory). Images: depth float32 (H, W) metres; colour uint8 (H, W, 3) in RGB order (numpy,
// PIL, matplotlib); masks uint8 (H, W).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>
#include <memory>
#include <nlohmann/json.hpp>
#include <map>
#include <optional>

#include "floorcast/scenarios/driver.hpp"
#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/render.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/external.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/scenarios/scenario.hpp"
#include "floorcast/scenarios/walk_tracking.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/sim/walk_io.hpp"
#include "floorcast/sim/walk_sim.hpp"
#include "floorcast/track/tracker.hpp"

namespace py = pybind11;
using floorcast::InputError;

namespace floorcast {
namespace {

// ---- JSON <-> Python (through the json module: exact, no hand-written walker) ----
py::object to_python(const nlohmann::ordered_json& j) { return py::module_::import("json").attr("loads")(j.dump()); }
nlohmann::json from_python(const py::object& o) {
  if (o.is_none()) return nlohmann::json::object();
  const std::string text = py::module_::import("json").attr("dumps")(o).cast<std::string>();
  return nlohmann::json::parse(text);
}

// ---- cv::Mat <-> numpy (copies) ----
py::array mat_to_array(const cv::Mat& m, bool bgr_to_rgb = false) {
  if (m.empty()) return py::array();
  std::vector<py::ssize_t> shape{m.rows, m.cols};
  if (m.channels() > 1) shape.push_back(m.channels());
  py::array out;
  switch (m.depth()) {
    case CV_8U: out = py::array(py::dtype::of<std::uint8_t>(), shape); break;
    case CV_16U: out = py::array(py::dtype::of<std::uint16_t>(), shape); break;
    case CV_32F: out = py::array(py::dtype::of<float>(), shape); break;
    case CV_64F: out = py::array(py::dtype::of<double>(), shape); break;
    default: throw InputError("cannot convert an image of OpenCV type " + std::to_string(m.type()) + " to numpy");
  }
  const std::size_t row = static_cast<std::size_t>(m.cols) * m.elemSize();
  auto* dst = static_cast<std::uint8_t*>(out.mutable_data());
  for (int r = 0; r < m.rows; ++r) std::memcpy(dst + r * row, m.ptr(r), row);
  if (bgr_to_rgb && m.channels() == 3) {
    for (std::size_t i = 0; i < m.total(); ++i) std::swap(dst[3 * i], dst[3 * i + 2]);
  }
  return out;
}

/// A numpy view of an image's own pixels (no copy): edits change the image. The view keeps the
/// pixels alive (a cv::Mat header sharing them) even when the image is later replaced. Colour
/// images are stored BGR; rgb_order gives an RGB view of them (negative channel stride).
py::array mat_view(const cv::Mat& m, bool rgb_order = false) {
  if (m.empty()) return py::array();
  py::dtype dt;
  switch (m.depth()) {
    case CV_8U: dt = py::dtype::of<std::uint8_t>(); break;
    case CV_16U: dt = py::dtype::of<std::uint16_t>(); break;
    case CV_32F: dt = py::dtype::of<float>(); break;
    case CV_64F: dt = py::dtype::of<double>(); break;
    default: throw InputError("cannot view an image of OpenCV type " + std::to_string(m.type()) + " from numpy");
  }
  auto* keep = new cv::Mat(m);
  py::capsule base(keep, [](void* p) { delete static_cast<cv::Mat*>(p); });
  const auto e = static_cast<py::ssize_t>(m.elemSize1());
  std::vector<py::ssize_t> shape{m.rows, m.cols}, strides{static_cast<py::ssize_t>(m.step[0]), static_cast<py::ssize_t>(m.elemSize())};
  std::uint8_t* data = keep->data;
  if (m.channels() > 1) {
    shape.push_back(m.channels());
    strides.push_back(e);
    if (rgb_order && m.channels() == 3) {
      data += 2 * e;
      strides.back() = -e;
    }
  }
  return py::array(dt, shape, strides, data, base);
}

/// A read-only copy: in-place edits raise instead of being lost.
py::array read_only(py::array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

cv::Mat array_to_mat(const py::array& a, const std::string& what, int want_depth, int want_channels, bool rgb_to_bgr = false) {
  py::array c;
  if (want_depth == CV_32F) c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  else if (want_depth == CV_8U) c = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!c) throw InputError(what + ": cannot convert to a numeric array");
  const int nd = static_cast<int>(c.ndim());
  const int channels = nd == 3 ? static_cast<int>(c.shape(2)) : 1;
  if ((nd != 2 && nd != 3) || channels != want_channels) {
    throw InputError(what + ": expected shape (H, W" + (want_channels > 1 ? ", " + std::to_string(want_channels) : std::string()) + ")");
  }
  cv::Mat m(static_cast<int>(c.shape(0)), static_cast<int>(c.shape(1)), CV_MAKETYPE(want_depth, channels));
  std::memcpy(m.data, c.data(), m.total() * m.elemSize());
  if (rgb_to_bgr && channels == 3)
    for (std::size_t i = 0; i < m.total(); ++i) std::swap(m.data[3 * i], m.data[3 * i + 2]);
  return m;
}

py::array matrix4(const Eigen::Isometry3d& T) {
  py::array_t<double> out({4, 4});
  auto v = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v(r, c) = T.matrix()(r, c);
  return out;
}

Eigen::Isometry3d isometry(const py::array& a) {
  const auto m = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!m || m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4) throw InputError("T_scan_camera: expected a 4x4 array");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = m.at(r, c);
  Eigen::Isometry3d T;
  T.matrix() = M;
  return T;
}

Pose2 pose_from(const py::object& o) {
  const auto v = o.cast<std::vector<double>>();
  if (v.size() != 3) throw InputError("pose: expected (x_m, y_m, yaw_deg)");
  return {v[0], v[1], v[2] * kPi / 180.0};
}

py::dict pose_dict(const Pose2& p) {
  py::dict d;
  d["x_m"] = p.x_m;
  d["y_m"] = p.y_m;
  d["yaw_deg"] = p.yaw_rad * 180.0 / kPi;
  return d;
}

// ---- Python-side objects ----
struct PyPlan {
  FloorPlan plan;
  std::string source;
};

struct PyScan {
  Scan scan;
  std::optional<ScanTruth> truth;
};

struct PyObservation {
  ObservationRecord record;
  nlohmann::ordered_json diagnostics;
};

struct PyWalk {
  WalkRecord record;
  std::string dir;
};

struct PyTrack {
  WalkTrack track;
  std::string tracker, matcher, failure;
  nlohmann::ordered_json tracker_parameters, matcher_parameters, metrics;
  std::vector<Pose2> truth;  ///< per track step
};

/// A column of per-step values as a numpy array.
template <class T>
py::array_t<T> column(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
  return a;
}

/// Poses as float64 (N, 3): x_m, y_m, yaw_deg.
py::array_t<double> poses_array(const std::vector<Pose2>& poses) {
  py::array_t<double> a({static_cast<py::ssize_t>(poses.size()), py::ssize_t{3}});
  auto v = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    v(i, 0) = poses[i].x_m;
    v(i, 1) = poses[i].y_m;
    v(i, 2) = rad_to_deg(poses[i].yaw_rad);
  }
  return a;
}

struct PyMatch {
  Posterior posterior;
  PoseHypothesis best;
  std::vector<PoseHypothesis> top_k;
  double match_s = 0.0;
  double precompute_s = 0.0;
  nlohmann::ordered_json parameters;
  std::string matcher;
  std::optional<Pose2> truth;
  bool found = false;
  std::map<std::string, double> counters;
};

py::dict hypothesis_dict(const PoseHypothesis& h, const std::optional<Pose2>& truth) {
  py::dict d;
  d["x_m"] = h.x_m;
  d["y_m"] = h.y_m;
  d["yaw_deg"] = h.yaw_rad * 180.0 / kPi;
  d["score"] = h.score;
  if (truth) {
    d["position_error_m"] = std::hypot(h.x_m - truth->x_m, h.y_m - truth->y_m);
    d["yaw_error_deg"] = angle_distance_rad(h.yaw_rad, truth->yaw_rad) * 180.0 / kPi;
  }
  return d;
}

py::dict grid_dict(const GridSpec& g, const std::vector<double>& yaw_rad) {
  py::dict d;
  // The keys of the external-matcher protocol (match/external.hpp), then conveniences.
  d["origin_x_m"] = g.origin_x_m;
  d["origin_y_m"] = g.origin_y_m;
  d["width_px"] = g.width_px;
  d["height_px"] = g.height_px;
  d["origin_m"] = py::make_tuple(g.origin_x_m, g.origin_y_m);
  d["resolution_m"] = g.resolution_m_per_px;
  d["shape"] = py::make_tuple(static_cast<int>(yaw_rad.size()), g.height_px, g.width_px);
  d["axes"] = py::make_tuple("yaw", "y", "x");
  d["cell_centre"] = "x = origin_x + (col + 0.5) * resolution, y = origin_y + (row + 0.5) * resolution";
  std::vector<double> deg;
  for (double y : yaw_rad) deg.push_back(y * 180.0 / kPi);
  d["yaw_deg"] = deg;
  return d;
}

struct PyBuiltMatcher {
  std::shared_ptr<const Matcher> matcher;
};

/// One observation through a built matcher: the full posterior, its argmax and top-K modes.
PyMatch match_once(const Matcher& matcher, const PyObservation& obs, int top_k) {
  PyMatch r;
  {
    py::gil_scoped_release release;
    MatchRequest request;
    request.top_k = std::max(1, top_k);
    MatchResult res;
    try {
      res = matcher.match(obs.record.observation, request);
    } catch (const ExternalMethodError& e) {
      throw InputError(e.what());
    }
    // The matcher's own modes: the posterior's top-K for the kernel and ray matchers, refined
    // transforms for the plane matcher; none = not localized.
    r.found = res.has_pose();
    r.counters = res.counters;
    r.posterior = std::move(res.posterior);
    r.top_k = std::move(res.modes);
    r.match_s = res.match_s;
    r.precompute_s = matcher.precompute_s();
    r.parameters = matcher.parameters();
    r.matcher = matcher.name();
  }
  r.best = r.top_k.empty() ? PoseHypothesis{} : r.top_k.front();
  r.truth = obs.record.T_world_observer;
  return r;
}

GridSpec grid_from_dict(const py::dict& d) {
  const nlohmann::json j = from_python(d);
  GridSpec g;
  try {
    g.origin_x_m = j.at("origin_x_m").get<double>();
    g.origin_y_m = j.at("origin_y_m").get<double>();
    g.resolution_m_per_px = j.at("resolution_m").get<double>();
    g.width_px = j.at("width_px").get<int>();
    g.height_px = j.at("height_px").get<int>();
  } catch (const nlohmann::json::exception&) {
    throw InputError("grid: expected a dict with origin_x_m, origin_y_m, resolution_m, width_px, height_px (posterior_grid())");
  }
  if (!(g.resolution_m_per_px > 0.0) || g.width_px < 1 || g.height_px < 1) throw InputError("grid: empty or without resolution");
  check_raster_budget(g, kPlanRasterBytesPerCell, "plan rasters");
  return g;
}

// ---- own methods: matchers written in Python, registered under a name ----

/// What floorcast.register_matcher got. Python objects are released with the GIL held, and not at
/// all once the interpreter is finalising (the registry is cleared at exit, see __init__.py).
struct PyMethod {
  std::string name;
  py::object prepare, match;
  nlohmann::json defaults = nlohmann::json::object();  ///< the method's own parameters
  PosteriorGridParams grid;                            ///< the shared grid's defaults
  std::string version;
  ~PyMethod() {
    if (!Py_IsInitialized()) {
      (void)prepare.release();
      (void)match.release();
      return;
    }
    py::gil_scoped_acquire gil;
    prepare = py::object();
    match = py::object();
  }
};

std::string python_error(const std::string& who, py::error_already_set& e) {
  std::string text = e.what();
  return who + ": " + text;
}

ExternalMatchOutput output_from_python(const py::object& r, const PosteriorGrid& grid, const std::string& who) {
  ExternalMatchOutput out;
  if (py::isinstance<py::array>(r)) {
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(r);
    if (!a) throw ExternalMethodError(who + ": match() returned an array that is not numeric");
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    shape += ")";
    const std::string want = "(" + std::to_string(grid.yaw_rad.size()) + ", " + std::to_string(grid.grid.height_px) + ", " +
                             std::to_string(grid.grid.width_px) + ")";
    if (a.ndim() != 3 || a.shape(0) != static_cast<py::ssize_t>(grid.yaw_rad.size()) || a.shape(1) != grid.grid.height_px ||
        a.shape(2) != grid.grid.width_px)
      throw ExternalMethodError(who + ": match() returned an array of shape " + shape + "; the grid (yaw, y, x) is " + want);
    out.has_posterior = true;
    out.grid = grid;
    const std::size_t plane = static_cast<std::size_t>(grid.grid.height_px) * static_cast<std::size_t>(grid.grid.width_px);
    for (std::size_t s = 0; s < grid.yaw_rad.size(); ++s) {
      cv::Mat m(grid.grid.height_px, grid.grid.width_px, CV_32F);
      std::memcpy(m.data, a.data() + s * plane, plane * sizeof(float));
      out.scores.push_back(m);
    }
    return out;
  }
  if (py::isinstance<py::list>(r) || py::isinstance<py::tuple>(r)) {
    std::size_t i = 0;
    for (const py::handle& h : r) {
      const std::string where = who + ": match() pose " + std::to_string(i++);
      if (!py::isinstance<py::dict>(h)) throw ExternalMethodError(where + ": expected a dict {x_m, y_m, yaw_deg, score}");
      const py::dict d = py::reinterpret_borrow<py::dict>(h);
      PoseHypothesis p;
      double* fields[] = {&p.x_m, &p.y_m, &p.yaw_rad, &p.score};
      const char* keys[] = {"x_m", "y_m", "yaw_deg", "score"};
      for (int k = 0; k < 4; ++k) {
        if (!d.contains(keys[k])) throw ExternalMethodError(where + ": missing \"" + std::string(keys[k]) + "\"");
        try {
          *fields[k] = d[keys[k]].cast<double>();
        } catch (const py::cast_error&) {
          throw ExternalMethodError(where + ": \"" + std::string(keys[k]) + "\" is not a number");
        }
      }
      p.yaw_rad = deg_to_rad(p.yaw_rad);
      out.poses.push_back(p);
    }
    return out;
  }
  throw ExternalMethodError(who + ": match() returned " + py::str(py::type::of(r)).cast<std::string>() +
                            "; expected a numpy array (yaw, y, x) on the grid or a list of pose dicts");
}

class PyMatcher final : public Matcher {
 public:
  PyMatcher(std::shared_ptr<const PyMethod> method, const FloorPlan& plan, PosteriorGrid grid, nlohmann::json params,
            nlohmann::ordered_json parameters)
      : method_(std::move(method)), grid_(std::move(grid)), params_(std::move(params)), parameters_(std::move(parameters)),
        who_("python matcher \"" + method_->name + "\"") {
    const auto t0 = std::chrono::steady_clock::now();
    py::gil_scoped_acquire gil;
    try {
      state_ = method_->prepare.is_none()
                   ? py::object(py::none())
                   : method_->prepare(PyPlan{plan, "scenario plan " + plan.name}, grid_dict(grid_.grid, grid_.yaw_rad),
                                      to_python(nlohmann::ordered_json(params_)));
    } catch (py::error_already_set& e) {
      throw InputError(python_error(who_ + ": prepare() failed", e));
    }
    precompute_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  ~PyMatcher() override {
    if (!Py_IsInitialized()) {
      (void)state_.release();
      return;
    }
    py::gil_scoped_acquire gil;
    state_ = py::object();
  }
  std::string name() const override { return method_->name; }
  nlohmann::ordered_json parameters() const override { return parameters_; }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return 0; }
  BlockingOptions blocking() const override { return closed_door_map(); }
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override {
    const auto t0 = std::chrono::steady_clock::now();
    ExternalMatchOutput out;
    {
      py::gil_scoped_acquire gil;
      PyObservation o;
      o.record.observation = observation;
      o.record.source = "floorcast";
      try {
        const py::object r = method_->match(state_, o);
        out = output_from_python(r, grid_, who_);
      } catch (py::error_already_set& e) {
        throw ExternalMethodError(python_error(who_ + ": match() raised", e));
      }
    }
    MatchResult res = finish_external_output(std::move(out), grid_, request, who_);
    res.match_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  using Matcher::match;

 private:
  std::shared_ptr<const PyMethod> method_;
  PosteriorGrid grid_;
  nlohmann::json params_;
  nlohmann::ordered_json parameters_;
  std::string who_;
  py::object state_;
  double precompute_s_ = 0.0;
};

/// A registered Python method's configuration: the grid keys, then the method's own parameters.
class PyMatcherConfig final : public MatcherConfig {
 public:
  PyMatcherConfig(std::shared_ptr<const PyMethod> method, const nlohmann::json& overrides) : method_(std::move(method)) {
    grid_ = method_->grid;
    params_ = method_->defaults;
    const std::string who = "matcher " + method_->name;
    if (!overrides.is_object()) throw ParameterError(who + ": parameters must be a mapping", "");
    // The grid's keys through their field list; the method's own keys checked against the kinds
    // of their defaults.
    nlohmann::json grid_overrides = nlohmann::json::object();
    std::vector<std::string> grid_keys;
    for (const FieldInfo& f : PosteriorGridParams::fields().describe()) grid_keys.push_back(f.key);
    for (auto it = overrides.begin(); it != overrides.end(); ++it) {
      const std::string& k = it.key();
      const nlohmann::json& v = it.value();
      if (std::find(grid_keys.begin(), grid_keys.end(), k) != grid_keys.end()) {
        grid_overrides[k] = v;
      } else if (params_.contains(k)) {
        const nlohmann::json& d = params_.at(k);
        const bool same_kind = (d.is_number() && v.is_number()) || d.type() == v.type() || d.is_null();
        if (!same_kind)
          throw ParameterError(who + ": parameter \"" + k + "\": expected " + std::string(d.type_name()) + " like its default " +
                                   d.dump() + ", got " + v.dump(),
                               k);
        params_[k] = v;
      } else {
        std::string known;
        for (const std::string& g : grid_keys) known += (known.empty() ? "" : ", ") + g;
        for (auto p = params_.begin(); p != params_.end(); ++p) known += ", " + p.key();
        throw ParameterError(who + ": unknown parameter \"" + k + "\" (known: " + known + ")", k);
      }
    }
    PosteriorGridParams::fields().read(grid_, grid_overrides);
  }
  std::string name() const override { return method_->name; }
  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json j;
    j["version"] = method_->version;
    PosteriorGridParams::fields().write_into(j, grid_);
    for (auto it = params_.begin(); it != params_.end(); ++it) j[it.key()] = it.value();
    return j;
  }
  std::unique_ptr<Matcher> build(const FloorPlan& plan) const override {
    PosteriorGrid grid = grid_.make(plan);
    return std::make_unique<PyMatcher>(method_, plan, std::move(grid), params_, parameters());
  }

 private:
  std::shared_ptr<const PyMethod> method_;
  PosteriorGridParams grid_;
  nlohmann::json params_;
};

}  // namespace
}  // namespace floorcast

PYBIND11_MODULE(_floorcast, m) {
  using namespace floorcast;
  m.doc() = "floorcast: floor-plan-based indoor localization test-bed (PALMS / PALMS+ family)";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  // ---- plans ----
  py::class_<PyPlan>(m, "Plan", "A floor plan (walls, doors, windows, obstacles), world metres, y up")
      .def_property_readonly("name", [](const PyPlan& p) { return p.plan.name; })
      .def_property_readonly("source", [](const PyPlan& p) { return p.source; })
      .def_property_readonly("hash", [](const PyPlan& p) { return hex64(plan_hash(p.plan)); })
      .def("info", [](const PyPlan& p) {
        py::dict d;
        d["name"] = p.plan.name;
        d["walls"] = p.plan.walls.size();
        d["doors"] = p.plan.doors.size();
        d["windows"] = p.plan.windows.size();
        d["obstacles"] = p.plan.obstacles.size();
        const Eigen::Vector4d e = drawing_extent_m(p.plan);
        d["bounds_m"] = py::make_tuple(e[0], e[1], e[2], e[3]);
        d["hash"] = hex64(plan_hash(p.plan));
        return d;
      }, "Counts, bounding box (xmin, ymin, xmax, ymax) and hash")
      .def("to_json", [](const PyPlan& p) { return floor_plan_to_json(p.plan); }, "The plan in floorcast's JSON format")
      .def("rasters", [](const PyPlan& p, const py::dict& grid, bool doors_closed) {
        const GridSpec g = grid_from_dict(grid);
        BlockingOptions blocking = closed_door_map();
        blocking.open_doors_block = doors_closed;
        cv::Mat occupancy, valid, distance;
        {
          py::gil_scoped_release release;
          occupancy = rasterize_occupancy(p.plan, g, blocking);
          valid = valid_area_mask(p.plan, g);
          distance = distance_to_blocked_m(occupancy, g);
        }
        py::dict d;
        d["occupancy"] = mat_to_array(occupancy);
        d["valid"] = mat_to_array(valid);
        d["distance_m"] = mat_to_array(distance);
        return d;
      }, py::arg("grid"), py::arg("doors_closed") = true,
         "Rasters of the plan on a grid dict (posterior_grid(), or the grid a registered matcher's prepare() gets): "
         "occupancy uint8 (255 = blocked: walls, closed doors, glass), valid uint8 (255 = free floor inside), "
         "distance_m float32 (metres to the nearest blocked cell); rows are y (row 0 = lowest y)")
      .def("render", [](const PyPlan& p, double px_per_m) {
        RenderOptions o;
        o.px_per_m = px_per_m;
        return mat_to_array(render_plan(p.plan, o).bgr, true);
      }, py::arg("px_per_m") = 20.0, "The plan drawn for people: uint8 (H, W, 3) RGB")
      .def("__repr__", [](const PyPlan& p) {
        return "<floorcast.Plan '" + p.plan.name + "': " + std::to_string(p.plan.walls.size()) + " walls>";
      });
  m.def("load_plan", [](const std::string& path) { return PyPlan{load_floor_plan(path), path}; }, py::arg("path"),
        "Reads a floor-plan JSON file (validated; repairs reported by the loader)");
  m.def("generate_plan", [](const std::string& archetype, std::uint64_t seed) {
    return PyPlan{generate_building(parse_archetype(archetype), seed).plan, "generated " + archetype + " seed " + std::to_string(seed)};
  }, py::arg("archetype"), py::arg("seed") = 0, "A procedural building: apartment, office, campus, angled (calibrated on real plans) or office_repetitive, campus_repetitive, angled_repetitive (the hard case of identical rooms)");

  // ---- scans ----
  py::class_<DepthView>(m, "View", "One view of a scan: depth, optional colour and masks, intrinsics, pose")
      .def_property("depth", [](const DepthView& v) { return mat_view(v.depth_m); },
                    [](DepthView& v, const py::object& o) {
                      if (o.is_none()) {  // no depth: a colour-only view (depth made elsewhere)
                        v.depth_m.release();
                        v.glass_mask.release();
                        v.confidence.release();
                        return;
                      }
                      cv::Mat d = array_to_mat(o.cast<py::array>(), "depth", CV_32F, 1);
                      if (d.cols != v.intrinsics.width_px || d.rows != v.intrinsics.height_px)
                        throw InputError("depth: shape must be (height_px, width_px) of the intrinsics");
                      v.depth_m = d;
                      v.glass_mask.release();
                      v.confidence.release();
                    }, "float32 (H, W) z-depth in metres, 0 = no return: a view of the scan's own depth, so "
                       "in-place edits (view.depth[mask] = 0) change the scan; assigning an array replaces it (bring "
                       "your own depth; None removes it)")
      .def_property("rgb", [](const DepthView& v) { return mat_view(v.rgb, true); },
                    [](DepthView& v, const py::array& a) { v.rgb = array_to_mat(a, "rgb", CV_8U, 3, true); },
                    "uint8 (H, W, 3) RGB colour image (a view of the scan's pixels: in-place edits change it), or an "
                    "empty array")
      .def_property_readonly("glass_mask", [](const DepthView& v) { return mat_view(v.glass_mask); },
                             "uint8 (H, W) simulated glass mask (a view: in-place edits change the scan)")
      .def_property_readonly("confidence", [](const DepthView& v) { return mat_view(v.confidence); },
                             "uint8 (H, W) depth confidence (a view: in-place edits change the scan)")
      .def_property_readonly("view_index", [](const DepthView& v) { return v.view_index; })
      .def_property_readonly("intrinsics", [](const DepthView& v) {
        // Read-only: editing a copy would be silently lost.
        py::dict d;
        d["width_px"] = v.intrinsics.width_px;
        d["height_px"] = v.intrinsics.height_px;
        d["fx_px"] = v.intrinsics.fx_px;
        d["fy_px"] = v.intrinsics.fy_px;
        d["cx_px"] = v.intrinsics.cx_px;
        d["cy_px"] = v.intrinsics.cy_px;
        return py::module_::import("types").attr("MappingProxyType")(d);
      }, "read-only mapping: width_px, height_px, fx_px, fy_px, cx_px, cy_px")
      .def_property("T_scan_camera", [](const DepthView& v) { return read_only(matrix4(v.T_scan_camera)); },
                    [](DepthView& v, const py::array& a) { v.T_scan_camera = isometry(a); },
                    "4x4 camera pose in the scan frame (OpenCV camera: x right, y down, z forward); read-only array, "
                    "assign a whole new matrix to change it");
  py::class_<PyScan>(m, "Scan", "A rotating scan: views (depth, colour, intrinsics, poses) and, when simulated, its truth")
      .def_property_readonly("views", [](PyScan& s) {
        py::list l;
        for (DepthView& v : s.scan.views) l.append(py::cast(&v, py::return_value_policy::reference_internal, py::cast(&s)));
        return l;
      })
      .def_property_readonly("sensor", [](const PyScan& s) { return s.scan.sensor; })
      .def_property_readonly("truth", [](const PyScan& s) -> py::object {
        if (!s.truth) return py::none();
        py::dict d = pose_dict(s.truth->T_world_scan);
        d["camera_height_m"] = s.truth->camera_height_m;
        d["view_depth_scale"] = s.truth->view_depth_scale;
        return d;
      }, "Ground-truth pose (x_m, y_m, yaw_deg) of a simulated scan, else None")
      .def("save", [](const PyScan& s, const std::string& dir) { save_scan(dir, s.scan); }, py::arg("dir"),
           "Writes a scan folder (scan.json, 16-bit depth PNGs, colour PNGs) that `floorcast observe` reads")
      .def("__len__", [](const PyScan& s) { return s.scan.views.size(); })
      .def("__repr__", [](const PyScan& s) {
        return "<floorcast.Scan " + s.scan.sensor + ": " + std::to_string(s.scan.views.size()) + " views>";
      });
  m.def("simulate_scan", [](const PyPlan& plan, const py::object& pose_deg, const std::string& sensor, const std::string& setting,
                            std::uint64_t seed, bool rgb, bool doors_open, const py::object& params, bool semantics) {
    const Pose2 pose = pose_from(pose_deg);
    ScanParams p = scan_preset(sensor);
    if (!parse_scan_setting(setting, p.setting)) throw InputError("setting \"" + setting + "\": expected full, partial or single");
    p.seed = seed;
    if (!params.is_none()) apply_scan_overrides(p, from_python(params), "params");
    validate_scan_params(p);
    FloorPlan world = plan.plan;
    if (!doors_open)
      for (Door& d : world.doors) d.closed = true;
    check_observer_pose(world, pose, plan.source);
    PyScan out;
    SimulatedScan sim;
    {
      py::gil_scoped_release release;
      const RayScene scene(extrude_plan(world));
      SimulationOptions so;
      so.column_semantics = semantics;
      sim = simulate_scan(scene, pose, p, so);
      if (rgb) {
        GlRenderer gl(scene.mesh(), p.geometry.width_px, p.geometry.height_px);
        render_scan_colour(gl, sim);
      }
    }
    sim.truth.plan_hash = hex64(plan_hash(plan.plan));
    out.scan = std::move(sim.scan);
    out.truth = std::move(sim.truth);
    return out;
  }, py::arg("plan"), py::arg("pose"), py::arg("sensor") = "mono", py::arg("setting") = "full", py::arg("seed") = 0,
     py::arg("rgb") = false, py::arg("doors_open") = false, py::arg("params") = py::none(), py::arg("semantics") = false,
     "Simulates a rotating scan at pose (x_m, y_m, yaw_deg) with a sensor preset (perfect, lidar, mono, phone); "
     "rgb=True renders colour views (OpenGL, headless). params: nested dict of sensor overrides "
     "(e.g. {'sensor': {'mono': {'scale_sigma_ln': 0.2}}}). Doors closed unless doors_open, as `floorcast sim scan`. "
     "semantics=True annotates every view with its column semantics (the BEV predictor's truth: observe(bev=...)).");
  m.def("read_depth", [](const std::string& path, double integer_unit_m) {
    DepthFileOptions o;
    o.integer_unit_m = integer_unit_m;
    return mat_to_array(read_depth_file(path, o));
  }, py::arg("path"), py::arg("integer_unit_m") = 0.001,
     "Reads a depth map (.npy, .tif/.tiff, .exr in metres; 16-bit .png in integer_unit_m) as float32 (H, W) metres");
  m.def("write_depth", [](const std::string& path, const py::array& depth, double integer_unit_m) {
    DepthFileOptions o;
    o.integer_unit_m = integer_unit_m;
    write_depth_file(path, array_to_mat(depth, "depth", CV_32F, 1), o);
  }, py::arg("path"), py::arg("depth"), py::arg("integer_unit_m") = 0.001,
     "Writes float32 (H, W) metres as .npy, float .tif/.tiff or .exr, or 16-bit .png");
  m.def("load_scan", [](const std::string& dir, const std::optional<std::string>& depth_dir, const std::string& depth_kind,
                        bool rgb) {
    ScanLoadOptions lo;
    lo.require_depth = !depth_dir;
    lo.load_rgb = rgb;
    PyScan out;
    out.scan = load_scan(dir, lo);
    if (depth_dir) {
      DepthFileOptions o;
      o.kind = parse_depth_kind(depth_kind);
      (void)load_depth_directory(out.scan, *depth_dir, o);
    }
    if (auto sim = load_simulation_record(dir, out.scan.views.size())) out.truth = sim->truth;
    return out;
  }, py::arg("dir"), py::arg("depth_dir") = py::none(), py::arg("depth_kind") = "z", py::arg("rgb") = true,
     "Reads a scan folder; depth_dir replaces its depth by depth maps made elsewhere (.npy/.tif/.exr metres, 16-bit .png mm)");

  // ---- observations ----
  py::class_<PyObservation>(m, "Observation", "Observed wall segments (observer frame: x ahead, y left, metres) and rays")
      .def_property_readonly("segments", [](const PyObservation& o) {
        py::array_t<double> a({static_cast<py::ssize_t>(o.record.observation.segments_m.size()), py::ssize_t{4}});
        auto v = a.mutable_unchecked<2>();
        for (std::size_t i = 0; i < o.record.observation.segments_m.size(); ++i) {
          const Segment2& s = o.record.observation.segments_m[i];
          v(i, 0) = s.a_m.x();
          v(i, 1) = s.a_m.y();
          v(i, 2) = s.b_m.x();
          v(i, 3) = s.b_m.y();
        }
        return read_only(a);
      }, "float64 (N, 4): ax, ay, bx, by (read-only)")
      .def_property_readonly("ray_ranges", [](const PyObservation& o) {
        return read_only(py::array(py::cast(o.record.observation.ray_ranges_m)));
      }, "float64 (R,) ranges of equiangular rays (read-only)")
      .def_property_readonly("planes", [](const PyObservation& o) {
        py::list l;
        auto v3 = [](const Eigen::Vector3d& v) { return py::make_tuple(v.x(), v.y(), v.z()); };
        for (const PlanePatch& p : o.record.observation.planes) {
          py::dict d;
          d["normal"] = v3(p.normal);
          d["offset_m"] = p.offset_m;
          d["centroid_m"] = v3(p.centroid_m);
          d["radius_m"] = p.radius_m;
          d["area_m2"] = patch_area_m2(p, o.record.observation.plane_cell_m);
          py::array_t<double> cells({static_cast<py::ssize_t>(p.cells_m.size()), py::ssize_t{3}});
          auto c = cells.mutable_unchecked<2>();
          for (std::size_t i = 0; i < p.cells_m.size(); ++i)
            for (int k = 0; k < 3; ++k) c(static_cast<py::ssize_t>(i), k) = p.cells_m[i][k];
          d["cells_m"] = cells;
          l.append(d);
        }
        return l;
      }, "3D plane patches (observer frame, z up from the sensor): list of dicts normal, offset_m, centroid_m, "
         "radius_m, area_m2, cells_m (N, 3)")
      .def_property_readonly("max_range_m", [](const PyObservation& o) { return o.record.observation.max_range_m; })
      .def_property_readonly("truth", [](const PyObservation& o) -> py::object {
        return o.record.T_world_observer ? py::object(pose_dict(*o.record.T_world_observer)) : py::none();
      })
      .def_property_readonly("diagnostics", [](const PyObservation& o) { return to_python(o.diagnostics); })
      .def_property_readonly("bev", [](const PyObservation& o) {
        py::list l;
        for (const BevPrediction& b : o.record.observation.bev) {
          py::dict d;
          d["classes"] = bev_classes_name(b.classes);
          d["class_names"] = bev_class_names(b.classes);
          d["depth_bins"] = b.bins.count;
          d["min_depth_m"] = b.bins.min_m;
          d["max_depth_m"] = b.bins.max_m;
          d["column_azimuth_rad"] = py::array(py::cast(b.column_azimuth_rad));
          py::array_t<float> p({static_cast<py::ssize_t>(b.num_columns()), static_cast<py::ssize_t>(b.bins.count),
                                static_cast<py::ssize_t>(b.num_classes())});
          std::copy(b.probabilities.begin(), b.probabilities.end(), p.mutable_data());
          d["probabilities"] = p;
          l.append(d);
        }
        return l;
      }, "BEV predictions (semantic and/or occupancy): dicts with classes, depth bins, column_azimuth_rad (W) and "
         "probabilities float32 (W, D, C)")
      .def("save", [](const PyObservation& o, const std::string& path) { save_observation(path, o.record); }, py::arg("path"))
      .def("__repr__", [](const PyObservation& o) {
        return "<floorcast.Observation: " + std::to_string(o.record.observation.segments_m.size()) + " segments, " +
               std::to_string(o.record.observation.planes.size()) + " planes>";
      });
  m.def("perfect_observation", [](const PyPlan& plan, const py::object& pose_deg, int rays, double range_m, bool doors_open,
                                  int bev_columns) {
    const Pose2 pose = pose_from(pose_deg);
    check_observer_pose(plan.plan, pose, plan.source);
    PerfectObservationParams p;
    p.num_rays = rays;
    p.bev_columns = bev_columns;
    p.max_range_m = range_m;
    p.blocking.open_doors_block = !doors_open;
    const PerfectObserver observer(plan.plan, p);
    PyObservation o;
    o.record.observation = observer.observe(pose);
    o.record.source = "perfect";
    o.record.T_world_observer = pose;
    o.record.metadata["plan_hash"] = hex64(plan_hash(plan.plan));
    o.diagnostics = {{"params", p.to_json()}};
    return o;
  }, py::arg("plan"), py::arg("pose"), py::arg("rays") = PerfectObservationParams{}.num_rays,
     py::arg("range_m") = PerfectObservationParams{}.max_range_m, py::arg("doors_open") = false,
     py::arg("bev_columns") = PerfectObservationParams{}.bev_columns,
     "The exact visible wall surfaces within range (PALMS+ sec. 4.4 proxy; doors closed unless doors_open); "
     "bev_columns > 0 adds the perfect semantic and occupancy BEVs on that many equiangular columns");
  m.def("bev_observation", [](const py::array& probabilities, double hfov_deg, double min_depth_m, double max_depth_m) {
    const py::array_t<float, py::array::c_style | py::array::forcecast> a(probabilities);
    if (a.ndim() != 3 || (a.shape(2) != 4 && a.shape(2) != 2)) {
      throw InputError("bev_observation: probabilities must have shape (W, D, C) with C = 4 (wall, window, door, empty) "
                       "or 2 (occupied, empty)");
    }
    BevPrediction b;
    b.classes = a.shape(2) == 4 ? BevClasses::kSemantic : BevClasses::kOccupancy;
    b.bins = {static_cast<int>(a.shape(1)), min_depth_m, max_depth_m};
    const int W = static_cast<int>(a.shape(0));
    if (hfov_deg >= 360.0) {
      b.column_azimuth_rad = full_circle_azimuths(W);
    } else {
      const double t = std::tan(0.5 * hfov_deg * kPi / 180.0);
      for (int w = 0; w < W; ++w) b.column_azimuth_rad.push_back(std::atan((1.0 - 2.0 * (w + 0.5) / W) * t));
    }
    b.probabilities.assign(a.data(), a.data() + a.size());
    b.check("bev_observation");
    PyObservation o;
    o.record.observation.bev.push_back(std::move(b));
    o.record.observation.max_range_m = max_depth_m;
    o.record.source = "BEV";
    return o;
  }, py::arg("probabilities"), py::arg("hfov_deg") = 90.0, py::arg("min_depth_m") = 0.3, py::arg("max_depth_m") = 10.0,
     "An observation from a BEV of your own (a network's softmax output), float (W, D, C): columns left to right over a "
     "pinhole's horizontal field of view hfov_deg (360: counter-clockwise around the full circle), D log-spaced depth "
     "bins over [min_depth_m, max_depth_m); for match(..., matcher='bev')");
  m.def("observe", [](const PyScan& scan, const std::optional<std::string>& path, const std::optional<std::string>& scale_alignment,
                      const py::object& params, const std::optional<std::string>& bev) {
    ObservationParams p;
    if (!params.is_none()) apply_overrides(p, from_python(params));
    if (bev) {
      p.bev.enabled = true;
      p.bev.preset = *bev;
      p.bev.error = bev_error_preset(*bev);
    }
    if (path) p.path = parse_observation_path(*path);
    else if (params.is_none() && scan.scan.sensor == "lidar") p.path = ObservationPath::kLidar;
    if (scale_alignment) p.scale.mode = parse_scale_alignment(*scale_alignment);
    ObservationResult r;
    {
      py::gil_scoped_release release;
      r = observe_scan(scan.scan, p);
    }
    PyObservation o;
    o.record.observation = r.observation;
    o.record.source = "observation module (" + r.diagnostics.path + ")";
    if (scan.truth) {
      o.record.T_world_observer = scan.truth->T_world_scan;
      if (!scan.truth->plan_hash.empty()) o.record.metadata["plan_hash"] = scan.truth->plan_hash;
    }
    o.diagnostics = {{"diagnostics", to_json(r.diagnostics)}, {"params", to_json(p)}, {"total_s", r.total_s}};
    return o;
  }, py::arg("scan"), py::arg("path") = py::none(), py::arg("scale_alignment") = py::none(), py::arg("params") = py::none(),
     py::arg("bev") = py::none(),
     "The observation module: scan -> observed wall segments (path mono or lidar; scale alignment full, ground, none); "
     "bev=PRESET also makes the semantic BEV for matcher 'bev' (the views' own BEVs, else the simulated predictor: "
     "perfect, structured3d_good, structured3d_bad, custom_good, custom_bad; params {'bev': {...}} set its values)");
  m.def("load_observation", [](const std::string& path) {
    PyObservation o;
    o.record = load_observation(path);
    return o;
  }, py::arg("path"));

  // ---- matching ----
  py::class_<PyMatch>(m, "MatchResult", "A matcher's posterior over (yaw, y, x) and its estimate")
      .def_property_readonly("posterior", [](const PyMatch& r) {
        const GridSpec& g = r.posterior.grid;
        py::array_t<float> a({static_cast<py::ssize_t>(r.posterior.num_slices()), static_cast<py::ssize_t>(g.height_px),
                              static_cast<py::ssize_t>(g.width_px)});
        float* dst = a.mutable_data();
        const std::size_t plane = static_cast<std::size_t>(g.width_px) * g.height_px;
        for (int s = 0; s < r.posterior.num_slices(); ++s) {
          const cv::Mat& m = r.posterior.scores[static_cast<std::size_t>(s)];
          for (int row = 0; row < g.height_px; ++row)
            std::memcpy(dst + s * plane + static_cast<std::size_t>(row) * g.width_px, m.ptr<float>(row), sizeof(float) * g.width_px);
        }
        return a;
      }, "float32 (yaw, y, x) unnormalised scores; row 0 is the lowest y (see grid)")
      .def_property_readonly("yaw_deg", [](const PyMatch& r) {
        std::vector<double> d;
        for (double y : r.posterior.yaw_rad) d.push_back(y * 180.0 / kPi);
        return py::array(py::cast(d));
      })
      .def_property_readonly("grid", [](const PyMatch& r) { return grid_dict(r.posterior.grid, r.posterior.yaw_rad); })
      .def_property_readonly("estimate", [](const PyMatch& r) {
        py::dict d = hypothesis_dict(r.best, r.truth);
        const bool found = r.found;
        d["status"] = found ? "ok" : "not localized (no pose: empty posterior, rejected or below min_score)";
        if (!found) {
          d["x_m"] = py::none();
          d["y_m"] = py::none();
          d["yaw_deg"] = py::none();
        }
        return d;
      }, "dict: x_m, y_m, yaw_deg, score, status (and errors when the observation knows its truth)")
      .def_property_readonly("top_k", [](const PyMatch& r) {
        py::list l;
        for (const PoseHypothesis& h : r.top_k) l.append(hypothesis_dict(h, r.truth));
        return l;
      })
      .def_property_readonly("matcher", [](const PyMatch& r) { return r.matcher; })
      .def_property_readonly("localized", [](const PyMatch& r) { return r.found; }, "False: not localized (no pose)")
      .def_property_readonly("counters", [](const PyMatch& r) { return r.counters; })
      .def_property_readonly("parameters", [](const PyMatch& r) { return to_python(r.parameters); })
      .def_property_readonly("match_s", [](const PyMatch& r) { return r.match_s; })
      .def_property_readonly("precompute_s", [](const PyMatch& r) { return r.precompute_s; })
      .def("save_npy", [](const PyMatch& r, const std::string& path) {
        std::vector<float> values;
        const GridSpec& g = r.posterior.grid;
        for (const cv::Mat& s : r.posterior.scores)
          for (int row = 0; row < g.height_px; ++row) values.insert(values.end(), s.ptr<float>(row), s.ptr<float>(row) + g.width_px);
        write_npy(path, {static_cast<std::size_t>(r.posterior.num_slices()), static_cast<std::size_t>(g.height_px),
                         static_cast<std::size_t>(g.width_px)}, values);
      }, py::arg("path"));
  m.def("matcher_names", &matcher_names, "Built-in matchers and those registered with register_matcher");
  py::class_<PyBuiltMatcher>(m, "Matcher",
                             "A matcher built once for a plan (its per-plan preparation runs here), matched as often as "
                             "needed: Matcher(plan, 'kernel').match(observation)")
      .def(py::init([](const PyPlan& plan, const std::string& name, const py::object& params) {
             const nlohmann::json overrides = from_python(params);
             py::gil_scoped_release release;
             return PyBuiltMatcher{std::shared_ptr<const Matcher>(make_matcher(name, plan.plan, overrides))};
           }),
           py::arg("plan"), py::arg("name") = "kernel", py::arg("params") = py::none())
      .def("match", [](const PyBuiltMatcher& m, const PyObservation& obs, int top_k) { return match_once(*m.matcher, obs, top_k); },
           py::arg("observation"), py::arg("top_k") = 5, "The posterior and the estimate of one observation")
      .def_property_readonly("name", [](const PyBuiltMatcher& m) { return m.matcher->name(); })
      .def_property_readonly("parameters", [](const PyBuiltMatcher& m) { return to_python(m.matcher->parameters()); })
      .def_property_readonly("precompute_s", [](const PyBuiltMatcher& m) { return m.matcher->precompute_s(); })
      .def("__repr__", [](const PyBuiltMatcher& m) { return "<floorcast.Matcher " + m.matcher->name() + ">"; });
  m.def("match", [](const PyPlan& plan, const PyObservation& obs, const std::string& matcher, const py::object& params, int top_k) {
    const nlohmann::json overrides = from_python(params);
    std::unique_ptr<Matcher> mt;
    {
      py::gil_scoped_release release;
      mt = make_matcher(matcher, plan.plan, overrides);
    }
    return match_once(*mt, obs, top_k);
  }, py::arg("plan"), py::arg("observation"), py::arg("matcher") = "kernel", py::arg("params") = py::none(),
     py::arg("top_k") = 5,
     "Builds a matcher (kernel, ray, planes, a registered one, ...) and runs it on one observation; to match several "
     "observations build it once with Matcher(plan, name) instead");

  // ---- own methods ----
  // Names registered from Python, released at interpreter exit (__init__.py) while Python objects
  // can still be dropped.
  static std::set<std::string> python_matchers;
  m.def("register_matcher", [](const std::string& name, const py::object& match, const py::object& prepare,
                               const py::object& params, double resolution_m, int yaw_bins, double grid_margin_m,
                               const std::string& version) {
    if (!PyCallable_Check(match.ptr())) throw InputError("register_matcher(\"" + name + "\"): match must be callable");
    if (!prepare.is_none() && !PyCallable_Check(prepare.ptr()))
      throw InputError("register_matcher(\"" + name + "\"): prepare must be callable or None");
    auto method = std::make_shared<PyMethod>();
    method->name = name;
    method->prepare = prepare;
    method->match = match;
    method->defaults = from_python(params);
    if (!method->defaults.is_object()) throw InputError("register_matcher(\"" + name + "\"): params must be a dict");
    for (const char* reserved : {"resolution_m", "yaw_bins", "grid_margin_m", "version"})
      if (method->defaults.contains(reserved))
        throw InputError("register_matcher(\"" + name + "\"): \"" + reserved + "\" is a registration argument, not a params key");
    method->grid.resolution_m = resolution_m;
    method->grid.yaw_bins = yaw_bins;
    method->grid.grid_margin_m = grid_margin_m;
    PosteriorGridParams::fields().validate(method->grid);
    method->version = version;
    // Checked now, so a bad grid argument fails here rather than in a scenario.
    (void)PyMatcherConfig(method, nlohmann::json::object());
    std::shared_ptr<const PyMethod> shared = method;
    register_matcher(name, [shared](const nlohmann::json& overrides, const SharedParams&) {
      return std::make_shared<PyMatcherConfig>(shared, overrides);
    });
    python_matchers.insert(name);
  }, py::arg("name"), py::kw_only(), py::arg("match"), py::arg("prepare") = py::none(), py::arg("params") = py::none(),
     py::arg("resolution_m") = 0.1, py::arg("yaw_bins") = 36, py::arg("grid_margin_m") = 1.0, py::arg("version") = "1",
     "Registers a matcher written in Python under `name`, for scenarios (`matcher: NAME`), Matcher(), track() and "
     "everything else that builds matchers by name.\n\n"
     "prepare(plan, grid, params) -> state runs once per building (grid: the shared posterior grid, a dict with "
     "origin_x_m, origin_y_m, resolution_m, width_px, height_px, yaw_deg); match(state, observation) runs once per "
     "observation and returns float scores (yaw, y, x) on that grid (>= 0, higher = better) or a list of pose dicts "
     "{x_m, y_m, yaw_deg, score} (best first; [] = no pose). params: the method's parameters with their defaults "
     "(a scenario overrides them by key). version: part of the configuration hash; change it when the code changes, "
     "so a resumed run never mixes results of two versions. Exceptions and malformed results are reported per unit.");
  m.def("unregister_matcher", [](const std::string& name) {
    python_matchers.erase(name);
    return unregister_matcher(name);
  }, py::arg("name"));
  m.def("_unregister_python_matchers", [] {
    for (const std::string& n : python_matchers) unregister_matcher(n);
    python_matchers.clear();
  });
  m.def("posterior_grid", [](const PyPlan& plan, double resolution_m, int yaw_bins, double grid_margin_m) {
    const PosteriorGrid g = shared_posterior_grid(plan.plan, resolution_m, yaw_bins, grid_margin_m);
    return grid_dict(g.grid, g.yaw_rad);
  }, py::arg("plan"), py::arg("resolution_m") = 0.1, py::arg("yaw_bins") = 36, py::arg("grid_margin_m") = 1.0,
     "The shared posterior grid of a plan (what registered and external matchers return scores on)");

  // ---- walks and tracking ----
  py::class_<PyWalk>(m, "Walk",
                     "A walk folder (`floorcast sim walk`, sim_walk, or a recording in its layout): truth, odometry and "
                     "the observations on its schedule")
      .def_property_readonly("dir", [](const PyWalk& w) { return w.dir; })
      .def_property_readonly("t_s", [](const PyWalk& w) {
        std::vector<double> t;
        for (const WalkStep& s : w.record.walk.steps) t.push_back(s.t_s);
        return column(t);
      }, "float64 (N,) time of every step, s")
      .def_property_readonly("truth", [](const PyWalk& w) {
        std::vector<Pose2> p;
        for (const WalkStep& s : w.record.walk.steps) p.push_back(s.T_world_body);
        return poses_array(p);
      }, "float64 (N, 3) true pose of every step: x_m, y_m, yaw_deg")
      .def_property_readonly("odometry", [](const PyWalk& w) { return poses_array(w.record.odometry.poses); },
                             "float64 (N, 3) the odometry's increments chained from the true start pose (the odometry frame "
                             "aligned with the world at the start, as evo aligns the first pose): x_m, y_m, yaw_deg")
      .def_property_readonly("observations", [](const PyWalk& w) {
        py::list l;
        for (const WalkObservation& o : w.record.observations) {
          py::dict d;
          d["step"] = o.step;
          d["kind"] = o.kind;
          d["path"] = (std::filesystem::path(w.dir) / o.path).string();
          l.append(d);
        }
        return l;
      }, "The scheduled observations: [{step, kind ('scan' or 'perfect'), path (its folder)}]; a scan folder holds "
         "view_NNN_rgb.png when simulated with rgb=True")
      .def_property_readonly("summary", [](const PyWalk& w) {
        return to_python(walk_summary_fields().write(w.record.walk.summary));
      }, "length_m, duration_s, speed_mps, pauses, ... of the walk")
      .def_property_readonly("plan_name", [](const PyWalk& w) { return w.record.plan_name; })
      .def("scan", [](const PyWalk& w, std::size_t i, bool rgb) {
        if (i >= w.record.observations.size()) throw py::index_error("observation index out of range");
        const WalkObservation& o = w.record.observations[i];
        if (o.kind != "scan") throw InputError("observation " + std::to_string(i) + " is a " + o.kind + " observation, not a scan");
        const std::string dir = (std::filesystem::path(w.dir) / o.path).string();
        ScanLoadOptions lo;
        lo.load_rgb = rgb;
        PyScan out;
        out.scan = load_scan(dir, lo);
        if (auto sim = load_simulation_record(dir, out.scan.views.size())) out.truth = sim->truth;
        return out;
      }, py::arg("index"), py::arg("rgb") = true, "The scan of observation `index` (its views: depth, colour, poses)")
      .def("__len__", [](const PyWalk& w) { return w.record.walk.steps.size(); })
      .def("__repr__", [](const PyWalk& w) {
        return "<floorcast.Walk " + w.dir + ": " + std::to_string(w.record.walk.steps.size()) + " steps, " +
               std::to_string(w.record.observations.size()) + " observations>";
      });
  m.def("load_walk", [](const std::string& dir) { return PyWalk{load_walk(dir), dir}; }, py::arg("dir"),
        "Reads a walk folder (strict: errors name the file, element and reason)");
  m.def("sim_walk", [](const PyPlan& plan, const std::string& out, int steps, const py::object& start, const std::string& sensor,
                       const std::string& setting, bool rgb, bool initial, int scan_every, double scan_every_m,
                       const std::string& odometry, std::uint64_t seed, const std::optional<double>& range_m, int rays,
                       bool doors_open, const py::object& walk_params, const py::object& odometry_params) {
    WalkSimulationOptions o;
    o.walk.steps = steps;
    o.walk.seed = seed;
    if (!walk_params.is_none()) o.walk.apply_overrides(from_python(walk_params));
    o.odometry.seed = mix64(seed ^ 0x0d0e7e11ULL);  // as `floorcast sim walk --seed`
    if (!odometry_params.is_none()) o.odometry.apply_overrides(from_python(odometry_params));
    o.odometry.apply_overrides({{"model", odometry}});
    o.schedule = {initial, scan_every, scan_every_m};
    if (!start.is_none()) o.start = pose_from(start);
    o.perfect = sensor == "perfect";
    o.perfect_params.num_rays = rays;
    if (range_m) o.perfect_params.max_range_m = *range_m;
    o.perfect_params.blocking.open_doors_block = !doors_open;
    if (!o.perfect) {
      o.scan = scan_preset(sensor);
      if (!parse_scan_setting(setting, o.scan.setting)) throw InputError("setting \"" + setting + "\": expected full, partial or single");
      if (range_m) o.scan.sensor.max_range_m = *range_m;
    }
    o.scan_seed = seed;
    o.rgb = rgb;
    {
      py::gil_scoped_release release;
      (void)write_simulated_walk(plan.plan, o, out);
    }
    return PyWalk{load_walk(out), out};
  }, py::arg("plan"), py::arg("out"), py::kw_only(), py::arg("steps") = WalkParams{}.steps, py::arg("start") = py::none(),
     py::arg("sensor") = "perfect", py::arg("setting") = "full", py::arg("rgb") = false, py::arg("initial") = true,
     py::arg("scan_every") = 0, py::arg("scan_every_m") = 0.0, py::arg("odometry") = "vio", py::arg("seed") = 1,
     py::arg("range_m") = py::none(), py::arg("rays") = PerfectObservationParams{}.num_rays, py::arg("doors_open") = false,
     py::arg("walk_params") = py::none(), py::arg("odometry_params") = py::none(),
     "Simulates a walk into the walk folder `out`, as `floorcast sim walk` (same seed, same bytes): start "
     "(x_m, y_m, yaw_deg) or None (seeded random start), odometry exact | vio | pdr, observations at the start "
     "(initial) and every scan_every steps / scan_every_m metres; sensor 'perfect' or a scan preset (setting full | "
     "partial | single); rgb=True renders every view in colour for a depth network. Returns the Walk.");
  py::class_<PyTrack>(m, "TrackResult", "A tracker's run along a walk: per-step errors as numpy arrays, metrics as a dict")
      .def_property_readonly("started", [](const PyTrack& t) { return t.track.run.started; })
      .def_property_readonly("failure", [](const PyTrack& t) { return t.failure; }, "why the tracker did not start ('' when it did)")
      .def_property_readonly("tracker", [](const PyTrack& t) { return t.tracker; })
      .def_property_readonly("matcher", [](const PyTrack& t) { return t.matcher; })
      .def_property_readonly("first_step", [](const PyTrack& t) { return t.track.first_step; })
      .def_property_readonly("observations_used", [](const PyTrack& t) { return t.track.observations_used; })
      .def_property_readonly("step", [](const PyTrack& t) {
        std::vector<int> v;
        for (const TrackRunStep& s : t.track.run.steps) v.push_back(s.step);
        return column(v);
      }, "int (N,) walk step of every track step (from first_step to the end)")
      .def_property_readonly("t_s", [](const PyTrack& t) { return column(t.track.record.t_s); })
      .def_property_readonly("distance_m", [](const PyTrack& t) { return column(t.track.record.distance_m); },
                             "float64 (N,) distance walked since the tracker started, m")
      .def_property_readonly("position_error_m", [](const PyTrack& t) { return column(t.track.record.position_error_m); })
      .def_property_readonly("yaw_error_deg", [](const PyTrack& t) { return column(t.track.record.yaw_error_deg); })
      .def_property_readonly("stage", [](const PyTrack& t) { return column(t.track.record.stage); },
                             "int (N,) convergence stage per step")
      .def_property_readonly("updated", [](const PyTrack& t) {
        std::vector<std::uint8_t> v;
        for (const TrackRunStep& s : t.track.run.steps) v.push_back(s.updated ? 1 : 0);
        return column(v).attr("astype")("bool");
      }, "bool (N,) an observation's posterior was applied at this step")
      .def_property_readonly("estimate", [](const PyTrack& t) {
        std::vector<Pose2> p;
        for (const TrackRunStep& s : t.track.run.steps) p.push_back(s.estimate.pose);
        return poses_array(p);
      }, "float64 (N, 3) estimated pose per step: x_m, y_m, yaw_deg")
      .def_property_readonly("truth", [](const PyTrack& t) { return poses_array(t.truth); },
                             "float64 (N, 3) true pose per step: x_m, y_m, yaw_deg")
      .def_property_readonly("metrics", [](const PyTrack& t) { return to_python(t.metrics); },
                             "rmse_m, rmse_last_m, end_error_m, success_1m, success_0.5m, converged, ... (as metrics.json "
                             "of `floorcast track`)")
      .def_property_readonly("tracker_parameters", [](const PyTrack& t) { return to_python(t.tracker_parameters); })
      .def_property_readonly("matcher_parameters", [](const PyTrack& t) { return to_python(t.matcher_parameters); })
      .def_property_readonly("notes", [](const PyTrack& t) { return t.track.notes; },
                             "depth maps repaired, observations without walls (no update)")
      .def("__repr__", [](const PyTrack& t) {
        if (!t.track.run.started) return "<floorcast.TrackResult " + t.tracker + ": no track: " + t.failure + ">";
        return "<floorcast.TrackResult " + t.tracker + " (" + t.matcher + "): " + std::to_string(t.track.run.steps.size()) +
               " steps, RMSE " + format_fixed(t.track.outcome.rmse_m, 2) + " m>";
      });
  m.def("track", [](const PyPlan& plan, const py::object& walk_arg, const std::string& tracker_name, const py::object& matcher_arg,
                    const py::object& tracker_params, const py::object& matcher_params, const std::optional<std::string>& depth_dir,
                    const std::string& depth_kind, double depth_unit_m, const py::object& observe_params, std::uint64_t seed,
                    const std::optional<double>& range_m) {
    PyWalk walk = py::isinstance<PyWalk>(walk_arg) ? walk_arg.cast<PyWalk>()
                                                   : PyWalk{load_walk(walk_arg.cast<std::string>()), walk_arg.cast<std::string>()};
    // Every parameter parsed and checked before any work, as `floorcast track`.
    nlohmann::json tracker_overrides = from_python(tracker_params);
    if (tracker_name == "pf" && !tracker_overrides.contains("seed")) tracker_overrides["seed"] = seed;
    // The walk's stated odometry error (walk.json odometry_uncertainty), params' odometry keys on top.
    tracker_overrides = with_odometry(tracker_overrides, walk.record.odometry_uncertainty);
    const std::shared_ptr<const TrackerConfig> tracker_config = make_tracker_config(tracker_name, tracker_overrides);
    std::shared_ptr<const Matcher> matcher;
    if (py::isinstance<PyBuiltMatcher>(matcher_arg)) {
      if (!matcher_params.is_none()) throw InputError("track: matcher_params go with a matcher name; this matcher is built already");
      matcher = matcher_arg.cast<const PyBuiltMatcher&>().matcher;
    } else {
      const std::string name = matcher_arg.is_none() ? default_tracker_matcher(tracker_name) : matcher_arg.cast<std::string>();
      SharedParams shared;
      if (range_m) shared.range_m = *range_m;
      const auto config = make_matcher_config(name, from_python(matcher_params), shared);
      py::gil_scoped_release release;
      matcher = config->build(plan.plan);
    }
    ObservationParams base;
    const nlohmann::json observe_overrides = from_python(observe_params);
    apply_overrides(base, observe_overrides);
    WalkTrackingOptions options;
    options.observation_params = [base, path_given = observe_overrides.contains("path")](const Scan& scan) {
      ObservationParams p = base;
      if (!path_given && scan.sensor == "lidar") p.path = ObservationPath::kLidar;  // the path follows the sensor
      return p;
    };
    if (depth_dir) options.depth_dir = *depth_dir;
    options.depth_file.kind = parse_depth_kind(depth_kind);
    options.depth_file.integer_unit_m = depth_unit_m;
    PyTrack out;
    const std::unique_ptr<Tracker> tracker = tracker_config->build(plan.plan);
    {
      py::gil_scoped_release release;
      try {
        out.track = track_walk_folder(walk.dir, walk.record, *matcher, *tracker, options);
      } catch (const ExternalMethodError& e) {
        throw InputError(e.what());
      }
    }
    out.tracker = tracker->name();
    out.matcher = matcher->name();
    out.failure = out.track.run.started ? std::string() : out.track.run.failure;
    out.tracker_parameters = tracker->parameters();
    out.matcher_parameters = matcher->parameters();
    if (out.track.run.started) {
      out.metrics = walk_track_metrics(out.track, options.scoring, *tracker);
      for (const TrackRunStep& s : out.track.run.steps)
        out.truth.push_back(walk.record.walk.steps.at(static_cast<std::size_t>(s.step)).T_world_body);
    } else {
      out.metrics = {{"started", false}, {"failure", out.failure}};
    }
    return out;
  }, py::arg("plan"), py::arg("walk"), py::kw_only(), py::arg("tracker") = "pf", py::arg("matcher") = py::none(),
     py::arg("tracker_params") = py::none(), py::arg("matcher_params") = py::none(), py::arg("depth_dir") = py::none(),
     py::arg("depth_kind") = "z", py::arg("depth_unit_m") = 0.001, py::arg("observe_params") = py::none(),
     py::arg("seed") = 1, py::arg("range_m") = py::none(),
     "Sequential localization of a walk (a Walk or its folder), as `floorcast track`: tracker pf | hist (params: "
     "their parameters), matcher a name (kernel, ray, one registered with register_matcher, a module) or a Matcher "
     "built once; depth_dir: depth maps made elsewhere for every scan observation (DEPTH_DIR/observations/step_NNNN "
     "or DEPTH_DIR/step_NNNN, named as for load_scan). Returns a TrackResult (per-step errors as numpy, metrics).");

  // ---- scenarios ----
  m.def("run_scenario", [](const std::string& path, const std::string& out, int jobs, bool quiet, const std::string& shard) -> py::object {
    {
      py::gil_scoped_release release;
      const Scenario s = load_scenario(path, data_dir());
      RunRequest request;
      request.jobs = jobs;
      request.shard = shard;
      if (!quiet) {
        request.on_progress = [](const RunProgress& p) {
          if (p.finished == p.to_run || p.finished % 10 == 0)
            std::fprintf(stderr, "progress: %zu/%zu units (%zu resumed)\n", p.finished, p.to_run, p.skipped);
        };
      }
      const RunSummary summary = run_scenario(s, out, request);
      if (summary.summary_md && !quiet) std::cout << *summary.summary_md << std::flush;
    }
    const std::string summary = (std::filesystem::path(out) / "summary.json").string();
    if (!std::filesystem::is_regular_file(summary)) return py::none();  // a shard: merge_runs reports
    return py::module_::import("json").attr("loads")(read_text_file(summary));
  }, py::arg("scenario"), py::arg("out"), py::arg("jobs") = 0, py::arg("quiet") = true, py::arg("shard") = "0/1",
     "Runs a scenario file (or shard \"I/N\" of it) into run directory `out` (resumable) and returns its summary.json "
     "as a dict (None for a shard: combine the shards with merge_runs). Matchers registered with register_matcher "
     "can be named in it.");
  m.def("merge_runs", [](const std::vector<std::string>& inputs, const std::string& out, bool quiet) {
    {
      py::gil_scoped_release release;
      const MergeSummary m = merge_runs(inputs, out);
      if (!quiet) {
        std::cerr << "merged " << m.copied << " units from " << inputs.size() << " directories into " << out << "\n";
        std::cout << m.summary_md << std::flush;
      }
    }
    return py::module_::import("json").attr("loads")(read_text_file((std::filesystem::path(out) / "summary.json").string()));
  }, py::arg("shards"), py::arg("out"), py::arg("quiet") = true,
     "Combines shard run directories into one run at `out` (as `floorcast merge`) and returns its summary.json");
  m.def("data_dir", &data_dir, "Where floorcast's shipped data (buildings, scenarios) is");
  m.attr("__version__") = FLOORCAST_VERSION;
}
