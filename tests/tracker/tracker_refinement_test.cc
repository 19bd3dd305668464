// Pose-mode refinement inside ProcessWindowJob (TrackerOptions::refinement): a partial duplicate
// of a person (a second 2D skeleton on the same body in some views) is merged back into it,
// fragments of a few joints are dropped, and missing joints are completed.

#include <catch2/catch.hpp>
#include <random>
#include <vector>

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

tracker::TrackerOptions PoseOptions() {
  tracker::TrackerOptions o;
  o.mode = tracker::InputMode::kPoses;
  o.layout = core::KeypointLayoutId::kShelf14;
  return o;
}

// Keeps only the joints in [first, last] of an observation (the others: confidence 0).
auto KeepJoints(int first, int last) {
  return [first, last](FrameIndex, core::Observation2D* obs) {
    for (int k = 0; k < static_cast<int>(obs->confidence.size()); ++k) {
      if (k < first || k > last) obs->confidence[static_cast<std::size_t>(k)] = 0.0;
    }
  };
}

// One walker seen whole by all four cameras over the window [0, 30); in cameras 3 and 5 (the
// first two) the 2D detector also reports joints `part_first..part_last` a second time, as a
// separate partial skeleton (on Shelf, OpenPose's grouping builds such skeletons from leftover
// candidates). The cannot-link rule keeps each camera's two skeletons in different clusters,
// so association yields a second, partial person on the same body.
tracker::WindowJob DuplicatePartJob(int part_first, int part_last) {
  const auto cameras = RoomCameras();
  const Walker walker;
  std::mt19937 rng(11);
  const ViewSpec spec{false, 0.5};
  tracker::WindowJob job;
  job.window_id = 0;
  job.begin = 0;
  job.end = 30;
  job.finalize_from = 0;
  job.finalize_to = 30;
  const auto frames = FrameRange(0, 29);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    job.tracklets.push_back(MakeTracklet(cameras[c], 1, walker, frames, spec, &rng));
    if (c < 2) {
      job.tracklets.push_back(MakeTracklet(
          cameras[c], 2, walker, frames, spec, &rng, KeepJoints(part_first, part_last)));
    }
  }
  return job;
}

TEST_CASE("A partial duplicate of a person is merged back into it", "[unit][tracker]") {
  const geometry::CameraRig rig = MakeRig(RoomCameras());
  const tracker::WindowJob job = DuplicatePartJob(6, 11);  // both arms a second time
  tracker::TrackerOptions options = PoseOptions();

  options.refinement.merge_distance_m = 0.0;  // merging off: the duplicate shows
  const tracker::WindowResult unmerged = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(unmerged.persons.size() == 2);

  options.refinement.merge_distance_m = 0.2;
  const tracker::WindowResult merged = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(merged.persons.size() == 1);
  const core::Tracklet3D& person = merged.persons.front();
  CHECK(person.source_tracklets.size() == job.tracklets.size());
  REQUIRE(person.frames.size() == 30);
  const Walker walker;
  double worst = 0.0;
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    const auto truth = walker.Joints(person.frames[f]);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      REQUIRE(person.points[f][k].has_value());
      worst = std::max(worst, (*person.points[f][k] - truth[k]).norm());
    }
  }
  CHECK(worst < 0.02);
}

TEST_CASE("Fragments of a few joints are not people", "[unit][tracker]") {
  const geometry::CameraRig rig = MakeRig(RoomCameras());
  const auto cameras = RoomCameras();
  std::mt19937 rng(5);
  const ViewSpec spec{false, 0.5};
  tracker::WindowJob job;
  job.begin = 0;
  job.end = 30;
  job.finalize_to = 30;
  const auto frames = FrameRange(0, 29);
  const Walker walker;
  for (const auto& camera : cameras) {
    job.tracklets.push_back(MakeTracklet(camera, 1, walker, frames, spec, &rng));
  }
  // Cameras 3 and 5 also see one wrist (joint 6, 1 of 14 joints < 25 %) of somebody standing
  // in a corner, nothing else of that body.
  Walker corner;
  corner.start = Vec3(2.0, -2.0, 0.0);
  corner.velocity_mps = Vec3(0.01, 0.0, 0.0);
  for (std::size_t c = 0; c < 2; ++c) {
    job.tracklets.push_back(
        MakeTracklet(cameras[c], 2, corner, frames, spec, &rng, KeepJoints(6, 6)));
  }
  tracker::TrackerOptions options = PoseOptions();
  options.refinement.min_person_point_fraction = 0.0;
  REQUIRE(tracker::ProcessWindowJob(rig, options, job).persons.size() == 2);
  options.refinement.min_person_point_fraction = 0.25;
  const tracker::WindowResult r = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(r.persons.size() == 1);
  CHECK(triangulation::MaxPointsPerFrame(r.persons.front()) == testing::kNumJoints);
  CHECK((*r.persons.front().points[0][12] - walker.Joints(0)[12]).norm() < 0.02);
}

TEST_CASE("A joint seen by one camera only is completed from nearby frames", "[unit][tracker]") {
  const geometry::CameraRig rig = MakeRig(RoomCameras());
  const auto cameras = RoomCameras();
  const Walker walker;
  std::mt19937 rng(3);
  const ViewSpec spec{false, 0.0};
  tracker::WindowJob job;
  job.begin = 0;
  job.end = 30;
  job.finalize_to = 30;
  // The head top (13) is seen by camera 3 only on frames 10-19: no pair can triangulate it.
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    job.tracklets.push_back(MakeTracklet(cameras[c],
                                         1,
                                         walker,
                                         FrameRange(0, 29),
                                         spec,
                                         &rng,
                                         [c](FrameIndex t, core::Observation2D* obs) {
                                           if (c > 0 && t >= 10 && t <= 19)
                                             obs->confidence[13] = 0.0;
                                         }));
  }
  tracker::TrackerOptions options = PoseOptions();
  options.triangulation.phi = 0;  // no 2D interpolation: only completion can fill the gap
  options.refinement.max_fill_gap = 0;
  tracker::WindowResult r = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(r.persons.size() == 1);
  CHECK_FALSE(r.persons.front().points[15][13].has_value());

  options.refinement.max_fill_gap = 15;
  // Nearest neighbours of the head top: neck and shoulders, which move rigidly with it here
  // (the elbows, next in line, swing).
  options.refinement.fill_neighbors = 3;
  r = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(r.persons.size() == 1);
  const core::Tracklet3D& person = r.persons.front();
  for (FrameIndex t = 10; t <= 19; ++t) {
    const auto f = static_cast<std::size_t>(person.IndexOf(t));
    REQUIRE(person.points[f][13].has_value());
    // The head moves rigidly with the neck and shoulders in the synthetic walker (no swing).
    CHECK((*person.points[f][13] - walker.Joints(t)[13]).norm() < 1e-6);
  }
}

}  // namespace
}  // namespace mvtrack
