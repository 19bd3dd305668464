// CMU Panoptic on the real data (../shared/data/panoptic or $MVTRACK_DATA/panoptic); the test
// cases skip with a warning when the dataset is missing, and fail instead when CI is set.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "data_test_util.h"

namespace mvtrack::datasets {
namespace {

PanopticOptions Clean(const std::string& sequence) {
  PanopticOptions options;
  options.sequence = sequence;
  options.corruption = CorruptionOptions::Clean();
  return options;
}

TEST_CASE("Panoptic real data (skipped without ../shared/data/panoptic): sizes and cameras",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "panoptic");
  for (const auto& [sequence, first] : std::vector<std::pair<std::string, FrameIndex>>{
           {"160906_band1", 168}, {"160906_band2", 139}}) {
    INFO(sequence);
    const Dataset ds = LoadPanoptic(root, Clean(sequence));
    CHECK(ds.name == "panoptic/" + sequence);
    CHECK(ds.fps == 29.97);
    REQUIRE(ds.cameras.size() == 6);
    const std::vector<CameraId> ids = {2, 6, 7, 12, 13, 28};
    for (std::size_t c = 0; c < 6; ++c) {
      CHECK(ds.cameras[c].id == ids[c]);
      CHECK(ds.cameras[c].width_px == 1920);
      CHECK(ds.cameras[c].height_px == 1080);
      CHECK_FALSE(ds.cameras[c].distortion.IsZero());
      // Our world is z up in metres: the dome's HD cameras hang 0.7-3.4 m above the floor.
      CHECK(ds.cameras[c].CenterInWorld().z() > 0.5);
      CHECK(ds.cameras[c].CenterInWorld().z() < 4.0);
    }
    REQUIRE(ds.detections.size() == 20);
    REQUIRE(ds.ground_truth.size() == 20);
    CHECK(ds.ground_truth.front().frame == first);
    CHECK(ds.ground_truth.back().frame == first + 19);
    CHECK(ds.detections[3][0].utime == FrameUtime(first + 3, 29.97));
    for (const eval::EvalFrame& f : ds.ground_truth) {
      REQUIRE(f.objects.size() == 3);
      std::set<std::int64_t> object_ids;
      for (const eval::EvalObject& o : f.objects) {
        object_ids.insert(o.id);
        REQUIRE(o.joints.size() == 19);
        // Seated musicians, z up: neck (0) above the body centre (2) above the ankles (8, 14).
        REQUIRE(o.joints[0].has_value());
        REQUIRE(o.joints[2].has_value());
        CHECK(o.joints[0]->z() > o.joints[2]->z() + 0.1);
        for (int ankle : {8, 14}) {
          if (!o.joints[static_cast<std::size_t>(ankle)].has_value()) continue;
          CHECK(o.joints[2]->z() > o.joints[static_cast<std::size_t>(ankle)]->z() + 0.2);
          CHECK(o.joints[static_cast<std::size_t>(ankle)]->z() > -0.2);
          CHECK(o.joints[static_cast<std::size_t>(ankle)]->z() < 0.4);
        }
      }
      CHECK(object_ids == std::set<std::int64_t>{0, 1, 2});
    }
    std::string why;
    CHECK(eval::ValidateSequence(ds.ground_truth, sequence, &why));
  }
}

TEST_CASE(
    "Panoptic real data (skipped without ../shared/data/panoptic): the 3 bodies lie "
    "inside the 6 default cameras",
    "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "panoptic");
  const Dataset ds = LoadPanoptic(root, Clean("160906_band2"));
  // Every valid joint of every body, in every frame, is detected in each default camera (the
  // projection with distortion lands inside the 1920x1080 image), at exactly the projection.
  int checked = 0;
  for (std::size_t f = 0; f < ds.ground_truth.size(); ++f) {
    for (std::size_t c = 0; c < ds.cameras.size(); ++c) {
      const geometry::CameraModel& camera = ds.cameras[c];
      REQUIRE(ds.detections[f][c].detections.size() == 3);
      for (std::size_t i = 0; i < 3; ++i) {
        const core::Detection2D& d = ds.detections[f][c].detections[i];
        CHECK(d.layout == core::KeypointLayoutId::kPanoptic19);
        const std::int64_t id = ds.source_ids[f][c][i];
        const eval::EvalObject& body = ds.ground_truth[f].objects[static_cast<std::size_t>(id)];
        REQUIRE(body.id == id);
        for (std::size_t j = 0; j < 19; ++j) {
          if (!body.joints[j].has_value()) {
            CHECK(d.keypoints[j].confidence == 0.0);
            continue;
          }
          ++checked;
          CHECK(d.keypoints[j].confidence == 1.0);
          CHECK(camera.InImage(d.keypoints[j].position_px));
          const std::optional<Vec2> raw = camera.Project(*body.joints[j]);
          REQUIRE(raw.has_value());
          CHECK((*raw - d.keypoints[j].position_px).norm() < 1e-9);
          // The distortion is really applied: undistorting the detection gives the pinhole
          // projection.
          const std::optional<Vec2> pinhole = camera.ProjectUndistorted(*body.joints[j]);
          REQUIRE(pinhole.has_value());
          CHECK((camera.UndistortPixel(d.keypoints[j].position_px) - *pinhole).norm() < 1e-6);
        }
      }
    }
  }
  CHECK(checked > 6 * 20 * 3 * 15);
}

TEST_CASE("Panoptic real data (skipped without ../shared/data/panoptic): camera selection",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "panoptic");
  PanopticOptions by_name = Clean("160906_band1");
  by_name.cameras = {"00_30", "00_00", "00_15"};
  PanopticOptions by_index = by_name;
  by_index.cameras = {"30", "0", "15"};
  const Dataset a = LoadPanoptic(root, by_name);
  const Dataset b = LoadPanoptic(root, by_index);
  REQUIRE(a.cameras.size() == 3);
  REQUIRE(b.cameras.size() == 3);
  CHECK(a.cameras[0].id == 30);
  CHECK(a.cameras[1].id == 0);
  for (std::size_t c = 0; c < 3; ++c) {
    CHECK(a.cameras[c].id == b.cameras[c].id);
    CHECK((a.cameras[c].K - b.cameras[c].K).norm() == 0.0);
    CHECK(a.detections[5][c].detections.size() == b.detections[5][c].detections.size());
  }
  // Cameras at the side of the dome do not see every joint: some are dropped, none is outside.
  int dropped = 0;
  for (const auto& frame : a.detections) {
    for (std::size_t c = 0; c < 3; ++c) {
      for (const core::Detection2D& d : frame[c].detections) {
        for (const core::Keypoint2D& kp : d.keypoints) {
          if (kp.confidence == 0.0)
            ++dropped;
          else
            CHECK(a.cameras[c].InImage(kp.position_px));
        }
      }
    }
  }
  CHECK(dropped > 0);
}

TEST_CASE("Panoptic real data (skipped without ../shared/data/panoptic): default corruption",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "panoptic");
  const Dataset clean = LoadPanoptic(root, Clean("160906_band2"));
  const Dataset noisy = LoadPanoptic(root);
  const Dataset again = LoadPanoptic(root);
  CHECK(noisy.protocol_notes.find("sigma 6 px") != std::string::npos);
  double sq = 0.0;
  int samples = 0;
  bool identical = true;
  for (std::size_t f = 0; f < clean.detections.size(); ++f) {
    for (std::size_t c = 0; c < clean.cameras.size(); ++c) {
      const auto& n = noisy.detections[f][c].detections;
      if (noisy.source_ids[f][c] != again.source_ids[f][c]) identical = false;
      for (std::size_t i = 0; i < n.size(); ++i) {
        const std::int64_t id = noisy.source_ids[f][c][i];
        for (std::size_t j = 0; j < 19 && identical; ++j) {
          const Vec2& repeated = again.detections[f][c].detections[i].keypoints[j].position_px;
          if (n[i].keypoints[j].position_px != repeated) identical = false;
        }
        if (id == kFalsePositiveSourceId) continue;
        const auto& ids = clean.source_ids[f][c];
        const std::size_t k =
            static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
        REQUIRE(k < ids.size());
        for (std::size_t j = 0; j < 19; ++j) {
          if (n[i].keypoints[j].confidence == 0.0) continue;
          sq += (n[i].keypoints[j].position_px -
                 clean.detections[f][c].detections[k].keypoints[j].position_px)
                    .squaredNorm();
          samples += 2;
        }
      }
    }
  }
  CHECK(identical);
  const double sigma = std::sqrt(sq / samples);
  INFO("noise sigma " << sigma << " px over " << samples / 2 << " keypoints");
  CHECK(std::abs(sigma - 6.0) < 0.4);
}

}  // namespace
}  // namespace mvtrack::datasets
