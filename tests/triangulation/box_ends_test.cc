// TriangulateBoxEnds (triangulation/refinement.h): the box ends of a person's views triangulated
// per frame, kept where they are plausible feet and head, and the frame dropped where the views
// disagree on where the person stands.

#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "triangulation/refinement.h"
#include "triangulation/synthetic_person.h"

namespace mvtrack {
namespace {

using testing::MakeRig;
using testing::RoomCameras;
using testing::Walker;

// Camera `c`'s observation of the walker at frame t: centre (pelvis), feet (the floor under
// it), head (1.8 m above the floor), each shifted by `shift_px` (feet only) to corrupt it.
core::Tracklet2D EndsTracklet(const geometry::CameraModel& camera,
                              const Walker& w,
                              FrameIndex first,
                              FrameIndex last,
                              double feet_shift_px) {
  core::Tracklet2D t;
  t.camera_id = camera.id;
  t.track_id = 1;
  for (FrameIndex f = first; f <= last; ++f) {
    const Vec3 pelvis = w.Pelvis(f);
    const Vec3 feet(pelvis.x(), pelvis.y(), 0.0);
    const Vec3 head(pelvis.x(), pelvis.y(), 1.8);
    core::Observation2D o;
    o.points_px = {*camera.ProjectUndistorted(pelvis),
                   *camera.ProjectUndistorted(feet),
                   *camera.ProjectUndistorted(head)};
    o.points_px[1].y() += feet_shift_px;
    o.confidence = {1.0, 1.0, 1.0};
    o.scale_px = 400.0;
    t.frames.push_back(f);
    t.observations.push_back(o);
  }
  return t;
}

core::Tracklet3D PersonAt(const Walker& w, FrameIndex first, FrameIndex last) {
  core::Tracklet3D p;
  for (FrameIndex f = first; f <= last; ++f) {
    p.frames.push_back(f);
    p.points.push_back({w.Pelvis(f)});
  }
  return p;
}

const std::vector<triangulation::HeightRange> kRanges = {{-0.4, 0.4}, {0.8, 2.4}};

TEST_CASE("Box ends: consistent views give the feet and the head", "[unit]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker w;
  const std::vector<core::Tracklet2D> tracklets = {EndsTracklet(cameras[0], w, 0, 9, 0.0),
                                                   EndsTracklet(cameras[1], w, 0, 9, 0.0)};
  core::Tracklet3D person = PersonAt(w, 0, 9);
  const triangulation::BoxEndsStats s =
      triangulation::TriangulateBoxEnds(rig, tracklets, {0, 1}, 1, kRanges, 0.1, &person);
  CHECK(s.points == 20);
  CHECK(s.implausible_frames == 0);
  REQUIRE(person.frames.size() == 10);
  for (std::size_t f = 0; f < 10; ++f) {
    REQUIRE(person.points[f].size() == 3);
    REQUIRE(person.points[f][1].has_value());
    REQUIRE(person.points[f][2].has_value());
    CHECK(person.points[f][1]->z() == Approx(0.0).margin(1e-6));
    CHECK(person.points[f][2]->z() == Approx(1.8).margin(1e-6));
  }
}

TEST_CASE("Box ends: feet that float mean crossed rays, the frame is dropped", "[unit]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker w;
  // Camera 1's feet are 150 px too high (another person's box, or a box cut by an occluder):
  // with two views the feet triangulate far above the floor.
  const std::vector<core::Tracklet2D> two = {EndsTracklet(cameras[0], w, 0, 9, 0.0),
                                             EndsTracklet(cameras[1], w, 0, 9, -150.0)};
  core::Tracklet3D person = PersonAt(w, 0, 9);
  const triangulation::BoxEndsStats s =
      triangulation::TriangulateBoxEnds(rig, two, {0, 1}, 1, kRanges, 0.1, &person);
  CHECK(s.implausible_frames == 10);
  CHECK(person.frames.empty());

  // With a third, consistent view the frames are kept: the three-view solution (or, where it
  // is not plausible, the best leave-one-out one) puts the feet within the plausible band.
  // (The ends gate persons; they are not a refined estimate of the feet.)
  const std::vector<core::Tracklet2D> three = {EndsTracklet(cameras[0], w, 0, 9, 0.0),
                                               EndsTracklet(cameras[1], w, 0, 9, -150.0),
                                               EndsTracklet(cameras[2], w, 0, 9, 0.0)};
  core::Tracklet3D rescued = PersonAt(w, 0, 9);
  const triangulation::BoxEndsStats r =
      triangulation::TriangulateBoxEnds(rig, three, {0, 1, 2}, 1, kRanges, 0.1, &rescued);
  CHECK(r.implausible_frames == 0);
  REQUIRE(rescued.frames.size() == 10);
  for (const auto& row : rescued.points) {
    REQUIRE(row[1].has_value());
    CHECK(row[1]->z() >= -0.4);
    CHECK(row[1]->z() <= 0.4);
  }
}

TEST_CASE("Box ends: unknown ends (confidence 0) are not triangulated", "[unit]") {
  const auto cameras = RoomCameras();
  const geometry::CameraRig rig = MakeRig(cameras);
  const Walker w;
  std::vector<core::Tracklet2D> tracklets = {EndsTracklet(cameras[0], w, 0, 4, 0.0),
                                             EndsTracklet(cameras[1], w, 0, 4, 0.0)};
  for (core::Observation2D& o : tracklets[1].observations) o.confidence[1] = 0.0;  // feet cut
  core::Tracklet3D person = PersonAt(w, 0, 4);
  triangulation::TriangulateBoxEnds(rig, tracklets, {0, 1}, 1, kRanges, 0.1, &person);
  REQUIRE(person.frames.size() == 5);
  for (const auto& row : person.points) {
    CHECK_FALSE(row[1].has_value());  // one view only
    CHECK(row[2].has_value());
  }
}

}  // namespace
}  // namespace mvtrack
