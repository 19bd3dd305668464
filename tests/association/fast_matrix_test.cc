// Regression guard for the speed shortcuts of ComputeDistanceMatrixForClustering (the early
// exit at lambda; any future gating) on mid-size simulated store scenes from lib/sim: the matrix
// keeps its contract (same kinds, equal values below lambda, lower bounds in [lambda, exact]
// above it) and the clusters equal those of the exact all-pairs matrix, in box and pose mode,
// ring and ceiling grid. Also a constructed two-camera case: a far pair is cut short, a near
// pair stays exact.

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "association/association.h"
#include "geometry/camera_rig.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"
#include "sim/scene_presets.h"

namespace mvtrack::association {
namespace {

// The window [0, frames) of a simulated scene as 2D tracklets, one per (camera, person) from
// the detector model's labelled detections (false positives become one-frame tracklets), with
// the observation the tracker would build: the box centre (box mode) or the 17 keypoints (pose
// mode), scale = w + h.
struct GateScene {
  std::vector<geometry::CameraModel> cameras;
  std::vector<core::Tracklet2D> tracklets;
};

GateScene MakeGateScene(int num_cameras, int num_people, bool poses, int frames) {
  sim::SceneOptions so = sim::SizedScene(num_cameras, num_people, poses, 5);
  so.num_frames = frames;
  GateScene scene;
  scene.cameras = sim::MakeCameras(so);
  sim::CrowdSimulator crowd(so);
  std::map<std::pair<CameraId, int>, core::Tracklet2D> by_person;
  TrackId2D next_false_positive = 100000;
  for (int f = 0; f < frames; ++f) {
    const sim::FrameTruth truth = crowd.Next();
    const sim::RenderedFrame rendered = sim::RenderFrame(so, scene.cameras, truth);
    for (std::size_t c = 0; c < rendered.cameras.size(); ++c) {
      const core::CameraFrame& cf = rendered.cameras[c];
      for (std::size_t d = 0; d < cf.detections.size(); ++d) {
        const core::Detection2D& det = cf.detections[d];
        core::Observation2D o;
        o.scale_px = det.box.width() + det.box.height();
        if (poses) {
          for (const core::Keypoint2D& k : det.keypoints) {
            o.points_px.push_back(k.position_px);
            o.confidence.push_back(k.confidence);
          }
        } else {
          o.points_px = {
              Vec2(0.5 * (det.box.x_min + det.box.x_max), 0.5 * (det.box.y_min + det.box.y_max))};
          o.confidence = {1.0};
        }
        const int person = rendered.person_ids[c][d];
        const int key = person >= 0 ? person : static_cast<int>(next_false_positive++);
        core::Tracklet2D& t = by_person[{cf.camera_id, key}];
        t.camera_id = cf.camera_id;
        t.track_id = key;
        t.frames.push_back(f);
        t.observations.push_back(std::move(o));
      }
    }
  }
  for (auto& [key, t] : by_person) scene.tracklets.push_back(std::move(t));
  return scene;
}

void CheckGateKeepsResults(int num_cameras, int num_people, bool poses) {
  const GateScene scene = MakeGateScene(num_cameras, num_people, poses, 30);
  const geometry::CameraRig rig(scene.cameras);
  const AssociationOptions options;
  const DistanceMatrix exact = ComputeDistanceMatrix(rig, scene.tracklets, options);
  const DistanceMatrix fast = ComputeDistanceMatrixForClustering(rig, scene.tracklets, options);
  const int n = exact.size();
  REQUIRE(n > 4 * num_people);  // a realistic number of tracklets
  int lower_bounds = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const TrackletDistance e = exact.at(i, j);
      const TrackletDistance f = fast.at(i, j);
      REQUIRE(e.kind == f.kind);
      if (!e.is_value()) continue;
      if (e.value < options.lambda) {
        REQUIRE(f.value == e.value);
      } else {
        REQUIRE(f.value >= options.lambda);
        REQUIRE(f.value <= e.value);
        if (f.value < e.value) ++lower_bounds;
      }
    }
  }
  CHECK(lower_bounds > 0);  // the early exit was taken (the test is not vacuous)
  const auto clusters = AssociateTracklets(rig, scene.tracklets, options);
  const auto reference = ClusterTracklets(exact, options);
  REQUIRE(clusters == reference);
}

TEST_CASE("fast matrix: store scene, boxes: clusters equal the exact matrix's", "[unit]") {
  CheckGateKeepsResults(12, 24, false);
}

TEST_CASE("fast matrix: store scene, poses: clusters equal the exact matrix's", "[unit]") {
  CheckGateKeepsResults(12, 24, true);
}

TEST_CASE("fast matrix: room ring, boxes: clusters equal the exact matrix's", "[unit]") {
  CheckGateKeepsResults(6, 8, false);
}

// Two cameras facing each other across a room; person A and person B far apart.
TEST_CASE("fast matrix: cuts far pairs short with a lower bound, keeps near pairs exact",
          "[unit]") {
  const geometry::CameraModel c0 =
      sim::MakeCamera(0, 1280, 720, 80.0, Vec3(0.0, 3.0, 2.5), Vec3(1.0, 0.0, -0.3));
  const geometry::CameraModel c1 =
      sim::MakeCamera(1, 1280, 720, 80.0, Vec3(6.0, 3.0, 2.5), Vec3(-1.0, 0.0, -0.3));
  const geometry::CameraRig rig({c0, c1});
  auto tracklet = [](const geometry::CameraModel& cam, const Vec3& point) {
    core::Tracklet2D t;
    t.camera_id = cam.id;
    for (FrameIndex f = 0; f < 10; ++f) {
      core::Observation2D o;
      const Vec3 moving = point + Vec3(0.0, 0.01 * static_cast<double>(f), 0.0);
      o.points_px = {*cam.ProjectUndistorted(moving)};
      o.confidence = {1.0};
      o.scale_px = 250.0;
      t.frames.push_back(f);
      t.observations.push_back(o);
    }
    return t;
  };
  const Vec3 a(3.0, 1.0, 1.0), b(3.0, 5.0, 1.0);
  // 0: A in camera 0, 1: A in camera 1, 2: B in camera 1.
  const std::vector<core::Tracklet2D> tracklets = {
      tracklet(c0, a), tracklet(c1, a), tracklet(c1, b)};
  AssociationOptions options;
  const DistanceMatrix exact = ComputeDistanceMatrix(rig, tracklets, options);
  const DistanceMatrix fast = ComputeDistanceMatrixForClustering(rig, tracklets, options);
  // Same person: exact (tiny) distance, identical.
  REQUIRE(exact.at(0, 1).is_value());
  CHECK(exact.at(0, 1).value < 0.01);
  CHECK(fast.at(0, 1) == exact.at(0, 1));
  // Different people 4 m apart: far above lambda, so the fast matrix stops early and holds a
  // lower bound in [lambda, exact].
  REQUIRE(exact.at(0, 2).is_value());
  const double e = exact.at(0, 2).value;
  REQUIRE(e > 1.0);
  const TrackletDistance f = fast.at(0, 2);
  REQUIRE(f.is_value());
  CHECK(f.value >= options.lambda);
  CHECK(f.value <= e);
  CHECK(AssociateTracklets(rig, tracklets, options) == std::vector<std::vector<int>>{{0, 1}, {2}});
}

}  // namespace
}  // namespace mvtrack::association
