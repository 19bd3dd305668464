// Tests of the normalized epipolar distance as used by the association (Eq. 2), the tracklet
// distance of Eq. 3-4 with its empty and infinite cases, DistanceMatrix and the options.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "association/association.h"
#include "association/association_scene.h"
#include "geometry/camera_rig.h"
#include "geometry/epipolar.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::association {
namespace {

using testing::BoxPerson;
using testing::LookAtCamera;
using testing::ObserveBoxPerson;

// Two ceiling cameras 3 m apart (baseline along world x), 2.5 m high, looking down the room
// (+y); 1920x1080 images, fx = 1000 px.
std::vector<geometry::CameraModel> TwoCameras() {
  return {LookAtCamera(0, Vec3(-1.5, 0.0, 2.5), Vec3(0.0, 8.0, 0.9), 1000.0, 1920, 1080),
          LookAtCamera(1, Vec3(1.5, 0.0, 2.5), Vec3(0.0, 8.0, 0.9), 1000.0, 1920, 1080)};
}

core::Observation2D PointObservation(const Vec2& x, double scale_px, double confidence = 1.0) {
  core::Observation2D o;
  o.points_px = {x};
  o.confidence = {confidence};
  o.scale_px = scale_px;
  return o;
}

core::Tracklet2D TrackletAt(CameraId camera, std::vector<FrameIndex> frames) {
  core::Tracklet2D t;
  t.camera_id = camera;
  t.frames = std::move(frames);
  for (std::size_t i = 0; i < t.frames.size(); ++i) {
    const Vec2 x(100.0 + 10.0 * static_cast<double>(i), 200.0);
    t.observations.push_back(PointObservation(x, 300.0));
  }
  return t;
}

TEST_CASE("normalized epipolar distance does not depend on the person-to-camera distance",
          "[unit]") {
  // The paper's claim for Eq. 2: the same 3D detection bias gives (almost) the same normalized
  // distance whether the person is near or far, while the raw Eq. 1 distance in pixels shrinks
  // with 1/depth. The person is a 0.5 x 0.3 x 1.8 m box; its image box (hence |w + h|) comes
  // from projecting the 8 corners. Camera 1 sees the box centre 0.1 m too high (a vertical bias;
  // a bias along the baseline would stay inside the epipolar plane and be invisible to any
  // epipolar distance).
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const Mat3 f = geometry::FundamentalMatrix(cameras[0], cameras[1]);
  const BoxPerson person;
  const Vec3 bias(0.0, 0.0, 0.1);
  std::vector<double> normalized, raw;
  for (int y = 2; y <= 15; ++y) {
    const Vec3 foot(0.0, static_cast<double>(y), 0.0);
    const auto o0 = ObserveBoxPerson(cameras[0], person, foot, Vec3::Zero());
    const auto o1 = ObserveBoxPerson(cameras[1], person, foot, bias);
    REQUIRE(o0);
    REQUIRE(o1);
    // Without the bias both distances vanish: the construction is consistent.
    const auto clean = ObserveBoxPerson(cameras[1], person, foot, Vec3::Zero());
    REQUIRE(clean);
    REQUIRE(geometry::SymmetricEpipolarDistance(o0->points_px[0], clean->points_px[0], f) < 1e-6);
    normalized.push_back(geometry::NormalizedEpipolarDistance(
        o0->points_px[0], o0->scale_px, o1->points_px[0], o1->scale_px, f));
    raw.push_back(geometry::SymmetricEpipolarDistance(o0->points_px[0], o1->points_px[0], f));
  }
  const auto [n_min, n_max] = std::minmax_element(normalized.begin(), normalized.end());
  const auto [r_min, r_max] = std::minmax_element(raw.begin(), raw.end());
  INFO("normalized in [" << *n_min << ", " << *n_max << "], raw px in [" << *r_min << ", " << *r_max
                         << "]");
  CHECK(*n_max / *n_min < 1.5);
  CHECK(*r_max / *r_min > 3.0);
  // And the tracklet distance (Eq. 3-4) over the whole walk is the mean of those values.
  core::Tracklet2D a, b;
  a.camera_id = 0;
  b.camera_id = 1;
  for (int y = 2; y <= 15; ++y) {
    const Vec3 foot(0.0, static_cast<double>(y), 0.0);
    a.frames.push_back(y);
    b.frames.push_back(y);
    a.observations.push_back(*ObserveBoxPerson(cameras[0], person, foot, Vec3::Zero()));
    b.observations.push_back(*ObserveBoxPerson(cameras[1], person, foot, bias));
  }
  double mean = 0.0;
  for (double v : normalized) mean += v / static_cast<double>(normalized.size());
  const TrackletDistance d = ComputeTrackletDistance(a, b, f, AssociationOptions{});
  REQUIRE(d.is_value());
  CHECK(d.value == Approx(mean).epsilon(1e-12));
}

TEST_CASE("Eq. 4: same camera with a common frame is infinite", "[unit]") {
  const Mat3 f = Mat3::Zero();  // never used for a same-camera pair
  const core::Tracklet2D a = TrackletAt(3, {0, 1, 2, 3});
  const core::Tracklet2D b = TrackletAt(3, {3, 4, 5});
  CHECK(ComputeTrackletDistance(a, b, f, AssociationOptions{}).is_infinite());
  CHECK(ComputeTrackletDistance(b, a, f, AssociationOptions{}).is_infinite());
  // Coexisting in time is what matters, not whether the points are usable.
  core::Tracklet2D hidden = b;
  for (core::Observation2D& o : hidden.observations) o.confidence = {0.0};
  CHECK(ComputeTrackletDistance(a, hidden, f, AssociationOptions{}).is_infinite());
}

TEST_CASE("Eq. 4: no common frame is empty, for the same or different cameras", "[unit]") {
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const Mat3 f = geometry::FundamentalMatrix(cameras[0], cameras[1]);
  const AssociationOptions options;
  SECTION("disjoint frame ranges") {
    CHECK(ComputeTrackletDistance(TrackletAt(0, {0, 1, 2}), TrackletAt(0, {3, 4}), f, options)
              .is_empty());
    CHECK(ComputeTrackletDistance(TrackletAt(0, {0, 1, 2}), TrackletAt(1, {3, 4}), f, options)
              .is_empty());
  }
  SECTION("interleaved frames without a common one") {
    CHECK(ComputeTrackletDistance(TrackletAt(0, {0, 2, 4, 6}), TrackletAt(0, {1, 3, 5}), f, options)
              .is_empty());
    CHECK(ComputeTrackletDistance(TrackletAt(0, {0, 2, 4, 6}), TrackletAt(1, {1, 3, 5}), f, options)
              .is_empty());
  }
  SECTION("an empty tracklet") {
    CHECK(ComputeTrackletDistance(TrackletAt(0, {}), TrackletAt(0, {1, 2}), f, options).is_empty());
    CHECK(ComputeTrackletDistance(TrackletAt(0, {1, 2}), TrackletAt(1, {}), f, options).is_empty());
  }
  SECTION("common frames but no common usable point") {
    core::Tracklet2D a = TrackletAt(0, {0, 1, 2});
    core::Tracklet2D b = TrackletAt(1, {1, 2, 3});
    a.observations[1].confidence = {0.05};  // below min_confidence = 0.1
    b.observations[1].confidence = {0.0};   // frame 2 of b
    CHECK(ComputeTrackletDistance(a, b, f, options).is_empty());
  }
}

TEST_CASE("Eq. 3-4: different cameras with overlap give the mean over common frames", "[unit]") {
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  const BoxPerson person;
  auto walk = [](FrameIndex f) { return Vec3(-1.0 + 0.1 * static_cast<double>(f), 5.0, 0.0); };
  std::mt19937 rng(11);
  // a: frames 0..9, b: frames 5..14; 2 px of noise so every frame has its own value.
  const core::Tracklet2D a =
      testing::MakeBoxTracklet(cameras[0], 1, person, 0, 9, walk, Vec3::Zero(), 2.0, &rng);
  const core::Tracklet2D b =
      testing::MakeBoxTracklet(cameras[1], 2, person, 5, 14, walk, Vec3::Zero(), 2.0, &rng);
  REQUIRE(a.frames.size() == 10);
  REQUIRE(b.frames.size() == 10);
  double expected = 0.0;
  for (FrameIndex frame = 5; frame <= 9; ++frame) {
    const core::Observation2D& oa = a.observations[static_cast<std::size_t>(a.IndexOf(frame))];
    const core::Observation2D& ob = b.observations[static_cast<std::size_t>(b.IndexOf(frame))];
    expected +=
        geometry::NormalizedEpipolarDistance(
            oa.points_px[0], oa.scale_px, ob.points_px[0], ob.scale_px, rig.fundamental(0, 1)) /
        5.0;
  }
  REQUIRE(expected > 0.0);
  const TrackletDistance ab =
      ComputeTrackletDistance(a, b, rig.fundamental(0, 1), AssociationOptions{});
  const TrackletDistance ba =
      ComputeTrackletDistance(b, a, rig.fundamental(1, 0), AssociationOptions{});
  REQUIRE(ab.is_value());
  REQUIRE(ba.is_value());
  CHECK(ab.value == Approx(expected).epsilon(1e-12));
  CHECK(ba.value == Approx(expected).epsilon(1e-9));  // Eq. 2 is symmetric
}

TEST_CASE("pose mode: joints averaged per frame, low-confidence joints and empty frames skipped",
          "[unit]") {
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const Mat3 f = geometry::FundamentalMatrix(cameras[0], cameras[1]);
  // Three joints of a person at 6 m; 3 px of noise per joint and view.
  const std::vector<Vec3> joints = {Vec3(0.0, 6.0, 1.7), Vec3(-0.2, 6.0, 1.4), Vec3(0.2, 6.0, 1.0)};
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 3.0);
  core::Tracklet2D a, b;
  a.camera_id = 0;
  b.camera_id = 1;
  for (FrameIndex frame = 0; frame < 4; ++frame) {
    core::Observation2D oa, ob;
    for (const Vec3& j : joints) {
      const Vec3 moved = j + Vec3(0.05 * static_cast<double>(frame), 0.0, 0.0);
      oa.points_px.push_back(*cameras[0].ProjectUndistorted(moved) + Vec2(noise(rng), noise(rng)));
      ob.points_px.push_back(*cameras[1].ProjectUndistorted(moved) + Vec2(noise(rng), noise(rng)));
    }
    oa.confidence = {0.9, 0.8, 0.7};
    ob.confidence = {0.9, 0.8, 0.7};
    oa.scale_px = 300.0 + 5.0 * static_cast<double>(frame);
    ob.scale_px = 280.0 - 5.0 * static_cast<double>(frame);
    a.frames.push_back(frame);
    b.frames.push_back(frame);
    a.observations.push_back(oa);
    b.observations.push_back(ob);
  }
  // Frame 0: all joints usable. Frame 1: joint 1 of a below min_confidence (0.1).
  // Frame 2: only joint 1 usable in both (b's joint 0 missing, joint 2 below the threshold).
  // Frame 3: no joint usable in both views -> frame skipped.
  a.observations[1].confidence[1] = 0.05;
  b.observations[2].confidence[0] = 0.0;
  b.observations[2].confidence[2] = 0.09;
  a.observations[3].confidence[0] = 0.0;
  b.observations[3].confidence[1] = 0.0;
  b.observations[3].confidence[2] = 0.0;
  const std::vector<std::vector<std::size_t>> used = {{0, 1, 2}, {0, 2}, {1}};
  auto joint_distance = [&](std::size_t frame, std::size_t k) {
    const core::Observation2D& oa = a.observations[frame];
    const core::Observation2D& ob = b.observations[frame];
    return geometry::NormalizedEpipolarDistance(
        oa.points_px[k], oa.scale_px, ob.points_px[k], ob.scale_px, f);
  };
  double expected = 0.0;
  for (std::size_t frame = 0; frame < used.size(); ++frame) {
    double frame_sum = 0.0;
    for (std::size_t k : used[frame]) frame_sum += joint_distance(frame, k);
    expected += frame_sum / static_cast<double>(used[frame].size()) / 3.0;
  }
  // What ignoring the confidences would give: all joints of all four frames.
  double unfiltered = 0.0;
  for (std::size_t frame = 0; frame < 4; ++frame) {
    for (std::size_t k = 0; k < 3; ++k) unfiltered += joint_distance(frame, k) / 12.0;
  }
  REQUIRE(std::abs(unfiltered - expected) > 1e-3 * expected);

  const TrackletDistance d = ComputeTrackletDistance(a, b, f, AssociationOptions{});
  REQUIRE(d.is_value());
  CHECK(d.value == Approx(expected).epsilon(1e-12));

  SECTION("a confidence equal to min_confidence is usable; 0 never is") {
    AssociationOptions options;
    options.min_confidence = 0.09;  // b's joint 2 in frame 2 becomes usable
    double expected_09 = 0.0;
    const std::vector<std::vector<std::size_t>> used_09 = {{0, 1, 2}, {0, 2}, {1, 2}};
    for (std::size_t frame = 0; frame < used_09.size(); ++frame) {
      double frame_sum = 0.0;
      for (std::size_t k : used_09[frame]) frame_sum += joint_distance(frame, k);
      expected_09 += frame_sum / static_cast<double>(used_09[frame].size()) / 3.0;
    }
    const TrackletDistance d09 = ComputeTrackletDistance(a, b, f, options);
    REQUIRE(d09.is_value());
    CHECK(d09.value == Approx(expected_09).epsilon(1e-12));
    options.min_confidence = 0.0;  // frame 3 still has no joint with a non-zero confidence in both
    const std::vector<std::vector<std::size_t>> used_0 = {{0, 1, 2}, {0, 1, 2}, {1, 2}};
    double expected_0 = 0.0;
    for (std::size_t frame = 0; frame < used_0.size(); ++frame) {
      double frame_sum = 0.0;
      for (std::size_t k : used_0[frame]) frame_sum += joint_distance(frame, k);
      expected_0 += frame_sum / static_cast<double>(used_0[frame].size()) / 3.0;
    }
    const TrackletDistance d0 = ComputeTrackletDistance(a, b, f, options);
    REQUIRE(d0.is_value());
    CHECK(d0.value == Approx(expected_0).epsilon(1e-12));
  }
}

TEST_CASE("DistanceMatrix starts empty, is symmetric and keeps the three kinds", "[unit]") {
  DistanceMatrix m(4);
  CHECK(m.size() == 4);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      if (i != j) CHECK(m.at(i, j).is_empty());
    }
  }
  m.set(2, 0, TrackletDistance::Value(0.25));
  m.set(1, 3, TrackletDistance::Infinite());
  m.set(3, 2, TrackletDistance::Value(0.0));
  CHECK(m.at(0, 2) == TrackletDistance::Value(0.25));
  CHECK(m.at(2, 0) == TrackletDistance::Value(0.25));
  CHECK(m.at(3, 1).is_infinite());
  CHECK(m.at(2, 3) == TrackletDistance::Value(0.0));
  CHECK(m.at(0, 1).is_empty());
  CHECK(m.at(0, 3).is_empty());
  m.set(0, 2, TrackletDistance::Empty());
  CHECK(m.at(2, 0).is_empty());
  CHECK(DistanceMatrix().size() == 0);
  CHECK(DistanceMatrix(1).size() == 1);
}

TEST_CASE("ComputeDistanceMatrix applies Eq. 4 to every pair with the rig's F", "[unit]") {
  std::vector<geometry::CameraModel> cameras =
      testing::RingOfCameras(3, 6.0, 2.5, Vec3(0.0, 0.0, 0.9), 1000.0, 1920, 1080, 10);
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  const BoxPerson person;
  std::mt19937 rng(3);
  auto walk = [](FrameIndex f) { return Vec3(0.05 * static_cast<double>(f), -0.5, 0.0); };
  std::vector<core::Tracklet2D> tracklets = {
      testing::MakeBoxTracklet(cameras[2], 1, person, 0, 9, walk, Vec3::Zero(), 1.0, &rng),
      testing::MakeBoxTracklet(cameras[0], 1, person, 3, 12, walk, Vec3::Zero(), 1.0, &rng),
      testing::MakeBoxTracklet(cameras[1], 1, person, 11, 20, walk, Vec3::Zero(), 1.0, &rng),
      testing::MakeBoxTracklet(cameras[2], 2, person, 5, 7, walk, Vec3(0.0, 0.0, 0.3), 1.0, &rng),
  };
  const DistanceMatrix m = ComputeDistanceMatrix(rig, tracklets, AssociationOptions{});
  REQUIRE(m.size() == 4);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      if (i == j) continue;
      const core::Tracklet2D& a = tracklets[static_cast<std::size_t>(i)];
      const core::Tracklet2D& b = tracklets[static_cast<std::size_t>(j)];
      const Mat3& f = rig.fundamental(*rig.IndexOf(a.camera_id), *rig.IndexOf(b.camera_id));
      const TrackletDistance expected = ComputeTrackletDistance(a, b, f, AssociationOptions{});
      INFO("pair " << i << ", " << j);
      CHECK(m.at(i, j).kind == expected.kind);
      if (expected.is_value()) CHECK(m.at(i, j).value == Approx(expected.value).epsilon(1e-9));
    }
  }
  CHECK(m.at(0, 1).is_value());
  CHECK(m.at(0, 2).is_empty());     // frames 0-9 vs 11-20
  CHECK(m.at(0, 3).is_infinite());  // same camera, frames 5-7 in common
  CHECK(m.at(2, 3).is_empty());
  CHECK(ComputeDistanceMatrix(rig, {}, AssociationOptions{}).size() == 0);
}

TEST_CASE("cameras that never see one place: infinite with a common frame, else empty", "[unit]") {
  // Two cameras 40 m apart looking down at their own floor: the epipolar geometry still pairs
  // points of their images, but no person can be in both at once.
  std::vector<geometry::CameraModel> cameras = {
      LookAtCamera(0, Vec3(0.0, 0.0, 3.0), Vec3(1.0, 3.0, 0.0), 1000.0, 1920, 1080),
      LookAtCamera(1, Vec3(40.0, 0.0, 3.0), Vec3(41.0, 3.0, 0.0), 1000.0, 1920, 1080)};
  geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  const std::vector<core::Tracklet2D> tracklets = {
      TrackletAt(0, {1, 2, 3}), TrackletAt(1, {2, 3, 4}), TrackletAt(1, {7, 8})};
  // Before the rig knows which cameras share a view: Eq. 4 as usual.
  CHECK(ComputeDistanceMatrix(rig, tracklets, AssociationOptions{}).at(0, 1).is_value());
  rig.ComputeSharedViews(0.0);
  REQUIRE_FALSE(rig.SharesView(0, 1));
  for (const DistanceMatrix& m :
       {ComputeDistanceMatrix(rig, tracklets, AssociationOptions{}),
        ComputeDistanceMatrixForClustering(rig, tracklets, AssociationOptions{})}) {
    CHECK(m.at(0, 1).is_infinite());  // frames 2-3 in common
    CHECK(m.at(0, 2).is_empty());     // none in common
  }
  CHECK(
      ComputeTrackletDistance(rig, tracklets[0], tracklets[1], AssociationOptions{}).is_infinite());
  CHECK(ComputeTrackletDistance(rig, tracklets[0], tracklets[2], AssociationOptions{}).is_empty());
}

// Random pose-mode tracklets (5 joints, random confidences, some observations with fewer
// joints, random frame sets) of 3 people in 4 cameras.
std::vector<core::Tracklet2D> RandomPoseTracklets(const std::vector<geometry::CameraModel>& cameras,
                                                  std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 4.0);
  std::vector<core::Tracklet2D> tracklets;
  for (const geometry::CameraModel& camera : cameras) {
    for (int person = 0; person < 3; ++person) {
      core::Tracklet2D t;
      t.camera_id = camera.id;
      t.track_id = person;
      const FrameIndex first = static_cast<FrameIndex>((*rng)() % 20);
      for (FrameIndex f = first; f < first + 12; ++f) {
        if (uniform(*rng) < 0.2) continue;  // gaps
        core::Observation2D o;
        const std::size_t joints = uniform(*rng) < 0.1 ? 3 : 5;
        for (std::size_t k = 0; k < joints; ++k) {
          const Vec3 joint(-1.0 + 1.0 * person + 0.03 * static_cast<double>(f),
                           0.5 * person - 0.5,
                           0.3 + 0.3 * static_cast<double>(k));
          o.points_px.push_back(*camera.ProjectUndistorted(joint) + Vec2(noise(*rng), noise(*rng)));
          const double u = uniform(*rng);
          o.confidence.push_back(u < 0.15 ? 0.0 : (u < 0.3 ? 0.05 : u));
        }
        o.scale_px = 150.0 + 100.0 * uniform(*rng);
        t.frames.push_back(f);
        t.observations.push_back(o);
      }
      tracklets.push_back(t);
    }
  }
  return tracklets;
}

TEST_CASE("the all-pairs computation equals the pairwise definition in pose mode", "[unit]") {
  const std::vector<geometry::CameraModel> cameras =
      testing::RingOfCameras(4, 5.0, 2.5, Vec3(0.0, 0.0, 0.9), 900.0, 1280, 720, 7);
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  std::mt19937 rng(17);
  int values = 0, empties = 0, infinities = 0;
  for (int round = 0; round < 5; ++round) {
    std::vector<core::Tracklet2D> tracklets = RandomPoseTracklets(cameras, &rng);
    std::shuffle(tracklets.begin(), tracklets.end(), rng);  // cameras interleaved in the input
    const AssociationOptions options;
    const DistanceMatrix m = ComputeDistanceMatrix(rig, tracklets, options);
    const DistanceMatrix fast = ComputeDistanceMatrixForClustering(rig, tracklets, options);
    const int n = static_cast<int>(tracklets.size());
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        const core::Tracklet2D& a = tracklets[static_cast<std::size_t>(i)];
        const core::Tracklet2D& b = tracklets[static_cast<std::size_t>(j)];
        const Mat3& f = rig.fundamental(*rig.IndexOf(a.camera_id), *rig.IndexOf(b.camera_id));
        const TrackletDistance expected = ComputeTrackletDistance(a, b, f, options);
        INFO("round " << round << " pair " << i << ", " << j);
        REQUIRE(m.at(i, j).kind == expected.kind);
        REQUIRE(fast.at(i, j).kind == expected.kind);
        if (expected.is_value()) {
          ++values;
          CHECK(m.at(i, j).value == Approx(expected.value).epsilon(1e-9));
          // The clustering variant is exact below lambda and a lower bound >= lambda above.
          if (expected.value < options.lambda) {
            CHECK(fast.at(i, j).value == m.at(i, j).value);
          } else {
            CHECK(fast.at(i, j).value >= options.lambda);
            CHECK(fast.at(i, j).value <= m.at(i, j).value * (1.0 + 1e-12));
          }
        }
        empties += expected.is_empty() ? 1 : 0;
        infinities += expected.is_infinite() ? 1 : 0;
      }
    }
    for (ClusteringMethod method : {ClusteringMethod::kPdnc,
                                    ClusteringMethod::kCompleteLinkageEmptyAsZero,
                                    ClusteringMethod::kCompleteLinkageEmptyAsUpper,
                                    ClusteringMethod::kSingleLinkageEmptyAsUpper}) {
      AssociationOptions o = options;
      o.method = method;
      CHECK(ClusterTracklets(fast, o) == ClusterTracklets(m, o));
    }
  }
  // The random scenes exercised all three kinds.
  CHECK(values > 100);
  CHECK(empties > 0);
  CHECK(infinities > 10);
}

// Box-mode observation with the box ends: the centre, the feet (on the floor z = 0) and the
// head of a 1.8 m person standing at `foot`, projected into `camera`; |w + h| from the height.
core::Observation2D BoxWithEnds(const geometry::CameraModel& camera,
                                const Vec3& foot,
                                const Vec2& noise_px = Vec2::Zero()) {
  core::Observation2D o;
  for (double z : {0.9, 0.0, 1.8}) {
    o.points_px.push_back(*camera.ProjectUndistorted(foot + Vec3(0.0, 0.0, z)) + noise_px);
    o.confidence.push_back(1.0);
  }
  o.scale_px = 1.3 * (o.points_px[1] - o.points_px[2]).norm();
  return o;
}

core::Tracklet2D BoxEndsTracklet(const geometry::CameraModel& camera,
                                 const Vec3& foot,
                                 FrameIndex frames,
                                 const Vec2& noise_px = Vec2::Zero()) {
  core::Tracklet2D t;
  t.camera_id = camera.id;
  for (FrameIndex f = 0; f < frames; ++f) {
    t.frames.push_back(f);
    t.observations.push_back(
        BoxWithEnds(camera, foot + Vec3(0.04 * static_cast<double>(f), 0.0, 0.0), noise_px));
  }
  return t;
}

TEST_CASE("the feet on the floor tell apart two people the epipolar geometry cannot", "[unit]") {
  // Two people at the same distance from the baseline of two cameras of the same height: every
  // point of one lies in the epipolar plane of the same point of the other (Eq. 2 is about 0
  // for camera 0 seeing one and camera 1 the other). Their feet are 1.6 m apart on the floor.
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  const Vec3 left(-0.8, 6.0, 0.0), right(0.8, 6.0, 0.0);
  const core::Tracklet2D a = BoxEndsTracklet(cameras[0], left, 5);
  const core::Tracklet2D b_same = BoxEndsTracklet(cameras[1], left, 5, Vec2(2.0, -3.0));
  const core::Tracklet2D b_other = BoxEndsTracklet(cameras[1], right, 5);
  AssociationOptions epipolar;
  AssociationOptions floor;
  floor.floor_point = 1;
  const TrackletDistance other_epipolar = ComputeTrackletDistance(rig, a, b_other, epipolar);
  REQUIRE(other_epipolar.is_value());
  CHECK(other_epipolar.value < 0.01);  // the ambiguity
  const TrackletDistance other_floor = ComputeTrackletDistance(rig, a, b_other, floor);
  REQUIRE(other_floor.is_value());
  // Per frame, the mean of the centre's and the head's Eq. 2 and the feet term: the mean of
  // the two one-way distances between a view's feet and the other person's feet carried over
  // the floor, i.e. projected from the other's floor point (exact, no noise).
  double expected = 0.0;
  for (std::size_t f = 0; f < 5; ++f) {
    const core::Observation2D& oa = a.observations[f];
    const core::Observation2D& ob = b_other.observations[f];
    const Vec3 step(0.04 * static_cast<double>(f), 0.0, 0.0);
    const Vec2 left_in_1 = *cameras[1].ProjectUndistorted(left + step);
    const Vec2 right_in_0 = *cameras[0].ProjectUndistorted(right + step);
    const double feet = 0.5 * ((left_in_1 - ob.points_px[1]).norm() / ob.scale_px +
                               (right_in_0 - oa.points_px[1]).norm() / oa.scale_px);
    double epipolar_sum = 0.0;
    for (std::size_t k : {std::size_t{0}, std::size_t{2}}) {
      epipolar_sum += geometry::NormalizedEpipolarDistance(
          oa.points_px[k], oa.scale_px, ob.points_px[k], ob.scale_px, rig.fundamental(0, 1));
    }
    expected += (epipolar_sum + feet) / 3.0 / 5.0;
  }
  CHECK(other_floor.value == Approx(expected).epsilon(1e-9));
  CHECK(other_floor.value > 20.0 * other_epipolar.value);
  const TrackletDistance same_floor = ComputeTrackletDistance(rig, a, b_same, floor);
  REQUIRE(same_floor.is_value());
  CHECK(same_floor.value < 0.05);

  SECTION("the F overload refuses a floor point; the rig overload without one is Eq. 2") {
    CHECK(ComputeTrackletDistance(rig, a, b_other, epipolar) ==
          ComputeTrackletDistance(a, b_other, rig.fundamental(0, 1), epipolar));
  }

  SECTION("the floor height moves the plane the feet are carried over") {
    AssociationOptions raised = floor;
    raised.floor_height_m = 0.5;  // the feet are not on this plane: the same person disagrees
    const TrackletDistance d = ComputeTrackletDistance(rig, a, b_same, raised);
    REQUIRE(d.is_value());
    CHECK(d.value > same_floor.value + 0.05);
  }

  SECTION("a foot whose ray does not meet the floor in front of its camera is not compared") {
    core::Tracklet2D up = a;
    for (core::Observation2D& o : up.observations) o.points_px[1].y() = -5000.0;  // sky
    AssociationOptions no_feet = floor;
    const TrackletDistance d = ComputeTrackletDistance(rig, up, b_same, no_feet);
    REQUIRE(d.is_value());
    // The frame mean is over the centre and the head only.
    AssociationOptions two_points = epipolar;
    core::Tracklet2D up_no_feet = up, b_no_feet = b_same;
    for (core::Observation2D& o : up_no_feet.observations) o.confidence[1] = 0.0;
    const TrackletDistance two_point =
        ComputeTrackletDistance(rig, up_no_feet, b_no_feet, two_points);
    REQUIRE(two_point.is_value());
    CHECK(d.value == Approx(two_point.value).epsilon(1e-12));
  }
}

TEST_CASE("the all-pairs computation equals the pairwise definition with a floor point", "[unit]") {
  const std::vector<geometry::CameraModel> cameras =
      testing::RingOfCameras(4, 6.0, 2.5, Vec3(0.0, 0.0, 0.9), 1000.0, 1920, 1080, 3);
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  std::normal_distribution<double> noise(0.0, 3.0);
  std::vector<core::Tracklet2D> tracklets;
  for (const geometry::CameraModel& camera : cameras) {
    for (int person = 0; person < 4; ++person) {
      const Vec3 foot(uniform(rng), uniform(rng), 0.0);
      core::Tracklet2D t = BoxEndsTracklet(camera, foot, 8, Vec2(noise(rng), noise(rng)));
      t.track_id = person;
      if (person == 3) {
        for (core::Observation2D& o : t.observations) o.confidence[1] = 0.0;  // cut feet
      }
      tracklets.push_back(std::move(t));
    }
  }
  std::shuffle(tracklets.begin(), tracklets.end(), rng);
  AssociationOptions options;
  options.floor_point = 1;
  const DistanceMatrix m = ComputeDistanceMatrix(rig, tracklets, options);
  const DistanceMatrix fast = ComputeDistanceMatrixForClustering(rig, tracklets, options);
  const int n = static_cast<int>(tracklets.size());
  int values = 0, below_lambda = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const TrackletDistance expected =
          ComputeTrackletDistance(rig,
                                  tracklets[static_cast<std::size_t>(i)],
                                  tracklets[static_cast<std::size_t>(j)],
                                  options);
      INFO("pair " << i << ", " << j);
      REQUIRE(m.at(i, j).kind == expected.kind);
      if (!expected.is_value()) continue;
      ++values;
      CHECK(m.at(i, j).value == Approx(expected.value).epsilon(1e-9));
      if (expected.value < options.lambda) {
        ++below_lambda;
        CHECK(fast.at(i, j).value == m.at(i, j).value);
      } else {
        CHECK(fast.at(i, j).value >= options.lambda);
      }
    }
  }
  CHECK(values == 96);  // every pair of different cameras: 6 camera pairs x 16
  CHECK(below_lambda > 10);
}

// A unit embedding along axis k of a 16-dimensional space.
core::EmbeddingPtr Axis(int k) {
  auto e = std::make_shared<std::vector<float>>(16, 0.0f);
  (*e)[static_cast<std::size_t>(k)] = 1.0f;
  return e;
}

TEST_CASE("ExpectedLookDistance: from how well each tracklet's embeddings agree", "[unit]") {
  // Identical embeddings: the sum's length is the count, the means must coincide.
  CHECK(ExpectedLookDistance(10, 10.0, 4, 4.0) == Approx(0.0).margin(1e-12));
  // Mutually orthogonal embeddings (length sqrt(count)): nothing to expect, distance 1.
  CHECK(ExpectedLookDistance(9, 3.0, 16, 4.0) == Approx(1.0).margin(1e-12));
  // Pairwise cosine 0.5 inside both (length^2 = n + n (n - 1) 0.5): n = 3 gives length^2 = 6,
  // and the means are expected at cosine 9 x 0.5 / 6 = 0.75.
  CHECK(ExpectedLookDistance(3, std::sqrt(6.0), 3, std::sqrt(6.0)) == Approx(0.25));
  // Fewer than two embeddings, or none: no expectation.
  CHECK(ExpectedLookDistance(1, 1.0, 10, 10.0) == 2.0);
  CHECK(ExpectedLookDistance(10, 10.0, 0, 0.0) == 2.0);
}

TEST_CASE(
    "appearance in cross-view association: the weight adds, the gate cuts consistent strangers",
    "[unit]") {
  const std::vector<geometry::CameraModel> cameras = TwoCameras();
  const geometry::CameraRig rig(cameras);
  REQUIRE(rig.ok());
  const BoxPerson person;
  auto walk = [](FrameIndex f) { return Vec3(-1.0 + 0.1 * static_cast<double>(f), 5.0, 0.0); };
  std::mt19937 rng(5);
  core::Tracklet2D a =
      testing::MakeBoxTracklet(cameras[0], 1, person, 0, 9, walk, Vec3::Zero(), 2.0, &rng);
  core::Tracklet2D b =
      testing::MakeBoxTracklet(cameras[1], 2, person, 0, 9, walk, Vec3::Zero(), 2.0, &rng);
  const TrackletDistance geometric =
      ComputeTrackletDistance(a, b, rig.fundamental(0, 1), AssociationOptions{});
  REQUIRE(geometric.is_value());
  const auto set_looks = [](core::Tracklet2D* t, auto look_of) {
    for (std::size_t i = 0; i < t->observations.size(); ++i) {
      t->observations[i].embedding = look_of(static_cast<int>(i));
    }
  };
  const auto distance = [&](const AssociationOptions& o) {
    const TrackletDistance pairwise = ComputeTrackletDistance(a, b, rig.fundamental(0, 1), o);
    // The all-pairs computation agrees with the pairwise definition.
    const TrackletDistance all = ComputeDistanceMatrix(rig, {a, b}, o).at(0, 1);
    CHECK(all.kind == pairwise.kind);
    if (pairwise.is_value()) CHECK(all.value == Approx(pairwise.value).epsilon(1e-9));
    return pairwise;
  };
  AssociationOptions weighted;
  weighted.appearance_weight = 0.3;
  AssociationOptions gated = weighted;
  gated.appearance_gate = 0.5;

  // Both tracklets look the same: cosine distance 0, nothing changes.
  set_looks(&a, [](int) { return Axis(0); });
  set_looks(&b, [](int) { return Axis(0); });
  CHECK(distance(gated).value == Approx(geometric.value).epsilon(1e-12));

  // b looks like somebody else, consistently: + 0.3 x 1 without the gate, ∞ with it.
  set_looks(&b, [](int) { return Axis(1); });
  CHECK(distance(weighted).value == Approx(geometric.value + 0.3).epsilon(1e-9));
  CHECK(distance(gated).is_infinite());
  AssociationOptions gate_only;
  gate_only.appearance_gate = 0.5;
  CHECK(distance(gate_only).is_infinite());

  // b's embeddings disagree with each other (an unreliable look): its mean says little, so the
  // gate does not apply; the weight still does.
  set_looks(&b, [](int i) { return Axis(1 + i); });
  const TrackletDistance unreliable = distance(gated);
  REQUIRE(unreliable.is_value());
  CHECK(unreliable.value == Approx(geometric.value + 0.3).epsilon(1e-9));

  // No embeddings on one side: the geometric distance.
  for (core::Observation2D& o : b.observations) o.embedding.reset();
  CHECK(distance(gated).value == Approx(geometric.value).epsilon(1e-12));
}

TEST_CASE("AssociationOptions validation and method names", "[unit]") {
  std::string why;
  CHECK(AssociationOptions{}.Validate(&why));
  AssociationOptions o;
  o.lambda = 0.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("lambda"));
  o = AssociationOptions{};
  o.lambda = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  o = AssociationOptions{};
  o.min_confidence = 1.5;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("min_confidence"));
  o = AssociationOptions{};
  o.empty_upper_bound = -1.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("empty_upper_bound"));
  o = AssociationOptions{};
  o.appearance_gate = 2.5;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("appearance_gate"));
  o.appearance_gate = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  o = AssociationOptions{};
  o.floor_point = -2;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("floor_point"));
  o = AssociationOptions{};
  o.floor_height_m = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("floor_height_m"));
  o = AssociationOptions{};
  o.method = static_cast<ClusteringMethod>(42);
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("method"));
  CHECK(o.Validate(nullptr) == false);
  for (ClusteringMethod m : {ClusteringMethod::kPdnc,
                             ClusteringMethod::kCompleteLinkageEmptyAsZero,
                             ClusteringMethod::kCompleteLinkageEmptyAsUpper,
                             ClusteringMethod::kSingleLinkageEmptyAsUpper}) {
    CHECK(ClusteringMethodFromName(ClusteringMethodName(m)) == m);
  }
  CHECK(ClusteringMethodName(ClusteringMethod::kPdnc) == "pdnc");
  CHECK_FALSE(ClusteringMethodFromName("average_linkage").has_value());
}

}  // namespace
}  // namespace mvtrack::association
