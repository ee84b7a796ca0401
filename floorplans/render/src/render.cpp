// Plan drawing: one display list (polygons, lines, polylines, circles, texts in pixel
// coordinates) built from the plan, then drawn by OpenCV or written as SVG.
#include "floorcast/floorplans/render.hpp"

#include "floorcast/floorplans/figure.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/image_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "floorcast/core/format.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {

constexpr int kHeaderPx = 36;
constexpr int kFooterPx = 56;
constexpr int kMinWidthPx = 420;  // room for the title, scale bar and legend
constexpr int kAxisLeftPx = 46;   // coordinates: the y labels' band
constexpr int kAxisBottomPx = 24; // coordinates: the x labels' band
constexpr double kAxisTextPx = 11.0;

struct Prim {
  enum Type { kPolygon, kLine, kPolyline, kCircle } type = kPolygon;
  std::vector<cv::Point2d> pts;  // kCircle: pts[0] = centre
  cv::Scalar color;
  double width_px = 1.0;         // kLine / kPolyline stroke width; kCircle: radius
  std::string group;
};

struct Text {
  cv::Point2d org;  // baseline start
  std::string text;
  double size_px = 14.0;
  cv::Scalar color;
};

struct Scene {
  int width = 0, height = 0;
  PlanImage mapping;  // bgr left empty
  std::vector<Prim> prims;
  std::vector<Text> texts;
};

/// Width in pixels of a text drawn by the raster backend (the SVG uses the same layout).
double text_width_px(const std::string& text, double size_px) {
  int baseline = 0;
  return cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, size_px / 22.0, 1, &baseline).width;
}

std::string printable(const std::string& s) {
  std::string out;
  for (unsigned char c : s) out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  return out;
}

}  // namespace

Eigen::Vector4d drawing_extent_m(const FloorPlan& plan) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector4d box(inf, inf, -inf, -inf);
  auto add = [&box](const Vec2& p) {
    box[0] = std::min(box[0], p.x());
    box[1] = std::min(box[1], p.y());
    box[2] = std::max(box[2], p.x());
    box[3] = std::max(box[3], p.y());
  };
  for (const Wall& w : plan.walls) {
    const double len = w.length_m();
    if (!(len > 0.0)) continue;
    const Vec2 d = w.direction() * (0.5 * w.thickness_m);
    const Vec2 n(-d.y(), d.x());
    for (const Vec2& p : {Vec2(w.a_m - d), Vec2(w.b_m + d)}) {
      add(p + n);
      add(p - n);
    }
  }
  for (const Obstacle& o : plan.obstacles) {
    if (o.kind == ObstacleKind::kPillar) {
      const double r = 0.5 * o.size_m.x();
      add(o.center_m - Vec2(r, r));
      add(o.center_m + Vec2(r, r));
    } else {
      const double c = std::cos(o.yaw_rad), sn = std::sin(o.yaw_rad);
      const Vec2 ex = 0.5 * o.size_m.x() * Vec2(c, sn), ey = 0.5 * o.size_m.y() * Vec2(-sn, c);
      for (const Vec2& p : {Vec2(o.center_m - ex - ey), Vec2(o.center_m + ex - ey), Vec2(o.center_m + ex + ey),
                            Vec2(o.center_m - ex + ey)}) {
        add(p);
      }
    }
  }
  if (box[0] > box[2]) box.setZero();
  return box;
}

namespace {

Scene build_scene(const FloorPlan& plan, const RenderOptions& o) {
  if (!std::isfinite(o.px_per_m) || o.px_per_m <= 0.0) {
    throw InputError("render: px_per_m must be a positive number, got " + std::to_string(o.px_per_m));
  }
  if (!std::isfinite(o.margin_m) || o.margin_m < 0.0) throw InputError("render: margin_m must be >= 0");
  const double s = o.px_per_m;
  const Eigen::Vector4d box = drawing_extent_m(plan);
  const int axis_left = o.draw_coordinates ? kAxisLeftPx : 0;
  const int axis_bottom = o.draw_coordinates ? kAxisBottomPx : 0;
  const double plan_w_d = std::ceil((box[2] - box[0] + 2.0 * o.margin_m) * s);
  const double plan_h_d = std::ceil((box[3] - box[1] + 2.0 * o.margin_m) * s);
  const double map_w_d = plan_w_d + axis_left;
  const double map_h_d = plan_h_d + axis_bottom;
  const int header = o.draw_title ? kHeaderPx : 0;
  const int footer = (o.draw_scale_bar || o.draw_legend) ? kFooterPx : 0;
  const double width_d = std::max(map_w_d, (header || footer) ? static_cast<double>(kMinWidthPx) : 1.0);
  const double height_d = map_h_d + header + footer;
  if (width_d > o.max_side_px || height_d > o.max_side_px) {
    std::ostringstream os;
    os << "render: the image would be " << static_cast<long long>(width_d) << " x " << static_cast<long long>(height_d)
       << " px at " << s << " px/m (limit " << o.max_side_px << " px per side); lower --px-per-m";
    throw InputError(os.str());
  }
  check_image_size(static_cast<long long>(width_d), static_cast<long long>(height_d), "render");
  Scene sc;
  sc.width = static_cast<int>(width_d);
  sc.height = static_cast<int>(height_d);
  PlanImage& m = sc.mapping;
  m.px_per_m = s;
  m.origin_x_m = box[0] - o.margin_m - (axis_left + 0.5 * (width_d - map_w_d)) / s;
  m.top_y_m = box[3] + o.margin_m;
  m.map_top_px = header;
  m.map_rect = cv::Rect(0, header, sc.width, static_cast<int>(map_h_d));

  auto px = [&m](const Vec2& p) { return m.world_to_pixel(p); };
  auto rect_prim = [&](const Vec2& a, const Vec2& b, double half_w, const cv::Scalar& color, const std::string& group) {
    const Vec2 d = (b - a).normalized();
    const Vec2 n(-d.y(), d.x());
    const double thick_px = 2.0 * half_w * s;
    Prim p;
    p.color = color;
    p.group = group;
    if (thick_px < 3.0) {  // too thin to fill: a crisp line at least 2 px wide
      p.type = Prim::kLine;
      p.pts = {px(a), px(b)};
      p.width_px = std::max(2.0, std::round(thick_px));
    } else {
      p.type = Prim::kPolygon;
      p.pts = {px(a - half_w * n), px(b - half_w * n), px(b + half_w * n), px(a + half_w * n)};
    }
    sc.prims.push_back(std::move(p));
  };

  // Obstacles first (walls are drawn over them).
  if (o.draw_obstacles) {
    for (const Obstacle& ob : plan.obstacles) {
      const cv::Scalar color = ob.height_m > o.cut_height_m ? RenderColors::obstacle_tall() : RenderColors::obstacle_low();
      Prim p;
      p.color = color;
      p.group = "obstacles";
      if (ob.kind == ObstacleKind::kPillar) {
        p.type = Prim::kCircle;
        p.pts = {px(ob.center_m)};
        p.width_px = std::max(1.0, 0.5 * ob.size_m.x() * s);
      } else {
        const double c = std::cos(ob.yaw_rad), sn = std::sin(ob.yaw_rad);
        const Vec2 ex = 0.5 * ob.size_m.x() * Vec2(c, sn), ey = 0.5 * ob.size_m.y() * Vec2(-sn, c);
        p.type = Prim::kPolygon;
        p.pts = {px(ob.center_m - ex - ey), px(ob.center_m + ex - ey), px(ob.center_m + ex + ey),
                 px(ob.center_m - ex + ey)};
      }
      sc.prims.push_back(std::move(p));
    }
  }

  // Walls split at their openings.
  struct Opening {
    double t0, t1;
    int type;  // 0 open door, 1 closed door, 2 window
  };
  std::vector<Prim> swings;
  const WallJoins joins(plan);
  for (std::size_t wi = 0; wi < plan.walls.size(); ++wi) {
    const Wall& w = plan.walls[wi];
    const double len = w.length_m();
    if (!(len > 0.0)) continue;
    const Vec2 dir = w.direction();
    const Vec2 nrm(-dir.y(), dir.x());
    const double half = 0.5 * w.thickness_m;
    std::vector<Opening> ops;
    for (const std::size_t di : joins.doors_on(wi)) {
      const Door& d = plan.doors[di];
      const OpeningSpan sp = opening_span(plan, static_cast<int>(wi), d.center_m, d.width_m);
      ops.push_back({std::max(0.0, sp.t0_m), std::min(len, sp.t1_m), d.closed ? 1 : 0});
    }
    for (const std::size_t ni : joins.windows_on(wi)) {
      const Window& win = plan.windows[ni];
      const OpeningSpan sp = opening_span(plan, static_cast<int>(wi), win.center_m, win.width_m);
      ops.push_back({std::max(0.0, sp.t0_m), std::min(len, sp.t1_m), 2});
    }
    std::sort(ops.begin(), ops.end(), [](const Opening& a, const Opening& b) { return a.t0 < b.t0; });
    const cv::Scalar body = w.material == WallMaterial::kGlass ? RenderColors::glass() : RenderColors::wall();
    const std::string body_group = w.material == WallMaterial::kGlass ? "glass" : "walls";
    double cursor = joins.end_joined(wi, w.a_m) ? -half : 0.0;
    const double t_end = joins.end_joined(wi, w.b_m) ? len + half : len;
    auto at = [&](double t) { return Vec2(w.a_m + t * dir); };
    for (const Opening& op : ops) {
      if (op.t0 > cursor) rect_prim(at(cursor), at(op.t0), half, body, body_group);
      cursor = std::max(cursor, op.t1);
      if (op.type == 2) {
        rect_prim(at(op.t0), at(op.t1), half, RenderColors::glass(), "windows");
      } else if (op.type == 1) {
        rect_prim(at(op.t0), at(op.t1), std::max(half * 0.6, 0.03), RenderColors::door_closed(), "doors");
      } else if (o.draw_door_swings) {
        const double width = op.t1 - op.t0;
        const bool double_door = width >= 1.5;
        const int leaves = double_door ? 2 : 1;
        const double r = width / leaves;
        for (int k = 0; k < leaves; ++k) {
          const double hinge_t = k == 0 ? op.t0 : op.t1;
          const double sign = k == 0 ? 1.0 : -1.0;  // towards the other jamb
          const Vec2 hinge = at(hinge_t);
          Prim leaf;
          leaf.type = Prim::kLine;
          leaf.color = RenderColors::door_swing();
          leaf.width_px = std::max(1.0, std::min(3.0, 0.04 * s));
          leaf.group = "doors";
          leaf.pts = {px(hinge), px(hinge + r * nrm)};
          swings.push_back(leaf);
          Prim arc;
          arc.type = Prim::kPolyline;
          arc.color = RenderColors::door_swing();
          arc.width_px = 1.0;
          arc.group = "doors";
          for (int i = 0; i <= 16; ++i) {
            const double a = 0.5 * kPi * i / 16.0;
            arc.pts.push_back(px(hinge + r * (std::cos(a) * nrm + sign * std::sin(a) * dir)));
          }
          swings.push_back(arc);
        }
      }
    }
    if (t_end > cursor) rect_prim(at(cursor), at(t_end), half, body, body_group);
  }
  for (Prim& p : swings) sc.prims.push_back(std::move(p));

  // Coordinates: a frame around the plan area, ticks every "nice" step (about 90 px apart), the
  // metre values in the bands left of and below it.
  if (o.draw_coordinates) {
    const double x_lo = box[0] - o.margin_m, x_hi = box[2] + o.margin_m;
    const double y_lo = box[1] - o.margin_m, y_hi = box[3] + o.margin_m;
    const cv::Point2d c00 = px(Vec2(x_lo, y_lo)), c11 = px(Vec2(x_hi, y_hi));
    Prim frame;
    frame.type = Prim::kPolyline;
    frame.group = "axes";
    frame.color = RenderColors::text();
    frame.width_px = 1.0;
    frame.pts = {{c00.x, c00.y}, {c11.x, c00.y}, {c11.x, c11.y}, {c00.x, c11.y}, {c00.x, c00.y}};
    sc.prims.push_back(frame);
    const double step = figure::nice_scale_length_m(std::max(90.0 / s, 1e-3));
    auto tick = [&](const cv::Point2d& a, const cv::Point2d& b) {
      Prim t;
      t.type = Prim::kLine;
      t.group = "axes";
      t.color = RenderColors::text();
      t.width_px = 1.0;
      t.pts = {a, b};
      sc.prims.push_back(t);
    };
    for (double x = std::ceil(x_lo / step) * step; x <= x_hi + 1e-9; x += step) {
      const cv::Point2d p = px(Vec2(x, y_lo));
      tick(p, p + cv::Point2d(0, 5));
      const std::string label = figure::tick_text(x, step);
      sc.texts.push_back({cv::Point2d(p.x - 0.5 * text_width_px(label, kAxisTextPx), p.y + 17.0), label, kAxisTextPx,
                          RenderColors::text()});
    }
    for (double y = std::ceil(y_lo / step) * step; y <= y_hi + 1e-9; y += step) {
      const cv::Point2d p = px(Vec2(x_lo, y));
      tick(p, p - cv::Point2d(5, 0));
      const std::string label = figure::tick_text(y, step);
      sc.texts.push_back({cv::Point2d(p.x - 8.0 - text_width_px(label, kAxisTextPx), p.y + 4.0), label, kAxisTextPx,
                          RenderColors::text()});
    }
    // The unit in the corner where the two bands meet.
    sc.texts.push_back({cv::Point2d(c00.x - kAxisLeftPx + 4.0, c00.y + 17.0), "m",
                        kAxisTextPx, RenderColors::text()});
  }

  // Header: the name.
  if (o.draw_title) {
    sc.texts.push_back({cv::Point2d(10, 24), printable(plan.name.empty() ? "(unnamed plan)" : plan.name), 16.0,
                        RenderColors::text()});
  }
  // Footer: scale bar and legend.
  const double y_bar = header + map_h_d + 18.0;
  double x_legend = 10.0;
  if (o.draw_scale_bar) {
    const double len_m = figure::nice_scale_length_m(std::max(1.0, 0.3 * sc.width / s));
    const double len_px = len_m * s;
    const double x0 = 10.0;
    for (int k = 0; k < 4; ++k) {
      Prim seg;
      seg.type = Prim::kPolygon;
      seg.group = "scale";
      seg.color = (k % 2 == 0) ? RenderColors::wall() : RenderColors::background();
      const double a = x0 + len_px * k / 4.0, b = x0 + len_px * (k + 1) / 4.0;
      seg.pts = {{a, y_bar}, {b, y_bar}, {b, y_bar + 6.0}, {a, y_bar + 6.0}};
      sc.prims.push_back(seg);
    }
    Prim frame;
    frame.type = Prim::kPolyline;
    frame.group = "scale";
    frame.color = RenderColors::wall();
    frame.width_px = 1.0;
    frame.pts = {{x0, y_bar}, {x0 + len_px, y_bar}, {x0 + len_px, y_bar + 6.0}, {x0, y_bar + 6.0}, {x0, y_bar}};
    sc.prims.push_back(frame);
    char label[64];
    std::snprintf(label, sizeof label, "%g m", len_m);
    sc.texts.push_back({cv::Point2d(x0, y_bar + 24.0), "0", 12.0, RenderColors::text()});
    const double label_w = text_width_px(label, 12.0);
    sc.texts.push_back({cv::Point2d(x0 + len_px - 0.5 * label_w, y_bar + 24.0), label, 12.0, RenderColors::text()});
    x_legend = x0 + len_px + 0.5 * label_w + 24.0;
  }
  if (o.draw_legend) {
    const struct {
      cv::Scalar color;
      const char* label;
    } items[] = {{RenderColors::wall(), "wall"},
                 {RenderColors::glass(), "glass"},
                 {RenderColors::door_closed(), "closed door"},
                 {RenderColors::obstacle_tall(), "obstacle"}};
    double x = x_legend;
    for (const auto& it : items) {
      const double item_w = 16.0 + text_width_px(it.label, 12.0);
      if (x + item_w > sc.width - 4.0) break;
      Prim sw;
      sw.type = Prim::kPolygon;
      sw.group = "legend";
      sw.color = it.color;
      sw.pts = {{x, y_bar}, {x + 12.0, y_bar}, {x + 12.0, y_bar + 12.0}, {x, y_bar + 12.0}};
      sc.prims.push_back(sw);
      sc.texts.push_back({cv::Point2d(x + 16.0, y_bar + 11.0), it.label, 12.0, RenderColors::text()});
      x += item_w + 16.0;
    }
  }
  // Draw order by group (stable inside a group): obstacles under walls, door swings on top.
  const auto rank = [](const std::string& g) {
    const char* order[] = {"obstacles", "walls", "glass", "windows", "doors", "axes", "scale", "legend"};
    for (int i = 0; i < 8; ++i) {
      if (g == order[i]) return i;
    }
    return 8;
  };
  std::stable_sort(sc.prims.begin(), sc.prims.end(),
                   [&rank](const Prim& a, const Prim& b) { return rank(a.group) < rank(b.group); });
  return sc;
}

std::string hex_color(const cv::Scalar& bgr) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(bgr[2]), static_cast<int>(bgr[1]),
                static_cast<int>(bgr[0]));
  return buf;
}

}  // namespace

PlanImage render_plan(const FloorPlan& plan, const RenderOptions& options) {
  Scene sc = build_scene(plan, options);
  PlanImage img = sc.mapping;
  img.bgr = cv::Mat(sc.height, sc.width, CV_8UC3, RenderColors::background());

  if (options.draw_interior) {
    GridSpec g;
    g.resolution_m_per_px = 1.0 / img.px_per_m;
    g.width_px = img.map_rect.width;
    g.height_px = img.map_rect.height;
    g.origin_x_m = img.origin_x_m;
    g.origin_y_m = img.top_y_m - g.height_px * g.resolution_m_per_px;
    const cv::Mat valid = valid_area_mask(plan, g);
    cv::Mat flipped;
    cv::flip(valid, flipped, 0);  // grid rows grow with +y, image rows grow downwards
    img.bgr(img.map_rect).setTo(RenderColors::interior(), flipped);
  }

  constexpr int kShift = 4;
  constexpr double kScale = 1 << kShift;
  auto fixed = [](const cv::Point2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x * kScale)), static_cast<int>(std::lround(p.y * kScale)));
  };
  for (const Prim& p : sc.prims) {
    switch (p.type) {
      case Prim::kPolygon: {
        std::vector<cv::Point> pts;
        for (const auto& q : p.pts) pts.push_back(fixed(q - cv::Point2d(0.5, 0.5)));
        cv::fillConvexPoly(img.bgr, pts, p.color, cv::LINE_AA, kShift);
        break;
      }
      case Prim::kLine:
        if (p.width_px >= 2.0) {
          cv::line(img.bgr, fixed(p.pts[0] - cv::Point2d(0.5, 0.5)), fixed(p.pts[1] - cv::Point2d(0.5, 0.5)), p.color,
                   static_cast<int>(std::lround(p.width_px)), cv::LINE_8, kShift);
        } else {
          cv::line(img.bgr, fixed(p.pts[0] - cv::Point2d(0.5, 0.5)), fixed(p.pts[1] - cv::Point2d(0.5, 0.5)), p.color,
                   1, cv::LINE_AA, kShift);
        }
        break;
      case Prim::kPolyline: {
        std::vector<cv::Point> pts;
        for (const auto& q : p.pts) pts.push_back(fixed(q - cv::Point2d(0.5, 0.5)));
        cv::polylines(img.bgr, pts, false, p.color, std::max(1, static_cast<int>(std::lround(p.width_px))), cv::LINE_AA,
                      kShift);
        break;
      }
      case Prim::kCircle:
        cv::circle(img.bgr, fixed(p.pts[0] - cv::Point2d(0.5, 0.5)), static_cast<int>(std::lround(p.width_px * kScale)),
                   p.color, cv::FILLED, cv::LINE_AA, kShift);
        break;
    }
  }
  for (const Text& t : sc.texts) {
    const double scale = t.size_px / 22.0;
    cv::putText(img.bgr, t.text, cv::Point(static_cast<int>(t.org.x), static_cast<int>(t.org.y)),
                cv::FONT_HERSHEY_SIMPLEX, scale, t.color, 1, cv::LINE_AA);
  }
  return img;
}

std::string render_plan_svg(const FloorPlan& plan, const RenderOptions& options) {
  const Scene sc = build_scene(plan, options);
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << sc.width << "\" height=\"" << sc.height
     << "\" viewBox=\"0 0 " << sc.width << " " << sc.height << "\">\n"
     << "<title>" << xml_escape(plan.name) << "</title>\n"
     << "<rect x=\"0\" y=\"0\" width=\"" << sc.width << "\" height=\"" << sc.height << "\" fill=\""
     << hex_color(RenderColors::background()) << "\"/>\n";
  std::string open_group;
  for (const Prim& p : sc.prims) {
    if (p.group != open_group) {
      if (!open_group.empty()) os << "</g>\n";
      os << "<g class=\"" << p.group << "\">\n";
      open_group = p.group;
    }
    const std::string color = hex_color(p.color);
    switch (p.type) {
      case Prim::kPolygon:
        os << "<polygon points=\"";
        for (std::size_t i = 0; i < p.pts.size(); ++i) os << (i ? " " : "") << format_fixed(p.pts[i].x, 2) << "," << format_fixed(p.pts[i].y, 2);
        os << "\" fill=\"" << color << "\"/>\n";
        break;
      case Prim::kLine:
        os << "<line x1=\"" << format_fixed(p.pts[0].x, 2) << "\" y1=\"" << format_fixed(p.pts[0].y, 2) << "\" x2=\"" << format_fixed(p.pts[1].x, 2)
           << "\" y2=\"" << format_fixed(p.pts[1].y, 2) << "\" stroke=\"" << color << "\" stroke-width=\"" << format_fixed(p.width_px, 2)
           << "\"/>\n";
        break;
      case Prim::kPolyline:
        os << "<polyline points=\"";
        for (std::size_t i = 0; i < p.pts.size(); ++i) os << (i ? " " : "") << format_fixed(p.pts[i].x, 2) << "," << format_fixed(p.pts[i].y, 2);
        os << "\" fill=\"none\" stroke=\"" << color << "\" stroke-width=\"" << format_fixed(p.width_px, 2) << "\"/>\n";
        break;
      case Prim::kCircle:
        os << "<circle cx=\"" << format_fixed(p.pts[0].x, 2) << "\" cy=\"" << format_fixed(p.pts[0].y, 2) << "\" r=\"" << format_fixed(p.width_px, 2)
           << "\" fill=\"" << color << "\"/>\n";
        break;
    }
  }
  if (!open_group.empty()) os << "</g>\n";
  if (!sc.texts.empty()) {
    os << "<g class=\"text\" font-family=\"sans-serif\">\n";
    for (const Text& t : sc.texts) {
      os << "<text x=\"" << format_fixed(t.org.x, 2) << "\" y=\"" << format_fixed(t.org.y, 2) << "\" font-size=\"" << format_fixed(t.size_px, 2)
         << "\" fill=\"" << hex_color(t.color) << "\">" << xml_escape(t.text) << "</text>\n";
    }
    os << "</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace floorcast
