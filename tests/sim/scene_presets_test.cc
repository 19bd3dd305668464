// Scene presets (sim::SizedScene): valid from 2 cameras x 2 people to 64 cameras x 400 people,
// ring for small rooms and a ceiling grid for store floors, the floor grows with the crowd, and
// the large preset really covers its floor: almost every person is detectable in >= 2 views.

#include "sim/scene_presets.h"

#include <catch2/catch.hpp>
#include <map>
#include <string>

#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"

namespace mvtrack::sim {
namespace {

TEST_CASE("SizedScene is valid across the benchmark grids and beyond", "[unit]") {
  for (const int cameras : {2, 3, 4, 5, 6, 8, 16, 32, 64}) {
    for (const int people : {0, 2, 4, 8, 16, 32, 64, 100, 400}) {
      for (const bool poses : {false, true}) {
        const SceneOptions o = SizedScene(cameras, people, poses, 3);
        std::string why;
        INFO(cameras << " cameras, " << people << " people: " << why);
        REQUIRE(o.Validate(&why));
        CHECK(o.num_cameras == cameras);
        CHECK(o.num_people == people);
        CHECK(o.poses == poses);
        CHECK(o.seed == 3u);
        // Floor: at least 6 x 6 m and at least kPresetAreaPerPersonM2 per person.
        CHECK(o.room_width_m >= kPresetMinSideM);
        CHECK(o.room_width_m * o.room_depth_m >= kPresetAreaPerPersonM2 * people);
      }
    }
  }
}

TEST_CASE("SizedScene: ring for small rooms, ceiling grid for store floors", "[unit]") {
  CHECK(SizedScene(2, 2, false, 1).camera_layout == CameraLayout::kRing);
  CHECK(SizedScene(8, 16, false, 1).camera_layout == CameraLayout::kRing);
  CHECK(SizedScene(16, 16, false, 1).camera_layout == CameraLayout::kCeilingGrid);
  CHECK(SizedScene(8, 100, false, 1).camera_layout == CameraLayout::kCeilingGrid);  // 20 m floor
  const SceneOptions store = SizedScene(32, 100, false, 1);
  CHECK(store.room_width_m == 20.0);
  CHECK(store.image_width_px == 1920);
  CHECK(store.camera_height_m == 4.0);
}

// Fraction of person-frames detected in at least two cameras.
double TwoViewCoverage(const SceneOptions& o, int frames) {
  const std::vector<geometry::CameraModel> cameras = MakeCameras(o);
  CrowdSimulator crowd(o);
  long long person_frames = 0, covered = 0;
  for (int f = 0; f < frames; ++f) {
    const FrameTruth truth = crowd.Next();
    const RenderedFrame r = RenderFrame(o, cameras, truth);
    std::map<int, int> views;
    for (const auto& ids : r.person_ids) {
      for (const int id : ids) {
        if (id >= 0) ++views[id];
      }
    }
    person_frames += static_cast<long long>(truth.people.size());
    for (const auto& [id, n] : views) covered += n >= 2 ? 1 : 0;
  }
  return static_cast<double>(covered) / static_cast<double>(person_frames);
}

TEST_CASE("SizedScene: the store preset covers its floor with overlapping views", "[unit]") {
  // 32 cameras, 100 people on 20 x 20 m; misses and occlusion included.
  CHECK(TwoViewCoverage(SizedScene(32, 100, false, 2), 3) > 0.9);
  CHECK(TwoViewCoverage(SizedScene(16, 32, false, 2), 3) > 0.9);
  CHECK(TwoViewCoverage(SizedScene(2, 8, false, 2), 3) > 0.6);
}

}  // namespace
}  // namespace mvtrack::sim
