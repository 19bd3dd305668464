#pragma once
/// @file
/// One sliding window's work: the immutable job the WindowBuilder emits when a window closes,
/// and ProcessWindowJob, which runs cross-view association (Eq. 2-4, PDNC, Algorithm 1) and
/// CMMT (Algorithm 2, Eq. 5-7) on it. Window linking (Eq. 8-9) is not part of the job: it
/// depends on the previous windows and runs in window order in the WindowFinalizer.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "tracker/options.h"
#include "triangulation/triangulation.h"

namespace mvtrack::tracker {

/// The input of one window, immutable once built (the pipeline shares it across threads as
/// `std::shared_ptr<const WindowJob>`).
struct WindowJob {
  /// Strictly increasing over a Tracker's or Pipeline's life (gaps after a re-anchor or flush).
  std::int64_t window_id = 0;
  FrameIndex begin = 0;          ///< first frame of the window
  FrameIndex end = 0;            ///< one past the last frame ([begin, end); shorter at a flush)
  FrameIndex finalize_from = 0;  ///< this window finalizes the frames [finalize_from,
  FrameIndex finalize_to = 0;    ///<   finalize_to) (see docs/DECISIONS.md "Tracker facade")
  /// The stream's frame period in seconds, measured from the capture times of the latest
  /// closed frames (WindowBuilder): what converts frames to the seconds of the options.
  double seconds_per_frame = 1.0 / 30.0;
  /// Every camera's confirmed 2D tracks cropped to [begin, end), cameras in rig order, tracks
  /// by id; only tracklets with at least min_tracklet_length observations.
  std::vector<core::Tracklet2D> tracklets;
  /// Every 2D track with at least one observation in [begin, end), also those too short to be
  /// a tracklet, sorted by camera id then track id: which 2D tracks are still alive (the
  /// linker ends a lost 3D track none of whose 2D tracks continues).
  std::vector<core::TrackletMember> live_tracks;
};

/// The output of ProcessWindowJob: the window's persons, not yet linked.
struct WindowResult {
  std::int64_t window_id = 0;             ///< copied from the job
  FrameIndex begin = 0;                   ///< copied from the job
  FrameIndex end = 0;                     ///< copied from the job
  FrameIndex finalize_from = 0;           ///< copied from the job
  FrameIndex finalize_to = 0;             ///< copied from the job
  double seconds_per_frame = 1.0 / 30.0;  ///< copied from the job
  /// PDNC clusters of indices into the job's tracklets (association::AssociateTracklets).
  std::vector<std::vector<int>> clusters;
  /// One short-term 3D tracklet per cluster seen by >= 2 cameras with at least one
  /// triangulated frame, in cluster order. Pose mode refines them (TrackerOptions::refinement):
  /// duplicates are merged (the united clusters triangulated again, in the place of the first),
  /// fragments dropped, temporal outliers removed and missing joints completed; the
  /// `source_tracklets` of a merged person list both clusters' tracklets. Box mode removes
  /// points at implausible heights (box_min_height_m, box_max_height_m; a person left without
  /// points is dropped) and merges duplicates by footprint distance (box_merge_distance_m).
  std::vector<core::Tracklet3D> persons;
  /// Box mode with LinkerOptions::monocular_max_s > 0: one tracklet per 2D tracklet that no
  /// person was triangulated from, its frames placed by that camera alone: where the ray through
  /// the bottom of the box (the feet, on the person's vertical axis) meets the floor, as point 0
  /// at 0.9 m above it (the other points missing; frames whose box is cut at the bottom left
  /// out), members, cameras and appearance set: what the linker may continue a track on
  /// (linking::WindowLinker::Link). Empty otherwise.
  std::vector<core::Tracklet3D> monocular;
  /// Copied from the job.
  std::vector<core::TrackletMember> live_tracks;
};

/// A result with the job's window and frame ranges and no persons: what a window that could
/// not be processed contributes (the linker then sees a window without tracklets).
WindowResult EmptyWindowResult(const WindowJob& job);

/// Reusable per-thread scratch space for ProcessWindowJob (the CMMT workspace). Results do not
/// depend on what the workspace was used for before. Single-owner, single-threaded object:
/// one per worker thread.
class WindowWorkspace {
 public:
  /// `options` must be valid.
  explicit WindowWorkspace(const triangulation::TriangulationOptions& options);

  /// The triangulation workspace.
  triangulation::PersonTriangulator& triangulator() { return triangulator_; }

 private:
  triangulation::PersonTriangulator triangulator_;
};

/// Processes one window: association (Eq. 2-4 + PDNC) of the job's tracklets, then CMMT
/// (Algorithm 2) of every cluster whose tracklets come from at least two cameras, then the
/// refinement of triangulation/refinement.h for the mode (see WindowResult::persons).
///
/// Pure and thread-compatible: it reads `rig`, `options` and `job` only (any number of threads
/// may run it concurrently on shared immutable inputs) and writes only `workspace` and its
/// result. `options` must be the valid options the job was built with and `workspace` must
/// have been made for options.triangulation (checked).
WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& options,
                              const WindowJob& job,
                              WindowWorkspace* workspace);

/// One person's triangulation inside ProcessWindowJob: person `index` on workspace `ws`.
using PersonTask = std::function<void(int index, WindowWorkspace* ws)>;
/// Runs task(i, ws) for every i in [0, n) and returns when all calls have returned, in any order
/// and on any threads, each call with a workspace (made for the same triangulation options) that
/// no concurrent call uses. Lets a threaded caller spread one window's persons over its workers.
using PersonLoop = std::function<void(int n, const PersonTask& task)>;

/// ProcessWindowJob with the persons' triangulation (CMMT and its per-person box gating) run by
/// `person_loop` (empty: in order, on `workspace`). The result is identical either way.
WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& options,
                              const WindowJob& job,
                              WindowWorkspace* workspace,
                              const PersonLoop& person_loop);

/// As above with a fresh workspace.
WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& options,
                              const WindowJob& job);

/// Box mode (box_point bottom_center or center_ends): where the ray through the bottom of the
/// box (the feet, on the person's vertical axis) meets the floor z = ground_height_m, as seen by
/// `camera` alone; nullopt in pose mode, for box_point center, for a box cut at the bottom, or
/// when the ray descends less steeply than monocular_min_elevation_deg (a pixel's error then
/// moves the point far along the floor). What places a monocular tracklet
/// (WindowResult::monocular) and a provisional track seen by one camera.
std::optional<Vec3> FeetOnFloor(const geometry::CameraModel& camera,
                                const TrackerOptions& options,
                                const core::Observation2D& observation);

/// One step of ProcessWindowJob, exposed for tests. Box mode: a person seen by two cameras
/// only is weak evidence (any two rays of one epipolar plane meet, so two cameras' tracklets
/// of different people can pair up), three agreeing views are strong. A tracklet of a
/// two-camera person that another person of at least two cameras reprojects onto as closely as
/// one person's own views do (triangulation::ReprojectionResidual at most half of
/// RefinementOptions::box_split_residual) and whose cluster has no tracklet of its camera in
/// the same frames joins that person (the best fitting), which is triangulated again; the
/// two-camera person is dissolved (what is left of it, one camera, can only continue a track
/// alone: LinkerOptions::monocular_max_s). Persons are judged on their triangulations before
/// any move, in order: a person that received a tracklet is not dissolved afterwards, and a
/// dissolved one receives none. `clusters` (indices into job.tracklets) and `persons` are parallel.
/// Off when box_split_residual is 0. docs/DECISIONS.md "Two-camera persons".
void RegroupTwoCameraPersons(const geometry::CameraRig& rig,
                             const TrackerOptions& options,
                             const WindowJob& job,
                             WindowWorkspace* workspace,
                             std::vector<std::vector<int>>* clusters,
                             std::vector<core::Tracklet3D>* persons);

}  // namespace mvtrack::tracker
