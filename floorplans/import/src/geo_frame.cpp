// GeoFrame (import.hpp): source coordinates -> local east/north metres through PROJ.
#include <proj.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"

namespace floorcast {

using import_detail::fmt;
using import_detail::quoted;

struct GeoFrame::Impl {
  PJ_CONTEXT* ctx = nullptr;
  PJ* to_geographic = nullptr;  ///< projected source -> (lon, lat) degrees of its datum; null: geographic
  PJ* to_local = nullptr;       ///< (lon, lat) degrees -> topocentric (east, north, up) metres
  double semi_major_m = 6378137.0;
  double inverse_flattening = 298.257223563;  ///< 0 for a sphere
  std::string description = "WGS 84 longitude/latitude (default)";
  std::string what;

  ~Impl() {
    for (PJ* p : {to_geographic, to_local}) {
      if (p) proj_destroy(p);
    }
    if (ctx) proj_context_destroy(ctx);
  }
  std::string error() const { return proj_context_errno_string(ctx, proj_context_errno(ctx)); }
};

namespace {

/// Owns a PJ for the duration of a scope.
struct PjHolder {
  PJ* p = nullptr;
  explicit PjHolder(PJ* pj) : p(pj) {}
  ~PjHolder() {
    if (p) proj_destroy(p);
  }
  PjHolder(const PjHolder&) = delete;
  PjHolder& operator=(const PjHolder&) = delete;
  void reset(PJ* pj) {
    if (p) proj_destroy(p);
    p = pj;
  }
};

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string crs_label(const PJ* crs) {
  std::string s = proj_get_name(crs) ? proj_get_name(crs) : "unnamed CRS";
  const char* auth = proj_get_id_auth_name(crs, 0);
  const char* code = proj_get_id_code(crs, 0);
  if (auth && code) s += std::string(" (") + auth + ":" + code + ")";
  return s;
}

}  // namespace

GeoFrame::GeoFrame(const std::string& crs, const std::string& what) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.what = what;
  d.ctx = proj_context_create();
  if (!d.ctx) throw InputError(what + ": PROJ could not create a context");
  proj_log_level(d.ctx, PJ_LOG_NONE);  // errors come back through errno, never printed
  if (crs.empty()) return;
  PjHolder source(proj_create(d.ctx, crs.c_str()));
  if (!source.p) {
    throw InputError(what + ": coordinate reference system " + quoted(crs) + " is not one PROJ knows (" + d.error() +
                     "); give e.g. EPSG:32632 or urn:ogc:def:crs:EPSG::32632");
  }
  // A bound CRS (with a transformation to WGS84 attached) or a compound one (horizontal +
  // vertical): the horizontal CRS is what the positions are in.
  if (proj_get_type(source.p) == PJ_TYPE_BOUND_CRS) source.reset(proj_get_source_crs(d.ctx, source.p));
  if (source.p && proj_get_type(source.p) == PJ_TYPE_COMPOUND_CRS) source.reset(proj_crs_get_sub_crs(d.ctx, source.p, 0));
  if (!source.p) throw InputError(what + ": coordinate reference system " + quoted(crs) + ": " + d.error());
  const PJ_TYPE type = proj_get_type(source.p);
  const bool geographic = type == PJ_TYPE_GEOGRAPHIC_2D_CRS || type == PJ_TYPE_GEOGRAPHIC_3D_CRS;
  if (!geographic && type != PJ_TYPE_PROJECTED_CRS) {
    throw InputError(what + ": coordinate reference system " + quoted(crs) + " (" + crs_label(source.p) +
                     ") is neither geographic nor projected; floor plans need longitude/latitude or easting/northing");
  }
  d.description = crs_label(source.p);
  PjHolder datum(proj_crs_get_geodetic_crs(d.ctx, source.p));
  if (!datum.p) throw InputError(what + ": " + d.description + " has no geodetic datum (" + d.error() + ")");
  PjHolder ellipsoid(proj_get_ellipsoid(d.ctx, datum.p));
  double semi_minor = 0.0, inv_f = 0.0;
  int computed = 0;
  if (!ellipsoid.p || !proj_ellipsoid_get_parameters(d.ctx, ellipsoid.p, &d.semi_major_m, &semi_minor, &computed, &inv_f)) {
    throw InputError(what + ": " + d.description + ": no ellipsoid (" + d.error() + ")");
  }
  d.inverse_flattening = inv_f;
  if (!geographic) {
    // The inverse projection onto the CRS's own geographic CRS (no datum change), axes as GIS
    // software writes them: (easting, northing) in, (longitude, latitude) degrees out.
    PjHolder op(proj_create_crs_to_crs_from_pj(d.ctx, source.p, datum.p, nullptr, nullptr));
    if (!op.p) throw InputError(what + ": no conversion from " + d.description + " to longitude/latitude (" + d.error() + ")");
    d.to_geographic = proj_normalize_for_visualization(d.ctx, op.p);
    if (!d.to_geographic) throw InputError(what + ": " + d.description + ": " + d.error());
  }
}

GeoFrame::~GeoFrame() = default;
GeoFrame::GeoFrame(GeoFrame&&) noexcept = default;
GeoFrame& GeoFrame::operator=(GeoFrame&&) noexcept = default;

bool GeoFrame::geographic() const { return impl_->to_geographic == nullptr; }
const std::string& GeoFrame::description() const { return impl_->description; }

Vec2 GeoFrame::to_geographic_deg(const Vec2& p, const std::string& where) const {
  const Impl& d = *impl_;
  auto shown = [&] { return "[" + fmt(p.x()) + ", " + fmt(p.y()) + "]"; };
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) throw InputError(where + ": position " + shown() + " is not finite");
  if (!d.to_geographic) {
    if (std::abs(p.x()) <= 180.0 && std::abs(p.y()) <= 90.0) return p;
    std::string msg = where + ": position " + shown() + " is not a longitude/latitude of " + d.description;
    if (std::abs(p.x()) > 1000.0 || std::abs(p.y()) > 1000.0) {
      msg += ": the numbers look like metres of a projected system (UTM, a national grid); declare it (a GeoJSON "
             "\"crs\" member) or give it with --crs EPSG:NNNN";
    }
    throw InputError(msg);
  }
  PJ_COORD c = proj_coord(p.x(), p.y(), 0.0, 0.0);
  proj_errno_reset(d.to_geographic);
  const PJ_COORD out = proj_trans(d.to_geographic, PJ_FWD, c);
  if (!std::isfinite(out.xy.x) || !std::isfinite(out.xy.y) || out.xy.x == HUGE_VAL || std::abs(out.xy.y) > 90.0) {
    throw InputError(where + ": position " + shown() + " cannot be converted from " + d.description + " (" + d.error() +
                     ")");
  }
  return {out.xy.x, out.xy.y};
}

void GeoFrame::set_origin_deg(const Vec2& o) {
  Impl& d = *impl_;
  if (d.to_local) proj_destroy(d.to_local);
  const std::string shape = d.inverse_flattening > 0.0
                                ? " +a=" + exact(d.semi_major_m) + " +rf=" + exact(d.inverse_flattening)
                                : " +R=" + exact(d.semi_major_m);
  const std::string pipeline = "+proj=pipeline +step +proj=unitconvert +xy_in=deg +xy_out=rad +step +proj=cart" + shape +
                               " +step +proj=topocentric" + shape + " +lon_0=" + exact(o.x()) + " +lat_0=" + exact(o.y());
  d.to_local = proj_create(d.ctx, pipeline.c_str());
  if (!d.to_local) throw InputError(d.what + ": PROJ could not set up the local plane (" + d.error() + ")");
}

Vec2 GeoFrame::to_local_m(const Vec2& lonlat) const {
  const Impl& d = *impl_;
  if (!d.to_local) throw InputError(d.what + ": the local plane has no origin (set_origin_deg first)");
  const PJ_COORD out = proj_trans(d.to_local, PJ_FWD, proj_coord(lonlat.x(), lonlat.y(), 0.0, 0.0));
  return {out.xyz.x, out.xyz.y};
}

}  // namespace floorcast
