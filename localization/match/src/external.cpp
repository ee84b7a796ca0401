#include "floorcast/match/external.hpp"

#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/module.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/process.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/matcher_module.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OJson = nlohmann::ordered_json;

// ---- the run-time registry ----

struct Registry {
  std::mutex mutex;
  std::map<std::string, MatcherConfigParser> parsers;
};
Registry& registry() {
  static Registry r;
  return r;
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// ---- modules: adapters turning a module's exceptions into floorcast's reporting ----

class ModuleMatcher final : public Matcher {
 public:
  ModuleMatcher(std::unique_ptr<Matcher> inner, std::string who) : inner_(std::move(inner)), who_(std::move(who)) {}
  std::string name() const override { return inner_->name(); }
  OJson parameters() const override { return inner_->parameters(); }
  double precompute_s() const override { return inner_->precompute_s(); }
  std::size_t precompute_bytes() const override { return inner_->precompute_bytes(); }
  BlockingOptions blocking() const override { return inner_->blocking(); }
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override {
    try {
      return inner_->match(observation, request);
    } catch (const ExternalMethodError&) {
      throw;
    } catch (const std::exception& e) {
      throw ExternalMethodError(who_ + ": match failed: " + e.what());
    }
  }
  using Matcher::match;

 private:
  std::unique_ptr<Matcher> inner_;
  std::string who_;
};

class ModuleConfig final : public MatcherConfig {
 public:
  ModuleConfig(std::shared_ptr<const MatcherConfig> inner, std::string name, std::string who)
      : inner_(std::move(inner)), name_(std::move(name)), who_(std::move(who)) {}
  std::string name() const override { return name_; }
  OJson parameters() const override { return inner_->parameters(); }
  std::unique_ptr<Matcher> build(const FloorPlan& plan) const override {
    try {
      return std::make_unique<ModuleMatcher>(inner_->build(plan), who_);
    } catch (const std::exception& e) {
      throw InputError(who_ + ": preparing the plan failed: " + e.what());
    }
  }

 private:
  std::shared_ptr<const MatcherConfig> inner_;
  std::string name_, who_;
};

MatcherConfigParser module_parser(const std::string& name, const std::string& path) {
  const std::string module = matcher_module::module_name(name);
  void* handle = load_module(module);
  const auto entry_fn = reinterpret_cast<matcher_module::EntryFn>(module_symbol(handle, module, matcher_module::kEntrySymbol));
  const matcher_module::Entry* entry = entry_fn();
  if (entry == nullptr || entry->api_version != matcher_module::kApiVersion || entry->parse == nullptr) {
    throw InputError("matcher module " + path + " was built for interface version " +
                     std::to_string(entry ? entry->api_version : -1) + ", this floorcast has " +
                     std::to_string(matcher_module::kApiVersion) + ": rebuild it against this floorcast's headers");
  }
  const std::string who = "matcher \"" + name + "\" (module " + path + ")";
  return [entry, name, who](const Json& overrides, const SharedParams& shared) -> std::shared_ptr<const MatcherConfig> {
    std::string error, key;
    std::shared_ptr<const MatcherConfig> config = entry->parse(overrides, shared, &error, &key);
    if (!config) {
      if (!key.empty()) throw ParameterError(who + ": " + error, key);
      throw InputError(who + ": " + (error.empty() ? std::string("its parser returned nothing") : error));
    }
    return std::make_shared<ModuleConfig>(std::move(config), name, who);
  };
}

// ---- reading an external program's answer ----

cv::Mat npy_slice(const NpyArray& a, std::size_t slice, const std::string& source) {
  const int h = static_cast<int>(a.shape[1]), w = static_cast<int>(a.shape[2]);
  cv::Mat m(h, w, CV_32F);
  const std::size_t plane = static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
  if (a.dtype == "<f4") {
    std::memcpy(m.data, a.data.data() + slice * plane * 4, plane * 4);
  } else if (a.dtype == "<f8") {
    const auto* src = reinterpret_cast<const unsigned char*>(a.data.data()) + slice * plane * 8;
    for (std::size_t i = 0; i < plane; ++i) {
      double d;
      std::memcpy(&d, src + i * 8, 8);
      m.at<float>(static_cast<int>(i)) = static_cast<float>(d);
    }
  } else {
    throw ExternalMethodError(source + ": dtype " + a.dtype + "; expected float32 or float64 scores");
  }
  return m;
}

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + ")";
}

PoseHypothesis pose_from_json(const Json& p, const std::string& where) {
  if (!p.is_object()) throw ExternalMethodError(where + ": expected an object {x_m, y_m, yaw_deg, score}");
  for (const char* k : {"x_m", "y_m", "yaw_deg", "score"})
    if (!p.contains(k) || !p[k].is_number()) throw ExternalMethodError(where + ": \"" + std::string(k) + "\" must be a number");
  PoseHypothesis h;
  h.x_m = p["x_m"].get<double>();
  h.y_m = p["y_m"].get<double>();
  h.yaw_rad = deg_to_rad(p["yaw_deg"].get<double>());
  h.score = p["score"].get<double>();
  return h;
}

std::string command_text(const std::vector<std::string>& command) {
  std::string s;
  for (const std::string& c : command) s += (s.empty() ? "" : " ") + c;
  return s;
}

/// Removes a folder when it goes out of scope.
struct FolderGuard {
  std::string path;
  ~FolderGuard() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

std::string make_temp_folder(const std::string& parent, const std::string& prefix) {
  std::string pattern = (fs::path(parent) / (prefix + "XXXXXX")).string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError("cannot create a temporary folder under " + parent + ": " + std::strerror(errno));
  return pattern;
}

}  // namespace

PosteriorGrid shared_posterior_grid(const FloorPlan& plan, double resolution_m, int yaw_bins, double margin_m) {
  if (!(yaw_bins >= 1 && yaw_bins <= 3600)) throw InputError("posterior grid: yaw_bins must be in [1, 3600]");
  PosteriorGrid g;
  g.grid = grid_for_plan(plan, resolution_m, margin_m);
  for (int k = 0; k < yaw_bins; ++k) g.yaw_rad.push_back(kTwoPi * k / yaw_bins);
  return g;
}

const FieldList<PosteriorGrid>& posterior_grid_fields() {
  using G = PosteriorGrid;
  constexpr double kAny = 1e300;
  static const FieldList<G> f =
      FieldList<G>("posterior grid")
          .number("origin_x_m", [](auto& g) -> auto& { return g.grid.origin_x_m; }, -kAny, kAny,
                  "world x of cell (0, 0)'s corner, m")
          .number("origin_y_m", [](auto& g) -> auto& { return g.grid.origin_y_m; }, -kAny, kAny,
                  "world y of cell (0, 0)'s corner, m")
          .number("resolution_m", [](auto& g) -> auto& { return g.grid.resolution_m_per_px; }, 1e-6, 1e6, "cell size, m")
          .integer("width_px", [](auto& g) -> auto& { return g.grid.width_px; }, 1, 100000, "columns (x)")
          .integer("height_px", [](auto& g) -> auto& { return g.grid.height_px; }, 1, 100000, "rows (y, row 0 = lowest y)")
          .custom(
              "yaw_deg",
              [](OJson& j, const G& g) {
                std::vector<double> deg;
                for (double y : g.yaw_rad) deg.push_back(rad_to_deg(y));
                j["yaw_deg"] = deg;
              },
              [](ParamReader& r, G& g) {
                std::vector<double> deg;
                r.read("yaw_deg", deg, -kAny, kAny);
                if (!deg.empty()) g.yaw_rad.clear();
                for (double d : deg) g.yaw_rad.push_back(deg_to_rad(d));
              },
              "numbers", "heading of each orientation slice, deg");
  return f;
}

OJson posterior_grid_to_json(const PosteriorGrid& g) { return posterior_grid_fields().write(g); }

PosteriorGrid posterior_grid_from_json(const Json& j, const std::string& source) {
  PosteriorGrid g;
  posterior_grid_fields().read_record(g, j, source);
  return g;
}

const FieldList<PosteriorGridParams>& PosteriorGridParams::fields() {
  using P = PosteriorGridParams;
  static const FieldList<P> f =
      FieldList<P>("posterior grid")
          .number("resolution_m", &P::resolution_m, 0.005, 10.0, "cell size of the shared posterior grid, m")
          .integer("yaw_bins", &P::yaw_bins, 1, 3600, "orientations of the shared posterior grid")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the grid around the plan, m");
  return f;
}

MatchResult finish_external_output(ExternalMatchOutput out, const PosteriorGrid& grid, const MatchRequest& request,
                                   const std::string& who) {
  MatchResult res;
  if (out.has_posterior) {
    const PosteriorGrid& g = out.grid;
    if (out.scores.size() != g.yaw_rad.size())
      throw ExternalMethodError(who + ": the posterior has " + std::to_string(out.scores.size()) + " orientation slices, its grid " +
                                std::to_string(g.yaw_rad.size()));
    for (std::size_t s = 0; s < out.scores.size(); ++s) {
      const cv::Mat& m = out.scores[s];
      if (m.type() != CV_32F || m.rows != g.grid.height_px || m.cols != g.grid.width_px)
        throw ExternalMethodError(who + ": posterior slice " + std::to_string(s) + " is " + std::to_string(m.rows) + " x " +
                                  std::to_string(m.cols) + ", the grid " + std::to_string(g.grid.height_px) + " x " +
                                  std::to_string(g.grid.width_px) + " (rows = y, columns = x)");
      cv::Point where;
      if (!cv::checkRange(m, true, &where))
        throw ExternalMethodError(who + ": posterior slice " + std::to_string(s) + " holds a non-finite score at row " +
                                  std::to_string(where.y) + ", column " + std::to_string(where.x));
      double lo = 0.0;
      cv::minMaxLoc(m, &lo, nullptr, nullptr, nullptr);
      if (lo < 0.0) throw ExternalMethodError(who + ": posterior slice " + std::to_string(s) + " holds a negative score (" +
                                              format_general(lo, 4) + "); scores must be >= 0");
    }
    res.posterior.grid = g.grid;
    res.posterior.yaw_rad = g.yaw_rad;
    res.posterior.scores = std::move(out.scores);
    finish_from_posterior(res, request);
    return res;
  }
  for (std::size_t i = 0; i < out.poses.size(); ++i) {
    const PoseHypothesis& p = out.poses[i];
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.yaw_rad) || !std::isfinite(p.score) || !(p.score > 0.0))
      throw ExternalMethodError(who + ": pose " + std::to_string(i) + " is not finite or its score is not > 0");
  }
  std::stable_sort(out.poses.begin(), out.poses.end(),
                   [](const PoseHypothesis& a, const PoseHypothesis& b) { return a.score > b.score; });
  for (PoseHypothesis& p : out.poses) {
    p.yaw_rad = wrap_angle_rad(p.yaw_rad);
    p.slice = p.row = p.col = -1;
  }
  res.grid = grid.grid;
  if (request.output != MatchOutput::kModes) {
    // The poses as a posterior: each pose's score in its cell and nearest orientation slice.
    Posterior& post = res.posterior;
    post.grid = grid.grid;
    post.yaw_rad = grid.yaw_rad;
    for (std::size_t s = 0; s < grid.yaw_rad.size(); ++s) post.scores.emplace_back(cv::Mat::zeros(grid.grid.height_px, grid.grid.width_px, CV_32F));
    for (const PoseHypothesis& p : out.poses) {
      int row = 0, col = 0;
      if (!grid.grid.world_to_cell({p.x_m, p.y_m}, row, col)) continue;
      std::size_t best = 0;
      for (std::size_t s = 1; s < grid.yaw_rad.size(); ++s)
        if (angle_distance_rad(grid.yaw_rad[s], p.yaw_rad) < angle_distance_rad(grid.yaw_rad[best], p.yaw_rad)) best = s;
      float& cell = post.scores[best].at<float>(row, col);
      cell = std::max(cell, static_cast<float>(p.score));
    }
    if (request.output == MatchOutput::kMaxOverYaw) {
      res.max_over_yaw = post.max_over_yaw();
      post.scores.clear();
      post.yaw_rad.clear();
    }
  }
  // The modes: the method's best top_k poses (every pose is in the posterior above).
  if (static_cast<int>(out.poses.size()) > std::max(1, request.top_k)) out.poses.resize(static_cast<std::size_t>(std::max(1, request.top_k)));
  res.modes = std::move(out.poses);
  return res;
}

void register_matcher(const std::string& name, MatcherConfigParser parser) {
  if (!valid_name(name)) throw InputError("matcher name \"" + name + "\": use letters, digits, '_' and '-'");
  const std::vector<std::string> builtin = builtin_matcher_names();
  if (std::find(builtin.begin(), builtin.end(), name) != builtin.end())
    throw InputError("matcher name \"" + name + "\" is a built-in matcher; register yours under another name");
  if (!parser) throw InputError("matcher \"" + name + "\": no parser given");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.parsers[name] = std::move(parser);
}

bool unregister_matcher(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.parsers.erase(name) > 0;
}

std::vector<std::string> registered_matcher_names() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [n, p] : r.parsers) names.push_back(n);
  return names;
}

MatcherConfigParser find_external_matcher(const std::string& name, std::string* tried) {
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    if (auto it = r.parsers.find(name); it != r.parsers.end()) return it->second;
  }
  if (!valid_name(name)) return nullptr;
  const std::string module = matcher_module::module_name(name);
  const std::string path = module_path(module);
  if (path.empty()) {
    // Not beside the binary: the dynamic loader's own path may still have it.
    try {
      (void)load_module(module);
    } catch (const InputError& e) {
      if (tried) *tried = e.what();
      return nullptr;
    }
  }
  return module_parser(name, path.empty() ? module + ".so" : path);
}

// ---- the external program matcher ----

void ExternalProgramParams::apply_shared(const SharedParams& shared) { blocking = shared.blocking; }

const FieldList<ExternalProgramParams>& ExternalProgramParams::fields() {
  using P = ExternalProgramParams;
  static const FieldList<P> f =
      FieldList<P>("matcher external")
          .texts("command", &P::command,
                 "the program and its first arguments, e.g. [python3, my_matcher.py]; the request file's path is "
                 "appended (required)")
          .number("timeout_s", &P::timeout_s, 0.001, 1e6, "seconds per observation before the program is killed")
          .flatten(&P::grid, PosteriorGridParams::fields())
          .flatten(&P::blocking, blocking_fields())
          .json("params", &P::program_params, "handed to the program verbatim (request.json \"params\")")
          .text("version", &P::version,
                "part of the configuration hash: change it when the program changes what it answers")
          .check([](const P& p, const ParamReader& r) {
            if (p.command.empty()) r.fail("command", "required: the program and its arguments, e.g. [python3, my_matcher.py]");
            for (const std::string& c : p.command)
              if (c.empty()) r.fail("command", "every element must be a non-empty string");
            if (!p.program_params.is_object()) r.fail("params", "expected an object (handed to the program verbatim)");
          });
  return f;
}

void ExternalProgramParams::apply_overrides(const Json& overrides) { fields().read(*this, overrides); }

OJson ExternalProgramParams::to_json() const { return fields().write(*this); }

ExternalProgramMatcher::ExternalProgramMatcher(const FloorPlan& plan, ExternalProgramParams params)
    : params_(std::move(params)) {
  const auto t0 = std::chrono::steady_clock::now();
  grid_ = params_.grid.make(plan);
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  folder_ = make_temp_folder(ec ? std::string("/tmp") : tmp.string(), "floorcast_external_");
  write_text_file_atomic(folder_ + "/plan.json", floor_plan_to_json(plan));
  precompute_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

ExternalProgramMatcher::~ExternalProgramMatcher() {
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

MatchResult ExternalProgramMatcher::match(const Observation2D& observation, const MatchRequest& request) const {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string who = "external matcher `" + command_text(params_.command) + "`";
  FolderGuard call{make_temp_folder(folder_, "call_")};
  const std::string out_dir = call.path + "/out";
  fs::create_directory(out_dir);
  ObservationRecord record;
  record.observation = observation;
  record.source = "floorcast";
  write_text_file_atomic(call.path + "/observation.json", observation_to_json_text(record));
  OJson req;
  req["protocol"] = "floorcast-matcher/1";
  req["plan"] = folder_ + "/plan.json";
  req["observation"] = call.path + "/observation.json";
  req["output_dir"] = out_dir;
  req["grid"] = posterior_grid_to_json(grid_);
  req["top_k"] = request.top_k;
  req["params"] = params_.program_params;
  write_text_file_atomic(call.path + "/request.json", req.dump(2) + "\n");

  std::vector<std::string> argv = params_.command;
  argv.push_back(call.path + "/request.json");
  ProcessOptions po;
  po.timeout_s = params_.timeout_s;
  po.stdout_path = call.path + "/stdout.txt";
  po.stderr_path = call.path + "/stderr.txt";
  const ProcessResult pr = run_process(argv, po);
  auto failure = [&](const std::string& what) {
    const std::string tail = file_tail(po.stderr_path);
    return ExternalMethodError(who + " " + what + (tail.empty() ? std::string() : "; its standard error ends:\n" + tail));
  };
  if (!pr.ok()) throw failure(pr.describe(params_.timeout_s));

  ExternalMatchOutput out;
  const std::string npy = out_dir + "/posterior.npy", poses = out_dir + "/top_k.json";
  if (fs::exists(npy)) {
    out.has_posterior = true;
    out.grid = grid_;
    if (fs::exists(out_dir + "/grid.json")) {
      try {
        out.grid = posterior_grid_from_json(read_json_file(out_dir + "/grid.json"), who + ": grid.json");
      } catch (const InputError& e) {
        throw ExternalMethodError(e.what());
      }
    }
    NpyArray a;
    try {
      a = read_npy(npy);
    } catch (const InputError& e) {
      throw ExternalMethodError(who + ": " + e.what());
    }
    const std::vector<std::size_t> want = {out.grid.yaw_rad.size(), static_cast<std::size_t>(out.grid.grid.height_px),
                                           static_cast<std::size_t>(out.grid.grid.width_px)};
    if (a.shape != want)
      throw ExternalMethodError(who + ": posterior.npy has shape " + shape_text(a.shape) + ", the grid (yaw, y, x) is " +
                                shape_text(want));
    for (std::size_t s = 0; s < want[0]; ++s) out.scores.push_back(npy_slice(a, s, who + ": posterior.npy"));
  } else if (fs::exists(poses)) {
    Json j;
    try {
      j = read_json_file(poses);
    } catch (const InputError& e) {
      throw ExternalMethodError(who + ": " + e.what());
    }
    if (!j.is_object() || !j.contains("poses") || !j["poses"].is_array())
      throw ExternalMethodError(who + ": top_k.json must be {\"poses\": [{\"x_m\", \"y_m\", \"yaw_deg\", \"score\"}, ...]}");
    for (std::size_t i = 0; i < j["poses"].size(); ++i)
      out.poses.push_back(pose_from_json(j["poses"][i], who + ": top_k.json poses[" + std::to_string(i) + "]"));
  } else {
    throw failure("exited with status 0 but wrote neither posterior.npy nor top_k.json into its output_dir");
  }
  MatchResult res = finish_external_output(std::move(out), grid_, request, who);
  res.match_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.stage_s["program"] = pr.wall_s;
  return res;
}

}  // namespace floorcast
