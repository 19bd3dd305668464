#include "body/skeleton.h"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
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

// A joint seen by one camera: its pinhole projection against the keypoint, in units of the
// keypoint's standard deviation.
struct ReprojectionError {
  ReprojectionError(const Mat34& projection, const Vec2& keypoint, double inverse_sigma)
      : p(projection), u(keypoint.x()), v(keypoint.y()), w(inverse_sigma) {}

  template <typename T>
  bool operator()(const T* joint, T* residual) const {
    T x[3];
    for (int i = 0; i < 3; ++i) {
      x[i] = p(i, 0) * joint[0] + p(i, 1) * joint[1] + p(i, 2) * joint[2] + p(i, 3);
    }
    if (x[2] <= T(1e-6)) {  // behind the camera: no information
      residual[0] = T(0);
      residual[1] = T(0);
      return true;
    }
    residual[0] = (x[0] / x[2] - u) * w;
    residual[1] = (x[1] / x[2] - v) * w;
    return true;
  }

  Mat34 p;
  double u, v, w;
};

// A bone's length against the track's.
struct BoneError {
  BoneError(double length, double inverse_sigma) : l(length), w(inverse_sigma) {}

  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    const T dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    residual[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz + T(1e-12)) - l) * w;
    return true;
  }

  double l, w;
};

// A joint's distance to a fixed point (its starting value, or the previous frame's).
struct PointError {
  PointError(const Vec3& point, double inverse_sigma) : q(point), w(inverse_sigma) {}

  template <typename T>
  bool operator()(const T* joint, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (joint[i] - q(i)) * w;
    return true;
  }

  Vec3 q;
  double w;
};

}  // namespace

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

}  // namespace

void BoneLengths::Update() {
  for (std::size_t i = 0; i < bones_.size(); ++i) {
    std::vector<std::pair<double, double>> s = samples_[static_cast<std::size_t>(pool_[i])];
    if (static_cast<int>(s.size()) < kMinSamples) {
      lengths_[i] = std::nullopt;
      uncertainties_[i] = 0.0;
      continue;
    }
    std::sort(s.begin(), s.end());
    const double median = WeightedMedian(s);
    double sum = 0.0, sum2 = 0.0;
    std::vector<std::pair<double, double>> deviations;
    deviations.reserve(s.size());
    for (const auto& [length, weight] : s) {
      deviations.emplace_back(std::abs(length - median), weight);
      sum += weight;
      sum2 += weight * weight;
    }
    std::sort(deviations.begin(), deviations.end());
    const double spread = 1.4826 * WeightedMedian(deviations);
    const double effective_samples = sum * sum / sum2;
    lengths_[i] = median;
    uncertainties_[i] = 1.253 * spread / std::sqrt(effective_samples);
  }
}

std::vector<std::optional<Vec3>> FitJoints(const std::vector<std::optional<Vec3>>& start,
                                           const std::vector<core::PersonView>& views,
                                           const std::vector<Mat34>& projections,
                                           const std::vector<std::pair<int, int>>& bones,
                                           const std::vector<std::optional<double>>& bone_lengths,
                                           const std::vector<std::optional<Vec3>>* previous,
                                           const FitOptions& options,
                                           const std::vector<double>* bone_uncertainty_m) {
  MVTRACK_CHECK(bone_lengths.size() == bones.size());
  const std::size_t n = start.size();
  std::vector<std::array<double, 3>> x(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (start[k]) x[k] = {start[k]->x(), start[k]->y(), start[k]->z()};
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss robust(2.0);
  int observed = 0;
  for (const core::PersonView& view : views) {
    if (view.camera_index < 0 || static_cast<std::size_t>(view.camera_index) >= projections.size())
      continue;
    const Mat34& p = projections[static_cast<std::size_t>(view.camera_index)];
    const core::Observation2D& o = view.observation;
    const double scale = std::max(o.scale_px, 1.0) * options.reprojection_sigma;
    for (std::size_t k = 0; k < n && k < o.points_px.size() && k < o.confidence.size(); ++k) {
      if (!start[k] || !(o.confidence[k] >= options.min_confidence)) continue;
      // Only keypoints the starting joint reprojects near: CMMT's clustering left out the
      // others (another person's limb, a left-right swap).
      const Vec3 h = p * start[k]->homogeneous();
      if (!(h.z() > 0.0) ||
          (h.hnormalized() - o.points_px[k]).norm() > options.gate * std::max(o.scale_px, 1.0)) {
        continue;
      }
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ReprojectionError, 2, 3>(
              new ReprojectionError(p, o.points_px[k], std::sqrt(o.confidence[k]) / scale)),
          &robust,
          x[k].data());
      ++observed;
    }
  }
  if (observed == 0) return start;
  for (std::size_t i = 0; i < bones.size(); ++i) {
    const auto a = static_cast<std::size_t>(bones[i].first);
    const auto b = static_cast<std::size_t>(bones[i].second);
    if (!bone_lengths[i] || a >= n || b >= n || !start[a] || !start[b]) continue;
    const double u = bone_uncertainty_m != nullptr && i < bone_uncertainty_m->size()
                         ? (*bone_uncertainty_m)[i]
                         : 0.0;
    const double sigma = std::sqrt(options.bone_sigma_m * options.bone_sigma_m + u * u);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BoneError, 1, 3, 3>(
                                 new BoneError(*bone_lengths[i], 1.0 / sigma)),
                             nullptr,
                             x[a].data(),
                             x[b].data());
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!start[k]) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointError, 3, 3>(
                                 new PointError(*start[k], 1.0 / options.anchor_sigma_m)),
                             nullptr,
                             x[k].data());
    if (previous != nullptr && k < previous->size() && (*previous)[k]) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointError, 3, 3>(
                                   new PointError(*(*previous)[k], 1.0 / options.smooth_sigma_m)),
                               nullptr,
                               x[k].data());
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  std::vector<std::optional<Vec3>> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!start[k]) continue;
    const Vec3 fitted(x[k][0], x[k][1], x[k][2]);
    out[k] = fitted.allFinite() ? fitted : *start[k];
  }
  return out;
}

}  // namespace mvtrack::body
