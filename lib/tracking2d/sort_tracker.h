#pragma once
/// @file
/// SORT single-camera multi-person tracker (Bewley et al., ICIP 2016), the "Multiple-frame
/// Single-view Multi-person Tracking" stage of the paper (Sec. "Method", Fig. 3): it links each
/// camera's detections into 2D tracks, which the sliding window later crops into the 2D
/// tracklets T_{k,i}. One instance per camera; single-owner, single-threaded, no I/O.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/linear_assignment.h"
#include "core/types.h"
#include "tracking2d/kalman_box_tracker.h"

namespace mvtrack::tracking2d {

/// SortTracker settings.
struct SortOptions {
  /// Number of consecutive frames (processed or skipped) a track survives without a match; it
  /// can still be matched in the frame after those. SORT's default is 1 (tuned for MOT
  /// benchmarks); 5 bridges the short occlusions of people crossing (2-5 frames at 25-30 fps),
  /// while a 5-frame constant-velocity extrapolation (about 0.2 s, ~0.25 m at walking speed)
  /// stays on the occluded person, so stale tracks expire before they can drift onto someone
  /// else. A broken track only starts a new 2D tracklet, which cross-view clustering can still
  /// assign to the right person, whereas an identity switch contaminates a tracklet.
  int max_age = 5;
  /// Consecutive matched frames (the creating detection counts as the first) before a track is
  /// confirmed and reported; once confirmed it stays confirmed until it dies. 1 reports every
  /// detection from its first frame: the 3D stage (cross-view clustering, robust
  /// triangulation) already rejects detector false positives, and every withheld observation
  /// is lost to the sliding window. Must be >= 1.
  int min_hits = 1;
  /// Minimum IoU between a track's predicted box and a detection for them to be matched
  /// (SORT's value). In (0, 1].
  double iou_threshold = 0.5;
  /// How far a person may move beyond the Kalman prediction between two processed frames, in
  /// box heights (a person is about as tall as their box): both the predicted box and the
  /// detection are grown by this times their height on every side before their IoU is taken
  /// (the buffered IoU of C-BIoU, Yang et al. WACV 2023). Not a configuration key: the tracker
  /// derives it from the stream's frame period (tracker::AtFrameRate): 0 at the reference
  /// rate, so that slower streams, where a walking person moves a body width between frames
  /// and IoU alone loses them, keep the same gate in metres. >= 0, finite.
  double motion_buffer = 0.0;
  /// The Kalman filter's process noise Q (SORT's, set per frame at the reference rate) times
  /// this. Not a configuration key either: tracker::AtFrameRate sets it to (frame period /
  /// reference period)^3 for a slower stream, the growth of a constant-velocity model's
  /// white-noise acceleration over the longer step in per-frame units, so a person may turn as
  /// much per second at 2 fps as at 25 (1 at the reference rate or faster). Finite, > 0.
  double process_noise_scale = 1.0;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Appearance in SORT (DeepSORT's metric, fused into one cost instead of its matching cascade:
/// docs/DECISIONS.md "Appearance"). Off when weight is 0 and gate is 2 (motion only, SORT).
struct SortAppearance {
  /// Cost of a (track, detection) pair that both carry appearance, where motion is ambiguous
  /// (the track has another detection, or the detection another track, inside the IoU gate):
  /// (1 - weight) (1 - IoU) + weight d, d the cosine distance of the detection's embedding to
  /// the track's nearest gallery entry. Unambiguous pairs keep SORT's cost. In [0, 1].
  double weight = 0.0;
  /// Ambiguous pairs with d above this are never matched. In [0, 2]. Appearance takes part only
  /// while one person's own detections in this camera lie within half the gate of their
  /// track's gallery (median of the latest certain continuations): with noisier embeddings
  /// SORT runs on motion alone.
  double gate = 2.0;
  /// Embeddings a track keeps (the latest). >= 1.
  int gallery_size = 32;

  bool Validate(std::string* why) const;
};

/// One detection of this frame with the 2D track it was assigned to.
struct TrackedDetection {
  /// Unique within this SortTracker, starts at 1, never reused.
  TrackId2D track_id = 0;
  /// Index into the `boxes` vector passed to SortTracker::Update.
  int detection_index = -1;
};

/// A read-only view of one live track (diagnostics and visualisation).
struct TrackSnapshot {
  TrackId2D track_id = 0;
  /// The Kalman estimate at the last processed frame: the posterior when matched there,
  /// otherwise the prediction.
  core::BoxPx box;
  /// Last frame at which a detection was matched (or the track was created).
  FrameIndex last_matched_frame = 0;
  /// True once the track has met SortOptions::min_hits.
  bool confirmed = false;
};

/// SORT (Bewley et al. 2016, Sec. 3): per frame, predict every track with its constant-velocity
/// Kalman filter (KalmanBoxTracker), match tracks to detections by optimal linear assignment
/// (core::SolveAssignment) on the cost 1 - IoU with pairs below `iou_threshold` forbidden,
/// update matched tracks, start a track for each unmatched detection and delete tracks unmatched
/// for more than `max_age` frames.
///
/// Single-owner, single-threaded; one instance per camera.
class SortTracker {
 public:
  /// `options` must be valid (checked; validate configuration beforehand).
  explicit SortTracker(SortOptions options = {});

  /// Processes one frame. Frames must be strictly increasing; a gap of g frames predicts g
  /// steps and counts g frames towards max_age. Boxes that are not IsUsableBox (non-finite,
  /// non-positive size) are ignored: never matched, never start a track, never reported.
  ///
  /// Returns the detections of THIS frame that belong to confirmed tracks (observed boxes only,
  /// never Kalman predictions), sorted by track id. When `frame` is not greater than the
  /// previous frame, returns an empty vector and changes nothing (the caller validates).
  ///
  /// `embeddings` (optional; else parallel to `boxes`): each detection's unit embedding or
  /// null. Used only with set_appearance(); embeddings of another length than a track's
  /// gallery are not compared.
  std::vector<TrackedDetection> Update(
      FrameIndex frame,
      const std::vector<core::BoxPx>& boxes,
      const std::vector<const std::vector<float>*>* embeddings = nullptr);
  /// Uses appearance from now on (valid: checked).
  void set_appearance(const SortAppearance& appearance);
  /// Bytes held by the tracks' galleries.
  std::size_t gallery_bytes() const;

  /// Number of live tracks (confirmed or not).
  int num_tracks() const { return static_cast<int>(tracks_.size()); }

  /// The live tracks in increasing id order.
  std::vector<TrackSnapshot> Tracks() const;

  /// The options in use.
  const SortOptions& options() const { return options_; }
  /// Replaces the options for the following frames (valid: checked); live tracks keep their
  /// state. The tracker scales max_age, min_hits and iou_threshold to the camera's frame rate.
  void set_options(const SortOptions& options);

 private:
  struct Track {
    TrackId2D id = 0;
    KalmanBoxTracker filter;
    FrameIndex last_matched_frame = 0;
    int hit_streak = 0;
    bool confirmed = false;
    std::vector<std::vector<float>> gallery;  // appearance on: the latest embeddings
  };

  // Appearance on: the latest distances of certain continuations to their track's gallery
  // (ring buffer), and whether their median is at most half the gate: only then does
  // appearance take part (embeddings so noisy that one person's own detections are far apart
  // would only break tracks).
  static constexpr std::size_t kSameTrackSamples = 128;
  static constexpr std::size_t kMinSameTrackSamples = 16;
  void RecordSameTrackDistance(double d);
  bool AppearanceReliable() const;
  std::vector<double> same_track_distances_;
  std::size_t next_sample_ = 0;
  // Appearance on: keeps `embedding` (if any, and of the gallery's length) in the track's
  // gallery, the oldest dropped beyond gallery_size.
  void AddToGallery(Track* track, const std::vector<float>* embedding) const;

  SortOptions options_;
  std::optional<SortAppearance> appearance_;
  std::vector<Track> tracks_;  // increasing id order
  std::optional<FrameIndex> last_frame_;
  TrackId2D next_id_ = 1;
  // Per-frame scratch kept between Update() calls so a warmed-up tracker does not reallocate
  // (the cost matrix only when its shape changes).
  std::vector<int> usable_;
  std::vector<core::BoxPx> predicted_;            // Update scratch: predicted box of each track
  std::vector<core::BoxPx> compared_;             // Update scratch: each usable detection's box
  std::vector<int> row_feasible_, col_feasible_;  // Update scratch (appearance): gated pairs
  Eigen::MatrixXd cost_;
  core::AssignmentWorkspace assignment_workspace_;
  core::Assignment assignment_;
};

}  // namespace mvtrack::tracking2d
