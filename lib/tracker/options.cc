#include "tracker/options.h"

#include <cmath>

namespace mvtrack::tracker {

bool TrackerOptions::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (window_size < 2 || window_size > 10000) return fail("window_size (ν) must be in [2, 10000]");
  if (window_step < 1 || window_step > window_size) {
    return fail("window_step (δ) must be in [1, window_size]");
  }
  if (mode == InputMode::kPoses && (layout == core::KeypointLayoutId::kNone ||
                                    core::GetKeypointLayout(layout).num_joints() == 0)) {
    return fail("pose mode needs a keypoint layout");
  }
  if (!std::isfinite(ground_height_m)) return fail("ground_height_m must be finite");
  if (!(box_ends_max_elevation_deg >= 0.0 && box_ends_max_elevation_deg <= 90.0)) {
    return fail("box_ends_max_elevation_deg must be in [0, 90]");
  }
  if (!(min_detection_score >= 0.0 && min_detection_score <= 1.0)) {
    return fail("min_detection_score must be in [0, 1]");
  }
  if (!(min_keypoint_confidence >= 0.0 && min_keypoint_confidence <= 1.0)) {
    return fail("min_keypoint_confidence must be in [0, 1]");
  }
  if (min_pose_keypoints < 1) return fail("min_pose_keypoints must be >= 1");
  if (min_tracklet_length < 1) return fail("min_tracklet_length must be >= 1");
  if (max_frame_jump < window_size) return fail("max_frame_jump must be >= window_size");
  if (!(box_margin_fraction >= 0.0 && box_margin_fraction <= 10.0)) {
    return fail("box_margin_fraction must be in [0, 10]");
  }
  if (max_detections_per_frame < 1) return fail("max_detections_per_frame must be >= 1");
  std::string nested;
  if (!sort.Validate(&nested)) return fail("sort: " + nested);
  if (!association.Validate(&nested)) return fail("association: " + nested);
  if (!triangulation.Validate(&nested)) return fail(nested);  // already prefixed "triangulation: "
  if (!linking.Validate(&nested)) return fail("linking: " + nested);
  if (!refinement.Validate(&nested)) return fail(nested);  // already prefixed "refinement: "
  return true;
}

int NumPoints(const TrackerOptions& options) {
  if (options.mode == InputMode::kPoses)
    return core::GetKeypointLayout(options.layout).num_joints();
  return options.box_point == BoxPoint::kCenterEnds ? 3 : 1;
}

std::vector<int> FootprintPoints(const TrackerOptions& options) {
  if (options.mode == InputMode::kBoxes) return {0};
  const core::KeypointLayout& layout = core::GetKeypointLayout(options.layout);
  int left = -1;
  int right = -1;
  for (int i = 0; i < layout.num_joints(); ++i) {
    if (layout.joints[static_cast<std::size_t>(i)] == "l_hip") left = i;
    if (layout.joints[static_cast<std::size_t>(i)] == "r_hip") right = i;
  }
  if (left >= 0 && right >= 0) return {left, right};
  return {};
}

int NumTriangulatedPoints(const TrackerOptions& options) {
  return options.mode == InputMode::kBoxes && options.box_point == BoxPoint::kCenterEnds
             ? 1
             : NumPoints(options);
}

}  // namespace mvtrack::tracker
