#pragma once
/// @file
/// WindowFinalizer: the last stage. It links each window's persons to long-term 3D tracks
/// (linking::WindowLinker, paper Eq. 8-9) strictly in window order, and turns the closed frames
/// into finalized Frame3D outputs (footprints, 3D joints, confidence, age). Pure, single-owner,
/// single-threaded object.

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "body/skeleton.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "linking/window_linker.h"
#include "tracker/options.h"
#include "tracker/types.h"
#include "tracker/window_builder.h"
#include "tracker/window_job.h"

namespace mvtrack::tracker {

/// Cumulative counters of a WindowFinalizer.
struct FinalizerCounters {
  std::int64_t frames_finalized = 0;   ///< Frame3D emitted
  std::int64_t windows_processed = 0;  ///< WindowResults linked
  std::int64_t tracks_born = 0;        ///< long-term tracks started
  std::int64_t tracks_revived = 0;     ///< ended tracks re-identified by appearance
  std::int64_t gallery_bytes = 0;      ///< appearance galleries' memory (latest window)
};

/// Consumes, in the order of the WindowBuilder's output sequence, closed frames
/// (AddClosedFrame), window results (Finalize; a result of ProcessWindowJob on that position's
/// WindowJob) and stream ends (EndStream), and emits finalized frames in increasing frame order.
/// A frame is output when the window that finalizes it has been linked (docs/DECISIONS.md
/// "Tracker facade"): it holds the confirmed tracks of that window's persons at that frame.
/// A confirmed track missing for at most TrackerOptions::bridge_max_gap_s gets the frames of the
/// gap that are not output yet interpolated (its points on both sides, linearly; no cameras).
/// Pose mode with refinement.fit_skeleton: every output frame's joints are fitted to the 2D
/// keypoints of the person's views (body::FitJoints) with its track's bone lengths
/// (body::BoneLengths, from the triangulated joints of the frames its windows finalized, the
/// current window's included) and near the track's previous frame.
/// Footprint (linking::FrameFootprint over tracker::FootprintPoints): box mode the
/// triangulated box point (center_ends: the centre) dropped onto z = ground_height_m; pose mode
/// the hip midpoint (else the centroid of the triangulated joints) dropped onto the floor.
///
/// Single-owner, single-threaded; deterministic.
class WindowFinalizer {
 public:
  /// `options` must be valid (checked by the caller: Tracker::Create / Pipeline::Create);
  /// `rig`: the cameras the window jobs' rig indices refer to.
  WindowFinalizer(const geometry::CameraRig& rig, const TrackerOptions& options);

  /// Registers a closed frame (a ClosedFrame of the builder's output).
  void AddClosedFrame(const ClosedFrame& frame);

  /// Links the next window's persons (Eq. 8-9), assigns their points in the window's finalize
  /// range to the closed frames, and appends every frame that became final to `out` (in
  /// increasing order). Results must come in increasing window_id (checked by the linker).
  /// Returns the linker's decisions.
  linking::LinkResult Finalize(const WindowResult& result, std::vector<Frame3D>* out);

  /// A StreamEnd of the builder's output: appends every closed frame not yet output to `out`.
  void EndStream(std::vector<Frame3D>* out);

  /// Cumulative counters.
  const FinalizerCounters& counters() const { return counters_; }
  /// The long-term tracks (diagnostics).
  const linking::WindowLinker& linker() const { return linker_; }
  /// Number of closed frames waiting to be output.
  std::size_t num_pending_frames() const { return pending_.size(); }

 private:
  struct PendingFrame {
    FrameIndex frame;
    Utime utime;
    std::vector<Track3D> tracks;  // filled when its finalizing window is linked
    bool final = false;
  };

  Vec3 FootprintOf(const std::vector<std::optional<Vec3>>& points) const;
  Track3D MakeTrack(TrackId3D id,
                    const std::vector<std::optional<Vec3>>& points,
                    FrameIndex frame,
                    FrameIndex first_frame,
                    linking::TrackState state) const;
  void EmitFinal(FrameIndex up_to, std::vector<Frame3D>* out);

  InputMode mode_ = InputMode::kBoxes;
  double ground_height_m_ = 0.0;
  int num_points_ = 1;
  linking::WindowLinker linker_;
  std::map<TrackId3D, FrameIndex> first_frame_of_track_;
  struct LastOutput {
    FrameIndex frame = 0;
    std::vector<std::optional<Vec3>> points;
  };
  std::map<TrackId3D, LastOutput> last_output_;  // each output track's latest output frame
  double bridge_max_gap_s_ = 0.0;                // TrackerOptions::bridge_max_gap_s
  std::map<FrameIndex, PendingFrame> pending_;   // closed frames not yet emitted
  FinalizerCounters counters_;
  // The skeleton fit (pose mode with refinement.fit_skeleton).
  bool fit_skeleton_ = false;
  std::vector<Mat34> projections_;  // by rig index, undistorted pixels
  core::KeypointLayout layout_;
  body::FitOptions fit_options_;
  std::map<TrackId3D, body::BoneLengths> bone_lengths_;  // of the tracks alive
};

}  // namespace mvtrack::tracker
