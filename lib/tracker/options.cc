#include "tracker/options.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

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
  if (!(monocular_min_elevation_deg >= 0.0 && monocular_min_elevation_deg <= 90.0)) {
    return fail("monocular_min_elevation_deg must be in [0, 90]");
  }
  if (!(bridge_max_gap_s >= 0.0 && bridge_max_gap_s <= 10.0)) {
    return fail("bridge_max_gap_s must be in [0, 10]");
  }
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
  if (!(reference_fps == 0.0 || (reference_fps >= 0.01 && reference_fps <= 1000.0))) {
    return fail("reference_fps must be 0 or in [0.01, 1000]");
  }
  std::string nested;
  if (!sort.Validate(&nested)) return fail("sort: " + nested);
  if (!association.Validate(&nested)) return fail("association: " + nested);
  if (!triangulation.Validate(&nested)) return fail(nested);  // already prefixed "triangulation: "
  if (!linking.Validate(&nested)) return fail("linking: " + nested);
  if (!refinement.Validate(&nested)) return fail(nested);  // already prefixed "refinement: "
  if (!appearance.Validate(&nested)) return fail("appearance: " + nested);
  return true;
}

namespace {

// A person's height (m): SORT's motion buffer is in box heights.
constexpr double kPersonHeightM = 1.7;

// The factor f of AtFrameRate (>= 1: nothing scales).
double RateFactor(const TrackerOptions& options, double seconds_per_frame) {
  MVTRACK_CHECK(std::isfinite(seconds_per_frame) && seconds_per_frame > 0.0);
  if (options.reference_fps <= 0.0) return 1.0;
  return 1.0 / (seconds_per_frame * options.reference_fps);
}

// max(minimum, ceil(n f)); a small tolerance keeps an exact product (30 frames x 0.1) from
// rounding up past it.
int Scaled(int n, int minimum, double f) {
  return std::max(minimum, static_cast<int>(std::ceil(static_cast<double>(n) * f - 1e-9)));
}

// SORT's gate at a stream slower than reference_fps (f < 1, frames seconds_per_frame apart):
// the boxes are buffered by the distance nobody exceeds on foot (linking::kMaxReidSpeedMps, the
// linker's own bound) in the time the frame period exceeds the reference one, in person
// heights (SortOptions::motion_buffer); the IoU threshold stays. docs/DECISIONS.md "Time".
tracking2d::SortOptions ScaledSort(const tracking2d::SortOptions& sort,
                                   double f,
                                   double seconds_per_frame) {
  tracking2d::SortOptions o = sort;
  if (sort.max_age > 0) o.max_age = Scaled(sort.max_age, 1, f);
  o.min_hits = Scaled(sort.min_hits, 1, f);
  o.motion_buffer = linking::kMaxReidSpeedMps * seconds_per_frame * (1.0 - f) / kPersonHeightM;
  o.process_noise_scale = 1.0 / (f * f * f);
  return o;
}

}  // namespace

TrackerOptions AtFrameRate(const TrackerOptions& options, double seconds_per_frame) {
  const double f = RateFactor(options, seconds_per_frame);
  if (!(f < 1.0)) return options;
  TrackerOptions o = options;
  o.window_size = Scaled(options.window_size, 2, f);
  o.window_step = std::min(o.window_size, Scaled(options.window_step, 1, f));
  o.min_tracklet_length = Scaled(options.min_tracklet_length, 1, f);
  o.sort = ScaledSort(options.sort, f, seconds_per_frame);
  if (options.triangulation.phi > 0) o.triangulation.phi = Scaled(options.triangulation.phi, 1, f);
  o.refinement.box_min_duplicate_frames = Scaled(options.refinement.box_min_duplicate_frames, 1, f);
  if (options.refinement.smooth_half_window > 0) {
    o.refinement.smooth_half_window = Scaled(options.refinement.smooth_half_window, 1, f);
  }
  return o;
}

geometry::CameraRig WithSharedViews(geometry::CameraRig rig, const TrackerOptions& options) {
  rig.ComputeSharedViews(options.ground_height_m);
  return rig;
}

association::AssociationOptions AssociationOptionsInEffect(const TrackerOptions& options) {
  association::AssociationOptions ao = options.association;
  if (options.mode == InputMode::kBoxes && !options.box_ends_in_association) ao.num_points = 1;
  if (options.mode == InputMode::kBoxes && options.box_point == BoxPoint::kCenterEnds &&
      options.box_ends_in_association) {
    ao.floor_point = kBoxBottomPoint;  // the feet stand on the floor
    ao.floor_height_m = options.ground_height_m;
  }
  if (options.appearance.enabled) {
    ao.appearance_weight = options.appearance.association_weight;
    ao.appearance_gate = options.appearance.association_gate;
  }
  return ao;
}

tracking2d::SortOptions SortOptionsAtFrameRate(const TrackerOptions& options,
                                               double seconds_per_frame) {
  const double f = RateFactor(options, seconds_per_frame);
  return f < 1.0 ? ScaledSort(options.sort, f, seconds_per_frame) : options.sort;
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
