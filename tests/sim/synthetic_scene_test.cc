// Whole scenes: structure and timing, determinism (same options -> identical scene), independent
// random streams, and a large ceiling-grid scene (32 cameras, 100 people).

#include "sim/synthetic_scene.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace mvtrack::sim {
namespace {

bool SameDetection(const core::Detection2D& a, const core::Detection2D& b) {
  if (a.box.x_min != b.box.x_min || a.box.y_min != b.box.y_min || a.box.x_max != b.box.x_max ||
      a.box.y_max != b.box.y_max || a.score != b.score || a.layout != b.layout ||
      a.embedding != b.embedding || a.keypoints.size() != b.keypoints.size()) {
    return false;
  }
  for (std::size_t j = 0; j < a.keypoints.size(); ++j) {
    if (a.keypoints[j].position_px != b.keypoints[j].position_px ||
        a.keypoints[j].confidence != b.keypoints[j].confidence) {
      return false;
    }
  }
  return true;
}

bool SameTruth(const FrameTruth& a, const FrameTruth& b) {
  if (a.frame != b.frame || a.utime != b.utime || a.people.size() != b.people.size()) return false;
  for (std::size_t i = 0; i < a.people.size(); ++i) {
    const PersonTruth& p = a.people[i];
    const PersonTruth& q = b.people[i];
    if (p.id != q.id || p.footprint_m != q.footprint_m || p.joints_m != q.joints_m ||
        p.head_top_m != q.head_top_m || p.velocity_mps != q.velocity_mps ||
        p.heading_rad != q.heading_rad || p.height_m != q.height_m) {
      return false;
    }
  }
  return true;
}

void RequireSameScene(const Scene& a, const Scene& b) {
  REQUIRE(a.cameras.size() == b.cameras.size());
  for (std::size_t c = 0; c < a.cameras.size(); ++c) {
    REQUIRE(a.cameras[c].id == b.cameras[c].id);
    REQUIRE(a.cameras[c].width_px == b.cameras[c].width_px);
    REQUIRE(a.cameras[c].height_px == b.cameras[c].height_px);
    REQUIRE(a.cameras[c].K == b.cameras[c].K);
    REQUIRE(a.cameras[c].cam_from_world.rotation == b.cameras[c].cam_from_world.rotation);
    REQUIRE(a.cameras[c].cam_from_world.translation == b.cameras[c].cam_from_world.translation);
  }
  REQUIRE(a.truth.size() == b.truth.size());
  REQUIRE(a.detections.size() == b.detections.size());
  REQUIRE(a.detection_person_ids == b.detection_person_ids);
  int different_truths = 0, different_frames = 0;
  for (std::size_t f = 0; f < a.truth.size(); ++f) {
    if (!SameTruth(a.truth[f], b.truth[f])) ++different_truths;
    REQUIRE(a.detections[f].size() == b.detections[f].size());
    for (std::size_t c = 0; c < a.detections[f].size(); ++c) {
      const core::CameraFrame& x = a.detections[f][c];
      const core::CameraFrame& y = b.detections[f][c];
      bool same = x.utime == y.utime && x.frame == y.frame && x.camera_id == y.camera_id &&
                  x.detections.size() == y.detections.size();
      for (std::size_t k = 0; same && k < x.detections.size(); ++k) {
        same = SameDetection(x.detections[k], y.detections[k]);
      }
      if (!same) ++different_frames;
    }
  }
  CHECK(different_truths == 0);
  CHECK(different_frames == 0);
}

SceneOptions Busy() {
  SceneOptions o;
  o.seed = 1234;
  o.num_people = 6;
  o.num_cameras = 4;
  o.num_frames = 150;
  o.enter_and_leave = true;
  o.mean_stay_s = 2.0;
  o.pixel_noise_px = 2.0;
  o.keypoint_dropout = 0.1;
  o.miss_rate = 0.1;
  o.false_positives_per_frame = 0.7;
  return o;
}

TEST_CASE("scene structure: one truth and one camera frame per camera per frame", "[unit][sim]") {
  SceneOptions o = Busy();
  o.fps = 25.0;
  o.start_utime = 1000;
  const Scene s = GenerateScene(o);
  REQUIRE(s.cameras.size() == 4u);
  REQUIRE(s.truth.size() == 150u);
  REQUIRE(s.detections.size() == 150u);
  REQUIRE(s.detection_person_ids.size() == 150u);
  for (std::size_t f = 0; f < s.truth.size(); ++f) {
    const Utime utime = 1000 + static_cast<Utime>(f) * 40000;  // 25 fps
    CHECK(s.truth[f].frame == static_cast<FrameIndex>(f));
    CHECK(s.truth[f].utime == utime);
    REQUIRE(s.detections[f].size() == 4u);
    REQUIRE(s.detection_person_ids[f].size() == 4u);
    for (std::size_t c = 0; c < 4; ++c) {
      const core::CameraFrame& cf = s.detections[f][c];
      CHECK(cf.camera_id == static_cast<CameraId>(c));
      CHECK(cf.frame == static_cast<FrameIndex>(f));
      CHECK(cf.utime == utime);
      REQUIRE(s.detection_person_ids[f][c].size() == cf.detections.size());
      std::set<int> truth_ids;
      for (const PersonTruth& p : s.truth[f].people) truth_ids.insert(p.id);
      std::set<int> seen;
      for (const int id : s.detection_person_ids[f][c]) {
        if (id < 0) continue;
        CHECK(truth_ids.count(id) == 1);  // only people in the room are detected
        CHECK(seen.insert(id).second);    // at most once per camera
      }
    }
  }
}

TEST_CASE("an empty room yields only false positives", "[unit][sim]") {
  SceneOptions o;
  o.num_people = 0;
  o.num_frames = 50;
  o.false_positives_per_frame = 2.0;
  const Scene s = GenerateScene(o);
  int false_positives = 0;
  for (std::size_t f = 0; f < s.truth.size(); ++f) {
    CHECK(s.truth[f].people.empty());
    for (const auto& ids : s.detection_person_ids[f]) {
      for (const int id : ids) {
        CHECK(id == -1);
        ++false_positives;
      }
    }
  }
  CHECK(false_positives > 200);  // Poisson(2) x 150 camera-frames: 300 expected
}

TEST_CASE("same options give the identical scene, another seed a different one", "[unit][sim]") {
  const Scene a = GenerateScene(Busy());
  const Scene b = GenerateScene(Busy());
  RequireSameScene(a, b);
  SceneOptions other = Busy();
  other.seed = 1235;
  const Scene c = GenerateScene(other);
  CHECK(c.truth[10].people.front().footprint_m != a.truth[10].people.front().footprint_m);
}

TEST_CASE("random streams are independent: detector rates do not change the walk or the noise",
          "[unit][sim]") {
  const Scene base = GenerateScene(Busy());
  SceneOptions more_fp = Busy();
  more_fp.false_positives_per_frame = 3.0;
  SceneOptions no_misses = Busy();
  no_misses.miss_rate = 0.0;
  for (const SceneOptions& o : {more_fp, no_misses}) {
    const Scene s = GenerateScene(o);
    int compared = 0, changed = 0, lost = 0, different_truths = 0;
    for (std::size_t f = 0; f < base.truth.size(); ++f) {
      if (!SameTruth(base.truth[f], s.truth[f])) ++different_truths;
      for (std::size_t c = 0; c < base.cameras.size(); ++c) {
        // Every true detection of the base scene is in the other scene, unchanged.
        const auto& ids = s.detection_person_ids[f][c];
        for (std::size_t k = 0; k < base.detection_person_ids[f][c].size(); ++k) {
          const int id = base.detection_person_ids[f][c][k];
          if (id < 0) continue;
          const auto it = std::find(ids.begin(), ids.end(), id);
          if (it == ids.end()) {
            ++lost;
            continue;
          }
          if (!SameDetection(
                  base.detections[f][c].detections[k],
                  s.detections[f][c].detections[static_cast<std::size_t>(it - ids.begin())])) {
            ++changed;
          }
          ++compared;
        }
      }
    }
    CHECK(different_truths == 0);
    CHECK(lost == 0);
    CHECK(changed == 0);
    CHECK(compared > 1000);
  }
}

TEST_CASE("32 ceiling cameras and 100 people: sizes and multi-view coverage", "[unit][sim]") {
  SceneOptions o;
  o.seed = 32;
  o.camera_layout = CameraLayout::kCeilingGrid;
  o.num_cameras = 32;
  o.num_people = 100;
  o.num_frames = 30;
  o.room_width_m = 16.0;
  o.room_depth_m = 16.0;
  o.camera_height_m = 3.5;
  const Scene s = GenerateScene(o);
  REQUIRE(s.cameras.size() == 32u);
  REQUIRE(s.truth.size() == 30u);
  REQUIRE(s.detections.size() == 30u);
  int instances = 0, seen_twice = 0;
  std::set<CameraId> productive_cameras;
  for (std::size_t f = 0; f < s.truth.size(); ++f) {
    REQUIRE(s.truth[f].people.size() == 100u);
    REQUIRE(s.detections[f].size() == 32u);
    std::map<int, int> views;
    for (std::size_t c = 0; c < 32; ++c) {
      for (const int id : s.detection_person_ids[f][c]) {
        if (id >= 0) ++views[id];
      }
      if (!s.detections[f][c].detections.empty()) {
        productive_cameras.insert(static_cast<CameraId>(c));
      }
    }
    for (const PersonTruth& p : s.truth[f].people) {
      ++instances;
      if (views[p.id] >= 2) ++seen_twice;
    }
  }
  const double fraction = static_cast<double>(seen_twice) / instances;
  INFO("person-frames seen by >= 2 cameras: " << fraction);
  CHECK(fraction > 0.9);
  CHECK(productive_cameras.size() == 32u);
}

}  // namespace
}  // namespace mvtrack::sim
