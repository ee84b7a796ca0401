// A contact sheet of a scan for people (`floorcast sim preview`): every view's colour image (when
// the scan has one) above its depth map (turbo colour map on one range for all views, no return
// black, glass-affected pixels tinted magenta), a caption per view (index, yaw, valid share), a
// title band and a depth colour bar in metres. Pure: returns a BGR image.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "floorcast/core/scan.hpp"

namespace floorcast {

struct ScanSheetStyle {
  int tile_width_px = 240;  ///< each view is scaled to this width
  int columns = 6;          ///< views per row (fewer when the scan has fewer)
};

/// Throws InputError when the scan has no view or a view has neither depth nor colour.
cv::Mat draw_scan_contact_sheet(const Scan& scan, const std::string& title, const ScanSheetStyle& style = {});

}  // namespace floorcast
