#include "floorcast/match/distance_volume.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {


double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Writes min(t) into zbuf for every cell centre inside the parallelogram of segment (a, b) swept
/// back along -u by `range`.
void splat_segment(std::vector<float>& zbuf, const GridSpec& grid, const Vec2& a, const Vec2& b, const Vec2& u,
                   double range) {
  const Vec2 e = b - a;
  const double ue = cross(u, e);
  const Vec2 back = -range * u;
  const Vec2 quad[4] = {a, b, b + back, a + back};
  double ymin = quad[0].y(), ymax = quad[0].y();
  for (const Vec2& q : quad) {
    ymin = std::min(ymin, q.y());
    ymax = std::max(ymax, q.y());
  }
  const double res = grid.resolution_m_per_px;
  const double ox = grid.origin_x_m, oy = grid.origin_y_m;
  // Rows whose centre y lies in [ymin, ymax].
  const int r0 = std::max(0, static_cast<int>(std::ceil((ymin - oy) / res - 0.5)));
  const int r1 = std::min(grid.height_px - 1, static_cast<int>(std::floor((ymax - oy) / res - 0.5)));
  const double inv_ue = 1.0 / ue;
  for (int r = r0; r <= r1; ++r) {
    const double y = oy + (r + 0.5) * res;
    // The quad's x-interval on this horizontal line: intersections with its edges.
    double xl = 1e300, xr = -1e300;
    for (int k = 0; k < 4; ++k) {
      const Vec2& p = quad[k];
      const Vec2& q = quad[(k + 1) % 4];
      const double dy = q.y() - p.y();
      if (dy == 0.0) {
        if (y == p.y()) {
          xl = std::min({xl, p.x(), q.x()});
          xr = std::max({xr, p.x(), q.x()});
        }
        continue;
      }
      const double s = (y - p.y()) / dy;
      if (s < 0.0 || s > 1.0) continue;
      const double x = p.x() + s * (q.x() - p.x());
      xl = std::min(xl, x);
      xr = std::max(xr, x);
    }
    if (xl > xr) continue;
    const int c0 = std::max(0, static_cast<int>(std::ceil((xl - ox) / res - 0.5)));
    const int c1 = std::min(grid.width_px - 1, static_cast<int>(std::floor((xr - ox) / res - 0.5)));
    if (c0 > c1) continue;
    // t(x) = cross(a - p, e) / cross(u, e) is affine in x along the row.
    const double ay = a.y() - y;
    float* z = zbuf.data() + static_cast<std::size_t>(r) * grid.width_px;
    for (int c = c0; c <= c1; ++c) {
      const double x = ox + (c + 0.5) * res;
      const double t = ((a.x() - x) * e.y() - ay * e.x()) * inv_ue;
      const float tf = static_cast<float>(std::clamp(t, 0.0, range));
      if (tf < z[c]) z[c] = tf;
    }
  }
}

}  // namespace

int DistanceVolume::max_units() const {
  return static_cast<int>(std::lround(max_range_m * 1000.0 / step_mm));
}

DistanceVolume compute_distance_volume(const std::vector<Segment2>& segments, const GridSpec& grid, const cv::Mat& mask,
                                       int D, double max_range_m, int bits) {
  if (bits != 8 && bits != 16) throw std::invalid_argument("compute_distance_volume: bits must be 8 or 16");
  if (D <= 0) throw std::invalid_argument("compute_distance_volume: num_directions must be positive");
  if (!(max_range_m > 0.0) || max_range_m > 65.535) {
    throw std::invalid_argument("compute_distance_volume: max_range_m must be in (0, 65.535]");
  }
  if (mask.type() != CV_8U || mask.rows != grid.height_px || mask.cols != grid.width_px) {
    throw std::invalid_argument("compute_distance_volume: mask must be CV_8U on the grid");
  }
  DistanceVolume v;
  v.grid = grid;
  v.num_directions = D;
  v.bits = bits;
  v.step_mm = bits == 8 ? static_cast<int>(std::ceil(std::lround(max_range_m * 1000.0) / 255.0)) : 1;
  v.max_range_m = max_range_m;
  const std::size_t HW = static_cast<std::size_t>(grid.height_px) * grid.width_px;
  v.cell_index.assign(HW, -1);
  for (int r = 0; r < grid.height_px; ++r) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < grid.width_px; ++c) {
      if (m[c]) {
        const std::size_t lin = static_cast<std::size_t>(r) * grid.width_px + c;
        v.cell_index[lin] = static_cast<std::int32_t>(v.cells.size());
        v.cells.push_back(static_cast<std::int32_t>(lin));
      }
    }
  }
  const std::size_t N = v.cells.size();
  if (bits == 8) {
    v.q8.assign(N * static_cast<std::size_t>(D), 0);
  } else {
    v.mm.assign(N * static_cast<std::size_t>(D), 0);
  }

  tbb::enumerable_thread_specific<std::vector<float>> buffers;
  tbb::parallel_for(0, D, [&](int d) {
    std::vector<float>& z = buffers.local();
    z.assign(HW, static_cast<float>(max_range_m));
    const double ang = 2.0 * kPi * d / D;
    const Vec2 u(std::cos(ang), std::sin(ang));
    for (const Segment2& s : segments) {
      const Vec2 e = s.b_m - s.a_m;
      // Front face for a ray along u: the free (left) side faces the ray, cross(u, e) > 0.
      if (!(cross(u, e) > 1e-12 * e.norm())) continue;
      splat_segment(z, grid, s.a_m, s.b_m, u, max_range_m);
    }
    if (bits == 8) {
      std::uint8_t* out = v.q8.data() + static_cast<std::size_t>(d) * N;
      const double per_unit = 1000.0 / v.step_mm;
      for (std::size_t i = 0; i < N; ++i) {
        out[i] = static_cast<std::uint8_t>(std::lround(static_cast<double>(z[static_cast<std::size_t>(v.cells[i])]) * per_unit));
      }
    } else {
      std::uint16_t* out = v.mm.data() + static_cast<std::size_t>(d) * N;
      for (std::size_t i = 0; i < N; ++i) {
        out[i] = static_cast<std::uint16_t>(std::lround(static_cast<double>(z[static_cast<std::size_t>(v.cells[i])]) * 1000.0));
      }
    }
  });
  return v;
}

double brute_force_ray_distance(const std::vector<Segment2>& segments, const Vec2& origin, double angle,
                                double max_range_m) {
  const Vec2 dir(std::cos(angle), std::sin(angle));
  double best = max_range_m;
  for (const Segment2& s : segments) {
    const double t = ray_segment_distance(origin, dir, s);
    if (t >= 0.0 && t < best) best = t;
  }
  return best;
}

std::vector<double> cast_rays_on_segments(const std::vector<Segment2>& segments, int n, double max_range_m) {
  std::vector<double> out(static_cast<std::size_t>(std::max(n, 0)), max_range_m);
  for (int i = 0; i < n; ++i) {
    out[static_cast<std::size_t>(i)] = brute_force_ray_distance(segments, Vec2::Zero(), 2.0 * kPi * i / n, max_range_m);
  }
  return out;
}

}  // namespace floorcast
