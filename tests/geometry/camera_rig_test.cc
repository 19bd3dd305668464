// Tests of geometry::CameraRig, and an end-to-end check of the geometry module on a realistic
// 4-camera ring rig with Panoptic-like lens distortion: raw detections -> undistortion ->
// epipolar association distances (Eq. 1-2) -> DLT triangulation (Eq. 5).

#include "geometry/camera_rig.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/epipolar.h"
#include "geometry/triangulation.h"
#include "geometry/view_region.h"
#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::geometry {
namespace {

using testing::IsApproxUpToScale;
using testing::IsApproxVec;

/// A 4-camera ring (radius 4.5 m, 3 m high, looking at the room centre at 1 m height) with
/// non-dense ids given out of order (30, 10, 40, 20) and Panoptic-like distortion.
std::vector<CameraModel> RingCamerasOutOfOrder() {
  std::vector<CameraModel> cameras =
      testing::RingOfCameras(4, 4.5, 3.0, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
  const CameraId ids[] = {30, 10, 40, 20};
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    cameras[i].id = ids[i];
    cameras[i].distortion = testing::PanopticLikeDistortion();
  }
  return cameras;
}

TEST_CASE("CameraRig sorts cameras by id and indexes them densely", "[unit]") {
  const std::vector<CameraModel> input = RingCamerasOutOfOrder();
  std::string why;
  const CameraRig rig(input, &why);
  REQUIRE(rig.ok());
  REQUIRE(rig.size() == 4);
  REQUIRE(rig.cameras().size() == 4);

  const CameraId sorted_ids[] = {10, 20, 30, 40};
  for (int i = 0; i < rig.size(); ++i) {
    INFO("index " << i);
    REQUIRE(rig.camera(i).id == sorted_ids[i]);
    REQUIRE(rig.IndexOf(sorted_ids[i]) == i);
    REQUIRE(&rig.cameras()[static_cast<std::size_t>(i)] == &rig.camera(i));
    // The camera at index i is the input camera with that id, unchanged.
    const CameraModel* original = nullptr;
    for (const CameraModel& c : input) {
      if (c.id == sorted_ids[i]) original = &c;
    }
    REQUIRE(original != nullptr);
    REQUIRE(rig.camera(i).K == original->K);
    REQUIRE(rig.camera(i).cam_from_world.rotation == original->cam_from_world.rotation);
    REQUIRE(rig.camera(i).cam_from_world.translation == original->cam_from_world.translation);
    REQUIRE(rig.camera(i).distortion.k1 == original->distortion.k1);
    REQUIRE_THAT(rig.projection(i), IsApproxVec(original->ProjectionMatrix(), 1e-12));
  }
}

TEST_CASE("CameraRig::IndexOf returns nullopt for unknown ids", "[unit]") {
  const CameraRig rig(RingCamerasOutOfOrder());
  REQUIRE(rig.ok());
  for (const CameraId unknown : {0, 1, 15, 41, -10, 1000}) {
    REQUIRE_FALSE(rig.IndexOf(unknown).has_value());
  }
  REQUIRE_FALSE(CameraRig().IndexOf(10).has_value());
}

TEST_CASE("CameraRig rejects duplicate camera ids with a reason", "[unit]") {
  std::vector<CameraModel> cameras = RingCamerasOutOfOrder();
  cameras[3].id = 30;  // now 30, 10, 40, 30
  std::string why;
  const CameraRig rig(cameras, &why);
  REQUIRE_FALSE(rig.ok());
  REQUIRE(rig.size() == 0);
  REQUIRE_FALSE(rig.IndexOf(10).has_value());
  REQUIRE_FALSE(rig.IndexOf(30).has_value());
  REQUIRE_THAT(why, Catch::Contains("duplicate") && Catch::Contains("30"));
  // A null reason pointer is allowed.
  REQUIRE_FALSE(CameraRig(cameras, nullptr).ok());
}

TEST_CASE("CameraRig rejects an invalid camera with Validate's reason", "[unit]") {
  std::vector<CameraModel> cameras = RingCamerasOutOfOrder();
  cameras[2].K(0, 0) = -5.0;  // camera 40
  std::string expected;
  REQUIRE_FALSE(cameras[2].Validate(&expected));
  std::string why;
  const CameraRig rig(cameras, &why);
  REQUIRE_FALSE(rig.ok());
  REQUIRE(rig.size() == 0);
  REQUIRE(why == expected);
  REQUIRE_THAT(why, Catch::Contains("camera 40") && Catch::Contains("focal"));
}

TEST_CASE("An empty CameraRig is not ok", "[unit]") {
  REQUIRE_FALSE(CameraRig().ok());
  REQUIRE(CameraRig().size() == 0);
  REQUIRE_FALSE(CameraRig(std::vector<CameraModel>{}).ok());
}

TEST_CASE("CameraRig::fundamental(i, j) is consistent with FundamentalMatrix", "[unit]") {
  const CameraRig rig(RingCamerasOutOfOrder());
  REQUIRE(rig.ok());
  const Vec3 point(0.4, -0.7, 1.3);
  for (int i = 0; i < rig.size(); ++i) {
    for (int j = 0; j < rig.size(); ++j) {
      if (i == j) continue;
      INFO("from " << i << " to " << j);
      const Mat3& f = rig.fundamental(i, j);
      REQUIRE_THAT(f, IsApproxVec(FundamentalMatrix(rig.camera(i), rig.camera(j)), 1e-12));
      REQUIRE_THAT(rig.fundamental(j, i), IsApproxUpToScale(f.transpose(), 1e-9));
      // Direction: points of camera i map to epipolar lines in camera j.
      const Vec2 x_i = *rig.camera(i).ProjectUndistorted(point);
      const Vec2 x_j = *rig.camera(j).ProjectUndistorted(point);
      REQUIRE(PointLineDistance(x_j, f * x_i.homogeneous()) < 1e-6);
      REQUIRE(PointLineDistance(x_i, f.transpose() * x_j.homogeneous()) < 1e-6);
    }
  }
}

/// Raw (distorted) detections of `point` in every camera of `rig`; all must be inside the image.
std::vector<Vec2> RawDetections(const CameraRig& rig, const Vec3& point) {
  std::vector<Vec2> raw;
  for (const CameraModel& camera : rig.cameras()) {
    const std::optional<Vec2> px = camera.Project(point);
    REQUIRE(px.has_value());
    REQUIRE(camera.InImage(*px));
    raw.push_back(*px);
  }
  return raw;
}

std::vector<Mat34> RigProjections(const CameraRig& rig) {
  std::vector<Mat34> p;
  for (int i = 0; i < rig.size(); ++i) p.push_back(rig.projection(i));
  return p;
}

TEST_CASE("Realistic 4-camera ring rig: undistort, check epipolar consistency, triangulate",
          "[unit]") {
  const CameraRig rig(RingCamerasOutOfOrder());
  REQUIRE(rig.ok());
  const Vec3 room_centre(0.0, 0.0, 1.0);

  // The rig is what it claims to be: cameras 3 m high on a 4.5 m circle, looking at the centre.
  for (const CameraModel& camera : rig.cameras()) {
    INFO("camera " << camera.id);
    const Vec3 c = camera.CenterInWorld();
    REQUIRE(c.z() == Approx(3.0));
    REQUIRE(c.head<2>().norm() == Approx(4.5));
    REQUIRE_THAT(*camera.ProjectUndistorted(room_centre),
                 IsApproxVec(camera.K.block<2, 1>(0, 2), 1e-9));
    REQUIRE_THAT(*camera.Project(room_centre), IsApproxVec(camera.K.block<2, 1>(0, 2), 1e-9));
    // Every corner of the 3 x 3 x 2 m capture volume is visible in every camera.
    for (const double x : {-1.5, 1.5}) {
      for (const double y : {-1.5, 1.5}) {
        for (const double z : {0.0, 2.0}) {
          const std::optional<Vec2> px = camera.Project(Vec3(x, y, z));
          REQUIRE(px.has_value());
          REQUIRE(camera.InImage(*px));
        }
      }
    }
  }

  std::mt19937 rng(401);
  std::uniform_real_distribution<double> xy(-1.5, 1.5), z(0.0, 2.0);
  double max_raw_epipolar_px = 0.0;
  for (int k = 0; k < 100; ++k) {
    const Vec3 point(xy(rng), xy(rng), z(rng));
    INFO("point " << point.transpose());
    const std::vector<Vec2> raw = RawDetections(rig, point);
    std::vector<Vec2> undistorted;
    for (int i = 0; i < rig.size(); ++i) {
      undistorted.push_back(rig.camera(i).UndistortPixel(raw[static_cast<std::size_t>(i)]));
    }
    // Epipolar consistency holds for undistorted pixels, not for raw ones.
    for (int i = 0; i < rig.size(); ++i) {
      for (int j = i + 1; j < rig.size(); ++j) {
        const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
        REQUIRE(SymmetricEpipolarDistance(undistorted[ui], undistorted[uj], rig.fundamental(i, j)) <
                1e-5);
        max_raw_epipolar_px =
            std::max(max_raw_epipolar_px,
                     SymmetricEpipolarDistance(raw[ui], raw[uj], rig.fundamental(i, j)));
      }
    }
    // All four views, and every pair, triangulate the point.
    const std::optional<Vec3> estimate = TriangulateDlt(RigProjections(rig), undistorted);
    REQUIRE(estimate.has_value());
    REQUIRE_THAT(*estimate, IsApproxVec(point, 1e-6));
    for (int i = 0; i < rig.size(); ++i) {
      REQUIRE(InFront(rig.projection(i), *estimate));
      REQUIRE(ReprojectionErrorPx(
                  rig.projection(i), *estimate, undistorted[static_cast<std::size_t>(i)]) < 1e-5);
      for (int j = i + 1; j < rig.size(); ++j) {
        const std::optional<Vec3> pair_estimate =
            TriangulateTwoView(rig.projection(i),
                               undistorted[static_cast<std::size_t>(i)],
                               rig.projection(j),
                               undistorted[static_cast<std::size_t>(j)]);
        REQUIRE(pair_estimate.has_value());
        REQUIRE_THAT(*pair_estimate, IsApproxVec(point, 1e-6));
      }
    }
  }
  // Lens distortion of this magnitude is far from negligible: ignoring it costs tens of pixels.
  REQUIRE(max_raw_epipolar_px > 10.0);
}

TEST_CASE("Realistic 4-camera ring rig: Eq. 2 separates two people in every camera pair",
          "[unit]") {
  const CameraRig rig(RingCamerasOutOfOrder());
  REQUIRE(rig.ok());
  // Two people 2 m apart; their torso centres at 1 m and a 1.7 m x 0.6 m bounding box each.
  const Vec3 torso_a(0.8, 0.6, 1.0);
  const Vec3 torso_b(-0.9, -0.5, 1.0);
  auto scale_px = [](const CameraModel& camera, const Vec3& torso) {
    const double fx = camera.K(0, 0);
    return fx * (0.6 + 1.7) / camera.Depth(torso);  // |w + h| of the person's box
  };
  std::mt19937 rng(402);
  std::normal_distribution<double> detector_noise(0.0, 2.0);
  for (int i = 0; i < rig.size(); ++i) {
    for (int j = 0; j < rig.size(); ++j) {
      if (i == j) continue;
      INFO("cameras " << rig.camera(i).id << " and " << rig.camera(j).id);
      const CameraModel& ci = rig.camera(i);
      const CameraModel& cj = rig.camera(j);
      const Mat3& f = rig.fundamental(i, j);
      // Detections: raw pixels with 2 px detector noise, undistorted before use.
      auto detect = [&](const CameraModel& camera, const Vec3& torso) {
        const Vec2 raw = *camera.Project(torso) + Vec2(detector_noise(rng), detector_noise(rng));
        return camera.UndistortPixel(raw);
      };
      const Vec2 a_i = detect(ci, torso_a), a_j = detect(cj, torso_a);
      const Vec2 b_j = detect(cj, torso_b);
      const double same =
          NormalizedEpipolarDistance(a_i, scale_px(ci, torso_a), a_j, scale_px(cj, torso_a), f);
      const double different =
          NormalizedEpipolarDistance(a_i, scale_px(ci, torso_a), b_j, scale_px(cj, torso_b), f);
      INFO("same person " << same << ", different people " << different);
      // 2 px of noise on boxes of ~700 px gives ~0.006 for the same person (measured at most
      // 0.016 over the 12 ordered pairs); the other person, 2 m away, gives 0.18 to 1.4, so a
      // threshold between 0.05 and 0.1 separates them in every pair.
      REQUIRE(same < 0.05);
      REQUIRE(different > 0.1);
    }
  }
}

TEST_CASE("ViewOnPlane: a camera looking straight down sees a square of the floor", "[unit]") {
  // 3 m above the origin, 90 degree field of view both ways (fx = 500 px on 1000 x 1000): the
  // floor seen is the 6 x 6 m square; at 1 m height, 4 x 4 m; nothing beyond the range.
  const CameraModel down =
      testing::LookAtCamera(1, Vec3(0.0, 0.0, 3.0), Vec3(0.0, 0.001, 0.0), 500.0, 1000, 1000);
  const std::vector<HalfPlane> floor = ViewOnPlane(down, 0.0, 60.0, 0.0);
  CHECK(IntersectionArea(floor, floor, 0.0, 0.0, 100.0) == Approx(36.0).epsilon(0.01));
  const std::vector<HalfPlane> chest = ViewOnPlane(down, 1.0, 60.0, 0.0);
  CHECK(IntersectionArea(chest, chest, 0.0, 0.0, 100.0) == Approx(16.0).epsilon(0.01));
  CHECK(IntersectionArea(floor, chest, 0.0, 0.0, 100.0) == Approx(16.0).epsilon(0.01));
  // The plane of the camera itself and above it: not seen (in front of it means below).
  CHECK(IntersectionArea(
            ViewOnPlane(down, 3.5, 60.0), ViewOnPlane(down, 3.5, 60.0), 0.0, 0.0, 100.0) == 0.0);
  // A range shorter than the height: nothing of the floor.
  CHECK(IntersectionArea(ViewOnPlane(down, 0.0, 2.0), floor, 0.0, 0.0, 100.0) == 0.0);
}

TEST_CASE("ComputeSharedViews: cameras far apart along a corridor never see one place", "[unit]") {
  // Wall cameras every 5 m along a 60 m corridor, looking across and 43 degrees down (the top
  // of the image 14 degrees below the horizon): neighbours share floor, cameras 30 m apart do
  // not.
  std::vector<CameraModel> cameras;
  for (int i = 0; i < 12; ++i) {
    const double x = 5.0 * i;
    const double y = i % 2 == 0 ? 0.0 : 6.0;
    cameras.push_back(
        testing::LookAtCamera(i, Vec3(x, y, 3.0), Vec3(x + 1.0, 3.0, 0.0), 640.0, 1280, 720));
  }
  CameraRig rig(cameras);
  REQUIRE(rig.ok());
  CHECK(rig.SharesView(0, 11));  // not computed yet: every pair
  CHECK(rig.num_sharing_pairs() == 66);
  rig.ComputeSharedViews(0.0);
  CHECK(rig.SharesView(0, 1));
  CHECK(rig.SharesView(3, 3));
  CHECK_FALSE(rig.SharesView(0, 6));
  CHECK_FALSE(rig.SharesView(11, 0));
  CHECK(rig.SharesView(5, 0) == rig.SharesView(0, 5));
  CHECK(rig.num_sharing_pairs() < 40);
  // A ring around one room: every pair sees the room.
  CameraRig ring(RingCamerasOutOfOrder());
  ring.ComputeSharedViews(0.0);
  CHECK(ring.num_sharing_pairs() == 6);
}

}  // namespace
}  // namespace mvtrack::geometry
