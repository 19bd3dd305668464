#pragma once
/// @file
/// Keypoint layouts as data: joint names, bones, and linear mappings between layouts so any
/// detector's output can feed the tracker and any ground truth can be compared. Stateless.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mvtrack::core {

/// Known layouts. kNone means "box only, no keypoints".
enum class KeypointLayoutId : int {
  kNone = 0,
  kCoco17 = 1,      ///< COCO keypoints (17)
  kBody25 = 2,      ///< OpenPose BODY_25 (25)
  kShelf14 = 3,     ///< Shelf / Campus 14-joint evaluation skeleton
  kPanoptic19 = 4,  ///< CMU Panoptic coco19 (19)
};

/// A layout: ordered joint names (canonical snake_case names shared across layouts) and bones.
struct KeypointLayout {
  KeypointLayoutId id = KeypointLayoutId::kNone;
  std::string name;                        ///< "coco17", "body25", "shelf14", "panoptic19"
  std::vector<std::string> joints;         ///< canonical joint names, in the layout's order
  std::vector<std::pair<int, int>> bones;  ///< limb segments as joint index pairs
  int num_joints() const { return static_cast<int>(joints.size()); }
};

/// The layout table entry for `id`. For kNone returns an empty layout.
const KeypointLayout& GetKeypointLayout(KeypointLayoutId id);
/// Parses "coco17", "body25", "shelf14", "campus14" (alias of shelf14), "panoptic19", "none".
std::optional<KeypointLayoutId> KeypointLayoutFromName(std::string_view name);
/// All layouts except kNone.
std::vector<KeypointLayoutId> AllKeypointLayouts();
/// Index of the joint named `name` in `layout` ("l_elbow"); -1 when it has none.
int JointIndex(const KeypointLayout& layout, std::string_view name);

/// A target joint expressed as a weighted sum of source joints (weights sum to 1).
struct JointSource {
  int source_joint = 0;
  double weight = 1.0;
};

/// Linear mapping from one layout to another: `targets[j]` lists the source joints that make
/// target joint j; an empty list means the target joint cannot be derived.
struct KeypointMapping {
  KeypointLayoutId from = KeypointLayoutId::kNone;
  KeypointLayoutId to = KeypointLayoutId::kNone;
  std::vector<std::vector<JointSource>> targets;
};

/// Builds the mapping `from` -> `to`: joints with the same canonical name map 1:1; derived
/// joints (neck, mid_hip, head_top, ...) use the rules documented in docs/DECISIONS.md.
KeypointMapping MakeKeypointMapping(KeypointLayoutId from, KeypointLayoutId to);

/// Applies `mapping` to one set of points with per-point validity. A target joint is valid only
/// when every source joint it needs is valid. Works for 2D and 3D points.
template <typename Point>
void ApplyKeypointMapping(const KeypointMapping& mapping,
                          const std::vector<Point>& from_points,
                          const std::vector<bool>& from_valid,
                          std::vector<Point>* to_points,
                          std::vector<bool>* to_valid) {
  const std::size_t n = mapping.targets.size();
  to_points->assign(n, Point::Zero());
  to_valid->assign(n, false);
  for (std::size_t j = 0; j < n; ++j) {
    const auto& sources = mapping.targets[j];
    if (sources.empty()) continue;
    Point sum = Point::Zero();
    bool ok = true;
    for (const JointSource& s : sources) {
      const auto idx = static_cast<std::size_t>(s.source_joint);
      if (idx >= from_points.size() || idx >= from_valid.size() || !from_valid[idx]) {
        ok = false;
        break;
      }
      sum += s.weight * from_points[idx];
    }
    if (ok) {
      (*to_points)[j] = sum;
      (*to_valid)[j] = true;
    }
  }
}

}  // namespace mvtrack::core
