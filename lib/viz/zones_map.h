#pragma once
/// @file
/// The picture of `mvtrack calib zones --png` (issue 43): the floor coloured by the zone whose
/// own cameras see it, the border floor (seen by the own cameras of two or more zones, where
/// the stitcher joins their tracks) light grey, the cameras in their zone's colour (a border
/// camera of another zone ringed in white), the zone names, and a legend. Stateless.

#include <opencv2/core.hpp>
#include <vector>

#include "config/calibration_check.h"
#include "config/zones.h"
#include "geometry/camera_model.h"

namespace mvtrack::viz {

/// Colour of zone `index` of `count` (hues spread around the circle).
cv::Scalar ZoneColor(int index, int count);
/// Colour of floor seen by the own cameras of two or more zones.
inline const cv::Scalar kBorderFloorColor{200, 200, 200};

/// The zones picture of `region` (longer side `max_side_px`; a legend band below), the floor
/// sampled every `cell_m` at `sample_height_m` above z = 0 (geometry::SeesPoint, as the split
/// itself samples). `zones` name cameras of `cameras`.
cv::Mat RenderZonesMap(const std::vector<geometry::CameraModel>& cameras,
                       const std::vector<config::Zone>& zones,
                       const config::FloorRegion& region,
                       double cell_m,
                       double sample_height_m,
                       int max_side_px = 1200);

}  // namespace mvtrack::viz
