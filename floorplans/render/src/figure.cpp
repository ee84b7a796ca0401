#include "floorcast/floorplans/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace floorcast::figure {
namespace {

std::string printable(const std::string& s) {
  std::string out;
  for (unsigned char c : s) out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  return out;
}

}  // namespace

double nice_step(double range, int target) {
  if (!(range > 0.0) || !std::isfinite(range)) return 1.0;
  const double raw = range / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * mag) return m * mag;
  return 10.0 * mag;
}

double nice_scale_length_m(double max_m) {
  double best = 1.0;
  for (double mag = 1.0; mag <= 1e6; mag *= 10.0)
    for (double m : {1.0, 2.0, 5.0})
      if (m * mag <= max_m) best = m * mag;
  return best;
}

std::string tick_text(double v, double step) {
  char buf[48];
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  if (std::abs(v) < 1e-12 * std::max(1.0, step)) v = 0.0;
  std::snprintf(buf, sizeof buf, "%.*f", std::max(decimals, 0), v);
  return buf;
}

cv::Size text_size(const std::string& text, double scale, int thickness) {
  int base = 0;
  return cv::getTextSize(printable(text), cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base);
}

double fit_text_scale(const std::string& text, double scale, int max_width_px, int thickness) {
  while (scale > 0.3 && text_size(text, scale, thickness).width > max_width_px) scale *= 0.93;
  return std::max(scale, 0.3);
}

void draw_text(cv::Mat& img, const std::string& text, cv::Point at, double scale, const cv::Scalar& colour, int align,
               int thickness) {
  const std::string t = printable(text);
  const cv::Size size = text_size(t, scale, thickness);
  if (align == 1) at.x -= size.width / 2;
  if (align == 2) at.x -= size.width;
  cv::putText(img, t, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thickness, cv::LINE_AA);
}

void draw_vertical_text(cv::Mat& img, const std::string& text, cv::Point centre, double scale, const cv::Scalar& colour) {
  if (text.empty()) return;
  int base = 0;
  const std::string t = printable(text);
  const cv::Size sz = cv::getTextSize(t, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base);
  cv::Mat patch(sz.height + base + 4, sz.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(patch, t, cv::Point(2, sz.height + 1), cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
  cv::Mat rotated;
  cv::rotate(patch, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int x = std::max(0, centre.x - rotated.cols / 2), y = std::max(0, centre.y - rotated.rows / 2);
  const cv::Rect r = cv::Rect(x, y, rotated.cols, rotated.rows) & cv::Rect(0, 0, img.cols, img.rows);
  if (r.width > 0 && r.height > 0) rotated(cv::Rect(0, 0, r.width, r.height)).copyTo(img(r));
}

cv::Rect draw_scale_bar(cv::Mat& img, cv::Point at, double px_per_m, int max_length_px) {
  if (!(px_per_m > 0.0) || max_length_px < 4) return {};
  double len_m = nice_scale_length_m(max_length_px / px_per_m);
  if (len_m * px_per_m > max_length_px) {  // below 1 m: halve until it fits
    while (len_m * px_per_m > max_length_px && len_m > 1e-3) len_m /= 2.0;
  }
  const int len = static_cast<int>(std::lround(len_m * px_per_m));
  const cv::Scalar black(0, 0, 0), white(255, 255, 255);
  for (int k = 0; k < 4; ++k) {
    const int a = at.x + len * k / 4, b = at.x + len * (k + 1) / 4;
    cv::rectangle(img, cv::Rect(a, at.y, std::max(1, b - a), 6), k % 2 == 0 ? black : white, cv::FILLED);
  }
  cv::rectangle(img, cv::Rect(at.x, at.y, len, 6), black, 1);
  char label[48];
  std::snprintf(label, sizeof label, "%g m", len_m);
  draw_text(img, "0", at + cv::Point(0, 22), 0.45, black, 1);
  draw_text(img, label, at + cv::Point(len, 22), 0.45, black, 1);
  return {at.x - 6, at.y, len + 12 + text_size(label, 0.45).width / 2, 26};
}

void draw_colour_bar(cv::Mat& img, cv::Rect bar, int colormap, const std::vector<std::pair<double, std::string>>& ticks,
                     const std::string& label) {
  bar &= cv::Rect(0, 0, img.cols, img.rows);
  if (bar.width < 2 || bar.height < 2) return;
  cv::Mat ramp(bar.height, 1, CV_8U);
  for (int r = 0; r < bar.height; ++r)
    ramp.at<std::uint8_t>(r) = static_cast<std::uint8_t>(std::lround(255.0 * (bar.height - 1 - r) / std::max(1, bar.height - 1)));
  cv::Mat colour;
  cv::applyColorMap(ramp, colour, colormap);
  cv::Mat wide;
  cv::resize(colour, wide, bar.size(), 0, 0, cv::INTER_NEAREST);
  wide.copyTo(img(bar));
  const cv::Scalar ink(40, 40, 40);
  // The frame goes around the bar, not over it: the first and last rows show the colour map's ends.
  cv::rectangle(img, cv::Rect(bar.x - 1, bar.y - 1, bar.width + 2, bar.height + 2), ink, 1);
  int text_w = 0;
  for (const auto& [f, t] : ticks) {
    const int y = bar.y + static_cast<int>(std::lround((1.0 - std::clamp(f, 0.0, 1.0)) * (bar.height - 1)));
    cv::line(img, {bar.x + bar.width, y}, {bar.x + bar.width + 4, y}, ink, 1);
    draw_text(img, t, {bar.x + bar.width + 7, y + 5}, 0.42, ink);
    text_w = std::max(text_w, text_size(t, 0.42).width);
  }
  draw_vertical_text(img, label, {bar.x + bar.width + 14 + text_w + 10, bar.y + bar.height / 2}, 0.45, ink);
}

int draw_legend_row(cv::Mat& img, cv::Point at, const std::vector<LegendEntry>& entries, double scale) {
  int x = at.x;
  for (const LegendEntry& e : entries) {
    const cv::Point c(x + 7, at.y - 5);
    switch (e.symbol) {
      case 'o': cv::circle(img, c, 6, e.colour, 2, cv::LINE_AA); break;
      case 'x': cv::drawMarker(img, c, e.colour, cv::MARKER_TILTED_CROSS, 13, 2, cv::LINE_AA); break;
      case '-': cv::line(img, c - cv::Point(7, 0), c + cv::Point(7, 0), e.colour, 3, cv::LINE_AA); break;
      default: cv::rectangle(img, cv::Rect(x + 1, at.y - 11, 12, 12), e.colour, cv::FILLED);
               cv::rectangle(img, cv::Rect(x + 1, at.y - 11, 12, 12), cv::Scalar(90, 90, 90), 1);
    }
    draw_text(img, e.text, {x + 19, at.y}, scale, cv::Scalar(30, 30, 30));
    x += 19 + text_size(e.text, scale).width + 16;
  }
  return x;
}

void draw_banner(cv::Mat& img, cv::Rect area, const std::string& text, const cv::Scalar& colour) {
  area &= cv::Rect(0, 0, img.cols, img.rows);
  if (area.width < 4 || area.height < 4) return;
  cv::Mat roi = img(area);
  cv::Mat fill(roi.size(), roi.type(), colour);
  cv::addWeighted(roi, 0.25, fill, 0.75, 0.0, roi);
  const double scale = fit_text_scale(text, 0.9, area.width - 20, 2);
  const cv::Size s = text_size(text, scale, 2);
  draw_text(img, text, {area.x + area.width / 2, area.y + (area.height + s.height) / 2}, scale, cv::Scalar(255, 255, 255), 1, 2);
}

}  // namespace floorcast::figure
