// Walls drawn as polygons with their thickness (import_common.hpp, walls_from_polygons).
#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/grid.hpp"
#include "import_common.hpp"

namespace floorcast::import_detail {
namespace {

/// A ring drawn closed (last = first) without its repeated vertex.
std::vector<Vec2> open_ring(std::vector<Vec2> ring) {
  if (ring.size() > 1 && (ring.front() - ring.back()).norm() < 1e-9) ring.pop_back();
  return ring;
}

/// A quadrilateral whose opposite sides are parallel and adjacent sides perpendicular (within
/// 1 degree): its axis (midpoints of the short sides) and thickness (mean short side).
bool rectangle_wall(const std::vector<Vec2>& ring, Segment2& axis, double& thickness_m) {
  if (ring.size() != 4) return false;
  Vec2 e[4];
  for (int k = 0; k < 4; ++k) e[k] = ring[static_cast<std::size_t>((k + 1) % 4)] - ring[static_cast<std::size_t>(k)];
  for (int k = 0; k < 4; ++k) {
    if (!(e[k].norm() > 0.0)) return false;
  }
  const double tol = std::sin(1.0 * 3.14159265358979323846 / 180.0);
  auto cross = [](const Vec2& a, const Vec2& b) { return std::abs(a.x() * b.y() - a.y() * b.x()) / (a.norm() * b.norm()); };
  auto dot = [](const Vec2& a, const Vec2& b) { return std::abs(a.dot(b)) / (a.norm() * b.norm()); };
  if (cross(e[0], e[2]) > tol || cross(e[1], e[3]) > tol || dot(e[0], e[1]) > tol) return false;
  // Short sides: the pair with the smaller mean length.
  const bool first_short = e[0].norm() + e[2].norm() <= e[1].norm() + e[3].norm();
  const int s0 = first_short ? 0 : 1, s1 = first_short ? 2 : 3;
  const Vec2 m0 = ring[static_cast<std::size_t>(s0)] + 0.5 * e[s0];
  const Vec2 m1 = ring[static_cast<std::size_t>(s1)] + 0.5 * e[s1];
  axis = {m0, m1};
  thickness_m = 0.5 * (e[s0].norm() + e[s1].norm());
  return axis.length_m() > 0.0;
}

}  // namespace

std::vector<Wall> walls_from_polygons(const std::vector<WallPolygon>& polygons, const ImportOptions& options,
                                      std::vector<std::string>& notes, int& rectangles, int& traced) {
  rectangles = traced = 0;
  std::vector<Wall> out;
  std::vector<const WallPolygon*> complex;
  for (const WallPolygon& p : polygons) {
    Segment2 axis;
    double thickness = 0.0;
    if (p.rings.size() == 1 && rectangle_wall(open_ring(p.rings.front()), axis, thickness)) {
      if (thickness > 5.0) {
        notes.push_back(p.what + ": a wall polygon " + fmt(std::round(thickness * 100.0) / 100.0) +
                        " m thick is no wall (more than 5 m), skipped");
        continue;
      }
      Wall w;
      w.id = p.id;
      w.a_m = axis.a_m;
      w.b_m = axis.b_m;
      w.thickness_m = thickness;
      w.material = p.glass ? WallMaterial::kGlass : WallMaterial::kSolid;
      out.push_back(std::move(w));
      ++rectangles;
    } else {
      complex.push_back(&p);
    }
  }
  if (complex.empty()) return out;
  // Other shapes (L and T pieces, a floor's walls as one polygon with the rooms as holes): drawn on
  // a fine raster and vectorised like an occupancy image, each wall's thickness measured.
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const WallPolygon* p : complex) {
    for (const auto& ring : p->rings) {
      for (const Vec2& v : ring) {
        xmin = std::min(xmin, v.x());
        xmax = std::max(xmax, v.x());
        ymin = std::min(ymin, v.y());
        ymax = std::max(ymax, v.y());
      }
    }
  }
  constexpr double kMaxCells = 2.0e7;
  double res = 0.02;
  const double margin = 0.2;
  const double area = (xmax - xmin + 2.0 * margin) * (ymax - ymin + 2.0 * margin);
  if (area / (res * res) > kMaxCells) res = std::sqrt(area / kMaxCells);
  const double w_px = std::ceil((xmax - xmin + 2.0 * margin) / res), h_px = std::ceil((ymax - ymin + 2.0 * margin) / res);
  check_raster_budget(w_px, h_px, res, 4.0, "wall polygons");
  const int W = static_cast<int>(w_px), H = static_cast<int>(h_px);
  const Vec2 origin(xmin - margin, ymin - margin);  // the image's bottom-left corner
  cv::Mat mask(H, W, CV_8U, cv::Scalar(0));
  constexpr int kShift = 4;
  auto to_px = [&](const std::vector<Vec2>& ring) {
    std::vector<cv::Point> pts;
    for (const Vec2& v : ring) {
      // Image row 0 is the top (largest y); pixel centres at integer coordinates.
      const double c = (v.x() - origin.x()) / res - 0.5, r = (H - (v.y() - origin.y()) / res) - 0.5;
      pts.emplace_back(static_cast<int>(std::lround(c * (1 << kShift))), static_cast<int>(std::lround(r * (1 << kShift))));
    }
    return pts;
  };
  for (const WallPolygon* p : complex) {
    for (std::size_t r = 0; r < p->rings.size(); ++r) {
      const cv::Scalar value = r == 0 ? cv::Scalar(255) : cv::Scalar(0);  // outer ring, then holes
      cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{to_px(p->rings[r])}, value, cv::LINE_8, kShift);
    }
    ++traced;
  }
  ImportOptions opts = options;
  opts.png_origin_m = origin;
  std::vector<Wall> walls = vectorize_occupancy(mask, res, opts, &notes);
  for (std::size_t k = 0; k < walls.size(); ++k) {
    walls[k].id = "wallpolygon-" + std::to_string(k + 1);
    out.push_back(std::move(walls[k]));
  }
  notes.push_back(std::to_string(traced) + " wall polygon(s) that are no rectangle traced on a " + fmt(res * 100.0) +
                  " cm raster into " + std::to_string(walls.size()) + " walls with measured thickness");
  return out;
}

}  // namespace floorcast::import_detail
