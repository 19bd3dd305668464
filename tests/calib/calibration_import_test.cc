#include "config/calibration_import.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calib/calib_test_util.h"
#include "config/calibration.h"
#include "datasets/panoptic.h"

namespace mvtrack::config {
namespace {

using testing::TempDir;
using testing::WriteText;

// `text` with the first `from` replaced by `to` (which must be present).
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

double MaxDiff(const Mat3& a, const Mat3& b) { return (a - b).cwiseAbs().maxCoeff(); }
double MaxDiff(const Vec3& a, const Vec3& b) { return (a - b).cwiseAbs().maxCoeff(); }

cv::Mat ToCv(const Mat3& m) {
  cv::Mat out(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.at<double>(r, c) = m(r, c);
  }
  return out;
}

cv::Mat Column(const Vec3& v) { return (cv::Mat_<double>(3, 1) << v.x(), v.y(), v.z()); }

// A known camera of the EasyMocap tests.
struct KnownCamera {
  std::string name;
  Mat3 K;
  Vec3 rvec;                 // Rodrigues
  Vec3 T;                    // metres
  std::vector<double> dist;  // empty: no dist_ entry
  Mat3 R() const {
    return rvec.norm() == 0.0 ? Mat3(Mat3::Identity())
                              : Mat3(Eigen::AngleAxisd(rvec.norm(), rvec.normalized()));
  }
};

std::vector<KnownCamera> KnownCameras() {
  Mat3 k1;
  k1 << 1000.5, 0.0, 640.25, 0.0, 998.0, 359.5, 0.0, 0.0, 1.0;
  Mat3 k2;
  k2 << 1400.0, 0.5, 960.0, 0.0, 1401.0, 540.0, 0.0, 0.0, 1.0;
  return {
      {"01", k1, Vec3(1.2, -0.3, 0.4), Vec3(0.5, -1.0, 4.0), {0.1, -0.05, 0.001, 0.002, 0.01}},
      {"02", k2, Vec3(-0.2, 2.0, 0.1), Vec3(-0.25, 0.75, 5.5), {-0.2, 0.04, 0.0, 0.0}},
      {"10", k1, Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 3.0), {}},
  };
}

// Writes intri.yml / extri.yml with OpenCV's own FileStorage writer, as EasyMocap does.
void WriteEasyMocap(const std::string& intri,
                    const std::string& extri,
                    const std::vector<KnownCamera>& cams,
                    bool with_rot,
                    bool with_rvec,
                    bool with_size) {
  cv::FileStorage fi(intri, cv::FileStorage::WRITE);
  cv::FileStorage fe(extri, cv::FileStorage::WRITE);
  fi << "names"
     << "[";
  fe << "names"
     << "[";
  for (const KnownCamera& c : cams) {
    fi << c.name;
    fe << c.name;
  }
  fi << "]";
  fe << "]";
  for (const KnownCamera& c : cams) {
    fi << "K_" + c.name << ToCv(c.K);
    if (!c.dist.empty()) fi << "dist_" + c.name << cv::Mat(c.dist).reshape(1, 1);
    if (with_size) {
      fi << "H_" + c.name << 720;
      fi << "W_" + c.name << 1280;
    }
    if (with_rvec) fe << "R_" + c.name << Column(c.rvec);
    if (with_rot) fe << "Rot_" + c.name << ToCv(c.R());
    fe << "T_" + c.name << Column(c.T);
  }
}

TEST_CASE("EasyMocap intri/extri written by OpenCV import to the same cameras", "[unit]") {
  TempDir dir;
  const std::vector<KnownCamera> cams = KnownCameras();
  WriteEasyMocap(dir.File("intri.yml"), dir.File("extri.yml"), cams, true, true, true);
  const ImportedCalibration imported =
      ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml"));
  const std::vector<geometry::CameraModel>& out = imported.document.cameras;
  REQUIRE(out.size() == 3);
  const CameraId ids[] = {1, 2, 10};
  for (std::size_t i = 0; i < 3; ++i) {
    INFO("camera " << cams[i].name);
    CHECK(out[i].id == ids[i]);
    CHECK(imported.document.names.at(ids[i]) == cams[i].name);
    CHECK(out[i].width_px == 1280);
    CHECK(out[i].height_px == 720);
    CHECK(MaxDiff(out[i].K, cams[i].K) < 1e-12);
    CHECK(MaxDiff(out[i].cam_from_world.rotation, cams[i].R()) < 1e-12);
    CHECK(MaxDiff(out[i].cam_from_world.translation, cams[i].T) < 1e-12);
    const std::vector<double>& d = cams[i].dist;
    CHECK(out[i].distortion.k1 == (d.empty() ? 0.0 : d[0]));
    CHECK(out[i].distortion.p2 == (d.empty() ? 0.0 : d[3]));
    CHECK(out[i].distortion.k3 == (d.size() == 5 ? d[4] : 0.0));
    // The imported camera projects like x = K (R X + T).
    const Vec3 X(0.3, -0.2, 0.5);
    const Vec3 x = cams[i].K * (cams[i].R() * X + cams[i].T);
    const Vec2 expected = x.hnormalized();
    CHECK((*out[i].ProjectUndistorted(X) - expected).norm() < 1e-9);
  }
  // The camera without dist_ is noted.
  bool noted = false;
  for (const std::string& n : imported.notes) noted |= n.find("no dist_10") != std::string::npos;
  CHECK(noted);
  // And our format keeps everything bit for bit.
  SaveCalibration(dir.File("ours.yaml"), out, imported.document.names);
  const CalibrationDocument back = LoadCalibrationDocument(dir.File("ours.yaml"));
  REQUIRE(back.cameras.size() == 3);
  CHECK(back.names.at(10) == "10");
  CHECK(back.cameras[0].K == out[0].K);
  CHECK(back.cameras[1].cam_from_world.rotation == out[1].cam_from_world.rotation);
}

TEST_CASE("EasyMocap: Rodrigues only, Rot only, disagreeing rotations, image size rules",
          "[unit]") {
  TempDir dir;
  const std::vector<KnownCamera> cams = KnownCameras();
  SECTION("only R_ (Rodrigues)") {
    WriteEasyMocap(dir.File("i.yml"), dir.File("e.yml"), cams, false, true, true);
    const ImportedCalibration c = ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml"));
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(MaxDiff(c.document.cameras[i].cam_from_world.rotation, cams[i].R()) < 1e-12);
    }
  }
  SECTION("only Rot_") {
    WriteEasyMocap(dir.File("i.yml"), dir.File("e.yml"), cams, true, false, true);
    const ImportedCalibration c = ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml"));
    CHECK(MaxDiff(c.document.cameras[1].cam_from_world.rotation, cams[1].R()) < 1e-12);
  }
  SECTION("Rot_ and R_ disagree") {
    std::vector<KnownCamera> wrong = cams;
    WriteEasyMocap(dir.File("i.yml"), dir.File("e.yml"), wrong, false, true, true);
    // Rewrite extri with a Rot_ that is not Rodrigues(R_).
    {
      cv::FileStorage fe(dir.File("e.yml"), cv::FileStorage::WRITE);
      fe << "names"
         << "["
         << "01"
         << "02"
         << "10"
         << "]";
      for (const KnownCamera& c : cams) {
        fe << "R_" + c.name << Column(c.rvec);
        fe << "Rot_" + c.name << ToCv(c.name == "02" ? Mat3(Mat3::Identity()) : c.R());
        fe << "T_" + c.name << Column(c.T);
      }
    }
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml")),
                      Catch::Contains("Rot_02") && Catch::Contains("Rodrigues"));
  }
  SECTION("no image size in the file: the given one, else an error naming --image-size") {
    WriteEasyMocap(dir.File("i.yml"), dir.File("e.yml"), cams, true, true, false);
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml")),
                      Catch::Contains("i.yml") && Catch::Contains("--image-size"));
    const ImportedCalibration c =
        ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml"), ImageSize{1920, 1080});
    CHECK(c.document.cameras[2].width_px == 1920);
    CHECK(c.document.cameras[2].height_px == 1080);
  }
  SECTION("a given size contradicting the file is an error") {
    WriteEasyMocap(dir.File("i.yml"), dir.File("e.yml"), cams, true, true, true);
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("i.yml"), dir.File("e.yml"), ImageSize{640, 480}),
                      Catch::Contains("1280x720") && Catch::Contains("640x480"));
  }
}

// EasyMocap's files as text (the %YAML:1.0 / !!opencv-matrix syntax), with names that are not
// numbers.
const char kIntri[] = R"(%YAML:1.0
---
names:
  - "left"
  - "right"
K_left: !!opencv-matrix
  rows: 3
  cols: 3
  dt: d
  data: [ 1.0e+03, 0., 6.4e+02, 0., 1.0e+03, 3.6e+02, 0., 0., 1. ]
dist_left: !!opencv-matrix
  rows: 5
  cols: 1
  dt: d
  data: [ 1.0e-01, 0., 0., 0., 0. ]
H_left: 720
W_left: 1280
K_right: !!opencv-matrix
  rows: 3
  cols: 3
  dt: d
  data: [ 900., 0., 640., 0., 900., 360., 0., 0., 1. ]
dist_right: !!opencv-matrix
  rows: 1
  cols: 8
  dt: d
  data: [ 0., 0., 0., 0., 0., 0., 0., 0. ]
H_right: 720
W_right: 1280
)";
const char kExtri[] = R"(%YAML:1.0
---
names:
  - "left"
  - "right"
R_left: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0., 0., 0. ]
T_left: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0.1, 0.2, 3.0 ]
R_right: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0., 1.5707963267948966, 0. ]
T_right: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0., 0., 4.0 ]
)";

TEST_CASE("EasyMocap text files: names that are not numbers get ids by position", "[unit]") {
  TempDir dir;
  WriteText(dir.File("intri.yml"), kIntri);
  WriteText(dir.File("extri.yml"), kExtri);
  const ImportedCalibration c = ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml"));
  REQUIRE(c.document.cameras.size() == 2);
  CHECK(c.document.cameras[0].id == 0);
  CHECK(c.document.cameras[1].id == 1);
  CHECK(c.document.names.at(0) == "left");
  CHECK(c.document.names.at(1) == "right");
  CHECK(c.document.cameras[0].distortion.k1 == 0.1);
  CHECK(c.document.cameras[0].cam_from_world.translation == Vec3(0.1, 0.2, 3.0));
  // 90 degrees about y: camera z axis = world -x... R maps world x to camera -z.
  CHECK(MaxDiff(c.document.cameras[1].cam_from_world.rotation * Vec3(1, 0, 0), Vec3(0, 0, -1)) <
        1e-12);
}

TEST_CASE("EasyMocap errors name the file and the entry", "[unit]") {
  TempDir dir;
  WriteText(dir.File("extri.yml"), kExtri);
  SECTION("missing K") {
    WriteText(dir.File("intri.yml"), Replace(kIntri, "K_right", "K_rihgt"));
    CHECK_THROWS_WITH(
        ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
        Catch::Contains("intri.yml") && Catch::Contains("K_right") && Catch::Contains("missing"));
  }
  SECTION("K of the wrong shape") {
    WriteText(dir.File("intri.yml"), Replace(kIntri, "rows: 3\n  cols: 3", "rows: 1\n  cols: 9"));
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
                      Catch::Contains("K_left") && Catch::Contains("3x3"));
  }
  SECTION("rational distortion") {
    WriteText(dir.File("intri.yml"),
              Replace(kIntri,
                      "data: [ 0., 0., 0., 0., 0., 0., 0., 0. ]",
                      "data: [ 0., 0., 0., 0., 0., 0.5, 0., 0. ]"));
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
                      Catch::Contains("dist_right") && Catch::Contains("rational"));
  }
  SECTION("a camera missing from extri.yml") {
    WriteText(dir.File("intri.yml"), kIntri);
    WriteText(dir.File("extri.yml"), Replace(kExtri, "T_right", "T_riht_"));
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
                      Catch::Contains("extri.yml") && Catch::Contains("T_right"));
  }
  SECTION("not a FileStorage file, or no file") {
    WriteText(dir.File("intri.yml"), "this: [is: not\n");
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
                      Catch::Contains("intri.yml"));
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("nope.yml"), dir.File("extri.yml")),
                      Catch::Contains("nope.yml") && Catch::Contains("does not exist"));
  }
  SECTION("an invalid camera") {
    WriteText(dir.File("intri.yml"),
              Replace(kIntri, "900., 0., 640., 0., 900.", "-90., 0., 640., 0., 900."));
    CHECK_THROWS_WITH(ImportEasyMocap(dir.File("intri.yml"), dir.File("extri.yml")),
                      Catch::Contains("camera 'right'"));
  }
}

TEST_CASE("VoxelPose: T is the camera centre in mm, the image size is required", "[unit]") {
  TempDir dir;
  WriteText(dir.File("vp.json"), R"({
  "3": {"R": [[1, 0, 0], [0, 0, -1], [0, 1, 0]], "T": [[1000.0], [-4000.0], [1500.0]],
        "fx": 1000.0, "fy": 1010.0, "cx": 500.0, "cy": 380.0,
        "k": [[0.1], [0.01], [0.001]], "p": [[0.002], [0.003]]},
  "0": {"R": [[1, 0, 0], [0, 0, -1], [0, 1, 0]], "T": [[0.0], [-3000.0], [1000.0]],
        "fx": 900.0, "fy": 900.0, "cx": 516.0, "cy": 388.0,
        "k": [[0.0], [0.0], [0.0]], "p": [[0.0], [0.0]]}
})");
  const ImportedCalibration c = ImportVoxelPose(dir.File("vp.json"), ImageSize{1032, 776});
  REQUIRE(c.document.cameras.size() == 2);
  const geometry::CameraModel& cam0 = c.document.cameras[0];
  const geometry::CameraModel& cam3 = c.document.cameras[1];
  CHECK(cam0.id == 0);  // sorted by id
  CHECK(cam3.id == 3);
  CHECK(MaxDiff(cam3.CenterInWorld(), Vec3(1.0, -4.0, 1.5)) < 1e-12);
  CHECK(cam3.K(1, 1) == 1010.0);
  CHECK(cam3.distortion.k1 == 0.1);
  CHECK(cam3.distortion.k3 == 0.001);
  CHECK(cam3.distortion.p1 == 0.002);
  CHECK(cam3.distortion.p2 == 0.003);
  CHECK(cam3.width_px == 1032);
  // x_cam = R (X - T): a point 4 m straight ahead of camera 0 (its axis is world +y).
  const Vec2 px = *cam0.ProjectUndistorted(Vec3(0.0, 1.0, 1.0));
  CHECK((px - Vec2(516.0, 388.0)).norm() < 1e-9);

  CHECK_THROWS_WITH(ImportVoxelPose(dir.File("vp.json"), ImageSize{}),
                    Catch::Contains("--image-size"));
  // A rotation printed with 6 decimals is not orthonormal to 1e-6: it is replaced by the
  // nearest rotation (with a note); a matrix far from a rotation is an error.
  const double co = std::cos(0.3), sn = std::sin(0.3);
  char rounded[512];
  std::snprintf(
      rounded,
      sizeof rounded,
      R"({"0": {"R": [[%.6f, %.6f, 0], [%.6f, %.6f, 0], [0, 0, 1]], "T": [[0], [0], [-3000]],
  "fx": 900, "fy": 900, "cx": 516, "cy": 388, "k": [[0], [0], [0]], "p": [[0], [0]]}})",
      co,
      -sn,
      sn,
      co);
  WriteText(dir.File("rounded.json"), rounded);
  const ImportedCalibration r = ImportVoxelPose(dir.File("rounded.json"), ImageSize{1032, 776});
  const Mat3& R = r.document.cameras[0].cam_from_world.rotation;
  CHECK((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(std::abs(R(0, 0) - co) < 1e-6);
  bool noted = false;
  for (const std::string& n : r.notes) noted |= n.find("nearest rotation") != std::string::npos;
  CHECK(noted);
  WriteText(dir.File("skewed.json"),
            R"({"0": {"R": [[1, 0.01, 0], [0, 1, 0], [0, 0, 1]], "T": [[0], [0], [-3000]],
  "fx": 900, "fy": 900, "cx": 516, "cy": 388, "k": [[0], [0], [0]], "p": [[0], [0]]}})");
  CHECK_THROWS_WITH(ImportVoxelPose(dir.File("skewed.json"), ImageSize{1032, 776}),
                    Catch::Contains("orthonormal"));
  WriteText(dir.File("bad.json"),
            R"({"0": {"R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "T": [[0], [0], [0]],
  "fx": 1, "fy": 1, "cx": 1, "cy": 1, "k": [[0], [0], [0]], "p": [[0], [0]], "Q": 1}})");
  CHECK_THROWS_WITH(
      ImportVoxelPose(dir.File("bad.json"), ImageSize{10, 10}),
      Catch::Contains("bad.json:") && Catch::Contains("Q") && Catch::Contains("unknown key"));
  WriteText(dir.File("bad2.json"), R"({"zero": {}})");
  CHECK_THROWS_WITH(ImportVoxelPose(dir.File("bad2.json"), ImageSize{10, 10}),
                    Catch::Contains("'zero' is not a non-negative integer"));
}

// WILDTRACK's official XML files (format of calibrations/intrinsic_zero/intr_<name>.xml and
// calibrations/extrinsic/extr_<name>.xml).
std::string IntrinsicXml(double fx, double cx) {
  return "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix type_id=\"opencv-matrix\">\n"
         "  <rows>3</rows>\n  <cols>3</cols>\n  <dt>d</dt>\n  <data>\n    " +
         std::to_string(fx) + " 0. " + std::to_string(cx) + " 0. " + std::to_string(fx) +
         " 4.4439877319335938e+02 0. 0. 1.</data></camera_matrix>\n"
         "<distortion_coefficients type_id=\"opencv-matrix\">\n  <rows>1</rows>\n  <cols>5</cols>\n"
         "  <dt>d</dt>\n  <data>\n    0. 0. 0. 0. 0.</data></distortion_coefficients>\n"
         "</opencv_storage>\n";
}
std::string ExtrinsicXml(const std::string& rvec, const std::string& tvec) {
  return "<?xml version=\"1.0\"?>\n<opencv_storage>\n<rvec>" + rvec + "</rvec>\n<tvec>" + tvec +
         "</tvec>\n</opencv_storage>\n";
}

TEST_CASE("WILDTRACK XML calibrations: rvec/tvec in cm, the dataset's camera order", "[unit]") {
  TempDir dir;
  const std::filesystem::path cal = dir.path() / "Wildtrack" / "calibrations";
  WriteText((cal / "intrinsic_zero" / "intr_CVLab1.xml").string(), IntrinsicXml(1743.5, 934.5));
  WriteText((cal / "intrinsic_zero" / "intr_CVLab2.xml").string(), IntrinsicXml(1707.3, 978.1));
  WriteText((cal / "extrinsic" / "extr_CVLab1.xml").string(),
            ExtrinsicXml("1.7590990066528320e+00 4.6710100769996643e-01 -3.3169901371002197e-01",
                         "-5.2589416503906250e+02 4.5407634735107422e+01 9.8672351074218750e+02"));
  WriteText((cal / "extrinsic" / "extr_CVLab2.xml").string(),
            ExtrinsicXml("0. 0. 0.", "100. 200. 300."));
  // The parent of calibrations/ and calibrations/ itself both work.
  for (const std::filesystem::path& where : {dir.path() / "Wildtrack", cal}) {
    const ImportedCalibration c = ImportWildtrack(where.string());
    REQUIRE(c.document.cameras.size() == 2);
    CHECK(c.document.names.at(0) == "CVLab1");
    CHECK(c.document.names.at(1) == "CVLab2");
    const geometry::CameraModel& c0 = c.document.cameras[0];
    CHECK(c0.width_px == 1920);
    CHECK(c0.height_px == 1080);
    CHECK(c0.K(0, 0) == Approx(1743.5));
    CHECK(c0.K(1, 2) == Approx(444.39877319335938));
    const Vec3 r(1.7590990066528320, 0.46710100769996643, -0.33169901371002197);
    CHECK(MaxDiff(c0.cam_from_world.rotation, Mat3(Eigen::AngleAxisd(r.norm(), r.normalized()))) <
          1e-12);
    CHECK(MaxDiff(c0.cam_from_world.translation,
                  Vec3(-5.258941650390625, 0.45407634735107422, 9.867235107421875)) < 1e-12);
    CHECK(c.document.cameras[1].cam_from_world.translation == Vec3(1.0, 2.0, 3.0));
  }
  const ImportedCalibration sized = ImportWildtrack(cal.string(), ImageSize{960, 540});
  CHECK(sized.document.cameras[1].width_px == 960);
  // An intrinsic file without its extrinsic file.
  WriteText((cal / "intrinsic_zero" / "intr_IDIAP1.xml").string(), IntrinsicXml(1700.0, 960.0));
  CHECK_THROWS_WITH(ImportWildtrack(cal.string()),
                    Catch::Contains("extr_IDIAP1.xml") && Catch::Contains("does not exist"));
  CHECK_THROWS_WITH(ImportWildtrack(dir.File("nothing")), Catch::Contains("no such file"));
  std::filesystem::create_directories(dir.path() / "empty");
  CHECK_THROWS_WITH(ImportWildtrack((dir.path() / "empty").string()),
                    Catch::Contains("intrinsic_zero/"));
}

TEST_CASE("4D Association, Panoptic and Campus files go through the dataset parsers", "[unit]") {
  TempDir dir;
  WriteText(dir.File("4da.json"), R"({
  "1": {"K": [1000, 0, 516, 0, 1000, 388, 0, 0, 1],
        "RT": [1, 0, 0, 0.5, 0, 0, -1, 1.0, 0, 1, 0, 4.0], "imgSize": [1032, 776]},
  "0": {"K": [1100, 0, 500, 0, 1100, 380, 0, 0, 1],
        "RT": [1, 0, 0, 0, 0, 0, -1, 1.0, 0, 1, 0, 3.0], "imgSize": [1032, 776]}
})");
  const ImportedCalibration fda = ImportFourDAssociation(dir.File("4da.json"));
  REQUIRE(fda.document.cameras.size() == 2);
  CHECK(fda.document.cameras[1].id == 1);
  CHECK(fda.document.cameras[1].cam_from_world.translation == Vec3(0.5, 1.0, 4.0));
  CHECK(fda.document.cameras[0].K(0, 0) == 1100.0);

  WriteText(dir.File("panoptic.json"), R"({"calibDataSource": "test", "cameras": [
  {"name": "01_01", "type": "vga", "resolution": [640, 480], "panel": 1, "node": 1,
   "K": [[700, 0, 320], [0, 700, 240], [0, 0, 1]], "distCoef": [0, 0, 0, 0, 0],
   "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [[0], [0], [100]]},
  {"name": "00_03", "type": "hd", "resolution": [1920, 1080], "panel": 0, "node": 3,
   "K": [[1600, 0, 960], [0, 1600, 540], [0, 0, 1]], "distCoef": [-0.2, 0.1, 0.001, 0.002, 0.01],
   "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [[10], [20], [300]]},
  {"name": "00_00", "type": "hd", "resolution": [1920, 1080], "panel": 0, "node": 0,
   "K": [[1500, 0, 960], [0, 1500, 540], [0, 0, 1]], "distCoef": [0, 0, 0, 0, 0],
   "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [[0], [0], [250]]}]})");
  const ImportedCalibration pan = ImportPanoptic(dir.File("panoptic.json"), {});
  REQUIRE(pan.document.cameras.size() == 2);  // HD only, in index order
  CHECK(pan.document.cameras[0].id == 0);
  CHECK(pan.document.cameras[1].id == 3);
  CHECK(pan.document.names.at(3) == "00_03");
  const geometry::CameraModel& c3 = pan.document.cameras[1];
  CHECK(MaxDiff(c3.cam_from_world.translation, Vec3(0.1, 0.2, 3.0)) < 1e-15);
  CHECK(MaxDiff(c3.cam_from_world.rotation, datasets::PanopticToWorldRotation().transpose()) <
        1e-15);
  CHECK(c3.distortion.k3 == 0.01);
  const ImportedCalibration one = ImportPanoptic(dir.File("panoptic.json"), {"3"});
  REQUIRE(one.document.cameras.size() == 1);
  CHECK(one.document.cameras[0].id == 3);
  CHECK_THROWS_WITH(ImportPanoptic(dir.File("panoptic.json"), {"00_07"}),
                    Catch::Contains("no HD camera named 00_07"));
  CHECK_THROWS_WITH(ImportPanoptic(dir.File("panoptic.json"), {"3", "00_03"}),
                    Catch::Contains("listed twice"));

  WriteText(dir.File("campus.json"), R"({"cameras": {"Camera1": {
  "K": [[1.2, 0, 0.5], [0, 1.5, 0.5], [0, 0, 1]],
  "Tw": [[1, 0, 0, 100], [0, 0, 1, -500], [0, -1, 0, 200], [0, 0, 0, 1]],
  "dist_coeffs": [0, 0, 0, 0]}}})");
  const ImportedCalibration campus = ImportCampus(dir.File("campus.json"));
  REQUIRE(campus.document.cameras.size() == 1);
  CHECK(campus.document.cameras[0].id == 1);
  CHECK(campus.document.cameras[0].K(0, 0) == Approx(1.2 * 360));
  CHECK(campus.document.cameras[0].K(1, 2) == Approx(0.5 * 288));
  CHECK(MaxDiff(campus.document.cameras[0].CenterInWorld(), Vec3(1.0, -5.0, 2.0)) < 1e-12);

  // Errors keep the dataset parser's file and JSON path.
  WriteText(dir.File("4da_bad.json"), R"({"0": {"K": [1, 2], "RT": [], "imgSize": [1, 1]}})");
  CHECK_THROWS_AS(ImportFourDAssociation(dir.File("4da_bad.json")), ConfigError);
  CHECK_THROWS_WITH(ImportFourDAssociation(dir.File("4da_bad.json")),
                    Catch::Contains("4da_bad.json") && Catch::Contains("K"));
}

TEST_CASE("ParseImageSize", "[unit]") {
  const ImageSize s = ParseImageSize("1920x1080", "arg");
  CHECK(s.width_px == 1920);
  CHECK(s.height_px == 1080);
  for (const char* bad : {"1920", "x1080", "1920x", "0x10", "10x-1", "1920X1080", "1e3x10", ""}) {
    INFO(bad);
    CHECK_THROWS_AS(ParseImageSize(bad, "arg"), ConfigError);
  }
}

}  // namespace
}  // namespace mvtrack::config
