#pragma once
/// @file
/// A simple articulated COCO-17 body: a kinematic walking skeleton whose limbs swing with the
/// walk phase. Stateless functions.

#include <array>
#include <span>
#include <vector>

#include "core/types.h"

namespace mvtrack::sim {

/// Number of joints of the COCO-17 layout (core::KeypointLayoutId::kCoco17, same order).
inline constexpr int kNumCocoJoints = 17;

/// Pose parameters of one body at one instant.
struct BodyState {
  Vec3 footprint_m = Vec3::Zero();  ///< ground point under the pelvis (z = 0), world frame
  double heading_rad = 0.0;         ///< facing direction, counter-clockwise from world +x
  double height_m = 1.75;           ///< standing height (floor to head top)
  double walk_phase_rad = 0.0;      ///< gait phase; one period is one stride (two steps)
  double gait_amplitude = 0.0;      ///< 0 = standing still, 1 = full walking swing
};

/// The 17 COCO joints of `body` in the world frame (COCO order: nose, eyes, ears, shoulders,
/// elbows, wrists, hips, knees, ankles; left before right).
///
/// Proportions (fractions of the height H, after Drillis & Contini's segment table): hip joints
/// at 0.52 H, +-0.06 H lateral; thigh and shank 0.24 H each (ankles at 0.04 H when straight);
/// shoulders at 0.82 H, +-0.11 H; upper arm 0.18 H, forearm 0.15 H; ears at 0.925 H,
/// +-0.075 m x H/1.75; eyes 8.5 cm forward and 1.2 cm above the ears; nose 10.5 cm forward and
/// 2 cm below the ears (head offsets scale with H/1.75). Gait: hip flexion 22 deg x amplitude x
/// sin(phase) (right leg in anti-phase), knee flexion (5 + 40 max(0, cos(leg phase))) deg x
/// amplitude, arms swinging 18 deg x amplitude opposite to the leg on the same side, elbows bent
/// 12 + 8 x amplitude deg.
std::array<Vec3, kNumCocoJoints> Coco17Joints(const BodyState& body);

/// The top of the head of `body` (world frame): height H, above the ears' midpoint.
Vec3 HeadTop(const BodyState& body);

/// The points whose projections bound a person's box: the 17 COCO `joints`, the head top, and
/// per foot a heel point (4 cm behind the ankle) and a toe point (14 cm ahead of it; both
/// x H/1.75), 0.04 H below the ankle but not below the floor. `heading_rad` and `height_m` are
/// those of the body.
std::vector<Vec3> BoxPoints(std::span<const Vec3> joints,
                            const Vec3& head_top,
                            double heading_rad,
                            double height_m);

}  // namespace mvtrack::sim
