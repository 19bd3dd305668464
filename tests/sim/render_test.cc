// The detector model: clean detections are exact projections of the truth, occlusion follows the
// depth order and the covered fraction, misses / false positives / dropout match the configured
// rates, and the detection order carries no identity.

#include "sim/render.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "sim/body.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/synthetic_scene.h"

namespace mvtrack::sim {
namespace {

// A person standing (or mid-stride) at `x, y`, built from the body model.
PersonTruth MakePerson(int id,
                       double x,
                       double y,
                       double heading_rad,
                       double height_m,
                       double phase = 0.0,
                       double amplitude = 0.0) {
  BodyState body;
  body.footprint_m = Vec3(x, y, 0.0);
  body.heading_rad = heading_rad;
  body.height_m = height_m;
  body.walk_phase_rad = phase;
  body.gait_amplitude = amplitude;
  PersonTruth p;
  p.id = id;
  p.footprint_m = body.footprint_m;
  const auto joints = Coco17Joints(body);
  p.joints_m.assign(joints.begin(), joints.end());
  p.head_top_m = HeadTop(body);
  p.heading_rad = heading_rad;
  p.height_m = height_m;
  return p;
}

// Mean pixel distance between a detection's keypoints and projected joints.
double KeypointDistance(const core::Detection2D& d, const std::vector<Vec2>& joints_px) {
  double sum = 0.0;
  for (std::size_t j = 0; j < joints_px.size(); ++j) {
    sum += (d.keypoints[j].position_px - joints_px[j]).norm();
  }
  return sum / static_cast<double>(joints_px.size());
}

SceneOptions CleanOptions() {
  SceneOptions o;
  o.seed = 21;
  o.num_people = 5;
  o.num_cameras = 4;
  o.num_frames = 40;
  o.pixel_noise_px = 0.0;
  o.keypoint_dropout = 0.0;
  o.miss_rate = 0.0;
  o.false_positives_per_frame = 0.0;
  o.occlusion = false;
  return o;
}

TEST_CASE("clean detections are the exact projections of the truth", "[unit][sim]") {
  const SceneOptions o = CleanOptions();
  const Scene scene = GenerateScene(o);
  int detections = 0, partially_outside = 0, matched_twice = 0, wrong_labels = 0, bad_scores = 0,
      boxes_outside_image = 0, bad_confidences = 0, keypoints_outside_box = 0;
  double worst_match_px = 0.0;
  for (std::size_t f = 0; f < scene.truth.size(); ++f) {
    const FrameTruth& truth = scene.truth[f];
    for (std::size_t c = 0; c < scene.cameras.size(); ++c) {
      const geometry::CameraModel& cam = scene.cameras[c];
      const core::CameraFrame& frame = scene.detections[f][c];
      // Who should be detected: everyone in front of the camera whose box (the projected body
      // points, including head top and feet, padded symmetrically) is centred in the image.
      std::map<int, std::vector<Vec2>> expected;  // id -> projected joints
      for (const PersonTruth& p : truth.people) {
        double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
        bool in_front = true;
        for (const Vec3& point : BoxPoints(p)) {
          const auto px = cam.Project(point);
          if (!px || cam.Depth(point) <= kNearPlaneM) {
            in_front = false;
            break;
          }
          x_lo = std::min(x_lo, px->x());
          x_hi = std::max(x_hi, px->x());
          y_lo = std::min(y_lo, px->y());
          y_hi = std::max(y_hi, px->y());
        }
        if (in_front && cam.InImage(Vec2(0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi)))) {
          for (const Vec3& joint : p.joints_m) expected[p.id].push_back(*cam.Project(joint));
        }
      }
      INFO("frame " << f << " camera " << c);
      REQUIRE(frame.detections.size() == expected.size());
      REQUIRE(scene.detection_person_ids[f][c].size() == expected.size());
      // Match each detection to the person whose projected joints it reproduces.
      std::map<int, int> matched;
      for (std::size_t k = 0; k < frame.detections.size(); ++k) {
        const core::Detection2D& d = frame.detections[k];
        REQUIRE(d.layout == core::KeypointLayoutId::kCoco17);
        REQUIRE(d.keypoints.size() == 17u);
        int best_id = -1;
        double best = std::numeric_limits<double>::infinity();
        for (const auto& [id, joints_px] : expected) {
          const double dist = KeypointDistance(d, joints_px);
          if (dist < best) {
            best = dist;
            best_id = id;
          }
        }
        worst_match_px = std::max(worst_match_px, best);
        if (++matched[best_id] != 1) ++matched_twice;
        if (scene.detection_person_ids[f][c][k] != best_id) ++wrong_labels;
        if (!(d.score >= 0.5 && d.score <= 1.0)) ++bad_scores;
        if (d.box.x_min < 0.0 || d.box.y_min < 0.0 || d.box.x_max > cam.width_px ||
            d.box.y_max > cam.height_px) {
          ++boxes_outside_image;
        }
        // Confidence: (0.5, 1] inside the image, 0 outside; the box holds the visible joints.
        bool any_outside = false;
        for (const core::Keypoint2D& kp : d.keypoints) {
          if (cam.InImage(kp.position_px)) {
            if (!(kp.confidence > 0.5 && kp.confidence <= 1.0)) ++bad_confidences;
            if (kp.position_px.x() < d.box.x_min || kp.position_px.x() > d.box.x_max ||
                kp.position_px.y() < d.box.y_min || kp.position_px.y() > d.box.y_max) {
              ++keypoints_outside_box;
            }
          } else {
            if (kp.confidence != 0.0) ++bad_confidences;
            any_outside = true;
          }
        }
        ++detections;
        if (any_outside) ++partially_outside;
      }
    }
  }
  CHECK(worst_match_px < 1e-9);
  CHECK(matched_twice == 0);
  CHECK(wrong_labels == 0);
  CHECK(bad_scores == 0);
  CHECK(boxes_outside_image == 0);
  CHECK(bad_confidences == 0);
  CHECK(keypoints_outside_box == 0);
  INFO(detections << " detections, " << partially_outside << " partially outside the image");
  CHECK(detections > 400);
  CHECK(partially_outside > 0);  // the out-of-image case was exercised
}

TEST_CASE("CoveredArea is the exact area of a union of rectangles", "[unit][sim]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(0.0, 100.0);
  for (int trial = 0; trial < 40; ++trial) {
    const core::BoxPx target{20.0, 10.0, 80.0, 90.0};
    std::vector<core::BoxPx> rects;
    const int n = 1 + trial % 6;
    for (int i = 0; i < n; ++i) {
      // Integer corners so that counting unit cells is exact.
      double a = std::floor(coord(rng)), b = std::floor(coord(rng));
      double c = std::floor(coord(rng)), d = std::floor(coord(rng));
      rects.push_back({std::min(a, b), std::min(c, d), std::max(a, b) + 1.0, std::max(c, d) + 1.0});
    }
    int cells = 0;
    for (int x = 20; x < 80; ++x) {
      for (int y = 10; y < 90; ++y) {
        const double cx = x + 0.5, cy = y + 0.5;
        for (const core::BoxPx& r : rects) {
          if (cx > r.x_min && cx < r.x_max && cy > r.y_min && cy < r.y_max) {
            ++cells;
            break;
          }
        }
      }
    }
    CHECK(CoveredArea(target, rects) == Approx(static_cast<double>(cells)));
  }
  CHECK(CoveredArea({0, 0, 10, 10}, {}) == 0.0);
  CHECK(CoveredArea({0, 0, 10, 10}, {{-5, -5, 20, 20}}) == Approx(100.0));
}

TEST_CASE("occlusion hides people behind others and lowers covered keypoints", "[unit][sim]") {
  // A camera 1.5 m high looking along +x; A stands 5 m in front of it, B right behind A.
  const geometry::CameraModel cam =
      MakeCamera(0, 1280, 720, 60.0, Vec3(0.0, 0.0, 1.5), Vec3(1.0, 0.0, 0.0));
  SceneOptions o;
  o.pixel_noise_px = 0.0;
  o.occlusion = true;
  FrameTruth t;
  t.frame = 3;
  t.people = {MakePerson(0, 5.0, 0.0, 0.0, 1.8), MakePerson(1, 7.0, 0.0, 0.0, 1.7)};

  std::vector<int> ids;
  core::CameraFrame hidden = RenderCamera(o, cam, t, &ids);
  CHECK(ids == std::vector<int>{0});  // B is entirely behind A
  o.occlusion = false;
  core::CameraFrame unhidden = RenderCamera(o, cam, t, &ids);
  CHECK(unhidden.detections.size() == 2u);

  // B steps 0.4 m aside: partially covered, detected, with its keypoints behind A's box at a
  // lower confidence than the others.
  o.occlusion = true;
  t.people[1] = MakePerson(1, 7.0, 0.4, 0.0, 1.7);
  const auto a_view = ProjectPerson(cam, t.people[0]);
  const auto b_view = ProjectPerson(cam, t.people[1]);
  REQUIRE(a_view);
  REQUIRE(b_view);
  const double covered = CoveredArea(b_view->clipped_box, {a_view->clipped_box}) /
                         (b_view->clipped_box.width() * b_view->clipped_box.height());
  REQUIRE(covered > 0.05);
  REQUIRE(covered < o.occlusion_threshold);
  const core::CameraFrame partial = RenderCamera(o, cam, t, &ids);
  REQUIRE(partial.detections.size() == 2u);
  const std::size_t b = ids[0] == 1 ? 0 : 1;
  const core::Detection2D& db = partial.detections[b];
  const core::Detection2D& da = partial.detections[1 - b];
  int low = 0, high = 0;
  for (std::size_t j = 0; j < 17; ++j) {
    const Vec2& kp = b_view->keypoints_px[j];
    const core::BoxPx& ab = a_view->clipped_box;
    const bool behind_a =
        kp.x() >= ab.x_min && kp.x() <= ab.x_max && kp.y() >= ab.y_min && kp.y() <= ab.y_max;
    if (behind_a) {
      CHECK(db.keypoints[j].confidence <= 0.5);
      CHECK(db.keypoints[j].confidence > 0.05);
      ++low;
    } else {
      CHECK(db.keypoints[j].confidence > 0.5);
      ++high;
    }
    CHECK(da.keypoints[j].confidence > 0.5);  // the nearer person is unaffected
  }
  CHECK(low > 0);
  CHECK(high > 0);
  CHECK(db.score <= 0.5 + 0.5 * (1.0 - covered) + 1e-12);  // covered people score lower

  // Depth order, not list order, decides: swapping who stands in front swaps who is hidden.
  t.people = {MakePerson(0, 7.0, 0.0, 0.0, 1.7), MakePerson(1, 5.0, 0.0, 0.0, 1.8)};
  RenderCamera(o, cam, t, &ids);
  CHECK(ids == std::vector<int>{1});
}

TEST_CASE("occlusion in a crowd follows the covered fraction of each box", "[unit][sim]") {
  SceneOptions o = CleanOptions();
  o.num_people = 14;
  o.num_frames = 25;
  o.occlusion = true;
  const Scene scene = GenerateScene(o);
  int hidden = 0, shown = 0, low_keypoints = 0, wrong_decisions = 0, wrong_confidences = 0;
  for (std::size_t f = 0; f < scene.truth.size(); ++f) {
    for (std::size_t c = 0; c < scene.cameras.size(); ++c) {
      const geometry::CameraModel& cam = scene.cameras[c];
      const std::vector<int>& ids = scene.detection_person_ids[f][c];
      std::vector<std::optional<PersonProjection>> views;
      for (const PersonTruth& p : scene.truth[f].people) views.push_back(ProjectPerson(cam, p));
      for (std::size_t i = 0; i < views.size(); ++i) {
        if (!views[i] || !views[i]->in_view) continue;
        const core::BoxPx& own = views[i]->clipped_box;
        // Brute-force covered fraction: a 32 x 32 sample grid over the box.
        std::vector<core::BoxPx> nearer;
        for (std::size_t k = 0; k < views.size(); ++k) {
          if (k != i && views[k] && views[k]->depth_m < views[i]->depth_m) {
            nearer.push_back(views[k]->clipped_box);
          }
        }
        int inside = 0;
        for (int sx = 0; sx < 32; ++sx) {
          for (int sy = 0; sy < 32; ++sy) {
            const double x = own.x_min + (sx + 0.5) / 32.0 * own.width();
            const double y = own.y_min + (sy + 0.5) / 32.0 * own.height();
            for (const core::BoxPx& b : nearer) {
              if (x >= b.x_min && x <= b.x_max && y >= b.y_min && y <= b.y_max) {
                ++inside;
                break;
              }
            }
          }
        }
        const double fraction = inside / 1024.0;
        const int id = scene.truth[f].people[i].id;
        const auto it = std::find(ids.begin(), ids.end(), id);
        const bool detected = it != ids.end();
        if (std::abs(fraction - o.occlusion_threshold) < 0.04) continue;  // sampling tolerance
        if (detected != (fraction < o.occlusion_threshold)) {
          ++wrong_decisions;
          UNSCOPED_INFO("frame " << f << " camera " << c << " person " << id << " covered "
                                 << fraction << (detected ? " detected" : " hidden"));
        }
        if (!detected) {
          ++hidden;
          continue;
        }
        ++shown;
        const core::Detection2D& d =
            scene.detections[f][c].detections[static_cast<std::size_t>(it - ids.begin())];
        for (std::size_t j = 0; j < 17; ++j) {
          if (!views[i]->keypoint_in_image[j]) continue;
          const Vec2& kp = views[i]->keypoints_px[j];
          const bool covered = std::any_of(nearer.begin(), nearer.end(), [&](const auto& b) {
            return kp.x() >= b.x_min && kp.x() <= b.x_max && kp.y() >= b.y_min && kp.y() <= b.y_max;
          });
          if ((d.keypoints[j].confidence <= 0.5) != covered) ++wrong_confidences;
          if (covered) ++low_keypoints;
        }
      }
    }
  }
  CHECK(wrong_decisions == 0);
  CHECK(wrong_confidences == 0);
  INFO(shown << " shown, " << hidden << " hidden, " << low_keypoints << " occluded keypoints");
  CHECK(hidden > 10);
  CHECK(shown > hidden);
  CHECK(low_keypoints > 100);
}

TEST_CASE("misses, false positives and keypoint dropout match the configured rates",
          "[unit][sim]") {
  SceneOptions clean = CleanOptions();
  clean.num_people = 3;
  clean.num_cameras = 3;
  clean.num_frames = 600;
  clean.pixel_noise_px = 1.0;
  SceneOptions noisy = clean;
  noisy.miss_rate = 0.2;
  noisy.false_positives_per_frame = 0.5;
  noisy.keypoint_dropout = 0.1;
  const Scene a = GenerateScene(clean);
  const Scene b = GenerateScene(noisy);
  double candidates = 0, kept = 0, false_positives = 0, visible_keypoints = 0, dropped = 0;
  int implausible_false_positives = 0, moved_keypoints = 0;
  for (std::size_t f = 0; f < a.truth.size(); ++f) {
    REQUIRE(a.truth[f].people.size() == b.truth[f].people.size());  // same walk
    for (std::size_t c = 0; c < a.cameras.size(); ++c) {
      const auto& ids_a = a.detection_person_ids[f][c];
      const auto& ids_b = b.detection_person_ids[f][c];
      candidates += static_cast<double>(ids_a.size());  // clean: every person in view
      for (std::size_t k = 0; k < ids_b.size(); ++k) {
        const core::Detection2D& db = b.detections[f][c].detections[k];
        if (ids_b[k] < 0) {
          ++false_positives;
          if (!(db.score >= 0.5 && db.score < 0.8) || db.box.x_min < 0.0 ||
              db.box.x_max > b.cameras[c].width_px || db.box.y_min < 0.0 ||
              db.box.y_max > b.cameras[c].height_px || db.box.height() < 1.0 ||
              db.box.width() < 1.0 || db.keypoints.size() != 17u) {
            ++implausible_false_positives;
          }
          continue;
        }
        ++kept;
        const auto it = std::find(ids_a.begin(), ids_a.end(), ids_b[k]);
        REQUIRE(it != ids_a.end());  // a detection of someone the clean run also shows
        const core::Detection2D& da =
            a.detections[f][c].detections[static_cast<std::size_t>(it - ids_a.begin())];
        for (std::size_t j = 0; j < 17; ++j) {
          if (da.keypoints[j].confidence == 0.0) continue;  // outside the image
          ++visible_keypoints;
          if (db.keypoints[j].confidence == 0.0) ++dropped;
          // Noise streams do not depend on the rates: same positions in both runs.
          if (db.keypoints[j].position_px != da.keypoints[j].position_px) ++moved_keypoints;
        }
      }
    }
  }
  CHECK(implausible_false_positives == 0);
  CHECK(moved_keypoints == 0);
  const double camera_frames = static_cast<double>(a.truth.size() * a.cameras.size());
  const double misses = candidates - kept;
  const double miss_sigma = std::sqrt(candidates * 0.2 * 0.8);
  const double fp_sigma = std::sqrt(0.5 * camera_frames);
  const double drop_sigma = std::sqrt(visible_keypoints * 0.1 * 0.9);
  INFO("misses " << misses << " of " << candidates << ", false positives " << false_positives
                 << " in " << camera_frames << " camera-frames, dropped " << dropped << " of "
                 << visible_keypoints);
  CHECK(std::abs(misses - 0.2 * candidates) < 4.0 * miss_sigma);
  CHECK(std::abs(false_positives - 0.5 * camera_frames) < 4.0 * fp_sigma);
  CHECK(std::abs(dropped - 0.1 * visible_keypoints) < 4.0 * drop_sigma);
}

TEST_CASE("detection order carries no identity", "[unit][sim]") {
  SceneOptions o = CleanOptions();
  o.num_frames = 100;
  const Scene scene = GenerateScene(o);
  // Under a uniformly random order the lowest id comes first with probability 1/n.
  double frames = 0, lowest_first = 0, expected = 0, variance = 0;
  for (const auto& cameras : scene.detection_person_ids) {
    for (const std::vector<int>& ids : cameras) {
      if (ids.size() < 2) continue;
      const double p = 1.0 / static_cast<double>(ids.size());
      ++frames;
      expected += p;
      variance += p * (1.0 - p);
      if (ids.front() == *std::min_element(ids.begin(), ids.end())) ++lowest_first;
    }
  }
  INFO(lowest_first << " of " << frames << " camera-frames start with the lowest id, expected "
                    << expected);
  REQUIRE(frames > 200);
  CHECK(std::abs(lowest_first - expected) < 4.0 * std::sqrt(variance));
}

}  // namespace
}  // namespace mvtrack::sim
