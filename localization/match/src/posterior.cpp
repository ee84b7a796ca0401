#include "floorcast/match/posterior.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace floorcast {
namespace {

/// The hypothesis of cell (row, col) of slice `slice`, scored `score`.
PoseHypothesis hypothesis_at(const Posterior& post, int slice, int row, int col, float score) {
  PoseHypothesis h;
  const Vec2 p = post.grid.cell_center_m(row, col);
  h.x_m = p.x();
  h.y_m = p.y();
  h.yaw_rad = post.yaw_rad[static_cast<std::size_t>(slice)];
  h.score = score;
  h.slice = slice;
  h.row = row;
  h.col = col;
  return h;
}

}  // namespace

void Posterior::check() const {
  if (scores.size() != yaw_rad.size()) {
    throw std::invalid_argument("Posterior: " + std::to_string(scores.size()) + " slices but " +
                                std::to_string(yaw_rad.size()) + " yaws");
  }
  for (std::size_t s = 0; s < scores.size(); ++s) {
    const cv::Mat& m = scores[s];
    if (m.type() != CV_32F || m.rows != grid.height_px || m.cols != grid.width_px) {
      throw std::invalid_argument("Posterior: slice " + std::to_string(s) +
                                  " is not a CV_32F map of the grid's size");
    }
    for (int r = 0; r < m.rows; ++r) {
      const float* row = m.ptr<float>(r);
      for (int c = 0; c < m.cols; ++c) {
        if (!(row[c] >= 0.0f) || !std::isfinite(row[c])) {
          throw std::invalid_argument("Posterior: slice " + std::to_string(s) + " cell (" +
                                      std::to_string(r) + ", " + std::to_string(c) +
                                      ") is negative or not finite");
        }
      }
    }
  }
}

PoseHypothesis Posterior::argmax() const {
  if (scores.empty()) throw std::invalid_argument("Posterior::argmax: no slices");
  float best = -std::numeric_limits<float>::infinity();
  int bs = 0, br = 0, bc = 0;
  for (int s = 0; s < num_slices(); ++s) {
    const cv::Mat& m = scores[static_cast<std::size_t>(s)];
    for (int r = 0; r < m.rows; ++r) {
      const float* row = m.ptr<float>(r);
      for (int c = 0; c < m.cols; ++c) {
        if (row[c] > best) {
          best = row[c];
          bs = s;
          br = r;
          bc = c;
        }
      }
    }
  }
  return hypothesis_at(*this, bs, br, bc, best);
}

std::vector<PoseHypothesis> Posterior::top_k(int k, double min_separation_m, double min_separation_rad) const {
  std::vector<PoseHypothesis> modes;
  if (k <= 0 || scores.empty()) return modes;
  const int S = num_slices(), H = grid.height_px, W = grid.width_px;
  const double res = grid.resolution_m_per_px;
  // Suppressed cells and, per (slice, row), the maximum over the row's live cells; a round scans
  // the S x H row maxima, then one row, and only re-scans rows touched by the suppression.
  std::vector<cv::Mat> dead(static_cast<std::size_t>(S));
  std::vector<float> row_max(static_cast<std::size_t>(S) * static_cast<std::size_t>(H));
  auto rescan_row = [&](int s, int r) {
    const float* row = scores[static_cast<std::size_t>(s)].ptr<float>(r);
    const std::uint8_t* d = dead[static_cast<std::size_t>(s)].ptr<std::uint8_t>(r);
    float m = 0.0f;  // only positive scores are modes
    for (int c = 0; c < W; ++c)
      if (!d[c] && row[c] > m) m = row[c];
    row_max[static_cast<std::size_t>(s) * H + r] = m;
  };
  for (int s = 0; s < S; ++s) {
    dead[static_cast<std::size_t>(s)] = cv::Mat::zeros(H, W, CV_8U);
    for (int r = 0; r < H; ++r) rescan_row(s, r);
  }
  const double r_px = min_separation_m / res;
  const int rad = static_cast<int>(std::floor(r_px + 1e-9));
  while (static_cast<int>(modes.size()) < k) {
    float best = 0.0f;
    int bs = -1, br = -1;
    for (int s = 0; s < S; ++s) {
      const float* rm = &row_max[static_cast<std::size_t>(s) * H];
      for (int r = 0; r < H; ++r) {
        if (rm[r] > best) {
          best = rm[r];
          bs = s;
          br = r;
        }
      }
    }
    if (bs < 0) break;
    const float* row = scores[static_cast<std::size_t>(bs)].ptr<float>(br);
    const std::uint8_t* d = dead[static_cast<std::size_t>(bs)].ptr<std::uint8_t>(br);
    int bc = -1;
    for (int c = 0; c < W; ++c) {
      if (!d[c] && row[c] == best) {
        bc = c;
        break;
      }
    }
    const PoseHypothesis h = hypothesis_at(*this, bs, br, bc, best);
    modes.push_back(h);
    // Suppress every live cell within the separation in position and yaw (the mode itself
    // included: distance 0).
    for (int s = 0; s < S; ++s) {
      if (angle_distance_rad(yaw_rad[static_cast<std::size_t>(s)], h.yaw_rad) > min_separation_rad) continue;
      cv::Mat& dm = dead[static_cast<std::size_t>(s)];
      for (int r = std::max(0, br - rad - 1); r <= std::min(H - 1, br + rad + 1); ++r) {
        std::uint8_t* drow = dm.ptr<std::uint8_t>(r);
        bool touched = false;
        for (int c = std::max(0, bc - rad - 1); c <= std::min(W - 1, bc + rad + 1); ++c) {
          // Same test as in metres, on cell centres (the grid is uniform).
          const double dx = (c - bc) * res, dy = (r - br) * res;
          if (std::sqrt(dx * dx + dy * dy) <= min_separation_m + 1e-12 && !drow[c]) {
            drow[c] = 1;
            touched = true;
          }
        }
        if (touched) rescan_row(s, r);
      }
    }
  }
  return modes;
}

std::vector<PoseHypothesis> Posterior::maximum_filter_peaks(int k, int half_cells, int half_slices) const {
  std::vector<PoseHypothesis> peaks;
  if (k <= 0 || scores.empty()) return peaks;
  const int S = num_slices();
  const cv::Mat kernel = cv::Mat::ones(2 * half_cells + 1, 2 * half_cells + 1, CV_8U);
  std::vector<cv::Mat> spatial(static_cast<std::size_t>(S));
  for (int s = 0; s < S; ++s) {
    cv::dilate(scores[static_cast<std::size_t>(s)], spatial[static_cast<std::size_t>(s)], kernel, cv::Point(-1, -1), 1,
               cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  struct Peak {
    float score;
    int s, r, c;
  };
  std::vector<Peak> found;
  for (int s = 0; s < S; ++s) {
    cv::Mat window = spatial[static_cast<std::size_t>(s)].clone();
    for (int d = 1; d <= std::min(half_slices, S / 2); ++d) {
      cv::max(window, spatial[static_cast<std::size_t>((s + d) % S)], window);
      cv::max(window, spatial[static_cast<std::size_t>((s - d + S) % S)], window);
    }
    const cv::Mat& m = scores[static_cast<std::size_t>(s)];
    for (int r = 0; r < m.rows; ++r) {
      const float* v = m.ptr<float>(r);
      const float* w = window.ptr<float>(r);
      for (int c = 0; c < m.cols; ++c) {
        if (v[c] > 0.0f && v[c] >= w[c]) found.push_back({v[c], s, r, c});
      }
    }
  }
  std::sort(found.begin(), found.end(), [](const Peak& a, const Peak& b) {
    if (a.score != b.score) return a.score > b.score;
    if (a.s != b.s) return a.s < b.s;
    return a.r != b.r ? a.r < b.r : a.c < b.c;
  });
  for (std::size_t i = 0; i < found.size() && static_cast<int>(peaks.size()) < k; ++i) {
    peaks.push_back(hypothesis_at(*this, found[i].s, found[i].r, found[i].c, found[i].score));
  }
  return peaks;
}

cv::Mat Posterior::max_over_yaw() const {
  cv::Mat out = cv::Mat::zeros(grid.height_px, grid.width_px, CV_32F);
  for (const cv::Mat& m : scores) cv::max(out, m, out);
  return out;
}

double Posterior::total() const {
  double sum = 0.0;
  for (const cv::Mat& m : scores) {
    for (int r = 0; r < m.rows; ++r) {
      const float* row = m.ptr<float>(r);
      double rs = 0.0;
      for (int c = 0; c < m.cols; ++c) rs += row[c];
      sum += rs;
    }
  }
  return sum;
}

std::vector<cv::Mat> Posterior::normalised_pdf() const {
  const double sum = total();
  std::vector<cv::Mat> out;
  out.reserve(scores.size());
  for (const cv::Mat& m : scores) {
    cv::Mat p;
    if (sum > 0.0) {
      m.convertTo(p, CV_32F, 1.0 / sum);
    } else {
      p = cv::Mat::zeros(m.size(), CV_32F);
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace floorcast
