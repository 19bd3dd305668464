// Tests of Algorithm 1 (PDNC) and of the appendix's alternatives (c)-(e) on hand-made and random
// distance matrices, against an independent brute-force reference.

#include "association/clustering.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "association/association_scene.h"

namespace mvtrack::association {
namespace {

using testing::AsPartition;
using testing::SameCluster;
using Clusters = std::vector<std::vector<int>>;

constexpr ClusteringMethod kAllMethods[] = {ClusteringMethod::kPdnc,
                                            ClusteringMethod::kCompleteLinkageEmptyAsZero,
                                            ClusteringMethod::kCompleteLinkageEmptyAsUpper,
                                            ClusteringMethod::kSingleLinkageEmptyAsUpper};

AssociationOptions Options(ClusteringMethod method, double lambda) {
  AssociationOptions o;
  o.method = method;
  o.lambda = lambda;
  o.empty_upper_bound = 1.0;
  return o;
}

// Brute-force reference, written from the closed forms of the cluster distances rather than
// from Algorithm 1's incremental update:
//  - PDNC: the max over the calculable (non-∅) member pairs, ∅ if there is none (iterating the
//    case table of Algorithm 1 step c yields exactly this);
//  - complete linkage: the max over all member pairs, ∅ substituted;
//  - single linkage: ∞ if any member pair is ∞, else the min over member pairs, ∅ substituted.
// Each step recomputes every cluster pair and merges the lowest value < lambda, ties to the
// lexicographically lowest (smallest member, smallest member). nullopt stands for ∅.
std::optional<double> ReferenceClusterDistance(const DistanceMatrix& m,
                                               const std::vector<int>& a,
                                               const std::vector<int>& b,
                                               const AssociationOptions& o) {
  const double inf = std::numeric_limits<double>::infinity();
  std::optional<double> result;
  bool any_infinite = false;
  double min_value = inf;
  for (int i : a) {
    for (int j : b) {
      const TrackletDistance d = m.at(i, j);
      std::optional<double> v;
      if (d.is_value()) v = d.value;
      if (d.is_infinite()) v = inf;
      if (d.is_empty()) {
        if (o.method == ClusteringMethod::kCompleteLinkageEmptyAsZero) v = 0.0;
        if (o.method == ClusteringMethod::kCompleteLinkageEmptyAsUpper ||
            o.method == ClusteringMethod::kSingleLinkageEmptyAsUpper) {
          v = o.empty_upper_bound;
        }
      }
      if (!v) continue;  // PDNC ignores ∅ pairs
      any_infinite = any_infinite || std::isinf(*v);
      min_value = std::min(min_value, *v);
      result = result ? std::max(*result, *v) : *v;
    }
  }
  if (o.method == ClusteringMethod::kSingleLinkageEmptyAsUpper) {
    return any_infinite ? inf : min_value;
  }
  return result;
}

Clusters ReferenceCluster(const DistanceMatrix& m, const AssociationOptions& o) {
  Clusters clusters;
  for (int i = 0; i < m.size(); ++i) clusters.push_back({i});
  while (true) {
    std::optional<double> best;
    std::size_t best_a = 0, best_b = 0;
    for (std::size_t a = 0; a < clusters.size(); ++a) {
      for (std::size_t b = a + 1; b < clusters.size(); ++b) {
        const std::optional<double> d = ReferenceClusterDistance(m, clusters[a], clusters[b], o);
        if (!d || !(*d < o.lambda)) continue;
        if (!best || *d < *best) {
          best = d;
          best_a = a;
          best_b = b;
        }
      }
    }
    if (!best) break;
    clusters[best_a].insert(
        clusters[best_a].end(), clusters[best_b].begin(), clusters[best_b].end());
    std::sort(clusters[best_a].begin(), clusters[best_a].end());
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(best_b));
  }
  return clusters;  // ordered by smallest member, as clusters keep their position
}

// The appendix example (paper lines 727-741, Fig. "compare clustering"): four cameras, two
// people, lambda = 0.5, tracklets that partly do not overlap in time.
//   person A: 0 = cam0 frames 0-9, 1 = cam1 frames 0-29, 2 = cam2 frames 10-19
//   person B: 3 = cam2 frames 0-9, 4 = cam0 frames 20-29, 5 = cam3 frames 0-29
// Pairs without a common frame are ∅: (0,2), (0,4) [same camera], (2,3) [same camera], (2,4),
// (3,4). Person B stands on A's epipolar plane of cameras 0 and 2 during frames 0-9, so the
// wrong pair (0,3) gets a small distance 0.25, between A's own distances (0.05, 0.15) and B's
// weakest link (3,5) = 0.35. Other cross-person pairs are large.
DistanceMatrix AppendixMatrix() {
  DistanceMatrix m(6);
  auto v = [&](int i, int j, double d) { m.set(i, j, TrackletDistance::Value(d)); };
  v(1, 2, 0.05);  // A
  v(4, 5, 0.10);  // B
  v(0, 1, 0.15);  // A
  v(0, 3, 0.25);  // A-B, ambiguous
  v(3, 5, 0.35);  // B
  v(0, 5, 0.90);
  v(1, 3, 0.80);
  v(1, 4, 0.85);
  v(1, 5, 0.95);
  v(2, 5, 0.70);
  return m;  // everything else stays ∅
}

TEST_CASE("appendix example: PDNC is right and strategies (c), (d), (e) fail as described",
          "[unit]") {
  const DistanceMatrix m = AppendixMatrix();
  const std::set<std::set<int>> truth = {{0, 1, 2}, {3, 4, 5}};

  // (a) PDNC: ∅ is propagated; 0 joins {1, 2} through d(0,1) although d(0,2) = ∅.
  std::vector<MergeStep> trace;
  const Clusters pdnc = ClusterTracklets(m, Options(ClusteringMethod::kPdnc, 0.5), &trace);
  CHECK(AsPartition(pdnc) == truth);
  CHECK(pdnc == Clusters{{0, 1, 2}, {3, 4, 5}});
  REQUIRE(trace.size() == 4);
  CHECK(trace[2].cluster_a == 0);
  CHECK(trace[2].cluster_b == 1);
  CHECK(trace[2].distance == 0.15);  // max(d(0,1), ∅) = d(0,1)

  // (c) ∅ := 0: in its first steps 0, 2, 3 and 4 end up together (two persons).
  const Clusters c =
      ClusterTracklets(m, Options(ClusteringMethod::kCompleteLinkageEmptyAsZero, 0.5), &trace);
  REQUIRE(trace.size() >= 3);
  CHECK(trace[0].distance == 0.0);
  CHECK(trace[1].distance == 0.0);
  CHECK(SameCluster(c, 0, 2));
  CHECK(SameCluster(c, 0, 3));
  CHECK(SameCluster(c, 0, 4));
  CHECK(AsPartition(c) != truth);
  CHECK(AsPartition(c) == std::set<std::set<int>>{{0, 2, 3, 4}, {1}, {5}});

  // (d) ∅ := 1.0, complete linkage: 0 cannot join {1, 2} (d(0,2) = 1.0), so it takes 3.
  const Clusters d =
      ClusterTracklets(m, Options(ClusteringMethod::kCompleteLinkageEmptyAsUpper, 0.5));
  CHECK(SameCluster(d, 0, 3));
  CHECK(AsPartition(d) == std::set<std::set<int>>{{0, 3}, {1, 2}, {4, 5}});

  // (e) ∅ := 1.0, single linkage: the chain 2-1-0-3-5-4 merges everything.
  const Clusters e =
      ClusterTracklets(m, Options(ClusteringMethod::kSingleLinkageEmptyAsUpper, 0.5));
  CHECK(e == Clusters{{0, 1, 2, 3, 4, 5}});

  // The independent reference agrees on all four.
  for (ClusteringMethod method : kAllMethods) {
    CHECK(ClusterTracklets(m, Options(method, 0.5)) == ReferenceCluster(m, Options(method, 0.5)));
  }
}

TEST_CASE("a pair at distance infinity never ends up in one cluster", "[unit]") {
  SECTION("all other distances tiny") {
    DistanceMatrix m(5);
    for (int i = 0; i < 5; ++i) {
      for (int j = i + 1; j < 5; ++j) m.set(i, j, TrackletDistance::Value(0.01 * (i + j)));
    }
    m.set(0, 1, TrackletDistance::Infinite());  // same camera, overlapping
    for (ClusteringMethod method : kAllMethods) {
      const Clusters c = ClusterTracklets(m, Options(method, 0.3));
      INFO(ClusteringMethodName(method));
      CHECK_FALSE(SameCluster(c, 0, 1));
      CHECK(c.size() == 2);
    }
  }
  SECTION("infinity reached through an empty distance") {
    // d(1,2) merges first; d({1,2}, 0) combines ∞ (from 1) and ∅ (from 2): it must stay ∞.
    DistanceMatrix m(3);
    m.set(0, 1, TrackletDistance::Infinite());
    m.set(1, 2, TrackletDistance::Value(0.01));
    for (ClusteringMethod method : kAllMethods) {
      INFO(ClusteringMethodName(method));
      AssociationOptions o = Options(method, 0.3);
      o.empty_upper_bound = 0.0;  // makes ∅ attractive for the alternatives too
      const Clusters c = ClusterTracklets(m, o);
      CHECK_FALSE(SameCluster(c, 0, 1));
      // PDNC merges 1+2; the alternatives merge 0+2 at ∅ := 0 first, and then must not absorb
      // 1 (single linkage would, through min(∞, 0.01), without the cannot-link).
      CHECK(SameCluster(c, 1, 2) == (method == ClusteringMethod::kPdnc));
      CHECK(c.size() == 2);
    }
  }
  SECTION("even with a huge lambda") {
    DistanceMatrix m(4);
    m.set(0, 2, TrackletDistance::Infinite());
    m.set(1, 3, TrackletDistance::Infinite());
    for (ClusteringMethod method : kAllMethods) {
      INFO(ClusteringMethodName(method));
      AssociationOptions o = Options(method, 1e12);
      const Clusters c = ClusterTracklets(m, o);
      CHECK_FALSE(SameCluster(c, 0, 2));
      CHECK_FALSE(SameCluster(c, 1, 3));
    }
  }
}

TEST_CASE("empty distances alone never merge under PDNC, values merge only below lambda",
          "[unit]") {
  DistanceMatrix all_empty(4);
  CHECK(ClusterTracklets(all_empty, Options(ClusteringMethod::kPdnc, 0.3)) ==
        Clusters{{0}, {1}, {2}, {3}});
  // Strategy (c) turns the same matrix into zeros and merges everything.
  CHECK(ClusterTracklets(all_empty, Options(ClusteringMethod::kCompleteLinkageEmptyAsZero, 0.3)) ==
        Clusters{{0, 1, 2, 3}});
  // Strategy (d) with an upper bound above lambda does not merge.
  CHECK(ClusterTracklets(all_empty, Options(ClusteringMethod::kCompleteLinkageEmptyAsUpper, 0.3))
            .size() == 4);

  DistanceMatrix m(3);
  m.set(0, 1, TrackletDistance::Value(0.3));  // exactly lambda: not < lambda
  m.set(1, 2, TrackletDistance::Value(0.299));
  m.set(0, 2, TrackletDistance::Value(0.9));  // no ∅ here: the alternatives see the same matrix
  for (ClusteringMethod method : kAllMethods) {
    INFO(ClusteringMethodName(method));
    CHECK(ClusterTracklets(m, Options(method, 0.3)) == Clusters{{0}, {1, 2}});
  }
}

TEST_CASE("PDNC update follows Algorithm 1's case table", "[unit]") {
  // Three tracklets that merge 1+2 first, then test d({1,2}, q) for each case.
  auto run = [](TrackletDistance d10, TrackletDistance d20, double lambda) {
    DistanceMatrix m(3);
    m.set(1, 2, TrackletDistance::Value(0.01));
    m.set(0, 1, d10);
    m.set(0, 2, d20);
    std::vector<MergeStep> trace;
    ClusterTracklets(m, Options(ClusteringMethod::kPdnc, lambda), &trace);
    return trace;
  };
  const auto V = TrackletDistance::Value;
  // Both calculable: max.
  auto t = run(V(0.1), V(0.2), 0.5);
  REQUIRE(t.size() == 2);
  CHECK(t[1].distance == 0.2);
  CHECK(run(V(0.1), V(0.6), 0.5).size() == 1);  // max 0.6 >= lambda: no second merge
  // One ∅: the calculable one (either side).
  t = run(TrackletDistance::Empty(), V(0.2), 0.5);
  REQUIRE(t.size() == 2);
  CHECK(t[1].distance == 0.2);
  t = run(V(0.3), TrackletDistance::Empty(), 0.5);
  REQUIRE(t.size() == 2);
  CHECK(t[1].distance == 0.3);
  // Both ∅: ∅, no merge.
  CHECK(run(TrackletDistance::Empty(), TrackletDistance::Empty(), 0.5).size() == 1);
  // ∞ with anything: ∞.
  CHECK(run(TrackletDistance::Infinite(), V(0.0), 0.5).size() == 1);
  CHECK(run(V(0.0), TrackletDistance::Infinite(), 0.5).size() == 1);
}

TEST_CASE("clustering matches the brute-force reference on random matrices (ties included)",
          "[unit]") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int merged_somewhere = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const int n = 2 + static_cast<int>(rng() % 13);
    const bool quantized = trial % 2 == 0;  // many exact ties
    DistanceMatrix m(n);
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        const double u = uniform(rng);
        if (u < 0.25) continue;  // ∅
        if (u < 0.35) {
          m.set(i, j, TrackletDistance::Infinite());
          continue;
        }
        double v = uniform(rng) * 0.8;
        if (quantized) v = std::round(v * 10.0) / 10.0;
        m.set(i, j, TrackletDistance::Value(v));
      }
    }
    for (ClusteringMethod method : kAllMethods) {
      AssociationOptions o = Options(method, 0.35);
      o.empty_upper_bound = trial % 3 == 0 ? 0.2 : 1.0;
      std::vector<MergeStep> trace;
      const Clusters got = ClusterTracklets(m, o, &trace);
      const Clusters expected = ReferenceCluster(m, o);
      INFO("trial " << trial << " n " << n << " method " << ClusteringMethodName(method));
      REQUIRE(got == expected);
      // Invariants: a partition of 0..n-1 in canonical order, no ∞ pair inside a cluster,
      // merges below lambda in non-decreasing order (the linkages are monotone).
      std::vector<int> all;
      for (std::size_t k = 0; k < got.size(); ++k) {
        CHECK(std::is_sorted(got[k].begin(), got[k].end()));
        if (k > 0) CHECK(got[k - 1].front() < got[k].front());
        for (int a : got[k]) {
          all.push_back(a);
          for (int b : got[k]) {
            if (a != b) CHECK_FALSE(m.at(a, b).is_infinite());
          }
        }
      }
      std::sort(all.begin(), all.end());
      std::vector<int> iota(static_cast<std::size_t>(n));
      for (int k = 0; k < n; ++k) iota[static_cast<std::size_t>(k)] = k;
      CHECK(all == iota);
      CHECK(static_cast<int>(trace.size()) == n - static_cast<int>(got.size()));
      for (std::size_t k = 0; k < trace.size(); ++k) {
        CHECK(trace[k].distance < o.lambda);
        CHECK(trace[k].cluster_a < trace[k].cluster_b);
        if (k > 0) CHECK(trace[k - 1].distance <= trace[k].distance);
      }
      if (!trace.empty()) ++merged_somewhere;
    }
  }
  CHECK(merged_somewhere > 200);  // the comparison exercised real merges
}

TEST_CASE("degenerate inputs and the rvalue overload", "[unit]") {
  for (ClusteringMethod method : kAllMethods) {
    CHECK(ClusterTracklets(DistanceMatrix(0), Options(method, 0.3)).empty());
    CHECK(ClusterTracklets(DistanceMatrix(), Options(method, 0.3)).empty());
    CHECK(ClusterTracklets(DistanceMatrix(1), Options(method, 0.3)) == Clusters{{0}});
    DistanceMatrix m = AppendixMatrix();
    const Clusters by_ref = ClusterTracklets(m, Options(method, 0.5));
    CHECK(ClusterTracklets(std::move(m), Options(method, 0.5)) == by_ref);
  }
}

}  // namespace
}  // namespace mvtrack::association
