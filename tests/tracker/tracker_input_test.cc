// Bad input to the Tracker: each case has a defined outcome (rejected with a reason and counted,
// or handled), never a crash or a corrupted state. See docs/DECISIONS.md "Bad input".

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "tracker/scene_eval.h"

namespace mvtrack {
namespace {

sim::Scene SmallScene(int frames = 90, bool poses = false) {
  sim::SceneOptions o;
  o.seed = 3;
  o.num_cameras = 3;
  o.num_people = 2;
  o.num_frames = frames;
  o.poses = poses;
  o.occlusion = false;
  return sim::GenerateScene(o);
}

std::unique_ptr<tracker::Tracker> Make(const sim::Scene& scene,
                                       tracker::TrackerOptions options = {}) {
  std::string why;
  auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), options, &why);
  INFO(why);
  REQUIRE(t);
  return t;
}

TEST_CASE("a rig with a single camera is refused with a reason", "[unit][tracker]") {
  const sim::Scene scene = SmallScene();
  std::string why;
  auto t = tracker::Tracker::Create(geometry::CameraRig({scene.cameras[0]}), {}, &why);
  CHECK(t == nullptr);
  CHECK_THAT(why, Catch::Contains("at least 2"));
}

TEST_CASE("invalid options are refused naming the field", "[unit][tracker]") {
  const sim::Scene scene = SmallScene();
  tracker::TrackerOptions o;
  o.window_step = 40;  // δ > ν
  std::string why;
  CHECK(tracker::Tracker::Create(geometry::CameraRig(scene.cameras), o, &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("window_step"));
  o = {};
  o.association.lambda = -1.0;
  CHECK(tracker::Tracker::Create(geometry::CameraRig(scene.cameras), o, &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("association"));
  // Nested option groups are named once: "triangulation: phi ...", not "triangulation:
  // triangulation: ...".
  o = {};
  o.triangulation.phi = -1;
  CHECK(tracker::Tracker::Create(geometry::CameraRig(scene.cameras), o, &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("triangulation: phi"));
  CHECK_THAT(why, !Catch::Contains("triangulation: triangulation"));
  o = {};
  o.refinement.outlier_half_window = -1;
  CHECK(tracker::Tracker::Create(geometry::CameraRig(scene.cameras), o, &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("refinement: outlier_half_window"));
  CHECK_THAT(why, !Catch::Contains("refinement: refinement"));
}

TEST_CASE("unknown camera, stale frame, duplicate camera, flood: rejected and counted",
          "[unit][tracker]") {
  const sim::Scene scene = SmallScene();
  auto t = Make(scene);
  core::CameraFrame cf = scene.detections[10][0];
  REQUIRE(t->Add(cf).rejection == tracker::FrameRejection::kNone);

  core::CameraFrame unknown = cf;
  unknown.camera_id = 99;
  tracker::AddResult r = t->Add(unknown);
  CHECK(r.rejection == tracker::FrameRejection::kUnknownCamera);
  CHECK_THAT(r.reason, Catch::Contains("99"));

  r = t->Add(cf);
  CHECK(r.rejection == tracker::FrameRejection::kDuplicateCamera);

  core::CameraFrame older = scene.detections[5][1];
  r = t->Add(older);
  CHECK(r.rejection == tracker::FrameRejection::kStaleFrame);

  core::CameraFrame flood = scene.detections[10][1];
  flood.detections.assign(10000,
                          flood.detections.empty() ? core::Detection2D{} : flood.detections[0]);
  r = t->Add(flood);
  CHECK(r.rejection == tracker::FrameRejection::kTooManyDetections);

  // Frame indices outside [0, 2^53] (the window arithmetic's range) are refused.
  for (const FrameIndex bad : {FrameIndex{-1},
                               std::numeric_limits<FrameIndex>::min(),
                               tracker::kMaxFrameIndex + 1,
                               std::numeric_limits<FrameIndex>::max()}) {
    core::CameraFrame odd = scene.detections[10][1];
    odd.frame = bad;
    r = t->Add(odd);
    CHECK(r.rejection == tracker::FrameRejection::kBadFrameIndex);
    CHECK_THAT(r.reason, Catch::Contains("outside [0, 2^53]"));
  }

  CHECK(t->stats().camera_frames_rejected == 8);
  CHECK(t->stats().rejections.at(tracker::FrameRejection::kStaleFrame) == 1);
  // The rejected frames changed nothing: camera 1 can still deliver frame 10.
  CHECK(t->Add(scene.detections[10][1]).rejection == tracker::FrameRejection::kNone);
}

TEST_CASE("NaN, inf, degenerate boxes and out-of-image keypoints among good data",
          "[unit][tracker]") {
  const sim::Scene scene = SmallScene(150, /*poses=*/true);
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kPoses;
  auto clean = Make(scene, options);
  auto dirty = Make(scene, options);
  const auto clean_frames = testing::RunScene(clean.get(), scene);

  std::vector<tracker::Frame3D> dirty_frames;
  std::int64_t rejected = 0, repaired = 0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& cams : scene.detections) {
    for (core::CameraFrame cf : cams) {
      // Append garbage detections next to the good ones, and dirty one good keypoint.
      core::Detection2D bad;
      bad.box = {nan, 10, 50, 80};
      cf.detections.push_back(bad);
      bad.box = {10, 10, inf, 80};
      cf.detections.push_back(bad);
      bad.box = {50, 50, 40, 40};  // negative width
      cf.detections.push_back(bad);
      bad.box = {50, 50, 50, 90};  // zero width
      cf.detections.push_back(bad);
      bad.box = {-5000, -5000, -4000, -4000};  // outside the image
      cf.detections.push_back(bad);
      if (!cf.detections.empty() && !cf.detections[0].keypoints.empty()) {
        core::Detection2D extra = cf.detections[0];
        extra.keypoints[0].position_px = {1e7, 1e7};  // way outside the image: repaired
        extra.keypoints[1].position_px = {nan, 3.0};
        cf.detections.push_back(extra);
        cf.detections.erase(cf.detections.begin());
      }
      tracker::AddResult r = dirty->Add(cf);
      REQUIRE(r.rejection == tracker::FrameRejection::kNone);
      rejected += r.detections_rejected;
      repaired += r.detections_repaired;
      for (auto& f : r.finalized) dirty_frames.push_back(std::move(f));
    }
  }
  for (auto& f : dirty->Flush()) dirty_frames.push_back(std::move(f));
  CHECK(rejected == 5 * static_cast<std::int64_t>(scene.detections.size() * scene.cameras.size()));
  CHECK(repaired > 0);
  CHECK(dirty->stats().detections_rejected == rejected);
  // The good data is still tracked as well as without the garbage.
  const auto sc = testing::ScoreRun(scene, clean_frames, 0);
  const auto sd = testing::ScoreRun(scene, dirty_frames, 0);
  CHECK(sd.matched >= sc.matched - sc.gt_instances / 50);
  CHECK(sd.id_switches == sc.id_switches);
  for (const auto& f : dirty_frames) {
    for (const auto& track : f.tracks) {
      CHECK(track.position.allFinite());
      for (const auto& j : track.joints) CHECK((!j || j->allFinite()));
    }
  }
}

TEST_CASE("empty frames and silent cameras produce empty but complete output", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(100);
  auto t = Make(scene);
  std::vector<tracker::Frame3D> out;
  for (const auto& cams : scene.detections) {
    core::CameraFrame empty = cams[0];
    empty.detections.clear();
    auto r = t->Add(empty);  // only camera 0 speaks, and it sees nobody
    for (auto& f : r.finalized) out.push_back(std::move(f));
  }
  for (auto& f : t->Flush()) out.push_back(std::move(f));
  REQUIRE(out.size() == scene.detections.size());
  for (const auto& f : out) CHECK(f.tracks.empty());
}

TEST_CASE("one camera alone sees people: nothing can be triangulated, no tracks",
          "[unit][tracker]") {
  const sim::Scene scene = SmallScene(100);
  auto t = Make(scene);
  std::vector<tracker::Frame3D> out;
  for (const auto& cams : scene.detections) {
    auto r = t->Add(cams[1]);
    for (auto& f : r.finalized) out.push_back(std::move(f));
  }
  for (auto& f : t->Flush()) out.push_back(std::move(f));
  REQUIRE(out.size() == scene.detections.size());
  for (const auto& f : out) CHECK(f.tracks.empty());
}

TEST_CASE("frame gaps and a restart far in the future", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(200);
  tracker::TrackerOptions options;
  options.max_frame_jump = 500;
  auto t = Make(scene, options);
  std::vector<tracker::Frame3D> out;
  int fed = 0;
  for (std::size_t i = 0; i < scene.detections.size(); ++i) {
    if (i >= 60 && i < 66) continue;  // a short gap: 6 frames missing
    for (core::CameraFrame cf : scene.detections[i]) {
      if (i >= 100) cf.frame += 1000000;  // the stream restarts with new frame numbers
      auto r = t->Add(cf);
      REQUIRE(r.rejection == tracker::FrameRejection::kNone);
      for (auto& f : r.finalized) out.push_back(std::move(f));
    }
    ++fed;
  }
  for (auto& f : t->Flush()) out.push_back(std::move(f));
  CHECK(static_cast<int>(out.size()) == fed);  // every received frame, once, in order
  for (std::size_t i = 1; i < out.size(); ++i) CHECK(out[i].frame > out[i - 1].frame);
  CHECK(t->stats().reanchors == 1);
  // Tracks exist on both sides of the restart, with new ids after it.
  std::set<TrackId3D> before, after;
  for (const auto& f : out) {
    for (const auto& tr : f.tracks) (f.frame < 1000000 ? before : after).insert(tr.id);
  }
  CHECK(!before.empty());
  CHECK(!after.empty());
  for (TrackId3D id : after) CHECK(before.count(id) == 0);
}

}  // namespace
}  // namespace mvtrack
