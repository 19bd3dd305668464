#include "config/tracker_options.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "association/options.h"
#include "config/internal/tracker_options_node.h"
#include "config/internal/yaml_node.h"
#include "core/keypoint_layout.h"
#include "triangulation/triangulation.h"

namespace mvtrack::config {
namespace {

using internal::DoubleRange;
using internal::FormatDouble;
using internal::GetDouble;
using internal::GetEnum;
using internal::GetInt;
using internal::GetInt64;
using internal::KeyHint;
using internal::MapRef;
using internal::NodeRef;
using tracker::TrackerOptions;

constexpr std::array<std::pair<tracker::InputMode, std::string_view>, 2> kInputModeNames = {{
    {tracker::InputMode::kBoxes, "boxes"},
    {tracker::InputMode::kPoses, "poses"},
}};
constexpr std::array<std::pair<tracker::BoxPoint, std::string_view>, 3> kBoxPointNames = {{
    {tracker::BoxPoint::kCenter, "center"},
    {tracker::BoxPoint::kBottomCenter, "bottom_center"},
    {tracker::BoxPoint::kCenterEnds, "center_ends"},
}};

// The sub-maps of `tracker:`, in output order.
const std::vector<std::string> kSections = {
    "sort", "association", "triangulation", "linking", "refinement", "appearance"};

// One option: its sub-map ("" = directly under `tracker:`), its key, how to read it from YAML
// (with the range checks of the owning struct's Validate, so errors point at the key) and how
// to write it. The table is the single list of options: parsing, writing, the allowed keys and
// the did-you-mean hints all derive from it.
struct Field {
  std::string section;
  std::string key;
  std::function<void(const NodeRef&, TrackerOptions*)> parse;
  std::function<std::string(const TrackerOptions&)> format;
};

// `access` is a generic lambda returning a reference to the option in a (const) TrackerOptions.
template <typename Access>
Field IntField(std::string section, std::string key, Access access, int min, int max) {
  return Field{std::move(section),
               std::move(key),
               [=](const NodeRef& node, TrackerOptions* o) { access(*o) = GetInt(node, min, max); },
               [=](const TrackerOptions& o) { return std::to_string(access(o)); }};
}

template <typename Access>
Field Int64Field(std::string section, std::string key, Access access, std::int64_t min) {
  return Field{std::move(section),
               std::move(key),
               [=](const NodeRef& node, TrackerOptions* o) { access(*o) = GetInt64(node, min); },
               [=](const TrackerOptions& o) { return std::to_string(access(o)); }};
}

template <typename Access>
Field DoubleField(std::string section, std::string key, Access access, DoubleRange range) {
  return Field{std::move(section),
               std::move(key),
               [=](const NodeRef& node, TrackerOptions* o) { access(*o) = GetDouble(node, range); },
               [=](const TrackerOptions& o) { return FormatDouble(access(o)); }};
}

template <typename Enum, typename Access, typename FromName, typename ToName>
Field EnumField(std::string section,
                std::string key,
                Access access,
                FromName from_name,
                ToName to_name,
                std::vector<std::string> names) {
  return Field{std::move(section),
               std::move(key),
               [=](const NodeRef& node, TrackerOptions* o) {
                 access(*o) = GetEnum<Enum>(node, from_name, names);
               },
               [=](const TrackerOptions& o) { return std::string(to_name(access(o))); }};
}

// true / false only (YAML's yes, on, 1 ... are refused like every non-canonical scalar).
template <typename Access>
Field BoolField(std::string section, std::string key, Access access) {
  static const std::vector<std::string> kNames = {"true", "false"};
  return Field{std::move(section),
               std::move(key),
               [=](const NodeRef& node, TrackerOptions* o) {
                 access(*o) = GetEnum<bool>(
                     node,
                     [](std::string_view name) -> std::optional<bool> {
                       if (name == "true") return true;
                       if (name == "false") return false;
                       return std::nullopt;
                     },
                     kNames);
               },
               [=](const TrackerOptions& o) { return std::string(access(o) ? "true" : "false"); }};
}

std::string LayoutName(core::KeypointLayoutId id) { return core::GetKeypointLayout(id).name; }

std::vector<std::string> LayoutNames() {
  std::vector<std::string> names;
  for (const core::KeypointLayoutId id : core::AllKeypointLayouts()) {
    names.push_back(LayoutName(id));
  }
  names.push_back("campus14");
  names.push_back(LayoutName(core::KeypointLayoutId::kNone));
  return names;
}

std::vector<std::string> ClusteringMethodNames() {
  std::vector<std::string> names;
  for (const association::ClusteringMethod m :
       {association::ClusteringMethod::kPdnc,
        association::ClusteringMethod::kCompleteLinkageEmptyAsZero,
        association::ClusteringMethod::kCompleteLinkageEmptyAsUpper,
        association::ClusteringMethod::kSingleLinkageEmptyAsUpper}) {
    names.emplace_back(association::ClusteringMethodName(m));
  }
  return names;
}

std::vector<std::string> TriangulationMethodNames() {
  std::vector<std::string> names;
  for (const triangulation::TriangulationMethod m : {triangulation::TriangulationMethod::kCmmt,
                                                     triangulation::TriangulationMethod::kDlt,
                                                     triangulation::TriangulationMethod::kRansac}) {
    names.emplace_back(triangulation::TriangulationMethodName(m));
  }
  return names;
}

std::vector<Field> MakeFields() {
  constexpr int kIntMax = std::numeric_limits<int>::max();
  const DoubleRange unit = DoubleRange::Closed(0.0, 1.0);
  std::vector<Field> f;
  // tracker (TrackerOptions::Validate; cross-field rules are left to Validate itself).
  f.push_back(EnumField<tracker::InputMode>("",
                                            "mode",
                                            [](auto& o) -> auto& { return o.mode; },
                                            InputModeFromName,
                                            InputModeName,
                                            {"boxes", "poses"}));
  f.push_back(EnumField<core::KeypointLayoutId>(
      "",
      "layout",
      [](auto& o) -> auto& { return o.layout; },
      [](std::string_view name) { return core::KeypointLayoutFromName(name); },
      LayoutName,
      LayoutNames()));
  f.push_back(IntField(
      "", "window_size", [](auto& o) -> auto& { return o.window_size; }, 2, 10000));
  f.push_back(IntField(
      "", "window_step", [](auto& o) -> auto& { return o.window_step; }, 1, 10000));
  f.push_back(DoubleField(
      "",
      "reference_fps",
      [](auto& o) -> auto& { return o.reference_fps; },
      DoubleRange::Closed(0.0, 1000.0)));
  f.push_back(EnumField<tracker::BoxPoint>("",
                                           "box_point",
                                           [](auto& o) -> auto& { return o.box_point; },
                                           BoxPointFromName,
                                           BoxPointName,
                                           {"center", "bottom_center", "center_ends"}));
  f.push_back(BoolField(
      "", "box_ends_in_association", [](auto& o) -> auto& { return o.box_ends_in_association; }));
  f.push_back(BoolField(
      "", "box_complete_cut", [](auto& o) -> auto& { return o.box_complete_cut; }));
  f.push_back(DoubleField(
      "",
      "box_ends_max_elevation_deg",
      [](auto& o) -> auto& { return o.box_ends_max_elevation_deg; },
      DoubleRange::Closed(0.0, 90.0)));
  f.push_back(DoubleField(
      "",
      "ground_height_m",
      [](auto& o) -> auto& { return o.ground_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "",
      "monocular_min_elevation_deg",
      [](auto& o) -> auto& { return o.monocular_min_elevation_deg; },
      DoubleRange::Closed(0.0, 90.0)));
  f.push_back(DoubleField(
      "",
      "bridge_max_gap_s",
      [](auto& o) -> auto& { return o.bridge_max_gap_s; },
      DoubleRange::Closed(0.0, 10.0)));
  f.push_back(DoubleField(
      "", "min_detection_score", [](auto& o) -> auto& { return o.min_detection_score; }, unit));
  f.push_back(DoubleField(
      "",
      "min_keypoint_confidence",
      [](auto& o) -> auto& { return o.min_keypoint_confidence; },
      unit));
  f.push_back(IntField(
      "", "min_pose_keypoints", [](auto& o) -> auto& { return o.min_pose_keypoints; }, 1, kIntMax));
  f.push_back(IntField(
      "",
      "min_tracklet_length",
      [](auto& o) -> auto& { return o.min_tracklet_length; },
      1,
      kIntMax));
  f.push_back(Int64Field(
      "", "max_frame_jump", [](auto& o) -> auto& { return o.max_frame_jump; }, 2));
  f.push_back(DoubleField(
      "",
      "box_margin_fraction",
      [](auto& o) -> auto& { return o.box_margin_fraction; },
      DoubleRange::Closed(0.0, 10.0)));
  f.push_back(IntField(
      "",
      "max_detections_per_frame",
      [](auto& o) -> auto& { return o.max_detections_per_frame; },
      1,
      kIntMax));
  // sort (tracking2d::SortOptions::Validate).
  f.push_back(IntField(
      "sort", "max_age", [](auto& o) -> auto& { return o.sort.max_age; }, 0, kIntMax));
  f.push_back(IntField(
      "sort", "min_hits", [](auto& o) -> auto& { return o.sort.min_hits; }, 1, kIntMax));
  f.push_back(DoubleField(
      "sort",
      "iou_threshold",
      [](auto& o) -> auto& { return o.sort.iou_threshold; },
      DoubleRange::LeftOpen(0.0, 1.0)));
  // association (association::AssociationOptions::Validate).
  f.push_back(DoubleField(
      "association",
      "lambda",
      [](auto& o) -> auto& { return o.association.lambda; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "association",
      "min_confidence",
      [](auto& o) -> auto& { return o.association.min_confidence; },
      unit));
  f.push_back(EnumField<association::ClusteringMethod>(
      "association",
      "method",
      [](auto& o) -> auto& { return o.association.method; },
      association::ClusteringMethodFromName,
      association::ClusteringMethodName,
      ClusteringMethodNames()));
  f.push_back(DoubleField(
      "association",
      "empty_upper_bound",
      [](auto& o) -> auto& { return o.association.empty_upper_bound; },
      DoubleRange::AtLeast(0.0)));
  // triangulation (triangulation::TriangulationOptions::Validate).
  f.push_back(EnumField<triangulation::TriangulationMethod>(
      "triangulation",
      "method",
      [](auto& o) -> auto& { return o.triangulation.method; },
      triangulation::TriangulationMethodFromName,
      triangulation::TriangulationMethodName,
      TriangulationMethodNames()));
  f.push_back(IntField(
      "triangulation", "phi", [](auto& o) -> auto& { return o.triangulation.phi; }, 0, kIntMax));
  f.push_back(DoubleField(
      "triangulation",
      "kappa_m",
      [](auto& o) -> auto& { return o.triangulation.kappa_m; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "triangulation",
      "min_confidence",
      [](auto& o) -> auto& { return o.triangulation.min_confidence; },
      unit));
  f.push_back(DoubleField(
      "triangulation",
      "ransac_threshold_px",
      [](auto& o) -> auto& { return o.triangulation.ransac_threshold_px; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(IntField(
      "triangulation",
      "min_inliers",
      [](auto& o) -> auto& { return o.triangulation.min_inliers; },
      1,
      kIntMax));
  f.push_back(
      Field{"triangulation",
            "max_views",
            [](const NodeRef& node, TrackerOptions* o) {
              const int value = GetInt(node, 0, kIntMax);
              if (value == 1) {
                node.Fail("value 1 out of range: must be 0 (all views) or >= 2");
              }
              o->triangulation.max_views = value;
            },
            [](const TrackerOptions& o) { return std::to_string(o.triangulation.max_views); }});
  // linking (linking::LinkerOptions::Validate).
  f.push_back(DoubleField(
      "linking",
      "max_link_distance_m",
      [](auto& o) -> auto& { return o.linking.max_link_distance_m; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(IntField(
      "linking", "min_hits", [](auto& o) -> auto& { return o.linking.min_hits; }, 1, kIntMax));
  f.push_back(IntField(
      "linking",
      "strong_birth_cameras",
      [](auto& o) -> auto& { return o.linking.strong_birth_cameras; },
      2,
      kIntMax));
  f.push_back(BoolField(
      "linking", "fragment_births_wait", [](auto& o) -> auto& {
        return o.linking.fragment_births_wait;
      }));
  f.push_back(IntField(
      "linking",
      "fragment_min_hits",
      [](auto& o) -> auto& { return o.linking.fragment_min_hits; },
      1,
      kIntMax));
  f.push_back(DoubleField(
      "linking",
      "isolated_birth_distance_m",
      [](auto& o) -> auto& { return o.linking.isolated_birth_distance_m; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "duplicate_distance_m",
      [](auto& o) -> auto& { return o.linking.duplicate_distance_m; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "duplicate_max_gap_s",
      [](auto& o) -> auto& { return o.linking.duplicate_max_gap_s; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(BoolField(
      "linking", "merge_linked_duplicates", [](auto& o) -> auto& {
        return o.linking.merge_linked_duplicates;
      }));
  f.push_back(DoubleField(
      "linking",
      "max_lost_s",
      [](auto& o) -> auto& { return o.linking.max_lost_s; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "monocular_max_s",
      [](auto& o) -> auto& { return o.linking.monocular_max_s; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "measurement_sigma_m",
      [](auto& o) -> auto& { return o.linking.motion.measurement_sigma_m; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "linking",
      "acceleration_sigma_mps2",
      [](auto& o) -> auto& { return o.linking.motion.acceleration_sigma_mps2; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "linking",
      "initial_speed_sigma_mps",
      [](auto& o) -> auto& { return o.linking.motion.initial_speed_sigma_mps; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "linking",
      "gap_gate_chi2",
      [](auto& o) -> auto& { return o.linking.gap_gate_chi2; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(DoubleField(
      "linking",
      "reid_gate_chi2",
      [](auto& o) -> auto& { return o.linking.reid_gate_chi2; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "reid_margin_chi2",
      [](auto& o) -> auto& { return o.linking.reid_margin_chi2; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "linking",
      "max_reid_gap_s",
      [](auto& o) -> auto& { return o.linking.max_reid_gap_s; },
      DoubleRange::AtLeast(0.0)));
  // refinement (triangulation::RefinementOptions::Validate; pose mode, after CMMT).
  f.push_back(DoubleField(
      "refinement",
      "merge_distance_m",
      [](auto& o) -> auto& { return o.refinement.merge_distance_m; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(IntField(
      "refinement",
      "box_min_duplicate_frames",
      [](auto& o) -> auto& { return o.refinement.box_min_duplicate_frames; },
      1,
      kIntMax));
  f.push_back(IntField(
      "refinement",
      "min_duplicate_pairs",
      [](auto& o) -> auto& { return o.refinement.min_duplicate_pairs; },
      1,
      kIntMax));
  f.push_back(DoubleField(
      "refinement",
      "box_merge_distance_m",
      [](auto& o) -> auto& { return o.refinement.box_merge_distance_m; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "refinement",
      "box_min_height_m",
      [](auto& o) -> auto& { return o.refinement.box_min_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "box_max_height_m",
      [](auto& o) -> auto& { return o.refinement.box_max_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "box_bottom_min_height_m",
      [](auto& o) -> auto& { return o.refinement.box_bottom_min_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "box_bottom_max_height_m",
      [](auto& o) -> auto& { return o.refinement.box_bottom_max_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "box_top_min_height_m",
      [](auto& o) -> auto& { return o.refinement.box_top_min_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "box_top_max_height_m",
      [](auto& o) -> auto& { return o.refinement.box_top_max_height_m; },
      DoubleRange::Any()));
  f.push_back(DoubleField(
      "refinement",
      "jump_gate_chi2",
      [](auto& o) -> auto& { return o.refinement.jump_gate_chi2; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "refinement",
      "box_split_residual",
      [](auto& o) -> auto& { return o.refinement.box_split_residual; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "refinement",
      "min_person_point_fraction",
      [](auto& o) -> auto& { return o.refinement.min_person_point_fraction; },
      unit));
  f.push_back(IntField(
      "refinement",
      "outlier_half_window",
      [](auto& o) -> auto& { return o.refinement.outlier_half_window; },
      0,
      kIntMax));
  f.push_back(DoubleField(
      "refinement",
      "outlier_distance_m",
      [](auto& o) -> auto& { return o.refinement.outlier_distance_m; },
      DoubleRange::GreaterThan(0.0)));
  f.push_back(IntField(
      "refinement",
      "smooth_half_window",
      [](auto& o) -> auto& { return o.refinement.smooth_half_window; },
      0,
      kIntMax));
  f.push_back(IntField(
      "refinement",
      "smooth_max_views",
      [](auto& o) -> auto& { return o.refinement.smooth_max_views; },
      0,
      kIntMax));
  f.push_back(BoolField(
      "refinement", "fit_skeleton", [](auto& o) -> auto& { return o.refinement.fit_skeleton; }));
  f.push_back(IntField(
      "refinement",
      "max_fill_gap",
      [](auto& o) -> auto& { return o.refinement.max_fill_gap; },
      0,
      kIntMax));
  f.push_back(IntField(
      "refinement",
      "fill_neighbors",
      [](auto& o) -> auto& { return o.refinement.fill_neighbors; },
      1,
      kIntMax));
  f.push_back(BoolField(
      "appearance", "enabled", [](auto& o) -> auto& { return o.appearance.enabled; }));
  f.push_back(IntField(
      "appearance",
      "gallery_size",
      [](auto& o) -> auto& { return o.appearance.gallery_size; },
      1,
      kIntMax));
  f.push_back(DoubleField(
      "appearance",
      "reid_max_distance",
      [](auto& o) -> auto& { return o.appearance.reid_max_distance; },
      DoubleRange::Closed(0.0, 2.0)));
  f.push_back(DoubleField(
      "appearance",
      "reid_margin",
      [](auto& o) -> auto& { return o.appearance.reid_margin; },
      DoubleRange::Closed(0.0, 2.0)));
  f.push_back(BoolField(
      "appearance", "reid_disjoint_same_person", [](auto& o) -> auto& {
        return o.appearance.reid_disjoint_same_person;
      }));
  f.push_back(DoubleField(
      "appearance",
      "max_reid_s",
      [](auto& o) -> auto& { return o.appearance.max_reid_s; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(BoolField(
      "appearance", "defer_weak_reid", [](auto& o) -> auto& {
        return o.appearance.defer_weak_reid;
      }));
  f.push_back(IntField(
      "appearance",
      "max_departed",
      [](auto& o) -> auto& { return o.appearance.max_departed; },
      0,
      kIntMax));
  f.push_back(DoubleField(
      "appearance",
      "link_max_distance",
      [](auto& o) -> auto& { return o.appearance.link_max_distance; },
      DoubleRange::Closed(0.0, 2.0)));
  f.push_back(DoubleField(
      "appearance",
      "association_weight",
      [](auto& o) -> auto& { return o.appearance.association_weight; },
      DoubleRange::AtLeast(0.0)));
  f.push_back(DoubleField(
      "appearance",
      "association_gate",
      [](auto& o) -> auto& { return o.appearance.association_gate; },
      DoubleRange::Closed(0.0, 2.0)));
  f.push_back(DoubleField(
      "appearance",
      "sort_weight",
      [](auto& o) -> auto& { return o.appearance.sort_weight; },
      unit));
  f.push_back(DoubleField(
      "appearance",
      "sort_gate",
      [](auto& o) -> auto& { return o.appearance.sort_gate; },
      DoubleRange::Closed(0.0, 2.0)));
  f.push_back(IntField(
      "appearance",
      "sort_gallery_size",
      [](auto& o) -> auto& { return o.appearance.sort_gallery_size; },
      1,
      kIntMax));
  f.push_back(IntField(
      "refinement",
      "min_points_to_fill",
      [](auto& o) -> auto& { return o.refinement.min_points_to_fill; },
      1,
      kIntMax));
  return f;
}

const std::vector<Field>& Fields() {
  static const std::vector<Field> fields = MakeFields();
  return fields;
}

const Field* FindField(std::string_view section, std::string_view key) {
  for (const Field& field : Fields()) {
    if (field.section == section && field.key == key) return &field;
  }
  return nullptr;
}

std::vector<std::string> KeysOf(std::string_view section) {
  std::vector<std::string> keys;
  for (const Field& field : Fields()) {
    if (field.section == section) keys.push_back(field.key);
  }
  if (section.empty()) keys.insert(keys.end(), kSections.begin(), kSections.end());
  return keys;
}

// Full key path of an option below the tracker map at `tracker_path`.
std::string OptionPath(const std::string& tracker_path,
                       const std::string& section,
                       const std::string& key) {
  std::string path = tracker_path;
  for (const std::string& part : {section, key}) {
    if (part.empty()) continue;
    if (!path.empty()) path += '.';
    path += part;
  }
  return path;
}

// Hints for keys written in the wrong map: every option key that does not belong to `section`,
// pointing at the place(s) where it does.
std::vector<KeyHint> HintsFor(const std::string& tracker_path, const std::string& section) {
  std::map<std::string, std::vector<std::string>> places;  // key -> full paths
  for (const Field& field : Fields()) {
    if (field.section == section) continue;
    places[field.key].push_back(OptionPath(tracker_path, field.section, field.key));
  }
  const std::vector<std::string> own = KeysOf(section);
  std::vector<KeyHint> hints;
  for (auto& [key, paths] : places) {
    if (std::find(own.begin(), own.end(), key) != own.end()) continue;
    std::string suggestion;
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (i > 0) suggestion += " or ";
      suggestion += "'" + paths[i] + "'";
    }
    hints.push_back(KeyHint{key, suggestion});
  }
  return hints;
}

// Whether `word` occurs in `text` as a whole identifier; returns its position.
std::optional<std::size_t> FindWord(std::string_view text, std::string_view word) {
  const auto is_ident = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  };
  for (std::size_t pos = text.find(word); pos != std::string_view::npos;
       pos = text.find(word, pos + 1)) {
    const bool starts = pos == 0 || !is_ident(text[pos - 1]);
    const std::size_t end = pos + word.size();
    const bool ends = end == text.size() || !is_ident(text[end]);
    if (starts && ends) return pos;
  }
  return std::nullopt;
}

// TrackerOptions::Validate failed with `why` ("<section>: <field> must ..." or
// "<field> must ..."): report it at the key it names when the file sets that key, else at the
// map of its section (or the tracker map).
[[noreturn]] void FailValidation(const std::string& why,
                                 const MapRef& tracker_map,
                                 const std::map<std::string, MapRef>& section_maps) {
  std::string section;
  std::string_view rest = why;
  for (const std::string& s : kSections) {
    const std::string prefix = s + ": ";
    if (rest.substr(0, prefix.size()) == prefix) {
      section = s;
      while (rest.substr(0, prefix.size()) == prefix) rest.remove_prefix(prefix.size());
      break;
    }
  }
  const MapRef* map = &tracker_map;
  if (!section.empty()) {
    const auto found = section_maps.find(section);
    map = found != section_maps.end() ? &found->second : nullptr;
  }
  // The key named first in `why`, else the section (emplace, not assignment: NodeRef is not
  // assignable, see yaml_node.h).
  std::optional<NodeRef> named_key;
  if (map != nullptr) {
    std::size_t best = std::string_view::npos;
    for (const std::string& key : KeysOf(section)) {
      const std::optional<std::size_t> pos = FindWord(rest, key);
      const std::optional<NodeRef> value = map->Find(key);
      if (pos.has_value() && *pos < best && value.has_value()) {
        best = *pos;
        named_key.emplace(*value);
      }
    }
  }
  const NodeRef& where =
      named_key.has_value() ? *named_key : (map != nullptr ? map->ref() : tracker_map.ref());
  where.Fail("invalid options: " + why);
}

}  // namespace

std::string_view InputModeName(tracker::InputMode mode) {
  for (const auto& [m, name] : kInputModeNames) {
    if (m == mode) return name;
  }
  return "unknown";
}

std::optional<tracker::InputMode> InputModeFromName(std::string_view name) {
  for (const auto& [m, n] : kInputModeNames) {
    if (n == name) return m;
  }
  return std::nullopt;
}

std::string_view BoxPointName(tracker::BoxPoint point) {
  for (const auto& [p, name] : kBoxPointNames) {
    if (p == point) return name;
  }
  return "unknown";
}

std::optional<tracker::BoxPoint> BoxPointFromName(std::string_view name) {
  for (const auto& [p, n] : kBoxPointNames) {
    if (n == name) return p;
  }
  return std::nullopt;
}

namespace internal {

tracker::TrackerOptions ParseTrackerOptionsNode(const NodeRef& node) {
  TrackerOptions options;
  const MapRef tracker_map(node, KeysOf(""), /*null_is_empty=*/true, HintsFor(node.path(), ""));
  std::map<std::string, MapRef> section_maps;
  for (const std::string& key : tracker_map.keys()) {
    const NodeRef value = *tracker_map.Find(key);
    if (std::find(kSections.begin(), kSections.end(), key) == kSections.end()) {
      FindField("", key)->parse(value, &options);
      continue;
    }
    const MapRef section_map(
        value, KeysOf(key), /*null_is_empty=*/true, HintsFor(node.path(), key));
    for (const std::string& option : section_map.keys()) {
      FindField(key, option)->parse(*section_map.Find(option), &options);
    }
    section_maps.emplace(key, section_map);
  }
  std::string why;
  if (!options.Validate(&why)) FailValidation(why, tracker_map, section_maps);
  return options;
}

void AppendTrackerOptionsYaml(const tracker::TrackerOptions& options,
                              int indent,
                              std::string* out) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  for (const Field& field : Fields()) {
    if (field.section.empty()) *out += pad + field.key + ": " + field.format(options) + "\n";
  }
  for (const std::string& section : kSections) {
    *out += pad + section + ":\n";
    for (const Field& field : Fields()) {
      if (field.section == section) {
        *out += pad + "  " + field.key + ": " + field.format(options) + "\n";
      }
    }
  }
}

}  // namespace internal

tracker::TrackerOptions ParseTrackerOptions(std::string_view text, const std::string& source_name) {
  const NodeRef root = internal::ParseDocument(text, source_name);
  if (root.IsNull()) root.Fail("empty document (expected a map with the key 'tracker')");
  try {
    std::vector<KeyHint> hints;
    for (const std::string& key : KeysOf("")) {
      hints.push_back(KeyHint{key, "'tracker." + key + "'"});
    }
    for (const KeyHint& hint : HintsFor("tracker", "")) hints.push_back(hint);
    const MapRef document(root, {"tracker"}, /*null_is_empty=*/false, hints);
    return internal::ParseTrackerOptionsNode(document.Get("tracker"));
  } catch (const YAML::Exception& e) {
    // Backstop: the helpers check types before touching yaml-cpp's throwing accessors.
    throw ConfigError(source_name,
                      e.mark.is_null() ? 0 : e.mark.line + 1,
                      e.mark.is_null() ? 0 : e.mark.column + 1,
                      "",
                      e.msg);
  }
}

tracker::TrackerOptions LoadTrackerOptionsFile(const std::string& path) {
  return ParseTrackerOptions(internal::ReadTextFile(path), path);
}

std::string TrackerOptionsToYaml(const tracker::TrackerOptions& options) {
  std::string out = "tracker:\n";
  internal::AppendTrackerOptionsYaml(options, 2, &out);
  return out;
}

}  // namespace mvtrack::config
