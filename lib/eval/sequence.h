#pragma once
/// @file
/// Plain input data for the evaluation metrics: a sequence of frames, each a list of objects
/// (an id, a footprint and optional 3D joints), used both for ground truth and for a
/// tracker's predictions, plus the two distances the metrics match objects with. Ground truth
/// and predictions must already be in the same keypoint layout (map them with
/// core::MakeKeypointMapping / core::ApplyKeypointMapping first). Stateless, pure functions.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"

namespace mvtrack::eval {

/// One ground-truth person or one predicted track in one frame.
struct EvalObject {
  /// Identity: the ground-truth actor id, or the predicted track id. Unique within a frame.
  std::int64_t id = 0;
  /// Footprint on the floor (world frame, z up, metres). Only x and y are used.
  Vec3 position = Vec3::Zero();
  /// 3D joints (world frame, metres) in the layout shared by ground truth and predictions;
  /// std::nullopt marks a missing joint. Empty for footprint-only data.
  std::vector<std::optional<Vec3>> joints;
};

/// All objects of one frame.
struct EvalFrame {
  FrameIndex frame = 0;
  std::vector<EvalObject> objects;
};

/// A sequence of frames, in any order (the metrics sort by frame index). A frame index may
/// appear at most once; frames missing from one side simply have no objects on that side.
using EvalSequence = std::vector<EvalFrame>;

/// An inclusive range of frame indices [first, last].
struct FrameRange {
  FrameIndex first = 0;
  FrameIndex last = 0;
};

/// True when `ranges` is empty (no restriction) or `frame` lies in one of them.
bool InFrameRanges(FrameIndex frame, const std::vector<FrameRange>& ranges);

/// "all" for no ranges, else "[300, 600]" or "[350, 470] + [650, 750]".
std::string DescribeFrameRanges(const std::vector<FrameRange>& ranges);

/// Checks `ranges`: every range has first <= last. On failure writes a reason to `why`.
bool ValidateFrameRanges(const std::vector<FrameRange>& ranges, std::string* why);

/// Checks one sequence: unique frame indices, unique ids within each frame, finite positions
/// and joints, and the same number of joints for every object. `name` ("ground truth",
/// "predictions") prefixes the reason written to `why` (if not null) on failure.
bool ValidateSequence(const EvalSequence& sequence, const std::string& name, std::string* why);

/// Validates both sequences and checks that they agree on the number of joints per object
/// (a sequence without objects agrees with anything). On success writes that number to
/// `num_joints` (if not null; 0 when neither side has objects).
bool ValidateSequencePair(const EvalSequence& ground_truth,
                          const EvalSequence& predictions,
                          std::string* why,
                          int* num_joints);

/// The distance objects are matched with.
enum class DistanceKind {
  kFootprint,  ///< Euclidean distance of the footprints in the ground plane (x, y), metres
  kMeanJoint,  ///< mean Euclidean 3D distance over the joints valid in both objects, metres
};

/// "footprint_xy" or "mean_joint".
const char* DistanceKindName(DistanceKind kind);

/// Ground-plane distance ||(a.x, a.y) - (b.x, b.y)||.
double FootprintDistance(const EvalObject& a, const EvalObject& b);

/// Mean over joints j valid in both of ||a_j - b_j||; std::nullopt when no joint is valid in
/// both (the pair can then never be matched). Joints beyond the shorter list are ignored.
std::optional<double> MeanJointDistance(const EvalObject& a, const EvalObject& b);

/// FootprintDistance or MeanJointDistance, as selected by `kind`.
std::optional<double> ObjectDistance(DistanceKind kind, const EvalObject& a, const EvalObject& b);

/// One evaluated frame of both sequences: each side's objects sorted by id (pointers into the
/// sequences, which must outlive it).
struct AlignedFrame {
  FrameIndex frame = 0;
  std::vector<const EvalObject*> gt;
  std::vector<const EvalObject*> pred;
};

/// The union of both sequences' frames inside `ranges` (empty: all), in increasing frame order.
std::vector<AlignedFrame> AlignFrames(const EvalSequence& ground_truth,
                                      const EvalSequence& predictions,
                                      const std::vector<FrameRange>& ranges);

}  // namespace mvtrack::eval
