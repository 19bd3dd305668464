#include "config/calibration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "config/config_error.h"
#include "config_test_util.h"
#include "geometry/camera_rig.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::config {
namespace {

using testing::CheckLocated;
using testing::LineOf;
using testing::RequireConfigError;

// Bit-exact equality of every field of two cameras.
void RequireSameCamera(const geometry::CameraModel& a, const geometry::CameraModel& b) {
  INFO("camera " << a.id);
  REQUIRE(a.id == b.id);
  REQUIRE(a.width_px == b.width_px);
  REQUIRE(a.height_px == b.height_px);
  REQUIRE(a.K == b.K);
  REQUIRE(a.distortion.k1 == b.distortion.k1);
  REQUIRE(a.distortion.k2 == b.distortion.k2);
  REQUIRE(a.distortion.p1 == b.distortion.p1);
  REQUIRE(a.distortion.p2 == b.distortion.p2);
  REQUIRE(a.distortion.k3 == b.distortion.k3);
  REQUIRE(a.cam_from_world.rotation == b.cam_from_world.rotation);
  REQUIRE(a.cam_from_world.translation == b.cam_from_world.translation);
}

// `count` cameras with distinct random ids, random poses around the origin, random intrinsics
// (including skew) and random distortion: every value has a full-precision mantissa.
std::vector<geometry::CameraModel> RandomRig(std::mt19937* rng, int count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<int> ids(50);
  for (int i = 0; i < 50; ++i) ids[static_cast<std::size_t>(i)] = 3 * i;
  std::shuffle(ids.begin(), ids.end(), *rng);
  std::vector<geometry::CameraModel> cameras;
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * std::numbers::pi * unit(*rng);
    const Vec3 position(6.0 * std::cos(angle), 6.0 * std::sin(angle), 1.0 + 2.0 * unit(*rng));
    const Vec3 target(unit(*rng) - 0.5, unit(*rng) - 0.5, unit(*rng));
    geometry::CameraModel camera = mvtrack::testing::LookAtCamera(
        ids[static_cast<std::size_t>(i)], position, target, 800.0 + 800.0 * unit(*rng), 1920, 1080);
    camera.K(1, 1) = camera.K(0, 0) * (0.99 + 0.02 * unit(*rng));
    camera.K(0, 1) = 0.01 * (unit(*rng) - 0.5);
    camera.K(0, 2) += 20.0 * (unit(*rng) - 0.5);
    camera.K(1, 2) += 20.0 * (unit(*rng) - 0.5);
    camera.distortion.k1 = -0.3 * unit(*rng);
    camera.distortion.k2 = 0.1 * unit(*rng);
    camera.distortion.p1 = 1e-3 * (unit(*rng) - 0.5);
    camera.distortion.p2 = 1e-3 * (unit(*rng) - 0.5);
    camera.distortion.k3 = -0.02 * unit(*rng);
    REQUIRE(camera.Validate(nullptr));
    cameras.push_back(camera);
  }
  return cameras;
}

std::vector<geometry::CameraModel> SortedById(std::vector<geometry::CameraModel> cameras) {
  std::sort(
      cameras.begin(), cameras.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return cameras;
}

// A JSON rendering written independently of CalibrationToYaml ("%.17g" is exact for doubles).
std::string Real(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

std::string JsonMatrix(const Mat3& m) {
  std::string out = "[";
  for (int r = 0; r < 3; ++r) {
    out += r > 0 ? ", [" : "[";
    for (int c = 0; c < 3; ++c) out += (c > 0 ? ", " : "") + Real(m(r, c));
    out += "]";
  }
  return out + "]";
}

std::string ToJson(const std::vector<geometry::CameraModel>& cameras) {
  std::string out =
      "{\n  \"format\": \"mvtrack.calibration/1\",\n  \"units\": \"m\",\n"
      "  \"cameras\": [\n";
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const geometry::CameraModel& c = cameras[i];
    const geometry::Distortion& d = c.distortion;
    const Vec3& t = c.cam_from_world.translation;
    out += "    {\"id\": " + std::to_string(c.id) + ", \"image_size\": [" +
           std::to_string(c.width_px) + ", " + std::to_string(c.height_px) + "],\n";
    out += "     \"K\": " + JsonMatrix(c.K) + ",\n";
    out += "     \"distortion\": [" + Real(d.k1) + ", " + Real(d.k2) + ", " + Real(d.p1) + ", " +
           Real(d.p2) + ", " + Real(d.k3) + "],\n";
    out += "     \"R\": " + JsonMatrix(c.cam_from_world.rotation) + ",\n";
    out += "     \"t\": [" + Real(t.x()) + ", " + Real(t.y()) + ", " + Real(t.z()) + "]}";
    out += i + 1 < cameras.size() ? ",\n" : "\n";
  }
  return out + "  ]\n}\n";
}

TEST_CASE("Calibration YAML round-trips bit for bit and is canonical", "[unit]") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<geometry::CameraModel> cameras = RandomRig(&rng, 2 + trial);
    std::map<CameraId, std::string> names;
    names[cameras[0].id] = "cam \"zero\": front\\left";
    names[cameras[1].id] = "caméra 1";
    const std::string text = CalibrationToYaml(cameras, names);
    const CalibrationDocument back = ParseCalibrationDocument(text, "round_trip.yaml");
    const std::vector<geometry::CameraModel> expected = SortedById(cameras);
    REQUIRE(back.cameras.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
      RequireSameCamera(back.cameras[i], expected[i]);
    }
    CHECK(back.names == names);
    // Canonical: the input order does not matter, and writing the parsed cameras reproduces
    // the text exactly.
    std::vector<geometry::CameraModel> shuffled = cameras;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    CHECK(CalibrationToYaml(shuffled, names) == text);
    CHECK(CalibrationToYaml(back.cameras, back.names) == text);
  }
}

TEST_CASE("JSON calibration files parse exactly", "[unit]") {
  std::mt19937 rng(11);
  const std::vector<geometry::CameraModel> cameras = RandomRig(&rng, 4);
  const std::string json = ToJson(cameras);
  const std::vector<geometry::CameraModel> back = ParseCalibration(json, "rig.json");
  REQUIRE(back.size() == cameras.size());
  // File order is kept.
  for (std::size_t i = 0; i < cameras.size(); ++i) RequireSameCamera(back[i], cameras[i]);

  // Errors in JSON are located like errors in YAML.
  std::string bad = json;
  const std::size_t pos = bad.find("\"distortion\"", bad.find("\"distortion\"") + 1);
  bad.replace(pos, 12, "\"distorsion\"");
  CheckLocated(RequireConfigError([&] { ParseCalibration(bad, "rig.json"); }),
               "rig.json",
               LineOf(bad, "\"distorsion\""),
               "cameras[1].distorsion",
               "unknown key (did you mean 'distortion'?)");

  // The scalar intrinsics and rvec forms work in JSON too.
  const std::string scalar_form =
      R"({"format": "mvtrack.calibration/1", "cameras": [{"id": 4, "image_size": [640, 480],
          "fx": 500, "fy": 505.5, "cx": 320.25, "cy": 239.75, "skew": 0.5,
          "rvec": [0, 0, 0], "t": [0.5, -0.25, 3]}]})";
  const std::vector<geometry::CameraModel> scalar = ParseCalibration(scalar_form, "s.json");
  REQUIRE(scalar.size() == 1);
  Mat3 expected_k;
  expected_k << 500.0, 0.5, 320.25, 0.0, 505.5, 239.75, 0.0, 0.0, 1.0;
  CHECK(scalar[0].K == expected_k);
  CHECK(scalar[0].cam_from_world.rotation == Mat3::Identity());
  CHECK(scalar[0].cam_from_world.translation == Vec3(0.5, -0.25, 3.0));
  CHECK(scalar[0].distortion.IsZero());
}

TEST_CASE("rvec is a Rodrigues vector (OpenCV convention)", "[unit]") {
  const auto rotation_of = [](const Vec3& rvec) {
    const std::string text =
        "format: mvtrack.calibration/1\ncameras:\n  - id: 0\n"
        "    image_size: [10, 10]\n    fx: 1\n    fy: 1\n    cx: 5\n"
        "    cy: 5\n    rvec: [" +
        Real(rvec.x()) + ", " + Real(rvec.y()) + ", " + Real(rvec.z()) + "]\n    t: [0, 0, 0]\n";
    return ParseCalibration(text, "r.yaml").front().cam_from_world.rotation;
  };
  // A quarter turn about +z maps +x to +y (right-hand rule).
  const Mat3 quarter = rotation_of(Vec3(0.0, 0.0, std::numbers::pi / 2.0));
  CHECK((quarter * Vec3::UnitX() - Vec3::UnitY()).norm() < 1e-15);
  CHECK((quarter * Vec3::UnitZ() - Vec3::UnitZ()).norm() < 1e-15);
  // A general vector: the axis is fixed, the angle is |rvec| (trace = 1 + 2 cos angle).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-1.5, 1.5);
  for (int i = 0; i < 20; ++i) {
    const Vec3 rvec(coord(rng), coord(rng), coord(rng));
    const Mat3 r = rotation_of(rvec);
    CHECK((r * rvec - rvec).norm() < 1e-12);
    CHECK(std::abs(r.trace() - (1.0 + 2.0 * std::cos(rvec.norm()))) < 1e-12);
    CHECK(std::abs(r.determinant() - 1.0) < 1e-12);
    // The direction of rotation: a vector orthogonal to the axis turns by +angle about it.
    const Vec3 axis = rvec.normalized();
    const Vec3 u = axis.unitOrthogonal();
    const Vec3 turned = r * u;
    CHECK(std::abs(std::atan2(axis.dot(u.cross(turned)), u.dot(turned)) - rvec.norm()) < 1e-12);
  }
}

TEST_CASE("Optional keys: distortion, units and name", "[unit]") {
  const std::string text =
      "format: mvtrack.calibration/1\n"
      "cameras:\n"
      "  - id: 9\n"
      "    image_size: [64, 48]\n"
      "    K: [[50, 0, 32], [0, 50, 24], [0, 0, 1]]\n"
      "    R: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
      "    t: [0, 0, 1]\n";
  const CalibrationDocument doc = ParseCalibrationDocument(text, "o.yaml");
  REQUIRE(doc.cameras.size() == 1);
  CHECK(doc.cameras[0].distortion.IsZero());
  CHECK(doc.cameras[0].width_px == 64);
  CHECK(doc.cameras[0].height_px == 48);
  CHECK(doc.names.empty());
}

TEST_CASE("SaveCalibration writes a file LoadCalibration reads back exactly", "[unit]") {
  const testing::TempDir dir;
  std::mt19937 rng(5);
  const std::vector<geometry::CameraModel> cameras = RandomRig(&rng, 3);
  const std::string path = dir.File("rig.yaml");
  SaveCalibration(path, cameras, {{cameras[2].id, "third"}});
  const std::vector<geometry::CameraModel> back = LoadCalibration(path);
  const std::vector<geometry::CameraModel> expected = SortedById(cameras);
  REQUIRE(back.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) RequireSameCamera(back[i], expected[i]);
  CHECK(LoadCalibrationDocument(path).names.at(cameras[2].id) == "third");

  // Invalid input is refused before anything is written.
  std::vector<geometry::CameraModel> duplicate = cameras;
  duplicate[1].id = duplicate[0].id;
  const std::string other = dir.File("other.yaml");
  const ConfigError dup = RequireConfigError([&] { SaveCalibration(other, duplicate); });
  CHECK(dup.file() == other);
  CHECK(dup.key_path() == "cameras[1].id");
  std::vector<geometry::CameraModel> invalid = cameras;
  invalid[2].K(0, 0) = -1.0;
  CHECK(RequireConfigError([&] { SaveCalibration(other, invalid); }).key_path() == "cameras[2]");
  CHECK(RequireConfigError([&] { SaveCalibration(other, {}); }).key_path() == "cameras");
  CHECK_FALSE(std::filesystem::exists(other));
}

TEST_CASE("The example calibration parses into the documented rig", "[unit]") {
  const std::string path =
      std::string(MVTRACK_SOURCE_DIR) + "/docs/examples/calibration.example.yaml";
  const CalibrationDocument doc = LoadCalibrationDocument(path);
  REQUIRE(doc.cameras.size() == 3);
  CHECK(doc.names == std::map<CameraId, std::string>{{0, "north"}, {1, "east"}, {2, "west"}});
  std::string why;
  const geometry::CameraRig rig(doc.cameras, &why);
  INFO(why);
  REQUIRE(rig.ok());
  // The centres stated in the file's comments, each looking horizontally at the room centre:
  // a point 1.5 m above the centre is on the optical axis, 4 m deep.
  const std::vector<Vec3> centres = {{0.0, 4.0, 1.5}, {4.0, 0.0, 1.5}, {-4.0, 0.0, 1.5}};
  for (std::size_t i = 0; i < 3; ++i) {
    const geometry::CameraModel& camera = doc.cameras[i];
    INFO("camera " << camera.id);
    CHECK((camera.CenterInWorld() - centres[i]).norm() < 1e-12);
    const Vec3 on_axis(0.0, 0.0, 1.5);
    CHECK(std::abs(camera.Depth(on_axis) - 4.0) < 1e-12);
    const std::optional<Vec2> pixel = camera.ProjectUndistorted(on_axis);
    REQUIRE(pixel.has_value());
    CHECK((*pixel - Vec2(camera.K(0, 2), camera.K(1, 2))).norm() < 1e-9);
    // The room centre on the floor is in view, below the principal point (image y down).
    const std::optional<Vec2> floor = camera.Project(Vec3::Zero());
    REQUIRE(floor.has_value());
    CHECK(camera.InImage(*floor));
    CHECK(floor->y() > camera.K(1, 2));
  }
  CHECK_FALSE(doc.cameras[2].distortion.IsZero());
}

// A valid two-camera file the strictness cases below modify one line at a time.
const std::string kBase =
    "format: mvtrack.calibration/1\n"
    "units: m\n"
    "cameras:\n"
    "  - id: 0\n"
    "    name: left\n"
    "    image_size: [640, 480]\n"
    "    K: [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]]\n"
    "    distortion: [0.0, 0.0, 0.0, 0.0, 0.0]\n"
    "    R: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n"
    "    t: [0.0, 0.0, 5.0]\n"
    "  - id: 1\n"
    "    image_size: [640, 480]\n"
    "    fx: 500.0\n"
    "    fy: 510.0\n"
    "    cx: 320.0\n"
    "    cy: 240.0\n"
    "    rvec: [0.0, 0.1, 0.0]\n"
    "    t: [-1.0, 0.0, 5.0]\n";

TEST_CASE("The strictness base file is valid", "[unit]") {
  const std::vector<geometry::CameraModel> cameras = ParseCalibration(kBase, "calib.yaml");
  REQUIRE(cameras.size() == 2);
  CHECK(cameras[1].K(1, 1) == 510.0);
}

TEST_CASE("Calibration units: cm and mm are converted to metres, a unit mistake is refused",
          "[unit]") {
  const std::vector<geometry::CameraModel> metres = ParseCalibration(kBase, "calib.yaml");
  std::string mm = kBase;
  mm.replace(mm.find("units: m"), 8, "units: mm");
  mm.replace(mm.find("t: [-1.0, 0.0, 5.0]"), 19, "t: [-1000.0, 0.0, 5000.0]");
  const std::vector<geometry::CameraModel> from_mm = ParseCalibration(mm, "mm.yaml");
  REQUIRE(from_mm.size() == metres.size());
  CHECK((from_mm[1].cam_from_world.translation - metres[1].cam_from_world.translation).norm() <
        1e-12);
  std::string cm = kBase;
  cm.replace(cm.find("units: m"), 8, "units: cm");
  cm.replace(cm.find("t: [-1.0, 0.0, 5.0]"), 19, "t: [-100.0, 0.0, 500.0]");
  CHECK((ParseCalibration(cm, "cm.yaml")[1].cam_from_world.translation -
         metres[1].cam_from_world.translation)
            .norm() < 1e-12);
  // Centimetres without a unit: refused, naming centimetres (cameras 5 m up = 500 "m").
  std::string bare = cm;
  bare.replace(bare.find("units: cm\n"), 10, "");
  try {
    ParseCalibration(bare, "bare.yaml");
    FAIL("a rig 500 m up was accepted");
  } catch (const ConfigError& e) {
    CHECK_THAT(e.what(), Catch::Contains("look like centimetres"));
    CHECK_THAT(e.what(), Catch::Contains("write 'units: cm'"));
  }
}

TEST_CASE("Calibration strictness: every error names file, line and key path", "[unit]") {
  struct Case {
    std::string name;
    std::string from;    // text of kBase to replace (first occurrence)
    std::string to;      // replacement
    std::string marker;  // text in the modified file on the reported line
    std::string key_path;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"unknown camera key",
       "    distortion:",
       "    distorsion:",
       "distorsion",
       "cameras[0].distorsion",
       "unknown key (did you mean 'distortion'?)"},
      {"unknown top-level key",
       "units: m",
       "unit: m",
       "unit:",
       "unit",
       "unknown key (did you mean 'units'?)"},
      {"wrong format",
       "calibration/1",
       "calibration/2",
       "format:",
       "format",
       "unsupported format 'mvtrack.calibration/2'"},
      {"units other than metres, centimetres and millimetres",
       "units: m",
       "units: ft",
       "units:",
       "units",
       "unsupported units 'ft' (m, cm or mm: the unit of every camera's t)"},
      {"translations in millimetres said to be metres",
       "    t: [-1.0, 0.0, 5.0]",
       "    t: [-1000.0, 0.0, 5000.0]",
       "units:",
       "units",
       "the translations t look like millimetres, not metres; write 'units: mm'"},
      {"missing format",
       "format: mvtrack.calibration/1\n",
       "",
       "units:",
       "",
       "missing required key 'format'"},
      {"missing id",
       "  - id: 1\n    image_size: [640, 480]\n    fx",
       "  - image_size: [640, 480]\n    fx",
       "  - image_size: [640, 480]\n    fx",
       "cameras[1]",
       "missing required key 'id'"},
      {"missing image_size",
       "    image_size: [640, 480]\n    fx",
       "    fx",
       "id: 1",
       "cameras[1]",
       "missing required key 'image_size'"},
      {"missing t",
       "    t: [-1.0, 0.0, 5.0]\n",
       "",
       "id: 1",
       "cameras[1]",
       "missing required key 't'"},
      {"missing rotation",
       "    rvec: [0.0, 0.1, 0.0]\n",
       "",
       "id: 1",
       "cameras[1]",
       "missing rotation: give exactly one of 'R', 'rvec'"},
      {"missing intrinsics",
       "    K: [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]]\n",
       "",
       "id: 0",
       "cameras[0]",
       "missing intrinsics"},
      {"incomplete scalar intrinsics",
       "    fy: 510.0\n",
       "",
       "id: 1",
       "cameras[1]",
       "missing required key 'fy'"},
      {"wrong type",
       "id: 1",
       "id: one",
       "id: one",
       "cameras[1].id",
       "expected an integer, got 'one'"},
      {"negative id",
       "id: 1",
       "id: -1",
       "id: -1",
       "cameras[1].id",
       "value -1 out of range: must be >= 0"},
      {"quoted number",
       "fy: 510.0",
       "fy: \"510.0\"",
       "fy:",
       "cameras[1].fy",
       "expected a number, got the quoted string \"510.0\""},
      {"image_size too short",
       "image_size: [640, 480]",
       "image_size: [640]",
       "image_size: [640]",
       "cameras[0].image_size",
       "expected a list of 2 values, got 1"},
      {"image_size zero",
       "image_size: [640, 480]",
       "image_size: [0, 480]",
       "image_size: [0",
       "cameras[0].image_size[0]",
       "must be in [1, "},
      {"non-number in K",
       "[0.0, 0.0, 1.0]]",
       "[x, 0.0, 1.0]]",
       "[x,",
       "cameras[0].K[2][0]",
       "expected a number, got 'x'"},
      {"K with two rows",
       "[0.0, 500.0, 240.0], [0.0, 0.0, 1.0]]",
       "[0.0, 500.0, 240.0]]",
       "K:",
       "cameras[0].K",
       "expected a list of 3 values, got 2"},
      {"non-finite t",
       "t: [0.0, 0.0, 5.0]",
       "t: [0.0, .nan, 5.0]",
       "t: [0.0, .nan",
       "cameras[0].t[1]",
       "non-finite number '.nan'"},
      {"infinite K",
       "[[500.0, 0.0",
       "[[.inf, 0.0",
       "K:",
       "cameras[0].K[0][0]",
       "non-finite number '.inf'"},
      {"duplicate ids",
       "id: 1",
       "id: 0",
       "  - id: 0\n    image_size",
       "cameras[1].id",
       "duplicate camera id 0 (also used by cameras[0] at line 4)"},
      {"scaled rotation",
       "R: [[1.0, 0.0, 0.0]",
       "R: [[1.1, 0.0, 0.0]",
       "R:",
       "cameras[0].R",
       "rotation is not a proper orthonormal matrix"},
      {"reflection",
       "R: [[1.0, 0.0, 0.0]",
       "R: [[-1.0, 0.0, 0.0]",
       "R:",
       "cameras[0].R",
       "rotation is not a proper orthonormal matrix"},
      {"K and fx",
       "    distortion:",
       "    fx: 500.0\n    distortion:",
       "fx: 500.0\n    distortion",
       "cameras[0].fx",
       "either as 'K' or as 'fx', 'fy', 'cx', 'cy' (+ 'skew'), not both"},
      {"R and rvec",
       "    t: [0.0, 0.0, 5.0]",
       "    rvec: [0.0, 0.0, 0.0]\n    t: [0.0, 0.0, 5.0]",
       "rvec: [0.0, 0.0, 0.0]",
       "cameras[0].rvec",
       "give exactly one rotation form, not both 'R', 'rvec'"},
      {"distortion of 4",
       "distortion: [0.0, 0.0, 0.0, 0.0, 0.0]",
       "distortion: [0.0, 0.0, 0.0, 0.0]",
       "distortion:",
       "cameras[0].distortion",
       "expected a list of 5 values, got 4"},
      {"K not upper triangular",
       "[0.0, 0.0, 1.0]]",
       "[0.0, 0.0, 2.0]]",
       "K:",
       "cameras[0].K",
       "K must be upper triangular with K(2,2) = 1"},
      {"negative focal length in K",
       "[[500.0, 0.0",
       "[[-500.0, 0.0",
       "K:",
       "cameras[0].K",
       "focal lengths fx, fy must be positive"},
      {"negative fx", "fx: 500.0", "fx: -500.0", "fx:", "cameras[1].fx", "must be > 0"},
      {"name not a string",
       "name: left",
       "name: [left]",
       "name:",
       "cameras[0].name",
       "expected a string, got a list"},
      {"empty camera list",
       kBase.substr(kBase.find("cameras:")),
       "cameras: []\n",
       "cameras:",
       "cameras",
       "the rig needs at least one camera"},
      {"cameras as a map",
       kBase.substr(kBase.find("cameras:")),
       "cameras: {a: 1}\n",
       "cameras:",
       "cameras",
       "expected a list, got a map"},
      {"camera as a list",
       "  - id: 0\n",
       "  - [1, 2]\n  - id: 0\n",
       "[1, 2]",
       "cameras[0]",
       "expected a map, got a list"},
  };
  for (const Case& c : cases) {
    INFO("case: " << c.name);
    std::string text = kBase;
    const std::size_t pos = text.find(c.from);
    REQUIRE(pos != std::string::npos);
    text.replace(pos, c.from.size(), c.to);
    const ConfigError e = RequireConfigError([&] { ParseCalibration(text, "calib.yaml"); });
    CheckLocated(e, "calib.yaml", LineOf(text, c.marker), c.key_path, c.reason);
  }
}

TEST_CASE("Calibration file-level errors", "[unit]") {
  const testing::TempDir dir;
  // Empty and comment-only files.
  for (const std::string text : {"", "# nothing here\n"}) {
    const std::string path = dir.Write("empty.yaml", text);
    const ConfigError e = RequireConfigError([&] { LoadCalibration(path); });
    CHECK(e.file() == path);
    CHECK_THAT(e.reason(), Catch::Contains("empty calibration"));
  }
  // A file that does not exist.
  const std::string missing = dir.File("nope.yaml");
  const ConfigError e = RequireConfigError([&] { LoadCalibration(missing); });
  CHECK(std::string(e.what()) == missing + ": file does not exist");
  // A YAML syntax error names its line.
  const std::string broken = "format: mvtrack.calibration/1\ncameras:\n  - id: [0\n    t: 1\n";
  const std::string broken_path = dir.Write("broken.yaml", broken);
  const ConfigError syntax = RequireConfigError([&] { LoadCalibration(broken_path); });
  CHECK(syntax.file() == broken_path);
  CHECK(syntax.line() >= 3);
  CHECK_THAT(syntax.reason(), Catch::StartsWith("YAML syntax error"));
  CHECK_THAT(std::string(syntax.what()),
             Catch::StartsWith(broken_path + ":" + std::to_string(syntax.line()) + ":"));
  // A scalar document.
  CHECK_THAT(RequireConfigError([] { ParseCalibration("42\n", "s.yaml"); }).reason(),
             Catch::Contains("expected a map"));
}

}  // namespace
}  // namespace mvtrack::config
