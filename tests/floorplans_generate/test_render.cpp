// Plan rendering: pixel colours at known places, image size vs scale, mapping, SVG structure.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/render.hpp"

namespace floorcast {
namespace {

/// An 8 x 5 m room: solid west/south/north walls (0.3 m), a glass east wall (0.05 m), a closed
/// door and a window in the south wall, an open door in the north wall, a low box, a tall pillar.
FloorPlan sample_plan(const std::string& name = "render test") {
  FloorPlan p;
  p.name = name;
  p.walls = {
      {"south", {0, 0}, {8, 0}, 0.3, WallMaterial::kSolid, 0.0, {}},
      {"east", {8, 0}, {8, 5}, 0.05, WallMaterial::kGlass, 0.0, {}},
      {"north", {8, 5}, {0, 5}, 0.3, WallMaterial::kSolid, 0.0, {}},
      {"west", {0, 5}, {0, 0}, 0.3, WallMaterial::kSolid, 0.0, {}},
  };
  p.doors = {{"closed", "south", {2.0, 0.0}, 1.0, true}, {"open", "north", {4.0, 5.0}, 0.9, false}};
  p.windows = {{"win", "south", {6.0, 0.0}, 1.5, 0.9, 2.1}};
  p.obstacles = {{"box", ObstacleKind::kBox, {2.0, 3.0}, {1.0, 0.6}, 0.0, 0.75},
                 {"pillar", ObstacleKind::kPillar, {6.0, 3.0}, {0.4, 0.4}, 0.0, 3.0}};
  return p;
}

cv::Vec3b color_at(const PlanImage& img, const Vec2& p_m) {
  const cv::Point2d px = img.world_to_pixel(p_m);
  return img.bgr.at<cv::Vec3b>(static_cast<int>(std::floor(px.y)), static_cast<int>(std::floor(px.x)));
}

cv::Vec3b vec(const cv::Scalar& s) {
  return cv::Vec3b(static_cast<uchar>(s[0]), static_cast<uchar>(s[1]), static_cast<uchar>(s[2]));
}

TEST(Render, ColoursAtKnownPlaces) {
  RenderOptions o;
  o.px_per_m = 50.0;
  o.margin_m = 1.0;
  const PlanImage img = render_plan(sample_plan(), o);
  ASSERT_EQ(img.bgr.type(), CV_8UC3);
  EXPECT_EQ(color_at(img, {0.0, 2.5}), vec(RenderColors::wall()));          // west wall
  EXPECT_EQ(color_at(img, {4.0, 0.0}), vec(RenderColors::wall()));          // south wall between openings
  EXPECT_EQ(color_at(img, {8.0, 2.5}), vec(RenderColors::glass()));         // glass wall
  EXPECT_EQ(color_at(img, {6.0, 0.0}), vec(RenderColors::glass()));         // window
  EXPECT_EQ(color_at(img, {2.0, 0.0}), vec(RenderColors::door_closed()));   // closed door leaf
  EXPECT_NE(color_at(img, {4.0, 5.0}), vec(RenderColors::wall()));          // open door: a gap
  EXPECT_EQ(color_at(img, {2.0, 3.0}), vec(RenderColors::obstacle_low()));  // 0.75 m box
  EXPECT_EQ(color_at(img, {6.0, 3.0}), vec(RenderColors::obstacle_tall())); // 3 m pillar
  EXPECT_EQ(color_at(img, {4.0, 2.0}), vec(RenderColors::interior()));
  EXPECT_EQ(color_at(img, {-0.8, 2.5}), vec(RenderColors::background()));   // outside
  // The open door's swing: its 90-degree leaf lies on the left of north's a->b (-x), i.e. south
  // of the wall, from the hinge at t0 (x = 4.45) to 0.9 m into the room.
  EXPECT_EQ(color_at(img, {4.45, 4.4}), vec(RenderColors::door_swing()));
}

TEST(Render, YPointsUpAndTheMappingRoundTrips) {
  RenderOptions o;
  o.px_per_m = 40.0;
  const PlanImage img = render_plan(sample_plan(), o);
  EXPECT_LT(img.world_to_pixel({0.0, 5.0}).y, img.world_to_pixel({0.0, 0.0}).y);
  EXPECT_LT(img.world_to_pixel({0.0, 0.0}).x, img.world_to_pixel({8.0, 0.0}).x);
  for (const Vec2& p : {Vec2(0.0, 0.0), Vec2(3.7, -1.2), Vec2(8.0, 5.0)}) {
    const Vec2 back = img.pixel_to_world(img.world_to_pixel(p));
    EXPECT_NEAR(back.x(), p.x(), 1e-9);
    EXPECT_NEAR(back.y(), p.y(), 1e-9);
  }
  // The map area holds the whole plan.
  const cv::Point2d lo = img.world_to_pixel({-0.3, -0.3}), hi = img.world_to_pixel({8.3, 5.3});
  EXPECT_TRUE(img.map_rect.contains(cv::Point(static_cast<int>(lo.x), static_cast<int>(lo.y))));
  EXPECT_TRUE(img.map_rect.contains(cv::Point(static_cast<int>(hi.x), static_cast<int>(hi.y))));
}

TEST(Render, ImageSizeFollowsTheScale) {
  const FloorPlan plan = generate_building(Archetype::kOffice, 1).plan;
  const Eigen::Vector4d ext = drawing_extent_m(plan);
  for (double s : {5.0, 10.0, 20.0}) {
    RenderOptions o;
    o.px_per_m = s;
    o.margin_m = 2.0;
    o.draw_interior = false;  // faster; size does not depend on it
    const PlanImage img = render_plan(plan, o);
    const int map_w = static_cast<int>(std::ceil((ext[2] - ext[0] + 4.0) * s));
    const int map_h = static_cast<int>(std::ceil((ext[3] - ext[1] + 4.0) * s));
    EXPECT_EQ(img.map_rect.width, map_w) << s;
    EXPECT_EQ(img.map_rect.height, map_h) << s;
    EXPECT_EQ(img.bgr.cols, std::max(map_w, 420)) << s;
    EXPECT_EQ(img.bgr.rows, map_h + 36 + 56) << s;
  }
  // Without header and footer the image is exactly the map.
  RenderOptions bare;
  bare.px_per_m = 10.0;
  bare.draw_title = bare.draw_scale_bar = bare.draw_legend = false;
  bare.draw_interior = false;
  const PlanImage img = render_plan(plan, bare);
  EXPECT_EQ(img.bgr.cols, static_cast<int>(std::ceil((ext[2] - ext[0] + 3.0) * 10.0)));
  EXPECT_EQ(img.bgr.rows, static_cast<int>(std::ceil((ext[3] - ext[1] + 3.0) * 10.0)));
  EXPECT_EQ(img.map_top_px, 0);
}

TEST(Render, TitleAndScaleBarAreDrawn) {
  RenderOptions o;
  o.px_per_m = 30.0;
  o.draw_interior = false;
  const PlanImage img = render_plan(sample_plan(), o);
  auto dark_pixels = [&img](const cv::Rect& r) {
    int n = 0;
    for (int y = r.y; y < r.y + r.height; ++y) {
      for (int x = r.x; x < r.x + r.width; ++x) {
        const cv::Vec3b c = img.bgr.at<cv::Vec3b>(y, x);
        if (c[0] < 100 && c[1] < 100 && c[2] < 100) ++n;
      }
    }
    return n;
  };
  EXPECT_GT(dark_pixels(cv::Rect(0, 0, img.bgr.cols, img.map_top_px)), 30);  // the name
  const int footer_y = img.map_rect.y + img.map_rect.height;
  EXPECT_GT(dark_pixels(cv::Rect(0, footer_y, img.bgr.cols, img.bgr.rows - footer_y)), 100);  // scale bar
  // The scale bar's black first quarter starts 10 px from the left, 18 px below the map.
  EXPECT_EQ(img.bgr.at<cv::Vec3b>(footer_y + 20, 12), vec(RenderColors::wall()));
}

TEST(Render, CoordinatesGetBandsOfTheirOwnAndKeepTheMapping) {
  RenderOptions plain;
  plain.px_per_m = 60.0;  // wider than the minimum image width, so the band shows in the width
  plain.margin_m = 1.0;
  RenderOptions axes = plain;
  axes.draw_coordinates = true;
  const PlanImage a = render_plan(sample_plan(), plain), b = render_plan(sample_plan(), axes);
  // 46 px for the y labels on the left, 24 px for the x labels below the map.
  EXPECT_EQ(b.map_rect.width, a.map_rect.width + 46);
  EXPECT_EQ(b.map_rect.height, a.map_rect.height + 24);
  // Every element stays where the mapping says.
  EXPECT_EQ(color_at(b, {0.0, 2.5}), vec(RenderColors::wall()));
  EXPECT_EQ(color_at(b, {8.0, 2.5}), vec(RenderColors::glass()));
  EXPECT_EQ(color_at(b, {2.0, 0.0}), vec(RenderColors::door_closed()));
  // Ticks: 90 px / 60 px per m -> every 2 m; the tick of x = 4 m hangs below the frame (the
  // plan's extent less the margin): dark pixels there (anti-aliased 1 px line).
  const Eigen::Vector4d ext = drawing_extent_m(sample_plan());
  const cv::Point2d t = b.world_to_pixel({4.0, ext[1] - 1.0});
  const cv::Vec3b tick = b.bgr.at<cv::Vec3b>(static_cast<int>(t.y) + 3, static_cast<int>(std::floor(t.x)));
  EXPECT_LT(tick[0] + tick[1] + tick[2], 3 * 128) << tick;
  // Labels in the bands: dark pixels left of the frame and below it, none there without coordinates.
  auto dark = [](const PlanImage& img, const cv::Rect& r) {
    int n = 0;
    for (int y = r.y; y < r.y + r.height; ++y)
      for (int x = r.x; x < r.x + r.width; ++x) {
        const cv::Vec3b c = img.bgr.at<cv::Vec3b>(y, x);
        if (c[0] < 100 && c[1] < 100 && c[2] < 100) ++n;
      }
    return n;
  };
  const cv::Point2d lo = b.world_to_pixel({ext[0] - 1.0, ext[1] - 1.0});
  EXPECT_GT(dark(b, cv::Rect(0, b.map_top_px, static_cast<int>(lo.x) - 2, static_cast<int>(lo.y) - b.map_top_px)), 20);
  EXPECT_GT(dark(b, cv::Rect(static_cast<int>(lo.x), static_cast<int>(lo.y) + 6, b.bgr.cols - static_cast<int>(lo.x), 14)), 20);
  // SVG: the same texts (the x labels 0, 2, 4, 6, 8 among them).
  const std::string svg = render_plan_svg(sample_plan(), axes);
  EXPECT_NE(svg.find("<g class=\"axes\">"), std::string::npos);
  EXPECT_NE(svg.find(">6</text>"), std::string::npos);
}

TEST(Render, RefusesBadScales) {
  const FloorPlan p = sample_plan();
  for (double s : {0.0, -3.0, std::nan("")}) {
    RenderOptions o;
    o.px_per_m = s;
    EXPECT_THROW(render_plan(p, o), InputError) << s;
    EXPECT_THROW(render_plan_svg(p, o), InputError) << s;
  }
  RenderOptions huge;
  huge.px_per_m = 1e5;
  EXPECT_THROW(render_plan(p, huge), InputError);
}

TEST(Render, EveryShippedBuildingShowsWallsAndGlass) {
  for (const char* name : {"two_rooms", "apartment", "office", "campus", "angled"}) {
    const FloorPlan p = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/" + name + ".json");
    RenderOptions o;
    o.px_per_m = 8.0;
    const PlanImage img = render_plan(p, o);
    int black = 0, blue = 0;
    for (int y = img.map_rect.y; y < img.map_rect.y + img.map_rect.height; ++y) {
      for (int x = 0; x < img.bgr.cols; ++x) {
        const cv::Vec3b c = img.bgr.at<cv::Vec3b>(y, x);
        if (c == vec(RenderColors::wall())) ++black;
        if (c == vec(RenderColors::glass())) ++blue;
      }
    }
    EXPECT_GT(black, 100) << name;
    EXPECT_GT(blue, 5) << name;
  }
}

// ---- SVG ----------------------------------------------------------------------------------------

/// A small XML well-formedness check: balanced tags, quoted attributes, only the five predefined
/// entities, a single root element.
bool well_formed_xml(const std::string& s, std::string& error) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  int roots = 0;
  auto entity_ok = [&s](std::size_t amp) {
    for (const char* e : {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"}) {
      if (s.compare(amp, std::strlen(e), e) == 0) return true;
    }
    return false;
  };
  if (s.compare(0, 5, "<?xml") == 0) {
    i = s.find("?>");
    if (i == std::string::npos) return error = "unterminated declaration", false;
    i += 2;
  }
  while (i < s.size()) {
    const std::size_t lt = s.find('<', i);
    for (std::size_t k = i; k < std::min(lt, s.size()); ++k) {
      if (s[k] == '&' && !entity_ok(k)) return error = "bare & in text at " + std::to_string(k), false;
      if (s[k] == '>') return error = "stray > at " + std::to_string(k), false;
      if (stack.empty() && !std::isspace(static_cast<unsigned char>(s[k]))) return error = "text outside root", false;
    }
    if (lt == std::string::npos) break;
    std::size_t k = lt + 1;
    const bool closing = k < s.size() && s[k] == '/';
    if (closing) ++k;
    const std::size_t name_start = k;
    while (k < s.size() && (std::isalnum(static_cast<unsigned char>(s[k])) || s[k] == '-' || s[k] == ':')) ++k;
    const std::string name = s.substr(name_start, k - name_start);
    if (name.empty()) return error = "empty tag name at " + std::to_string(lt), false;
    if (closing) {
      if (k >= s.size() || s[k] != '>') return error = "bad closing tag " + name, false;
      if (stack.empty() || stack.back() != name) return error = "mismatched </" + name + ">", false;
      stack.pop_back();
      i = k + 1;
      continue;
    }
    // Attributes.
    while (true) {
      while (k < s.size() && std::isspace(static_cast<unsigned char>(s[k]))) ++k;
      if (k >= s.size()) return error = "unterminated tag " + name, false;
      if (s[k] == '/' || s[k] == '>') break;
      const std::size_t a0 = k;
      while (k < s.size() && (std::isalnum(static_cast<unsigned char>(s[k])) || s[k] == '-' || s[k] == ':')) ++k;
      if (k == a0 || k >= s.size() || s[k] != '=') return error = "bad attribute in " + name, false;
      ++k;
      if (k >= s.size() || s[k] != '"') return error = "unquoted attribute in " + name, false;
      const std::size_t close = s.find('"', k + 1);
      if (close == std::string::npos) return error = "unterminated attribute in " + name, false;
      for (std::size_t m = k + 1; m < close; ++m) {
        if (s[m] == '<') return error = "< in attribute of " + name, false;
        if (s[m] == '&' && !entity_ok(m)) return error = "bare & in attribute of " + name, false;
      }
      k = close + 1;
    }
    if (stack.empty()) ++roots;
    if (s[k] == '/') {
      if (k + 1 >= s.size() || s[k + 1] != '>') return error = "bad self-closing tag " + name, false;
      i = k + 2;
    } else {
      stack.push_back(name);
      i = k + 1;
    }
  }
  if (!stack.empty()) return error = "unclosed <" + stack.back() + ">", false;
  if (roots != 1) return error = "expected one root element, got " + std::to_string(roots), false;
  return true;
}

TEST(RenderSvg, CheckerRejectsBrokenXml) {
  std::string err;
  EXPECT_TRUE(well_formed_xml("<a x=\"1\"><b/>t &amp; u</a>\n", err)) << err;
  EXPECT_FALSE(well_formed_xml("<a><b></a>", err));
  EXPECT_FALSE(well_formed_xml("<a x=1/>", err));
  EXPECT_FALSE(well_formed_xml("<a>R&D</a>", err));
  EXPECT_FALSE(well_formed_xml("<a/><b/>", err));
}

TEST(RenderSvg, IsWellFormedAndEscapesTheName) {
  RenderOptions o;
  o.px_per_m = 50.0;
  const std::string svg = render_plan_svg(sample_plan("R&D <lab> \"x\""), o);
  std::string err;
  EXPECT_TRUE(well_formed_xml(svg, err)) << err;
  EXPECT_NE(svg.find("R&amp;D &lt;lab&gt; &quot;x&quot;"), std::string::npos);
  EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  // Colours of the drawing appear: wall black, glass blue, closed door.
  EXPECT_NE(svg.find("fill=\"#000000\""), std::string::npos);
  EXPECT_NE(svg.find("#1478eb"), std::string::npos);
  EXPECT_NE(svg.find("#e67800"), std::string::npos);
  // Same size as the raster.
  const PlanImage img = render_plan(sample_plan(), o);
  EXPECT_NE(svg.find("width=\"" + std::to_string(img.bgr.cols) + "\" height=\"" + std::to_string(img.bgr.rows) + "\""),
            std::string::npos);
}

TEST(RenderSvg, ShippedCampusIsWellFormed) {
  const FloorPlan p = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/campus.json");
  const std::string svg = render_plan_svg(p, RenderOptions{});
  std::string err;
  EXPECT_TRUE(well_formed_xml(svg, err)) << err;
  std::size_t polygons = 0;
  for (std::size_t pos = svg.find("<polygon"); pos != std::string::npos; pos = svg.find("<polygon", pos + 1)) ++polygons;
  EXPECT_GT(polygons, p.walls.size());
}

}  // namespace
}  // namespace floorcast
