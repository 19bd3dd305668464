#include "eval/head_rule.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "core/check.h"

namespace mvtrack::eval {
namespace {

/// Joint `name` of a BODY25 skeleton derived from `source` (layout `mapping.from`) with the
/// mapping's rule; std::nullopt when a source joint it needs is missing or it is not derivable.
std::optional<Vec3> Derived(const core::KeypointMapping& mapping,
                            std::string_view name,
                            const std::vector<std::optional<Vec3>>& source) {
  const int j = core::JointIndex(core::GetKeypointLayout(mapping.to), name);
  MVTRACK_CHECK_MSG(j >= 0, "joint missing from the target layout");
  const auto& terms = mapping.targets[static_cast<std::size_t>(j)];
  if (terms.empty()) return std::nullopt;
  Vec3 sum = Vec3::Zero();
  for (const core::JointSource& t : terms) {
    const auto s = static_cast<std::size_t>(t.source_joint);
    if (s >= source.size() || !source[s]) return std::nullopt;
    sum += t.weight * *source[s];
  }
  return sum;
}

}  // namespace

std::string_view HeadRuleName(HeadRule rule) {
  switch (rule) {
    case HeadRule::kCampus:
      return "campus";
    case HeadRule::kShelf4da:
      return "shelf-4da";
  }
  return "unknown";
}

std::optional<HeadRule> HeadRuleFromName(std::string_view name) {
  for (const HeadRule r : {HeadRule::kCampus, HeadRule::kShelf4da}) {
    if (name == HeadRuleName(r)) return r;
  }
  return std::nullopt;
}

std::optional<Vec3> FourDAssociationHeadTop(const Vec3& head_bottom,
                                            const Vec3& neck,
                                            const Vec3& mid_hip,
                                            const Vec3& r_shoulder,
                                            const Vec3& l_shoulder) {
  const Vec3 face = (neck - mid_hip).cross(r_shoulder - l_shoulder);
  const double n = face.norm();
  if (!(n > 0.0) || !std::isfinite(n)) return std::nullopt;
  return head_bottom + 0.125 * (face / n) + 0.145 * Vec3::UnitZ();
}

void ApplyHeadRule(HeadRule rule,
                   core::KeypointLayoutId from,
                   const std::vector<std::optional<Vec3>>& source,
                   std::vector<std::optional<Vec3>>* shelf14) {
  MVTRACK_CHECK(shelf14 != nullptr);
  const core::KeypointLayout& shelf = core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
  MVTRACK_CHECK_MSG(shelf14->size() == static_cast<std::size_t>(shelf.num_joints()),
                    "ApplyHeadRule: the mapped skeleton must have the shelf14 joints");
  MVTRACK_CHECK_MSG(
      source.size() == static_cast<std::size_t>(core::GetKeypointLayout(from).num_joints()),
      "ApplyHeadRule: the source skeleton must have the joints of its layout");
  if (rule == HeadRule::kCampus || from == core::KeypointLayoutId::kShelf14) return;
  const auto top = static_cast<std::size_t>(core::JointIndex(shelf, "head_top"));
  const auto bottom = static_cast<std::size_t>(core::JointIndex(shelf, "head_bottom"));
  (*shelf14)[top].reset();
  if (!(*shelf14)[bottom]) return;
  const core::KeypointMapping to_body25 =
      core::MakeKeypointMapping(from, core::KeypointLayoutId::kBody25);
  const std::optional<Vec3> neck = Derived(to_body25, "neck", source);
  const std::optional<Vec3> mid_hip = Derived(to_body25, "mid_hip", source);
  const std::optional<Vec3> r_shoulder = Derived(to_body25, "r_shoulder", source);
  const std::optional<Vec3> l_shoulder = Derived(to_body25, "l_shoulder", source);
  if (!neck || !mid_hip || !r_shoulder || !l_shoulder) return;
  (*shelf14)[top] =
      FourDAssociationHeadTop(*(*shelf14)[bottom], *neck, *mid_hip, *r_shoulder, *l_shoulder);
}

}  // namespace mvtrack::eval
