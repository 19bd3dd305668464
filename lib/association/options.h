#pragma once
/// @file
/// Options of the cross-view association (paper Sec. 3.1: Eq. 2-4 and Algorithm 1, PDNC), and
/// the clustering strategies compared in the paper's appendix. Plain data plus validation.

#include <optional>
#include <string>
#include <string_view>

namespace mvtrack::association {

/// How the tracklet distance matrix is clustered. All strategies merge the closest pair of
/// clusters while its distance is below `AssociationOptions::lambda`; they differ in how the
/// incalculable distance ∅ of Eq. 4 is treated and how cluster distances are updated. In every
/// strategy the infinite distance ∞ of Eq. 4 (same camera, temporal overlap) is a hard
/// cannot-link: a cluster never contains two tracklets whose distance is ∞.
enum class ClusteringMethod {
  /// Algorithm 1 (the paper's proposal): ∅ is kept as a third kind of distance; after a merge
  /// the distance to another cluster is the max of the two calculable distances, the
  /// calculable one if the other is ∅, and ∅ if both are ∅. ∅ never triggers a merge.
  kPdnc,
  /// Appendix strategy (c): ∅ := 0, complete linkage (max update).
  kCompleteLinkageEmptyAsZero,
  /// Appendix strategy (d): ∅ := `empty_upper_bound`, complete linkage (the "conventional
  /// complete-linkage clustering" of Algorithm 1's struck-out line and of the ablation).
  kCompleteLinkageEmptyAsUpper,
  /// Appendix strategy (e): ∅ := `empty_upper_bound`, single linkage (min update; ∞ still
  /// dominates, see above).
  kSingleLinkageEmptyAsUpper,
};

/// Stable lower_snake name of `method` ("pdnc", "complete_linkage_empty_as_zero",
/// "complete_linkage_empty_as_upper", "single_linkage_empty_as_upper"), e.g. for config files.
std::string_view ClusteringMethodName(ClusteringMethod method);
/// Inverse of ClusteringMethodName; nullopt for an unknown name.
std::optional<ClusteringMethod> ClusteringMethodFromName(std::string_view name);

/// Options of the tracklet distance (Eq. 2-4) and of the clustering (Algorithm 1).
struct AssociationOptions {
  /// Cut threshold λ on the normalized epipolar distance (Eq. 2 units: a fraction of the
  /// person's image scale |w + h|). Two clusters merge only while their distance is < λ.
  /// The paper uses λ = 0.3 (Sec. 4, Table of hyper-parameters).
  double lambda = 0.3;
  /// Points (box centre or joints) with a lower confidence are not used by Eq. 2; points with
  /// confidence 0 are never used. In [0, 1].
  double min_confidence = 0.1;
  /// Eq. 2 averages over the first `num_points` points of each observation only (0: all of
  /// them). Set by the tracker (box ends that do not take part in association); not a file
  /// option. >= 0.
  int num_points = 0;
  /// Index of the point that stands on the floor plane z = floor_height_m (box mode with the
  /// box ends: the feet), or -1 for none. For that point Eq. 2's point-to-line distances are
  /// replaced by point-to-point distances: each view's point is carried over the floor plane
  /// into the other view, and the mean of the two normalized distances is taken (a person's
  /// feet are one floor point, which fixes where along the epipolar line the other view's feet
  /// must be). Set by the tracker (docs/DECISIONS.md "Feet on the floor"); not a file option.
  int floor_point = -1;
  /// Height of the floor plane in the world frame (TrackerOptions::ground_height_m). Set by the
  /// tracker with floor_point; finite.
  double floor_height_m = 0.0;
  /// Appearance fusion (the paper's "w/ appearance" variant): a finite cross-camera distance
  /// becomes d + appearance_weight x the cosine distance between the two tracklets' mean
  /// embeddings (when both have one); ∅ and ∞ are unchanged. 0 = epipolar only. Set by the
  /// tracker from core::AppearanceOptions; not a file option of this map. Finite, >= 0.
  double appearance_weight = 0.0;
  /// Appearance gate (DeepSORT's gate, for cross-view association): a finite cross-camera
  /// distance becomes ∞ (the two cannot be one person) when the cosine distance between the two
  /// tracklets' mean embeddings is above this, provided the embeddings can tell: each tracklet's
  /// own embeddings agree so well that the same person's two means would be expected within
  /// half the gate (ExpectedLookDistance). >= 2: no gate. Set by the tracker from
  /// core::AppearanceOptions; not a file option of this map. In [0, 2].
  double appearance_gate = 2.0;
  /// Clustering strategy; kPdnc is the paper's method, the others exist for the ablation.
  ClusteringMethod method = ClusteringMethod::kPdnc;
  /// Value substituted for ∅ by kCompleteLinkageEmptyAsUpper and kSingleLinkageEmptyAsUpper
  /// (the appendix uses 1.0). Finite, >= 0. Unused by the other strategies.
  double empty_upper_bound = 1.0;

  /// True when every field is in range; otherwise sets `why` (if non-null) naming the field.
  bool Validate(std::string* why) const;
};

}  // namespace mvtrack::association
