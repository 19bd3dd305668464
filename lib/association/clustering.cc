#include "association/clustering.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>

#include "core/check.h"

namespace mvtrack::association {
namespace {

constexpr double kInfinite = std::numeric_limits<double>::infinity();

/// Cluster-distance update of Algorithm 1 (step c) or of the selected alternative, on the
/// encoded distances (NaN = ∅, +inf = ∞, else a value). For the alternatives ∅ has already been
/// substituted, so their inputs are never NaN.
double MergedDistance(ClusteringMethod method, double d_iq, double d_jq) {
  switch (method) {
    case ClusteringMethod::kPdnc:
      if (std::isnan(d_iq)) return d_jq;  // ∅ and x -> x (x may be ∅ too)
      if (std::isnan(d_jq)) return d_iq;
      return std::max(d_iq, d_jq);  // both calculable; max with ∞ is ∞
    case ClusteringMethod::kCompleteLinkageEmptyAsZero:
    case ClusteringMethod::kCompleteLinkageEmptyAsUpper:
      return std::max(d_iq, d_jq);
    case ClusteringMethod::kSingleLinkageEmptyAsUpper:
      if (std::isinf(d_iq) || std::isinf(d_jq)) return kInfinite;  // ∞ stays a cannot-link
      return std::min(d_iq, d_jq);
  }
  return kInfinite;
}

/// In-place agglomerative clustering on the packed strict upper triangle `d` of an n x n
/// matrix. Slot i always holds the cluster whose smallest member is i: merging slots i < j
/// keeps slot i and retires slot j.
class Clusterer {
 public:
  Clusterer(int n, std::vector<double>* d, const AssociationOptions& options)
      : n_(static_cast<std::size_t>(n)),
        d_(*d),
        method_(options.method),
        lambda_(options.lambda),
        active_(n_, 1),
        best_j_(n_, kNone),
        best_value_(n_, kInfinite),
        next_member_(n_, kNone),
        last_member_(n_) {
    for (std::size_t i = 0; i < n_; ++i) last_member_[i] = i;
    row_start_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) row_start_[i] = i * n_ - i * (i + 1) / 2;
    SubstituteEmpty(options);
    for (std::size_t i = 0; i < n_; ++i) RecomputeRow(i);
  }

  void Run(std::vector<MergeStep>* trace) {
    while (true) {
      // Closest pair: lowest value, ties to the lowest i (rows hold the lowest j on ties).
      std::size_t i = kNone;
      for (std::size_t r = 0; r < n_; ++r) {
        if (!active_[r] || best_j_[r] == kNone) continue;
        if (i == kNone || best_value_[r] < best_value_[i]) i = r;
      }
      if (i == kNone) return;  // no pair with a value < lambda remains
      const std::size_t j = best_j_[i];
      if (trace != nullptr) {
        trace->push_back({static_cast<int>(i), static_cast<int>(j), best_value_[i]});
      }
      Merge(i, j);
    }
  }

  std::vector<std::vector<int>> Clusters() const {
    std::vector<std::vector<int>> clusters;
    for (std::size_t i = 0; i < n_; ++i) {
      if (!active_[i]) continue;
      std::vector<int> members;
      for (std::size_t m = i; m != kNone; m = next_member_[m]) {
        members.push_back(static_cast<int>(m));
      }
      std::sort(members.begin(), members.end());
      clusters.push_back(std::move(members));
    }
    return clusters;
  }

 private:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

  // Entry (r, c) with r < c.
  double& At(std::size_t r, std::size_t c) { return d_[row_start_[r] + (c - r - 1)]; }
  double& Sym(std::size_t a, std::size_t b) { return a < b ? At(a, b) : At(b, a); }

  void SubstituteEmpty(const AssociationOptions& options) {
    double empty_value = 0.0;
    switch (method_) {
      case ClusteringMethod::kPdnc:
        return;  // ∅ stays a distinct kind
      case ClusteringMethod::kCompleteLinkageEmptyAsZero:
        empty_value = 0.0;
        break;
      case ClusteringMethod::kCompleteLinkageEmptyAsUpper:
      case ClusteringMethod::kSingleLinkageEmptyAsUpper:
        empty_value = options.empty_upper_bound;
        break;
    }
    for (double& v : d_) {
      if (std::isnan(v)) v = empty_value;
    }
  }

  /// Nearest active neighbour c > r of row r among entries < lambda (lowest c on ties).
  void RecomputeRow(std::size_t r) {
    std::size_t best = kNone;
    double best_value = kInfinite;
    const double* row = d_.data() + row_start_[r];
    for (std::size_t c = r + 1; c < n_; ++c) {
      const double v = row[c - r - 1];
      // NaN (∅) and ∞ compare false: they never become a merge candidate.
      if (active_[c] && v < lambda_ && (best == kNone || v < best_value)) {
        best = c;
        best_value = v;
      }
    }
    best_j_[r] = best;
    best_value_[r] = best_value;
  }

  void Merge(std::size_t i, std::size_t j) {
    // Step b: ω_p = ω_i ∪ ω_j (kept in slot i; i < j so i stays the smallest member).
    next_member_[last_member_[i]] = j;
    last_member_[i] = last_member_[j];
    active_[j] = 0;
    // Step c: distances from ω_p to every other cluster.
    for (std::size_t q = 0; q < n_; ++q) {
      if (!active_[q] || q == i) continue;
      double& d_iq = Sym(i, q);
      d_iq = MergedDistance(method_, d_iq, Sym(j, q));
    }
    // Step d and the nearest-neighbour caches.
    RecomputeRow(i);
    for (std::size_t q = 0; q < j; ++q) {
      if (!active_[q] || q == i) continue;
      if (best_j_[q] == i || best_j_[q] == j) {
        RecomputeRow(q);  // its nearest neighbour changed or disappeared
      } else if (q < i) {
        // Only (q, i) changed in this row; it may now be the nearest (it can decrease under
        // PDNC when it was ∅, and under single linkage).
        const double v = At(q, i);
        if (v < lambda_ && (best_j_[q] == kNone || v < best_value_[q] ||
                            (v == best_value_[q] && i < best_j_[q]))) {
          best_j_[q] = i;
          best_value_[q] = v;
        }
      }
    }
  }

  std::size_t n_;
  std::vector<double>& d_;
  ClusteringMethod method_;
  double lambda_;
  std::vector<std::size_t> row_start_;  ///< packed offset of entry (r, r + 1)
  std::vector<unsigned char> active_;
  std::vector<std::size_t> best_j_;
  std::vector<double> best_value_;
  std::vector<std::size_t> next_member_;
  std::vector<std::size_t> last_member_;
};

std::vector<std::vector<int>> ClusterInPlace(int n,
                                             std::vector<double>* packed,
                                             const AssociationOptions& options,
                                             std::vector<MergeStep>* trace) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  if (trace != nullptr) trace->clear();
  Clusterer clusterer(n, packed, options);
  clusterer.Run(trace);
  return clusterer.Clusters();
}

}  // namespace

std::vector<std::vector<int>> ClusterTracklets(const DistanceMatrix& distances,
                                               const AssociationOptions& options,
                                               std::vector<MergeStep>* trace) {
  std::vector<double> working = internal::DistanceMatrixAccess::Packed(distances);
  return ClusterInPlace(distances.size(), &working, options, trace);
}

std::vector<std::vector<int>> ClusterTracklets(DistanceMatrix&& distances,
                                               const AssociationOptions& options,
                                               std::vector<MergeStep>* trace) {
  const int n = distances.size();
  std::vector<double> working = std::move(internal::DistanceMatrixAccess::Packed(distances));
  distances = DistanceMatrix();
  return ClusterInPlace(n, &working, options, trace);
}

}  // namespace mvtrack::association
