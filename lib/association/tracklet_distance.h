#pragma once
/// @file
/// Cross-view distance between 2D tracklets of one sliding window: the normalized epipolar
/// distance of Eq. 2 averaged over points, the per-window distance set of Eq. 3 and the
/// three-case tracklet distance of Eq. 4 (a value, ∅ or ∞), and the symmetric matrix of those
/// distances that Algorithm 1 (PDNC) clusters. Stateless functions and a plain value type;
/// thread-compatible.

#include <cstddef>
#include <vector>

#include "association/options.h"
#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"

namespace mvtrack::association {

/// Eq. 4: a value (mean normalized epipolar distance over common frames), ∅ (incalculable: no
/// common frame, or no common usable point in any common frame), or ∞ (same camera and
/// temporal overlap: the two tracklets cannot be the same person).
struct TrackletDistance {
  /// Which case of Eq. 4 this distance is.
  enum class Kind { kValue, kEmpty, kInfinite };
  Kind kind = Kind::kEmpty;
  double value = 0.0;  ///< meaningful for kValue only: finite, >= 0

  /// A calculable distance `v` (finite, >= 0).
  static TrackletDistance Value(double v) { return {Kind::kValue, v}; }
  /// The incalculable distance ∅.
  static TrackletDistance Empty() { return {Kind::kEmpty, 0.0}; }
  /// The infinite distance ∞ (a cannot-link).
  static TrackletDistance Infinite() { return {Kind::kInfinite, 0.0}; }

  bool is_value() const { return kind == Kind::kValue; }
  bool is_empty() const { return kind == Kind::kEmpty; }
  bool is_infinite() const { return kind == Kind::kInfinite; }
  /// Same kind and, for values, the same value.
  bool operator==(const TrackletDistance& other) const {
    return kind == other.kind && (kind != Kind::kValue || value == other.value);
  }
};

namespace internal {
class DistanceMatrixAccess;
}  // namespace internal

/// Symmetric n x n matrix of TrackletDistance; the diagonal is not stored and must not be
/// accessed. Every entry starts as ∅. Storage is the packed strict upper triangle of doubles
/// (n (n - 1) / 2 entries, 8 bytes each: about 41 MB for n = 3200), with ∅ encoded as NaN and
/// ∞ as +infinity, which is why at() returns by value.
class DistanceMatrix {
 public:
  /// The empty (0 x 0) matrix.
  DistanceMatrix() = default;
  /// An n x n matrix (n >= 0) whose off-diagonal entries are all ∅.
  explicit DistanceMatrix(int n);

  /// Number of tracklets n.
  int size() const { return n_; }
  /// Distance between i and j (0 <= i, j < n, i != j); at(i, j) == at(j, i).
  TrackletDistance at(int i, int j) const;
  /// Sets the distance between i and j (and j and i). A kValue must be finite and >= 0
  /// (checked: programmer error).
  void set(int i, int j, TrackletDistance d);

 private:
  friend class internal::DistanceMatrixAccess;
  std::size_t PackedIndex(int i, int j) const;

  int n_ = 0;
  std::vector<double> packed_;  ///< row-major strict upper triangle; NaN = ∅, +inf = ∞
};

/// Eq. 3-4 between tracklets `a` and `b`. `f_a_to_b` maps undistorted points of a's camera to
/// epipolar lines in b's camera (rig.fundamental(index(a.camera_id), index(b.camera_id))); it
/// is not used when both tracklets come from the same camera.
///  - No common frame (same or different camera): ∅.
///  - Same camera and at least one common frame: ∞.
///  - Different cameras: per common frame, Eq. 2 averaged over the points usable in both
///    observations (confidence >= options.min_confidence and > 0; the first
///    min(#points a, #points b) points are compared, point k with point k), using
///    Observation2D::scale_px as |w + h|; frames without a common usable point are skipped
///    (so are points whose Eq. 2 value is not finite, e.g. a point exactly at an epipole);
///    the result is the mean over the remaining frames, or ∅ if none remains.
/// Cost O(|a| + |b| + common frames x points); no allocation. Without a floor point only
/// (options.floor_point must be -1, checked): use the rig overload for one.
TrackletDistance ComputeTrackletDistance(const core::Tracklet2D& a,
                                         const core::Tracklet2D& b,
                                         const Mat3& f_a_to_b,
                                         const AssociationOptions& options);

/// ComputeTrackletDistance with the rig's F, and for the floor point
/// (AssociationOptions::floor_point) the floor-plane transfer between the two cameras: that
/// point's term is the mean of |T_ab(x_a) - x_b| / |w_b + h_b| and |T_ba(x_b) - x_a| / |w_a +
/// h_a|, where T carries a pixel over the floor plane into the other camera; a frame's floor
/// point is not used when either transfer does not exist (a ray that misses the floor in front
/// of its camera, a floor point behind the other). Two cameras that the rig says never see one
/// place (CameraRig::SharesView, computed by the tracker) give ∞ with a common frame (they
/// cannot see one person at once), else ∅. Both cameras must be in `rig` (checked).
TrackletDistance ComputeTrackletDistance(const geometry::CameraRig& rig,
                                         const core::Tracklet2D& a,
                                         const core::Tracklet2D& b,
                                         const AssociationOptions& options);

/// Eq. 4 for every pair of `tracklets`: ComputeTrackletDistance(rig, ...) of each pair, up to
/// rounding. Every tracklet's camera must be in `rig` (checked with MVTRACK_CHECK: the
/// caller builds tracklets from the rig's cameras, so an unknown camera is a programmer error);
/// `options` must pass Validate() (checked). Computed camera pair by camera pair on a flat copy
/// of the tracklets, with each point's epipolar line in the other camera computed once per
/// camera pair, so Eq. 2 costs two dot products per point pair. Pairs whose frame ranges do not
/// intersect are ∅ in O(1). Time O(n^2) plus O(common frames x points) per overlapping pair of
/// different cameras; memory the matrix plus O(total observations x points).
DistanceMatrix ComputeDistanceMatrix(const geometry::CameraRig& rig,
                                     const std::vector<core::Tracklet2D>& tracklets,
                                     const AssociationOptions& options);

/// ComputeDistanceMatrix for clustering only: the computation of a pair stops as soon as its
/// mean is proven to be >= options.lambda (partial sum / number of common frames >= lambda),
/// and the entry then holds that lower bound, a value in [lambda, exact mean]. Kinds (value, ∅,
/// ∞) and all values < lambda are exactly those of ComputeDistanceMatrix. Every
/// ClusteringMethod gives the same clusters on both matrices: a distance >= lambda never
/// triggers a merge, and a cluster distance that involves it is either >= lambda too (max; ∞
/// dominates) or does not depend on it (min below lambda). Used by AssociateTracklets; much
/// cheaper in crowded scenes, where most pairs are different people far above lambda.
DistanceMatrix ComputeDistanceMatrixForClustering(const geometry::CameraRig& rig,
                                                  const std::vector<core::Tracklet2D>& tracklets,
                                                  const AssociationOptions& options);

/// The cosine distance expected between the mean embeddings of two tracklets of one person,
/// from how well each tracklet's own embeddings agree: tracklet a has `count_a` unit embeddings
/// whose sum has length `length_a` (likewise b). The mean pairwise cosine inside a tracklet is
/// s = (length^2 - count) / (count (count - 1)); if every embedding of the person is its look
/// plus independent noise, two of them, from the same tracklet or not, agree by s on average
/// (the geometric mean of the two tracklets' s is taken), so the two sums' expected dot product
/// is count_a count_b s and the expected cosine distance of the means is 1 - that / (length_a
/// length_b). 2 (nothing can be expected) when a tracklet has fewer than two embeddings. A
/// different look from another side of the person is not in it (the gate allows for that).
double ExpectedLookDistance(int count_a, double length_a, int count_b, double length_b);

namespace internal {
/// Raw access to a DistanceMatrix's packed storage, for the clustering's in-place working copy.
/// Not part of the public API.
class DistanceMatrixAccess {
 public:
  /// The packed strict upper triangle (row-major; NaN = ∅, +inf = ∞).
  static std::vector<double>& Packed(DistanceMatrix& m) { return m.packed_; }
  /// Read-only variant of Packed.
  static const std::vector<double>& Packed(const DistanceMatrix& m) { return m.packed_; }
};
}  // namespace internal

}  // namespace mvtrack::association
