// Campus on the real data (../shared/data/campus or $MVTRACK_DATA/campus); the test cases skip
// with a warning when the dataset is missing, and fail instead when CI is set.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <vector>

#include "data_test_util.h"
#include "eval/pcp.h"

namespace mvtrack::datasets {
namespace {

TEST_CASE("Campus real data (skipped without ../shared/data/campus): sizes and ids", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const Dataset& ds = testing::CampusClean();
  CHECK(ds.name == "campus");
  CHECK(ds.fps == 25.0);
  REQUIRE(ds.cameras.size() == 3);
  for (std::size_t c = 0; c < 3; ++c) {
    CHECK(ds.cameras[c].id == static_cast<CameraId>(c));
    CHECK(ds.cameras[c].width_px == 360);
    CHECK(ds.cameras[c].height_px == 288);
    CHECK(ds.cameras[c].distortion.IsZero());
  }
  REQUIRE(ds.detections.size() == 2000);
  REQUIRE(ds.ground_truth.size() == 2000);
  CHECK(ds.detections.front()[0].frame == 0);
  CHECK(ds.detections.back()[2].frame == 1999);
  CHECK(ds.detections[169][1].utime == 6'760'000);
  // SOURCE.md: 2D persons per id 2448 / 2082 / 1995; 3D frames per id 816 / 694 / 665; 1231
  // frames with at least one person.
  std::map<std::int64_t, int> persons_2d;
  for (std::size_t f = 0; f < ds.detections.size(); ++f) {
    for (std::size_t c = 0; c < 3; ++c) {
      REQUIRE(ds.source_ids[f][c].size() == ds.detections[f][c].detections.size());
      for (std::size_t i = 0; i < ds.source_ids[f][c].size(); ++i) {
        ++persons_2d[ds.source_ids[f][c][i]];
        const core::Detection2D& d = ds.detections[f][c].detections[i];
        CHECK(d.layout == core::KeypointLayoutId::kShelf14);
        CHECK(d.score == 1.0);
        for (const core::Keypoint2D& kp : d.keypoints) CHECK(kp.confidence == 1.0);
      }
    }
  }
  CHECK(persons_2d == std::map<std::int64_t, int>{{0, 2448}, {1, 2082}, {2, 1995}});
  std::map<std::int64_t, int> frames_per_id;
  int frames_with_people = 0;
  for (const eval::EvalFrame& f : ds.ground_truth) {
    if (!f.objects.empty()) ++frames_with_people;
    for (const eval::EvalObject& o : f.objects) ++frames_per_id[o.id];
  }
  CHECK(frames_per_id == std::map<std::int64_t, int>{{0, 816}, {1, 694}, {2, 665}});
  CHECK(frames_with_people == 1231);
  CHECK(ds.protocol_frames.size() == 2);
  std::string why;
  CHECK(eval::ValidateSequence(ds.ground_truth, "campus ground truth", &why));
}

TEST_CASE("Campus real data (skipped without ../shared/data/campus): 3D GT reprojects onto 2D GT",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const Dataset& ds = testing::CampusClean();
  for (std::size_t c = 0; c < ds.cameras.size(); ++c) {
    double sum = 0.0;
    double worst = 0.0;
    int n = 0;
    for (std::size_t f = 0; f < ds.detections.size(); ++f) {
      for (std::size_t i = 0; i < ds.detections[f][c].detections.size(); ++i) {
        const std::int64_t id = ds.source_ids[f][c][i];
        const auto& objects = ds.ground_truth[f].objects;
        const auto it = std::find_if(
            objects.begin(), objects.end(), [&](const eval::EvalObject& o) { return o.id == id; });
        if (it == objects.end()) continue;  // a 2D annotation without a 3D one
        for (std::size_t j = 0; j < 14; ++j) {
          const std::optional<Vec2> px = ds.cameras[c].Project(*it->joints[j]);
          REQUIRE(px.has_value());
          const Vec2& annotated = ds.detections[f][c].detections[i].keypoints[j].position_px;
          const double e = (*px - annotated).norm();
          sum += e;
          worst = std::max(worst, e);
          ++n;
        }
      }
    }
    const double mean = sum / n;
    INFO("camera " << c << ": mean reprojection error " << mean << " px, max " << worst
                   << " px over " << n << " joints");
    CHECK(n > 20000);
    CHECK(mean < 1.5);
  }
}

TEST_CASE("Campus real data (skipped without ../shared/data/campus): default corruption",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const Dataset& clean = testing::CampusClean();
  const Dataset& noisy = testing::CampusDefault();
  REQUIRE(noisy.detections.size() == clean.detections.size());
  int clean_persons = 0, kept = 0, ghosts = 0, view_frames = 0;
  int joints = 0, dropped = 0;
  double sq = 0.0;
  int samples = 0;
  for (std::size_t f = 0; f < clean.detections.size(); ++f) {
    for (std::size_t c = 0; c < clean.cameras.size(); ++c) {
      ++view_frames;
      clean_persons += static_cast<int>(clean.detections[f][c].detections.size());
      for (std::size_t i = 0; i < noisy.source_ids[f][c].size(); ++i) {
        const std::int64_t id = noisy.source_ids[f][c][i];
        if (id == kFalsePositiveSourceId) {
          ++ghosts;
          continue;
        }
        ++kept;
        const auto& ids = clean.source_ids[f][c];
        const std::size_t k =
            static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
        REQUIRE(k < ids.size());
        const core::Detection2D& a = clean.detections[f][c].detections[k];
        const core::Detection2D& b = noisy.detections[f][c].detections[i];
        for (std::size_t j = 0; j < 14; ++j) {
          ++joints;
          if (b.keypoints[j].confidence == 0.0) {
            ++dropped;
            continue;
          }
          sq += (b.keypoints[j].position_px - a.keypoints[j].position_px).squaredNorm();
          samples += 2;
        }
      }
    }
  }
  const double miss = 1.0 - static_cast<double>(kept) / clean_persons;
  const double fp = static_cast<double>(ghosts) / view_frames;
  const double dropout = static_cast<double>(dropped) / joints;
  const double sigma = std::sqrt(sq / samples);
  INFO("miss " << miss << ", false positives per view-frame " << fp << ", dropout " << dropout
               << ", noise sigma " << sigma << " px");
  // 6525 persons, 6000 view-frames, 85k joints: tolerances of about 4 standard errors; dropout
  // also counts joints pushed out of the image (people at the border).
  CHECK(std::abs(miss - 0.05) < 0.012);
  CHECK(std::abs(fp - 0.1) < 0.02);
  CHECK(dropout > 0.046);
  CHECK(dropout < 0.06);
  CHECK(std::abs(sigma - 2.0) < 0.05);
  CHECK(noisy.protocol_notes.find("sigma 2 px") != std::string::npos);
  // The ground truth does not depend on the corruption.
  CHECK(noisy.ground_truth.size() == clean.ground_truth.size());
  CHECK(noisy.ground_truth[400].objects.size() == clean.ground_truth[400].objects.size());
}

TEST_CASE("Campus real data (skipped without ../shared/data/campus): corruption is seeded",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const Dataset& first = testing::CampusDefault();
  const Dataset again = LoadCampus(root);
  CampusOptions other_seed;
  other_seed.corruption.seed = 2;
  const Dataset other = LoadCampus(root, other_seed);
  bool identical = true;
  int differing_frames = 0;
  for (std::size_t f = 0; f < first.detections.size(); ++f) {
    for (std::size_t c = 0; c < first.cameras.size(); ++c) {
      const auto& a = first.detections[f][c].detections;
      const auto& b = again.detections[f][c].detections;
      const auto& o = other.detections[f][c].detections;
      if (first.source_ids[f][c] != again.source_ids[f][c] || a.size() != b.size()) {
        identical = false;
        continue;
      }
      for (std::size_t i = 0; i < a.size(); ++i) {
        for (std::size_t j = 0; j < a[i].keypoints.size(); ++j) {
          if (a[i].keypoints[j].position_px != b[i].keypoints[j].position_px) identical = false;
        }
      }
      if (!a.empty() && (o.size() != a.size() || first.source_ids[f][c] != other.source_ids[f][c] ||
                         o[0].keypoints[0].position_px != a[0].keypoints[0].position_px)) {
        ++differing_frames;
      }
    }
  }
  CHECK(identical);
  CHECK(differing_frames > 2000);
}

TEST_CASE("Campus real data (skipped without ../shared/data/campus): Cross-View Tracking's output",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const Dataset& ds = testing::CampusClean();
  const PeerOutput peer = LoadCampusPeerCrossView(root);
  CHECK(peer.native_layout == core::KeypointLayoutId::kCoco17);
  REQUIRE(peer.native.size() == 1660);
  REQUIRE(peer.shelf14.size() == 1660);
  CHECK(peer.native.front().frame == 152);  // 6.08 s
  CHECK(peer.native.back().frame == 1814);  // 72.56 s
  CHECK(peer.original_ids.size() > 3);
  for (std::uint64_t id : peer.original_ids) CHECK(id > (std::uint64_t{1} << 32));
  std::string why;
  CHECK(eval::ValidateSequence(peer.native, "crossview", &why));
  CHECK(eval::ValidateSequence(peer.shelf14, "crossview shelf14", &why));
  // Footprints: at equal frames, the nearest output footprint is close to each GT footprint
  // (SOURCE.md: hip centres a median 9.8 cm apart at equal timestamps).
  std::map<FrameIndex, const eval::EvalFrame*> by_frame;
  for (const eval::EvalFrame& f : peer.native) by_frame[f.frame] = &f;
  std::vector<double> distances;
  for (const eval::EvalFrame& gt : ds.ground_truth) {
    const auto it = by_frame.find(gt.frame);
    if (it == by_frame.end()) continue;
    for (const eval::EvalObject& g : gt.objects) {
      double best = 1e9;
      for (const eval::EvalObject& p : it->second->objects) {
        best = std::min(best, eval::FootprintDistance(g, p));
      }
      if (best < 1e9) distances.push_back(best);
    }
  }
  std::sort(distances.begin(), distances.end());
  REQUIRE(distances.size() > 1500);
  const double median = distances[distances.size() / 2];
  // PCP with the standard protocol (the paper reports 96.6 % average on Campus).
  eval::PcpOptions options;
  options.actor_ids = ds.protocol_actor_ids;
  options.frame_ranges = ds.protocol_frames;
  const eval::PcpResult pcp =
      eval::EvaluatePcp(ds.ground_truth, peer.shelf14, eval::ShelfCampusPcpProtocol(), options);
  REQUIRE(pcp.valid);
  INFO("median footprint distance " << median << " m; PCP " << pcp.average_pcp << " (actors "
                                    << pcp.actors[0].pcp << ", " << pcp.actors[1].pcp << ", "
                                    << pcp.actors[2].pcp << ")");
  CHECK(median < 0.1);
  CHECK(pcp.average_pcp > 0.95);
}

}  // namespace
}  // namespace mvtrack::datasets
