// Scenario files: what to run (buildings, observation sampling, sensor, observation path,
// matchers) and a sweep whose axes form a Cartesian product of configurations ("cells").
//
// A scenario is read from YAML, validated with messages naming the file, line and key, then
// resolved: every default filled in, every sweep cell expanded. The resolved form is plain JSON
// (written next to the results) and the structs below (used by the runner).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/eval/metrics.hpp"
#include "floorcast/eval/sequential.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {

/// One building: a plan file, or a procedural generator spec.
struct BuildingSpec {
  std::string label;      ///< short name used in unit ids and tables (default: file stem / archetype_seed)
  std::string file;       ///< absolute path of a plan file; empty for generated buildings
  /// The plan file as the scenario names it (relative to the scenario's folder or the data
  /// folder), and the hash of its bytes: what the resolved configuration records, so that the
  /// configuration hash covers the plan's content, never where it lies.
  std::string file_given;
  std::string file_hash;
  std::string archetype;  ///< generator archetype when generated
  std::uint64_t seed = 0; ///< generator seed when generated
  /// Optional rooms file (`floorcast plan generate --rooms`) labelling the plan's rooms, for
  /// sampling.region_kinds; generated buildings carry their rooms themselves.
  std::string rooms_file;
  std::string rooms_given;  ///< the rooms file as the scenario names it
  std::string rooms_hash;   ///< hash of its bytes
  /// Resolved at load: how this building's observation points are placed: "transitional"
  /// (rooms of transitional kinds), "transitional_or_uniform" (the same, uniform when they cannot
  /// be sampled), "kinds" (rooms of sampling.region_kinds), "uniform" (asked
  /// for), or "uniform_unlabelled" (sampling.region transitional, but the plan has no room labels:
  /// the whole free space, stated in the resolved configuration and the summary).
  std::string sampling_region;
};

/// Where observation points are placed (the same points in every sweep cell).
struct SamplingSpec {
  int count = 20;                 ///< observation points per building
  std::uint64_t seed = 1;         ///< sampling seed
  double clearance_m = 0.5;       ///< minimum distance from any wall/obstacle
  bool random_yaw = true;         ///< random true heading per point (else 0)
  /// Where points go. "transitional" (default, the PALMS+ sec. 4.4 protocol): inside rooms of the
  /// transitional kinds (rooms.hpp: hallways, corridors, lobbies, atria, ...) of plans with room
  /// labels (generated buildings, plan files with "rooms", imported OSM/IMDF/GeoJSON plans, a
  /// rooms file); a plan without labels is sampled uniformly, and the resolved configuration and
  /// summary say so. "transitional_or_uniform": transitional where the plan's transitional spaces
  /// can be sampled, else (none, outside the free space, too narrow for the clearance) uniform, the
  /// reason in the run log. "uniform": the whole free space. "kinds": rooms of region_kinds (labels
  /// required). A point belongs to the smallest labelled room containing it (room_at).
  std::string region = "transitional";
  /// Room kinds for region "kinds" (giving region_kinds implies it; the word "transitional"
  /// expands to the transitional kinds).
  std::vector<std::string> region_kinds;
  /// Negative samples per building (scoring with rejection, VoxelPlane-Reloc sec. "Simulation
  /// dataset": submaps "that were not part of the specific scenario"): observations made at the
  /// points of the scenario's other buildings (another building or another level: round robin
  /// over them), matched against this building's plan. A matcher should answer "not localized".
  /// 0 = none; needs at least two buildings.
  int negatives = 0;
};

enum class ObservationSource { kPerfect, kScan };

/// How an observation is made at a point, with every stage's parameters parsed and complete.
/// The scenario keys (observation.*) are documented in scenarios/README.md.
struct ObservationSpec {
  /// perfect: exact visible wall surfaces from the plan (PALMS+ sec. 4.4 proxy, no rendering);
  /// scan: simulate a rotating scan with the sensor, then run the observation module.
  ObservationSource source = ObservationSource::kPerfect;
  /// source perfect: the perfect observer (range and blocking from the scenario's `shared`
  /// block unless observation.max_range_m / doors_closed override them; rays).
  PerfectObservationParams perfect;
  /// source scan: the sensor preset with its overrides and the setting (the seed is set per unit).
  ScanParams scan;
  /// source scan: the observation module (path, scale alignment, extractor, glass masking and
  /// observe_params overrides applied).
  ObservationParams observe;
  std::uint64_t seed = 1;  ///< scan: simulator seed (combined with building and point index)
  /// scan: depth maps made elsewhere (a depth network run on the colour views `floorcast export`
  /// writes) replace the simulated depth; unit u's maps at walk step s are in
  /// depth_dir/unit_scan_folder(scenario, u, s) (scenarios/runner.hpp). Empty: the simulated depth.
  std::string depth_dir;        ///< found at load (absolute), or as given in a resolved scenario
  std::string depth_dir_given;  ///< as the scenario names it (what the resolved configuration records)
  DepthFileOptions depth_file;
};

/// A tracker under a label: its configuration (parsed and complete at load), and the label of
/// the matcher whose posteriors it takes.
struct TrackerSpec {
  std::string label;
  std::shared_ptr<const TrackerConfig> config;
  std::string matcher;
};

/// Sequential scenarios (PALMS: scan, then walk): every work unit is a walk from the sampled
/// start, with odometry and observations on a schedule; matchers score the initial observation
/// as in single-shot scenarios, and every tracker follows the walk.
struct SequentialSpec {
  WalkParams walk;
  OdometryParams odometry;
  ObservationSchedule schedule;
  std::vector<TrackerSpec> trackers;
};

/// One configuration of the sweep.
struct CellSpec {
  int index = 0;
  std::string id;                 ///< "c000", "c001", ...
  nlohmann::ordered_json axes;    ///< sweep key -> value of this cell (empty without a sweep)
  ObservationSpec observation;
  /// Matchers under their labels (the keys of the scenario's `matchers` map), configurations
  /// parsed at load (shared quantities applied, then the cell's explicit parameters).
  std::vector<MatcherSpec> matchers;
  /// Set in sequential scenarios (a `walk`, `odometry`, `schedule` or `trackers` key).
  std::optional<SequentialSpec> sequential;
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
  /// Quantities every stage shares unless it overrides them (the `shared` block).
  SharedParams shared;
  /// Sequential scenarios: the sequential metrics' settings (scoring.sequential).
  SequentialScoring sequential_scoring;
  std::vector<std::string> sweep_keys;  ///< sweep keys in file order
  /// The sweep's axes in file order, each the keys that vary together (zipped); one key each in
  /// the mapping form. Reports draw one accuracy plot per axis.
  std::vector<std::vector<std::string>> sweep_axes;
  std::vector<CellSpec> cells;          ///< Cartesian product of the axes (one cell without a sweep)
  /// The whole resolved configuration: the scenario as written with every default filled in,
  /// plus per cell the complete parameters of every stage (perfect observer or sensor and
  /// observation module; matchers). Written next to every result.
  nlohmann::ordered_json resolved;
  std::string hash;                     ///< scenario_hash(resolved): identifies the run
};

/// The hash identifying a resolved configuration: over its content only. Building plan and rooms
/// files count by the hash of their bytes (file_hash, rooms_hash), never by their path, so the
/// same scenario gives the same hash in another checkout, folder or installation; an external
/// matcher program's files count by file name (its `version` by content, match/external.hpp).
std::string scenario_hash(const nlohmann::json& resolved);

/// The keys of the scenario blocks sampling, observation, scoring and output with their
/// defaults, types, ranges and meanings (from the field lists the loader reads them with).
std::vector<std::pair<std::string, std::vector<FieldInfo>>> scenario_block_fields();

/// The rooms of a generator rooms file (`floorcast plan generate --rooms FILE`:
/// {"rooms": [{"id", "kind", "polygon": [[x, y], ...]}, ...]}). Throws InputError naming the file
/// and element when it is not one.
std::vector<Room> load_rooms_file(const std::string& path);

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
