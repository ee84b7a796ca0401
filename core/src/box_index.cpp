#include "floorcast/core/box_index.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/box.hpp>
#include <boost/geometry/geometries/point.hpp>
#include <boost/geometry/index/rtree.hpp>

namespace floorcast {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using Point = bg::model::point<double, 2, bg::cs::cartesian>;
using Box = bg::model::box<Point>;
using Value = std::pair<Box, std::uint32_t>;

Box to_box(const IndexBox& b) { return Box(Point(b.xmin, b.ymin), Point(b.xmax, b.ymax)); }

/// Output iterator of the R-tree query: appends the ids of the values it is given.
struct IdInserter {
  std::vector<std::uint32_t>* out;
  using iterator_category = std::output_iterator_tag;
  using value_type = void;
  using difference_type = std::ptrdiff_t;
  using pointer = void;
  using reference = void;
  IdInserter& operator=(const Value& v) {
    out->push_back(v.second);
    return *this;
  }
  IdInserter& operator*() { return *this; }
  IdInserter& operator++() { return *this; }
  IdInserter operator++(int) { return *this; }
};

}  // namespace

struct BoxIndex::Tree {
  bgi::rtree<Value, bgi::rstar<16>> rtree;
};

BoxIndex::BoxIndex() : tree_(std::make_unique<Tree>()) {}

BoxIndex::BoxIndex(const std::vector<IndexBox>& boxes) : tree_(std::make_unique<Tree>()), size_(boxes.size()) {
  std::vector<Value> values;
  values.reserve(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const IndexBox& b = boxes[i];
    if (std::isnan(b.xmin) || std::isnan(b.ymin) || std::isnan(b.xmax) || std::isnan(b.ymax)) continue;
    IndexBox n{std::min(b.xmin, b.xmax), std::min(b.ymin, b.ymax), std::max(b.xmin, b.xmax), std::max(b.ymin, b.ymax)};
    values.emplace_back(to_box(n), static_cast<std::uint32_t>(i));
  }
  // The range constructor bulk-loads with the packing algorithm (STR-like): O(n log n).
  tree_->rtree = bgi::rtree<Value, bgi::rstar<16>>(values.begin(), values.end());
}

BoxIndex::~BoxIndex() = default;
BoxIndex::BoxIndex(BoxIndex&&) noexcept = default;
BoxIndex& BoxIndex::operator=(BoxIndex&&) noexcept = default;

void BoxIndex::query(const IndexBox& box, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (std::isnan(box.xmin) || std::isnan(box.ymin) || std::isnan(box.xmax) || std::isnan(box.ymax)) return;
  tree_->rtree.query(bgi::intersects(to_box(box)), IdInserter{&out});
  std::sort(out.begin(), out.end());
}

std::vector<std::uint32_t> BoxIndex::query(const IndexBox& box) const {
  std::vector<std::uint32_t> out;
  query(box, out);
  return out;
}

}  // namespace floorcast
