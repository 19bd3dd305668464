#pragma once
/// @file
/// A seeded model of 2D pose-detector errors, applied to clean 2D poses (Campus's 2D ground
/// truth, Panoptic's projected 3D ground truth) so the tracker can be evaluated on data with
/// detector-like noise. Stateless and deterministic: the randomness of one camera-frame comes
/// from streams seeded by (seed, frame, camera id), so frames and cameras can be corrupted in
/// any order with identical results.
///
/// The model, per camera-frame (every clean detection in order):
///  0. blackout: the blacked-out camera (if any) detects nothing in its blackout frames;
///  1. miss: the whole person is dropped with probability `miss_rate`;
///  2. keypoint noise: every detected keypoint (confidence > 0) moves by N(0, pixel_noise_px^2)
///     in x and in y, or with `noise_tail_dof` = n > 0 by a bivariate Student t with n degrees
///     of freedom and scale pixel_noise_px (the Gaussian offset times sqrt(n / chi2_n), one
///     chi-square draw per keypoint: heavy tails, a few keypoints far off); a keypoint that
///     leaves the image [0, W] x [0, H] gets confidence 0;
///     box noise (box-only detections, a person detector's output): each of the four box edges
///     moves by the same noise with the scale pixel_noise_px * box height / kReferenceHeightPx
///     (the same relative error at any resolution), the box is clipped to the image, and a box
///     left narrower or lower than 2 px is dropped (counted as a miss);
///  3. joint dropout: every detected keypoint gets confidence 0 with probability
///     `joint_dropout`;
///     a person left with fewer than 2 detected keypoints is dropped (counted as a miss);
///     the box and score are recomputed from the keypoints (BoxFromKeypoints,
///     MeanKeypointScore);
///  4. false positives: Poisson(false_positives_per_frame) ghost poses, each a copy of a
///     uniformly chosen pose from the camera's `false_positive_pool` (clean poses of the same
///     camera at any frame), translated so that its box centre is uniform over the positions
///     that keep the box inside the image, then given the noise and dropout of steps 2-3;
///  4b. false positives near real people: Poisson(near_false_positives_per_frame) poses, each a
///     copy of a uniformly chosen person detected in this camera-frame (after steps 1-3),
///     shifted sideways by 0.2-0.6 of its box height (either side), keeping each keypoint with
///     probability 1/2 (a partial skeleton, as a detector makes of a person half hidden behind
///     another), then given the noise and dropout of steps 2-3;
///  5. the result is shuffled (a uniformly random permutation), so order carries no identity.
/// Each keypoint and person consumes a fixed number of draws from its own stream (miss, noise,
/// tail, dropout, false positives, near false positives, shuffle), so changing one rate changes
/// only what it controls, and the options added after the default level (tails, near false
/// positives, blackout) leave the default level's output unchanged when off.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/detection.h"
#include "core/types.h"

namespace mvtrack::datasets {

/// The person height (pixels) at which pixel_noise_px is meant: Campus's median (360x288). Box
/// noise scales pixel_noise_px by box height / kReferenceHeightPx.
inline constexpr double kReferenceHeightPx = 95.0;

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
  /// Tails of the keypoint noise: 0 Gaussian; n in [1, 30] Student t with n degrees of freedom.
  int noise_tail_dof = 0;
  /// Mean number of partial false-positive poses next to a real person per camera and frame.
  double near_false_positives_per_frame = 0.0;
  /// Length of one camera's blackout, seconds (0: none). The loader places it (PlaceBlackout).
  double blackout_seconds = 0.0;
  /// The placed blackout: camera kNoBlackout (none) or the camera that detects nothing in frames
  /// [blackout_first_frame, blackout_first_frame + blackout_frames).
  CameraId blackout_camera = kNoBlackout;
  FrameIndex blackout_first_frame = 0;  ///< first blacked-out frame
  int blackout_frames = 0;              ///< number of blacked-out frames

  /// blackout_camera when there is no blackout.
  static constexpr CameraId kNoBlackout = -1;

  /// The clean variant: corruption disabled, everything else default.
  static CorruptionOptions Clean();

  /// Finite values; pixel_noise_px >= 0; joint_dropout and miss_rate in [0, 1];
  /// false_positives_per_frame and near_false_positives_per_frame in [0, 50]; noise_tail_dof in
  /// [0, 30]; blackout_seconds in [0, 3600]; blackout_frames >= 0. On failure writes the reason
  /// to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Named corruption levels of `mvtrack convert campus|panoptic --corruption`.
enum class CorruptionLevel {
  kClean,    ///< no corruption
  kDefault,  ///< the dataset's default options
  kHard,     ///< HardCorruption(default options)
};

/// "clean", "default", "hard" -> the level; nullopt for anything else.
std::optional<CorruptionLevel> CorruptionLevelFromName(std::string_view name);

/// The hard level derived from a dataset's default options (same seed): the default's keypoint
/// noise scale with Student-t tails of 3 degrees of freedom (1 % of coordinates off by more than
/// 5.8 scales, against 2.6 for Gaussian noise); joint dropout 0.15; miss
/// rate 0.15; 0.2 false positives and 0.3 partial false positives next to a real person per
/// camera and frame; one camera blacked out for 1 s (placed by the loader inside the test
/// frames). A realistic bad day: a weaker detector, crowded views, a camera that hiccups.
CorruptionOptions HardCorruption(const CorruptionOptions& defaults);

/// The options of `level` for a dataset whose default options are `defaults`.
CorruptionOptions CorruptionForLevel(CorruptionLevel level, const CorruptionOptions& defaults);

/// Places the blackout of `options` (blackout_seconds > 0, enabled): from a stream seeded by
/// options->seed, the camera uniform among `cameras` and the first frame uniform among those
/// for which all blackout_frames = max(1, min(round(blackout_seconds * fps), L / 2)) frames lie
/// inside one of `ranges` (inclusive frame ranges; L the longest one's length; longer ranges
/// hold more starts). Does nothing when blackout_seconds is 0 or corruption is disabled.
void PlaceBlackout(CorruptionOptions* options,
                   const std::vector<CameraId>& cameras,
                   const std::vector<std::pair<FrameIndex, FrameIndex>>& ranges,
                   double fps);

/// One corrupted camera-frame.
struct CorruptedFrame {
  /// The detections (frame, camera_id and utime copied from the clean frame).
  core::CameraFrame frame;
  /// Parallel to frame.detections: the id of the clean detection each one came from
  /// (clean_ids[i]) or kFalsePositiveSourceId for a ghost.
  std::vector<std::int64_t> source_ids;
};

/// Applies the model to one camera-frame of clean detections: poses (keypoints in any layout)
/// or box-only detections (box noise instead of keypoint noise and dropout). `clean_ids` is
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
