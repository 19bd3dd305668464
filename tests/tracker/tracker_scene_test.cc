// The full Tracker on small synthetic scenes: every person recovered with the right identity
// throughout, in box and pose mode; determinism.

#include <catch2/catch.hpp>

#include "tracker/scene_eval.h"

namespace mvtrack {
namespace {

sim::SceneOptions ThreePeopleThreeCameras(bool poses) {
  sim::SceneOptions o;
  o.seed = 7;
  o.num_cameras = 3;
  o.num_people = 3;
  o.num_frames = 300;
  o.poses = poses;
  o.pixel_noise_px = 1.0;
  o.occlusion = false;
  return o;
}

std::unique_ptr<tracker::Tracker> MakeTracker(const sim::Scene& scene, tracker::InputMode mode) {
  tracker::TrackerOptions options;
  options.mode = mode;
  options.layout = core::KeypointLayoutId::kCoco17;
  // These scenes check recovery and identity from the first frame on; a person first seen by
  // two of the three cameras near another person would otherwise be output from their second
  // window only (LinkerOptions::strong_birth_cameras, isolated_birth_distance_m; tests/linking).
  options.linking.strong_birth_cameras = 2;
  std::string why;
  auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), options, &why);
  INFO(why);
  REQUIRE(t != nullptr);
  return t;
}

void RequireEveryoneTrackedWithStableIdentity(const sim::Scene& scene,
                                              const testing::SceneScore& s) {
  INFO("matched " << s.matched << " of " << s.gt_instances << ", false tracks " << s.false_tracks
                  << ", id switches " << s.id_switches << ", mean position error "
                  << s.mean_position_error_m);
  // Every person is recovered in (almost) every frame, no identity changes, no extra tracks.
  CHECK(s.matched >= static_cast<int>(0.98 * s.gt_instances));
  CHECK(s.id_switches == 0);
  CHECK(s.false_tracks <= s.gt_instances / 100);
  REQUIRE(s.ids_of_person.size() == scene.truth.front().people.size());
  std::set<TrackId3D> all_ids;
  for (const auto& [person, ids] : s.ids_of_person) {
    INFO("person " << person);
    CHECK(ids.size() == 1);
    all_ids.insert(ids.begin(), ids.end());
  }
  CHECK(all_ids.size() == s.ids_of_person.size());  // distinct people get distinct ids
}

TEST_CASE("boxes: 3 cameras, 3 walking people, identities kept throughout", "[unit][tracker]") {
  const sim::Scene scene = sim::GenerateScene(ThreePeopleThreeCameras(false));
  auto t = MakeTracker(scene, tracker::InputMode::kBoxes);
  const auto frames = testing::RunScene(t.get(), scene);
  REQUIRE(frames.size() == scene.truth.size());  // every frame is finalized exactly once
  for (std::size_t i = 0; i < frames.size(); ++i) CHECK(frames[i].frame == scene.truth[i].frame);
  const testing::SceneScore s = testing::ScoreRun(scene, frames, scene.truth.front().frame);
  RequireEveryoneTrackedWithStableIdentity(scene, s);
  CHECK(s.mean_position_error_m < 0.15);
}

TEST_CASE("poses: 3 cameras, 3 walking people, 3D poses and identities", "[unit][tracker]") {
  const sim::Scene scene = sim::GenerateScene(ThreePeopleThreeCameras(true));
  auto t = MakeTracker(scene, tracker::InputMode::kPoses);
  const auto frames = testing::RunScene(t.get(), scene);
  REQUIRE(frames.size() == scene.truth.size());
  const testing::SceneScore s = testing::ScoreRun(scene, frames, scene.truth.front().frame);
  RequireEveryoneTrackedWithStableIdentity(scene, s);
  INFO("MPJPE " << s.mean_joint_error_m);
  CHECK(s.mean_joint_error_m < 0.05);
  for (const auto& f : frames) {
    for (const auto& track : f.tracks) CHECK(track.joints.size() == 17);
  }
}

TEST_CASE("output does not depend on the camera order within a frame", "[unit][tracker]") {
  sim::SceneOptions o = ThreePeopleThreeCameras(true);
  o.num_frames = 120;
  o.miss_rate = 0.05;
  o.false_positives_per_frame = 0.2;
  const sim::Scene scene = sim::GenerateScene(o);
  auto a = MakeTracker(scene, tracker::InputMode::kPoses);
  auto b = MakeTracker(scene, tracker::InputMode::kPoses);
  const auto fa = testing::RunScene(a.get(), scene, false);
  const auto fb = testing::RunScene(b.get(), scene, true);
  REQUIRE(fa.size() == fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    REQUIRE(fa[i].tracks.size() == fb[i].tracks.size());
    for (std::size_t k = 0; k < fa[i].tracks.size(); ++k) {
      CHECK(fa[i].tracks[k].id == fb[i].tracks[k].id);
      CHECK(fa[i].tracks[k].position == fb[i].tracks[k].position);  // bit-identical
    }
  }
}

TEST_CASE("noisy detections: misses and false positives still track everyone", "[unit][tracker]") {
  sim::SceneOptions o = ThreePeopleThreeCameras(true);
  o.miss_rate = 0.1;
  o.false_positives_per_frame = 0.5;
  o.keypoint_dropout = 0.1;
  o.pixel_noise_px = 2.0;
  const sim::Scene scene = sim::GenerateScene(o);
  auto t = MakeTracker(scene, tracker::InputMode::kPoses);
  const auto frames = testing::RunScene(t.get(), scene);
  const testing::SceneScore s = testing::ScoreRun(scene, frames, scene.truth.front().frame);
  INFO("matched " << s.matched << "/" << s.gt_instances << " switches " << s.id_switches
                  << " false " << s.false_tracks << " MPJPE " << s.mean_joint_error_m);
  CHECK(s.matched >= static_cast<int>(0.95 * s.gt_instances));
  CHECK(s.id_switches <= 1);
  CHECK(s.mean_joint_error_m < 0.08);
}

// A person that two of the three cameras lose for 8 frames (camera 2 alone cannot place it):
// with bridging, the frames of the gap carry the track, interpolated between its frames on
// both sides, close to the truth and with no cameras; without, they do not.
TEST_CASE("a short gap of a confirmed track is bridged by interpolation", "[unit][tracker]") {
  sim::SceneOptions o = ThreePeopleThreeCameras(true);
  o.num_people = 1;
  sim::Scene scene = sim::GenerateScene(o);
  constexpr FrameIndex kGapFirst = 130, kGapLast = 137;
  for (std::size_t f = 0; f < scene.detections.size(); ++f) {
    const FrameIndex frame = scene.truth[f].frame;
    if (frame < kGapFirst || frame > kGapLast) continue;
    for (std::size_t c = 0; c < 2; ++c) scene.detections[f][c].detections.clear();
  }
  auto run = [&](double bridge_max_gap_s) {
    tracker::TrackerOptions options;
    options.mode = tracker::InputMode::kPoses;
    options.layout = core::KeypointLayoutId::kCoco17;
    options.linking.strong_birth_cameras = 2;
    options.bridge_max_gap_s = bridge_max_gap_s;
    std::string why;
    auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), options, &why);
    INFO(why);
    REQUIRE(t != nullptr);
    return testing::RunScene(t.get(), scene);
  };
  auto in_gap = [&](const std::vector<tracker::Frame3D>& frames, double* max_error) {
    int present = 0;
    for (const tracker::Frame3D& f : frames) {
      if (f.frame < kGapFirst || f.frame > kGapLast || f.tracks.empty()) continue;
      ++present;
      const auto& truth =
          scene.truth[static_cast<std::size_t>(f.frame - scene.truth.front().frame)];
      REQUIRE(truth.people.size() == 1);
      const Vec2 error =
          f.tracks.front().position.head<2>() - truth.people.front().footprint_m.head<2>();
      *max_error = std::max(*max_error, error.norm());
      if (f.tracks.front().cameras.empty()) {
        CHECK(f.tracks.front().joints.size() == 17);
      }
    }
    return present;
  };
  double error_on = 0.0, error_off = 0.0;
  const auto on = run(0.6);
  const auto off = run(0.0);
  const int present_on = in_gap(on, &error_on);
  const int present_off = in_gap(off, &error_off);
  INFO("gap frames with the track: bridged " << present_on << ", not bridged " << present_off
                                             << "; max footprint error " << error_on << " m");
  CHECK(present_on == kGapLast - kGapFirst + 1);
  CHECK(present_off < present_on);
  CHECK(error_on < 0.15);
  // Outside the gap bridging changes nothing.
  REQUIRE(on.size() == off.size());
  for (std::size_t i = 0; i < on.size(); ++i) {
    if (on[i].frame >= kGapFirst && on[i].frame <= kGapLast) continue;
    CHECK(on[i].tracks.size() == off[i].tracks.size());
  }
}

}  // namespace
}  // namespace mvtrack
