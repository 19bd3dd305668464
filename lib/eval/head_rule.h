#pragma once
/// @file
/// How the Shelf/Campus head part (head_bottom -> head_top) is derived from a skeleton that has
/// no head joints of that kind (COCO-17, BODY25, Panoptic). Two published conventions:
///  - kCampus: VoxelPose's `coco2campus3D`, an affine rule of the shoulders and ears (the one
///    core::MakeKeypointMapping implements): head_bottom = mean(shoulder midpoint, ear
///    midpoint), head_top = 1.5 ear midpoint - 0.5 shoulder midpoint;
///  - kShelf4da: 4D Association's Shelf evaluation (`MappingToShelf` in its evaluate_shelf
///    program): the same head_bottom, but head_top = head_bottom + 0.125 m along the facing
///    direction unit((neck - mid_hip) x (r_shoulder - l_shoulder)) + 0.145 m along world z.
///    It is the protocol in which 4D Association's published Shelf numbers (and its committed
///    output, 96.3 PCP) are stated, so it is the one to compare with them on Shelf.
/// The rule only decides head_top; every other joint is mapped as before. Pure.

#include <optional>
#include <string_view>
#include <vector>

#include "core/keypoint_layout.h"
#include "core/types.h"

namespace mvtrack::eval {

/// The head_top convention used when predictions are mapped to shelf14.
enum class HeadRule {
  kCampus,    ///< VoxelPose coco2campus3D (affine; core::MakeKeypointMapping's rule)
  kShelf4da,  ///< 4D Association MappingToShelf (facing direction + fixed offsets)
};

/// "campus" or "shelf-4da".
std::string_view HeadRuleName(HeadRule rule);

/// Inverse of HeadRuleName; std::nullopt for an unknown name.
std::optional<HeadRule> HeadRuleFromName(std::string_view name);

/// 4D Association's head top: head_bottom + 0.125 m * unit((neck - mid_hip) x (r_shoulder -
/// l_shoulder)) + 0.145 m * z. std::nullopt when that cross product is zero or not finite.
std::optional<Vec3> FourDAssociationHeadTop(const Vec3& head_bottom,
                                            const Vec3& neck,
                                            const Vec3& mid_hip,
                                            const Vec3& r_shoulder,
                                            const Vec3& l_shoulder);

/// Re-derives head_top of `shelf14` (joints already mapped to core::KeypointLayoutId::kShelf14
/// from `source`, a skeleton in layout `from`) with `rule`. kCampus leaves `shelf14` as it is;
/// kShelf4da takes neck, mid_hip and the shoulders from `source` (derived by
/// core::MakeKeypointMapping's rules when `from` has no such joint, e.g. COCO-17's neck = the
/// shoulder midpoint) and head_bottom from `shelf14`; head_top becomes std::nullopt when any of
/// them is missing. Nothing changes when `from` is shelf14 itself (its head joints are data).
/// `shelf14` must have the 14 joints of shelf14 and `source` the joints of `from`.
void ApplyHeadRule(HeadRule rule,
                   core::KeypointLayoutId from,
                   const std::vector<std::optional<Vec3>>& source,
                   std::vector<std::optional<Vec3>>* shelf14);

}  // namespace mvtrack::eval
