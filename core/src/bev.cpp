#include "floorcast/core/bev.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "floorcast/core/math.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

const char* semantic_class_name(SemanticClass label) {
  switch (label) {
    case SemanticClass::kWall: return "wall";
    case SemanticClass::kWindow: return "window";
    case SemanticClass::kDoorOpen: return "door_open";
    case SemanticClass::kDoorClosed: return "door_closed";
    case SemanticClass::kFurniture: return "furniture";
  }
  return "unknown";
}

bool semantic_class_from_name(const std::string& name, SemanticClass& label) {
  for (SemanticClass c : {SemanticClass::kWall, SemanticClass::kWindow, SemanticClass::kDoorOpen,
                          SemanticClass::kDoorClosed, SemanticClass::kFurniture}) {
    if (name == semantic_class_name(c)) {
      label = c;
      return true;
    }
  }
  return false;
}

int bev_class_count(BevClasses classes) { return classes == BevClasses::kSemantic ? 4 : 2; }
int bev_empty_class(BevClasses classes) { return classes == BevClasses::kSemantic ? kBevEmpty : kBevFree; }
const char* bev_classes_name(BevClasses classes) { return classes == BevClasses::kSemantic ? "semantic" : "occupancy"; }

bool bev_classes_from_name(const std::string& name, BevClasses& classes) {
  if (name == "semantic") {
    classes = BevClasses::kSemantic;
    return true;
  }
  if (name == "occupancy") {
    classes = BevClasses::kOccupancy;
    return true;
  }
  return false;
}

std::vector<std::string> bev_class_names(BevClasses classes) {
  if (classes == BevClasses::kSemantic) return {"wall", "window", "door", "empty"};
  return {"occupied", "empty"};
}

int BevDepthBins::bin_of(double range_m) const {
  if (!(range_m < max_m)) return -1;
  if (range_m < min_m) return 0;
  const int k = static_cast<int>(std::floor(count * std::log(range_m / min_m) / std::log(max_m / min_m)));
  // Rounding at the edges: keep the bin consistent with edge_m.
  if (k >= count) return count - 1;
  if (k > 0 && range_m < edge_m(k)) return k - 1;
  if (k + 1 < count && range_m >= edge_m(k + 1)) return k + 1;
  return k;
}

double BevDepthBins::edge_m(int k) const {
  if (k <= 0) return min_m;
  if (k >= count) return max_m;
  return min_m * std::pow(max_m / min_m, static_cast<double>(k) / count);
}

double BevDepthBins::centre_m(int k) const { return std::sqrt(edge_m(k) * edge_m(k + 1)); }

void BevDepthBins::check(const std::string& who) const {
  if (count < 1 || count > 255) throw InputError(who + ": depth_bins must be in [1, 255], got " + std::to_string(count));
  if (!std::isfinite(min_m) || !std::isfinite(max_m) || !(min_m > 0.0) || !(max_m > min_m)) {
    throw InputError(who + ": depth bins need 0 < min_depth_m < max_depth_m (got " + std::to_string(min_m) + ", " +
                     std::to_string(max_m) + ")");
  }
}

void BevPrediction::check(const std::string& who) const {
  bins.check(who);
  if (column_azimuth_rad.empty()) throw InputError(who + ": BEV has no columns");
  for (std::size_t w = 0; w < column_azimuth_rad.size(); ++w) {
    if (!std::isfinite(column_azimuth_rad[w])) {
      throw InputError(who + ": BEV column " + std::to_string(w) + " has a non-finite azimuth");
    }
  }
  const int W = num_columns(), D = bins.count, C = num_classes();
  const std::size_t n = static_cast<std::size_t>(W) * D * C;
  if (probabilities.size() != n) {
    throw InputError(who + ": BEV has " + std::to_string(probabilities.size()) + " probabilities, expected W x D x C = " +
                     std::to_string(W) + " x " + std::to_string(D) + " x " + std::to_string(C));
  }
  for (int w = 0; w < W; ++w) {
    for (int d = 0; d < D; ++d) {
      double sum = 0.0;
      for (int c = 0; c < C; ++c) {
        const float v = p(w, d, c);
        if (!std::isfinite(v) || v < 0.0f || v > 1.0f + 1e-6f) {
          throw InputError(who + ": BEV probability at column " + std::to_string(w) + ", bin " + std::to_string(d) +
                           ", class " + std::to_string(c) + " is not in [0, 1]");
        }
        sum += v;
      }
      if (std::abs(sum - 1.0) > 1e-3) {
        throw InputError(who + ": BEV probabilities at column " + std::to_string(w) + ", bin " + std::to_string(d) +
                         " sum to " + std::to_string(sum) + ", not 1 (a distribution over the classes)");
      }
    }
  }
}

void render_bev_column(const std::vector<SemanticHit>& hits, BevClasses classes, const BevDepthBins& bins,
                       int* class_of_bin) {
  const int empty = bev_empty_class(classes);
  for (int d = 0; d < bins.count; ++d) class_of_bin[d] = empty;
  for (const SemanticHit& h : hits) {
    int cls = -1;
    bool stop = false;
    if (classes == BevClasses::kSemantic) {
      switch (h.label) {
        case SemanticClass::kWall: cls = kBevWall; stop = true; break;
        case SemanticClass::kWindow: cls = kBevWindow; break;
        case SemanticClass::kDoorOpen:
        case SemanticClass::kDoorClosed: cls = kBevDoor; break;
        case SemanticClass::kFurniture: break;
      }
    } else {
      if (h.label == SemanticClass::kWall || h.label == SemanticClass::kWindow) {
        cls = kBevOccupied;
        stop = true;
      }
    }
    if (cls < 0) continue;
    const int d = bins.bin_of(h.range_m);
    if (d < 0) break;  // beyond the last bin (hits are nearest first)
    class_of_bin[d] = cls;
    if (stop) break;
  }
}

BevPrediction one_hot_bev(const std::vector<std::vector<SemanticHit>>& column_hits,
                          const std::vector<double>& column_azimuth_rad, BevClasses classes, const BevDepthBins& bins) {
  if (column_hits.size() != column_azimuth_rad.size()) {
    throw std::invalid_argument("one_hot_bev: one hit list per column azimuth");
  }
  BevPrediction b;
  b.classes = classes;
  b.bins = bins;
  b.column_azimuth_rad = column_azimuth_rad;
  const int W = static_cast<int>(column_hits.size()), D = bins.count, C = bev_class_count(classes);
  b.probabilities.assign(static_cast<std::size_t>(W) * D * C, 0.0f);
  std::vector<int> cls(static_cast<std::size_t>(D));
  for (int w = 0; w < W; ++w) {
    render_bev_column(column_hits[static_cast<std::size_t>(w)], classes, bins, cls.data());
    for (int d = 0; d < D; ++d) b.p(w, d, cls[static_cast<std::size_t>(d)]) = 1.0f;
  }
  return b;
}

std::vector<double> full_circle_azimuths(int n) {
  std::vector<double> a(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) a[static_cast<std::size_t>(i)] = 2.0 * kPi * i / n;
  return a;
}

}  // namespace floorcast
