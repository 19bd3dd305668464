// The provisional layer (tracker::ProvisionalEstimator) against the final output of the same run:
// the issue-44 targets (ids of the final output in >= 99 % of track-frames, footprints within
// 0.15 m median) on simulated scenes, and its rules on a hand-made one.

#include "tracker/provisional.h"

#include <catch2/catch.hpp>

#include "eval/layer_agreement.h"
#include "sim/synthetic_scene.h"
#include "tracker/scene_eval.h"
#include "tracker/tracker.h"

namespace mvtrack {
namespace {

eval::EvalSequence Footprints(const std::vector<tracker::Frame3D>& frames) {
  eval::EvalSequence seq;
  for (const tracker::Frame3D& f : frames) {
    eval::EvalFrame e;
    e.frame = f.frame;
    for (const tracker::Track3D& t : f.tracks) e.objects.push_back({t.id, t.position, {}});
    seq.push_back(std::move(e));
  }
  return seq;
}

struct LayeredRun {
  std::vector<tracker::Frame3D> final_frames;
  std::vector<tracker::Frame3D> provisional;
};

LayeredRun Run(const sim::Scene& scene, const tracker::TrackerOptions& options) {
  std::string why;
  auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), options, &why, true);
  INFO(why);
  REQUIRE(t);
  LayeredRun run;
  for (const auto& cams : scene.detections) {
    for (const core::CameraFrame& cf : cams) {
      tracker::AddResult r = t->Add(cf);
      for (auto& f : r.finalized) run.final_frames.push_back(std::move(f));
    }
  }
  for (auto& f : t->Flush()) run.final_frames.push_back(std::move(f));
  run.provisional = t->TakeProvisional();
  return run;
}

sim::SceneOptions Scene(int cameras, int people, bool poses, std::uint64_t seed) {
  sim::SceneOptions o;
  o.seed = seed;
  o.num_cameras = cameras;
  o.num_people = people;
  o.num_frames = 450;
  o.poses = poses;
  o.miss_rate = 0.1;
  o.false_positives_per_frame = 0.3;
  o.pixel_noise_px = 1.5;
  return o;
}

TEST_CASE("provisional layer: the final output's ids, its footprints, every closed frame",
          "[tracker][provisional]") {
  for (const bool poses : {false, true}) {
    for (const std::uint64_t seed : {11u, 12u}) {
      INFO((poses ? "poses" : "boxes") << ", seed " << seed);
      const sim::Scene scene = sim::GenerateScene(Scene(poses ? 4 : 6, 8, poses, seed));
      tracker::TrackerOptions options;
      if (poses) options.mode = tracker::InputMode::kPoses;
      const LayeredRun run = Run(scene, options);
      // One provisional frame per closed frame, in order, sorted by id.
      REQUIRE(run.provisional.size() == run.final_frames.size());
      for (std::size_t i = 0; i < run.provisional.size(); ++i) {
        REQUIRE(run.provisional[i].frame == run.final_frames[i].frame);
        REQUIRE(run.provisional[i].utime == run.final_frames[i].utime);
        for (std::size_t k = 1; k < run.provisional[i].tracks.size(); ++k) {
          REQUIRE(run.provisional[i].tracks[k - 1].id < run.provisional[i].tracks[k].id);
        }
        for (const tracker::Track3D& t : run.provisional[i].tracks) {
          REQUIRE(!t.cameras.empty());
          REQUIRE(t.state == linking::TrackState::kConfirmed);
          REQUIRE(t.joints.size() == (poses ? 17u : 0u));
        }
      }
      const eval::LayerAgreement a =
          eval::CompareLayers(Footprints(run.final_frames), Footprints(run.provisional));
      INFO("same id " << a.same_id << "/" << a.provisional_track_frames << ", covered "
                      << a.final_covered << "/" << a.final_track_frames << ", median "
                      << a.median_distance_m << " m");
      CHECK(a.same_id_fraction() >= 0.99);
      CHECK(a.median_distance_m <= 0.15);
      CHECK(a.coverage() >= 0.8);
      // And against the truth: it finds the people where they are.
      const testing::SceneScore score = testing::ScoreRun(scene, run.provisional, 60);
      CHECK(score.matched >= score.gt_instances * 8 / 10);
      CHECK(score.false_tracks * 50 <= score.matched);
    }
  }
}

// Before any window is linked there is nothing to place; after a stream end neither.
TEST_CASE("provisional layer: no track before a window confirms it, none after a stream end",
          "[unit][tracker][provisional]") {
  const sim::Scene scene = sim::GenerateScene(Scene(4, 3, false, 5));
  tracker::TrackerOptions options;
  const geometry::CameraRig rig(scene.cameras);
  tracker::ProvisionalEstimator estimator(rig, options);
  std::vector<tracker::FrameView> views;
  for (const core::CameraFrame& cf : scene.detections[0]) {
    for (std::size_t i = 0; i < cf.detections.size(); ++i) {
      core::Observation2D obs;
      obs.points_px = {Vec2(100.0, 100.0)};
      obs.confidence = {1.0};
      views.push_back({*rig.IndexOf(cf.camera_id), static_cast<TrackId2D>(i + 1), obs});
    }
  }
  REQUIRE(!views.empty());
  CHECK(estimator.Estimate(0, 0, views).tracks.empty());
  linking::WindowLinker linker;
  estimator.OnLinked(linker);
  CHECK(estimator.Estimate(1, 1, views).tracks.empty());
  estimator.EndStream();
  CHECK(estimator.Estimate(2, 2, views).tracks.empty());
}

}  // namespace
}  // namespace mvtrack
