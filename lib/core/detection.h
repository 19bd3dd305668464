#pragma once
/// @file
/// 2D detections as they enter the tracker (one camera, one frame), and their validation.
/// Pure data plus stateless validation functions.

#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "core/types.h"

namespace mvtrack::core {

/// Axis-aligned box in (distorted, raw) image pixels; x right, y down, origin at the top-left
/// corner of the top-left pixel.
struct BoxPx {
  double x_min = 0.0;
  double y_min = 0.0;
  double x_max = 0.0;
  double y_max = 0.0;

  double width() const { return x_max - x_min; }
  double height() const { return y_max - y_min; }
  Vec2 center() const { return {0.5 * (x_min + x_max), 0.5 * (y_min + y_max)}; }
  Vec2 bottom_center() const { return {0.5 * (x_min + x_max), y_max}; }
  Vec2 top_center() const { return {0.5 * (x_min + x_max), y_min}; }
};

/// One 2D keypoint in raw image pixels; confidence in [0, 1], 0 meaning "not detected".
struct Keypoint2D {
  Vec2 position_px = Vec2::Zero();
  double confidence = 0.0;
};

/// One person detection in one camera image.
struct Detection2D {
  BoxPx box;
  /// Detector score in [0, 1].
  double score = 1.0;
  /// Empty for box-only detections; otherwise one entry per joint of `layout`.
  std::vector<Keypoint2D> keypoints;
  KeypointLayoutId layout = KeypointLayoutId::kNone;
  /// Optional appearance (re-identification) embedding; empty when absent.
  std::vector<float> embedding;
  /// Name of the model that computed `embedding` (detection_t.embedding_model; may be empty).
  std::string embedding_model;
};

/// All detections of one camera for one synchronized frame.
struct CameraFrame {
  Utime utime = 0;  ///< capture time, µs
  FrameIndex frame = 0;
  CameraId camera_id = 0;
  std::vector<Detection2D> detections;
};

/// Limits applied to untrusted detections.
struct DetectionLimits {
  int image_width_px = 0;   ///< 0 = unknown, no image-bounds checks
  int image_height_px = 0;  ///< 0 = unknown, no image-bounds checks
  /// Boxes may stick out of the image by this fraction of the image size before rejection.
  double box_margin_fraction = 0.5;
  /// Boxes (and their visible part) narrower or lower than this are rejected, pixels.
  double min_box_size_px = 2.0;
  /// Detections with more keypoints than this are rejected.
  int max_keypoints = 64;
  /// Detections with a longer appearance embedding than this are rejected.
  int max_embedding_size = 4096;

  /// True when the limits are usable: image sizes >= 0, box_margin_fraction finite and >= 0,
  /// min_box_size_px finite and > 0, max_keypoints >= 0, max_embedding_size >= 0. Otherwise
  /// false, with the first violated condition written to `why` (when not null).
  bool Validate(std::string* why) const;
};

/// What validation did to one detection.
enum class DetectionVerdict {
  kAccepted,          ///< used as is
  kAcceptedRepaired,  ///< used; some keypoints were invalidated (confidence set to 0)
  kRejected,          ///< not used; `reason` says why
};

struct DetectionCheck {
  DetectionVerdict verdict = DetectionVerdict::kAccepted;
  std::string reason;  ///< empty when accepted unchanged
  /// The embedding was dropped (oversized or non-finite; the reason says which).
  bool embedding_dropped = false;
};

/// Validates `detection` in place: non-finite or degenerate boxes, non-finite or out-of-range
/// scores, boxes (almost) entirely outside the image, or a keypoint count that does not match
/// the layout reject the detection. Keypoints that are non-finite, have an out-of-range
/// confidence, or lie outside the image (plus margin) get confidence 0, and an embedding that
/// is oversized or holds a non-finite value is dropped (cleared); the detection is kept
/// (kAcceptedRepaired, the reason says what was done). Stateless.
DetectionCheck ValidateDetection(Detection2D* detection, const DetectionLimits& limits);

}  // namespace mvtrack::core
