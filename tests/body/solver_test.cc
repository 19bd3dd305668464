// body::SolveFitProblem against Ceres Solver on the same residuals: the problem-specific solver
// (written for speed, docs/DECISIONS.md "Bodies") must find the minimum Ceres finds.

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "body/skeleton.h"
#include "body/test_cameras.h"

namespace mvtrack::body {
namespace {

struct ReprojectionError {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    T h[3];
    for (int i = 0; i < 3; ++i) {
      h[i] = p(i, 0) * x[0] + p(i, 1) * x[1] + p(i, 2) * x[2] + p(i, 3);
    }
    r[0] = (h[0] / h[2] - u(0)) * w;
    r[1] = (h[1] / h[2] - u(1)) * w;
    return true;
  }
  Mat34 p;
  Vec2 u;
  double w;
};

struct BoneError {
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    const T dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    r[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz) - l) * w;
    return true;
  }
  double l, w;
};

struct PointError {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = (x[i] - q(i)) * w;
    return true;
  }
  Vec3 q;
  double w;
};

// The same minimisation by Ceres (its cost is half of FitCost: the same minimiser).
std::vector<Vec3> SolveWithCeres(const FitProblem& problem, const std::vector<Vec3>& start) {
  std::vector<std::array<double, 3>> x(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) x[i] = {start[i].x(), start[i].y(), start[i].z()};
  ceres::Problem::Options options;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(options);
  ceres::CauchyLoss loss(problem.cauchy_scale);
  for (const FitProblem::Reprojection& r : problem.reprojections) {
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionError, 2, 3>(
                                       new ReprojectionError{r.projection, r.keypoint, r.weight}),
                                   &loss,
                                   x[static_cast<std::size_t>(r.slot)].data());
  }
  for (const FitProblem::Bone& b : problem.bones) {
    ceres_problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BoneError, 1, 3, 3>(new BoneError{b.length, b.weight}),
        nullptr,
        x[static_cast<std::size_t>(b.slot_a)].data(),
        x[static_cast<std::size_t>(b.slot_b)].data());
  }
  for (const FitProblem::Point& p : problem.points) {
    ceres_problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PointError, 3, 3>(new PointError{p.point, p.weight}),
        p.robust ? &loss : nullptr,
        x[static_cast<std::size_t>(p.slot)].data());
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 100;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &ceres_problem, &summary);
  std::vector<Vec3> out;
  for (const auto& p : x) out.emplace_back(p[0], p[1], p[2]);
  return out;
}

Mat34 Camera(double azimuth) { return testing::RingCamera(azimuth); }

}  // namespace

TEST_CASE("fit solver: the minimum Ceres finds, on trees and on layouts with loops", "[unit]") {
  // coco17 has loops (the torso, the face); body25 and shelf14 are a tree and a forest.
  for (const core::KeypointLayoutId id : {core::KeypointLayoutId::kCoco17,
                                          core::KeypointLayoutId::kBody25,
                                          core::KeypointLayoutId::kShelf14}) {
    const core::KeypointLayout& layout = core::GetKeypointLayout(id);
    INFO(layout.name);
    std::mt19937 rng(17);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t n = layout.joints.size();
    // A random body near the origin, seen by four cameras with 3 px of noise and 10 % of the
    // keypoints on somebody else (60 px off).
    std::vector<Vec3> truth;
    for (std::size_t k = 0; k < n; ++k) {
      truth.emplace_back(0.3 * noise(rng), 0.3 * noise(rng), 1.0 + 0.4 * noise(rng));
    }
    std::vector<Mat34> cameras;
    std::vector<core::PersonView> views;
    for (int c = 0; c < 4; ++c) {
      cameras.push_back(Camera(1.5 * c));
      core::PersonView v;
      v.camera_index = c;
      v.observation.scale_px = 600.0;
      for (const Vec3& j : truth) {
        Vec2 px = (cameras.back() * j.homogeneous()).hnormalized();
        px += 3.0 * Vec2(noise(rng), noise(rng));
        if (unit(rng) < 0.1) px += Vec2(60.0, -40.0);
        v.observation.points_px.push_back(px);
        v.observation.confidence.push_back(0.5 + 0.5 * unit(rng));
      }
      views.push_back(v);
    }
    std::vector<std::optional<Vec3>> start(n), previous(n);
    std::vector<std::optional<double>> lengths;
    for (std::size_t k = 0; k < n; ++k) {
      if (k == 3) continue;  // one joint without a start
      start[k] = truth[k] + 0.03 * Vec3(noise(rng), noise(rng), noise(rng));
      previous[k] = truth[k] + 0.05 * Vec3(noise(rng), noise(rng), noise(rng));
    }
    for (const auto& [a, b] : layout.bones) {
      lengths.push_back(
          (truth[static_cast<std::size_t>(a)] - truth[static_cast<std::size_t>(b)]).norm() *
          (1.0 + 0.03 * noise(rng)));
    }
    FitOptions options;
    options.max_iterations = 100;
    FitProblem problem =
        MakeFitProblem(start, views, cameras, layout.bones, lengths, &previous, options);
    problem.relative_tolerance = 1e-12;
    REQUIRE(problem.reprojections.size() > 2 * n);
    REQUIRE_FALSE(problem.bones.empty());
    std::vector<Vec3> x0;
    for (const int k : problem.joint_of_slot) x0.push_back(*start[static_cast<std::size_t>(k)]);
    const std::vector<Vec3> ours = SolveFitProblem(problem, x0);
    const std::vector<Vec3> reference = SolveWithCeres(problem, x0);
    CHECK(FitCost(problem, ours) <= FitCost(problem, reference) * (1.0 + 1e-6));
    for (std::size_t i = 0; i < ours.size(); ++i) {
      CHECK((ours[i] - reference[i]).norm() < 1e-4);
    }
    // The default iteration count already gets within a millimetre of it.
    FitProblem quick = problem;
    quick.max_iterations = FitOptions{}.max_iterations;
    quick.relative_tolerance = FitProblem{}.relative_tolerance;
    const std::vector<Vec3> fast = SolveFitProblem(quick, x0);
    for (std::size_t i = 0; i < fast.size(); ++i) CHECK((fast[i] - reference[i]).norm() < 1e-3);
  }
}

}  // namespace mvtrack::body
