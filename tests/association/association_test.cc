// End-to-end tests of the cross-view association on synthetic geometry: box-shaped people
// walking in a room seen by calibrated cameras, 2D tracklets with time gaps and detection
// biases, Eq. 2-4 distances and PDNC against the appendix's alternatives.

#include "association/association.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <iterator>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "association/association_scene.h"
#include "geometry/camera_rig.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::association {
namespace {

using testing::AsPartition;
using testing::BoxPerson;
using testing::MakeBoxTracklet;
using testing::SameCluster;
using Clusters = std::vector<std::vector<int>>;

AssociationOptions Options(ClusteringMethod method, double lambda) {
  AssociationOptions o;
  o.method = method;
  o.lambda = lambda;
  return o;
}

// The appendix example built from geometry. Four cameras on a ring (radius 6 m, 2.5 m high):
// cam0 at +x, cam1 at +y, cam2 at -x, cam3 at -y. Person A walks from (-1, 1) to (1, 1.5) over
// frames 0-29. Person B walks 1.3 m from A along the cam0-cam2 baseline (world x) during frames
// 0-9 -- i.e. on A's epipolar plane of cameras 0 and 2, the ambiguous configuration -- and then
// turns away. Tracklets (camera, frames) as in the hand-made appendix matrix:
//   A: 0 = (cam0, 0-9), 1 = (cam1, 0-29), 2 = (cam2, 10-19)
//   B: 3 = (cam2, 0-9), 4 = (cam0, 20-29), 5 = (cam3, 0-29)
// Each tracklet sees the box centre with its own constant vertical detection bias (A: 0.12,
// 0, 0.04 m; B: 0.4, 0.07, 0 m) and 0.5 px of noise: the biases set the size of the true-pair
// distances, the plane configuration makes the wrong pair (0,3) small.
struct AppendixScene {
  std::vector<geometry::CameraModel> cameras;
  geometry::CameraRig rig;
  std::vector<core::Tracklet2D> tracklets;
};

AppendixScene MakeAppendixScene() {
  AppendixScene s;
  s.cameras = testing::RingOfCameras(4, 6.0, 2.5, Vec3(0.0, 0.0, 0.9), 1000.0, 1920, 1080);
  s.rig = geometry::CameraRig(s.cameras);
  const BoxPerson person;
  auto a_at = [](FrameIndex f) {
    const double t = static_cast<double>(f) / 29.0;
    return Vec3(-1.0 + 2.0 * t, 1.0 + 0.5 * t, 0.0);
  };
  auto b_at = [a_at](FrameIndex f) {
    if (f <= 9) return Vec3(a_at(f) + Vec3(1.3, 0.0, 0.0));
    const double t = static_cast<double>(f - 9) / 20.0;
    return Vec3(a_at(9) + Vec3(1.3 + 1.0 * t, 1.5 * t, 0.0));
  };
  std::mt19937 rng(7);
  const double noise_px = 0.5;
  auto bias = [](double z) { return Vec3(0.0, 0.0, z); };
  const auto& c = s.cameras;
  s.tracklets = {
      MakeBoxTracklet(c[0], 0, person, 0, 9, a_at, bias(0.12), noise_px, &rng),
      MakeBoxTracklet(c[1], 1, person, 0, 29, a_at, bias(0.0), noise_px, &rng),
      MakeBoxTracklet(c[2], 2, person, 10, 19, a_at, bias(0.04), noise_px, &rng),
      MakeBoxTracklet(c[2], 3, person, 0, 9, b_at, bias(0.4), noise_px, &rng),
      MakeBoxTracklet(c[0], 4, person, 20, 29, b_at, bias(0.07), noise_px, &rng),
      MakeBoxTracklet(c[3], 5, person, 0, 29, b_at, bias(0.0), noise_px, &rng),
  };
  return s;
}

TEST_CASE("appendix example from geometry: PDNC recovers both persons, (c)-(e) do not", "[unit]") {
  const AppendixScene s = MakeAppendixScene();
  REQUIRE(s.rig.ok());
  const AssociationOptions pdnc = Options(ClusteringMethod::kPdnc, 0.5);  // appendix's lambda
  const DistanceMatrix m = ComputeDistanceMatrix(s.rig, s.tracklets, pdnc);
  // The time gaps produce the appendix's ∅ pattern and no ∞ (no same-camera overlap).
  const std::set<std::pair<int, int>> empty_pairs = {{0, 2}, {0, 4}, {2, 3}, {2, 4}, {3, 4}};
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      INFO("pair " << i << ", " << j);
      CHECK(m.at(i, j).is_empty() == (empty_pairs.count({i, j}) == 1));
      CHECK_FALSE(m.at(i, j).is_infinite());
    }
  }
  // The orderings the appendix's story needs (measured: d12 0.033, d45 0.053, d01 0.094,
  // d03 0.155, d35 0.332; d13 0.617, d15 0.858).
  const double d01 = m.at(0, 1).value, d12 = m.at(1, 2).value, d03 = m.at(0, 3).value;
  const double d35 = m.at(3, 5).value, d45 = m.at(4, 5).value;
  CHECK(d12 < d01);
  CHECK(d01 < d03);  // A's own link to 0 is tighter than the ambiguous wrong pair ...
  CHECK(d03 < d35);  // ... which is tighter than B's weakest link
  CHECK(d45 < d03);
  CHECK(d35 < 0.5);
  CHECK(m.at(1, 3).value > 0.5);
  CHECK(m.at(1, 5).value > 0.5);

  const std::set<std::set<int>> truth = {{0, 1, 2}, {3, 4, 5}};
  // (a) PDNC.
  CHECK(AsPartition(ClusterTracklets(m, pdnc)) == truth);
  CHECK(AsPartition(AssociateTracklets(s.rig, s.tracklets, pdnc)) == truth);
  // (c) ∅ := 0: the first three merges group 0, 2, 3 and 4 -- two persons.
  std::vector<MergeStep> trace;
  const Clusters c =
      ClusterTracklets(m, Options(ClusteringMethod::kCompleteLinkageEmptyAsZero, 0.5), &trace);
  REQUIRE(trace.size() >= 3);
  CHECK(trace[0].cluster_a == 0);
  CHECK(trace[0].cluster_b == 2);
  CHECK(trace[1].cluster_a == 0);
  CHECK(trace[1].cluster_b == 4);
  CHECK(trace[2].cluster_a == 0);
  CHECK(trace[2].cluster_b == 3);
  CHECK(SameCluster(c, 0, 3));
  CHECK(AsPartition(c) != truth);
  // (d) ∅ := 1.0, complete linkage: 0 and 3 end up together.
  const Clusters d =
      ClusterTracklets(m, Options(ClusteringMethod::kCompleteLinkageEmptyAsUpper, 0.5));
  CHECK(SameCluster(d, 0, 3));
  CHECK(AsPartition(d) == std::set<std::set<int>>{{0, 3}, {1, 2}, {4, 5}});
  // (e) ∅ := 1.0, single linkage: one cluster.
  CHECK(ClusterTracklets(m, Options(ClusteringMethod::kSingleLinkageEmptyAsUpper, 0.5)) ==
        Clusters{{0, 1, 2, 3, 4, 5}});
}

// A full synthetic window: 3 cameras (ring of radius 6 m, 2.8 m high), 4 people walking straight
// lines through a 6 x 6 m room for 30 frames, 1 px pixel noise and a random vertical detection
// bias of up to 5 cm per tracklet. Every camera sees every person during the whole window, except
// that camera 2's track of person 3 switched identity at frame 15 (two tracklets, 0-14 and
// 15-29). Returns the tracklets and each tracklet's person.
struct FullScene {
  std::vector<geometry::CameraModel> cameras;
  geometry::CameraRig rig;
  std::vector<core::Tracklet2D> tracklets;
  std::vector<int> person_of;
};

FullScene MakeFullScene() {
  FullScene s;
  s.cameras = testing::RingOfCameras(3, 6.0, 2.8, Vec3(0.0, 0.0, 0.9), 1000.0, 1920, 1080, 1);
  s.rig = geometry::CameraRig(s.cameras);
  const std::vector<Vec3> start = {
      Vec3(-2.5, -2.0, 0.0), Vec3(2.0, -2.5, 0.0), Vec3(-1.0, 2.5, 0.0), Vec3(1.5, 1.0, 0.0)};
  const std::vector<Vec3> end = {
      Vec3(0.5, 1.5, 0.0), Vec3(-1.5, -0.5, 0.0), Vec3(2.5, 1.0, 0.0), Vec3(-1.0, -2.5, 0.0)};
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> bias(-0.05, 0.05);
  const BoxPerson box;
  TrackId2D next_id = 1;
  for (std::size_t c = 0; c < s.cameras.size(); ++c) {
    for (int p = 0; p < 4; ++p) {
      auto at = [&, p](FrameIndex f) {
        const double t = static_cast<double>(f) / 29.0;
        const auto k = static_cast<std::size_t>(p);
        return Vec3((1.0 - t) * start[k] + t * end[k]);
      };
      const bool split = c == 2 && p == 3;
      for (auto [first, last] : split ? std::vector<std::pair<int, int>>{{0, 14}, {15, 29}}
                                      : std::vector<std::pair<int, int>>{{0, 29}}) {
        s.tracklets.push_back(MakeBoxTracklet(
            s.cameras[c], next_id++, box, first, last, at, Vec3(0.0, 0.0, bias(rng)), 1.0, &rng));
        s.person_of.push_back(p);
      }
    }
  }
  return s;
}

std::set<std::set<int>> TruePartition(const std::vector<int>& person_of) {
  std::vector<std::set<int>> by_person;
  for (std::size_t i = 0; i < person_of.size(); ++i) {
    const auto p = static_cast<std::size_t>(person_of[i]);
    if (by_person.size() <= p) by_person.resize(p + 1);
    by_person[p].insert(static_cast<int>(i));
  }
  return {by_person.begin(), by_person.end()};
}

TEST_CASE("full synthetic scene: PDNC associates every tracklet to its person", "[unit]") {
  const FullScene s = MakeFullScene();
  REQUIRE(s.rig.ok());
  REQUIRE(s.tracklets.size() == 13);
  for (const core::Tracklet2D& t : s.tracklets) REQUIRE(!t.frames.empty());
  const AssociationOptions options;  // the paper's lambda = 0.3
  const Clusters clusters = AssociateTracklets(s.rig, s.tracklets, options);
  CHECK(AsPartition(clusters) == TruePartition(s.person_of));
  CHECK(clusters == ClusterTracklets(ComputeDistanceMatrix(s.rig, s.tracklets, options), options));
  // The two halves of the switched track (same camera, no common frame) are ∅ to each other;
  // PDNC puts both into person 3's cluster. Conventional complete linkage with ∅ := 1.0 (the
  // ablation's baseline) cannot: it leaves one half out.
  const int half_a = 11, half_b = 12;
  REQUIRE(s.person_of[static_cast<std::size_t>(half_a)] == 3);
  REQUIRE(s.person_of[static_cast<std::size_t>(half_b)] == 3);
  const DistanceMatrix m = ComputeDistanceMatrix(s.rig, s.tracklets, options);
  CHECK(m.at(half_a, half_b).is_empty());
  CHECK(SameCluster(clusters, half_a, half_b));
  const Clusters d =
      ClusterTracklets(m, Options(ClusteringMethod::kCompleteLinkageEmptyAsUpper, options.lambda));
  CHECK_FALSE(SameCluster(d, half_a, half_b));
  // Same-camera tracklets of different people overlap in time: ∞.
  CHECK(m.at(0, 1).is_infinite());
}

TEST_CASE("the partition does not depend on the order of the input tracklets", "[unit]") {
  // Holds whenever the closest pair is unique at every step, which is the case for continuous
  // distances. Strategy (c) is excluded on purpose: ∅ := 0 creates exact ties among the
  // incalculable pairs, which the documented tie-break resolves by index, i.e. by input order
  // (in the appendix scene a different order yields {0,1} {2,3,4,5} instead of
  // {0,2,3,4,5} {1}) -- one more reason the paper rejects it.
  const FullScene s = MakeFullScene();
  const AppendixScene appendix = MakeAppendixScene();
  const ClusteringMethod methods[] = {ClusteringMethod::kPdnc,
                                      ClusteringMethod::kCompleteLinkageEmptyAsUpper,
                                      ClusteringMethod::kSingleLinkageEmptyAsUpper};
  std::mt19937 rng(99);
  for (int scene = 0; scene < 2; ++scene) {
    const geometry::CameraRig& rig = scene == 0 ? s.rig : appendix.rig;
    const std::vector<core::Tracklet2D>& tracklets = scene == 0 ? s.tracklets : appendix.tracklets;
    const double lambda = scene == 0 ? 0.3 : 0.5;
    const DistanceMatrix reference_matrix =
        ComputeDistanceMatrix(rig, tracklets, Options(ClusteringMethod::kPdnc, lambda));
    std::vector<std::set<std::set<int>>> reference;
    for (ClusteringMethod method : methods) {
      reference.push_back(AsPartition(ClusterTracklets(reference_matrix, Options(method, lambda))));
    }
    for (int round = 0; round < 4; ++round) {
      std::vector<int> order(tracklets.size());
      std::iota(order.begin(), order.end(), 0);
      std::shuffle(order.begin(), order.end(), rng);
      std::vector<core::Tracklet2D> permuted;
      for (int i : order) permuted.push_back(tracklets[static_cast<std::size_t>(i)]);
      const DistanceMatrix m =
          ComputeDistanceMatrix(rig, permuted, Options(ClusteringMethod::kPdnc, lambda));
      for (std::size_t k = 0; k < std::size(methods); ++k) {
        const Clusters clusters = ClusterTracklets(m, Options(methods[k], lambda));
        Clusters mapped_back;
        for (const std::vector<int>& cluster : clusters) {
          std::vector<int> original;
          for (int i : cluster) original.push_back(order[static_cast<std::size_t>(i)]);
          mapped_back.push_back(original);
        }
        INFO("scene " << scene << " method " << ClusteringMethodName(methods[k]) << " round "
                      << round);
        CHECK(AsPartition(mapped_back) == reference[k]);
        // And the output is canonical: sorted clusters ordered by their smallest index.
        for (std::size_t c = 0; c < clusters.size(); ++c) {
          CHECK(std::is_sorted(clusters[c].begin(), clusters[c].end()));
          if (c > 0) CHECK(clusters[c - 1].front() < clusters[c].front());
        }
      }
    }
  }
}

TEST_CASE("same-camera tracklets overlapping in time never merge, whatever lambda", "[unit]") {
  const FullScene s = MakeFullScene();
  for (ClusteringMethod method : {ClusteringMethod::kPdnc,
                                  ClusteringMethod::kCompleteLinkageEmptyAsZero,
                                  ClusteringMethod::kCompleteLinkageEmptyAsUpper,
                                  ClusteringMethod::kSingleLinkageEmptyAsUpper}) {
    INFO(ClusteringMethodName(method));
    // With a huge lambda every finite distance is "tiny": only ∞ can keep tracklets apart.
    const Clusters clusters = AssociateTracklets(s.rig, s.tracklets, Options(method, 1e9));
    int largest = 0;
    for (const std::vector<int>& cluster : clusters) {
      largest = std::max(largest, static_cast<int>(cluster.size()));
      for (int a : cluster) {
        for (int b : cluster) {
          if (a >= b) continue;
          const core::Tracklet2D& ta = s.tracklets[static_cast<std::size_t>(a)];
          const core::Tracklet2D& tb = s.tracklets[static_cast<std::size_t>(b)];
          if (ta.camera_id != tb.camera_id) continue;
          // Same camera inside one cluster: only allowed without a common frame.
          for (FrameIndex f : ta.frames) CHECK(tb.IndexOf(f) < 0);
        }
      }
    }
    CHECK(largest >= 3);  // merging did happen
  }
}

TEST_CASE("empty input and a single tracklet", "[unit]") {
  const FullScene s = MakeFullScene();
  CHECK(AssociateTracklets(s.rig, {}, AssociationOptions{}).empty());
  CHECK(AssociateTracklets(s.rig, {s.tracklets[3]}, AssociationOptions{}) == Clusters{{0}});
  core::Tracklet2D no_frames;
  no_frames.camera_id = s.tracklets[0].camera_id;
  CHECK(AssociateTracklets(s.rig, {no_frames, s.tracklets[0]}, AssociationOptions{}) ==
        Clusters{{0}, {1}});
}

}  // namespace
}  // namespace mvtrack::association
