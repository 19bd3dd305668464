#pragma once
/// @file
/// Complete-linkage clustering of 3D candidate positions with a distance cut, and the
/// largest-cluster vote of CMMT (paper Algorithm 2, steps b and c; Eq. 7).
///
/// Clustering is the conventional agglomerative complete linkage: two clusters may merge only if
/// every pair of their members is at most `kappa_m` apart, so every cluster has a diameter
/// <= kappa_m (which implies Eq. 7's constraint ||X - X_cand|| <= kappa for its centroid X).
/// Exact algorithm, O(m^2) time and O(m^2) memory in the worst case for m candidates:
///  1. if the bounding box of all candidates has a diagonal <= kappa, they form one cluster;
///  2. otherwise the candidates are split into the connected components of the graph
///     "distance <= kappa" (sweep along x); no complete-linkage cluster can span two components;
///  3. each component is clustered with the nearest-neighbour-chain algorithm (Murtagh 1983,
///     complete linkage is reducible) on a full (s x s) float distance matrix in which pairs
///     further apart than kappa are +inf, i.e. "never mergeable". The vote visits components by
///     decreasing size and stops once a component cannot beat the best cluster found.
/// Ties between equal merge distances are broken deterministically (NN-chain prefers the previous
/// chain element, then the lowest index), so results depend only on the input order.

#include <optional>
#include <span>
#include <vector>

#include "core/types.h"

namespace mvtrack::triangulation {

/// Result of the largest-cluster vote (Eq. 7).
struct ClusterVote {
  /// Centroid (unweighted mean, Eq. 7) of the largest cluster, world frame, metres.
  Vec3 point = Vec3::Zero();
  /// Number of candidates in the largest cluster, |omega_largest|.
  int cluster_size = 0;
  /// Number of (finite) candidates that took part in the vote.
  int num_candidates = 0;
};

/// Reusable workspace for complete-linkage clustering and the largest-cluster vote. Keeps its
/// buffers between calls so the per-frame hot loop of CMMT does not allocate once warmed up.
/// Single-owner, single-threaded object (not thread-safe; use one per thread).
class ClusterVoter {
 public:
  /// Complete-linkage clustering of `candidates` with cut `kappa_m` (> 0, finite), then the
  /// centroid of the largest cluster (Eq. 7). Non-finite candidates are ignored. Returns nullopt
  /// when no finite candidate exists.
  ///
  /// Tie-break among clusters of equal size: the cluster with the smallest mean Euclidean
  /// distance of its members to its centroid wins (the tightest, most self-consistent one; mean
  /// distances equal within 1e-9 m count as equal), then the cluster whose smallest candidate
  /// index is lowest.
  std::optional<ClusterVote> Vote(std::span<const Vec3> candidates, double kappa_m);

  /// Candidate indices (ascending) of the winning cluster of the last Vote() that returned a
  /// value; empty after a Vote() that returned nullopt.
  const std::vector<int>& winner_members() const { return winner_; }

  /// Full complete-linkage clustering with cut `kappa_m` (> 0, finite): `labels` receives one
  /// label per candidate, -1 for non-finite candidates, otherwise 0, 1, ... numbered by the
  /// lowest candidate index of each cluster.
  void Cluster(std::span<const Vec3> candidates, double kappa_m, std::vector<int>* labels);

 private:
  // Splits the finite candidates into connected components of the "distance <= kappa" graph:
  // fills comp_members_ (original candidate indices, ascending within a component) and
  // comp_offsets_ (size = number of components + 1).
  void FindComponents(std::span<const Vec3> candidates, double kappa_m);
  // Clusters component `comp` and appends its clusters to cluster_members_/cluster_offsets_.
  void ClusterComponent(std::span<const Vec3> candidates, int comp, double kappa_m);

  std::vector<int> valid_;         // indices of finite candidates, ascending
  bool all_within_kappa_ = false;  // last FindComponents: every finite pair within kappa
  std::vector<int> order_;         // positions into valid_ sorted by x
  std::vector<int> label_;         // per position into valid_: its component's representative
  std::vector<int> member_next_;   // per position: next position of its component, -1 at the end
  std::vector<int> member_tail_;   // per representative: last position of its component
  std::vector<int> member_count_;  // per representative: positions in its component
  std::vector<int> comp_of_root_;
  std::vector<int> comp_members_;  // original indices, grouped by component
  std::vector<int> comp_offsets_;
  std::vector<int> comp_order_;  // components by decreasing size
  std::vector<int> size_start_;  // counting-sort buckets of comp_order_
  std::vector<float> dist_;      // full s x s distance matrix of one component
  std::vector<int> active_;      // local ids of clusters still able to merge, ascending
  std::vector<int> chain_;       // nearest-neighbour chain
  std::vector<int> next_;        // linked member lists (local ids)
  std::vector<int> tail_;
  std::vector<int> cluster_members_;  // original indices, grouped by cluster
  std::vector<int> cluster_offsets_;
  std::vector<int> winner_;
};

/// Complete-linkage clustering of `candidates` with cut `kappa_m` and the centroid of the largest
/// cluster (paper Eq. 7; tie-break as in ClusterVoter::Vote). Convenience wrapper that allocates a
/// fresh ClusterVoter; hot loops should keep a ClusterVoter instead. Stateless.
std::optional<ClusterVote> LargestClusterCentroid(std::span<const Vec3> candidates, double kappa_m);

/// Cluster labels of a complete-linkage clustering with cut `kappa_m` (see ClusterVoter::Cluster).
/// Stateless.
std::vector<int> CompleteLinkageLabels(std::span<const Vec3> candidates, double kappa_m);

}  // namespace mvtrack::triangulation
