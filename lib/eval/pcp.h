#pragma once
/// @file
/// PCP (Percentage of Correctly estimated Parts) as the paper reports it for Campus and Shelf
/// (Sec. "Experiments", Tables "Comparison ... Campus and Shelf" and the CMMT ablation): the
/// protocol of Belagiannis et al. (3D Pictorial Structures, CVPR 2014) as implemented by the
/// evaluation code the compared methods share (MVPose, VoxelPose, 4D Association):
///  - per GT actor and frame, the prediction with the smallest mean joint error is selected;
///    identities are not used;
///  - a part (bone) with GT endpoints g_a, g_b and predicted endpoints p_a, p_b is correct iff
///    (||p_a - g_a|| + ||p_b - g_b||) / 2 <= alpha ||g_a - g_b||, alpha = 0.5;
///  - a frame in which no prediction can be selected counts every part wrong;
///  - actor PCP = correct parts / parts over all its frames; the average is over actors.
/// A bone endpoint may be a weighted set of joints, so derived parts such as the Shelf/Campus
/// torso (hip midpoint -> head_bottom) are expressed as data. Stateless and pure.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "eval/sequence.h"

namespace mvtrack::eval {

/// One term of a bone endpoint: `weight` times joint `joint`.
struct WeightedJoint {
  int joint = 0;
  double weight = 1.0;
};

/// A scored part. Each endpoint is sum_k weight_k * joint_k (weights sum to 1); an endpoint
/// exists only when all its joints are valid.
struct PcpBone {
  std::string name;
  std::vector<WeightedJoint> a;
  std::vector<WeightedJoint> b;

  /// The plain bone joint_a -> joint_b.
  static PcpBone Between(std::string name, int joint_a, int joint_b);
};

/// A named set of bones scored together (e.g. "upper arms" = both upper arms).
struct PcpBoneGroup {
  std::string name;
  std::vector<int> bones;  ///< indices into PcpProtocol::bones
};

/// The parts to score.
struct PcpProtocol {
  std::string name;  ///< stated in the result's protocol string
  std::vector<PcpBone> bones;
  std::vector<PcpBoneGroup> groups;

  /// Non-empty bones; every endpoint non-empty with joints in [0, num_joints), finite weights
  /// summing to 1 (within 1e-9); group bone indices valid. Reason written to `why` on failure.
  bool Validate(int num_joints, std::string* why) const;
};

/// The standard Shelf/Campus parts, in the shelf14 layout (core::KeypointLayoutId::kShelf14,
/// joints looked up by name): bones 0-8 as in that layout (right lower leg, right upper leg,
/// left upper leg, left lower leg, right lower arm, right upper arm, left upper arm, left lower
/// arm, head = head_bottom -> head_top) and bone 9, the torso = hip midpoint -> head_bottom;
/// groups Head [8], Torso [9], Upper arms [5, 6], Lower arms [4, 7], Upper legs [1, 2], Lower
/// legs [0, 3] (VoxelPose's `bone_group`).
PcpProtocol ShelfCampusPcpProtocol();

/// Every bone of a keypoint layout as a plain part named "<joint_a>-<joint_b>", no groups.
PcpProtocol LayoutPcpProtocol(core::KeypointLayoutId layout);

/// PCP settings. Shelf: actors {0, 1, 2}, frames [300, 600]; Campus: actors {0, 1, 2}, frames
/// [350, 470] + [650, 750] (VoxelPose's frame_range), both with alpha = 0.5.
struct PcpOptions {
  /// Correctness factor alpha (the protocol's 0.5). Finite, > 0.
  double alpha = 0.5;
  /// GT actors scored, in report order; empty = every GT id present in the evaluated frames,
  /// in increasing order. Actors that are never present get num_frames = 0 and pcp = NaN and
  /// are left out of the averages.
  std::vector<std::int64_t> actor_ids;
  /// Frames scored; empty = every GT frame.
  std::vector<FrameRange> frame_ranges;
  /// VoxelPose's "recall@500mm": an actor-frame counts as recalled iff its selected prediction
  /// has mean joint error < this. Metres, finite, > 0.
  double recall_threshold_m = 0.5;

  /// Checks the ranges above. On failure writes a reason to `why`.
  bool Validate(std::string* why) const;
};

/// PCP of one actor.
struct PcpActorResult {
  std::int64_t actor_id = 0;
  std::int64_t num_frames = 0;                     ///< scored frames with this actor in the GT
  std::int64_t num_frames_without_prediction = 0;  ///< of those, no prediction selectable
  std::int64_t correct_parts = 0;
  std::int64_t total_parts = 0;  ///< parts scored (parts with a missing GT endpoint are skipped)
  double pcp = std::numeric_limits<double>::quiet_NaN();  ///< correct / total
  std::vector<std::int64_t> bone_correct;                 ///< per protocol bone
  std::vector<std::int64_t> bone_total;                   ///< per protocol bone
  std::vector<double> group_pcp;  ///< per protocol group (NaN when never scored)
};

/// Everything EvaluatePcp computes. Averages are NaN when no actor was scored.
struct PcpResult {
  bool valid = false;  ///< false: inputs or options rejected, see `error`
  std::string error;
  /// Human-readable statement of the protocol (alpha, selection, parts, actors, frames).
  std::string protocol;
  double alpha = 0.5;
  std::vector<FrameRange> frame_ranges;
  std::vector<std::string> bone_names;
  std::vector<std::string> group_names;
  std::vector<PcpActorResult> actors;
  /// Mean of the actors' PCP (actors with at least one scored part).
  double average_pcp = std::numeric_limits<double>::quiet_NaN();
  /// Per group, mean over actors of the actor's group PCP (actors where it is defined).
  std::vector<double> average_group_pcp;
  std::int64_t recall_total = 0;    ///< scored actor-frames
  std::int64_t recall_matched = 0;  ///< of those, selected mean error < recall_threshold_m
  double recall = std::numeric_limits<double>::quiet_NaN();  ///< matched / total
};

/// Scores the 3D poses of `predictions` against `ground_truth` (both in the same layout, with
/// joints) by PCP with `protocol` and `options`. Ties in the selection go to the lowest
/// prediction id. A prediction sharing no valid joint with the GT actor cannot be selected.
PcpResult EvaluatePcp(const EvalSequence& ground_truth,
                      const EvalSequence& predictions,
                      const PcpProtocol& protocol,
                      const PcpOptions& options);

}  // namespace mvtrack::eval
