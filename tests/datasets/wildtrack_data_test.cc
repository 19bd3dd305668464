// WILDTRACK on the real data (../shared/data/wildtrack or $MVTRACK_DATA/wildtrack); the test
// cases skip with a warning when the dataset is missing, and fail instead when CI is set.

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "data_test_util.h"

namespace mvtrack::datasets {
namespace {

// Intersection of the viewing ray of raw pixel `px` with the ground plane z = 0.
Vec3 RayOnGround(const geometry::CameraModel& camera, const Vec2& px) {
  const Vec2 u = camera.UndistortPixel(px);
  const Vec3 ray_cam = camera.K.inverse() * Vec3(u.x(), u.y(), 1.0);
  const Mat3 world_from_cam = camera.cam_from_world.rotation.transpose();
  const Vec3 direction = world_from_cam * ray_cam;
  const Vec3 centre = camera.CenterInWorld();
  return centre - (centre.z() / direction.z()) * direction;
}

TEST_CASE("WILDTRACK real data (skipped without ../shared/data/wildtrack): sizes", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "wildtrack");
  const Dataset ds = LoadWildtrack(root);
  CHECK(ds.name == "wildtrack");
  CHECK(ds.fps == 2.0);
  REQUIRE(ds.cameras.size() == 7);
  for (std::size_t c = 0; c < 7; ++c) {
    CHECK(ds.cameras[c].id == static_cast<CameraId>(c));
    CHECK(ds.cameras[c].width_px == 1920);
    CHECK(ds.cameras[c].height_px == 1080);
    CHECK(ds.cameras[c].distortion.IsZero());
    // SOURCE.md: camera centres 1.7-3.4 m above the ground.
    CHECK(ds.cameras[c].CenterInWorld().z() > 1.5);
    CHECK(ds.cameras[c].CenterInWorld().z() < 3.6);
  }
  REQUIRE(ds.detections.size() == 40);
  CHECK(ds.detections.front()[0].frame == 360);
  CHECK(ds.detections.back()[6].frame == 399);
  CHECK(ds.detections[1][3].utime == 180'500'000);
  std::size_t boxes = 0;
  for (std::size_t f = 0; f < ds.detections.size(); ++f) {
    for (std::size_t c = 0; c < 7; ++c) {
      REQUIRE(ds.source_ids[f][c].size() == ds.detections[f][c].detections.size());
      for (const core::Detection2D& d : ds.detections[f][c].detections) {
        ++boxes;
        CHECK(d.keypoints.empty());
        CHECK(d.layout == core::KeypointLayoutId::kNone);
        CHECK(d.score == 1.0);
        CHECK(d.box.height() > 0.0);
      }
    }
  }
  CHECK(boxes == 5155);
  // Ground truth of the detection frames from mvdet/gt.txt (SOURCE.md: 952 positions in frames
  // 360-399, 23.8 per frame).
  REQUIRE(ds.ground_truth.size() == 40);
  std::size_t positions = 0;
  for (std::size_t f = 0; f < ds.ground_truth.size(); ++f) {
    CHECK(ds.ground_truth[f].frame == 360 + static_cast<FrameIndex>(f));
    for (std::size_t i = 0; i < ds.ground_truth[f].objects.size(); ++i) {
      const eval::EvalObject& o = ds.ground_truth[f].objects[i];
      CHECK(o.id == static_cast<std::int64_t>(i));
      CHECK(o.joints.empty());
      CHECK(o.position.z() == 0.0);
      CHECK(o.position.x() >= WildtrackArea::kMinX);
      CHECK(o.position.x() < WildtrackArea::kMaxX);
      CHECK(o.position.y() >= WildtrackArea::kMinY);
      CHECK(o.position.y() < WildtrackArea::kMaxY);
    }
    positions += ds.ground_truth[f].objects.size();
  }
  CHECK(positions == 952);
  CHECK(ds.gt_layout == core::KeypointLayoutId::kNone);
}

TEST_CASE(
    "WILDTRACK real data (skipped without ../shared/data/wildtrack): ground truth of any "
    "annotated frames",
    "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "wildtrack");
  // All 400 annotated frames (image frames 0, 5, ..., 1995), positions on the 2.5 cm grid.
  const eval::EvalSequence all = WildtrackGroundTruth(root, 0, 399);
  REQUIRE(all.size() == 400);
  std::size_t positions = 0;
  for (const eval::EvalFrame& f : all) {
    positions += f.objects.size();
    for (const eval::EvalObject& o : f.objects) {
      const double gx = (o.position.x() - WildtrackArea::kMinX) / 0.025;
      CHECK(std::abs(gx - std::round(gx)) < 1e-9);
    }
  }
  CHECK(positions > 8000);  // about 20 people per frame
  const eval::EvalSequence one = WildtrackGroundTruth(root, 360, 360);
  REQUIRE(one.size() == 1);
  CHECK(one[0].objects.size() == all[360].objects.size());
  CHECK_THROWS_AS(WildtrackGroundTruth(root, 350, 400), DatasetError);
  CHECK_THROWS_AS(WildtrackGroundTruth(root, 10, 5), DatasetError);
}

TEST_CASE(
    "WILDTRACK real data (skipped without ../shared/data/wildtrack): calibration agrees "
    "with the homographies",
    "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "wildtrack");
  const Dataset ds = LoadWildtrack(root);
  const std::vector<Mat3> homographies = WildtrackHomographies(root);
  REQUIRE(homographies.size() == 7);
  double worst_m = 0.0;
  for (std::size_t c = 0; c < 7; ++c) {
    const geometry::CameraModel& camera = ds.cameras[c];
    // K [r1 r2 t] in cm equals H up to scale (SOURCE.md: < 1e-5 after normalisation).
    Mat3 from_calibration;
    from_calibration.col(0) = camera.K * camera.cam_from_world.rotation.col(0);
    from_calibration.col(1) = camera.K * camera.cam_from_world.rotation.col(1);
    from_calibration.col(2) = camera.K * (100.0 * camera.cam_from_world.translation);
    const Mat3 a = from_calibration / from_calibration(2, 2);
    const Mat3 b = homographies[c] / homographies[c](2, 2);
    CHECK((a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff() < 1e-5);
    // Box bottom centres mapped to the ground by H^-1 and by the calibrated ray agree.
    for (const core::Detection2D& d : ds.detections[0][c].detections) {
      const Vec2 foot = d.box.bottom_center();
      const Vec3 g = homographies[c].inverse() * Vec3(foot.x(), foot.y(), 1.0);
      const Vec2 by_h = 0.01 * g.head<2>() / g.z();
      const Vec3 by_ray = RayOnGround(camera, foot);
      worst_m = std::max(worst_m, (by_ray.head<2>() - by_h).norm());
    }
  }
  INFO("largest homography-vs-calibration ground point difference, frame 360: " << worst_m << " m");
  CHECK(worst_m < 0.01);
}

TEST_CASE("WILDTRACK real data (skipped without ../shared/data/wildtrack): MVDeTr ground points",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "wildtrack");
  const Dataset ds = LoadWildtrack(root);
  const std::vector<Mat3> homographies = WildtrackHomographies(root);
  const std::vector<WildtrackGroundFrame> ground = WildtrackGroundPoints(root);
  REQUIRE(ground.size() == 40);
  std::size_t points = 0;
  int multi_view = 0;
  int boxes = 0, near = 0;
  for (std::size_t f = 0; f < ground.size(); ++f) {
    CHECK(ground[f].frame == 360 + static_cast<FrameIndex>(f));
    int views = 0;
    for (std::size_t i = 0; i < ground[f].points.size(); ++i) {
      const WildtrackGroundPoint& p = ground[f].points[i];
      views += p.num_views;
      CHECK(p.position_m.z() == 0.0);
      CHECK(p.num_views >= 1);
      CHECK(p.num_views <= 7);
      if (p.num_views >= 2) ++multi_view;
      if (i > 0) CHECK(ground[f].points[i - 1].position_m.x() <= p.position_m.x());
    }
    // Every box contributes to exactly one ground point.
    std::size_t frame_boxes = 0;
    for (std::size_t c = 0; c < 7; ++c) frame_boxes += ds.detections[f][c].detections.size();
    CHECK(static_cast<std::size_t>(views) == frame_boxes);
    points += ground[f].points.size();
    // Each box's own ground point lies near one of the merged points.
    for (std::size_t c = 0; c < 7; ++c) {
      for (const core::Detection2D& d : ds.detections[f][c].detections) {
        const Vec2 foot = d.box.bottom_center();
        const Vec3 g = homographies[c].inverse() * Vec3(foot.x(), foot.y(), 1.0);
        const Vec2 q = 0.01 * g.head<2>() / g.z();
        double best = 1e9;
        for (const WildtrackGroundPoint& p : ground[f].points) {
          best = std::min(best, (p.position_m.head<2>() - q).norm());
        }
        ++boxes;
        if (best <= 0.3) ++near;
      }
    }
  }
  const double per_frame = static_cast<double>(points) / 40.0;
  const double multi = static_cast<double>(multi_view) / static_cast<double>(points);
  INFO("ground points per frame " << per_frame << ", seen in >= 2 views " << multi
                                  << ", boxes within 0.3 m of their point "
                                  << static_cast<double>(near) / boxes);
  // SOURCE.md: about 20 people per frame; views agree within a few cm.
  CHECK(per_frame > 18.0);
  CHECK(per_frame < 32.0);
  CHECK(multi > 0.85);
  CHECK(static_cast<double>(near) / boxes > 0.99);
}

}  // namespace
}  // namespace mvtrack::datasets
