// Scenario files: what to run (buildings, observation sampling, sensor, observation path,
// matchers) and a sweep whose axes form a Cartesian product of configurations ("cells").
//
// A scenario is read from YAML, validated with messages naming the file, line and key, then
// resolved: every default filled in, every sweep cell expanded. The resolved form is plain JSON
// (written next to the results) and the structs below (used by the runner).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/eval/metrics.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {

/// One building: a plan file, or a procedural generator spec.
struct BuildingSpec {
  std::string label;      ///< short name used in unit ids and tables (default: file stem / archetype_seed)
  std::string file;       ///< absolute path of a plan file; empty for generated buildings
  std::string archetype;  ///< generator archetype when generated
  std::uint64_t seed = 0; ///< generator seed when generated
};

/// Where observation points are placed (the same points in every sweep cell).
struct SamplingSpec {
  int count = 20;                 ///< observation points per building
  std::uint64_t seed = 1;         ///< sampling seed
  double clearance_m = 0.5;       ///< minimum distance from any wall/obstacle
  bool random_yaw = true;         ///< random true heading per point (else 0)
};

/// How an observation is made at a point.
struct ObservationSpec {
  /// `perfect`: exact visible wall surfaces from the plan (PALMS+ sec. 4.4 proxy, no rendering);
  /// `scan`: simulate a rotating scan with the sensor, then run the observation module.
  std::string source = "perfect";
  double max_range_m = 10.0;   ///< perfect observations: range limit (PALMS+ 4.4: 10 m)
  bool doors_closed = true;    ///< perfect observations: all doors closed (PALMS+ 4.4)
  int rays = 36;               ///< perfect observations: equiangular rays for ray matchers
  std::string sensor = "mono"; ///< scan: sensor preset (perfect, lidar, mono, phone)
  nlohmann::json sensor_params = nlohmann::json::object();  ///< scan: sensor parameter overrides
  std::string setting = "full";          ///< scan: full | partial | single
  std::string path = "mono";             ///< scan: observation path mono | lidar
  std::string scale_alignment = "full";  ///< scan, mono path: full | ground | none
  /// scan, lidar path: pcl | voxelplane (default: the observation module's own default)
  std::string extractor = to_string(LidarPathParams{}.extractor);
  bool mask_glass = false;               ///< scan: drop glass-affected pixels ("PALMS+*")
  /// scan: observation-module parameter overrides (keys as in its to_json).
  nlohmann::json observe_params = nlohmann::json::object();
  std::uint64_t seed = 1;                ///< scan: simulator seed (combined with the point index)
};

/// One configuration of the sweep.
struct CellSpec {
  int index = 0;
  std::string id;                 ///< "c000", "c001", ...
  nlohmann::ordered_json axes;    ///< sweep key -> value of this cell (empty without a sweep)
  ObservationSpec observation;
  /// Matchers under their labels (the keys of the scenario's `matchers` map): registry name +
  /// parameter overrides passed to make_matcher.
  std::vector<MatcherSpec> matchers;
};

struct OutputSpec {
  int heatmaps = 3;  ///< posterior overlays drawn for the first N points of each building
};

/// A row of published numbers shown beside floorcast's in the Markdown tables.
struct PaperReference {
  std::string label;   ///< e.g. "PALMS+ paper, kernel"
  std::string source;  ///< e.g. "PALMS+ sec. 4.4, 4 campus buildings"
  std::string cell;    ///< cell id it compares with; empty = every cell
  std::map<std::string, double> values;  ///< metric name -> value (recalls as fractions)
};

struct Scenario {
  std::string name;
  std::string description;
  std::string source_file;
  std::vector<BuildingSpec> buildings;
  SamplingSpec sampling;
  ScoringParams scoring;
  OutputSpec output;
  std::vector<PaperReference> paper;
  std::vector<std::string> sweep_keys;  ///< sweep axes in file order
  std::vector<CellSpec> cells;          ///< Cartesian product of the axes (one cell without a sweep)
  nlohmann::ordered_json resolved;      ///< the whole resolved configuration (defaults filled)
  std::string hash;                     ///< hex digest of `resolved`, identifies the run
};

/// Reads, validates and resolves a scenario file. Relative building paths are resolved against
/// the scenario's folder, then the source tree root. Throws InputError naming file:line:col and
/// the key on unknown keys, wrong types, bad values, missing files.
Scenario load_scenario(const std::string& path, const std::string& source_root);

/// Rebuilds a scenario from its resolved JSON (as written next to results) without touching any
/// file: used by `floorcast merge` and resumed runs. Throws InputError if it is not valid.
Scenario scenario_from_resolved(const nlohmann::json& resolved, const std::string& source);

/// Same from YAML text (`source` names it in messages; `base_dir` resolves relative paths).
Scenario parse_scenario(const std::string& yaml_text, const std::string& source, const std::string& base_dir,
                        const std::string& source_root);

}  // namespace floorcast
