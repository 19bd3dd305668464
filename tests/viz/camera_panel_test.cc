#include "viz/camera_panel.h"

#include <catch2/catch.hpp>

#include "support/synthetic_cameras.h"
#include "viz/colors.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

// A camera 5 m from the origin on -y, 1.5 m high, looking at (0, 0, 1).
geometry::CameraModel TestCamera() {
  return mvtrack::testing::LookAtCamera(
      3, Vec3(0.0, -5.0, 1.5), Vec3(0.0, 0.0, 1.0), 800.0, 1000, 800);
}

cv::Point Expected(const geometry::CameraModel& camera, const Vec3& p, double scale) {
  const Vec2 px = *camera.Project(p);
  return {static_cast<int>(std::lround(px.x() * scale)),
          static_cast<int>(std::lround(px.y() * scale))};
}

TEST_CASE("A pose track is reprojected at the calibrated pixel in its colour", "[unit]") {
  const geometry::CameraModel camera = TestCamera();
  tracker::Frame3D frame;
  tracker::Track3D t;
  t.id = 5;
  const core::KeypointLayout& layout = core::GetKeypointLayout(core::KeypointLayoutId::kCoco17);
  t.joints.assign(static_cast<std::size_t>(layout.num_joints()), std::nullopt);
  const Vec3 left_shoulder(-0.2, 0.0, 1.4);
  const Vec3 left_hip(-0.15, 0.0, 0.9);
  const int ls = 5, lh = 11;  // COCO-17 left_shoulder, left_hip
  REQUIRE(layout.joints[ls] == "l_shoulder");
  REQUIRE(layout.joints[lh] == "l_hip");
  t.joints[ls] = left_shoulder;
  t.joints[lh] = left_hip;
  frame.tracks.push_back(t);
  CameraPanelOptions options;
  options.scale = 0.5;
  const cv::Mat half =
      RenderCameraPanel(camera, {}, frame, core::KeypointLayoutId::kCoco17, options);
  REQUIRE(half.cols == 500);
  REQUIRE(half.rows == 400);
  CHECK(ColorDistance(PixelAt(half, Expected(camera, left_shoulder, 0.5)), TrackColor(5)) == 0.0);
  options.scale = 1.0;
  const cv::Mat panel =
      RenderCameraPanel(camera, {}, frame, core::KeypointLayoutId::kCoco17, options);
  const cv::Point a = Expected(camera, left_shoulder, 1.0);
  const cv::Point b = Expected(camera, left_hip, 1.0);
  CHECK(ColorDistance(PixelAt(panel, a), TrackColor(5)) == 0.0);
  CHECK(ColorDistance(PixelAt(panel, b), TrackColor(5)) == 0.0);
  // Is there a bone between them? (they are a COCO bone only if the layout says so)
  bool bone = false;
  for (const auto& [i, j] : layout.bones) bone |= (i == ls && j == lh) || (i == lh && j == ls);
  REQUIRE(bone);
  CHECK(ColorDistance(PixelAt(panel, (a + b) / 2), TrackColor(5)) == 0.0);
  // Far from the person: background.
  CHECK(ColorDistance(PixelAt(panel, cv::Point(960, 760)), kBackground) == 0.0);
}

TEST_CASE("A footprint track is drawn as a standing person's box and centre line", "[unit]") {
  const geometry::CameraModel camera = TestCamera();
  tracker::Frame3D frame;
  tracker::Track3D t;
  t.id = 12;
  t.position = Vec3(0.5, 0.0, 0.0);
  frame.tracks.push_back(t);
  CameraPanelOptions options;
  options.scale = 1.0;
  const cv::Mat panel =
      RenderCameraPanel(camera, {}, frame, core::KeypointLayoutId::kNone, options);
  const cv::Point foot = Expected(camera, t.position, 1.0);
  const cv::Point head = Expected(camera, t.position + Vec3(0, 0, 1.8), 1.0);
  const cv::Point middle = (foot + head) / 2;
  CHECK(ColorDistance(PixelAt(panel, foot), TrackColor(12)) == 0.0);
  CHECK(ColorDistance(PixelAt(panel, middle), TrackColor(12)) == 0.0);
  // The box's left edge: the leftmost projected corner, at mid height.
  int left = panel.cols;
  for (double dx : {-0.25, 0.25}) {
    for (double dy : {-0.25, 0.25}) {
      for (double z : {0.0, 1.8})
        left = std::min(left, Expected(camera, t.position + Vec3(dx, dy, z), 1.0).x);
    }
  }
  CHECK(ColorDistance(PixelAt(panel, cv::Point(left + 1, middle.y)), TrackColor(12)) == 0.0);
  // Between the left edge and the centre line: background.
  CHECK(ColorDistance(PixelAt(panel, cv::Point((left + middle.x) / 2, middle.y)), kBackground) ==
        0.0);
}

TEST_CASE("Detections are drawn under the tracks, tracks behind the camera are not drawn",
          "[unit]") {
  const geometry::CameraModel camera = TestCamera();
  core::Detection2D d;
  d.box = core::BoxPx{100.0, 200.0, 300.0, 600.0};
  tracker::Frame3D frame;
  tracker::Track3D behind;
  behind.id = 1;
  behind.position = Vec3(0.0, -8.0, 0.0);  // 3 m behind the camera
  frame.tracks.push_back(behind);
  CameraPanelOptions options;
  options.scale = 1.0;
  options.title = " ";
  const cv::Mat panel =
      RenderCameraPanel(camera, {d}, frame, core::KeypointLayoutId::kNone, options);
  CHECK(ColorDistance(PixelAt(panel, cv::Point(200, 200)), kDetectionColor) == 0.0);
  CHECK(ColorDistance(PixelAt(panel, cv::Point(100, 400)), kDetectionColor) == 0.0);
  // Nothing but the detection box was drawn: every other pixel is background.
  cv::Mat mask;
  cv::inRange(panel, kBackground, kBackground, mask);
  const int non_background = panel.rows * panel.cols - cv::countNonZero(mask);
  const int box_perimeter = 2 * (200 + 1) + 2 * (400 - 1);
  CHECK(non_background == box_perimeter);
}

}  // namespace
}  // namespace mvtrack::viz
