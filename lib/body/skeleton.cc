#include "body/skeleton.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"

namespace mvtrack::body {
namespace {

// The mirror image of a joint name ("l_knee" <-> "r_knee"); the name itself when it has no side.
std::string Mirror(const std::string& name) {
  if (name.rfind("l_", 0) == 0) return "r_" + name.substr(2);
  if (name.rfind("r_", 0) == 0) return "l_" + name.substr(2);
  return name;
}

}  // namespace

double BoneLengths::StatureShare(const std::string& joint_a, const std::string& joint_b) {
  const auto bare = [](const std::string& name) {
    return name.rfind("l_", 0) == 0 || name.rfind("r_", 0) == 0 ? name.substr(2) : name;
  };
  const std::string a = bare(joint_a), b = bare(joint_b);
  const auto is = [&](const char* x, const char* y) {
    return (a == x && b == y) || (a == y && b == x);
  };
  if (is("shoulder", "elbow")) return 0.186;
  if (is("elbow", "wrist")) return 0.146;
  if (is("hip", "knee")) return 0.245;
  if (is("knee", "ankle")) return 0.246;
  return 0.0;
}

BoneLengths::BoneLengths(const core::KeypointLayout& layout) : bones_(layout.bones) {
  pool_.assign(bones_.size(), -1);
  int groups = 0;
  for (std::size_t i = 0; i < bones_.size(); ++i) {
    if (pool_[i] >= 0) continue;
    pool_[i] = groups;
    const auto name = [&](int joint) { return layout.joints[static_cast<std::size_t>(joint)]; };
    const std::string a = Mirror(name(bones_[i].first)), b = Mirror(name(bones_[i].second));
    for (std::size_t j = i + 1; j < bones_.size(); ++j) {
      if (pool_[j] < 0 && ((name(bones_[j].first) == a && name(bones_[j].second) == b) ||
                           (name(bones_[j].first) == b && name(bones_[j].second) == a))) {
        pool_[j] = groups;
      }
    }
    ++groups;
  }
  samples_.resize(static_cast<std::size_t>(groups));
  share_.assign(static_cast<std::size_t>(groups), 0.0);
  for (std::size_t i = 0; i < bones_.size(); ++i) {
    share_[static_cast<std::size_t>(pool_[i])] =
        StatureShare(layout.joints[static_cast<std::size_t>(bones_[i].first)],
                     layout.joints[static_cast<std::size_t>(bones_[i].second)]);
  }
  samples_per_bone_.assign(bones_.size(), 0);
  lengths_.assign(bones_.size(), std::nullopt);
  uncertainties_.assign(bones_.size(), 0.0);
}

void BoneLengths::AddFrame(const std::vector<std::optional<Vec3>>& joints,
                           const std::vector<core::PersonView>* views,
                           double min_confidence) {
  for (std::size_t i = 0; i < bones_.size(); ++i) {
    const auto a = static_cast<std::size_t>(bones_[i].first);
    const auto b = static_cast<std::size_t>(bones_[i].second);
    if (a >= joints.size() || b >= joints.size() || !joints[a] || !joints[b]) continue;
    if (samples_per_bone_[i] >= kMaxSamples) continue;
    const double length = (*joints[a] - *joints[b]).norm();
    if (!(length >= kMinLengthM && length <= kMaxLengthM)) continue;
    double weight = 1.0;
    if (views != nullptr) {
      int seen = 0;
      for (const core::PersonView& v : *views) {
        const std::vector<double>& c = v.observation.confidence;
        seen += a < c.size() && b < c.size() && c[a] >= min_confidence && c[b] >= min_confidence;
      }
      if (seen < 2) continue;
      weight = seen - 1.0;
    }
    samples_[static_cast<std::size_t>(pool_[i])].emplace_back(length, weight);
    ++samples_per_bone_[i];
  }
}

namespace {

// The weighted median of (value, weight) pairs sorted by value: the smallest value with at least
// half the total weight at or below it.
double WeightedMedian(const std::vector<std::pair<double, double>>& sorted) {
  double total = 0.0;
  for (const auto& [value, weight] : sorted) total += weight;
  double below = 0.0;
  for (const auto& [value, weight] : sorted) {
    below += weight;
    if (below >= 0.5 * total) return value;
  }
  return sorted.back().first;
}

// The weighted median of (value, weight) samples and its standard error: 1.253 × the samples'
// robust spread (1.4826 × their weighted median absolute deviation) over √ of the effective
// sample count. Sorts `samples`.
std::pair<double, double> MedianAndError(std::vector<std::pair<double, double>>* samples) {
  std::sort(samples->begin(), samples->end());
  const double median = WeightedMedian(*samples);
  double sum = 0.0, sum2 = 0.0;
  std::vector<std::pair<double, double>> deviations;
  deviations.reserve(samples->size());
  for (const auto& [value, weight] : *samples) {
    deviations.emplace_back(std::abs(value - median), weight);
    sum += weight;
    sum2 += weight * weight;
  }
  std::sort(deviations.begin(), deviations.end());
  const double spread = 1.4826 * WeightedMedian(deviations);
  return {median, 1.253 * spread / std::sqrt(sum * sum / sum2)};
}

}  // namespace

void BoneLengths::Update() {
  // Per pooled group (a bone and its mirror image): its length and the length's standard error.
  std::vector<std::optional<double>> group_length(samples_.size());
  std::vector<double> group_uncertainty(samples_.size(), 0.0);
  std::vector<std::pair<double, double>> stature_samples;
  for (std::size_t g = 0; g < samples_.size(); ++g) {
    if (share_[g] > 0.0) {
      for (const auto& [length, weight] : samples_[g]) {
        stature_samples.emplace_back(length / share_[g], weight);
      }
    }
    if (static_cast<int>(samples_[g].size()) < kMinSamples) continue;
    std::vector<std::pair<double, double>> s = samples_[g];
    const auto [median, error] = MedianAndError(&s);
    group_length[g] = median;
    group_uncertainty[g] = error;
  }
  // The limbs' share of the stature: the prior each limb's own estimate is combined with.
  if (static_cast<int>(stature_samples.size()) >= kMinSamples) {
    const auto [stature, stature_error] = MedianAndError(&stature_samples);
    for (std::size_t g = 0; g < samples_.size(); ++g) {
      if (share_[g] <= 0.0) continue;
      const double prior = stature * share_[g];
      const double prior_sigma = std::hypot(kShareSpread * prior, stature_error * share_[g]);
      if (!group_length[g]) {
        group_length[g] = prior;
        group_uncertainty[g] = prior_sigma;
      } else if (group_uncertainty[g] > 0.0) {
        const double own = 1.0 / (group_uncertainty[g] * group_uncertainty[g]);
        const double body = 1.0 / (prior_sigma * prior_sigma);
        group_length[g] = (*group_length[g] * own + prior * body) / (own + body);
        group_uncertainty[g] = 1.0 / std::sqrt(own + body);
      }
    }
  }
  for (std::size_t i = 0; i < bones_.size(); ++i) {
    const auto g = static_cast<std::size_t>(pool_[i]);
    lengths_[i] = group_length[g];
    uncertainties_[i] = group_uncertainty[g];
  }
}

namespace {

// Each unknown's couplings: (neighbour, bone index).
using Links = std::vector<std::vector<std::pair<int, int>>>;
Links MakeLinks(std::size_t m, const std::vector<FitProblem::Bone>& bones) {
  Links links(m);
  for (std::size_t k = 0; k < bones.size(); ++k) {
    links[static_cast<std::size_t>(bones[k].slot_a)].emplace_back(bones[k].slot_b,
                                                                  static_cast<int>(k));
    links[static_cast<std::size_t>(bones[k].slot_b)].emplace_back(bones[k].slot_a,
                                                                  static_cast<int>(k));
  }
  return links;
}

// An order to eliminate the unknowns of a block system coupled by `links` in: leaves first
// (an unknown with at most one neighbour left), so a tree or forest (every layout but coco17's
// face and torso loops) is solved without fill-in; what is left when only cycles remain comes
// last, solved together densely (SolveBlocks). -1 separates the two parts.
std::vector<int> EliminationOrder(const Links& links) {
  const std::size_t m = links.size();
  std::vector<int> degree(m);
  std::vector<char> done(m, 0);
  std::vector<int> leaves;
  for (std::size_t i = 0; i < m; ++i) {
    degree[i] = static_cast<int>(links[i].size());
    if (degree[i] <= 1) leaves.push_back(static_cast<int>(i));
  }
  std::vector<int> order;
  while (!leaves.empty()) {
    const int i = leaves.back();
    leaves.pop_back();
    if (done[static_cast<std::size_t>(i)]) continue;
    done[static_cast<std::size_t>(i)] = 1;
    order.push_back(i);
    for (const auto& [j, bone] : links[static_cast<std::size_t>(i)]) {
      if (done[static_cast<std::size_t>(j)]) continue;
      if (--degree[static_cast<std::size_t>(j)] <= 1) leaves.push_back(j);
    }
  }
  order.push_back(-1);
  for (std::size_t i = 0; i < m; ++i) {
    if (!done[i]) order.push_back(static_cast<int>(i));
  }
  return order;
}

// Solves the symmetric block system (diagonal blocks `diagonal`, the block of bone k between its
// two unknowns `coupling[k]`, symmetric) for `rhs` in place, in `order` (EliminationOrder):
// each leaf is eliminated into its one remaining neighbour, the rest (cycles) is solved densely,
// then the leaves are substituted back. False when a block is singular.
bool SolveBlocks(const std::vector<int>& order,
                 const Links& links,
                 const std::vector<Eigen::Matrix3d>& coupling,
                 std::vector<Eigen::Matrix3d>* diagonal,
                 std::vector<Vec3>* rhs) {
  const std::size_t m = diagonal->size();
  std::vector<char> eliminated(m, 0);
  struct Eliminated {
    int unknown, neighbour, bone;
    Eigen::Matrix3d inverse;
  };
  std::vector<Eliminated> stack;
  std::size_t pos = 0;
  for (; pos < order.size() && order[pos] >= 0; ++pos) {
    const int i = order[pos];
    const auto u = static_cast<std::size_t>(i);
    bool invertible = false;
    Eigen::Matrix3d inverse;
    (*diagonal)[u].computeInverseWithCheck(inverse, invertible);
    if (!invertible) return false;
    int neighbour = -1, bone = -1;
    for (const auto& [j, k] : links[u]) {
      if (!eliminated[static_cast<std::size_t>(j)]) {
        neighbour = j;
        bone = k;
      }
    }
    eliminated[u] = 1;
    if (neighbour >= 0) {
      const Eigen::Matrix3d& c = coupling[static_cast<std::size_t>(bone)];
      const auto v = static_cast<std::size_t>(neighbour);
      (*diagonal)[v].noalias() -= c * inverse * c;
      (*rhs)[v].noalias() -= c * (inverse * (*rhs)[u]);
    }
    stack.push_back({i, neighbour, bone, inverse});
  }
  // What is left (cycles): densely.
  std::vector<int> rest(
      order.begin() + static_cast<std::ptrdiff_t>(std::min(pos + 1, order.size())), order.end());
  if (!rest.empty()) {
    std::vector<int> index(m, -1);
    for (std::size_t r = 0; r < rest.size(); ++r)
      index[static_cast<std::size_t>(rest[r])] = static_cast<int>(r);
    const auto n = static_cast<Eigen::Index>(3 * rest.size());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b(n);
    for (std::size_t r = 0; r < rest.size(); ++r) {
      const auto u = static_cast<std::size_t>(rest[r]);
      const auto at = static_cast<Eigen::Index>(3 * r);
      a.block<3, 3>(at, at) = (*diagonal)[u];
      b.segment<3>(at) = (*rhs)[u];
      for (const auto& [j, k] : links[u]) {
        const int other = index[static_cast<std::size_t>(j)];
        if (other < 0) continue;
        a.block<3, 3>(at, 3 * other) = coupling[static_cast<std::size_t>(k)];
      }
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
    if (ldlt.info() != Eigen::Success) return false;
    const Eigen::VectorXd x = ldlt.solve(b);
    for (std::size_t r = 0; r < rest.size(); ++r) {
      (*rhs)[static_cast<std::size_t>(rest[r])] = x.segment<3>(static_cast<Eigen::Index>(3 * r));
    }
  }
  // Back-substitution, the last eliminated first: x_i = D_i^-1 (b_i - C x_neighbour).
  for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
    const auto u = static_cast<std::size_t>(it->unknown);
    Vec3 b = (*rhs)[u];
    if (it->neighbour >= 0) {
      b -= coupling[static_cast<std::size_t>(it->bone)] *
           (*rhs)[static_cast<std::size_t>(it->neighbour)];
    }
    (*rhs)[u] = it->inverse * b;
  }
  return true;
}

}  // namespace

FitProblem MakeFitProblem(const std::vector<std::optional<Vec3>>& start,
                          const std::vector<core::PersonView>& views,
                          const std::vector<Mat34>& projections,
                          const std::vector<std::pair<int, int>>& bones,
                          const std::vector<std::optional<double>>& bone_lengths,
                          const std::vector<std::optional<Vec3>>* previous,
                          const FitOptions& options,
                          const std::vector<double>* bone_uncertainty_m) {
  MVTRACK_CHECK(bone_lengths.size() == bones.size());
  FitProblem problem;
  problem.max_iterations = options.max_iterations;
  const std::size_t n = start.size();
  problem.slot_of_joint.assign(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    if (!start[k]) continue;
    problem.slot_of_joint[k] = static_cast<int>(problem.joint_of_slot.size());
    problem.joint_of_slot.push_back(static_cast<int>(k));
  }
  for (const core::PersonView& view : views) {
    if (view.camera_index < 0 || static_cast<std::size_t>(view.camera_index) >= projections.size())
      continue;
    const Mat34& p = projections[static_cast<std::size_t>(view.camera_index)];
    const core::Observation2D& o = view.observation;
    const double scale = std::max(o.scale_px, 1.0);
    for (std::size_t k = 0; k < n && k < o.points_px.size() && k < o.confidence.size(); ++k) {
      if (!start[k] || !(o.confidence[k] >= options.min_confidence)) continue;
      // Only keypoints the starting joint reprojects near: CMMT's clustering left out the
      // others (another person's limb, a left-right swap).
      const Vec3 h = p * start[k]->homogeneous();
      if (!(h.z() > 0.0) || (h.hnormalized() - o.points_px[k]).norm() > options.gate * scale) {
        continue;
      }
      problem.reprojections.push_back(
          {problem.slot_of_joint[k],
           p,
           o.points_px[k],
           std::sqrt(o.confidence[k]) / (scale * options.reprojection_sigma)});
    }
  }
  if (problem.reprojections.empty()) return problem;  // nothing to fit to
  for (std::size_t i = 0; i < bones.size(); ++i) {
    const auto a = static_cast<std::size_t>(bones[i].first);
    const auto b = static_cast<std::size_t>(bones[i].second);
    if (!bone_lengths[i] || a >= n || b >= n || !start[a] || !start[b]) continue;
    const double u = bone_uncertainty_m != nullptr && i < bone_uncertainty_m->size()
                         ? (*bone_uncertainty_m)[i]
                         : 0.0;
    const double sigma = std::sqrt(options.bone_sigma_m * options.bone_sigma_m + u * u);
    problem.bones.push_back(
        {problem.slot_of_joint[a], problem.slot_of_joint[b], *bone_lengths[i], 1.0 / sigma});
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!start[k]) continue;
    problem.points.push_back(
        {problem.slot_of_joint[k], *start[k], 1.0 / options.anchor_sigma_m, /*robust=*/true});
    if (previous != nullptr && k < previous->size() && (*previous)[k]) {
      problem.points.push_back(
          {problem.slot_of_joint[k], *(*previous)[k], 1.0 / options.smooth_sigma_m});
    }
  }
  return problem;
}

namespace {

// The Gauss-Newton normal equations of a FitProblem at one point: a 3x3 block per unknown, one
// per bone (between its two unknowns), the gradient, and the cost (FitCost).
struct Linearization {
  std::vector<Eigen::Matrix3d> diagonal;
  std::vector<Eigen::Matrix3d> coupling;  // by bone
  std::vector<Vec3> gradient;
  double cost = 0.0;
};

// Fills `out` at `x` (its cost is FitCost's); the reprojections are reweighted by the Cauchy
// loss's ρ'(s).
void Linearize(const FitProblem& problem, const std::vector<Vec3>& x, Linearization* out) {
  const double c2 = problem.cauchy_scale * problem.cauchy_scale;
  out->diagonal.assign(x.size(), Eigen::Matrix3d::Zero());
  out->gradient.assign(x.size(), Vec3::Zero());
  out->coupling.resize(problem.bones.size());
  out->cost = 0.0;
  for (const FitProblem::Reprojection& r : problem.reprojections) {
    const auto i = static_cast<std::size_t>(r.slot);
    const Vec3 h = r.projection * x[i].homogeneous();
    if (!(h.z() > 1e-6)) continue;  // behind the camera: no information
    const Vec2 e = (h.hnormalized() - r.keypoint) * r.weight;
    const double s = e.squaredNorm();
    out->cost += c2 * std::log1p(s / c2);
    const double omega = 1.0 / (1.0 + s / c2);
    Eigen::Matrix<double, 2, 3> j;
    j.row(0) = (r.projection.block<1, 3>(0, 0) - h.x() / h.z() * r.projection.block<1, 3>(2, 0)) /
               h.z() * r.weight;
    j.row(1) = (r.projection.block<1, 3>(1, 0) - h.y() / h.z() * r.projection.block<1, 3>(2, 0)) /
               h.z() * r.weight;
    out->diagonal[i].noalias() += omega * j.transpose() * j;
    out->gradient[i].noalias() += omega * j.transpose() * e;
  }
  for (std::size_t k = 0; k < problem.bones.size(); ++k) {
    const FitProblem::Bone& b = problem.bones[k];
    const auto ia = static_cast<std::size_t>(b.slot_a), ib = static_cast<std::size_t>(b.slot_b);
    const Vec3 d = x[ia] - x[ib];
    const double length = std::max(d.norm(), 1e-9);
    const Vec3 j = d / length * b.weight;  // the residual's gradient in x_a; in x_b it is -j
    const double r = (length - b.length) * b.weight;
    out->cost += r * r;
    const Eigen::Matrix3d jj = j * j.transpose();
    out->diagonal[ia] += jj;
    out->diagonal[ib] += jj;
    out->coupling[k] = -jj;
    out->gradient[ia] += j * r;
    out->gradient[ib] -= j * r;
  }
  for (const FitProblem::Point& p : problem.points) {
    const auto i = static_cast<std::size_t>(p.slot);
    const Vec3 d = x[i] - p.point;
    const double w2 = p.weight * p.weight;
    const double s = w2 * d.squaredNorm();
    const double omega = p.robust ? 1.0 / (1.0 + s / c2) : 1.0;
    out->cost += p.robust ? c2 * std::log1p(s / c2) : s;
    out->diagonal[i].diagonal().array() += omega * w2;
    out->gradient[i] += omega * w2 * d;
  }
}

}  // namespace

double FitCost(const FitProblem& problem, const std::vector<Vec3>& x) {
  Linearization at;
  Linearize(problem, x, &at);
  return at.cost;
}

std::vector<Vec3> SolveFitProblem(const FitProblem& problem, std::vector<Vec3> x) {
  const int m = static_cast<int>(x.size());
  if (m == 0 || problem.reprojections.empty()) return x;
  // The bones as a graph on the unknowns: its elimination order holds for every iteration.
  const Links links = MakeLinks(static_cast<std::size_t>(m), problem.bones);
  const std::vector<int> order = EliminationOrder(links);
  Linearization at, trial_at;
  Linearize(problem, x, &at);
  std::vector<Eigen::Matrix3d> damped(static_cast<std::size_t>(m));
  std::vector<Vec3> step(static_cast<std::size_t>(m));
  std::vector<Vec3> trial(static_cast<std::size_t>(m));
  double lambda = 1e-4;
  for (int iteration = 0; iteration < problem.max_iterations; ++iteration) {
    for (std::size_t u = 0; u < static_cast<std::size_t>(m); ++u) {
      damped[u] = at.diagonal[u];
      damped[u].diagonal() *= 1.0 + lambda;
      step[u] = -at.gradient[u];
    }
    if (!SolveBlocks(order, links, at.coupling, &damped, &step)) break;
    double step_norm = 0.0;
    for (std::size_t u = 0; u < static_cast<std::size_t>(m); ++u) {
      trial[u] = x[u] + step[u];
      step_norm += step[u].squaredNorm();
    }
    Linearize(problem, trial, &trial_at);
    if (std::isfinite(trial_at.cost) && trial_at.cost < at.cost) {
      const bool converged =
          at.cost - trial_at.cost <= problem.relative_tolerance * at.cost || step_norm < 1e-10;
      std::swap(x, trial);
      std::swap(at, trial_at);
      lambda = std::max(lambda * 0.3, 1e-9);
      if (converged) break;
    } else {
      lambda *= 10.0;
    }
  }
  return x;
}

std::vector<std::optional<Vec3>> FitJoints(const std::vector<std::optional<Vec3>>& start,
                                           const std::vector<core::PersonView>& views,
                                           const std::vector<Mat34>& projections,
                                           const std::vector<std::pair<int, int>>& bones,
                                           const std::vector<std::optional<double>>& bone_lengths,
                                           const std::vector<std::optional<Vec3>>* previous,
                                           const FitOptions& options,
                                           const std::vector<double>* bone_uncertainty_m) {
  const FitProblem problem = MakeFitProblem(
      start, views, projections, bones, bone_lengths, previous, options, bone_uncertainty_m);
  if (problem.reprojections.empty()) return start;
  std::vector<Vec3> x;
  x.reserve(problem.joint_of_slot.size());
  for (const int k : problem.joint_of_slot) x.push_back(*start[static_cast<std::size_t>(k)]);
  x = SolveFitProblem(problem, std::move(x));
  std::vector<std::optional<Vec3>> out(start.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto k = static_cast<std::size_t>(problem.joint_of_slot[i]);
    out[k] = x[i].allFinite() ? x[i] : *start[k];
  }
  return out;
}

}  // namespace mvtrack::body
