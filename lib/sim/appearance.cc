#include "sim/appearance.h"

#include <cmath>
#include <cstdint>

#include "core/check.h"
#include "sim/random.h"

namespace mvtrack::sim {
namespace {

using internal::DeriveSeed;
using internal::Stream;

// Sub-streams of Stream::kAppearance (argument b of DeriveSeed).
constexpr std::uint64_t kPopulationDirection = 0;
constexpr std::uint64_t kIdentity = 1;

std::vector<double> GaussianVector(int d, core::Random* rng) {
  std::vector<double> v(static_cast<std::size_t>(d));
  for (double& x : v) x = rng->Normal();
  return v;
}

void Normalize(std::vector<double>* v) {
  double n2 = 0.0;
  for (const double x : *v) n2 += x * x;
  const double n = std::sqrt(n2);
  MVTRACK_CHECK_MSG(n > 0.0, "degenerate synthetic embedding");
  for (double& x : *v) x /= n;
}

std::vector<double> UnitVector(int d, core::Random* rng) {
  std::vector<double> v = GaussianVector(d, rng);
  Normalize(&v);
  return v;
}

// normalize(a + s * unit), in place on a.
void Perturb(std::vector<double>* a, double s, const std::vector<double>& unit) {
  for (std::size_t k = 0; k < a->size(); ++k) (*a)[k] += s * unit[k];
  Normalize(a);
}

std::vector<float> ToFloat(const std::vector<double>& v) { return {v.begin(), v.end()}; }

// A stranger's prototype: the population direction mixed with a random unit vector.
std::vector<double> StrangerPrototype(const SceneOptions& o, core::Random* rng) {
  core::Random population(DeriveSeed(o.seed, Stream::kAppearance, 0, kPopulationDirection));
  const std::vector<double> m = UnitVector(o.embedding_dim, &population);
  const std::vector<double> u = UnitVector(o.embedding_dim, rng);
  const double c = std::sqrt(o.embedding_population_similarity);
  const double s = std::sqrt(1.0 - o.embedding_population_similarity);
  std::vector<double> p(u.size());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = c * m[k] + s * u[k];
  Normalize(&p);
  return p;
}

std::vector<double> FrontPrototype(const SceneOptions& o, int id, int* look_alike_of) {
  core::Random rng(
      DeriveSeed(o.seed, Stream::kAppearance, static_cast<std::uint64_t>(id) + 1, kIdentity));
  // Fixed draw order: the look-alike decision, the stranger prototype, the perturbation.
  const bool look_alike = id % 2 == 1 && rng.Uniform() < o.look_alike_fraction;
  std::vector<double> own = StrangerPrototype(o, &rng);
  const std::vector<double> spread = UnitVector(o.embedding_dim, &rng);
  if (!look_alike) {
    *look_alike_of = -1;
    return own;
  }
  int ignored = -1;
  std::vector<double> p = FrontPrototype(o, id - 1, &ignored);  // id - 1 is even: no recursion
  Perturb(&p, o.look_alike_spread, spread);
  *look_alike_of = id - 1;
  return p;
}

}  // namespace

std::shared_ptr<const PersonAppearance> MakePersonAppearance(const SceneOptions& options, int id) {
  MVTRACK_CHECK(options.embedding_dim > 0);
  MVTRACK_CHECK(id >= 0);
  auto a = std::make_shared<PersonAppearance>();
  std::vector<double> front = FrontPrototype(options, id, &a->look_alike_of);
  core::Random rng(DeriveSeed(
      options.seed, Stream::kAppearance, static_cast<std::uint64_t>(id) + 1, kIdentity + 1));
  std::vector<double> back = front;
  Perturb(&back, options.embedding_view_drift, UnitVector(options.embedding_dim, &rng));
  a->front = ToFloat(front);
  a->back = ToFloat(back);
  return a;
}

void ObserveEmbedding(const SceneOptions& options,
                      const PersonAppearance& person,
                      double view_cos,
                      const PersonAppearance* occluder,
                      double covered,
                      const std::vector<double>& noise,
                      std::vector<float>* embedding) {
  const auto d = static_cast<std::size_t>(options.embedding_dim);
  MVTRACK_CHECK(embedding != nullptr && noise.size() == d && person.front.size() == d);
  const double w_front = 0.5 * (1.0 + std::clamp(view_cos, -1.0, 1.0));
  std::vector<double> v(d);
  for (std::size_t k = 0; k < d; ++k) {
    v[k] = w_front * person.front[k] + (1.0 - w_front) * person.back[k];
  }
  Normalize(&v);
  if (occluder != nullptr && covered > 0.0) {
    const double c = std::clamp(covered, 0.0, 1.0);
    for (std::size_t k = 0; k < d; ++k) v[k] = (1.0 - c) * v[k] + c * occluder->front[k];
    Normalize(&v);
  }
  const double scale = options.embedding_noise / std::sqrt(static_cast<double>(d));
  for (std::size_t k = 0; k < d; ++k) v[k] += scale * noise[k];
  Normalize(&v);
  embedding->assign(v.begin(), v.end());
}

std::vector<float> StrangerEmbedding(const SceneOptions& options, core::Random* rng) {
  MVTRACK_CHECK(options.embedding_dim > 0 && rng != nullptr);
  return ToFloat(StrangerPrototype(options, rng));
}

}  // namespace mvtrack::sim
