#pragma once
/// @file
/// Per-person 3D triangulation of one PDNC cluster over one sliding window: the paper's
/// Collaborative Multi-frame Multi-view Triangulation (CMMT, Algorithm 2, Eq. 5-7) and, for the
/// ablation, plain N-view DLT and exhaustive RANSAC triangulation.
///
/// All 2D input is in undistorted pixels (core::Observation2D); 3D output is in the world frame,
/// metres. Stateless functions plus a single-owner, single-threaded workspace class.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "geometry/triangulation.h"
#include "triangulation/complete_linkage.h"

namespace mvtrack::triangulation {

/// Which triangulation TriangulatePerson applies at every (frame, point).
enum class TriangulationMethod {
  kCmmt,    ///< paper Algorithm 2: interpolation + all cross-view pairs + largest-cluster vote
  kDlt,     ///< N-view DLT of the observed points (Eq. 5 generalised to N views)
  kRansac,  ///< exhaustive two-view hypotheses, inliers by reprojection error, DLT refit
};

/// "cmmt", "dlt" or "ransac".
std::string_view TriangulationMethodName(TriangulationMethod method);
/// Inverse of TriangulationMethodName; nullopt for an unknown name.
std::optional<TriangulationMethod> TriangulationMethodFromName(std::string_view name);

/// Options of TriangulatePerson. Defaults follow the paper where it gives values.
struct TriangulationOptions {
  /// Triangulation method (the paper's is CMMT; DLT and RANSAC exist for the ablation).
  TriangulationMethod method = TriangulationMethod::kCmmt;
  /// Interpolation window phi in frames (Eq. 6): an interpolated 2D point at frame t uses the
  /// nearest valid observations before and after t, each at most phi frames away. 0 disables
  /// interpolation (CMMT then votes over observed points only). CMMT only.
  int phi = 7;
  /// Complete-linkage cut kappa in metres (Eq. 7): members of one cluster are pairwise at most
  /// kappa apart. CMMT only.
  double kappa_m = 0.2;
  /// 2D points with a confidence below this (or equal to 0) are not used by any method.
  double min_confidence = 0.1;
  /// RANSAC inlier threshold on the reprojection error, undistorted pixels. RANSAC only.
  double ransac_threshold_px = 15.0;
  /// CMMT: a point is accepted when its largest cluster holds at least
  /// min(min_inliers, number of candidates) candidates. With fewer candidates than min_inliers
  /// all of them must agree (one candidate is accepted, as two-view DLT would be).
  int min_inliers = 2;
  /// CMMT and RANSAC: at most this many views take part at one (frame, point); 0 = all views.
  /// Both methods cost O(views^2) two-view solves per point (CMMT's clustering O(views^4)), so
  /// large rigs need a cap. When more views have points, the most confident view is taken first
  /// and then, greedily, the view whose camera centre is farthest from the chosen ones (widest
  /// baselines; ties: higher confidence, then lower camera id). DLT always uses every view. The
  /// default 8 leaves rigs of up to 8 cameras (all of the paper's datasets) untouched.
  int max_views = 8;

  /// Checks ranges: phi >= 0, kappa_m > 0, min_confidence in [0, 1], ransac_threshold_px > 0,
  /// min_inliers >= 1, max_views == 0 or >= 2, all finite. On failure sets `why` (if non-null)
  /// and returns false.
  bool Validate(std::string* why) const;
};

/// Diagnostics of one TriangulatePerson call (counts, no timing).
struct TriangulationStats {
  /// (frame, point) slots where at least two views had a usable 2D point.
  std::int64_t num_points_attempted = 0;
  /// Slots that produced a 3D point.
  std::int64_t num_points_triangulated = 0;
  /// Interpolated 2D points generated (CMMT, Eq. 6).
  std::int64_t num_interpolated_2d = 0;
  /// Two-view DLT solves (CMMT candidate pairs, RANSAC hypotheses).
  std::int64_t num_pairs_evaluated = 0;
  /// CMMT 3D candidates kept after the cheirality check.
  std::int64_t num_candidates = 0;
  /// Largest CMMT candidate set at one (frame, point).
  int max_candidates_per_point = 0;
  /// Attempted slots where more than max_views views had points (CMMT, RANSAC).
  std::int64_t num_points_view_capped = 0;
};

/// Reusable triangulation workspace bound to one set of options. Buffers persist across frames
/// and calls, so a pipeline job triangulating many people allocates only for its outputs.
/// Single-owner, single-threaded object (not thread-safe; use one per worker).
class PersonTriangulator {
 public:
  /// `options` must pass Validate() (checked; aborts otherwise: config validates first).
  explicit PersonTriangulator(const TriangulationOptions& options);

  /// The options this triangulator uses.
  const TriangulationOptions& options() const { return options_; }
  /// Sets the interpolation window φ (frames, >= 0; checked) for the following calls: the
  /// tracker scales it to the stream's frame rate (tracker::AtFrameRate).
  void set_phi(int phi);

  /// See TriangulatePerson. `stats`, if non-null, is overwritten with this call's diagnostics.
  /// Rows are max(num_points, row_size) long; points from num_points on are left empty for the
  /// caller (box ends, triangulated afterwards).
  core::Tracklet3D Triangulate(const geometry::CameraRig& rig,
                               const std::vector<core::Tracklet2D>& tracklets,
                               const std::vector<int>& cluster,
                               FrameIndex begin,
                               FrameIndex end,
                               int num_points,
                               TriangulationStats* stats = nullptr,
                               int row_size = 0);

 private:
  /// One usable 2D point of one view at the current (frame, point).
  struct ViewPoint {
    Vec2 x_px = Vec2::Zero();
    double confidence = 0.0;
  };

  // Fills points_/view_offsets_/view_score_ for point k at frame t (observed and, for CMMT,
  // interpolated). Returns the number of views with at least one point.
  int Gather(const std::vector<core::Tracklet2D>& tracklets,
             FrameIndex t,
             int k,
             bool interpolate,
             bool best_only,
             TriangulationStats* stats);
  // Fills sel_views_ (ascending) with the views that have points, capped at `max_views` (> 0) by
  // the confidence-then-farthest-camera rule of TriangulationOptions::max_views.
  void SelectViews(int max_views, TriangulationStats* stats);
  std::optional<Vec3> SolveCmmt(TriangulationStats* stats);
  std::optional<Vec3> SolveDlt();
  std::optional<Vec3> SolveRansac(TriangulationStats* stats);

  TriangulationOptions options_;
  ClusterVoter voter_;
  // Per call.
  std::vector<std::pair<int, int>> entries_;  // (rig camera index, position in cluster)
  std::vector<Mat34> view_projections_;       // one per view (distinct camera), ascending camera id
  std::vector<Vec3> view_centers_;            // camera centres, world frame
  std::vector<double> center_distance_;       // views x views distances between camera centres
  std::vector<int> view_tracklets_;           // tracklet indices grouped by view
  std::vector<int> view_tracklet_offsets_;
  std::vector<int> cursor_;  // per view_tracklets_ entry: first index with frame >= t
  // Per (frame, point).
  std::vector<ViewPoint> points_;     // grouped by view
  std::vector<int> view_offsets_;     // size = number of views + 1
  std::vector<double> view_score_;    // per view: highest confidence among its points
  std::vector<int> sel_views_;        // views taking part, ascending
  std::vector<double> min_distance_;  // SelectViews: distance to the chosen set
  std::vector<char> chosen_;
  std::vector<geometry::TwoViewRows> rows_;  // CMMT: DLT rows of points_ (selected views)
  std::vector<Vec3> candidates_;
  std::vector<Mat34> sel_projections_;  // DLT / RANSAC: one entry per view with a point
  std::vector<Vec2> sel_points_;
  std::vector<double> sel_weights_;
  std::vector<char> inlier_;
  std::vector<char> best_inlier_;
  std::vector<Mat34> fit_projections_;
  std::vector<Vec2> fit_points_;
  std::vector<double> fit_weights_;
  std::vector<std::optional<Vec3>> row_;
};

/// Triangulates one person (a PDNC cluster) over the window frames [begin, end).
///
/// `cluster` indexes `tracklets`; every point index k < num_points (box mode: 1, pose mode: the
/// number of joints) is triangulated per frame with `options.method`:
///  - CMMT (Algorithm 2): each tracklet is merged with its interpolated tracklet (Eq. 6: at frame
///    t, the linear interpolation of the nearest valid observations before and after t, both
///    within phi frames and excluding t itself), so a frame may hold an observed and an
///    interpolated point per tracklet. For every pair of distinct cameras, every combination of
///    their points gives a 3D candidate by two-view DLT (Eq. 5); candidates behind either camera
///    are dropped; complete linkage with cut kappa; the centroid of the largest cluster (Eq. 7).
///  - DLT: confidence-weighted N-view DLT of the observed points at that frame.
///  - RANSAC: a hypothesis from every pair of observed views (exhaustive, deterministic), inliers
///    by reprojection error <= ransac_threshold_px, the hypothesis with the most inliers (then the
///    smallest summed inlier error, then the first pair) is refitted by weighted DLT on its
///    inliers; at least two inlier views are required.
/// CMMT and RANSAC use at most options.max_views views per (frame, point) (see there).
/// Tracklets of the same camera (non-overlapping fragments of one person) form one view and are
/// never paired with each other. DLT and RANSAC use one point per view: the most confident
/// observed one (the first in cluster order on ties). Every method drops a point that lies
/// behind a camera it used. Points need confidence >= min_confidence and > 0.
///
/// Returns a Tracklet3D holding the frames where at least one point was triangulated (each with
/// num_points entries); `cameras` = sorted unique camera ids of the cluster's tracklets that the
/// rig knows (tracklets of unknown cameras are ignored); `source_tracklets` = `cluster`.
/// Requirements (checked): valid options, num_points >= 1, begin <= end, cluster indices in
/// range, tracklets with frames/observations of equal length. Stateless (allocates a fresh
/// PersonTriangulator; hot loops should keep one).
core::Tracklet3D TriangulatePerson(const geometry::CameraRig& rig,
                                   const std::vector<core::Tracklet2D>& tracklets,
                                   const std::vector<int>& cluster,
                                   FrameIndex begin,
                                   FrameIndex end,
                                   int num_points,
                                   const TriangulationOptions& options);

}  // namespace mvtrack::triangulation
