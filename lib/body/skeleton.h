#pragma once
/// @file
/// Bodies, not point clouds (issue 40): a person's bone lengths, estimated per track from its
/// triangulated frames, and the per-frame fit of its joints to the 2D keypoints of every view
/// that sees it, with those bone lengths, near its previous frame (docs/DECISIONS.md "Bodies").
/// Pure: no I/O, deterministic; its solver is written for the problem (SolveFitProblem) and
/// checked against Ceres Solver in tests/body.

#include <optional>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "core/observation.h"
#include "core/types.h"

namespace mvtrack::body {

/// A track's bone lengths, one per bone of its layout (core::KeypointLayout::bones): the weighted
/// median of the lengths measured in its triangulated frames, a bone and its mirror image (l_
/// and r_) pooled, from the first kMaxSamples frames that measure it (then constant). A bone
/// measured in fewer than kMinSamples frames has no length (it is not constrained), unless it is
/// a limb (upper arm, forearm, thigh, shin) and the person's stature is known: then the limb's
/// share of the stature gives it one. The stature is the weighted median of every limb sample
/// divided by its limb's share (all four limbs' samples pooled: far more than any one limb has),
/// and each limb's own median is combined with its share of the stature by their uncertainties
/// (inverse-variance weights), the share uncertain by kShareSpread: a limb whose few samples
/// scatter or contradict the body's proportions leans on them, a well-measured limb keeps its
/// own length. Single-owner.
class BoneLengths {
 public:
  static constexpr int kMaxSamples = 50;
  static constexpr int kMinSamples = 5;
  /// A limb's length as a fraction of the stature, by the joints' names without the side
  /// (Drillis & Contini 1966's segment table, the one lib/sim's bodies follow); 0 for any
  /// other bone.
  static double StatureShare(const std::string& joint_a, const std::string& joint_b);
  /// How much a limb's share of the stature varies between adults, relative (docs/DECISIONS.md
  /// "Bodies": measured 3-10 %, chosen 5 %).
  static constexpr double kShareSpread = 0.05;
  /// Shortest and longest plausible bone, metres: lengths outside are not samples (the crossing
  /// of two people's rays, a joint completed far off).
  static constexpr double kMinLengthM = 0.03;
  static constexpr double kMaxLengthM = 1.0;

  explicit BoneLengths(const core::KeypointLayout& layout);

  /// One frame's triangulated joints (layout order): a sample per bone with both ends, weighted
  /// by how many of `views` see both ends with at least `min_confidence`, less one (a joint two
  /// views triangulate carries their pixel noise into 3D; more views average it out); a bone
  /// seen by fewer than two views is not sampled. Without `views` every sample weighs 1.
  void AddFrame(const std::vector<std::optional<Vec3>>& joints,
                const std::vector<core::PersonView>* views = nullptr,
                double min_confidence = 0.0);
  /// Recomputes the lengths from the samples so far (a window's frames added, then this).
  void Update();
  /// Per bone of the layout; nullopt where not measured enough.
  const std::vector<std::optional<double>>& lengths() const { return lengths_; }
  /// Per bone, metres: the standard error of its length (1.253 × the samples' robust spread,
  /// 1.4826 × their weighted median absolute deviation, over √ of the effective sample count):
  /// how far the length may still be from the person's; 0 where no length is known.
  const std::vector<double>& uncertainties() const { return uncertainties_; }

 private:
  std::vector<std::pair<int, int>> bones_;
  std::vector<int> pool_;      // per bone: the pooled group (bone and mirror)
  std::vector<double> share_;  // per group: StatureShare, 0 for a bone that is no limb
  std::vector<std::vector<std::pair<double, double>>> samples_;  // per group: (length, weight)
  std::vector<int> samples_per_bone_;                            // per bone, capped at kMaxSamples
  std::vector<std::optional<double>> lengths_;
  std::vector<double> uncertainties_;
};

/// Weights of the fit, each a standard deviation of its residual.
struct FitOptions {
  /// Reprojection error of a joint, as a fraction of the person's box scale |w + h| (the 2D
  /// detector's error grows with the person's size in the image), at confidence 1.
  double reprojection_sigma = 0.015;
  /// A keypoint whose starting joint reprojects further than this from it (a fraction of the
  /// box scale) is not used.
  double gate = 0.05;
  /// Bone length, metres: small, the lengths are the track's.
  double bone_sigma_m = 0.005;
  /// Distance to the triangulated (or completed) joint the fit starts from, metres (Cauchy
  /// loss: a start several σ off its bones and views is an outlier, not evidence).
  double anchor_sigma_m = 0.03;
  /// Distance to the same joint in the previous frame, metres (only when the previous frame is
  /// the one just before).
  double smooth_sigma_m = 0.10;
  /// Keypoints below this confidence are not used (TriangulationOptions::min_confidence).
  double min_confidence = 0.1;
  int max_iterations = 5;
};

/// The residuals of one frame's fit (MakeFitProblem), in the units of their standard deviations.
/// The unknowns are the joints that have a starting value, in joint order ("slots").
struct FitProblem {
  std::vector<int> joint_of_slot;  ///< joint index per unknown
  std::vector<int> slot_of_joint;  ///< unknown per joint, -1 for a joint without a start
  /// π(P x) − keypoint, times `weight` (1 / σ), under a Cauchy loss of scale cauchy_scale.
  struct Reprojection {
    int slot = 0;
    Mat34 projection = Mat34::Zero();
    Vec2 keypoint = Vec2::Zero();
    double weight = 1.0;
  };
  /// (|x_a − x_b| − length) × weight.
  struct Bone {
    int slot_a = 0, slot_b = 0;
    double length = 0.0;
    double weight = 1.0;
  };
  /// (x − point) × weight; under the Cauchy loss when `robust` (a starting joint: a
  /// triangulation can be wrong by metres, e.g. two nearly parallel rays), squared otherwise.
  struct Point {
    int slot = 0;
    Vec3 point = Vec3::Zero();
    double weight = 1.0;
    bool robust = false;
  };
  std::vector<Reprojection> reprojections;
  std::vector<Bone> bones;
  std::vector<Point> points;
  double cauchy_scale = 2.0;
  int max_iterations = 5;
  /// Stops when an iteration lowers the cost by less than this fraction of it.
  double relative_tolerance = 1e-4;
};

/// The residuals FitJoints minimises (see there); exposed for tests that solve them otherwise.
FitProblem MakeFitProblem(const std::vector<std::optional<Vec3>>& start,
                          const std::vector<core::PersonView>& views,
                          const std::vector<Mat34>& projections,
                          const std::vector<std::pair<int, int>>& bones,
                          const std::vector<std::optional<double>>& bone_lengths,
                          const std::vector<std::optional<Vec3>>* previous,
                          const FitOptions& options,
                          const std::vector<double>* bone_uncertainty_m = nullptr);

/// The problem's cost at `x` (one point per slot): the sum of the squared bone residuals and
/// non-robust point residuals, and of ρ(s) = c² log(1 + s / c²) over the squared norms s of the
/// reprojections and the robust points.
double FitCost(const FitProblem& problem, const std::vector<Vec3>& x);

/// Minimises FitCost from `x` (one point per slot) by Levenberg-Marquardt on the Gauss-Newton
/// normal equations with iteratively reweighted reprojections (Cauchy weights 1 / (1 + s / c²)),
/// solved sparsely (a joint couples only to the joints it shares a bone with). Returns the
/// minimiser found within problem.max_iterations.
std::vector<Vec3> SolveFitProblem(const FitProblem& problem, std::vector<Vec3> x);

/// Fits one frame's joints: minimises the confidence-weighted reprojection error of every view's
/// keypoints (Cauchy loss: a keypoint on another person or a mirrored limb costs little),
/// the deviation of each bone from `bone_lengths` (where known; its standard deviation
/// FitOptions::bone_sigma_m combined with the length's `bone_uncertainty_m`, when given), the
/// distances to the starting joints (Cauchy loss too: a joint triangulated far off its bones is
/// placed on its views' rays where the bones allow) and to `previous` (where given). Joints without
/// a starting value stay missing; joints are never removed. `projections`: by rig index,
/// undistorted pixels.
std::vector<std::optional<Vec3>> FitJoints(const std::vector<std::optional<Vec3>>& start,
                                           const std::vector<core::PersonView>& views,
                                           const std::vector<Mat34>& projections,
                                           const std::vector<std::pair<int, int>>& bones,
                                           const std::vector<std::optional<double>>& bone_lengths,
                                           const std::vector<std::optional<Vec3>>* previous,
                                           const FitOptions& options,
                                           const std::vector<double>* bone_uncertainty_m = nullptr);

}  // namespace mvtrack::body
