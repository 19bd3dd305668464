#pragma once
/// @file
/// Agglomerative clustering of 2D tracklets from their Eq. 4 distance matrix: Algorithm 1 of the
/// paper (PDNC, Propagable Distance-based Non-parametric Clustering) and the conventional
/// alternatives of the paper's appendix, strategies (c)-(e). Stateless functions;
/// thread-compatible; deterministic.

#include <vector>

#include "association/options.h"
#include "association/tracklet_distance.h"

namespace mvtrack::association {

/// One merge performed by ClusterTracklets, in order.
struct MergeStep {
  int cluster_a = 0;      ///< smallest tracklet index of the first merged cluster
  int cluster_b = 0;      ///< smallest tracklet index of the second one (cluster_a < cluster_b)
  double distance = 0.0;  ///< the cluster distance at which they merged (< lambda)
};

/// Clusters the tracklets behind `distances` with the strategy `options.method` and the cut
/// threshold `options.lambda`: starting from singletons, repeatedly merge the two closest
/// clusters while their distance is a value < lambda (Algorithm 1's while loop). Cluster
/// distances after a merge of i and j into p, for every other cluster q:
///  - kPdnc (Algorithm 1, step c): max(d(i,q), d(j,q)) if both are calculable (values or ∞; max
///    with ∞ is ∞), the calculable one if the other is ∅, ∅ if both are ∅. Equivalently, the
///    distance between two clusters is the max over their calculable member pairs, ∅ if none.
///  - kCompleteLinkageEmptyAsZero / kCompleteLinkageEmptyAsUpper: ∅ is replaced by 0 /
///    options.empty_upper_bound up front, then max(d(i,q), d(j,q)).
///  - kSingleLinkageEmptyAsUpper: ∅ := options.empty_upper_bound, then min(d(i,q), d(j,q)),
///    except that ∞ dominates (∞ is a cannot-link in every strategy).
/// Hence no strategy ever forms a cluster holding two tracklets at distance ∞ (same camera,
/// overlapping in time).
///
/// Ties are broken deterministically: among equal distances the pair (a, b), a < b, of smallest
/// member indices that is lexicographically lowest merges first.
///
/// Result: every tracklet in exactly one cluster (singletons included); each cluster is a sorted
/// list of tracklet indices and clusters are ordered by their smallest index. If `trace` is not
/// null it receives the merges in order.
///
/// Cost: O(n^2) memory (one working copy of the packed matrix; none for the rvalue overload).
/// Time: O(n^2) to build per-row nearest-neighbour caches, then per merge O(n) to find the
/// closest pair and update the merged row, plus O(n) for each row whose cached nearest
/// neighbour was one of the two merged clusters: O(n^2) overall when few rows point at merged
/// clusters, O(n^3) in the worst case. No allocation inside the merge loop. `options` must
/// pass Validate() (checked).
std::vector<std::vector<int>> ClusterTracklets(const DistanceMatrix& distances,
                                               const AssociationOptions& options,
                                               std::vector<MergeStep>* trace = nullptr);

/// Same as above, reusing the matrix's storage as the working copy (no O(n^2) copy).
std::vector<std::vector<int>> ClusterTracklets(DistanceMatrix&& distances,
                                               const AssociationOptions& options,
                                               std::vector<MergeStep>* trace = nullptr);

}  // namespace mvtrack::association
