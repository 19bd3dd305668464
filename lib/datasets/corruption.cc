#include "datasets/corruption.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <utility>

#include "core/check.h"
#include "core/random.h"
#include "datasets/dataset.h"

namespace mvtrack::datasets {
namespace {

// ---------------------------------------------------------------------------------------------
// Portable random streams: only raw std::mt19937_64 output is used (its sequence is fixed by
// the C++ standard); the distributions are written here because the standard library's differ
// between implementations.

enum class Stream : std::uint64_t {
  kMiss = 1,
  kNoise = 2,
  kDropout = 3,
  kFalsePositive = 4,
  kShuffle = 5,
};

using core::Mix64;
using core::Random;

std::uint64_t StreamSeed(std::uint64_t seed, Stream stream, FrameIndex frame, CameraId camera) {
  std::uint64_t h = Mix64(seed);
  h = Mix64(h ^ static_cast<std::uint64_t>(stream));
  h = Mix64(h ^ static_cast<std::uint64_t>(frame));
  h = Mix64(h ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(camera)));
  return h;
}

bool InImage(const Vec2& p, int width, int height) {
  return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= static_cast<double>(width) &&
         p.y() <= static_cast<double>(height);
}

// Steps 2-3 of the model on one detection. Draws exactly 2 normals from `noise` and one uniform
// from `dropout` per keypoint, whatever the keypoint's state. Returns false when the detection
// is lost (a pose left with fewer than 2 detected keypoints).
bool PerturbPose(core::Detection2D* d,
                 Random* noise,
                 Random* dropout,
                 int width,
                 int height,
                 const CorruptionOptions& options) {
  for (core::Keypoint2D& kp : d->keypoints) {
    const double nx = noise->Normal();
    const double ny = noise->Normal();
    const double u = dropout->Uniform();
    if (!(kp.confidence > 0.0)) continue;
    kp.position_px += options.pixel_noise_px * Vec2(nx, ny);
    if (!InImage(kp.position_px, width, height) || u < options.joint_dropout) {
      kp.confidence = 0.0;
    }
  }
  if (d->keypoints.empty()) return true;  // box-only detection: nothing to perturb
  const std::optional<core::BoxPx> box = BoxFromKeypoints(d->keypoints);
  if (!box.has_value()) return false;
  d->box = *box;
  d->score = MeanKeypointScore(d->keypoints);
  return true;
}

// Centre coordinate that keeps an extent of `size` inside [0, limit]: uniform over the valid
// range, or the image centre when the extent does not fit.
double PlaceCentre(Random* rng, double size, int limit) {
  const double lim = static_cast<double>(limit);
  const double u = rng->Uniform();
  if (size >= lim) return 0.5 * lim;
  return 0.5 * size + u * (lim - size);
}

}  // namespace

CorruptionOptions CorruptionOptions::Clean() {
  CorruptionOptions options;
  options.enabled = false;
  return options;
}

bool CorruptionOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = std::string("corruption options: ") + reason;
    return false;
  };
  if (!(std::isfinite(pixel_noise_px) && pixel_noise_px >= 0.0)) {
    return fail("pixel_noise_px must be finite and >= 0");
  }
  if (!(joint_dropout >= 0.0 && joint_dropout <= 1.0)) {
    return fail("joint_dropout must be in [0, 1]");
  }
  if (!(miss_rate >= 0.0 && miss_rate <= 1.0)) return fail("miss_rate must be in [0, 1]");
  if (!(false_positives_per_frame >= 0.0 && false_positives_per_frame <= 50.0)) {
    return fail("false_positives_per_frame must be in [0, 50]");
  }
  return true;
}

std::string DescribeCorruption(const CorruptionOptions& options) {
  if (!options.enabled) return "clean (no corruption)";
  char text[256];
  std::snprintf(text,
                sizeof(text),
                "corrupted: seed %llu, keypoint noise sigma %.3g px, joint dropout %.3g, miss rate "
                "%.3g, false positives %.3g per camera-frame",
                static_cast<unsigned long long>(options.seed),
                options.pixel_noise_px,
                options.joint_dropout,
                options.miss_rate,
                options.false_positives_per_frame);
  return text;
}

CorruptedFrame CorruptCameraFrame(const core::CameraFrame& clean,
                                  const std::vector<std::int64_t>& clean_ids,
                                  const std::vector<core::Detection2D>& false_positive_pool,
                                  int image_width_px,
                                  int image_height_px,
                                  const CorruptionOptions& options) {
  MVTRACK_CHECK_MSG(clean_ids.size() == clean.detections.size(),
                    "clean_ids must be parallel to clean.detections");
  MVTRACK_CHECK(image_width_px > 0 && image_height_px > 0);
  MVTRACK_CHECK_MSG(options.Validate(nullptr), "invalid CorruptionOptions");

  CorruptedFrame out;
  out.frame.utime = clean.utime;
  out.frame.frame = clean.frame;
  out.frame.camera_id = clean.camera_id;
  if (!options.enabled) {
    out.frame.detections = clean.detections;
    out.source_ids = clean_ids;
    return out;
  }

  const auto seed = [&](Stream s) {
    return StreamSeed(options.seed, s, clean.frame, clean.camera_id);
  };
  Random miss(seed(Stream::kMiss));
  Random noise(seed(Stream::kNoise));
  Random dropout(seed(Stream::kDropout));
  Random ghost(seed(Stream::kFalsePositive));
  Random shuffle(seed(Stream::kShuffle));

  std::vector<std::pair<core::Detection2D, std::int64_t>> kept;
  kept.reserve(clean.detections.size() + 2);
  // Steps 1-3: misses, keypoint noise, joint dropout.
  for (std::size_t i = 0; i < clean.detections.size(); ++i) {
    const bool missed = miss.Uniform() < options.miss_rate;
    core::Detection2D d = clean.detections[i];
    const bool alive = PerturbPose(&d, &noise, &dropout, image_width_px, image_height_px, options);
    if (missed || !alive) continue;
    kept.emplace_back(std::move(d), clean_ids[i]);
  }

  // Step 4: false positives, all randomness from the false-positive stream.
  const int num_ghosts = ghost.Poisson(options.false_positives_per_frame);
  for (int g = 0; g < num_ghosts; ++g) {
    if (false_positive_pool.empty()) break;
    core::Detection2D d = false_positive_pool[ghost.Index(false_positive_pool.size())];
    const double cx = PlaceCentre(&ghost, d.box.width(), image_width_px);
    const double cy = PlaceCentre(&ghost, d.box.height(), image_height_px);
    const Vec2 shift = Vec2(cx, cy) - d.box.center();
    d.box.x_min += shift.x();
    d.box.x_max += shift.x();
    d.box.y_min += shift.y();
    d.box.y_max += shift.y();
    for (core::Keypoint2D& kp : d.keypoints) kp.position_px += shift;
    if (!PerturbPose(&d, &ghost, &ghost, image_width_px, image_height_px, options)) continue;
    kept.emplace_back(std::move(d), kFalsePositiveSourceId);
  }

  // Step 5: a uniformly random order (Fisher-Yates).
  for (std::size_t i = kept.size(); i > 1; --i) {
    const std::size_t j = shuffle.Index(i);
    std::swap(kept[i - 1], kept[j]);
  }
  out.frame.detections.reserve(kept.size());
  out.source_ids.reserve(kept.size());
  for (auto& [d, id] : kept) {
    out.frame.detections.push_back(std::move(d));
    out.source_ids.push_back(id);
  }
  return out;
}

}  // namespace mvtrack::datasets
