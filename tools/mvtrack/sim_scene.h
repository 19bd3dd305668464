#pragma once
/// @file
/// Helpers shared by `mvtrack sim` and `mvtrack bench`: the scene command-line options on top of
/// sim::SizedScene, and ground truth / tracker output as evaluation frames.

#include <string>
#include <vector>

#include "eval/sequence.h"
#include "mvtrack/cli.h"
#include "sim/crowd.h"
#include "sim/scene_options.h"
#include "tracker/types.h"

namespace mvtrack::cli {

/// Declares the scene options (--cameras, --people, --layout, --room, ..., the detector rates).
void DeclareSceneOptions(Args* args);

/// sim::SizedScene(--cameras, --people, --mode == poses, --seed) with every explicitly given
/// scene option applied on top, validated. @throws UsageError naming the option on bad values.
sim::SceneOptions SceneOptionsFromArgs(const Args& args);

/// One line describing a scene: cameras, layout, floor, people, frames, detector rates.
std::string DescribeScene(const sim::SceneOptions& options);

/// The ground truth of one frame as an evaluation frame: id, footprint and (if `with_joints`)
/// the 17 COCO joints of every person in the room.
eval::EvalFrame TruthEvalFrame(const sim::FrameTruth& truth, bool with_joints);

/// One tracker output frame as an evaluation frame (id, footprint, joints if any).
eval::EvalFrame TrackEvalFrame(const tracker::Frame3D& frame);

}  // namespace mvtrack::cli
