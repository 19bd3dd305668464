#pragma once
/// @file
/// Seeded random streams of the scene generator. Only raw std::mt19937_64 output (whose sequence
/// the C++ standard fixes) is used; the distributions are implemented here because the standard
/// library's distributions differ between implementations, which would make scenes
/// platform-dependent. Internal to lib/sim. Single-owner objects, not thread-safe.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "core/random.h"

namespace mvtrack::sim::internal {

/// Independent random streams; each is seeded by DeriveSeed(seed, stream, a, b).
enum class Stream : std::uint64_t {
  kPerson = 1,         ///< per person (a = person id): body, speed, waypoints, pauses, stays
  kPopulation = 2,     ///< initial placement, spawn timing and spawn points
  kMiss = 3,           ///< per camera-frame: miss decisions
  kNoise = 4,          ///< per camera-frame: pixel noise of true detections
  kConfidence = 5,     ///< per camera-frame: scores, keypoint confidences and dropout
  kFalsePositive = 6,  ///< per camera-frame: false-positive count, boxes and poses
  kShuffle = 7,        ///< per camera-frame: detection order
  kAppearance = 8,     ///< per person (a = id + 1): embedding prototypes; a = 0: the population's
  kEmbedding = 9,      ///< per camera-frame: embedding noise and false positives' embeddings
  kReentry = 10,       ///< re-entry decisions (enter_and_leave with reentry_probability > 0)
};

using core::Mix64;
using core::Random;

/// Seed of stream `stream` for the indices (a, b) (e.g. frame and camera), derived from the
/// master seed by chained mixing so nearby inputs give unrelated seeds.
inline std::uint64_t DeriveSeed(std::uint64_t seed,
                                Stream stream,
                                std::uint64_t a = 0,
                                std::uint64_t b = 0) {
  std::uint64_t h = Mix64(seed);
  h = Mix64(h ^ static_cast<std::uint64_t>(stream));
  h = Mix64(h ^ a);
  h = Mix64(h ^ b);
  return h;
}

}  // namespace mvtrack::sim::internal
