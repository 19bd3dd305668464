// Box-mode refinement inside ProcessWindowJob (TrackerOptions::refinement): duplicates of one
// person (association split its tracklets into two clusters) are merged by footprint distance
// (box_merge_distance_m), two real people walking side by side are not, and box points at
// implausible heights (box_min_height_m, box_max_height_m) are removed.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
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

tracker::TrackerOptions BoxOptions() {
  tracker::TrackerOptions o;
  o.mode = tracker::InputMode::kBoxes;
  o.layout = core::KeypointLayoutId::kNone;
  return o;
}

tracker::WindowJob EmptyJob() {
  tracker::WindowJob job;
  job.window_id = 0;
  job.begin = 0;
  job.end = 30;
  job.finalize_from = 0;
  job.finalize_to = 30;
  return job;
}

// Largest distance between a person's points and the walker's pelvis over its frames.
double WorstError(const core::Tracklet3D& person, const Walker& walker) {
  double worst = 0.0;
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    REQUIRE(person.points[f][0].has_value());
    worst = std::max(worst, (*person.points[f][0] - walker.Pelvis(person.frames[f])).norm());
  }
  return worst;
}

// One walker seen by all four cameras over [0, 30); cameras 3 and 5 (the first two) also report
// a second, simultaneous box track on the same body (a detector's duplicate box), with its own
// pixel noise. The cannot-link rule (two tracks of one camera at the same time) keeps each
// camera's two tracks in different clusters, so association yields a second person on the
// same body: a duplicate a few centimetres from the first.
TEST_CASE("Box mode: a duplicate of a person is merged back into it", "[unit][tracker]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(3);
  const ViewSpec spec{true, 1.0};
  tracker::WindowJob job = EmptyJob();
  const auto frames = FrameRange(0, 29);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    job.tracklets.push_back(MakeTracklet(cameras[c], 1, walker, frames, spec, &rng));
    if (c < 2) job.tracklets.push_back(MakeTracklet(cameras[c], 2, walker, frames, spec, &rng));
  }
  tracker::TrackerOptions options = BoxOptions();

  options.refinement.box_merge_distance_m = 0.0;  // merging off: the duplicate shows
  const tracker::WindowResult unmerged = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(unmerged.persons.size() == 2);
  // Both are the walker: the duplicate coincides with the person (it is not a wrong cluster).
  for (const core::Tracklet3D& person : unmerged.persons) CHECK(WorstError(person, walker) < 0.1);

  options.refinement.box_merge_distance_m = 0.3;
  const tracker::WindowResult merged = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(merged.persons.size() == 1);
  const core::Tracklet3D& person = merged.persons.front();
  std::vector<int> sources = person.source_tracklets;
  std::sort(sources.begin(), sources.end());
  CHECK(sources == std::vector<int>{0, 1, 2, 3, 4, 5});
  CHECK(person.frames.size() == 30);
  CHECK(WorstError(person, walker) < 0.1);
}

// Two people walking side by side, 0.7 m apart (body axes), seen by all four cameras. They are
// real people: the 0.3 m default keeps them apart, while a merge limit above their distance
// (1 m) would unite them, so the test proves the limit and not association decides.
TEST_CASE("Box mode: two people 0.7 m apart are not merged", "[unit][tracker]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker a;
  Walker b = a;
  const Vec3 left = Vec3::UnitZ().cross(a.velocity_mps.normalized());
  b.start = a.start + 0.7 * left;
  std::mt19937 rng(4);
  const ViewSpec spec{true, 1.0};
  tracker::WindowJob job = EmptyJob();
  const auto frames = FrameRange(0, 29);
  for (const auto& camera : cameras) {
    job.tracklets.push_back(MakeTracklet(camera, 1, a, frames, spec, &rng));
    job.tracklets.push_back(MakeTracklet(camera, 2, b, frames, spec, &rng));
  }
  tracker::TrackerOptions options = BoxOptions();
  REQUIRE(options.refinement.box_merge_distance_m == 0.3);
  const tracker::WindowResult r = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(r.persons.size() == 2);
  // One person per walker, each where its walker is.
  const double a0 = WorstError(r.persons[0], a) < 0.1 ? 0.0 : 1.0;
  const core::Tracklet3D& pa = a0 == 0.0 ? r.persons[0] : r.persons[1];
  const core::Tracklet3D& pb = a0 == 0.0 ? r.persons[1] : r.persons[0];
  CHECK(WorstError(pa, a) < 0.1);
  CHECK(WorstError(pb, b) < 0.1);

  options.refinement.box_merge_distance_m = 1.0;
  CHECK(tracker::ProcessWindowJob(rig, options, job).persons.size() == 1);
}

// One walker seen whole by all four cameras; cameras 3 and 5 also report a second box track
// whose points lie where a walker 0.6 m to the side would be: what the displaced centres of
// boxes cut by the image border give. Flagged cut on the edges the displacement points away
// from (Observation2D::cut_edges), that person stands on cut boxes, and every one of its
// tracklets reprojects onto the walker once the part past the cut edge is forgiven: it is
// merged into the walker. Flagged on the other edges, or with the test off, it stays.
TEST_CASE("Box mode: a person standing on cut boxes is merged into the person they show",
          "[unit][tracker]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker walker;
  Walker shifted = walker;
  shifted.start += 0.6 * Vec3::UnitZ().cross(walker.velocity_mps.normalized());
  const auto frames = FrameRange(0, 29);
  const auto make_job = [&](bool right_edges) {
    std::mt19937 rng(5);
    const ViewSpec spec{true, 1.0};
    tracker::WindowJob job = EmptyJob();
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      job.tracklets.push_back(MakeTracklet(cameras[c], 1, walker, frames, spec, &rng));
      if (c >= 2) continue;
      const auto flag = [&, c](FrameIndex t, core::Observation2D* obs) {
        const Vec2 d = *cameras[c].ProjectUndistorted(walker.Pelvis(t)) - obs->points_px[0];
        const bool left = d.x() < 0.0;
        const bool top = d.y() < 0.0;
        obs->cut_edges =
            static_cast<std::uint8_t>((left == right_edges ? core::kCutLeft : core::kCutRight) |
                                      (top == right_edges ? core::kCutTop : core::kCutBottom));
      };
      job.tracklets.push_back(MakeTracklet(cameras[c], 2, shifted, frames, spec, &rng, flag));
    }
    return job;
  };
  tracker::TrackerOptions options = BoxOptions();
  REQUIRE(options.refinement.box_merge_distance_m < 0.6);

  const tracker::WindowResult merged = tracker::ProcessWindowJob(rig, options, make_job(true));
  REQUIRE(merged.persons.size() == 1);
  std::vector<int> sources = merged.persons.front().source_tracklets;
  std::sort(sources.begin(), sources.end());
  CHECK(sources == std::vector<int>{0, 1, 2, 3, 4, 5});
  // The person keeps the triangulation of its whole views: where the walker is.
  CHECK(WorstError(merged.persons.front(), walker) < 0.1);

  // Cut on the other edges, the displacement is not explained: two persons.
  CHECK(tracker::ProcessWindowJob(rig, options, make_job(false)).persons.size() == 2);
  // The reprojection test off: no merge.
  options.refinement.box_split_residual = 0.0;
  CHECK(tracker::ProcessWindowJob(rig, options, make_job(true)).persons.size() == 2);
}

// A cluster whose box points triangulate below the floor (here a walker whose pelvis is 1 m
// under it: what the rays of two different people or of a clipped box can meet at) is no person.
TEST_CASE("Box mode: points at implausible heights are removed", "[unit][tracker]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker person;
  Walker under = person;
  under.start = Vec3(1.0, 1.5, -2.0);  // pelvis at -1.05 m
  std::mt19937 rng(6);
  const ViewSpec spec{true, 0.5};
  tracker::WindowJob job = EmptyJob();
  const auto frames = FrameRange(0, 29);
  for (const auto& camera : cameras) {
    job.tracklets.push_back(MakeTracklet(camera, 1, person, frames, spec, &rng));
    job.tracklets.push_back(MakeTracklet(camera, 2, under, frames, spec, &rng));
  }
  tracker::TrackerOptions options = BoxOptions();
  options.refinement.box_min_height_m = -5.0;  // gate wide open: both are triangulated
  REQUIRE(tracker::ProcessWindowJob(rig, options, job).persons.size() == 2);

  options.refinement.box_min_height_m = -0.3;
  const tracker::WindowResult r = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(r.persons.size() == 1);
  CHECK(WorstError(r.persons.front(), person) < 0.1);

  // The gate is relative to the floor: with the floor 1.2 m lower, the low walker's pelvis is
  // 0.15 m above it (plausible) and the other's 2.15 m (not).
  options.ground_height_m = -1.2;
  const tracker::WindowResult lowered = tracker::ProcessWindowJob(rig, options, job);
  REQUIRE(lowered.persons.size() == 1);
  CHECK(WorstError(lowered.persons.front(), under) < 0.1);
}

// One camera's box of a person standing at `feet` (1.7 m tall, 0.5 m wide), as the camera
// stage makes it with box_point center_ends: centre, bottom, top; the bottom cut when `cut`.
core::Observation2D BoxObservation(const geometry::CameraModel& camera,
                                   const Vec3& feet,
                                   bool cut = false) {
  const Vec2 bottom = *camera.ProjectUndistorted(feet);
  const Vec2 top = *camera.ProjectUndistorted(feet + Vec3(0.0, 0.0, 1.7));
  core::Observation2D obs;
  obs.points_px = {0.5 * (bottom + top), bottom, top};
  obs.confidence = {1.0, cut ? 0.0 : 1.0, 1.0};
  obs.cut_edges = cut ? core::kCutBottom : 0;
  obs.scale_px = 2.0 * (bottom - top).norm();
  return obs;
}

TEST_CASE("Box mode: a 2D tracklet no person was triangulated from is placed by its camera",
          "[unit][tracker]") {
  const auto cameras = RoomCameras();  // 2.6 m high in the corners of a 6 x 6 m room
  const geometry::CameraRig rig = MakeRig(cameras);
  const Vec3 feet(0.5, -0.2, 0.0);
  const auto job_of = [&](bool cut_from_frame_10) {
    tracker::WindowJob job = EmptyJob();
    core::Tracklet2D t;
    t.camera_id = cameras[0].id;
    t.track_id = 7;
    for (FrameIndex f = 0; f < 30; ++f) {
      t.frames.push_back(f);
      t.observations.push_back(BoxObservation(cameras[0], feet, cut_from_frame_10 && f >= 10));
    }
    job.tracklets.push_back(t);
    return job;
  };
  tracker::TrackerOptions options = BoxOptions();
  REQUIRE(options.box_point == tracker::BoxPoint::kCenterEnds);
  tracker::WindowResult r = tracker::ProcessWindowJob(rig, options, job_of(false));
  CHECK(r.persons.empty());
  REQUIRE(r.monocular.size() == 1);
  const core::Tracklet3D& mono = r.monocular.front();
  CHECK(mono.frames.size() == 30);
  CHECK(mono.cameras == std::vector<CameraId>{cameras[0].id});
  REQUIRE(mono.members.size() == 1);
  CHECK(mono.members.front().track_id == 7);
  REQUIRE(mono.points.front()[0].has_value());
  CHECK((mono.points.front()[0]->head<2>() - feet.head<2>()).norm() < 1e-6);
  CHECK(!mono.points.front()[1].has_value());
  // Frames whose box is cut at the bottom are left out.
  r = tracker::ProcessWindowJob(rig, options, job_of(true));
  REQUIRE(r.monocular.size() == 1);
  CHECK(r.monocular.front().frames.size() == 10);
  // The ray to these feet descends about 33 degrees (2.6 m over 4.1 m): a steeper minimum
  // leaves nothing; monocular_max_s 0 makes none.
  options.monocular_min_elevation_deg = 45.0;
  CHECK(tracker::ProcessWindowJob(rig, options, job_of(false)).monocular.empty());
  options.monocular_min_elevation_deg = 30.0;
  CHECK(tracker::ProcessWindowJob(rig, options, job_of(false)).monocular.size() == 1);
  options.linking.monocular_max_s = 0.0;
  CHECK(tracker::ProcessWindowJob(rig, options, job_of(false)).monocular.empty());
}

// RegroupTwoCameraPersons: walker A seen by cameras 3 and 5 is person Q; a two-camera cluster X
// pairs A's box in camera 8 with another walker's box in camera 13 (two cameras' tracklets of
// different people that association could pair). Q reprojects onto A's camera-8 box as its own
// views do, so that box joins Q and X is dissolved. Not when Q already has a camera-8 tracklet
// in those frames, not when X has three cameras, not with box_split_residual 0.
TEST_CASE("Box mode: a two-camera person's view that a third person explains joins it",
          "[unit][tracker]") {
  const auto cameras = RoomCameras();  // ids 3, 5, 8, 13
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker a;
  Walker b = a;
  b.start = a.start + Vec3(0.0, 2.0, 0.0);
  std::mt19937 rng(9);
  const ViewSpec spec{true, 0.5};
  const auto frames = FrameRange(0, 29);
  tracker::WindowJob job = EmptyJob();
  job.tracklets.push_back(MakeTracklet(cameras[0], 1, a, frames, spec, &rng));  // 0: A @ 3
  job.tracklets.push_back(MakeTracklet(cameras[1], 1, a, frames, spec, &rng));  // 1: A @ 5
  job.tracklets.push_back(MakeTracklet(cameras[2], 1, a, frames, spec, &rng));  // 2: A @ 8
  job.tracklets.push_back(MakeTracklet(cameras[3], 2, b, frames, spec, &rng));  // 3: B @ 13
  const tracker::TrackerOptions options = BoxOptions();
  // Q: the person of A's views in cameras 3 and 5 alone.
  tracker::WindowJob q_job = EmptyJob();
  q_job.tracklets = {job.tracklets[0], job.tracklets[1]};
  const tracker::WindowResult q = tracker::ProcessWindowJob(rig, options, q_job);
  REQUIRE(q.persons.size() == 1);
  REQUIRE(WorstError(q.persons[0], a) < 0.1);
  // X's own points (where the two rays pass closest) do not matter to the rule: here B's.
  core::Tracklet3D x = q.persons[0];
  for (std::size_t f = 0; f < x.frames.size(); ++f) x.points[f][0] = b.Pelvis(x.frames[f]);
  x.cameras = {8, 13};

  tracker::WindowWorkspace workspace(options.triangulation);
  {
    std::vector<std::vector<int>> clusters = {{0, 1}, {2, 3}};
    std::vector<core::Tracklet3D> persons = {q.persons[0], x};
    tracker::RegroupTwoCameraPersons(rig, options, job, &workspace, &clusters, &persons);
    REQUIRE(persons.size() == 1);
    CHECK(clusters[0] == std::vector<int>{0, 1, 2});
    CHECK(persons[0].cameras == std::vector<CameraId>{3, 5, 8});
    CHECK(WorstError(persons[0], a) < 0.1);
  }
  {  // Q already sees A in camera 8 over the same frames: nothing moves.
    tracker::WindowJob busy = job;
    busy.tracklets.push_back(MakeTracklet(cameras[2], 7, a, frames, spec, &rng));  // 4: A @ 8
    std::vector<std::vector<int>> clusters = {{0, 1, 4}, {2, 3}};
    std::vector<core::Tracklet3D> persons = {q.persons[0], x};
    tracker::RegroupTwoCameraPersons(rig, options, busy, &workspace, &clusters, &persons);
    CHECK(persons.size() == 2);
    CHECK(clusters[1] == std::vector<int>{2, 3});
  }
  {  // X has three cameras: strong enough, untouched.
    tracker::WindowJob three = job;
    three.tracklets.push_back(MakeTracklet(cameras[0], 9, b, frames, spec, &rng));  // 4: B @ 3
    std::vector<std::vector<int>> clusters = {{0, 1}, {2, 3, 4}};
    std::vector<core::Tracklet3D> persons = {q.persons[0], x};
    tracker::RegroupTwoCameraPersons(rig, options, three, &workspace, &clusters, &persons);
    CHECK(persons.size() == 2);
  }
  {  // Two two-camera persons that each explain a view of the other: one receives, one goes.
    std::vector<std::vector<int>> clusters = {{0, 1}, {2, 3}};
    std::vector<core::Tracklet3D> persons = {q.persons[0], q.persons[0]};
    persons[1].cameras = {8, 13};
    tracker::RegroupTwoCameraPersons(rig, options, job, &workspace, &clusters, &persons);
    CHECK(persons.size() == 1);
  }
  {  // Off with box_split_residual 0.
    tracker::TrackerOptions off = options;
    off.refinement.box_split_residual = 0.0;
    std::vector<std::vector<int>> clusters = {{0, 1}, {2, 3}};
    std::vector<core::Tracklet3D> persons = {q.persons[0], x};
    tracker::RegroupTwoCameraPersons(rig, off, job, &workspace, &clusters, &persons);
    CHECK(persons.size() == 2);
  }
}

}  // namespace
}  // namespace mvtrack
