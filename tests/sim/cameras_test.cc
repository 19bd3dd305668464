// Camera rigs: the look-at construction, the ring (every camera sees the room centre) and the
// ceiling grid (every camera above the room, pitched down, the floor covered).

#include "sim/cameras.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::sim {
namespace {

TEST_CASE("MakeCamera looks along the requested direction with a level image", "[unit][sim]") {
  const Vec3 centre(1.0, 2.0, 3.0);
  const Vec3 forward(2.0, -1.0, -0.7);
  const geometry::CameraModel cam = MakeCamera(4, 640, 480, 90.0, centre, forward);
  std::string why;
  REQUIRE(cam.Validate(&why));
  CHECK(cam.id == 4);
  CHECK((cam.CenterInWorld() - centre).norm() < 1e-12);
  // 90 deg horizontal field of view: fx = (640 / 2) / tan(45 deg).
  CHECK(cam.K(0, 0) == Approx(320.0));
  CHECK(cam.K(1, 1) == Approx(320.0));
  // A point on the optical axis projects to the principal point (image centre).
  const auto on_axis = cam.Project(centre + 5.0 * forward);
  REQUIRE(on_axis);
  CHECK((*on_axis - Vec2(320.0, 240.0)).norm() < 1e-9);
  // No roll: a point straight above the axis point appears higher (smaller y) in the same
  // column.
  const auto above = cam.Project(centre + 5.0 * forward + Vec3(0.0, 0.0, 0.5));
  REQUIRE(above);
  CHECK(above->y() < on_axis->y());
  CHECK(std::abs(above->x() - on_axis->x()) < 1e-9);
  // The world point to the right of the camera (forward x up) appears right of the centre.
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();
  const auto right_px = cam.Project(centre + 5.0 * forward + 0.5 * right);
  REQUIRE(right_px);
  CHECK(right_px->x() > on_axis->x());

  // Straight down is allowed (image x = world +x).
  const geometry::CameraModel down = MakeCamera(0, 640, 480, 90.0, centre, Vec3(0, 0, -1));
  REQUIRE(down.Validate(&why));
  const auto below = down.Project(centre + Vec3(0.0, 0.0, -2.0));
  const auto east = down.Project(centre + Vec3(0.5, 0.0, -2.0));
  REQUIRE(below);
  REQUIRE(east);
  CHECK((*below - Vec2(320.0, 240.0)).norm() < 1e-9);
  CHECK(east->x() > below->x());
}

TEST_CASE("ring cameras all see the room centre", "[unit][sim]") {
  const std::vector<std::pair<double, double>> rooms = {{6.0, 6.0}, {10.0, 4.0}, {3.0, 8.0}};
  for (const auto& [w, d] : rooms) {
    for (const int n : {1, 2, 3, 4, 6, 8, 12, 16}) {
      SceneOptions o;
      o.room_width_m = w;
      o.room_depth_m = d;
      o.num_cameras = n;
      o.num_people = 1;
      const std::vector<geometry::CameraModel> cams = MakeCameras(o);
      REQUIRE(cams.size() == static_cast<std::size_t>(n));
      std::set<std::pair<long, long>> positions;
      for (std::size_t i = 0; i < cams.size(); ++i) {
        const geometry::CameraModel& cam = cams[i];
        INFO("room " << w << " x " << d << ", " << n << " cameras, camera " << i);
        std::string why;
        REQUIRE(cam.Validate(&why));
        CHECK(cam.id == static_cast<CameraId>(i));
        CHECK(cam.distortion.IsZero());
        const Vec3 c = cam.CenterInWorld();
        CHECK(c.z() == Approx(o.camera_height_m));
        // On the ellipse through the room corners.
        const double ex = (c.x() - 0.5 * w) / (w / std::numbers::sqrt2);
        const double ey = (c.y() - 0.5 * d) / (d / std::numbers::sqrt2);
        CHECK(ex * ex + ey * ey == Approx(1.0));
        positions.insert({std::lround(c.x() * 1000), std::lround(c.y() * 1000)});
        // The look-at point is the image centre; the centre of the floor and a person's head
        // above it are in the image.
        const auto target = cam.Project(Vec3(0.5 * w, 0.5 * d, o.look_at_height_m));
        REQUIRE(target);
        CHECK((*target - Vec2(0.5 * o.image_width_px, 0.5 * o.image_height_px)).norm() < 1e-6);
        for (const double z : {0.0, 1.0, 1.9}) {
          const auto px = cam.Project(Vec3(0.5 * w, 0.5 * d, z));
          REQUIRE(px);
          CHECK(cam.InImage(*px));
        }
      }
      CHECK(positions.size() == cams.size());  // distinct mounting points
    }
  }
}

TEST_CASE("ceiling grid cameras are above the room, pitched down, and cover the floor",
          "[unit][sim]") {
  for (const int n : {1, 2, 5, 9, 32}) {
    SceneOptions o;
    o.camera_layout = CameraLayout::kCeilingGrid;
    o.num_cameras = n;
    o.room_width_m = 16.0;
    o.room_depth_m = 16.0;
    o.camera_height_m = 3.5;
    o.num_people = 1;
    const std::vector<geometry::CameraModel> cams = MakeCameras(o);
    REQUIRE(cams.size() == static_cast<std::size_t>(n));
    const double expected_forward_z = -std::sin(o.grid_pitch_deg * std::numbers::pi / 180.0);
    for (std::size_t i = 0; i < cams.size(); ++i) {
      INFO(n << " cameras, camera " << i);
      std::string why;
      REQUIRE(cams[i].Validate(&why));
      CHECK(cams[i].id == static_cast<CameraId>(i));
      const Vec3 c = cams[i].CenterInWorld();
      CHECK(c.z() == Approx(o.camera_height_m));
      CHECK((c.x() > 0.0 && c.x() < o.room_width_m && c.y() > 0.0 && c.y() < o.room_depth_m));
      const Vec3 forward = cams[i].cam_from_world.rotation.row(2).transpose();
      CHECK(forward.z() == Approx(expected_forward_z));
      // The optical axis hits the floor inside the room (border cameras look inwards).
      const Vec3 hit = c + forward * (c.z() / -forward.z());
      CHECK(
          (hit.x() > 0.0 && hit.x() < o.room_width_m && hit.y() > 0.0 && hit.y() < o.room_depth_m));
    }
    if (n != 32) continue;
    // 32 cameras over 16 x 16 m: every point at chest height (1.2 m) of the walkable area is in
    // an image, and almost all (all but a few near two corners) in at least two.
    int points = 0, covered_once = 0, covered_twice = 0;
    for (double x = 0.5; x <= 15.5 + 1e-9; x += 0.5) {
      for (double y = 0.5; y <= 15.5 + 1e-9; y += 0.5) {
        int views = 0;
        for (const auto& cam : cams) {
          const auto px = cam.Project(Vec3(x, y, 1.2));
          if (px && cam.InImage(*px)) ++views;
        }
        ++points;
        if (views >= 1) ++covered_once;
        if (views >= 2) ++covered_twice;
      }
    }
    CHECK(covered_once == points);
    CHECK(covered_twice >= 0.97 * points);
  }
}

TEST_CASE("corridor cameras are on the long walls and see local floor from both walls",
          "[unit][sim]") {
  SceneOptions o;
  o.camera_layout = CameraLayout::kCorridor;
  o.num_cameras = 32;
  o.room_width_m = 48.0;
  o.room_depth_m = 6.0;
  o.camera_height_m = 3.0;
  o.image_width_px = 1280;
  o.image_height_px = 720;
  o.horizontal_fov_deg = 80.0;
  o.num_people = 1;
  o.grid_pitch_deg = 35.0;  // mvtrack sim --layout corridor's
  const std::vector<geometry::CameraModel> cams = MakeCameras(o);
  REQUIRE(cams.size() == 32);
  for (std::size_t i = 0; i < cams.size(); ++i) {
    INFO("camera " << i);
    std::string why;
    REQUIRE(cams[i].Validate(&why));
    const Vec3 c = cams[i].CenterInWorld();
    CHECK(c.z() == Approx(3.0));
    CHECK(c.x() == Approx(48.0 * (static_cast<double>(i) + 0.5) / 32.0));
    CHECK(c.y() == Approx(i % 2 == 0 ? 0.0 : 6.0).margin(1e-9));  // alternating walls
    const Vec3 forward = cams[i].cam_from_world.rotation.row(2).transpose();
    CHECK(forward.z() == Approx(-std::sin(o.grid_pitch_deg * std::numbers::pi / 180.0)));
    CHECK((i % 2 == 0 ? forward.y() > 0.0 : forward.y() < 0.0));  // across the corridor
  }
  // Every point at chest height of the walkable corridor (but its two far corners) is seen by
  // at least two cameras, and away from the walls (1 m) and the ends (2 m) by cameras of both
  // walls; no camera sees chest height farther than 15 m along the corridor.
  for (double x = 0.5; x <= 47.5 + 1e-9; x += 0.5) {
    for (double y = 0.5; y <= 5.5 + 1e-9; y += 0.5) {
      int wall0 = 0, wall1 = 0;
      for (const auto& cam : cams) {
        const auto px = cam.Project(Vec3(x, y, 1.2));
        if (!px || !cam.InImage(*px)) continue;
        const Vec3 c = cam.CenterInWorld();
        CHECK(std::abs(c.x() - x) < 15.0);
        (c.y() < 1.0 ? wall0 : wall1) += 1;
      }
      INFO("at " << x << ", " << y);
      if (x >= 1.0 && x <= 47.0) CHECK(wall0 + wall1 >= 2);
      if (y >= 1.0 && y <= 5.0 && x >= 2.0 && x <= 46.0) {
        CHECK(wall0 >= 1);
        CHECK(wall1 >= 1);
      }
    }
  }
}

}  // namespace
}  // namespace mvtrack::sim
