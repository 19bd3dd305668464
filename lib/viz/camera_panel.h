#pragma once
/// @file
/// A camera panel: the camera's image area (no image, a dark background) with its 2D detections
/// in grey and the 3D tracks reprojected through the calibration (with lens distortion, the
/// pixels detections are in) in each track's colour: poses as skeletons of the layout's bones,
/// footprints as the outline of a standing person's box (0.5 m x 0.5 m x 1.8 m on the floor at
/// the track position) with a vertical centre line. Stateless; thread-compatible.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "geometry/camera_model.h"
#include "tracker/types.h"

namespace mvtrack::viz {

/// Options of RenderCameraPanel.
struct CameraPanelOptions {
  /// The panel is the camera image scaled by `scale` (> 0; 1 = full resolution).
  double scale = 0.5;
  /// Height and side of the box drawn for a track without joints, metres.
  double person_height_m = 1.8;
  double person_width_m = 0.5;  ///< see person_height_m
  /// Title drawn at the top-left ("C<id>" when empty).
  std::string title;
};

/// The panel size for `camera` at `scale`: round(width * scale) x round(height * scale), at
/// least 1 x 1.
cv::Size PanelSize(const geometry::CameraModel& camera, double scale);

/// Draws the panel: background, `detections` (boxes; keypoints and bones when they have a
/// layout), then every track of `frame` reprojected (joints when the track has any, the
/// layout's bones between present joints; else the footprint box), with its id. Points behind
/// the camera are not drawn. A CV_8UC3 image of PanelSize(camera, options.scale).
cv::Mat RenderCameraPanel(const geometry::CameraModel& camera,
                          const std::vector<core::Detection2D>& detections,
                          const tracker::Frame3D& frame,
                          core::KeypointLayoutId layout,
                          const CameraPanelOptions& options = {});

}  // namespace mvtrack::viz
