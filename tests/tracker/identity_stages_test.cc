// The tracker stages behind identity (docs/DECISIONS.md "Window linking", "Box points"):
// a cluster that joins two people in time is split where its footprint jumps; window jobs list
// the live 2D tracks and the stream's frame period; persons carry their (camera, 2D track)
// members; box ends are used only where they are the feet and the head.

#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "support/synthetic_cameras.h"
#include "tracker/camera_stage.h"
#include "tracker/frame_gate.h"
#include "tracker/window_builder.h"
#include "tracker/window_job.h"
#include "triangulation/synthetic_person.h"

namespace mvtrack {
namespace {

using testing::FrameRange;
using testing::MakeRig;
using testing::MakeTracklet;
using testing::RoomCameras;
using testing::ViewSpec;
using testing::Walker;

tracker::WindowJob Job(FrameIndex begin, FrameIndex end) {
  tracker::WindowJob job;
  job.begin = begin;
  job.end = end;
  job.finalize_from = begin;
  job.finalize_to = end;
  return job;
}

// Concatenates two tracklets of one camera (the first's frames before the second's) into one:
// a camera's 2D tracker that jumped from one person to another.
core::Tracklet2D Joined(core::Tracklet2D a, const core::Tracklet2D& b) {
  a.frames.insert(a.frames.end(), b.frames.begin(), b.frames.end());
  a.observations.insert(a.observations.end(), b.observations.begin(), b.observations.end());
  return a;
}

TEST_CASE("A cluster joining two people in time is split where its footprint jumps",
          "[unit][tracker]") {
  // A walks until frame 14 and vanishes; B appears 1.5 m away at frame 16. Cameras 3 and 5
  // end A's tracks and start new ones for B, but camera 8's tracker jumps from A to B: its one
  // tracklet bridges the two people, and association puts all of them into one cluster.
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  Walker a;
  Walker b;
  b.start = a.start + Vec3(0.0, 1.5, 0.0);
  std::mt19937 rng(11);
  const ViewSpec spec{true, 0.5};
  const auto early = FrameRange(0, 14);
  const auto late = FrameRange(16, 29);
  tracker::WindowJob job = Job(0, 30);
  job.tracklets.push_back(MakeTracklet(cameras[0], 1, a, early, spec, &rng));
  job.tracklets.push_back(MakeTracklet(cameras[0], 2, b, late, spec, &rng));
  job.tracklets.push_back(MakeTracklet(cameras[1], 1, a, early, spec, &rng));
  job.tracklets.push_back(MakeTracklet(cameras[1], 2, b, late, spec, &rng));
  job.tracklets.push_back(Joined(MakeTracklet(cameras[2], 1, a, early, spec, &rng),
                                 MakeTracklet(cameras[2], 1, b, late, spec, &rng)));
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kBoxes;
  options.layout = core::KeypointLayoutId::kNone;

  options.refinement.jump_gate_chi2 = 0.0;  // off: one person who teleports
  const tracker::WindowResult joined = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(joined.persons.size() == 1);
  CHECK(joined.persons[0].frames.front() == 0);
  CHECK(joined.persons[0].frames.back() == 29);

  options.refinement.jump_gate_chi2 = tracker::TrackerOptions{}.refinement.jump_gate_chi2;
  const tracker::WindowResult split = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(split.persons.size() == 2);
  for (const core::Tracklet3D& person : split.persons) {
    const Walker& w = person.frames.back() <= 15 ? a : b;
    for (std::size_t f = 0; f < person.frames.size(); ++f) {
      REQUIRE(person.points[f][0].has_value());
      CHECK((person.points[f][0]->head<2>() - w.Pelvis(person.frames[f]).head<2>()).norm() < 0.2);
    }
  }
  // Members are the person's 2D tracks inside its own frames.
  for (const core::Tracklet3D& person : split.persons) {
    CHECK_FALSE(person.members.empty());
    CHECK(std::is_sorted(
        person.members.begin(), person.members.end(), [](const auto& x, const auto& y) {
          return x.camera_id != y.camera_id ? x.camera_id < y.camera_id : x.track_id < y.track_id;
        }));
    for (const core::TrackletMember& m : person.members) {
      CHECK(m.first_frame >= person.frames.front());
      CHECK(m.last_frame <= person.frames.back());
      CHECK(m.num_observations >= 1);
    }
  }
}

TEST_CASE("Window jobs list every live 2D track and the measured frame period", "[unit][tracker]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  tracker::TrackerOptions options;
  options.window_size = 10;
  options.window_step = 10;
  options.min_tracklet_length = 3;
  options.reference_fps = 0.0;  // frame counts as given at this 2 fps stream
  tracker::FrameGate gate(rig, options);
  tracker::WindowBuilder builder(rig, options);
  std::vector<tracker::BuilderOutput> out;
  // 2 fps: utimes 0.5 s apart. Camera index 0 has track 7 in every frame and track 9 in two
  // frames only (too short for a tracklet, still alive).
  for (FrameIndex f = 0; f <= 10; ++f) {
    core::CameraFrame cf;
    cf.camera_id = rig.camera(0).id;
    cf.frame = f;
    cf.utime = 1'000'000 + f * 500'000;
    const tracker::FrameAdmission admission = gate.Admit(cf);
    tracker::TrackedCameraFrame tracked{0, f, cf.utime, {}};
    core::Observation2D obs;
    obs.points_px = {Vec2(100.0, 100.0)};
    obs.confidence = {1.0};
    obs.scale_px = 50.0;
    tracked.observations.emplace_back(7, obs);
    if (f == 3 || f == 4) tracked.observations.emplace_back(9, obs);
    builder.Add(admission.events, std::move(tracked), &out);
  }
  const tracker::WindowJob* job = nullptr;
  for (const auto& o : out) {
    if (const auto* j = std::get_if<tracker::WindowJob>(&o)) job = j;
  }
  REQUIRE(job != nullptr);
  CHECK(job->seconds_per_frame == Approx(0.5));
  REQUIRE(job->tracklets.size() == 1);
  CHECK(job->tracklets[0].track_id == 7);
  REQUIRE(job->live_tracks.size() == 2);
  CHECK(job->live_tracks[0].track_id == 7);
  CHECK(job->live_tracks[0].num_observations == 10);
  CHECK(job->live_tracks[1].track_id == 9);
  CHECK(job->live_tracks[1].first_frame == 3);
  CHECK(job->live_tracks[1].last_frame == 4);
  CHECK(builder.SecondsPerFrame() == Approx(0.5));
}

TEST_CASE("At 2 fps the window grid keeps the durations of the 25 fps frame counts",
          "[unit][tracker]") {
  // reference_fps 25, nu 30, delta 20 -> at 2 fps nu = 3, delta = 2 (AtFrameRate); the geometry
  // is fixed once three frames are closed, so window [0, 3) comes out when frame 3 opens.
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const tracker::TrackerOptions options;
  tracker::FrameGate gate(rig, options);
  tracker::WindowBuilder builder(rig, options);
  std::vector<tracker::BuilderOutput> out;
  for (FrameIndex f = 0; f < 9; ++f) {
    core::CameraFrame cf;
    cf.camera_id = rig.camera(0).id;
    cf.frame = f;
    cf.utime = f * 500'000;
    const tracker::FrameAdmission admission = gate.Admit(cf);
    builder.Add(admission.events, tracker::TrackedCameraFrame{0, f, cf.utime, {}}, &out);
  }
  std::vector<std::pair<FrameIndex, FrameIndex>> windows;
  for (const auto& o : out) {
    if (const auto* j = std::get_if<tracker::WindowJob>(&o)) windows.emplace_back(j->begin, j->end);
  }
  // Frames 0..7 are closed (8 is open): windows [0,3), [2,5), [4,7).
  const std::vector<std::pair<FrameIndex, FrameIndex>> expected = {{0, 3}, {2, 5}, {4, 7}};
  CHECK(windows == expected);
  CHECK(builder.window_size() == 3);
}

// One camera-frame with a single box; returns its observation.
core::Observation2D ObserveBox(const geometry::CameraModel& camera,
                               const tracker::TrackerOptions& options,
                               const core::BoxPx& box) {
  tracker::CameraStage stage(camera, 0, options);
  core::CameraFrame cf;
  cf.camera_id = camera.id;
  cf.frame = 0;
  core::Detection2D d;
  d.box = box;
  d.score = 0.9;
  cf.detections.push_back(d);
  tracker::CameraStageCounters counters;
  const tracker::TrackedCameraFrame t = stage.Process(cf, 0, &counters);
  REQUIRE(t.observations.size() == 1);
  return t.observations[0].second;
}

// A 2D track walks left into the image border: its box is cut there, and the observation's
// centre is that of the box completed to the track's last whole width (box_complete_cut).
TEST_CASE("A cut box is completed to its track's whole size", "[unit][tracker]") {
  const geometry::CameraModel level =
      testing::LookAtCamera(0, Vec3(0.0, -5.0, 1.0), Vec3(0.0, 0.0, 1.0), 1000.0, 1920, 1080);
  const auto run = [&](bool complete, FrameIndex first_frame) {
    tracker::TrackerOptions options;
    options.mode = tracker::InputMode::kBoxes;
    options.layout = core::KeypointLayoutId::kNone;
    options.box_complete_cut = complete;
    tracker::CameraStage stage(level, 0, options);
    core::Observation2D last;
    for (FrameIndex f = first_frame; f <= 4; ++f) {
      core::CameraFrame cf;
      cf.camera_id = 0;
      cf.frame = f;
      core::Detection2D d;
      // Whole boxes 100 px wide moving left 20 px per frame; at frame 4 cut at x = 0.
      d.box = f < 4 ? core::BoxPx{80.0 - 20.0 * static_cast<double>(f),
                                  300.0,
                                  180.0 - 20.0 * static_cast<double>(f),
                                  700.0}
                    : core::BoxPx{0.0, 300.0, 80.0, 700.0};
      d.score = 0.9;
      cf.detections.push_back(d);
      tracker::CameraStageCounters counters;
      const tracker::TrackedCameraFrame t = stage.Process(cf, 0, &counters);
      REQUIRE(t.observations.size() == 1);
      last = t.observations[0].second;
    }
    CHECK(last.cut_edges == core::kCutLeft);
    return last;
  };
  const core::Observation2D completed = run(true, 0);
  CHECK(completed.points_px[0].x() == Approx(30.0));  // (80 - 100 + 80) / 2
  CHECK(completed.points_px[0].y() == Approx(500.0));
  CHECK(completed.scale_px == Approx(500.0));
  // Off, or a track that never had a whole box: the cut box's own centre.
  CHECK(run(false, 0).points_px[0].x() == Approx(40.0));
  CHECK(run(true, 4).points_px[0].x() == Approx(40.0));
}

TEST_CASE("Box ends: the feet and head on the vertical axis, unknown where the box is cut",
          "[unit][tracker]") {
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kBoxes;
  options.layout = core::KeypointLayoutId::kNone;
  REQUIRE(options.box_point == tracker::BoxPoint::kCenterEnds);
  // A camera looking horizontally: verticals are vertical in the image.
  const geometry::CameraModel level =
      testing::LookAtCamera(0, Vec3(0.0, -5.0, 1.0), Vec3(0.0, 0.0, 1.0), 1000.0, 1920, 1080);
  const core::BoxPx box{900.0, 300.0, 1000.0, 700.0};
  const core::Observation2D o = ObserveBox(level, options, box);
  REQUIRE(o.points_px.size() == 3);
  CHECK(o.points_px[0].x() == Approx(950.0));
  CHECK(o.points_px[0].y() == Approx(500.0));
  CHECK(o.points_px[1].x() == Approx(950.0));  // feet
  CHECK(o.points_px[1].y() == Approx(700.0));
  CHECK(o.points_px[2].y() == Approx(300.0));  // head
  CHECK(o.confidence == std::vector<double>{1.0, 1.0, 1.0});
  // Cut by the bottom image border: the feet are unknown.
  const core::Observation2D cut = ObserveBox(level, options, {900.0, 600.0, 1000.0, 1080.0});
  CHECK(cut.confidence == std::vector<double>{1.0, 0.0, 1.0});
  // Cut at the top: the head is unknown.
  const core::Observation2D top = ObserveBox(level, options, {900.0, 0.0, 1000.0, 400.0});
  CHECK(top.confidence == std::vector<double>{1.0, 1.0, 0.0});
  // The observation names the cut edges; a box inside the image has none.
  CHECK(o.cut_edges == 0);
  CHECK(cut.cut_edges == core::kCutBottom);
  CHECK(top.cut_edges == core::kCutTop);
  CHECK(ObserveBox(level, options, {0.0, 300.0, 100.0, 700.0}).cut_edges == core::kCutLeft);
  CHECK(ObserveBox(level, options, {1850.0, 0.0, 1920.0, 700.0}).cut_edges ==
        (core::kCutRight | core::kCutTop));

  // A camera high above, looking steeply down: no ends at all (box_ends_max_elevation_deg).
  const geometry::CameraModel steep =
      testing::LookAtCamera(1, Vec3(0.0, -1.0, 4.0), Vec3(0.0, 0.0, 0.0), 1000.0, 1920, 1080);
  const core::Observation2D above = ObserveBox(steep, options, box);
  CHECK(above.confidence == std::vector<double>{1.0, 0.0, 0.0});

  // A camera tilted down 30 degrees: off the image centre the person's vertical axis leans,
  // and the ends lie on it, not straight below and above the box centre.
  const geometry::CameraModel tilted =
      testing::LookAtCamera(2, Vec3(0.0, -5.0, 3.9), Vec3(0.0, 0.0, 1.0), 1000.0, 1920, 1080);
  const core::Observation2D lean = ObserveBox(tilted, options, {1500.0, 300.0, 1600.0, 700.0});
  REQUIRE(lean.confidence[1] == 1.0);
  // The vertical vanishing point lies below the image: towards it the feet are nearer the
  // image centre column than the head.
  CHECK(std::abs(lean.points_px[1].x() - 960.0) < std::abs(lean.points_px[2].x() - 960.0));
  CHECK(lean.points_px[1].x() < 1550.0);
  CHECK(lean.points_px[2].x() > 1550.0);
}

}  // namespace
}  // namespace mvtrack
