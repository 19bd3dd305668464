#include "datasets/corruption.h"

#include <algorithm>
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
  kTail = 6,
  kNearFalsePositive = 7,
  kBlackout = 8,
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

// The factor sqrt(n / chi2_n) that turns a Gaussian offset into a Student-t one (n >= 1 draws
// from `tail`); 1 for Gaussian noise (no draw).
double TailScale(Random* tail, int dof) {
  if (dof <= 0) return 1.0;
  double chi2 = 0.0;
  for (int i = 0; i < dof; ++i) {
    const double z = tail->Normal();
    chi2 += z * z;
  }
  // chi2 == 0 has probability 0; the guard keeps a degenerate draw finite.
  return std::sqrt(static_cast<double>(dof) / std::max(chi2, 1e-12));
}

// Step 2 for a box-only detection (a person detector's box): each of the four edges moves by
// the keypoint noise scaled to the box, pixel_noise_px * height / kReferenceHeightPx (the
// corruption levels were set for people kReferenceHeightPx tall, Campus's median, so a level
// means the same relative error at any resolution), with the same tails; the box is clipped to
// the image. Draws exactly 4 normals from `noise` and 4 * noise_tail_dof from `tail`. Returns
// false when less than 2 px of width or height is left (the person is lost: a miss).
bool PerturbBox(core::Detection2D* d,
                Random* noise,
                Random* tail,
                int width,
                int height,
                const CorruptionOptions& options) {
  const double sigma = options.pixel_noise_px * d->box.height() / kReferenceHeightPx;
  double* const edges[4] = {&d->box.x_min, &d->box.y_min, &d->box.x_max, &d->box.y_max};
  for (double* edge : edges) {
    const double z = noise->Normal();
    *edge += sigma * TailScale(tail, options.noise_tail_dof) * z;
  }
  d->box.x_min = std::clamp(d->box.x_min, 0.0, static_cast<double>(width));
  d->box.x_max = std::clamp(d->box.x_max, 0.0, static_cast<double>(width));
  d->box.y_min = std::clamp(d->box.y_min, 0.0, static_cast<double>(height));
  d->box.y_max = std::clamp(d->box.y_max, 0.0, static_cast<double>(height));
  return d->box.width() >= 2.0 && d->box.height() >= 2.0;
}

// Steps 2-3 of the model on one detection. Draws exactly 2 normals from `noise`, noise_tail_dof
// normals from `tail` and one uniform from `dropout` per keypoint, whatever the keypoint's
// state. Returns false when the detection is lost (a pose left with fewer than 2 detected
// keypoints).
bool PerturbPose(core::Detection2D* d,
                 Random* noise,
                 Random* tail,
                 Random* dropout,
                 int width,
                 int height,
                 const CorruptionOptions& options) {
  for (core::Keypoint2D& kp : d->keypoints) {
    const double nx = noise->Normal();
    const double ny = noise->Normal();
    const double scale = TailScale(tail, options.noise_tail_dof);
    const double u = dropout->Uniform();
    if (!(kp.confidence > 0.0)) continue;
    kp.position_px += options.pixel_noise_px * scale * Vec2(nx, ny);
    if (!InImage(kp.position_px, width, height) || u < options.joint_dropout) {
      kp.confidence = 0.0;
    }
  }
  if (d->keypoints.empty()) return PerturbBox(d, noise, tail, width, height, options);
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
  if (!(near_false_positives_per_frame >= 0.0 && near_false_positives_per_frame <= 50.0)) {
    return fail("near_false_positives_per_frame must be in [0, 50]");
  }
  if (noise_tail_dof < 0 || noise_tail_dof > 30) return fail("noise_tail_dof must be in [0, 30]");
  if (!(blackout_seconds >= 0.0 && blackout_seconds <= 3600.0)) {
    return fail("blackout_seconds must be in [0, 3600]");
  }
  if (blackout_frames < 0) return fail("blackout_frames must be >= 0");
  return true;
}

std::optional<CorruptionLevel> CorruptionLevelFromName(std::string_view name) {
  if (name == "clean") return CorruptionLevel::kClean;
  if (name == "default") return CorruptionLevel::kDefault;
  if (name == "hard") return CorruptionLevel::kHard;
  return std::nullopt;
}

CorruptionOptions HardCorruption(const CorruptionOptions& defaults) {
  CorruptionOptions o = defaults;
  o.enabled = true;
  o.noise_tail_dof = 3;
  o.joint_dropout = 0.15;
  o.miss_rate = 0.15;
  o.false_positives_per_frame = 0.2;
  o.near_false_positives_per_frame = 0.3;
  o.blackout_seconds = 1.0;
  return o;
}

CorruptionOptions CorruptionForLevel(CorruptionLevel level, const CorruptionOptions& defaults) {
  switch (level) {
    case CorruptionLevel::kClean: {
      CorruptionOptions o = defaults;
      o.enabled = false;
      return o;
    }
    case CorruptionLevel::kDefault:
      return defaults;
    case CorruptionLevel::kHard:
      return HardCorruption(defaults);
  }
  return defaults;
}

void PlaceBlackout(CorruptionOptions* options,
                   const std::vector<CameraId>& cameras,
                   const std::vector<std::pair<FrameIndex, FrameIndex>>& ranges,
                   double fps) {
  options->blackout_camera = CorruptionOptions::kNoBlackout;
  options->blackout_frames = 0;
  if (!options->enabled || !(options->blackout_seconds > 0.0) || cameras.empty() || !(fps > 0.0)) {
    return;
  }
  // At most half of the longest range, so short excerpts (Panoptic's 20 frames) get one too.
  std::int64_t longest = 0;
  for (const auto& [first, last] : ranges)
    longest = std::max<std::int64_t>(longest, last - first + 1);
  const int frames = static_cast<int>(std::max<std::int64_t>(
      1, std::min<std::int64_t>(std::lround(options->blackout_seconds * fps), longest / 2)));
  // Every valid first frame, range by range.
  std::int64_t starts = 0;
  for (const auto& [first, last] : ranges)
    starts += std::max<std::int64_t>(0, last - first + 2 - frames);
  if (starts == 0) return;
  Random rng(StreamSeed(options->seed, Stream::kBlackout, 0, 0));
  const CameraId camera = cameras[rng.Index(cameras.size())];
  std::int64_t pick = static_cast<std::int64_t>(rng.Index(static_cast<std::uint64_t>(starts)));
  for (const auto& [first, last] : ranges) {
    const std::int64_t n = std::max<std::int64_t>(0, last - first + 2 - frames);
    if (pick < n) {
      options->blackout_camera = camera;
      options->blackout_first_frame = first + pick;
      options->blackout_frames = frames;
      return;
    }
    pick -= n;
  }
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
  std::string out = text;
  if (options.noise_tail_dof > 0) {
    out += ", Student-t noise tails (" + std::to_string(options.noise_tail_dof) + " dof)";
  }
  if (options.near_false_positives_per_frame > 0.0) {
    std::snprintf(text,
                  sizeof(text),
                  ", partial false positives next to real people %.3g per camera-frame",
                  options.near_false_positives_per_frame);
    out += text;
  }
  if (options.blackout_camera != CorruptionOptions::kNoBlackout) {
    out += ", camera " + std::to_string(options.blackout_camera) + " blacked out in frames " +
           std::to_string(options.blackout_first_frame) + "-" +
           std::to_string(options.blackout_first_frame + options.blackout_frames - 1);
  }
  return out;
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
  Random tail(seed(Stream::kTail));
  Random near(seed(Stream::kNearFalsePositive));

  // Step 0: a blacked-out camera detects nothing.
  if (clean.camera_id == options.blackout_camera && clean.frame >= options.blackout_first_frame &&
      clean.frame < options.blackout_first_frame + options.blackout_frames) {
    return out;
  }

  std::vector<std::pair<core::Detection2D, std::int64_t>> kept;
  kept.reserve(clean.detections.size() + 2);
  // Steps 1-3: misses, keypoint noise, joint dropout.
  for (std::size_t i = 0; i < clean.detections.size(); ++i) {
    const bool missed = miss.Uniform() < options.miss_rate;
    core::Detection2D d = clean.detections[i];
    const bool alive =
        PerturbPose(&d, &noise, &tail, &dropout, image_width_px, image_height_px, options);
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
    if (!PerturbPose(&d, &ghost, &ghost, &ghost, image_width_px, image_height_px, options)) {
      continue;
    }
    kept.emplace_back(std::move(d), kFalsePositiveSourceId);
  }

  // Step 4b: partial false positives next to a real person, all randomness from their stream.
  std::vector<std::size_t> real;  // the detected real people of this view
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (kept[i].second != kFalsePositiveSourceId) real.push_back(i);
  }
  const int num_near = options.near_false_positives_per_frame > 0.0
                           ? near.Poisson(options.near_false_positives_per_frame)
                           : 0;
  for (int g = 0; g < num_near && !real.empty(); ++g) {
    core::Detection2D d = kept[real[near.Index(real.size())]].first;
    const double side = near.Uniform() < 0.5 ? -1.0 : 1.0;
    const Vec2 shift(side * near.Uniform(0.2, 0.6) * d.box.height(), 0.0);
    d.box.x_min += shift.x();
    d.box.x_max += shift.x();
    for (core::Keypoint2D& kp : d.keypoints) {
      kp.position_px += shift;
      if (near.Uniform() < 0.5) kp.confidence = 0.0;
    }
    if (!PerturbPose(&d, &near, &near, &near, image_width_px, image_height_px, options)) continue;
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
