// The semantic bird's-eye view (BEV) of the floor-plan localization thesis (seed paper 004,
// sec. 3.3-3.4): for each of W image columns (a vertical plane through the camera centre, i.e. an
// azimuth in the observer frame) and each of D log-spaced depth bins, a distribution over classes
// (wall, window, door, empty; or occupied, empty without semantics, Table 4.3).
//
// Two kinds of value live here:
// - the sensor-side semantic annotation of a view (SemanticHit): what the horizontal ray of one
//   image column meets at camera height, nearest first (the simulator writes it, a labelled mesh
//   or a labelling tool can; it is the truth a BEV predictor turns into a prediction);
// - the BEV itself (BevPrediction): a network's output, a simulated predictor's, or the one-hot
//   rendering of a floor plan (render_bev_column).
// Plan-independent (core).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace floorcast {

/// What a column's horizontal ray meets. Values are stable (files).
enum class SemanticClass : std::uint8_t {
  kWall = 1,        ///< solid wall: stops the ray
  kWindow = 2,      ///< window pane or glass wall (the ray passes)
  kDoorOpen = 3,    ///< open doorway (the ray passes)
  kDoorClosed = 4,  ///< closed door leaf (a camera does not see past it; the thesis' plan rays pass)
  kFurniture = 5,   ///< clutter, furniture (not in floor plans)
};

/// "wall", "window", "door_open", "door_closed", "furniture".
const char* semantic_class_name(SemanticClass label);
/// Inverse of semantic_class_name; false if unknown.
bool semantic_class_from_name(const std::string& name, SemanticClass& label);

/// One element a horizontal ray meets: its class and the horizontal distance from the camera
/// centre to where the ray enters it, metres.
struct SemanticHit {
  SemanticClass label = SemanticClass::kWall;
  double range_m = 0.0;
  bool operator==(const SemanticHit& o) const { return label == o.label && range_m == o.range_m; }
};

/// Class sets of a BEV: the thesis' semantic classes, or its no-semantics variant (Table 4.3:
/// doors removed, walls and windows one occupied class).
enum class BevClasses { kSemantic, kOccupancy };

/// Class indices of the semantic set.
constexpr int kBevWall = 0, kBevWindow = 1, kBevDoor = 2, kBevEmpty = 3;
/// Class indices of the occupancy set.
constexpr int kBevOccupied = 0, kBevFree = 1;

int bev_class_count(BevClasses classes);           ///< 4 or 2
int bev_empty_class(BevClasses classes);           ///< kBevEmpty or kBevFree
const char* bev_classes_name(BevClasses classes);  ///< "semantic" or "occupancy"
bool bev_classes_from_name(const std::string& name, BevClasses& classes);
/// {"wall", "window", "door", "empty"} or {"occupied", "empty"}.
std::vector<std::string> bev_class_names(BevClasses classes);

/// Log-spaced depth bins (thesis sec. 3.3.3: "D log distributed depth bins"): bin k covers
/// [min * q^k, min * q^(k+1)) with q = (max / min)^(1 / count); a range below min falls into
/// bin 0, a range >= max into none.
struct BevDepthBins {
  int count = 32;
  double min_m = 0.3;
  double max_m = 10.0;

  /// Bin of a horizontal range, or -1 when it is >= max_m (or not finite).
  int bin_of(double range_m) const;
  /// Edge k (k = 0..count): edge 0 = min_m, edge count = max_m.
  double edge_m(int k) const;
  /// Geometric centre of bin k.
  double centre_m(int k) const;
  /// Throws InputError (naming `who`) unless 1 <= count <= 255 and 0 < min < max are finite.
  void check(const std::string& who) const;
  bool operator==(const BevDepthBins& o) const { return count == o.count && min_m == o.min_m && max_m == o.max_m; }
};

/// A BEV: probabilities of W columns x D depth bins x C classes, each (column, bin) a
/// distribution over the classes (the thesis' softmax over classes, sec. 5.1).
struct BevPrediction {
  BevClasses classes = BevClasses::kSemantic;
  BevDepthBins bins;
  /// Azimuth of each column in the observer frame (CCW from the heading +x), radians. A
  /// perspective view's columns run left to right in the image, i.e. in decreasing azimuth.
  std::vector<double> column_azimuth_rad;
  /// W x D x C, index (w * D + d) * C + c.
  std::vector<float> probabilities;

  int num_columns() const { return static_cast<int>(column_azimuth_rad.size()); }
  int num_classes() const { return bev_class_count(classes); }
  bool empty() const { return column_azimuth_rad.empty(); }
  float p(int w, int d, int c) const {
    return probabilities[(static_cast<std::size_t>(w) * bins.count + static_cast<std::size_t>(d)) * num_classes() +
                         static_cast<std::size_t>(c)];
  }
  float& p(int w, int d, int c) {
    return probabilities[(static_cast<std::size_t>(w) * bins.count + static_cast<std::size_t>(d)) * num_classes() +
                         static_cast<std::size_t>(c)];
  }
  /// Throws InputError naming `who` unless: bins valid, at least one column, finite azimuths,
  /// W * D * C probabilities, each finite in [0, 1] and each (column, bin) summing to 1 within
  /// 1e-3.
  void check(const std::string& who) const;
};

/// The one-hot rendering of one column (the thesis' ray casting, sec. 3.3.4, and the B_s of Eq.
/// 3.3): the class index of every depth bin, written into class_of_bin[0..bins.count).
/// - semantic: doors (open and closed) and windows let the ray pass and mark their bin; the first
///   wall stops it and marks its bin; furniture is not drawn (floor plans have none);
/// - occupancy (no semantics): walls and windows are one occupied class and stop the ray; doors
///   are removed; furniture is not drawn.
/// Every other bin, including every bin beyond the stop, is empty. Hits must be nearest first; a
/// later hit in an already marked bin overwrites it (the stopping wall wins its bin).
void render_bev_column(const std::vector<SemanticHit>& hits, BevClasses classes, const BevDepthBins& bins,
                       int* class_of_bin);

/// A one-hot BEV (probability 1 on the rendered class of every bin) from per-column hits.
BevPrediction one_hot_bev(const std::vector<std::vector<SemanticHit>>& column_hits,
                          const std::vector<double>& column_azimuth_rad, BevClasses classes, const BevDepthBins& bins);

/// Azimuths (observer frame) of n equiangular columns around the full circle: column i at
/// 2 pi i / n (CCW), i.e. the same convention as Observation2D::ray_ranges_m.
std::vector<double> full_circle_azimuths(int n);

}  // namespace floorcast
