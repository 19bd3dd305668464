// EPFL Terrace 1 on the real data (../shared/data/epfl or $MVTRACK_DATA/epfl); the test cases
// skip with a warning when the dataset is missing, and fail instead when CI is set. Figures from
// SOURCE.md: frames 59-4887 with people, 9 ids, 25,754 person-frames; focal lengths 420-447 px;
// people about 93 floor units tall (1.7 m: 0.0183 m per unit).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "data_test_util.h"
#include "datasets/epfl.h"

namespace mvtrack::datasets {
namespace {

struct Loaded {
  Dataset ds;
  EpflCalibration calibration;
};

const Loaded& Clean() {
  static const Loaded loaded = [] {
    Loaded l;
    EpflOptions options;
    options.corruption = CorruptionOptions::Clean();
    l.ds = LoadEpflTerrace(DefaultDataRoot(), options, &l.calibration);
    return l;
  }();
  return loaded;
}

TEST_CASE("EPFL Terrace real data (skipped without ../shared/data/epfl): sizes, ids, frames",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "epfl");
  const Dataset& ds = Clean().ds;
  CHECK(ds.name == "epfl/terrace1");
  CHECK(ds.fps == 25.0);
  REQUIRE(ds.cameras.size() == 4);
  for (std::size_t c = 0; c < 4; ++c) {
    CHECK(ds.cameras[c].id == static_cast<CameraId>(c));
    CHECK(ds.cameras[c].width_px == 360);
    CHECK(ds.cameras[c].height_px == 288);
    CHECK(ds.cameras[c].Validate(nullptr));
  }
  REQUIRE(ds.detections.size() == 4887 - 59 + 1);
  REQUIRE(ds.ground_truth.size() == ds.detections.size());
  CHECK(ds.detections.front()[0].frame == 59);
  CHECK(ds.detections.back()[3].frame == 4887);
  CHECK(ds.detections[41][2].utime == 4'000'000);  // frame 100 at 25 fps
  REQUIRE(ds.protocol_frames.size() == 1);
  CHECK(ds.protocol_frames[0].first == 59);
  CHECK(ds.protocol_frames[0].last == 4887);
  CHECK(ds.gt_layout == core::KeypointLayoutId::kNone);
  // Detections: box-only, score 1, inside the image, source ids = person ids; per camera the
  // gt.txt rows with lost = 0 (c0 23,492, c1 24,834, c2 23,118, c3 20,571).
  std::vector<int> per_camera(4, 0);
  std::set<std::int64_t> ids;
  for (std::size_t f = 0; f < ds.detections.size(); ++f) {
    for (std::size_t c = 0; c < 4; ++c) {
      REQUIRE(ds.source_ids[f][c].size() == ds.detections[f][c].detections.size());
      for (std::size_t i = 0; i < ds.source_ids[f][c].size(); ++i) {
        const core::Detection2D& d = ds.detections[f][c].detections[i];
        CHECK(d.layout == core::KeypointLayoutId::kNone);
        CHECK(d.keypoints.empty());
        CHECK(d.score == 1.0);
        CHECK(d.box.x_min >= 0.0);
        CHECK(d.box.x_max <= 360.0);
        CHECK(d.box.y_max <= 288.0);
        ids.insert(ds.source_ids[f][c][i]);
        ++per_camera[c];
      }
    }
  }
  CHECK(per_camera == std::vector<int>{23492, 24834, 23118, 20571});
  CHECK(ids == std::set<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8});
  // Ground truth: every person annotated in a camera, once, on the floor.
  std::int64_t person_frames = 0;
  std::set<std::int64_t> gt_ids;
  for (std::size_t f = 0; f < ds.ground_truth.size(); ++f) {
    CHECK(ds.ground_truth[f].frame == ds.detections[f][0].frame);
    std::set<std::int64_t> in_frame;
    for (std::size_t c = 0; c < 4; ++c) {
      in_frame.insert(ds.source_ids[f][c].begin(), ds.source_ids[f][c].end());
    }
    std::set<std::int64_t> gt_in_frame;
    for (const eval::EvalObject& o : ds.ground_truth[f].objects) {
      CHECK(o.position.z() == 0.0);
      CHECK(o.joints.empty());
      gt_in_frame.insert(o.id);
      gt_ids.insert(o.id);
    }
    CHECK(gt_in_frame == in_frame);
    person_frames += static_cast<std::int64_t>(ds.ground_truth[f].objects.size());
  }
  CHECK(person_frames == 25754);
  CHECK(gt_ids == ids);
  CHECK_THAT(ds.protocol_notes, Catch::Contains("25754 person-frames"));
}

TEST_CASE("EPFL Terrace real data: the cameras from the homographies, the unit from 1.7 m",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "epfl");
  const Loaded& l = Clean();
  const EpflCalibration& cal = l.calibration;
  REQUIRE(cal.cameras.size() == 4);
  REQUIRE(cal.person_height.ok);
  CHECK(cal.unit_estimated);
  // SOURCE.md: about 93 units tall (p10-p90 86-96) over about 90,000 boxes: 0.0183 m per unit.
  CHECK(cal.person_height.median_height == Approx(93.0).margin(2.0));
  CHECK(cal.person_height.p10_height > 80.0);
  CHECK(cal.person_height.p90_height < 100.0);
  CHECK(cal.person_height.boxes_used > 80000);
  CHECK(cal.floor_unit_m == Approx(0.0183).margin(0.0005));
  CHECK(cal.floor_unit_m == Approx(1.7 / cal.person_height.median_height));
  for (const geometry::FloorHomographyCamera& c : cal.cameras) {
    INFO("camera " << c.camera.id);
    CHECK(c.ok);
    CHECK(c.mirrored_y == cal.mirrored_y);
    // SOURCE.md: 420-447 px (measured here: 446.9, 420.2, 431.4, 432.8 px refined from the
    // closed-form 442.2, 420.2, 439.6, 454.7 px).
    CHECK(c.focal_px > 415.0);
    CHECK(c.focal_px < 450.0);
    CHECK(c.horizontal_fov_deg == Approx(45.0).margin(3.0));
    // Measured 1.6e-2, 1.7e-8, 3.2e-2, 7.4e-2: the homographies are not exactly of a camera with
    // square pixels and a centred principal point (SOURCE.md's "<= 4e-3" is not this measure).
    CHECK(c.orthogonality_residual < 0.08);
    // 90-104 floor units up.
    CHECK(c.height_m / cal.floor_unit_m > 85.0);
    CHECK(c.height_m / cal.floor_unit_m < 110.0);
    // Measured after the refinement: median 0.4, 0.0, 0.8, 1.7 px; max 1.0, 0.0, 2.1, 4.5 px.
    CHECK(c.floor_reprojection_median_px < 2.0);
    CHECK(c.floor_reprojection_max_px < 5.0);
  }
  // The ground truth is in the tracked area (floor units -33..299 x 12..387, SOURCE.md), mapped
  // to metres in the world frame (y mirrored with the cameras).
  const double unit = cal.floor_unit_m;
  for (const eval::EvalFrame& f : l.ds.ground_truth) {
    for (const eval::EvalObject& o : f.objects) {
      const double x = o.position.x() / unit;
      const double y = (cal.mirrored_y ? -o.position.y() : o.position.y()) / unit;
      CHECK(x > -60.0);
      CHECK(x < 330.0);
      CHECK(y > -20.0);
      CHECK(y < 420.0);
    }
  }
  // Each ground-truth point projects near its person's box bottom in the cameras that see it
  // uncut (the mean of the views' floor points: SOURCE.md median 21 units apart).
  std::vector<double> distances_px;
  for (std::size_t f = 0; f < l.ds.detections.size(); f += 10) {
    std::map<std::int64_t, Vec3> gt;
    for (const eval::EvalObject& o : l.ds.ground_truth[f].objects) gt[o.id] = o.position;
    for (std::size_t c = 0; c < 4; ++c) {
      for (std::size_t i = 0; i < l.ds.source_ids[f][c].size(); ++i) {
        const core::BoxPx& box = l.ds.detections[f][c].detections[i].box;
        if (box.y_max >= 287.0) continue;
        const std::optional<Vec2> px =
            l.ds.cameras[c].ProjectUndistorted(gt.at(l.ds.source_ids[f][c][i]));
        REQUIRE(px.has_value());
        distances_px.push_back((*px - box.bottom_center()).norm());
      }
    }
  }
  REQUIRE(distances_px.size() > 5000);
  std::sort(distances_px.begin(), distances_px.end());
  CHECK(distances_px[distances_px.size() / 2] < 10.0);
}

TEST_CASE("EPFL Terrace real data: the corrupted variant is seeded, a given unit is used",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "epfl");
  const Dataset a = LoadEpflTerrace(root);
  const Dataset b = LoadEpflTerrace(root);
  std::int64_t na = 0;
  std::int64_t fp = 0;
  bool same = true;
  for (std::size_t f = 0; f < a.detections.size(); ++f) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto& da = a.detections[f][c].detections;
      const auto& db = b.detections[f][c].detections;
      same &= da.size() == db.size();
      for (std::size_t i = 0; same && i < da.size(); ++i) {
        same &= da[i].box.x_min == db[i].box.x_min && da[i].box.y_max == db[i].box.y_max;
      }
      na += static_cast<std::int64_t>(da.size());
      for (std::int64_t id : a.source_ids[f][c]) fp += id == kFalsePositiveSourceId ? 1 : 0;
    }
  }
  CHECK(same);
  CHECK(fp > 0);
  // 5 % misses of 92,015 boxes, 0.1 false positives per camera-frame.
  CHECK(na - fp < 92015);
  CHECK(na - fp > 85000);
  CHECK_THAT(a.protocol_notes, Catch::Contains("corrupted: seed 1"));
  // Same ground truth and cameras as the clean variant.
  REQUIRE(a.ground_truth.size() == Clean().ds.ground_truth.size());
  CHECK(a.ground_truth[1000].objects.size() == Clean().ds.ground_truth[1000].objects.size());
  CHECK(a.cameras[2].cam_from_world.translation ==
        Clean().ds.cameras[2].cam_from_world.translation);

  EpflOptions given;
  given.corruption = CorruptionOptions::Clean();
  given.floor_unit_m = 0.02;
  EpflCalibration cal;
  const Dataset g = LoadEpflTerrace(root, given, &cal);
  CHECK_FALSE(cal.unit_estimated);
  CHECK(cal.floor_unit_m == 0.02);
  CHECK(g.cameras[0].CenterInWorld().z() == Approx(Clean().ds.cameras[0].CenterInWorld().z() *
                                                   0.02 / Clean().calibration.floor_unit_m));
  CHECK_THAT(g.protocol_notes, Catch::Contains("as given"));
  EpflOptions bad;
  bad.person_height_m = 0.0;
  CHECK_THROWS_WITH(LoadEpflTerrace(root, bad), Catch::Contains("person_height_m"));
}

}  // namespace
}  // namespace mvtrack::datasets
