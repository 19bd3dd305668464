#pragma once
/// @file
/// The common result of the dataset loaders (Shelf, Campus, CMU Panoptic, WILDTRACK): cameras,
/// per-frame 2D detections in the tracker's input format, and ground truth in the evaluator's
/// format; plus the typed error every loader throws on missing or malformed files, the data-root
/// lookup, and the small rules the loaders share (box from keypoints, footprint, frame time).
///
/// This is a runtime module (it reads files); it is not one of the pure algorithm modules. The
/// datasets are never copied into the repository: they are read from `../shared/data` relative
/// to the repository root, or from $MVTRACK_DATA. Formats, units and provenance of every file
/// are described in the `SOURCE.md` of each dataset folder. All functions are stateless and
/// thread-compatible.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/types.h"
#include "eval/sequence.h"
#include "geometry/camera_model.h"

namespace mvtrack::datasets {

/// A dataset file is missing, unreadable or malformed. `file()` is the offending file and
/// `problem()` says what is wrong (with line:column and JSON path where known); what() is
/// "<file>: <problem>".
class DatasetError : public std::runtime_error {
 public:
  /// `file`: the offending file (or directory); `problem`: what is wrong with it.
  DatasetError(std::string file, std::string problem);
  /// The offending file.
  const std::string& file() const { return file_; }
  /// What is wrong, without the file name.
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

/// Identity recorded for a detection whose source person is not known (real detector output).
inline constexpr std::int64_t kUnknownSourceId = -2;
/// Identity recorded for a false positive added by the corruption model.
inline constexpr std::int64_t kFalsePositiveSourceId = -1;

/// One loaded dataset, ready for the tracker (detections) and the evaluator (ground truth).
struct Dataset {
  /// "shelf", "campus", "panoptic/160906_band2", "wildtrack".
  std::string name;
  /// The cameras, in the order of the inner index of `detections`; CameraModel::id is the
  /// dataset's camera number (Panoptic: the HD camera index 0..30). Our world frame: metres,
  /// z up.
  std::vector<geometry::CameraModel> cameras;
  /// Frame rate of the frame numbering, frames per second.
  double fps = 0.0;
  /// [frame][camera]: the detections of every camera at every frame of the sequence, frames in
  /// increasing order (frame numbers as in `ground_truth`, see each loader), cameras in the
  /// order of `cameras`. CameraFrame::utime = FrameUtime(frame, fps); CameraFrame::camera_id =
  /// cameras[c].id.
  std::vector<std::vector<core::CameraFrame>> detections;
  /// [frame][camera][detection], same shape as `detections`: the ground-truth id of the person
  /// each detection shows, kFalsePositiveSourceId for corruption false positives, or
  /// kUnknownSourceId for real detector output (Shelf, WILDTRACK). For diagnostics and tests
  /// only: a tracker must not read it.
  std::vector<std::vector<std::vector<std::int64_t>>> source_ids;
  /// Ground truth, one EvalFrame per frame of the sequence (also frames without people).
  /// EvalObject::position = footprint: the hip midpoint dropped onto the ground plane z = 0
  /// (FootprintFromJoints); joints in `gt_layout`, metres. Empty for WILDTRACK.
  eval::EvalSequence ground_truth;
  /// Layout of ground_truth's joints (kNone when there is no ground truth).
  core::KeypointLayoutId gt_layout = core::KeypointLayoutId::kNone;
  /// The frames the dataset's standard protocol scores (empty: all frames).
  std::vector<eval::FrameRange> protocol_frames;
  /// The actor ids the standard protocol scores (empty: all actors).
  std::vector<std::int64_t> protocol_actor_ids;
  /// Human-readable provenance and protocol: frame numbering, cameras, detection source,
  /// joint mapping, corruption level, deviations from the data's own conventions.
  std::string protocol_notes;
};

/// A peer method's published tracking output, as the evaluator reads predictions.
struct PeerOutput {
  /// "4d_association" or "crossview_tracking".
  std::string name;
  /// The output in its own joint order. `native_layout` is kNone when the order is not one of
  /// core's layouts (4D Association's SKEL19); `native_joint_names` always names the joints.
  eval::EvalSequence native;
  core::KeypointLayoutId native_layout = core::KeypointLayoutId::kNone;
  std::vector<std::string> native_joint_names;
  /// The output mapped to the Shelf/Campus 14-joint layout (core::KeypointLayoutId::kShelf14),
  /// ready to be scored against the dataset's ground truth.
  eval::EvalSequence shelf14;
  /// EvalObject ids are dense (1, 2, ... in order of first appearance); `original_ids[id - 1]`
  /// is the id written in the file.
  std::vector<std::uint64_t> original_ids;
  /// Provenance, units, frame numbering and the joint mapping used.
  std::string protocol_notes;
};

/// The data root: $MVTRACK_DATA when set and non-empty, else `<repository>/../shared/data`
/// (the path is fixed at configure time).
std::filesystem::path DefaultDataRoot();

/// Capture time of frame `frame` at `fps`: round(frame * 1e6 / fps) microseconds (the
/// sequence's frame 0 is at utime 0).
Utime FrameUtime(FrameIndex frame, double fps);

/// Fraction of the keypoint bounds' height added on every side of a keypoint-derived box.
inline constexpr double kBoxPaddingFraction = 0.1;

/// The box of a pose: the bounds of the keypoints with confidence > 0, grown on each of the
/// four sides by kBoxPaddingFraction times the bounds' height (at least 1 px), so the box
/// centre is the centre of the keypoint bounds. std::nullopt with fewer than 2 such keypoints.
std::optional<core::BoxPx> BoxFromKeypoints(const std::vector<core::Keypoint2D>& keypoints);

/// Mean confidence of the keypoints with confidence > 0 (0 when there are none): the score of
/// a keypoint-only detection.
double MeanKeypointScore(const std::vector<core::Keypoint2D>& keypoints);

/// A person's footprint on the ground plane (z = 0, z up): the midpoint of joints `l_hip` and
/// `r_hip` of `layout` when both are present, else the centroid of the present joints, with z
/// set to 0. std::nullopt when no joint is present.
std::optional<Vec3> FootprintFromJoints(const std::vector<std::optional<Vec3>>& joints,
                                        core::KeypointLayoutId layout);

}  // namespace mvtrack::datasets
