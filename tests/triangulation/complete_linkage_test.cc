#include "triangulation/complete_linkage.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "support/eigen_matchers.h"

namespace mvtrack::triangulation {
namespace {

using testing::IsApproxVec;

/// Uniform point in the axis-aligned box [lo, hi].
Vec3 UniformIn(std::mt19937* rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return lo + (hi - lo).cwiseProduct(Vec3(u(*rng), u(*rng), u(*rng)));
}

/// Uniform point in the ball of radius r around c (rejection sampling).
Vec3 UniformInBall(std::mt19937* rng, const Vec3& c, double r) {
  for (;;) {
    const Vec3 d = UniformIn(rng, Vec3::Constant(-r), Vec3::Constant(r));
    if (d.norm() <= r) return c + d;
  }
}

/// Reference: textbook greedy agglomerative complete linkage, O(m^3): repeatedly merge the two
/// clusters with the smallest maximum pairwise distance while it is <= kappa. Labels numbered by
/// the smallest member index, -1 for non-finite points.
std::vector<int> NaiveCompleteLinkage(const std::vector<Vec3>& p, double kappa) {
  std::vector<std::vector<int>> clusters;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i].allFinite()) clusters.push_back({static_cast<int>(i)});
  }
  auto at = [&](int i) { return p[static_cast<std::size_t>(i)]; };
  auto link = [&](const std::vector<int>& a, const std::vector<int>& b) {
    double d = 0.0;
    for (int i : a) {
      for (int j : b) d = std::max(d, (at(i) - at(j)).norm());
    }
    return d;
  };
  for (;;) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t bi = 0, bj = 0;
    for (std::size_t i = 0; i < clusters.size(); ++i) {
      for (std::size_t j = i + 1; j < clusters.size(); ++j) {
        const double d = link(clusters[i], clusters[j]);
        if (d < best) {
          best = d;
          bi = i;
          bj = j;
        }
      }
    }
    if (!(best <= kappa)) break;
    clusters[bi].insert(clusters[bi].end(), clusters[bj].begin(), clusters[bj].end());
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(bj));
  }
  std::vector<std::pair<int, std::size_t>> by_min;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    by_min.emplace_back(*std::min_element(clusters[c].begin(), clusters[c].end()), c);
  }
  std::sort(by_min.begin(), by_min.end());
  std::vector<int> labels(p.size(), -1);
  for (std::size_t l = 0; l < by_min.size(); ++l) {
    for (int i : clusters[by_min[l].second]) {
      labels[static_cast<std::size_t>(i)] = static_cast<int>(l);
    }
  }
  return labels;
}

/// Largest pairwise distance inside each label; and the smallest complete-linkage distance
/// between two different labels.
void CheckCompleteLinkageInvariants(const std::vector<Vec3>& p,
                                    const std::vector<int>& labels,
                                    double kappa) {
  const int num_labels = *std::max_element(labels.begin(), labels.end()) + 1;
  // link[a][b] = max distance between members of labels a and b.
  const auto n = static_cast<std::size_t>(num_labels);
  std::vector<std::vector<double>> link(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (labels[i] < 0 || labels[j] < 0) continue;
      double& l = link[static_cast<std::size_t>(labels[i])][static_cast<std::size_t>(labels[j])];
      l = std::max(l, (p[i] - p[j]).norm());
    }
  }
  for (int a = 0; a < num_labels; ++a) {
    // Every cluster has a diameter <= kappa ...
    REQUIRE(link[static_cast<std::size_t>(a)][static_cast<std::size_t>(a)] <= kappa);
    // ... and no two clusters could still be merged.
    for (int b = a + 1; b < num_labels; ++b) {
      REQUIRE(link[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] > kappa);
    }
  }
}

TEST_CASE("LargestClusterCentroid recovers the truth with fewer than 50% inliers", "[unit]") {
  constexpr double kKappa = 0.2;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const Vec3 truth = UniformIn(&rng, Vec3(-2.0, -2.0, 0.2), Vec3(2.0, 2.0, 1.8));
    std::vector<Vec3> candidates;
    Vec3 inlier_sum = Vec3::Zero();
    for (int i = 0; i < 8; ++i) {
      candidates.push_back(UniformInBall(&rng, truth, 0.03));
      inlier_sum += candidates.back();
    }
    // 12 outliers spread over the room, never clustered: pairwise and to the truth > 0.5 m.
    while (candidates.size() < 20) {
      const Vec3 o = UniformIn(&rng, Vec3(-3.0, -3.0, 0.0), Vec3(3.0, 3.0, 2.5));
      if ((o - truth).norm() <= 0.5) continue;
      bool isolated = true;
      for (std::size_t j = 8; j < candidates.size(); ++j) {
        isolated = isolated && (o - candidates[j]).norm() > 0.5;
      }
      if (isolated) candidates.push_back(o);
    }
    std::shuffle(candidates.begin(), candidates.end(), rng);

    const auto vote = LargestClusterCentroid(candidates, kKappa);
    REQUIRE(vote.has_value());
    CHECK(vote->cluster_size == 8);
    CHECK(vote->num_candidates == 20);
    CHECK((vote->point - truth).norm() < 0.03);
    // Eq. 7: exactly the mean of the inliers.
    CHECK_THAT(vote->point, IsApproxVec(inlier_sum / 8.0, 1e-12));
    // Plain averaging of all candidates is pulled far off by the 60% outliers.
    Vec3 mean = Vec3::Zero();
    for (const Vec3& c : candidates) mean += c;
    mean /= static_cast<double>(candidates.size());
    CHECK((mean - truth).norm() > 0.1);
  }
}

TEST_CASE("LargestClusterCentroid handles empty, non-finite and single inputs", "[unit]") {
  CHECK_FALSE(LargestClusterCentroid({}, 0.2).has_value());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Vec3> only_nan = {Vec3(nan, 0.0, 0.0), Vec3(0.0, inf, 1.0)};
  CHECK_FALSE(LargestClusterCentroid(only_nan, 0.2).has_value());

  const std::vector<Vec3> one = {Vec3(1.0, 2.0, 3.0)};
  const auto vote = LargestClusterCentroid(one, 0.2);
  REQUIRE(vote.has_value());
  CHECK(vote->cluster_size == 1);
  CHECK(vote->num_candidates == 1);
  CHECK_THAT(vote->point, IsApproxVec(Vec3(1.0, 2.0, 3.0), 0.0));

  // Non-finite candidates are ignored, not counted.
  const std::vector<Vec3> mixed = {Vec3(nan, 0.0, 0.0), Vec3(0.0, 0.0, 1.0), Vec3(0.1, 0.0, 1.0)};
  const auto mixed_vote = LargestClusterCentroid(mixed, 0.2);
  REQUIRE(mixed_vote.has_value());
  CHECK(mixed_vote->num_candidates == 2);
  CHECK(mixed_vote->cluster_size == 2);
  CHECK_THAT(mixed_vote->point, IsApproxVec(Vec3(0.05, 0.0, 1.0), 1e-15));
  CHECK(CompleteLinkageLabels(mixed, 0.2) == std::vector<int>{-1, 0, 0});
}

TEST_CASE("LargestClusterCentroid breaks ties deterministically", "[unit]") {
  const Vec3 a(0.0, 0.0, 1.0), b(3.0, 1.0, 1.0);
  auto blob = [](const Vec3& c, double r) {
    return std::vector<Vec3>{c + Vec3(r, 0.0, 0.0), c - Vec3(r, 0.0, 0.0), c + Vec3(0.0, r, 0.0)};
  };

  SECTION("equal size: the tighter cluster wins whatever the order") {
    std::vector<Vec3> loose = blob(b, 0.05), tight = blob(a, 0.01);
    std::vector<Vec3> loose_first = loose;
    loose_first.insert(loose_first.end(), tight.begin(), tight.end());
    std::vector<Vec3> tight_first = tight;
    tight_first.insert(tight_first.end(), loose.begin(), loose.end());
    for (const auto& candidates : {loose_first, tight_first}) {
      const auto vote = LargestClusterCentroid(candidates, 0.2);
      REQUIRE(vote.has_value());
      CHECK(vote->cluster_size == 3);
      CHECK((vote->point - a).norm() < 0.01);
    }
  }

  SECTION("equal size and spread: the cluster holding the lowest index wins") {
    const std::vector<Vec3> ca = blob(a, 0.04), cb = blob(b, 0.04);
    // Interleave so the first candidate decides: b first, then a first.
    const std::vector<Vec3> b_first = {cb[0], ca[0], cb[1], ca[1], cb[2], ca[2]};
    const std::vector<Vec3> a_first = {ca[0], cb[0], ca[1], cb[1], ca[2], cb[2]};
    const auto vb = LargestClusterCentroid(b_first, 0.2);
    const auto va = LargestClusterCentroid(a_first, 0.2);
    REQUIRE(vb.has_value());
    REQUIRE(va.has_value());
    CHECK((vb->point - b).norm() < 0.04);
    CHECK((va->point - a).norm() < 0.04);
  }

  SECTION("a larger cluster beats a tighter one") {
    std::vector<Vec3> candidates = blob(a, 0.001);
    const std::vector<Vec3> four = {
        b, b + Vec3(0.08, 0.0, 0.0), b + Vec3(0.0, 0.08, 0.0), b + Vec3(0.0, 0.0, 0.08)};
    candidates.insert(candidates.end(), four.begin(), four.end());
    const auto vote = LargestClusterCentroid(candidates, 0.2);
    REQUIRE(vote.has_value());
    CHECK(vote->cluster_size == 4);
    CHECK(vote->num_candidates == 7);
  }
}

TEST_CASE("Complete linkage respects the cut kappa on a chain (single linkage would not)",
          "[unit]") {
  // Ten points 8 cm apart on a line: every neighbour is within kappa = 0.2 m, so single linkage
  // would chain them into one 0.72 m cluster; complete linkage must keep diameters <= 0.2 m.
  std::vector<Vec3> chain;
  for (int i = 0; i < 10; ++i) chain.emplace_back(0.08 * i, 0.5, 1.0);
  const std::vector<int> labels = CompleteLinkageLabels(chain, 0.2);
  CheckCompleteLinkageInvariants(chain, labels, 0.2);
  CHECK(*std::max_element(labels.begin(), labels.end()) >= 3);  // at least 4 clusters

  ClusterVoter voter;
  const auto vote = voter.Vote(chain, 0.2);
  REQUIRE(vote.has_value());
  CHECK(vote->cluster_size <= 3);
  const auto& members = voter.winner_members();
  REQUIRE(static_cast<int>(members.size()) == vote->cluster_size);
  Vec3 centroid = Vec3::Zero();
  for (int i : members) {
    centroid += chain[static_cast<std::size_t>(i)];
    for (int j : members) {
      const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
      CHECK((chain[ui] - chain[uj]).norm() <= 0.2);
    }
  }
  CHECK_THAT(vote->point, IsApproxVec(centroid / static_cast<double>(members.size()), 1e-12));
  // Eq. 7's constraint follows: every member within kappa of the centroid.
  for (int i : members) CHECK((vote->point - chain[static_cast<std::size_t>(i)]).norm() <= 0.2);
}

TEST_CASE("Complete linkage matches a naive greedy reference on random scenes", "[unit]") {
  for (unsigned seed = 100; seed < 106; ++seed) {
    std::mt19937 rng(seed);
    std::vector<Vec3> p;
    // Blobs of varying spread (some wider than kappa, so they must split) plus scattered points.
    for (int b = 0; b < 4; ++b) {
      const Vec3 c = UniformIn(&rng, Vec3(-1.0, -1.0, 0.0), Vec3(1.0, 1.0, 2.0));
      const double r = 0.03 + 0.06 * b;
      for (int i = 0; i < 8; ++i) p.push_back(UniformInBall(&rng, c, r));
    }
    for (int i = 0; i < 12; ++i) {
      p.push_back(UniformIn(&rng, Vec3(-1.5, -1.5, 0.0), Vec3(1.5, 1.5, 2.0)));
    }
    std::shuffle(p.begin(), p.end(), rng);
    for (const double kappa : {0.1, 0.2, 0.35}) {
      const std::vector<int> expected = NaiveCompleteLinkage(p, kappa);
      const std::vector<int> labels = CompleteLinkageLabels(p, kappa);
      REQUIRE(labels == expected);
      CheckCompleteLinkageInvariants(p, labels, kappa);

      // The vote picks the largest reference cluster.
      std::vector<int> sizes(p.size(), 0);
      for (int l : expected) ++sizes[static_cast<std::size_t>(l)];
      const auto vote = LargestClusterCentroid(p, kappa);
      REQUIRE(vote.has_value());
      CHECK(vote->cluster_size == *std::max_element(sizes.begin(), sizes.end()));
    }
  }
}

TEST_CASE("ClusterVoter gives the same answers when its workspace is reused", "[unit]") {
  std::mt19937 rng(7);
  std::vector<std::vector<Vec3>> scenes;
  for (int s = 0; s < 4; ++s) {
    std::vector<Vec3> p;
    const int n = 5 + 17 * s;
    for (int i = 0; i < n; ++i) {
      p.push_back(UniformIn(&rng, Vec3::Zero(), Vec3::Constant(0.6 + 0.3 * s)));
    }
    scenes.push_back(p);
  }
  ClusterVoter reused;
  for (int round = 0; round < 2; ++round) {
    for (const auto& p : scenes) {
      const auto fresh = LargestClusterCentroid(p, 0.2);
      const auto again = reused.Vote(p, 0.2);
      REQUIRE(fresh.has_value());
      REQUIRE(again.has_value());
      CHECK(fresh->cluster_size == again->cluster_size);
      CHECK(fresh->num_candidates == again->num_candidates);
      CHECK_THAT(again->point, IsApproxVec(fresh->point, 0.0));
    }
  }
}

TEST_CASE("A tight blob of many candidates is one cluster", "[unit]") {
  std::mt19937 rng(3);
  std::vector<Vec3> p;
  const Vec3 c(0.5, -0.2, 1.3);
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < 500; ++i) {
    p.push_back(UniformInBall(&rng, c, 0.05));
    sum += p.back();
  }
  const auto vote = LargestClusterCentroid(p, 0.2);
  REQUIRE(vote.has_value());
  CHECK(vote->cluster_size == 500);
  CHECK_THAT(vote->point, IsApproxVec(sum / 500.0, 1e-12));
}

}  // namespace
}  // namespace mvtrack::triangulation
