#pragma once
/// @file
/// The picture of `mvtrack calib check`: the floor region coloured by how many cameras see each
/// cell (config::CalibrationReport's grid), the cameras, and the overlap graph (a line between
/// the centres of every camera pair with common floor area, red for short-baseline pairs, with
/// the common area and median triangulation angle written on it), with a legend. Stateless.

#include <opencv2/core.hpp>
#include <vector>

#include "analytics/site_analytics.h"
#include "config/calibration_check.h"
#include "geometry/camera_model.h"

namespace mvtrack::viz {

/// Colour of a cell seen by no camera.
inline const cv::Scalar kUnseenColor{40, 40, 40};
/// Colour of a cell seen by exactly one camera (no triangulation possible).
inline const cv::Scalar kSingleViewColor{50, 50, 150};
/// Colour of a cell seen by two or more cameras, all with too small triangulation angles.
inline const cv::Scalar kWeakColor{0, 120, 220};

/// Colour of a cell that `count` >= 2 cameras see with a large enough triangulation angle:
/// green, brighter with more cameras (2, 3, 4+).
cv::Scalar TriangulableColor(int count);

/// The colour RenderCoverageMap gives cell `cell` of `report.grid`.
cv::Scalar CellColor(const config::CalibrationReport& report, std::size_t cell);

/// Height of the legend band under the map, pixels.
inline constexpr int kLegendBandPx = 128;

/// The coverage picture: the map (longer side `max_side_px`, via FloorMapping::Fit of the
/// report's region) with cells, grid, cameras (no fields of view) and the overlap graph, and a
/// legend band of kLegendBandPx below it. `cameras` are the ones the report was computed from.
/// With `site`, its regions and lines are drawn over the map (DrawSite), so the cameras' coverage
/// of each region can be seen.
cv::Mat RenderCoverageMap(const std::vector<geometry::CameraModel>& cameras,
                          const config::CalibrationReport& report,
                          int max_side_px = 900,
                          const analytics::Site* site = nullptr);

}  // namespace mvtrack::viz
