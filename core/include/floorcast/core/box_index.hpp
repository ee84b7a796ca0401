// The one spatial index of floorcast (issue 28): a static R-tree over axis-aligned boxes
// (Boost.Geometry, bulk-loaded with its packing algorithm), so code that pairs or searches walls,
// rooms or segments asks for the few candidates near a box instead of scanning them all (a
// 1,000,000-wall plan: ~1 s to build, microseconds per query, where the scan was quadratic).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace floorcast {

/// An axis-aligned box [xmin, xmax] x [ymin, ymax] (metres or pixels; the index does not care).
struct IndexBox {
  double xmin = 0.0, ymin = 0.0, xmax = 0.0, ymax = 0.0;
  /// The box grown by `margin` on every side.
  IndexBox grown(double margin) const { return {xmin - margin, ymin - margin, xmax + margin, ymax + margin}; }
};

class BoxIndex {
 public:
  BoxIndex();
  /// Indexes `boxes`; a box's id is its position in the vector. Boxes with a NaN coordinate are
  /// left out (they intersect nothing).
  explicit BoxIndex(const std::vector<IndexBox>& boxes);
  ~BoxIndex();
  BoxIndex(BoxIndex&&) noexcept;
  BoxIndex& operator=(BoxIndex&&) noexcept;

  /// Ids of the boxes that intersect `box` (touching counts), ascending: the order a scan over
  /// all boxes would meet them, so callers that sum or pick the first match stay bit-identical.
  std::vector<std::uint32_t> query(const IndexBox& box) const;
  /// As query(), into `out` (cleared first), to reuse its memory in a loop.
  void query(const IndexBox& box, std::vector<std::uint32_t>& out) const;

  std::size_t size() const { return size_; }

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
  std::size_t size_ = 0;
};

}  // namespace floorcast
