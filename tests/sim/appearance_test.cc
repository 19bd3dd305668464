// Synthetic embeddings and re-entries: off changes nothing, on is deterministic, unit length,
// closer for the same person than for strangers, closer still for look-alikes; a re-entering
// person keeps id, height and appearance.

#include "sim/appearance.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include "core/appearance.h"
#include "sim/crowd.h"
#include "sim/synthetic_scene.h"

namespace mvtrack::sim {
namespace {

SceneOptions Base() {
  SceneOptions o;
  o.seed = 77;
  o.num_people = 6;
  o.num_cameras = 4;
  o.num_frames = 120;
  o.pixel_noise_px = 1.5;
  o.miss_rate = 0.05;
  o.false_positives_per_frame = 0.5;
  return o;
}

double Norm(const std::vector<float>& v) {
  double n2 = 0.0;
  for (const float x : v) n2 += static_cast<double>(x) * static_cast<double>(x);
  return std::sqrt(n2);
}

TEST_CASE("embeddings off: detections carry none, on: boxes and keypoints unchanged",
          "[unit][sim]") {
  const SceneOptions off = Base();
  SceneOptions on = off;
  on.embedding_dim = 32;
  const Scene a = GenerateScene(off);
  const Scene b = GenerateScene(on);
  REQUIRE(a.detections.size() == b.detections.size());
  REQUIRE(a.detection_person_ids == b.detection_person_ids);
  int with = 0;
  for (std::size_t f = 0; f < a.detections.size(); ++f) {
    for (std::size_t c = 0; c < a.detections[f].size(); ++c) {
      const auto& x = a.detections[f][c].detections;
      const auto& y = b.detections[f][c].detections;
      REQUIRE(x.size() == y.size());
      for (std::size_t k = 0; k < x.size(); ++k) {
        CHECK(x[k].embedding.empty());
        CHECK(x[k].box.x_min == y[k].box.x_min);
        CHECK(x[k].box.y_max == y[k].box.y_max);
        CHECK(x[k].score == y[k].score);
        REQUIRE(x[k].keypoints.size() == y[k].keypoints.size());
        for (std::size_t j = 0; j < x[k].keypoints.size(); ++j) {
          CHECK(x[k].keypoints[j].position_px == y[k].keypoints[j].position_px);
        }
        REQUIRE(y[k].embedding.size() == 32u);
        CHECK(std::abs(Norm(y[k].embedding) - 1.0) < 1e-5);
        CHECK(y[k].embedding_model == kSimEmbeddingModel);
        ++with;
      }
    }
  }
  CHECK(with > 1000);
  // Deterministic.
  const Scene c = GenerateScene(on);
  for (std::size_t f = 0; f < b.detections.size(); ++f) {
    for (std::size_t cam = 0; cam < b.detections[f].size(); ++cam) {
      for (std::size_t k = 0; k < b.detections[f][cam].detections.size(); ++k) {
        REQUIRE(b.detections[f][cam].detections[k].embedding ==
                c.detections[f][cam].detections[k].embedding);
      }
    }
  }
}

// Mean cosine distance between detections of the same person / of different people.
std::pair<double, double> SameAndOtherDistance(const Scene& s) {
  double same = 0.0, other = 0.0;
  std::int64_t n_same = 0, n_other = 0;
  for (std::size_t f = 0; f + 1 < s.detections.size(); f += 7) {
    const auto& cams = s.detections[f];
    const auto& ids = s.detection_person_ids[f];
    for (std::size_t c1 = 0; c1 < cams.size(); ++c1) {
      for (std::size_t c2 = c1 + 1; c2 < cams.size(); ++c2) {
        for (std::size_t i = 0; i < cams[c1].detections.size(); ++i) {
          for (std::size_t j = 0; j < cams[c2].detections.size(); ++j) {
            if (ids[c1][i] < 0 || ids[c2][j] < 0) continue;
            const double d = core::CosineDistance(cams[c1].detections[i].embedding,
                                                  cams[c2].detections[j].embedding);
            if (ids[c1][i] == ids[c2][j]) {
              same += d;
              ++n_same;
            } else {
              other += d;
              ++n_other;
            }
          }
        }
      }
    }
  }
  REQUIRE(n_same > 50);
  REQUIRE(n_other > 50);
  return {same / static_cast<double>(n_same), other / static_cast<double>(n_other)};
}

TEST_CASE("same person closer than strangers, more noise blurs the difference", "[unit][sim]") {
  SceneOptions o = Base();
  o.embedding_dim = 128;
  o.false_positives_per_frame = 0.0;
  const auto [same, other] = SameAndOtherDistance(GenerateScene(o));
  // Noise 0.5 and a view drift of 0.5: about 0.2-0.35 for one person, about 0.7 for strangers.
  CHECK(same > 0.1);
  CHECK(same < 0.4);
  CHECK(other > 0.6);
  o.embedding_noise = 2.0;
  const auto [noisy_same, noisy_other] = SameAndOtherDistance(GenerateScene(o));
  CHECK(noisy_same > same + 0.2);
  CHECK(noisy_other - noisy_same < other - same);
}

TEST_CASE("look-alikes: odd ids near their even twin's prototype", "[unit][sim]") {
  SceneOptions o = Base();
  o.embedding_dim = 128;
  o.look_alike_fraction = 1.0;
  for (int id = 1; id < 9; id += 2) {
    const auto twin = MakePersonAppearance(o, id);
    const auto of = MakePersonAppearance(o, id - 1);
    const auto stranger = MakePersonAppearance(o, id + 1);
    CHECK(twin->look_alike_of == id - 1);
    CHECK(of->look_alike_of == -1);
    const double d_twin = core::CosineDistance(twin->front, of->front);
    const double d_stranger = core::CosineDistance(twin->front, stranger->front);
    CHECK(d_twin < 0.1);
    CHECK(d_stranger > 0.5);
  }
  o.look_alike_fraction = 0.0;
  CHECK(MakePersonAppearance(o, 1)->look_alike_of == -1);
  // A function of (seed, id) only.
  CHECK(MakePersonAppearance(o, 5)->front == MakePersonAppearance(o, 5)->front);
  SceneOptions other_seed = o;
  other_seed.seed = 78;
  CHECK(MakePersonAppearance(o, 5)->front != MakePersonAppearance(other_seed, 5)->front);
}

TEST_CASE("re-entry: a returning person keeps id, height and appearance", "[unit][sim]") {
  SceneOptions o;
  o.seed = 5;
  o.num_people = 4;
  o.num_frames = 30 * 240;
  o.enter_and_leave = true;
  o.mean_stay_s = 6.0;
  o.mean_absence_s = 2.0;
  o.embedding_dim = 16;
  o.reentry_probability = 0.8;
  o.min_reentry_absence_s = 10.0;
  o.max_reentry_absence_s = 40.0;
  REQUIRE(o.Validate(nullptr));
  CrowdSimulator crowd(o);
  std::map<int, FrameIndex> last_seen;
  std::map<int, double> height;
  std::map<int, std::vector<float>> front;
  int returns = 0;
  for (int f = 0; f < o.num_frames; ++f) {
    const FrameTruth t = crowd.Next();
    for (const PersonTruth& p : t.people) {
      REQUIRE(p.appearance != nullptr);
      const auto it = last_seen.find(p.id);
      if (it != last_seen.end() && f - it->second > 30) {
        ++returns;
        // Away for at least the minimum (less the time spent walking outside the room).
        CHECK(static_cast<double>(f - it->second) / o.fps > o.min_reentry_absence_s - 3.0);
        CHECK(static_cast<double>(f - it->second) / o.fps < o.max_reentry_absence_s + 3.0);
        CHECK(height.at(p.id) == p.height_m);
        CHECK(front.at(p.id) == p.appearance->front);
      }
      last_seen[p.id] = f;
      height[p.id] = p.height_m;
      front[p.id] = p.appearance->front;
    }
  }
  CHECK(returns >= 5);
  // Without re-entry every entry is a new id.
  o.reentry_probability = 0.0;
  CrowdSimulator plain(o);
  std::map<int, FrameIndex> seen;
  for (int f = 0; f < o.num_frames; ++f) {
    for (const PersonTruth& p : plain.Next().people) {
      const auto it = seen.find(p.id);
      if (it != seen.end()) CHECK(f - it->second <= 1);
      seen[p.id] = f;
    }
  }
}

TEST_CASE("appearance options are validated", "[unit][sim]") {
  SceneOptions o = Base();
  std::string why;
  o.embedding_dim = -1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("embedding_dim") != std::string::npos);
  o = Base();
  o.embedding_population_similarity = 1.0;
  CHECK_FALSE(o.Validate(&why));
  o = Base();
  o.embedding_noise = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  o = Base();
  o.max_reentry_absence_s = 5.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("max_reentry_absence_s") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::sim
