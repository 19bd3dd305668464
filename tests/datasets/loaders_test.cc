// The loaders on small synthetic datasets written to a temporary data root: conventions (units,
// axes, frame numbering, calibration formats) checked against geometry constructed here, and
// the error messages on malformed files. Needs no real data.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "data_test_util.h"
#include "datasets/campus.h"
#include "datasets/dataset.h"
#include "datasets/panoptic.h"
#include "datasets/shelf.h"
#include "datasets/wildtrack.h"

namespace mvtrack::datasets {
namespace {

using testing::TempDir;

std::string Num(double v) {
  std::ostringstream os;
  os << std::setprecision(17) << v;
  return os.str();
}

std::string Array(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i > 0 ? ", " : "") + Num(v[i]);
  return s + "]";
}

std::string Matrix(const Mat3& m) {
  std::string s = "[";
  for (int r = 0; r < 3; ++r) {
    s += (r > 0 ? ", " : "") + Array({m(r, 0), m(r, 1), m(r, 2)});
  }
  return s + "]";
}

// Pinhole projection computed independently of CameraModel.
Vec2 Pinhole(const Mat3& K, const Mat3& R, const Vec3& t, const Vec3& X) {
  const Vec3 x = K * (R * X + t);
  return x.head<2>() / x.z();
}

// A camera looking horizontally along +y from (0.5, -4, 1.6) (z up), 1032x776.
struct TestCamera {
  Mat3 K;
  Mat3 R;  // cam_from_world
  Vec3 t;  // metres
};

TestCamera MakeTestCamera() {
  TestCamera c;
  c.K << 1000.0, 0.0, 516.0, 0.0, 990.0, 388.0, 0.0, 0.0, 1.0;
  // Camera axes in world coordinates: x_cam = +x, y_cam = -z (down), z_cam = +y (forward),
  // then a small yaw so that nothing is axis-aligned.
  Mat3 base;
  base << 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0;
  c.R = base * Eigen::AngleAxisd(0.2, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre(0.5, -4.0, 1.6);
  c.t = -c.R * centre;
  return c;
}

std::string ShelfCalibration(const TestCamera& c) {
  std::vector<double> rt;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) rt.push_back(c.R(r, k));
    rt.push_back(c.t(r));
  }
  std::vector<double> k(c.K.data(), c.K.data() + 9);
  const Mat3 kt = c.K.transpose();  // row-major
  k.assign(kt.data(), kt.data() + 9);
  return "{\n\t\"0\": \n\t{\n\t\t\"K\" : " + Array(k) + ",\n\t\t\"RT\" : " + Array(rt) +
         ",\n\t\t\"imgSize\" : [1032, 776]\n\t}\n}\n";
}

// A 15-joint gt.txt person (rows x, y, z, valid) standing at (x0, y0).
std::string GtPerson(int id, double x0, double y0) {
  std::string s = std::to_string(id) + "\n";
  for (int r = 0; r < 4; ++r) {
    for (int j = 0; j < 15; ++j) {
      double v = 1.0;
      if (r == 0) v = x0 + 0.01 * j;
      if (r == 1) v = y0 - 0.02 * j;
      if (r == 2) v = 0.1 * j;
      s += Num(v) + (j < 14 ? " " : "\n");
    }
  }
  return s;
}

std::string Body25Person(const std::vector<double>& scores) {
  std::string s = "{\"keypoints\": [";
  for (int j = 0; j < 25; ++j) {
    const double score = scores[static_cast<std::size_t>(j)];
    s += (j > 0 ? ", " : "") +
         (score > 0.0 ? Array({100.0 + 2.0 * j, 200.0 + 10.0 * j, score}) : Array({0, 0, 0}));
  }
  return s + "], \"bbox_from_keypoints\": [0, 0, 1, 1], \"num_joints\": 25}";
}

void WriteMiniShelf(const TempDir& dir) {
  const TestCamera cam = MakeTestCamera();
  dir.Write("shelf/4d_association/calibration.json", ShelfCalibration(cam));
  dir.Write("shelf/4d_association/gt.txt",
            "15 2\n2\n" + GtPerson(0, 0.0, 1.0) + GtPerson(3, 1.0, 2.0) + "0\n");
  std::vector<double> scores(25, 0.5);
  scores[3] = 0.0;
  scores[4] = 1.02;  // OpenPose scores may exceed 1 slightly
  dir.Write("shelf/derived/persons2d_body25_cam0.json",
            "{\"camera\": 0, \"image_size\": [1032, 776], \"frames\": [{\"frame_index\": 0, "
            "\"persons\": [" +
                Body25Person(scores) + "]}, {\"frame_index\": 1, \"persons\": []}]}");
}

TEST_CASE("LoadShelf on a synthetic Shelf: calibration, frame offset 300, BODY25, shelf14",
          "[unit]") {
  TempDir dir;
  WriteMiniShelf(dir);
  const TestCamera cam = MakeTestCamera();
  const Dataset ds = LoadShelf(dir.path());
  CHECK(ds.name == "shelf");
  REQUIRE(ds.cameras.size() == 1);
  CHECK(ds.cameras[0].width_px == 1032);
  CHECK(ds.cameras[0].height_px == 776);
  CHECK((ds.cameras[0].K - cam.K).norm() < 1e-12);
  CHECK((ds.cameras[0].cam_from_world.rotation - cam.R).norm() < 1e-12);
  CHECK((ds.cameras[0].cam_from_world.translation - cam.t).norm() < 1e-12);
  CHECK(ds.cameras[0].distortion.IsZero());
  CHECK(ds.fps == 25.0);

  REQUIRE(ds.detections.size() == 2);
  REQUIRE(ds.detections[0].size() == 1);
  CHECK(ds.detections[0][0].frame == 300);
  CHECK(ds.detections[1][0].frame == 301);
  CHECK(ds.detections[1][0].utime == 12'040'000);
  REQUIRE(ds.detections[0][0].detections.size() == 1);
  CHECK(ds.detections[1][0].detections.empty());
  const core::Detection2D& d = ds.detections[0][0].detections[0];
  CHECK(d.layout == core::KeypointLayoutId::kBody25);
  REQUIRE(d.keypoints.size() == 25);
  CHECK(d.keypoints[3].confidence == 0.0);
  CHECK(d.keypoints[4].confidence == 1.0);  // clamped
  CHECK(d.keypoints[24].position_px.y() == Approx(440.0));
  // Detected keypoints span x [100, 148], y [200, 440]: the box adds 24 px on every side.
  CHECK(d.box.x_min == Approx(100.0 - 24.0));
  CHECK(d.box.y_max == Approx(440.0 + 24.0));
  CHECK(d.score == Approx((23 * 0.5 + 1.0) / 24.0));
  CHECK(ds.source_ids[0][0] == std::vector<std::int64_t>{kUnknownSourceId});

  REQUIRE(ds.ground_truth.size() == 2);
  CHECK(ds.gt_layout == core::KeypointLayoutId::kShelf14);
  CHECK(ds.ground_truth[0].frame == 300);
  REQUIRE(ds.ground_truth[0].objects.size() == 2);
  CHECK(ds.ground_truth[1].objects.empty());
  const eval::EvalObject& person = ds.ground_truth[0].objects[1];
  CHECK(person.id == 3);
  REQUIRE(person.joints.size() == 14);  // pelvis dropped
  REQUIRE(person.joints[13].has_value());
  CHECK((*person.joints[13] - Vec3(1.13, 2.0 - 0.26, 1.3)).norm() < 1e-12);
  // Footprint: midpoint of joints 2 and 3 on the ground.
  CHECK((person.position - Vec3(1.025, 2.0 - 0.05, 0.0)).norm() < 1e-12);
  CHECK(ds.protocol_frames.size() == 1);
  CHECK(ds.protocol_frames[0].first == 300);
  CHECK(ds.protocol_frames[0].last == 301);
  CHECK(ds.protocol_actor_ids == std::vector<std::int64_t>{0, 1, 2});
}

// SKEL19 person with joint j at p(j) = (j, j^2, 0.1 j + 1) (confidence 1 unless listed).
std::string Skel19Person(int id, const std::vector<int>& missing) {
  std::string s = std::to_string(id) + "\n";
  for (int r = 0; r < 4; ++r) {
    for (int j = 0; j < 19; ++j) {
      double v = 0.0;
      const bool absent = std::find(missing.begin(), missing.end(), j) != missing.end();
      if (r == 0) v = absent ? 0.0 : j;
      if (r == 1) v = absent ? 0.0 : static_cast<double>(j * j);
      if (r == 2) v = absent ? 0.0 : 0.1 * j + 1.0;
      if (r == 3) v = absent ? 0.0 : 1.0;
      s += Num(v) + (j < 18 ? " " : "\n");
    }
  }
  return s;
}

Vec3 P19(int j) { return Vec3(j, j * j, 0.1 * j + 1.0); }

TEST_CASE("LoadShelfPeer4DA maps SKEL19 to shelf14 as 4D Association's evaluation", "[unit]") {
  TempDir dir;
  std::vector<int> all(19);
  for (int j = 0; j < 19; ++j) all[static_cast<std::size_t>(j)] = j;
  dir.Write(
      "shelf/4d_association/skel.txt",
      "19 2\n2\n" + Skel19Person(4, {9}) + Skel19Person(1, all) + "1\n" + Skel19Person(7, {}));
  const PeerOutput peer = LoadShelfPeer4DA(dir.path());
  CHECK(peer.name == "4d_association");
  CHECK(peer.native_layout == core::KeypointLayoutId::kNone);
  REQUIRE(peer.native_joint_names.size() == 19);
  CHECK(peer.native_joint_names[13] == "r_ankle");
  REQUIRE(peer.shelf14.size() == 2);
  CHECK(peer.shelf14[0].frame == 300);
  // The all-missing skeleton (id 1) is left out; ids are dense in order of appearance.
  REQUIRE(peer.shelf14[0].objects.size() == 1);
  REQUIRE(peer.native[0].objects.size() == 1);
  CHECK(peer.original_ids == std::vector<std::uint64_t>{4, 7});
  CHECK(peer.shelf14[0].objects[0].id == 1);
  CHECK(peer.shelf14[1].objects[0].id == 2);

  // Limbs: shelf14 joint k comes from SKEL19 joint kFrom[k].
  const int kFrom[12] = {13, 7, 2, 3, 8, 14, 15, 11, 5, 6, 12, 16};
  const eval::EvalObject& full = peer.shelf14[1].objects[0];
  REQUIRE(full.joints.size() == 14);
  for (int k = 0; k < 12; ++k) {
    REQUIRE(full.joints[static_cast<std::size_t>(k)].has_value());
    CHECK((*full.joints[static_cast<std::size_t>(k)] - P19(kFrom[k])).norm() < 1e-12);
  }
  // Head: bottom = shoulder_mid + 0.5 (ear_mid - shoulder_mid); top = bottom + 0.125 face +
  // 0.145 z with face = normalize((neck - mid_hip) x (r_shoulder - l_shoulder)).
  const Vec3 shoulder_mid = 0.5 * (P19(5) + P19(6));
  const Vec3 ear_mid = 0.5 * (P19(9) + P19(10));
  const Vec3 bottom = shoulder_mid + 0.5 * (ear_mid - shoulder_mid);
  const Vec3 face = (P19(1) - P19(0)).cross(P19(5) - P19(6)).normalized();
  REQUIRE(full.joints[12].has_value());
  REQUIRE(full.joints[13].has_value());
  CHECK((*full.joints[12] - bottom).norm() < 1e-12);
  CHECK((*full.joints[13] - (bottom + 0.125 * face + 0.145 * Vec3::UnitZ())).norm() < 1e-12);
  // Footprint: hip midpoint (SKEL19 joints 2, 3) on the ground.
  CHECK((full.position - Vec3(2.5, 6.5, 0.0)).norm() < 1e-12);

  // Id 4 misses its right ear (joint 9): no head joints, limbs still present.
  const eval::EvalObject& partial = peer.shelf14[0].objects[0];
  CHECK_FALSE(partial.joints[12].has_value());
  CHECK_FALSE(partial.joints[13].has_value());
  CHECK(partial.joints[0].has_value());
  CHECK_FALSE(peer.native[0].objects[0].joints[9].has_value());
}

// A Campus-format camera: K normalised by 360x288, Tw = world_from_camera with the centre in cm.
std::string CampusCalibration(const Mat3& K, const Mat3& R, const Vec3& centre_m) {
  Mat3 kn = K;
  kn.row(0) /= 360.0;
  kn.row(1) /= 288.0;
  const Mat3 rt = R.transpose();
  std::string tw = "[";
  for (int r = 0; r < 3; ++r) {
    tw += Array({rt(r, 0), rt(r, 1), rt(r, 2), 100.0 * centre_m(r)}) + ", ";
  }
  tw += "[0.0, 0.0, 0.0, 1.0]]";
  return "{\"cameras\": {\"Camera0\": {\"K\": " + Matrix(kn) + ", \"Tw\": " + tw +
         ", \"dist_coeffs\": [-0.2, 0.1, 0, 0]}}}";
}

TEST_CASE("LoadCampus on a synthetic Campus: K de-normalised, Tw inverted, cm, 25 fps", "[unit]") {
  TempDir dir;
  Mat3 K;
  K << 438.0, 0.0, 185.4, 0.0, 437.0, 139.3, 0.0, 0.0, 1.0;
  Mat3 base;
  base << 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0;
  const Mat3 R = base * Eigen::AngleAxisd(-0.3, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre(1.0, -6.0, 1.9);
  const Vec3 t = -R * centre;
  dir.Write("campus/crossview_longcw/calibration.json", CampusCalibration(K, R, centre));

  // One person at frame 1 (timestamp 0.04 s); joints in cm.
  std::vector<Vec3> joints_m;
  for (int j = 0; j < 14; ++j) {
    joints_m.push_back(Vec3(0.3 + 0.02 * j, 1.0 - 0.01 * j, 0.12 * j));
  }
  std::string points_3d = "[", points_2d = "[", scores = "[";
  for (int j = 0; j < 14; ++j) {
    const Vec3& X = joints_m[static_cast<std::size_t>(j)];
    const Vec2 x = Pinhole(K, R, t, X);
    points_3d += (j > 0 ? ", " : "") + Array({100.0 * X.x(), 100.0 * X.y(), 100.0 * X.z()});
    points_2d += (j > 0 ? ", " : "") + Array({x.x(), x.y()});
    scores += std::string(j > 0 ? ", " : "") + "1.0";
  }
  points_3d += "]";
  points_2d += "]";
  scores += "]";
  dir.Write("campus/crossview_longcw/annotation_3d.json",
            "[{\"timestamp\": 0.0, \"poses\": []}, {\"timestamp\": 0.04, \"poses\": [{\"id\": 2, "
            "\"points_3d\": " +
                points_3d + ", \"scores\": " + scores + "}]}]");
  dir.Write("campus/crossview_longcw/annotation_2d.json",
            "{\"image_wh\": [360, 288], \"frames\": {\"Camera0/0000.000.jpg\": {\"camera\": "
            "\"Camera0\", \"timestamp\": 0.0, \"poses\": []}, \"Camera0/0000.040.jpg\": "
            "{\"camera\": \"Camera0\", \"timestamp\": 0.04, \"poses\": [{\"id\": 2, "
            "\"points_2d\": " +
                points_2d + ", \"scores\": " + scores + "}]}}}");

  CampusOptions options;
  options.corruption = CorruptionOptions::Clean();
  const Dataset ds = LoadCampus(dir.path(), options);
  REQUIRE(ds.cameras.size() == 1);
  const geometry::CameraModel& camera = ds.cameras[0];
  CHECK(camera.width_px == 360);
  CHECK(camera.height_px == 288);
  CHECK((camera.K - K).norm() < 1e-9);
  CHECK((camera.cam_from_world.rotation - R).norm() < 1e-12);
  CHECK((camera.CenterInWorld() - centre).norm() < 1e-12);
  CHECK(camera.distortion.IsZero());  // dist_coeffs are not applied
  REQUIRE(ds.detections.size() == 2);
  CHECK(ds.detections[1][0].frame == 1);
  CHECK(ds.detections[1][0].utime == 40'000);
  REQUIRE(ds.detections[1][0].detections.size() == 1);
  CHECK(ds.source_ids[1][0] == std::vector<std::int64_t>{2});
  const core::Detection2D& d = ds.detections[1][0].detections[0];
  CHECK(d.layout == core::KeypointLayoutId::kShelf14);
  REQUIRE(ds.ground_truth.size() == 2);
  REQUIRE(ds.ground_truth[1].objects.size() == 1);
  const eval::EvalObject& gt = ds.ground_truth[1].objects[0];
  CHECK(gt.id == 2);
  for (std::size_t j = 0; j < 14; ++j) {
    REQUIRE(gt.joints[j].has_value());
    CHECK((*gt.joints[j] - joints_m[j]).norm() < 1e-12);  // cm -> m
    // The loaded camera reproduces the 2D annotation from the loaded 3D ground truth.
    const std::optional<Vec2> px = camera.Project(*gt.joints[j]);
    REQUIRE(px.has_value());
    CHECK((*px - d.keypoints[j].position_px).norm() < 1e-9);
  }
  CHECK(ds.protocol_frames.size() == 2);
  CHECK(ds.protocol_notes.find("clean") != std::string::npos);
}

TEST_CASE("LoadWildtrack and WildtrackGroundPoints on a synthetic WILDTRACK", "[unit]") {
  TempDir dir;
  Mat3 K;
  K << 1700.0, 0.0, 950.0, 0.0, 1710.0, 540.0, 0.0, 0.0, 1.0;
  const Vec3 rvec(1.7, 0.4, -0.3);
  const Mat3 R = Eigen::AngleAxisd(rvec.norm(), rvec.normalized()).toRotationMatrix();
  const Vec3 t_cm(-500.0, 50.0, 1000.0);
  const std::string camera =
      "{\"index\": 0, \"name\": \"CVLab1\", \"K\": " + Matrix(K) +
      ", \"dist\": [0, 0, 0, 0, 0], \"rvec\": " + Array({rvec.x(), rvec.y(), rvec.z()}) +
      ", \"tvec_cm\": " + Array({t_cm.x(), t_cm.y(), t_cm.z()}) + ", \"R\": " + Matrix(R) + "}";
  dir.Write(
      "wildtrack/derived/calibration_wildtrack.json",
      "{\"image_size\": [1920, 1080], \"world_units\": \"cm\", \"cameras\": [" + camera + "]}");
  // H = K [r1 r2 t] maps ground (x, y, 1) in cm to pixels.
  Mat3 H;
  H.col(0) = K * R.col(0);
  H.col(1) = K * R.col(1);
  H.col(2) = K * t_cm;
  dir.Write("wildtrack/rest/metainfo.json",
            "{\"sequence1\": {\"cam_nbr\": 1, \"homography\": [" + Matrix(H) + "]}}");
  // A person standing at (2.0, 3.0) m: box bottom centre at the projection of that point.
  const Vec3 foot_cm(200.0, 300.0, 0.0);
  const Vec3 x = K * (R * foot_cm + t_cm);
  const Vec2 foot_px = x.head<2>() / x.z();
  const double w = 60.0, h = 200.0;
  dir.Write("wildtrack/rest/MVDeTr_test.json",
            "{\"361\": [" + Array({foot_px.x() - w / 2, foot_px.y() - h, w, h, -1, 0}) +
                "], \"360\": []}");

  const Dataset ds = LoadWildtrack(dir.path());
  REQUIRE(ds.cameras.size() == 1);
  CHECK((ds.cameras[0].cam_from_world.rotation - R).norm() < 1e-12);
  CHECK((ds.cameras[0].cam_from_world.translation - 0.01 * t_cm).norm() < 1e-12);
  CHECK(ds.fps == 2.0);
  REQUIRE(ds.detections.size() == 2);
  CHECK(ds.detections[0][0].frame == 360);
  CHECK(ds.detections[1][0].frame == 361);
  CHECK(ds.detections[1][0].utime == 180'500'000);
  REQUIRE(ds.detections[1][0].detections.size() == 1);
  const core::Detection2D& d = ds.detections[1][0].detections[0];
  CHECK(d.layout == core::KeypointLayoutId::kNone);
  CHECK(d.keypoints.empty());
  CHECK(d.score == 1.0);
  CHECK(d.box.width() == Approx(w));
  CHECK((d.box.bottom_center() - foot_px).norm() < 1e-9);
  CHECK(ds.ground_truth.empty());
  CHECK(ds.gt_layout == core::KeypointLayoutId::kNone);

  const std::vector<WildtrackGroundFrame> ground = WildtrackGroundPoints(dir.path());
  REQUIRE(ground.size() == 2);
  CHECK(ground[0].points.empty());
  REQUIRE(ground[1].points.size() == 1);
  CHECK((ground[1].points[0].position_m - Vec3(2.0, 3.0, 0.0)).norm() < 1e-9);
  CHECK(ground[1].points[0].num_views == 1);

  // Ground truth (mvdet/gt.txt, `image_frame grid_x grid_y`): image frame 1805 = annotated
  // frame 361; cell (200, 480) = (-3 + 5, -9 + 12) = (2, 3) m.
  CHECK_FALSE(HasWildtrackGroundTruth(dir.path()));
  dir.Write("wildtrack/mvdet/gt.txt", "1800 0 0\n1805 200 480\n1805 479 1439\n\n");
  CHECK(HasWildtrackGroundTruth(dir.path()));
  const Dataset with_gt = LoadWildtrack(dir.path());
  REQUIRE(with_gt.ground_truth.size() == 2);
  CHECK(with_gt.ground_truth[0].frame == 360);
  REQUIRE(with_gt.ground_truth[0].objects.size() == 1);
  CHECK((with_gt.ground_truth[0].objects[0].position - Vec3(-3.0, -9.0, 0.0)).norm() < 1e-12);
  REQUIRE(with_gt.ground_truth[1].objects.size() == 2);
  CHECK(with_gt.ground_truth[1].objects[0].id == 0);
  CHECK(with_gt.ground_truth[1].objects[1].id == 1);
  CHECK((with_gt.ground_truth[1].objects[0].position - Vec3(2.0, 3.0, 0.0)).norm() < 1e-12);
  CHECK((with_gt.ground_truth[1].objects[1].position - Vec3(8.975, 26.975, 0.0)).norm() < 1e-9);
  for (const char* bad :
       {"1800 0\n", "1801 0 0\n", "1800 480 0\n", "1800 0 -1\n", "1800 0 0 7\n", "x 0 0\n"}) {
    dir.Write("wildtrack/mvdet/gt.txt", bad);
    INFO(bad);
    CHECK_THROWS_AS(WildtrackGroundTruth(dir.path(), 360, 360), DatasetError);
  }
}

TEST_CASE("MergeGroundPoints merges across views within the radius only", "[unit]") {
  // Person A seen by cameras 0, 1, 2 within a few cm; person B 0.25 m away seen by 0 and 3; a
  // second camera-0 point near A (a different person in the same view, 0.12 m from A's
  // camera-0 point, > 0.1 m from the others) must stay apart.
  const std::vector<Vec2> points = {{1.00, 1.00},
                                    {1.03, 0.99},
                                    {0.98, 1.02},
                                    {1.25, 1.00},
                                    {1.27, 1.01},
                                    {1.02, 1.12},
                                    {5.0, 5.0}};
  const std::vector<int> cameras = {0, 1, 2, 0, 3, 0, 4};
  const std::vector<WildtrackGroundPoint> merged = MergeGroundPoints(points, cameras, 0.1);
  REQUIRE(merged.size() == 4);
  // Sorted by x: A (3 views), the lone camera-0 point at 1.02, B (2 views), the far point.
  CHECK(merged[0].num_views == 3);
  CHECK((merged[0].position_m - Vec3(1.0033333333333332, 1.0033333333333332, 0.0)).norm() < 1e-12);
  CHECK(merged[1].num_views == 1);
  CHECK(merged[1].position_m.x() == Approx(1.02));
  CHECK(merged[2].num_views == 2);
  CHECK(merged[2].position_m.x() == Approx(1.26));
  CHECK(merged[3].num_views == 1);
  // A radius of 0 merges nothing; a huge one merges everything compatible (camera 0 appears
  // three times, so at least three clusters remain).
  CHECK(MergeGroundPoints(points, cameras, 0.0).size() == points.size());
  const std::vector<WildtrackGroundPoint> all = MergeGroundPoints(points, cameras, 100.0);
  CHECK(all.size() == 3);
  int views = 0;
  for (const WildtrackGroundPoint& p : all) views += p.num_views;
  CHECK(views == 7);
}

// --- Malformed files ---------------------------------------------------------------------------

template <typename F>
DatasetError CatchDatasetError(F&& f) {
  try {
    f();
  } catch (const DatasetError& e) {
    return e;
  }
  FAIL("no DatasetError thrown");
  return DatasetError("", "");
}

TEST_CASE("A JSON syntax error names the file and the line", "[unit]") {
  TempDir dir;
  dir.Write("shelf/4d_association/calibration.json", "{\n  \"0\": {\n    \"K\": [1, 2,\n");
  const DatasetError e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.file() == (dir.path() / "shelf/4d_association/calibration.json").string());
  CHECK(e.problem().find("not valid JSON") != std::string::npos);
  CHECK(std::string(e.what()).find("calibration.json") != std::string::npos);
}

TEST_CASE("A missing member, a wrong type and a quoted number are reported with their path",
          "[unit]") {
  TempDir dir;
  dir.Write("shelf/4d_association/calibration.json",
            "{\"0\": {\"K\": [1, 0, 0, 0, 1, 0, 0, 0, 1], \"imgSize\": [10, 10]}}");
  DatasetError e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("$.0: missing member \"RT\"") != std::string::npos);
  CHECK(e.problem().find("1:") == 0);  // line:column of the object

  dir.Write("shelf/4d_association/calibration.json",
            "{\"0\": {\"K\": [1, 0, 0, \"abc\", 1, 0, 0, 0, 1], \"RT\": [], \"imgSize\": [10, "
            "10]}}");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("$.0.K[3]: expected a number") != std::string::npos);

  dir.Write("shelf/4d_association/calibration.json",
            "{\"0\": {\"K\": [1, 0, 0, 0, \"1.0\", 0, 0, 0, 1], \"RT\": [], \"imgSize\": [10, "
            "10]}}");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("$.0.K[4]: expected a number") != std::string::npos);

  dir.Write("shelf/4d_association/calibration.json",
            "{\"0\": {\"K\": [1, 0, 0, 0, 1, 0, 0, 0, 1], \"RT\": [1, 0, 0, 0, 0, 1, 0, 0], "
            "\"imgSize\": [10, 10]}}");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("$.0.RT: expected an array of 12 numbers, got 8 entries") !=
        std::string::npos);
}

TEST_CASE("A missing file and an invalid calibration are reported", "[unit]") {
  TempDir dir;
  DatasetError e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.file() == (dir.path() / "shelf/4d_association/calibration.json").string());
  CHECK(e.problem().find("file not found") != std::string::npos);

  // A reflection is not a rotation.
  dir.Write("shelf/4d_association/calibration.json",
            "{\"0\": {\"K\": [1000, 0, 500, 0, 1000, 400, 0, 0, 1], \"RT\": [-1, 0, 0, 0, 0, 1, "
            "0, 0, 0, 0, 1, 0], \"imgSize\": [1032, 776]}}");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("camera \"0\": invalid calibration") != std::string::npos);
}

TEST_CASE("Malformed skeleton text files are reported with the line", "[unit]") {
  TempDir dir;
  WriteMiniShelf(dir);
  dir.Write("shelf/4d_association/gt.txt", "15 2\n1\n0\n1 2 3\n");
  DatasetError e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.file() == (dir.path() / "shelf/4d_association/gt.txt").string());
  CHECK(e.problem().find("line 5: unexpected end of file, expected x of joint 3") !=
        std::string::npos);

  dir.Write("shelf/4d_association/gt.txt", "15 1\n1\n0\n" + std::string("1 x\n"));
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("line 4: expected x of joint 1 of person 0 in frame 0") !=
        std::string::npos);

  dir.Write("shelf/4d_association/gt.txt", "14 1\n0\n");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("expected 15 joints") != std::string::npos);

  dir.Write("shelf/4d_association/gt.txt", "15 1\n2\n" + GtPerson(1, 0, 0) + GtPerson(1, 1, 1));
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("person id 1 appears twice in frame 0") != std::string::npos);

  dir.Write("shelf/4d_association/gt.txt", "15 1\n0\n7\n");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.problem().find("unexpected content after the last frame") != std::string::npos);

  // The detection file disagrees with gt.txt on the number of frames.
  dir.Write("shelf/4d_association/gt.txt", "15 3\n0\n0\n0\n");
  e = CatchDatasetError([&] { LoadShelf(dir.path()); });
  CHECK(e.file() == (dir.path() / "shelf/derived/persons2d_body25_cam0.json").string());
  CHECK(e.problem().find("2 frames, but gt.txt has 3") != std::string::npos);
}

TEST_CASE("Malformed Campus, WILDTRACK and Panoptic inputs are reported", "[unit]") {
  TempDir dir;
  // Campus: a timestamp off the 25 fps grid.
  dir.Write("campus/crossview_longcw/annotation_2d.json",
            "{\"image_wh\": [360, 288], \"frames\": {}}");
  Mat3 K;
  K << 400.0, 0.0, 180.0, 0.0, 400.0, 144.0, 0.0, 0.0, 1.0;
  dir.Write("campus/crossview_longcw/calibration.json",
            CampusCalibration(K, Mat3::Identity(), Vec3(0, 0, -5)));
  dir.Write("campus/crossview_longcw/annotation_3d.json",
            "[{\"timestamp\": 0.0, \"poses\": []}, {\"timestamp\": 0.05, \"poses\": []}]");
  DatasetError e = CatchDatasetError([&] { LoadCampus(dir.path()); });
  CHECK(e.file() == (dir.path() / "campus/crossview_longcw/annotation_3d.json").string());
  CHECK(e.problem().find("$[1].timestamp: timestamp 0.050000 s is not on the 25 fps grid") !=
        std::string::npos);
  // Campus: a pose with 13 points.
  dir.Write("campus/crossview_longcw/annotation_3d.json",
            "[{\"timestamp\": 0.0, \"poses\": [{\"id\": 0, \"points_3d\": [[0, 0, 0]], "
            "\"scores\": [1]}]}]");
  e = CatchDatasetError([&] { LoadCampus(dir.path()); });
  CHECK(e.problem().find("$[0].poses[0].points_3d: expected a 14x3 matrix, got 1 rows") !=
        std::string::npos);
  // Campus: invalid options.
  CampusOptions bad;
  bad.corruption.miss_rate = 2.0;
  e = CatchDatasetError([&] { LoadCampus(dir.path(), bad); });
  CHECK(e.problem().find("miss_rate") != std::string::npos);

  // WILDTRACK: a box with 5 numbers.
  dir.Write("wildtrack/derived/calibration_wildtrack.json",
            "{\"image_size\": [1920, 1080], \"world_units\": \"cm\", \"cameras\": [{\"index\": 0, "
            "\"K\": [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]], \"dist\": [0, 0, 0, 0, 0], "
            "\"rvec\": [0, 0, 0], \"tvec_cm\": [0, 0, 500], \"R\": [[1, 0, 0], [0, 1, 0], [0, 0, "
            "1]]}]}");
  dir.Write("wildtrack/rest/MVDeTr_test.json", "{\"360\": [[1, 2, 3, 4, 0]]}");
  e = CatchDatasetError([&] { LoadWildtrack(dir.path()); });
  CHECK(e.problem().find("$.360[0]: expected an array of 6 numbers, got 5 entries") !=
        std::string::npos);
  // WILDTRACK: a camera index out of range.
  dir.Write("wildtrack/rest/MVDeTr_test.json", "{\"360\": [[1, 2, 3, 4, -1, 7]]}");
  e = CatchDatasetError([&] { LoadWildtrack(dir.path()); });
  CHECK(e.problem().find("is not one of the 1 cameras") != std::string::npos);
  // WILDTRACK: R inconsistent with rvec.
  dir.Write("wildtrack/derived/calibration_wildtrack.json",
            "{\"image_size\": [1920, 1080], \"world_units\": \"cm\", \"cameras\": [{\"index\": 0, "
            "\"K\": [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]], \"dist\": [0, 0, 0, 0, 0], "
            "\"rvec\": [0.1, 0, 0], \"tvec_cm\": [0, 0, 500], \"R\": [[1, 0, 0], [0, 1, 0], [0, "
            "0, 1]]}]}");
  e = CatchDatasetError([&] { LoadWildtrack(dir.path()); });
  CHECK(e.problem().find("R differs from Rodrigues(rvec)") != std::string::npos);

  // Panoptic: invalid options, and a missing calibration.
  PanopticOptions options;
  options.cameras = {"00_99"};
  e = CatchDatasetError([&] { LoadPanoptic(dir.path(), options); });
  CHECK(e.problem().find("00_99") != std::string::npos);
  e = CatchDatasetError([&] { LoadPanoptic(dir.path()); });
  CHECK(e.file() == (dir.path() / "panoptic/160906_band2/calibration_160906_band2.json").string());
}

}  // namespace
}  // namespace mvtrack::datasets
