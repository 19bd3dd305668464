#pragma once
/// @file
/// A seeded model of 2D pose-detector errors, applied to clean 2D poses (Campus's 2D ground
/// truth, Panoptic's projected 3D ground truth) so the tracker can be evaluated on data with
/// detector-like noise. Stateless and deterministic: the randomness of one camera-frame comes
/// from streams seeded by (seed, frame, camera id), so frames and cameras can be corrupted in
/// any order with identical results.
///
/// The model, per camera-frame (every clean detection in order):
///  1. miss: the whole person is dropped with probability `miss_rate`;
///  2. keypoint noise: every detected keypoint (confidence > 0) moves by N(0, pixel_noise_px^2)
///     in x and in y; a keypoint that leaves the image [0, W] x [0, H] gets confidence 0;
///  3. joint dropout: every detected keypoint gets confidence 0 with probability
///     `joint_dropout`;
///     a person left with fewer than 2 detected keypoints is dropped (counted as a miss);
///     the box and score are recomputed from the keypoints (BoxFromKeypoints,
///     MeanKeypointScore);
///  4. false positives: Poisson(false_positives_per_frame) ghost poses, each a copy of a
///     uniformly chosen pose from the camera's `false_positive_pool` (clean poses of the same
///     camera at any frame), translated so that its box centre is uniform over the positions
///     that keep the box inside the image, then given the noise and dropout of steps 2-3;
///  5. the result is shuffled (a uniformly random permutation), so order carries no identity.
/// Each keypoint and person consumes a fixed number of draws from its own stream (miss, noise,
/// dropout, false positives, shuffle), so changing one rate changes only what it controls.

#include <cstdint>
#include <string>
#include <vector>

#include "core/detection.h"

namespace mvtrack::datasets {

/// Parameters of the corruption model. The defaults model a modern top-down 2D pose estimator
/// at Campus's resolution (360x288, people 65-167 px tall, median 95 px): keypoint noise
/// sigma 2 px (about 2 % of the person height, the order of HRNet-class localisation errors),
/// 5 % of joints lost (low-confidence, occluded parts), 5 % of people missed in a view, 0.1
/// ghost detections per view and frame (a detector run at a high-precision threshold).
struct CorruptionOptions {
  /// false: the clean variant, detections are passed through unchanged.
  bool enabled = true;
  /// Master seed of the random streams.
  std::uint64_t seed = 1;
  /// Standard deviation of the keypoint noise in x and in y, pixels.
  double pixel_noise_px = 2.0;
  /// Probability that a detected keypoint is lost (confidence set to 0).
  double joint_dropout = 0.05;
  /// Probability that a person is not detected at all in one view.
  double miss_rate = 0.05;
  /// Mean number of false-positive poses per camera and frame (Poisson).
  double false_positives_per_frame = 0.1;

  /// The clean variant: corruption disabled, everything else default.
  static CorruptionOptions Clean();

  /// Finite values; pixel_noise_px >= 0; joint_dropout and miss_rate in [0, 1];
  /// false_positives_per_frame in [0, 50]. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// One corrupted camera-frame.
struct CorruptedFrame {
  /// The detections (frame, camera_id and utime copied from the clean frame).
  core::CameraFrame frame;
  /// Parallel to frame.detections: the id of the clean detection each one came from
  /// (clean_ids[i]) or kFalsePositiveSourceId for a ghost.
  std::vector<std::int64_t> source_ids;
};

/// Applies the model to one camera-frame of clean pose detections (keypoints in any layout;
/// box-only detections have no keypoints and are only subject to misses). `clean_ids` is
/// parallel to clean.detections. `image_width_px`, `image_height_px` > 0 are the image size.
/// With options.enabled false, returns the clean frame and ids unchanged. `options` must be
/// valid (checked).
CorruptedFrame CorruptCameraFrame(const core::CameraFrame& clean,
                                  const std::vector<std::int64_t>& clean_ids,
                                  const std::vector<core::Detection2D>& false_positive_pool,
                                  int image_width_px,
                                  int image_height_px,
                                  const CorruptionOptions& options);

/// Human-readable one-line description of `options` for protocol notes.
std::string DescribeCorruption(const CorruptionOptions& options);

}  // namespace mvtrack::datasets
