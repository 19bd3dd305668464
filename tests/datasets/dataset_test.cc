#include "datasets/dataset.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "datasets/panoptic.h"

namespace mvtrack::datasets {
namespace {

core::Keypoint2D Kp(double x, double y, double confidence) {
  core::Keypoint2D kp;
  kp.position_px = Vec2(x, y);
  kp.confidence = confidence;
  return kp;
}

TEST_CASE("BoxFromKeypoints pads the detected keypoints' bounds by 10% of their height", "[unit]") {
  // Detected: x in [100, 140], y in [50, 250] (height 200); the confidence-0 point at (0, 0)
  // must be ignored.
  const std::vector<core::Keypoint2D> kps = {
      Kp(120, 50, 0.9), Kp(100, 150, 0.5), Kp(0, 0, 0.0), Kp(140, 250, 0.7)};
  const std::optional<core::BoxPx> box = BoxFromKeypoints(kps);
  REQUIRE(box.has_value());
  CHECK(box->x_min == Approx(100 - 20));
  CHECK(box->x_max == Approx(140 + 20));
  CHECK(box->y_min == Approx(50 - 20));
  CHECK(box->y_max == Approx(250 + 20));
  // The centre is the centre of the keypoint bounds.
  CHECK(box->center().x() == Approx(120));
  CHECK(box->center().y() == Approx(150));
}

TEST_CASE("BoxFromKeypoints needs two detected keypoints and pads flat poses by 1 px", "[unit]") {
  CHECK_FALSE(BoxFromKeypoints({}).has_value());
  CHECK_FALSE(BoxFromKeypoints({Kp(10, 10, 1.0), Kp(20, 20, 0.0)}).has_value());
  const std::optional<core::BoxPx> flat = BoxFromKeypoints({Kp(10, 30, 1.0), Kp(50, 30, 1.0)});
  REQUIRE(flat.has_value());
  CHECK(flat->y_min == Approx(29.0));
  CHECK(flat->y_max == Approx(31.0));
  CHECK(flat->x_min == Approx(9.0));
  CHECK(flat->x_max == Approx(51.0));
}

TEST_CASE("MeanKeypointScore averages the detected keypoints only", "[unit]") {
  CHECK(MeanKeypointScore({Kp(0, 0, 0.5), Kp(0, 0, 0.0), Kp(0, 0, 1.0)}) == Approx(0.75));
  CHECK(MeanKeypointScore({Kp(0, 0, 0.0)}) == 0.0);
}

TEST_CASE("FootprintFromJoints drops the hip midpoint onto z = 0, else the centroid", "[unit]") {
  // shelf14: r_hip = 2, l_hip = 3.
  std::vector<std::optional<Vec3>> joints(14);
  joints[2] = Vec3(1.0, 2.0, 0.9);
  joints[3] = Vec3(1.4, 2.2, 0.8);
  joints[13] = Vec3(5.0, 5.0, 1.7);
  std::optional<Vec3> f = FootprintFromJoints(joints, core::KeypointLayoutId::kShelf14);
  REQUIRE(f.has_value());
  CHECK(f->x() == Approx(1.2));
  CHECK(f->y() == Approx(2.1));
  CHECK(f->z() == 0.0);

  // panoptic19: l_hip = 6, r_hip = 12 (the layout's names decide, not fixed indices).
  std::vector<std::optional<Vec3>> pan(19);
  pan[6] = Vec3(0.0, 0.0, 1.0);
  pan[12] = Vec3(2.0, 4.0, 1.0);
  pan[2] = Vec3(9.0, 9.0, 9.0);
  f = FootprintFromJoints(pan, core::KeypointLayoutId::kPanoptic19);
  REQUIRE(f.has_value());
  CHECK(f->x() == Approx(1.0));
  CHECK(f->y() == Approx(2.0));

  // One hip missing: centroid of the present joints.
  joints[3].reset();
  f = FootprintFromJoints(joints, core::KeypointLayoutId::kShelf14);
  REQUIRE(f.has_value());
  CHECK(f->x() == Approx(3.0));
  CHECK(f->y() == Approx(3.5));
  CHECK(f->z() == 0.0);

  CHECK_FALSE(
      FootprintFromJoints(std::vector<std::optional<Vec3>>(14), core::KeypointLayoutId::kShelf14)
          .has_value());
}

TEST_CASE("FrameUtime is frame / fps in microseconds", "[unit]") {
  CHECK(FrameUtime(0, 25.0) == 0);
  CHECK(FrameUtime(300, 25.0) == 12'000'000);
  CHECK(FrameUtime(1, 29.97) == 33'367);  // 33366.7 us rounded
  CHECK(FrameUtime(399, 2.0) == 199'500'000);
}

TEST_CASE("DefaultDataRoot honours MVTRACK_DATA", "[unit]") {
  const char* old = std::getenv("MVTRACK_DATA");
  const std::optional<std::string> saved =
      old != nullptr ? std::optional<std::string>(old) : std::nullopt;
  setenv("MVTRACK_DATA", "/some/where/data", 1);
  CHECK(DefaultDataRoot() == std::filesystem::path("/some/where/data"));
  unsetenv("MVTRACK_DATA");
  const std::filesystem::path fallback = DefaultDataRoot();
  CHECK(fallback.filename() == "data");
  CHECK(fallback.parent_path().filename() == "shared");
  if (saved.has_value()) setenv("MVTRACK_DATA", saved->c_str(), 1);
}

TEST_CASE("DatasetError names the file and the problem", "[unit]") {
  const DatasetError e("/x/calibration.json", "3:4: $.K: expected a number");
  CHECK(e.file() == "/x/calibration.json");
  CHECK(e.problem() == "3:4: $.K: expected a number");
  CHECK(std::string(e.what()) == "/x/calibration.json: 3:4: $.K: expected a number");
}

TEST_CASE("PanopticToWorldRotation turns Panoptic's y-down world into z up", "[unit]") {
  const Mat3 r = PanopticToWorldRotation();
  CHECK((r.transpose() * r - Mat3::Identity()).norm() < 1e-15);
  CHECK(r.determinant() == Approx(1.0));
  // Panoptic "up" is -y.
  CHECK((r * Vec3(0, -1, 0) - Vec3(0, 0, 1)).norm() < 1e-15);
  CHECK((r * Vec3(1, 0, 0) - Vec3(1, 0, 0)).norm() < 1e-15);
}

TEST_CASE("PanopticOptions validation", "[unit]") {
  PanopticOptions options;
  std::string why;
  CHECK(options.Validate(&why));
  CHECK(options.corruption.pixel_noise_px == 6.0);
  options.cameras = {"00_03", "12", "0"};
  CHECK(options.Validate(&why));
  options.cameras = {"00_31"};
  CHECK_FALSE(options.Validate(&why));
  CHECK(why.find("00_31") != std::string::npos);
  options.cameras = {"3", "00_03"};
  CHECK_FALSE(options.Validate(&why));
  CHECK(why.find("twice") != std::string::npos);
  options.cameras = {};
  options.sequence = "160906_pizza1";
  CHECK_FALSE(options.Validate(&why));
  CHECK(why.find("160906_pizza1") != std::string::npos);
  CHECK(DefaultPanopticCameras().size() == 6);
}

}  // namespace
}  // namespace mvtrack::datasets
