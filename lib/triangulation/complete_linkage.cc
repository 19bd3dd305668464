#include "triangulation/complete_linkage.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>

#include "core/check.h"

namespace mvtrack::triangulation {
namespace {

constexpr float kNotMergeable = std::numeric_limits<float>::infinity();
/// Mean member-to-centroid distances closer than this count as a tie (metres).
constexpr double kTieTolerance_m = 1e-9;

/// Squared-distance bound beyond which a pair is certainly further apart than kappa: sqrt is
/// correctly rounded and monotone, so squaredNorm > kappa^2 * (1 + 1e-9) implies
/// norm() = sqrt(squaredNorm) > kappa. Pairs under the bound take the exact test (norm() <= kappa),
/// so the prefilter only skips square roots and never changes a decision.
double FarSquared(double kappa_m) { return kappa_m * kappa_m * (1.0 + 1e-9); }

/// Distance of a and b (exactly Eigen's norm()), or +inf when it exceeds kappa: the one
/// "may be in the same cluster" predicate used everywhere (components, distances).
double DistanceWithin(const Vec3& a, const Vec3& b, double kappa_m, double far_sq) {
  const double sq = (a - b).squaredNorm();
  if (sq > far_sq) return std::numeric_limits<double>::infinity();
  const double d = std::sqrt(sq);
  return d <= kappa_m ? d : std::numeric_limits<double>::infinity();
}

/// Diagonal of the axis-aligned bounding box of candidates[idx[0..n)]; an upper bound of the
/// largest pairwise distance.
double BoxDiagonal(std::span<const Vec3> candidates, const int* idx, std::size_t n) {
  Vec3 lo = candidates[static_cast<std::size_t>(idx[0])];
  Vec3 hi = lo;
  for (std::size_t i = 1; i < n; ++i) {
    const Vec3& p = candidates[static_cast<std::size_t>(idx[i])];
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

/// Statistics of one cluster used by the vote's ordering.
struct ClusterScore {
  int size = 0;
  double mean_distance_m = 0.0;
  int min_index = 0;
  Vec3 centroid = Vec3::Zero();
};

/// Unweighted mean of candidates[members[0..n)], summed in member order.
Vec3 Centroid(std::span<const Vec3> candidates, const int* members, std::size_t n) {
  Vec3 centroid = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) centroid += candidates[static_cast<std::size_t>(members[i])];
  centroid /= static_cast<double>(n);
  return centroid;
}

ClusterScore Score(std::span<const Vec3> candidates, const int* members, std::size_t n) {
  ClusterScore s;
  s.size = static_cast<int>(n);
  s.min_index = members[0];
  for (std::size_t i = 0; i < n; ++i) s.min_index = std::min(s.min_index, members[i]);
  s.centroid = Centroid(candidates, members, n);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += (candidates[static_cast<std::size_t>(members[i])] - s.centroid).norm();
  }
  s.mean_distance_m = sum / static_cast<double>(n);
  return s;
}

/// Whether cluster `a` beats cluster `b`: larger, then tighter, then lower smallest index.
bool Better(const ClusterScore& a, const ClusterScore& b) {
  if (a.size != b.size) return a.size > b.size;
  if (std::abs(a.mean_distance_m - b.mean_distance_m) > kTieTolerance_m) {
    return a.mean_distance_m < b.mean_distance_m;
  }
  return a.min_index < b.min_index;
}

}  // namespace

void ClusterVoter::FindComponents(std::span<const Vec3> candidates, double kappa_m) {
  valid_.clear();
  all_within_kappa_ = false;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].allFinite()) valid_.push_back(static_cast<int>(i));
  }
  comp_members_.clear();
  comp_offsets_.assign(1, 0);
  const std::size_t n = valid_.size();
  if (n == 0) return;

  // Shortcut: every pair is within kappa, so complete linkage merges everything.
  if (BoxDiagonal(candidates, valid_.data(), n) <= kappa_m) {
    all_within_kappa_ = true;
    comp_members_ = valid_;
    comp_offsets_.push_back(static_cast<int>(n));
    return;
  }

  // Connected components of the "distance <= kappa" graph by a sweep along x. Each component
  // is a linked list of positions headed by its representative, and every position carries its
  // representative's id (relabelling the smaller list on a union), so "already connected" is
  // one comparison.
  label_.resize(n);
  std::iota(label_.begin(), label_.end(), 0);
  member_next_.assign(n, -1);
  member_tail_.resize(n);
  std::iota(member_tail_.begin(), member_tail_.end(), 0);
  member_count_.assign(n, 1);
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  const double far_sq = FarSquared(kappa_m);
  auto x_of = [&](int pos) {
    return candidates[static_cast<std::size_t>(valid_[static_cast<std::size_t>(pos)])].x();
  };
  std::sort(order_.begin(), order_.end(), [&](int a, int b) {
    const double xa = x_of(a), xb = x_of(b);
    return xa != xb ? xa < xb : a < b;
  });
  for (std::size_t ii = 0; ii < n; ++ii) {
    const int i = order_[ii];
    const Vec3& pi = candidates[static_cast<std::size_t>(valid_[static_cast<std::size_t>(i)])];
    for (std::size_t jj = ii + 1; jj < n; ++jj) {
      const int j = order_[jj];
      const Vec3& pj = candidates[static_cast<std::size_t>(valid_[static_cast<std::size_t>(j)])];
      if (pj.x() - pi.x() > kappa_m) break;
      const int li = label_[static_cast<std::size_t>(i)];
      const int lj = label_[static_cast<std::size_t>(j)];
      // Already connected: the edge could not change the components, skip its distance.
      if (li == lj) continue;
      if (DistanceWithin(pi, pj, kappa_m, far_sq) > kappa_m) continue;
      const bool li_larger = member_count_[static_cast<std::size_t>(li)] >=
                             member_count_[static_cast<std::size_t>(lj)];
      const int big = li_larger ? li : lj;
      const int small = li_larger ? lj : li;
      for (int u = small; u >= 0; u = member_next_[static_cast<std::size_t>(u)]) {
        label_[static_cast<std::size_t>(u)] = big;
      }
      member_next_[static_cast<std::size_t>(member_tail_[static_cast<std::size_t>(big)])] = small;
      member_tail_[static_cast<std::size_t>(big)] = member_tail_[static_cast<std::size_t>(small)];
      member_count_[static_cast<std::size_t>(big)] +=
          member_count_[static_cast<std::size_t>(small)];
    }
  }

  // Group by component: components numbered by their smallest candidate index, members ascending.
  comp_of_root_.assign(n, -1);
  int num_comps = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(label_[i]);
    if (comp_of_root_[r] < 0) comp_of_root_[r] = num_comps++;
  }
  comp_offsets_.assign(static_cast<std::size_t>(num_comps) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(label_[i]);
    ++comp_offsets_[static_cast<std::size_t>(comp_of_root_[r]) + 1];
  }
  for (std::size_t c = 0; c < static_cast<std::size_t>(num_comps); ++c) {
    comp_offsets_[c + 1] += comp_offsets_[c];
  }
  comp_members_.resize(n);
  // order_ is reused as the fill cursor of each component.
  order_.assign(comp_offsets_.begin(), comp_offsets_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(label_[i]);
    const auto c = static_cast<std::size_t>(comp_of_root_[r]);
    comp_members_[static_cast<std::size_t>(order_[c]++)] = valid_[i];
  }
}

void ClusterVoter::ClusterComponent(std::span<const Vec3> candidates, int comp, double kappa_m) {
  const auto uc = static_cast<std::size_t>(comp);
  const int* members = comp_members_.data() + comp_offsets_[uc];
  const auto s = static_cast<std::size_t>(comp_offsets_[uc + 1] - comp_offsets_[uc]);
  auto emit_all = [&]() {
    cluster_members_.insert(cluster_members_.end(), members, members + s);
    cluster_offsets_.push_back(static_cast<int>(cluster_members_.size()));
  };
  if (s == 1 || BoxDiagonal(candidates, members, s) <= kappa_m) {
    emit_all();
    return;
  }

  // Full symmetric s x s distance matrix (row-major, diagonal +inf) so the nearest-neighbour
  // scans read one contiguous row; pairs further apart than kappa can never share a cluster.
  dist_.resize(s * s);
  const double far_sq = FarSquared(kappa_m);
  for (std::size_t i = 0; i < s; ++i) {
    const Vec3& pi = candidates[static_cast<std::size_t>(members[i])];
    float* row_i = dist_.data() + i * s;
    row_i[i] = kNotMergeable;  // never a nearest neighbour of itself
    for (std::size_t j = i + 1; j < s; ++j) {
      const double d =
          DistanceWithin(pi, candidates[static_cast<std::size_t>(members[j])], kappa_m, far_sq);
      const float f = d <= kappa_m ? static_cast<float>(d) : kNotMergeable;
      row_i[j] = f;
      dist_[j * s + i] = f;
    }
  }
  active_.resize(s);
  std::iota(active_.begin(), active_.end(), 0);
  next_.assign(s, -1);
  tail_.resize(s);
  std::iota(tail_.begin(), tail_.end(), 0);
  chain_.clear();

  auto row = [&](int i) { return dist_.data() + static_cast<std::size_t>(i) * s; };
  auto remove_active = [&](int id) {
    active_.erase(std::lower_bound(active_.begin(), active_.end(), id));
  };

  // Nearest-neighbour chain: follow nearest neighbours until two clusters are reciprocal nearest
  // neighbours, merge them (complete linkage: d(a u b, j) = max(d(a, j), d(b, j))). A cluster
  // whose nearest neighbour is not mergeable stays final: complete-linkage distances only grow.
  while (!active_.empty()) {
    if (chain_.empty()) chain_.push_back(active_.front());
    const int a = chain_.back();
    const int prev = chain_.size() >= 2 ? chain_[chain_.size() - 2] : -1;
    const float* row_a = row(a);
    int b = prev;
    float best = prev >= 0 ? row_a[prev] : kNotMergeable;
    // Neither a (its diagonal is +inf) nor prev (equal to best, not below it) can win, so the
    // scan needs no tests for them.
    for (const int j : active_) {
      const float dj = row_a[j];
      if (dj < best) {
        best = dj;
        b = j;
      }
    }
    if (b < 0 || best == kNotMergeable) {
      // Final cluster: emit its members.
      for (int u = a; u >= 0; u = next_[static_cast<std::size_t>(u)]) {
        cluster_members_.push_back(members[static_cast<std::size_t>(u)]);
      }
      cluster_offsets_.push_back(static_cast<int>(cluster_members_.size()));
      remove_active(a);
      chain_.pop_back();
      continue;
    }
    if (b != prev) {
      chain_.push_back(b);
      continue;
    }
    // a and b are reciprocal nearest neighbours: merge into the lower id.
    chain_.pop_back();
    chain_.pop_back();
    const int keep = std::min(a, b), drop = std::max(a, b);
    float* row_keep = row(keep);
    const float* row_b = row(b);
    // For j = a or b one operand is a diagonal (+inf): keep's diagonal stays +inf and drop's
    // entries are never read again, so they need no test either.
    for (const int j : active_) {
      const float merged = std::max(row_a[j], row_b[j]);
      row_keep[j] = merged;
      row(j)[keep] = merged;
    }
    next_[static_cast<std::size_t>(tail_[static_cast<std::size_t>(keep)])] = drop;
    tail_[static_cast<std::size_t>(keep)] = tail_[static_cast<std::size_t>(drop)];
    remove_active(drop);
  }
}

std::optional<ClusterVote> ClusterVoter::Vote(std::span<const Vec3> candidates, double kappa_m) {
  MVTRACK_CHECK_MSG(std::isfinite(kappa_m) && kappa_m > 0.0, "kappa_m must be finite and > 0");
  winner_.clear();
  FindComponents(candidates, kappa_m);
  const std::size_t num_comps = comp_offsets_.size() - 1;
  if (num_comps == 0) return std::nullopt;
  if (all_within_kappa_) {
    // One component whose bounding box is within kappa: ClusterComponent would emit it as the
    // only cluster (the same bounding-box test), so it wins without scoring or tie-breaks.
    winner_ = valid_;
    ClusterVote vote;
    vote.point = Centroid(candidates, valid_.data(), valid_.size());
    vote.cluster_size = static_cast<int>(valid_.size());
    vote.num_candidates = static_cast<int>(valid_.size());
    return vote;
  }

  auto comp_size = [&](int c) {
    const auto uc = static_cast<std::size_t>(c);
    return comp_offsets_[uc + 1] - comp_offsets_[uc];
  };
  // Components by decreasing size, then ascending number: a counting sort on the size (sizes
  // are at most the number of finite candidates), linear instead of a comparison sort.
  const std::size_t max_size = valid_.size();
  size_start_.assign(max_size + 2, 0);
  for (std::size_t c = 0; c < num_comps; ++c) {
    // Bucket of size z is max_size - z, so larger components come first.
    ++size_start_[max_size - static_cast<std::size_t>(comp_size(static_cast<int>(c))) + 1];
  }
  for (std::size_t z = 1; z < size_start_.size(); ++z) size_start_[z] += size_start_[z - 1];
  comp_order_.resize(num_comps);
  for (std::size_t c = 0; c < num_comps; ++c) {
    const std::size_t bucket = max_size - static_cast<std::size_t>(comp_size(static_cast<int>(c)));
    comp_order_[static_cast<std::size_t>(size_start_[bucket]++)] = static_cast<int>(c);
  }

  std::optional<ClusterScore> best;
  for (const int c : comp_order_) {
    // A component can only hold clusters no larger than itself.
    if (best && comp_size(c) < best->size) break;
    cluster_members_.clear();
    cluster_offsets_.assign(1, 0);
    ClusterComponent(candidates, c, kappa_m);
    for (std::size_t k = 0; k + 1 < cluster_offsets_.size(); ++k) {
      const int* m = cluster_members_.data() + cluster_offsets_[k];
      const auto n = static_cast<std::size_t>(cluster_offsets_[k + 1] - cluster_offsets_[k]);
      if (best && static_cast<int>(n) < best->size) continue;
      const ClusterScore score = Score(candidates, m, n);
      if (!best || Better(score, *best)) {
        best = score;
        winner_.assign(m, m + n);
      }
    }
  }
  std::sort(winner_.begin(), winner_.end());
  ClusterVote vote;
  vote.point = best->centroid;
  vote.cluster_size = best->size;
  vote.num_candidates = static_cast<int>(valid_.size());
  return vote;
}

void ClusterVoter::Cluster(std::span<const Vec3> candidates,
                           double kappa_m,
                           std::vector<int>* labels) {
  MVTRACK_CHECK_MSG(std::isfinite(kappa_m) && kappa_m > 0.0, "kappa_m must be finite and > 0");
  MVTRACK_CHECK(labels != nullptr);
  labels->assign(candidates.size(), -1);
  FindComponents(candidates, kappa_m);
  cluster_members_.clear();
  cluster_offsets_.assign(1, 0);
  const auto num_comps = static_cast<int>(comp_offsets_.size()) - 1;
  for (int c = 0; c < num_comps; ++c) ClusterComponent(candidates, c, kappa_m);

  // Number clusters by their smallest member index.
  const std::size_t num_clusters = cluster_offsets_.size() - 1;
  std::vector<std::pair<int, int>> by_min_index(num_clusters);
  for (std::size_t k = 0; k < num_clusters; ++k) {
    const auto first = cluster_members_.begin() + cluster_offsets_[k];
    const auto last = cluster_members_.begin() + cluster_offsets_[k + 1];
    by_min_index[k] = {*std::min_element(first, last), static_cast<int>(k)};
  }
  std::sort(by_min_index.begin(), by_min_index.end());
  for (std::size_t label = 0; label < num_clusters; ++label) {
    const auto k = static_cast<std::size_t>(by_min_index[label].second);
    for (int i = cluster_offsets_[k]; i < cluster_offsets_[k + 1]; ++i) {
      (*labels)[static_cast<std::size_t>(cluster_members_[static_cast<std::size_t>(i)])] =
          static_cast<int>(label);
    }
  }
}

std::optional<ClusterVote> LargestClusterCentroid(std::span<const Vec3> candidates,
                                                  double kappa_m) {
  ClusterVoter voter;
  return voter.Vote(candidates, kappa_m);
}

std::vector<int> CompleteLinkageLabels(std::span<const Vec3> candidates, double kappa_m) {
  ClusterVoter voter;
  std::vector<int> labels;
  voter.Cluster(candidates, kappa_m, &labels);
  return labels;
}

}  // namespace mvtrack::triangulation
