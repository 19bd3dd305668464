#include "datasets/corruption.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "datasets/dataset.h"

namespace mvtrack::datasets {
namespace {

constexpr int kWidth = 360;
constexpr int kHeight = 288;
constexpr int kJoints = 14;

// A random upright pose (14 keypoints, confidence 1) with its box from BoxFromKeypoints, kept
// `margin` px away from the image border.
core::Detection2D RandomPose(std::mt19937* rng, double margin) {
  std::uniform_real_distribution<double> height(60.0, 120.0);
  const double h = height(*rng);
  std::uniform_real_distribution<double> cx(margin + 0.3 * h, kWidth - margin - 0.3 * h);
  std::uniform_real_distribution<double> top(margin, kHeight - margin - h);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const double x0 = cx(*rng);
  const double y0 = top(*rng);
  core::Detection2D d;
  d.layout = core::KeypointLayoutId::kShelf14;
  d.keypoints.resize(kJoints);
  for (int j = 0; j < kJoints; ++j) {
    d.keypoints[static_cast<std::size_t>(j)].position_px =
        Vec2(x0 + jitter(*rng) * h, y0 + (static_cast<double>(j) / (kJoints - 1)) * h);
    d.keypoints[static_cast<std::size_t>(j)].confidence = 1.0;
  }
  d.box = *BoxFromKeypoints(d.keypoints);
  d.score = 1.0;
  return d;
}

struct CleanFrames {
  std::vector<core::CameraFrame> frames;
  std::vector<std::vector<std::int64_t>> ids;
  std::vector<core::Detection2D> pool;
};

// `n` camera-frames of camera 3 with 3 people (ids 0, 1, 2) each; the pool is 5 other poses.
CleanFrames MakeCleanFrames(int n, double margin = 20.0) {
  std::mt19937 rng(42);
  CleanFrames out;
  for (int f = 0; f < n; ++f) {
    core::CameraFrame frame;
    frame.frame = 1000 + f;
    frame.camera_id = 3;
    frame.utime = FrameUtime(frame.frame, 25.0);
    std::vector<std::int64_t> ids;
    for (int p = 0; p < 3; ++p) {
      frame.detections.push_back(RandomPose(&rng, margin));
      ids.push_back(p);
    }
    out.frames.push_back(frame);
    out.ids.push_back(ids);
  }
  for (int i = 0; i < 5; ++i) out.pool.push_back(RandomPose(&rng, margin));
  return out;
}

bool SameDetections(const CorruptedFrame& a, const CorruptedFrame& b) {
  if (a.source_ids != b.source_ids) return false;
  if (a.frame.detections.size() != b.frame.detections.size()) return false;
  for (std::size_t i = 0; i < a.frame.detections.size(); ++i) {
    const auto& x = a.frame.detections[i];
    const auto& y = b.frame.detections[i];
    if (x.keypoints.size() != y.keypoints.size()) return false;
    for (std::size_t j = 0; j < x.keypoints.size(); ++j) {
      if (x.keypoints[j].position_px != y.keypoints[j].position_px ||
          x.keypoints[j].confidence != y.keypoints[j].confidence) {
        return false;
      }
    }
  }
  return true;
}

TEST_CASE("CorruptionOptions validation", "[unit]") {
  std::string why;
  CHECK(CorruptionOptions{}.Validate(&why));
  CHECK(CorruptionOptions::Clean().Validate(&why));
  CHECK_FALSE(CorruptionOptions::Clean().enabled);
  CorruptionOptions o;
  o.pixel_noise_px = -1.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("pixel_noise_px") != std::string::npos);
  o = CorruptionOptions{};
  o.joint_dropout = 1.5;
  CHECK_FALSE(o.Validate(&why));
  o = CorruptionOptions{};
  o.miss_rate = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("miss_rate") != std::string::npos);
  o = CorruptionOptions{};
  o.false_positives_per_frame = -0.1;
  CHECK_FALSE(o.Validate(&why));
}

TEST_CASE("The clean variant passes detections through unchanged", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(20);
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out = CorruptCameraFrame(
        clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, CorruptionOptions::Clean());
    CHECK(out.frame.frame == clean.frames[f].frame);
    CHECK(out.frame.camera_id == 3);
    CHECK(out.frame.utime == clean.frames[f].utime);
    CorruptedFrame expected;
    expected.frame = clean.frames[f];
    expected.source_ids = clean.ids[f];
    CHECK(SameDetections(out, expected));
    REQUIRE(out.frame.detections.size() == 3);
    CHECK(out.frame.detections[1].box.x_min == clean.frames[f].detections[1].box.x_min);
  }
}

TEST_CASE("Corruption statistics match the configured rates", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(2000);
  const CorruptionOptions options;  // defaults: 2 px, 5 % dropout, 5 % miss, 0.1 FP
  int persons = 0, kept_persons = 0, ghosts = 0;
  int kept_keypoints = 0, dropped_keypoints = 0;
  double sum = 0.0, sum_sq = 0.0;
  int noise_samples = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, options);
    REQUIRE(out.source_ids.size() == out.frame.detections.size());
    persons += static_cast<int>(clean.frames[f].detections.size());
    for (std::size_t i = 0; i < out.frame.detections.size(); ++i) {
      const core::Detection2D& d = out.frame.detections[i];
      // Every detected keypoint lies in the image and the box is recomputed from them.
      for (const auto& kp : d.keypoints) {
        if (kp.confidence > 0.0) {
          CHECK(kp.position_px.x() >= 0.0);
          CHECK(kp.position_px.x() <= kWidth);
          CHECK(kp.position_px.y() >= 0.0);
          CHECK(kp.position_px.y() <= kHeight);
        }
      }
      const std::optional<core::BoxPx> box = BoxFromKeypoints(d.keypoints);
      REQUIRE(box.has_value());
      CHECK(d.box.x_min == box->x_min);
      CHECK(d.box.y_max == box->y_max);
      if (out.source_ids[i] == kFalsePositiveSourceId) {
        ++ghosts;
        continue;
      }
      ++kept_persons;
      const auto id = static_cast<std::size_t>(out.source_ids[i]);
      const core::Detection2D& src = clean.frames[f].detections[id];
      for (std::size_t j = 0; j < d.keypoints.size(); ++j) {
        if (d.keypoints[j].confidence == 0.0) {
          ++dropped_keypoints;
          continue;
        }
        ++kept_keypoints;
        const Vec2 delta = d.keypoints[j].position_px - src.keypoints[j].position_px;
        sum += delta.x() + delta.y();
        sum_sq += delta.squaredNorm();
        noise_samples += 2;
      }
    }
  }
  const double miss = 1.0 - static_cast<double>(kept_persons) / persons;
  const double dropout = static_cast<double>(dropped_keypoints) /
                         static_cast<double>(kept_keypoints + dropped_keypoints);
  const double mean = sum / noise_samples;
  const double sigma = std::sqrt(sum_sq / noise_samples - mean * mean);
  const double fp_rate = static_cast<double>(ghosts) / static_cast<double>(clean.frames.size());
  INFO("miss " << miss << " dropout " << dropout << " noise mean " << mean << " sigma " << sigma
               << " false positives per frame " << fp_rate);
  // Tolerances: about 4 standard errors (6000 persons, 80k keypoints, 2000 frames).
  CHECK(std::abs(miss - 0.05) < 0.012);
  CHECK(std::abs(dropout - 0.05) < 0.004);
  CHECK(std::abs(mean) < 0.03);
  CHECK(std::abs(sigma - 2.0) < 0.04);
  CHECK(std::abs(fp_rate - 0.1) < 0.03);
}

TEST_CASE("False positives are pool poses moved inside the image", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(300);
  CorruptionOptions options;
  options.false_positives_per_frame = 2.0;
  options.pixel_noise_px = 0.0;
  options.joint_dropout = 0.0;
  int ghosts = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, options);
    for (std::size_t i = 0; i < out.frame.detections.size(); ++i) {
      if (out.source_ids[i] != kFalsePositiveSourceId) continue;
      ++ghosts;
      const core::Detection2D& d = out.frame.detections[i];
      CHECK(d.box.x_min >= 0.0);
      CHECK(d.box.y_min >= 0.0);
      CHECK(d.box.x_max <= kWidth);
      CHECK(d.box.y_max <= kHeight);
      // Without noise a ghost is exactly a translated pool pose.
      bool matches_pool = false;
      for (const core::Detection2D& p : clean.pool) {
        const Vec2 shift = d.keypoints[0].position_px - p.keypoints[0].position_px;
        double err = 0.0;
        for (std::size_t j = 0; j < p.keypoints.size(); ++j) {
          const Vec2 residual = d.keypoints[j].position_px - p.keypoints[j].position_px - shift;
          err = std::max(err, residual.norm());
        }
        if (err < 1e-9) matches_pool = true;
      }
      CHECK(matches_pool);
    }
  }
  CHECK(ghosts > 450);  // Poisson(2) over 300 frames: 600 expected
  CHECK(ghosts < 750);
}

TEST_CASE("Corruption is seeded and independent of the processing order", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(50);
  CorruptionOptions options;
  options.false_positives_per_frame = 1.0;
  std::vector<CorruptedFrame> forward;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    forward.push_back(
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, options));
  }
  // Reverse order, same seed: identical.
  for (std::size_t k = clean.frames.size(); k-- > 0;) {
    const CorruptedFrame again =
        CorruptCameraFrame(clean.frames[k], clean.ids[k], clean.pool, kWidth, kHeight, options);
    CHECK(SameDetections(again, forward[k]));
  }
  // Another seed: different noise.
  options.seed = 2;
  int differing = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame other =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, options);
    if (!SameDetections(other, forward[f])) ++differing;
  }
  CHECK(differing == static_cast<int>(clean.frames.size()));
  // Another camera id at the same frame: an independent stream too.
  core::CameraFrame moved = clean.frames[0];
  moved.camera_id = 4;
  options.seed = 1;
  const CorruptedFrame other_camera =
      CorruptCameraFrame(moved, clean.ids[0], clean.pool, kWidth, kHeight, options);
  CHECK_FALSE(SameDetections(other_camera, forward[0]));
}

TEST_CASE("Each rate changes only what it controls", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(200);
  CorruptionOptions low;
  low.miss_rate = 0.0;
  low.false_positives_per_frame = 0.0;
  CorruptionOptions high = low;
  high.miss_rate = 0.5;
  int compared = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame a =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, low);
    const CorruptedFrame b =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, high);
    CHECK(b.frame.detections.size() <= a.frame.detections.size());
    // A person kept under both rates has the same noise and dropout.
    for (std::size_t i = 0; i < b.frame.detections.size(); ++i) {
      for (std::size_t k = 0; k < a.frame.detections.size(); ++k) {
        if (a.source_ids[k] != b.source_ids[i]) continue;
        ++compared;
        for (std::size_t j = 0; j < kJoints; ++j) {
          CHECK(a.frame.detections[k].keypoints[j].position_px ==
                b.frame.detections[i].keypoints[j].position_px);
          CHECK(a.frame.detections[k].keypoints[j].confidence ==
                b.frame.detections[i].keypoints[j].confidence);
        }
      }
    }
  }
  CHECK(compared > 200);
}

TEST_CASE("Without noise, dropout, misses and ghosts the output is a permutation", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(100);
  CorruptionOptions options;
  options.pixel_noise_px = 0.0;
  options.joint_dropout = 0.0;
  options.miss_rate = 0.0;
  options.false_positives_per_frame = 0.0;
  int reordered = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, options);
    REQUIRE(out.frame.detections.size() == 3);
    std::vector<std::int64_t> ids = out.source_ids;
    if (ids != clean.ids[f]) ++reordered;
    std::sort(ids.begin(), ids.end());
    CHECK(ids == clean.ids[f]);
    for (std::size_t i = 0; i < 3; ++i) {
      const auto& src = clean.frames[f].detections[static_cast<std::size_t>(out.source_ids[i])];
      for (std::size_t j = 0; j < kJoints; ++j) {
        CHECK(out.frame.detections[i].keypoints[j].position_px == src.keypoints[j].position_px);
      }
    }
  }
  // 5 of 6 permutations differ from the input order.
  CHECK(reordered > 60);
}

TEST_CASE("Keypoints pushed out of the image are not detected", "[unit]") {
  // A pose on the left border: about half of the noisy border keypoints fall outside.
  core::CameraFrame frame;
  frame.frame = 7;
  core::Detection2D d;
  d.layout = core::KeypointLayoutId::kShelf14;
  d.keypoints.resize(kJoints);
  for (int j = 0; j < kJoints; ++j) {
    d.keypoints[static_cast<std::size_t>(j)].position_px =
        Vec2(j % 2 == 0 ? 0.0 : 40.0, 50.0 + 10.0 * j);
    d.keypoints[static_cast<std::size_t>(j)].confidence = 1.0;
  }
  d.box = *BoxFromKeypoints(d.keypoints);
  frame.detections.push_back(d);
  CorruptionOptions options;
  options.joint_dropout = 0.0;
  options.miss_rate = 0.0;
  options.false_positives_per_frame = 0.0;
  int border = 0, lost = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    options.seed = seed;
    const CorruptedFrame out = CorruptCameraFrame(frame, {0}, {}, kWidth, kHeight, options);
    REQUIRE(out.frame.detections.size() == 1);
    for (int j = 0; j < kJoints; j += 2) {
      ++border;
      const auto& kp = out.frame.detections[0].keypoints[static_cast<std::size_t>(j)];
      if (kp.confidence == 0.0) {
        ++lost;
        CHECK(kp.position_px.x() < 0.0);
      } else {
        CHECK(kp.position_px.x() >= 0.0);
      }
    }
  }
  const double fraction = static_cast<double>(lost) / border;
  CHECK(fraction > 0.4);
  CHECK(fraction < 0.6);
}

TEST_CASE("DescribeCorruption states the level", "[unit]") {
  CHECK(DescribeCorruption(CorruptionOptions::Clean()) == "clean (no corruption)");
  const std::string text = DescribeCorruption(CorruptionOptions{});
  CHECK(text.find("sigma 2 px") != std::string::npos);
  CHECK(text.find("miss rate 0.05") != std::string::npos);
  CHECK(text.find("seed 1") != std::string::npos);
}

TEST_CASE("Corruption levels: names, the hard level and validation of the new options", "[unit]") {
  CHECK(CorruptionLevelFromName("clean") == CorruptionLevel::kClean);
  CHECK(CorruptionLevelFromName("default") == CorruptionLevel::kDefault);
  CHECK(CorruptionLevelFromName("hard") == CorruptionLevel::kHard);
  CHECK_FALSE(CorruptionLevelFromName("Hard").has_value());
  CorruptionOptions defaults;
  defaults.seed = 7;
  defaults.pixel_noise_px = 6.0;
  const CorruptionOptions hard = CorruptionForLevel(CorruptionLevel::kHard, defaults);
  CHECK(hard.enabled);
  CHECK(hard.seed == 7);
  CHECK(hard.pixel_noise_px == 6.0);  // the dataset's scale, heavier tails
  CHECK(hard.noise_tail_dof == 3);
  CHECK(hard.joint_dropout == 0.15);
  CHECK(hard.miss_rate == 0.15);
  CHECK(hard.near_false_positives_per_frame == 0.3);
  CHECK(hard.blackout_seconds == 1.0);
  CHECK(hard.Validate(nullptr));
  CHECK_FALSE(CorruptionForLevel(CorruptionLevel::kClean, defaults).enabled);
  CHECK(CorruptionForLevel(CorruptionLevel::kDefault, defaults).noise_tail_dof == 0);
  std::string why;
  CorruptionOptions bad;
  bad.noise_tail_dof = 31;
  CHECK_FALSE(bad.Validate(&why));
  CHECK(why.find("noise_tail_dof") != std::string::npos);
  bad = CorruptionOptions{};
  bad.near_false_positives_per_frame = -1.0;
  CHECK_FALSE(bad.Validate(&why));
  bad = CorruptionOptions{};
  bad.blackout_seconds = std::nan("");
  CHECK_FALSE(bad.Validate(&why));
}

TEST_CASE("PlaceBlackout puts one camera's blackout inside the test frames, seeded", "[unit]") {
  const std::vector<std::pair<FrameIndex, FrameIndex>> ranges = {{350, 470}, {650, 750}};
  std::map<CameraId, int> cameras_hit;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    CorruptionOptions o;
    o.seed = seed;
    o.blackout_seconds = 1.0;
    PlaceBlackout(&o, {0, 1, 2}, ranges, 25.0);
    REQUIRE(o.blackout_frames == 25);
    REQUIRE(o.blackout_camera >= 0);
    REQUIRE(o.blackout_camera <= 2);
    ++cameras_hit[o.blackout_camera];
    const FrameIndex last = o.blackout_first_frame + o.blackout_frames - 1;
    const bool inside = (o.blackout_first_frame >= 350 && last <= 470) ||
                        (o.blackout_first_frame >= 650 && last <= 750);
    CHECK(inside);
    CorruptionOptions again;
    again.seed = seed;
    again.blackout_seconds = 1.0;
    PlaceBlackout(&again, {0, 1, 2}, ranges, 25.0);
    CHECK(again.blackout_camera == o.blackout_camera);
    CHECK(again.blackout_first_frame == o.blackout_first_frame);
  }
  CHECK(cameras_hit.size() == 3);  // every camera can be the one
  // A short excerpt gets a blackout of half its length; none when off or disabled.
  CorruptionOptions shortie;
  shortie.blackout_seconds = 1.0;
  PlaceBlackout(&shortie, {4}, {{100, 119}}, 29.97);
  CHECK(shortie.blackout_camera == 4);
  CHECK(shortie.blackout_frames == 10);
  CHECK(shortie.blackout_first_frame >= 100);
  CHECK(shortie.blackout_first_frame + 9 <= 119);
  CorruptionOptions off;
  PlaceBlackout(&off, {0, 1}, ranges, 25.0);
  CHECK(off.blackout_camera == CorruptionOptions::kNoBlackout);
  CorruptionOptions disabled = CorruptionOptions::Clean();
  disabled.blackout_seconds = 1.0;
  PlaceBlackout(&disabled, {0, 1}, ranges, 25.0);
  CHECK(disabled.blackout_camera == CorruptionOptions::kNoBlackout);
}

TEST_CASE("A blacked-out camera detects nothing in its blackout frames only", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(40);
  CorruptionOptions o;
  o.miss_rate = 0.0;
  o.false_positives_per_frame = 0.0;
  o.blackout_camera = 3;
  o.blackout_first_frame = 1010;
  o.blackout_frames = 5;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, o);
    const FrameIndex frame = clean.frames[f].frame;
    INFO("frame " << frame);
    CHECK(out.frame.frame == frame);
    CHECK(out.frame.camera_id == 3);
    if (frame >= 1010 && frame < 1015) {
      CHECK(out.frame.detections.empty());
    } else {
      CHECK_FALSE(out.frame.detections.empty());
    }
  }
}

TEST_CASE("Student-t noise has the tails it promises, the Gaussian default has none", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(2000, 60.0);
  auto far_fraction = [&](int dof) {
    CorruptionOptions o;
    o.joint_dropout = 0.0;
    o.miss_rate = 0.0;
    o.false_positives_per_frame = 0.0;
    o.noise_tail_dof = dof;
    int far = 0, total = 0;
    for (std::size_t f = 0; f < clean.frames.size(); ++f) {
      const CorruptedFrame out =
          CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, o);
      for (std::size_t i = 0; i < out.frame.detections.size(); ++i) {
        const auto& src = clean.frames[f].detections[static_cast<std::size_t>(out.source_ids[i])];
        for (std::size_t j = 0; j < src.keypoints.size(); ++j) {
          const auto& kp = out.frame.detections[i].keypoints[j];
          if (!(kp.confidence > 0.0)) continue;  // left the image
          const Vec2 d = kp.position_px - src.keypoints[j].position_px;
          far += std::abs(d.x()) > 5.84 * o.pixel_noise_px;  // t(3)'s two-sided 1 % point
          ++total;
        }
      }
    }
    return static_cast<double>(far) / total;
  };
  const double t3 = far_fraction(3);
  const double gauss = far_fraction(0);
  INFO("beyond 5.84 scales: t3 " << t3 << ", Gaussian " << gauss);
  CHECK(std::abs(t3 - 0.01) < 0.003);  // 84k coordinates: about 4 standard errors
  CHECK(gauss < 1e-4);
}

TEST_CASE("Partial false positives sit next to a real person of the same view", "[unit]") {
  const CleanFrames clean = MakeCleanFrames(2000, 60.0);
  CorruptionOptions o;
  o.pixel_noise_px = 0.0;
  o.joint_dropout = 0.0;
  o.miss_rate = 0.0;
  o.false_positives_per_frame = 0.0;
  o.near_false_positives_per_frame = 0.3;
  int ghosts = 0;
  for (std::size_t f = 0; f < clean.frames.size(); ++f) {
    const CorruptedFrame out =
        CorruptCameraFrame(clean.frames[f], clean.ids[f], clean.pool, kWidth, kHeight, o);
    for (std::size_t i = 0; i < out.frame.detections.size(); ++i) {
      if (out.source_ids[i] != kFalsePositiveSourceId) continue;
      ++ghosts;
      const core::Detection2D& g = out.frame.detections[i];
      // Some real person of this frame, shifted sideways by 0.2-0.6 of its height, with a
      // subset of its keypoints.
      bool explained = false;
      for (const core::Detection2D& p : clean.frames[f].detections) {
        const double h = p.box.height();
        std::optional<double> dx;
        bool same = true;
        int kept = 0;
        for (std::size_t j = 0; j < p.keypoints.size() && same; ++j) {
          if (!(g.keypoints[j].confidence > 0.0)) continue;
          ++kept;
          const Vec2 d = g.keypoints[j].position_px - p.keypoints[j].position_px;
          if (!dx) dx = d.x();
          same = std::abs(d.y()) < 1e-9 && std::abs(d.x() - *dx) < 1e-9;
        }
        if (same && dx && std::abs(*dx) >= 0.2 * h - 1e-9 && std::abs(*dx) <= 0.6 * h + 1e-9 &&
            kept < static_cast<int>(p.keypoints.size())) {
          explained = true;
        }
      }
      CHECK(explained);
    }
  }
  const double rate = static_cast<double>(ghosts) / 2000.0;
  INFO("partial false positives per frame " << rate);
  // Poisson(0.3) per frame, minus the few pushed out of the image or left with < 2 keypoints.
  CHECK(rate > 0.24);
  CHECK(rate < 0.33);
}

TEST_CASE("Box-only detections get box noise scaled to the box, clipped to the image", "[unit]") {
  // Two people's boxes, 100 and 200 px tall, in a 1920 x 1080 view; one box cut by the border.
  core::CameraFrame clean;
  clean.frame = 7;
  clean.camera_id = 1;
  core::Detection2D small;
  small.box = {100.0, 100.0, 140.0, 200.0};
  core::Detection2D large;
  large.box = {500.0, 300.0, 580.0, 500.0};
  core::Detection2D cut;
  cut.box = {0.0, 900.0, 60.0, 1080.0};
  for (core::Detection2D* d : {&small, &large, &cut}) {
    d->layout = core::KeypointLayoutId::kNone;
    d->score = 1.0;
  }
  clean.detections = {small, large, cut};
  CorruptionOptions o;
  o.miss_rate = 0.0;
  o.false_positives_per_frame = 0.0;
  o.pixel_noise_px = 2.0;
  std::vector<double> small_dev, large_dev;
  for (FrameIndex f = 0; f < 2000; ++f) {
    clean.frame = f;
    const CorruptedFrame out = CorruptCameraFrame(clean, {0, 1, 2}, {}, 1920, 1080, o);
    REQUIRE(out.frame.detections.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
      const core::BoxPx& b = out.frame.detections[i].box;
      REQUIRE(out.frame.detections[i].keypoints.empty());
      CHECK(b.x_min >= 0.0);
      CHECK(b.y_max <= 1080.0);
      CHECK(b.width() >= 2.0);
      const core::BoxPx& c = clean.detections[static_cast<std::size_t>(out.source_ids[i])].box;
      if (out.source_ids[i] == 0) small_dev.push_back(b.y_max - c.y_max);
      if (out.source_ids[i] == 1) large_dev.push_back(b.y_max - c.y_max);
    }
  }
  const auto rms = [](const std::vector<double>& v) {
    double s2 = 0.0;
    for (const double x : v) s2 += x * x;
    return std::sqrt(s2 / static_cast<double>(v.size()));
  };
  // sigma = 2 px x height / 95 px: 2.1 px for 100 px, 4.2 px for 200 px.
  CHECK(rms(small_dev) == Approx(2.0 * 100.0 / kReferenceHeightPx).epsilon(0.08));
  CHECK(rms(large_dev) == Approx(2.0 * 200.0 / kReferenceHeightPx).epsilon(0.08));
  // Without noise the boxes pass unchanged (only shuffled).
  o.pixel_noise_px = 0.0;
  const CorruptedFrame still = CorruptCameraFrame(clean, {0, 1, 2}, {}, 1920, 1080, o);
  for (std::size_t i = 0; i < 3; ++i) {
    const core::BoxPx& b = still.frame.detections[i].box;
    const core::BoxPx& c = clean.detections[static_cast<std::size_t>(still.source_ids[i])].box;
    CHECK((b.x_min == c.x_min && b.y_min == c.y_min && b.x_max == c.x_max && b.y_max == c.y_max));
  }
}

TEST_CASE("Box-only false positives are pool boxes moved inside the image", "[unit]") {
  core::CameraFrame clean;
  clean.camera_id = 2;
  core::Detection2D pool_box;
  pool_box.box = {10.0, 10.0, 50.0, 130.0};
  pool_box.layout = core::KeypointLayoutId::kNone;
  CorruptionOptions o;
  o.false_positives_per_frame = 2.0;
  int ghosts = 0;
  for (FrameIndex f = 0; f < 200; ++f) {
    clean.frame = f;
    const CorruptedFrame out = CorruptCameraFrame(clean, {}, {pool_box}, 1920, 1080, o);
    for (std::size_t i = 0; i < out.frame.detections.size(); ++i) {
      CHECK(out.source_ids[i] == kFalsePositiveSourceId);
      const core::BoxPx& b = out.frame.detections[i].box;
      CHECK((b.x_min >= 0.0 && b.y_min >= 0.0 && b.x_max <= 1920.0 && b.y_max <= 1080.0));
      ++ghosts;
    }
  }
  CHECK(ghosts == Approx(400).margin(60));
}

}  // namespace
}  // namespace mvtrack::datasets
