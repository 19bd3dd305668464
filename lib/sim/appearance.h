#pragma once
/// @file
/// Synthetic re-identification embeddings (SceneOptions "Appearance"): what a DeepSORT-style
/// detector (OSNet, FastReID, DeepStream's re-id head) reports with each detection, modelled as
/// a per-identity prototype on the unit sphere plus the three effects that make real
/// embeddings hard to use: per-observation noise, drift with the viewing angle (the back of a
/// person looks different from the front) and contamination by an occluder. Look-alike pairs
/// (two people whose prototypes are close) make identity ambiguous by appearance alone. Pure,
/// deterministic; internal to lib/sim and its tests.

#include <memory>
#include <vector>

#include "core/random.h"
#include "sim/scene_options.h"

namespace mvtrack::sim {

/// The embedding_model name of simulated embeddings.
inline constexpr const char* kSimEmbeddingModel = "mvtrack-sim";

/// The appearance of one identity: unit-norm prototypes of its front and back views
/// (SceneOptions::embedding_dim entries each).
struct PersonAppearance {
  std::vector<float> front;
  std::vector<float> back;
  /// The identity this one is a look-alike of (its prototype is that one's, perturbed), or -1.
  int look_alike_of = -1;
};

/// The appearance of identity `id` under `options` (embedding_dim > 0, checked): a function of
/// (seed, id) only, so a person who leaves and comes back looks the same. Every identity's
/// front prototype is normalize(c m + sqrt(1 - c^2) u_id), with m a direction shared by the
/// whole population and c = sqrt(embedding_population_similarity), so two strangers' prototypes
/// have a cosine similarity of about embedding_population_similarity (real embeddings of
/// different people are far from orthogonal). An odd id is, with probability
/// look_alike_fraction, a look-alike of id - 1: its front prototype is id - 1's plus
/// look_alike_spread times a random unit direction, renormalised. The back prototype is the
/// front one plus embedding_view_drift times a random unit direction, renormalised.
std::shared_ptr<const PersonAppearance> MakePersonAppearance(const SceneOptions& options, int id);

/// One observed embedding (unit norm, embedding_dim entries) of `person` seen at `view_cos` (the
/// cosine between the person's facing direction and the direction to the camera on the floor:
/// 1 frontal, -1 from behind), covered to the fraction `covered` in [0, 1) by `occluder` (null:
/// none): the view's prototype normalize(w_f front + w_b back), w_f = (1 + view_cos) / 2,
/// w_b = 1 - w_f; mixed with the occluder's prototype in proportion to `covered` (the detector's
/// crop shows both); plus embedding_noise times an isotropic Gaussian of unit expected norm
/// (`noise`: embedding_dim standard normal draws), renormalised.
void ObserveEmbedding(const SceneOptions& options,
                      const PersonAppearance& person,
                      double view_cos,
                      const PersonAppearance* occluder,
                      double covered,
                      const std::vector<double>& noise,
                      std::vector<float>* embedding);

/// The embedding of a false-positive detection: a random unit vector drawn like a prototype of
/// a stranger (population direction included), from `rng`.
std::vector<float> StrangerEmbedding(const SceneOptions& options, core::Random* rng);

}  // namespace mvtrack::sim
