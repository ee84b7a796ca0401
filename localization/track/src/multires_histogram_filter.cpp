#include "floorcast/track/multires_histogram_filter.hpp"

#include <algorithm>
#include <cmath>

#include "floorcast/core/grid.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

const FieldList<MultiResolutionHistogramFilterParams>& MultiResolutionHistogramFilterParams::fields() {
  using P = MultiResolutionHistogramFilterParams;
  static const FieldList<P> f =
      FieldList<P>("tracker hist_mr")
          .flatten(&P::filter, HistogramFilterParams::fields())
          .integer("coarse_factor", &P::coarse_factor, 1, 16,
                   "coarse belief over the whole plan at coarse_factor x resolution_m (1: the single-resolution filter)")
          .number("window_m", &P::window_m, 1.0, 10000.0,
                  "side of the fine window, m (plans whose grid fits in it: the single-resolution filter exactly)")
          .number("window_mass", &P::window_mass, 0.0, 1.0,
                  "the fine window is used while it holds at least this share of the coarse belief");
  return f;
}

nlohmann::ordered_json MultiResolutionHistogramFilterParams::to_json() const { return fields().write(*this); }

void MultiResolutionHistogramFilterParams::apply_overrides(const nlohmann::json& overrides) {
  fields().read(*this, overrides);
}

MultiResolutionHistogramFilter::MultiResolutionHistogramFilter(const FloorPlan& plan,
                                                               const MultiResolutionHistogramFilterParams& params)
    : params_(params) {
  const HistogramFilterParams& p = params_.filter;
  fine_grid_ = grid_for_plan(plan, p.resolution_m, p.grid_margin_m);
  const double res = fine_grid_.resolution_m_per_px;
  if (params_.coarse_factor <= 1 ||
      (fine_grid_.width_px * res <= params_.window_m && fine_grid_.height_px * res <= params_.window_m)) {
    fine_ = std::make_unique<HistogramFilter>(plan, p);
    use_fine_ = true;
    return;
  }
  check_raster_budget(fine_grid_, 1.0, "tracker hist_mr (fine interior)");
  fine_interior_ = HistogramFilter::belief_interior(plan, fine_grid_);
  // The coarse grid: the fine grid's origin, coarse_factor x its cells; a coarse cell is
  // interior where any of its fine cells is (a door narrower than a coarse cell stays open).
  const int k = params_.coarse_factor;
  GridSpec cg;
  cg.origin_x_m = fine_grid_.origin_x_m;
  cg.origin_y_m = fine_grid_.origin_y_m;
  cg.resolution_m_per_px = res * k;
  cg.width_px = (fine_grid_.width_px + k - 1) / k;
  cg.height_px = (fine_grid_.height_px + k - 1) / k;
  cv::Mat coarse_interior(cg.height_px, cg.width_px, CV_8U, cv::Scalar(0));
  for (int r = 0; r < fine_grid_.height_px; ++r) {
    const std::uint8_t* in = fine_interior_.ptr<std::uint8_t>(r);
    std::uint8_t* out = coarse_interior.ptr<std::uint8_t>(r / k);
    for (int c = 0; c < fine_grid_.width_px; ++c) {
      if (in[c]) out[c / k] = 255;
    }
  }
  HistogramFilterParams cp = p;
  cp.resolution_m = cg.resolution_m_per_px;
  coarse_ = std::make_unique<HistogramFilter>(cg, coarse_interior, cp);
}

MultiResolutionHistogramFilter::~MultiResolutionHistogramFilter() = default;

const GridSpec& MultiResolutionHistogramFilter::coarse_grid() const { return coarse_ ? coarse_->grid() : fine_grid_; }

std::size_t MultiResolutionHistogramFilter::state_bytes() const {
  std::size_t n = fine_interior_.total();
  if (coarse_) n += coarse_->state_bytes();
  if (fine_) n += fine_->state_bytes();
  return n;
}

void MultiResolutionHistogramFilter::window_box(double& x0, double& y0, double& x1, double& y1) const {
  const GridSpec& g = fine_->grid();
  x0 = g.origin_x_m;
  y0 = g.origin_y_m;
  x1 = g.origin_x_m + g.width_px * g.resolution_m_per_px;
  y1 = g.origin_y_m + g.height_px * g.resolution_m_per_px;
}

GridSpec MultiResolutionHistogramFilter::window_grid(const Vec2& centre) const {
  const double res = fine_grid_.resolution_m_per_px;
  const int W = fine_grid_.width_px, H = fine_grid_.height_px;
  const int wpx = std::min(W, static_cast<int>(std::ceil(params_.window_m / res)));
  const int hpx = std::min(H, static_cast<int>(std::ceil(params_.window_m / res)));
  const int cc = static_cast<int>(std::floor((centre.x() - fine_grid_.origin_x_m) / res));
  const int rc = static_cast<int>(std::floor((centre.y() - fine_grid_.origin_y_m) / res));
  const int c0 = std::clamp(cc - wpx / 2, 0, W - wpx), r0 = std::clamp(rc - hpx / 2, 0, H - hpx);
  GridSpec g;
  g.origin_x_m = fine_grid_.origin_x_m + c0 * res;
  g.origin_y_m = fine_grid_.origin_y_m + r0 * res;
  g.resolution_m_per_px = res;
  g.width_px = wpx;
  g.height_px = hpx;
  return g;
}

bool MultiResolutionHistogramFilter::build_window(const Vec2& centre, const Posterior& source) {
  const GridSpec g = window_grid(centre);
  const double res = fine_grid_.resolution_m_per_px;
  const int c0 = static_cast<int>(std::lround((g.origin_x_m - fine_grid_.origin_x_m) / res));
  const int r0 = static_cast<int>(std::lround((g.origin_y_m - fine_grid_.origin_y_m) / res));
  const int wpx = g.width_px, hpx = g.height_px;
  HistogramFilterParams fp = params_.filter;
  fp.init = BeliefInit::kPosterior;  // the window starts from the belief it is cut from
  auto f = std::make_unique<HistogramFilter>(g, fine_interior_(cv::Rect(c0, r0, wpx, hpx)).clone(), fp);
  try {
    f->initialise(source, last_step_);
  } catch (const InputError&) {
    return false;  // the source holds nothing in the window
  }
  fine_ = std::move(f);
  window_c0_ = c0;
  window_r0_ = r0;
  ++windows_built_;
  return true;
}

void MultiResolutionHistogramFilter::manage_window(const Posterior* fresh) {
  if (!coarse_) return;
  const TrackEstimate ce = coarse_->estimate();
  if (fine_) {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    window_box(x0, y0, x1, y1);
    window_share_ = coarse_->mass_within(x0, y0, x1, y1);
    const TrackEstimate fe = fine_->estimate();
    if (window_share_ >= params_.window_mass && fe.support > 0.0) {
      // Trusted: move it when its estimate comes within a quarter window of an edge that is not
      // the plan's, its belief carried over (what lay outside the old window starts at 0).
      const double margin = 0.25 * params_.window_m;
      const Vec2 p = fe.pose.position_m();
      const bool near = (window_c0_ > 0 && p.x() - x0 < margin) || (window_r0_ > 0 && p.y() - y0 < margin) ||
                        (window_c0_ + fine_->grid().width_px < fine_grid_.width_px && x1 - p.x() < margin) ||
                        (window_r0_ + fine_->grid().height_px < fine_grid_.height_px && y1 - p.y() < margin);
      if (near) {
        const Posterior carried = fine_->belief();
        if (build_window(p, carried)) {
          window_box(x0, y0, x1, y1);
          window_share_ = coarse_->mass_within(x0, y0, x1, y1);
        }
      }
      use_fine_ = true;
      return;
    }
    fine_.reset();
  }
  use_fine_ = false;
  window_share_ = 0.0;
  if (ce.degenerate || !(ce.support > 0.0)) return;
  // No trusted window: build one around the coarse estimate when the coarse belief holds
  // window_mass there.
  const Vec2 c = ce.pose.position_m();
  const GridSpec g = window_grid(c);
  const double share = coarse_->mass_within(g.origin_x_m, g.origin_y_m, g.origin_x_m + g.width_px * g.resolution_m_per_px,
                                            g.origin_y_m + g.height_px * g.resolution_m_per_px);
  if (share < params_.window_mass) return;
  const bool built = fresh ? build_window(c, *fresh) : build_window(c, coarse_->belief());
  if (!built) return;
  window_share_ = share;
  use_fine_ = true;
}

void MultiResolutionHistogramFilter::initialise(const Posterior& posterior, const OdometryStep& first) {
  last_step_ = first;
  windows_built_ = 0;
  if (!coarse_) {
    fine_->initialise(posterior, first);
    return;
  }
  fine_.reset();
  coarse_->initialise(posterior, first);
  // The first window starts from the posterior itself (fine cells) when the filter starts from it.
  manage_window(params_.filter.init == BeliefInit::kPosterior ? &posterior : nullptr);
}

void MultiResolutionHistogramFilter::predict(const OdometryStep& step) {
  last_step_ = step;
  if (coarse_) coarse_->predict(step);
  if (fine_) fine_->predict(step);
  manage_window();
}

void MultiResolutionHistogramFilter::update(const PosteriorQuery& posterior) {
  if (coarse_) coarse_->update(posterior);
  if (fine_) fine_->update(posterior);
  manage_window();
}

TrackEstimate MultiResolutionHistogramFilter::estimate() const {
  if (!coarse_) return fine_->estimate();
  if (!(use_fine_ && fine_)) return coarse_->estimate();
  TrackEstimate e = fine_->estimate();
  // Support in the whole belief: the fine support within the window's share of the coarse belief.
  e.support *= window_share_;
  e.stage = e.support >= params_.filter.converged_mass ? 2 : std::min(e.stage, 1);
  e.degenerate = e.degenerate || coarse_->estimate().degenerate;
  return e;
}

}  // namespace floorcast
