#include "config/tracker_options.h"

#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "config/config_error.h"
#include "config/internal/tracker_options_node.h"
#include "config/internal/yaml_node.h"
#include "config_test_util.h"
#include "core/keypoint_layout.h"

namespace mvtrack::config {
namespace {

using testing::CheckLocated;
using testing::ColumnOf;
using testing::LineOf;
using testing::RequireConfigError;
using tracker::TrackerOptions;

// Exact equality of every option (reals compared with ==: the round trip must be exact).
void RequireSameOptions(const TrackerOptions& a, const TrackerOptions& b) {
  REQUIRE(a.mode == b.mode);
  REQUIRE(a.layout == b.layout);
  REQUIRE(a.window_size == b.window_size);
  REQUIRE(a.window_step == b.window_step);
  REQUIRE(a.box_point == b.box_point);
  REQUIRE(a.box_ends_in_association == b.box_ends_in_association);
  REQUIRE(a.box_ends_max_elevation_deg == b.box_ends_max_elevation_deg);
  REQUIRE(a.box_complete_cut == b.box_complete_cut);
  REQUIRE(a.ground_height_m == b.ground_height_m);
  REQUIRE(a.monocular_min_elevation_deg == b.monocular_min_elevation_deg);
  REQUIRE(a.bridge_max_gap_s == b.bridge_max_gap_s);
  REQUIRE(a.min_detection_score == b.min_detection_score);
  REQUIRE(a.min_keypoint_confidence == b.min_keypoint_confidence);
  REQUIRE(a.min_pose_keypoints == b.min_pose_keypoints);
  REQUIRE(a.min_tracklet_length == b.min_tracklet_length);
  REQUIRE(a.max_frame_jump == b.max_frame_jump);
  REQUIRE(a.box_margin_fraction == b.box_margin_fraction);
  REQUIRE(a.max_detections_per_frame == b.max_detections_per_frame);
  REQUIRE(a.sort.max_age == b.sort.max_age);
  REQUIRE(a.sort.min_hits == b.sort.min_hits);
  REQUIRE(a.sort.iou_threshold == b.sort.iou_threshold);
  REQUIRE(a.association.lambda == b.association.lambda);
  REQUIRE(a.association.min_confidence == b.association.min_confidence);
  REQUIRE(a.association.method == b.association.method);
  REQUIRE(a.association.empty_upper_bound == b.association.empty_upper_bound);
  REQUIRE(a.triangulation.method == b.triangulation.method);
  REQUIRE(a.triangulation.phi == b.triangulation.phi);
  REQUIRE(a.triangulation.kappa_m == b.triangulation.kappa_m);
  REQUIRE(a.triangulation.min_confidence == b.triangulation.min_confidence);
  REQUIRE(a.triangulation.ransac_threshold_px == b.triangulation.ransac_threshold_px);
  REQUIRE(a.triangulation.min_inliers == b.triangulation.min_inliers);
  REQUIRE(a.triangulation.max_views == b.triangulation.max_views);
  REQUIRE(a.linking.max_link_distance_m == b.linking.max_link_distance_m);
  REQUIRE(a.linking.duplicate_distance_m == b.linking.duplicate_distance_m);
  REQUIRE(a.linking.duplicate_max_gap_s == b.linking.duplicate_max_gap_s);
  REQUIRE(a.linking.merge_linked_duplicates == b.linking.merge_linked_duplicates);
  REQUIRE(a.linking.min_hits == b.linking.min_hits);
  REQUIRE(a.linking.strong_birth_cameras == b.linking.strong_birth_cameras);
  REQUIRE(a.linking.isolated_birth_distance_m == b.linking.isolated_birth_distance_m);
  REQUIRE(a.linking.fragment_births_wait == b.linking.fragment_births_wait);
  REQUIRE(a.linking.fragment_min_hits == b.linking.fragment_min_hits);
  REQUIRE(a.linking.monocular_max_s == b.linking.monocular_max_s);
  REQUIRE(a.linking.max_lost_s == b.linking.max_lost_s);
  REQUIRE(a.linking.motion.measurement_sigma_m == b.linking.motion.measurement_sigma_m);
  REQUIRE(a.linking.motion.acceleration_sigma_mps2 == b.linking.motion.acceleration_sigma_mps2);
  REQUIRE(a.linking.motion.initial_speed_sigma_mps == b.linking.motion.initial_speed_sigma_mps);
  REQUIRE(a.linking.gap_gate_chi2 == b.linking.gap_gate_chi2);
  REQUIRE(a.linking.reid_gate_chi2 == b.linking.reid_gate_chi2);
  REQUIRE(a.linking.reid_margin_chi2 == b.linking.reid_margin_chi2);
  REQUIRE(a.linking.max_reid_gap_s == b.linking.max_reid_gap_s);
  REQUIRE(a.refinement.merge_distance_m == b.refinement.merge_distance_m);
  REQUIRE(a.refinement.min_duplicate_pairs == b.refinement.min_duplicate_pairs);
  REQUIRE(a.refinement.box_min_duplicate_frames == b.refinement.box_min_duplicate_frames);
  REQUIRE(a.refinement.box_bottom_min_height_m == b.refinement.box_bottom_min_height_m);
  REQUIRE(a.refinement.box_bottom_max_height_m == b.refinement.box_bottom_max_height_m);
  REQUIRE(a.refinement.box_top_min_height_m == b.refinement.box_top_min_height_m);
  REQUIRE(a.refinement.box_top_max_height_m == b.refinement.box_top_max_height_m);
  REQUIRE(a.refinement.jump_gate_chi2 == b.refinement.jump_gate_chi2);
  REQUIRE(a.refinement.box_merge_distance_m == b.refinement.box_merge_distance_m);
  REQUIRE(a.refinement.box_min_height_m == b.refinement.box_min_height_m);
  REQUIRE(a.refinement.box_max_height_m == b.refinement.box_max_height_m);
  REQUIRE(a.refinement.box_split_residual == b.refinement.box_split_residual);
  REQUIRE(a.refinement.min_person_point_fraction == b.refinement.min_person_point_fraction);
  REQUIRE(a.refinement.outlier_half_window == b.refinement.outlier_half_window);
  REQUIRE(a.refinement.outlier_distance_m == b.refinement.outlier_distance_m);
  REQUIRE(a.refinement.smooth_half_window == b.refinement.smooth_half_window);
  REQUIRE(a.refinement.smooth_max_views == b.refinement.smooth_max_views);
  REQUIRE(a.refinement.max_fill_gap == b.refinement.max_fill_gap);
  REQUIRE(a.refinement.fill_neighbors == b.refinement.fill_neighbors);
  REQUIRE(a.refinement.min_points_to_fill == b.refinement.min_points_to_fill);
  REQUIRE(a.appearance.enabled == b.appearance.enabled);
  REQUIRE(a.appearance.gallery_size == b.appearance.gallery_size);
  REQUIRE(a.appearance.reid_max_distance == b.appearance.reid_max_distance);
  REQUIRE(a.appearance.reid_margin == b.appearance.reid_margin);
  REQUIRE(a.appearance.reid_disjoint_same_person == b.appearance.reid_disjoint_same_person);
  REQUIRE(a.appearance.max_reid_s == b.appearance.max_reid_s);
  REQUIRE(a.appearance.max_departed == b.appearance.max_departed);
  REQUIRE(a.appearance.defer_weak_reid == b.appearance.defer_weak_reid);
  REQUIRE(a.appearance.link_max_distance == b.appearance.link_max_distance);
  REQUIRE(a.appearance.association_weight == b.appearance.association_weight);
  REQUIRE(a.appearance.association_gate == b.appearance.association_gate);
  REQUIRE(a.appearance.sort_weight == b.appearance.sort_weight);
  REQUIRE(a.appearance.sort_gate == b.appearance.sort_gate);
  REQUIRE(a.appearance.sort_gallery_size == b.appearance.sort_gallery_size);
}

// Valid options with every field drawn at random (full-precision reals).
TrackerOptions RandomOptions(std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto integer = [&](std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(*rng);
  };
  const auto small = [&](int lo, int hi) { return static_cast<int>(integer(lo, hi)); };
  TrackerOptions o;
  o.mode = integer(0, 1) == 0 ? tracker::InputMode::kBoxes : tracker::InputMode::kPoses;
  std::vector<core::KeypointLayoutId> layouts = core::AllKeypointLayouts();
  if (o.mode == tracker::InputMode::kBoxes) layouts.push_back(core::KeypointLayoutId::kNone);
  const std::int64_t last_layout = static_cast<std::int64_t>(layouts.size()) - 1;
  o.layout = layouts[static_cast<std::size_t>(integer(0, last_layout))];
  o.window_size = small(2, 200);
  o.window_step = small(1, o.window_size);
  o.box_point = static_cast<tracker::BoxPoint>(small(0, 2));
  o.box_ends_in_association = integer(0, 1) == 0;
  o.box_ends_max_elevation_deg = 90.0 * unit(*rng);
  o.box_complete_cut = unit(*rng) < 0.5;
  o.ground_height_m = 6.0 * unit(*rng) - 3.0;
  o.monocular_min_elevation_deg = 90.0 * unit(*rng);
  o.bridge_max_gap_s = 10.0 * unit(*rng);
  o.min_detection_score = unit(*rng);
  o.min_keypoint_confidence = unit(*rng);
  o.min_pose_keypoints = small(1, 30);
  o.min_tracklet_length = small(1, 30);
  o.max_frame_jump = integer(o.window_size, std::int64_t{1} << 40);
  o.box_margin_fraction = 10.0 * unit(*rng);
  o.max_detections_per_frame = small(1, 100000);
  o.sort.max_age = small(0, 100);
  o.sort.min_hits = small(1, 10);
  o.sort.iou_threshold = 1.0 - unit(*rng);  // (0, 1]
  o.association.lambda = 1e-3 + 2.0 * unit(*rng);
  o.association.min_confidence = unit(*rng);
  o.association.method = static_cast<association::ClusteringMethod>(small(0, 3));
  o.association.empty_upper_bound = 5.0 * unit(*rng);
  o.triangulation.method = static_cast<triangulation::TriangulationMethod>(small(0, 2));
  o.triangulation.phi = small(0, 30);
  o.triangulation.kappa_m = 0.01 + unit(*rng);
  o.triangulation.min_confidence = unit(*rng);
  o.triangulation.ransac_threshold_px = 0.1 + 50.0 * unit(*rng);
  o.triangulation.min_inliers = small(1, 8);
  o.triangulation.max_views = integer(0, 3) == 0 ? 0 : small(2, 16);
  o.linking.max_link_distance_m = 0.01 + 3.0 * unit(*rng);
  o.linking.duplicate_distance_m = o.linking.max_link_distance_m * unit(*rng);
  o.linking.duplicate_max_gap_s = 2.0 * unit(*rng);
  o.linking.merge_linked_duplicates = unit(*rng) < 0.5;
  o.linking.min_hits = small(1, 5);
  o.linking.strong_birth_cameras = small(2, 10);
  o.linking.isolated_birth_distance_m = 4.0 * unit(*rng);
  o.linking.fragment_births_wait = unit(*rng) < 0.5;
  o.linking.fragment_min_hits = small(1, 10);
  o.linking.monocular_max_s = 10.0 * unit(*rng);
  o.linking.max_lost_s = 10.0 * unit(*rng);
  o.linking.motion.measurement_sigma_m = 0.01 + unit(*rng);
  o.linking.motion.acceleration_sigma_mps2 = 0.01 + 3.0 * unit(*rng);
  o.linking.motion.initial_speed_sigma_mps = 0.01 + 3.0 * unit(*rng);
  o.linking.gap_gate_chi2 = 0.1 + 30.0 * unit(*rng);
  o.linking.reid_gate_chi2 = 20.0 * unit(*rng);
  o.linking.reid_margin_chi2 = 10.0 * unit(*rng);
  o.linking.max_reid_gap_s = 5.0 * unit(*rng);
  o.refinement.merge_distance_m = unit(*rng);
  o.refinement.min_duplicate_pairs = small(1, 30);
  o.refinement.box_min_duplicate_frames = small(1, 30);
  o.refinement.box_bottom_min_height_m = -unit(*rng);
  o.refinement.box_bottom_max_height_m = 0.01 + unit(*rng);
  o.refinement.box_top_min_height_m = unit(*rng);
  o.refinement.box_top_max_height_m = 1.01 + 2.0 * unit(*rng);
  o.refinement.jump_gate_chi2 = 100.0 * unit(*rng);
  o.refinement.box_merge_distance_m = unit(*rng);
  o.refinement.box_min_height_m = -unit(*rng);
  o.refinement.box_max_height_m = 0.01 + 3.0 * unit(*rng);
  o.refinement.box_split_residual = unit(*rng);
  o.refinement.min_person_point_fraction = unit(*rng);
  o.refinement.outlier_half_window = small(0, 10);
  o.refinement.outlier_distance_m = 0.01 + unit(*rng);
  o.refinement.smooth_half_window = small(0, 10);
  o.refinement.smooth_max_views = small(0, 8);
  o.refinement.max_fill_gap = small(0, 30);
  o.refinement.fill_neighbors = small(1, 8);
  o.refinement.min_points_to_fill = small(1, 10);
  o.appearance.enabled = unit(*rng) < 0.5;
  o.appearance.gallery_size = small(1, 64);
  o.appearance.reid_max_distance = 2.0 * unit(*rng);
  o.appearance.reid_margin = unit(*rng);
  o.appearance.reid_disjoint_same_person = unit(*rng) < 0.5;
  o.appearance.max_reid_s = 600.0 * unit(*rng);
  o.appearance.max_departed = small(0, 1000);
  o.appearance.defer_weak_reid = unit(*rng) < 0.5;
  o.appearance.link_max_distance = 2.0 * unit(*rng);
  o.appearance.association_weight = unit(*rng);
  o.appearance.association_gate = 2.0 * unit(*rng);
  o.appearance.sort_weight = unit(*rng);
  o.appearance.sort_gate = 2.0 * unit(*rng);
  o.appearance.sort_gallery_size = small(1, 100);
  return o;
}

// Every key path ("a.b.c") of the maps in a YAML document, leaves only.
void CollectKeyPaths(const YAML::Node& node,
                     const std::string& prefix,
                     std::set<std::string>* out) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = it->first.Scalar();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (it->second.IsMap()) {
      CollectKeyPaths(it->second, path, out);
    } else {
      out->insert(path);
    }
  }
}

std::string ExamplePath() {
  return std::string(MVTRACK_SOURCE_DIR) + "/docs/examples/tracker_options.yaml";
}

TEST_CASE("Option struct sizes match the fields config knows", "[unit]") {
  // Tripwire: a field added to an options struct changes its size. When this fails, add the
  // field to lib/config/tracker_options.cc (MakeFields), RequireSameOptions and RandomOptions
  // above, the explicit mapping test below, docs/examples/tracker_options.yaml and
  // docs/FORMATS.md, then update the sizes here (x86-64, g++). Not keys: SortOptions'
  // motion_buffer and process_noise_scale (derived from the frame period by
  // tracker::AtFrameRate); AssociationOptions' num_points, floor_point, floor_height_m and
  // appearance fields (set by the tracker from box_point, ground_height_m and appearance).
  CHECK(sizeof(tracking2d::SortOptions) == 32);
  CHECK(sizeof(triangulation::TriangulationOptions) == 40);
  CHECK(sizeof(linking::LinkerOptions) == 128);
  CHECK(sizeof(triangulation::RefinementOptions) == 136);
  CHECK(sizeof(core::AppearanceOptions) == 96);
  CHECK(sizeof(association::AssociationOptions) == 64);
  CHECK(sizeof(TrackerOptions) == 608);
}

TEST_CASE("Absent keys keep the defaults", "[unit]") {
  const TrackerOptions defaults;
  for (const std::string text :
       {"tracker: {}\n", "tracker:\n", "tracker:\n  sort:\n  linking: {}\n", "{\"tracker\": {}}"}) {
    INFO(text);
    RequireSameOptions(ParseTrackerOptions(text, "d.yaml"), defaults);
  }
  // The defaults are the paper's values.
  CHECK(defaults.window_size == 30);
  CHECK(defaults.window_step == 20);
  CHECK(defaults.association.lambda == 0.3);
  CHECK(defaults.triangulation.phi == 7);
  CHECK(defaults.triangulation.kappa_m == 0.2);
}

TEST_CASE("Every key sets its own field", "[unit]") {
  const std::string text =
      "tracker:\n"
      "  mode: poses\n"
      "  layout: campus14\n"
      "  window_size: 40\n"
      "  window_step: 10\n"
      "  box_point: bottom_center\n"
      "  box_ends_in_association: false\n"
      "  box_ends_max_elevation_deg: 35.5\n"
      "  ground_height_m: -0.25\n"
      "  bridge_max_gap_s: 1.5\n"
      "  min_detection_score: 0.35\n"
      "  min_keypoint_confidence: 0.45\n"
      "  min_pose_keypoints: 6\n"
      "  min_tracklet_length: 3\n"
      "  max_frame_jump: 5000000000\n"
      "  box_margin_fraction: 0.75\n"
      "  max_detections_per_frame: 77\n"
      "  sort: {max_age: 9, min_hits: 2, iou_threshold: 0.55}\n"
      "  association:\n"
      "    lambda: 0.27\n"
      "    min_confidence: 0.15\n"
      "    method: single_linkage_empty_as_upper\n"
      "    empty_upper_bound: 2.5\n"
      "  triangulation:\n"
      "    method: ransac\n"
      "    phi: 4\n"
      "    kappa_m: 0.125\n"
      "    min_confidence: 0.05\n"
      "    ransac_threshold_px: 12.5\n"
      "    min_inliers: 3\n"
      "    max_views: 0\n"
      "  linking:\n"
      "    max_link_distance_m: 0.65\n"
      "    duplicate_distance_m: 0.375\n"
      "    min_hits: 3\n"
      "    strong_birth_cameras: 4\n"
      "    isolated_birth_distance_m: 1.25\n"
      "    max_lost_s: 4.5\n"
      "    measurement_sigma_m: 0.05\n"
      "    acceleration_sigma_mps2: 1.5\n"
      "    initial_speed_sigma_mps: 2.5\n"
      "    gap_gate_chi2: 13.25\n"
      "    reid_gate_chi2: 9.5\n"
      "    reid_margin_chi2: 4.25\n"
      "    max_reid_gap_s: 1.25\n"
      "  refinement:\n"
      "    merge_distance_m: 0.15\n"
      "    min_duplicate_pairs: 7\n"
      "    box_min_duplicate_frames: 5\n"
      "    box_bottom_min_height_m: -0.25\n"
      "    box_bottom_max_height_m: 0.5\n"
      "    box_top_min_height_m: 0.75\n"
      "    box_top_max_height_m: 2.25\n"
      "    jump_gate_chi2: 33.5\n"
      "    box_merge_distance_m: 0.25\n"
      "    box_min_height_m: -0.5\n"
      "    box_max_height_m: 2.5\n"
      "    box_split_residual: 0.35\n"
      "    min_person_point_fraction: 0.375\n"
      "    outlier_half_window: 5\n"
      "    outlier_distance_m: 0.3\n"
      "    smooth_half_window: 4\n"
      "    smooth_max_views: 3\n"
      "    max_fill_gap: 11\n"
      "    fill_neighbors: 3\n"
      "    min_points_to_fill: 6\n";
  const TrackerOptions o = ParseTrackerOptions(text, "all.yaml");
  CHECK(o.mode == tracker::InputMode::kPoses);
  CHECK(o.layout == core::KeypointLayoutId::kShelf14);
  CHECK(o.window_size == 40);
  CHECK(o.window_step == 10);
  CHECK(o.box_point == tracker::BoxPoint::kBottomCenter);
  CHECK_FALSE(o.box_ends_in_association);
  CHECK(o.box_ends_max_elevation_deg == 35.5);
  CHECK(o.ground_height_m == -0.25);
  CHECK(o.bridge_max_gap_s == 1.5);
  CHECK(o.min_detection_score == 0.35);
  CHECK(o.min_keypoint_confidence == 0.45);
  CHECK(o.min_pose_keypoints == 6);
  CHECK(o.min_tracklet_length == 3);
  CHECK(o.max_frame_jump == 5000000000);
  CHECK(o.box_margin_fraction == 0.75);
  CHECK(o.max_detections_per_frame == 77);
  CHECK(o.sort.max_age == 9);
  CHECK(o.sort.min_hits == 2);
  CHECK(o.sort.iou_threshold == 0.55);
  CHECK(o.association.lambda == 0.27);
  CHECK(o.association.min_confidence == 0.15);
  CHECK(o.association.method == association::ClusteringMethod::kSingleLinkageEmptyAsUpper);
  CHECK(o.association.empty_upper_bound == 2.5);
  CHECK(o.triangulation.method == triangulation::TriangulationMethod::kRansac);
  CHECK(o.triangulation.phi == 4);
  CHECK(o.triangulation.kappa_m == 0.125);
  CHECK(o.triangulation.min_confidence == 0.05);
  CHECK(o.triangulation.ransac_threshold_px == 12.5);
  CHECK(o.triangulation.min_inliers == 3);
  CHECK(o.triangulation.max_views == 0);
  CHECK(o.linking.max_link_distance_m == 0.65);
  CHECK(o.linking.duplicate_distance_m == 0.375);
  CHECK(o.linking.min_hits == 3);
  CHECK(o.linking.strong_birth_cameras == 4);
  CHECK(o.linking.isolated_birth_distance_m == 1.25);
  CHECK(o.linking.max_lost_s == 4.5);
  CHECK(o.linking.motion.measurement_sigma_m == 0.05);
  CHECK(o.linking.motion.acceleration_sigma_mps2 == 1.5);
  CHECK(o.linking.motion.initial_speed_sigma_mps == 2.5);
  CHECK(o.linking.gap_gate_chi2 == 13.25);
  CHECK(o.linking.reid_gate_chi2 == 9.5);
  CHECK(o.linking.reid_margin_chi2 == 4.25);
  CHECK(o.linking.max_reid_gap_s == 1.25);
  CHECK(o.refinement.merge_distance_m == 0.15);
  CHECK(o.refinement.min_duplicate_pairs == 7);
  CHECK(o.refinement.box_min_duplicate_frames == 5);
  CHECK(o.refinement.box_bottom_min_height_m == -0.25);
  CHECK(o.refinement.box_bottom_max_height_m == 0.5);
  CHECK(o.refinement.box_top_min_height_m == 0.75);
  CHECK(o.refinement.box_top_max_height_m == 2.25);
  CHECK(o.refinement.jump_gate_chi2 == 33.5);
  CHECK(o.refinement.box_merge_distance_m == 0.25);
  CHECK(o.refinement.box_min_height_m == -0.5);
  CHECK(o.refinement.box_max_height_m == 2.5);
  CHECK(o.refinement.box_split_residual == 0.35);
  CHECK(o.refinement.min_person_point_fraction == 0.375);
  CHECK(o.refinement.outlier_half_window == 5);
  CHECK(o.refinement.outlier_distance_m == 0.3);
  CHECK(o.refinement.smooth_half_window == 4);
  CHECK(o.refinement.smooth_max_views == 3);
  CHECK(o.refinement.max_fill_gap == 11);
  CHECK(o.refinement.fill_neighbors == 3);
  CHECK(o.refinement.min_points_to_fill == 6);
}

TEST_CASE("Enum names", "[unit]") {
  CHECK(InputModeName(tracker::InputMode::kPoses) == "poses");
  CHECK(InputModeFromName("boxes") == tracker::InputMode::kBoxes);
  CHECK_FALSE(InputModeFromName("Boxes").has_value());
  CHECK(BoxPointName(tracker::BoxPoint::kBottomCenter) == "bottom_center");
  CHECK(BoxPointFromName("center") == tracker::BoxPoint::kCenter);
  CHECK_FALSE(BoxPointFromName("centre").has_value());
  for (const std::string method : {"pdnc",
                                   "complete_linkage_empty_as_zero",
                                   "complete_linkage_empty_as_upper",
                                   "single_linkage_empty_as_upper"}) {
    const TrackerOptions o =
        ParseTrackerOptions("tracker:\n  association:\n    method: " + method + "\n", "e.yaml");
    CHECK(association::ClusteringMethodName(o.association.method) == method);
  }
  for (const std::string layout : {"coco17", "body25", "shelf14", "panoptic19"}) {
    const TrackerOptions o = ParseTrackerOptions("tracker:\n  layout: " + layout + "\n", "e.yaml");
    CHECK(core::GetKeypointLayout(o.layout).name == layout);
  }
  CHECK(ParseTrackerOptions("tracker:\n  layout: none\n", "e.yaml").layout ==
        core::KeypointLayoutId::kNone);
}

TEST_CASE("Options round-trip exactly: defaults and random sets", "[unit]") {
  const TrackerOptions defaults;
  const std::string text = TrackerOptionsToYaml(defaults);
  RequireSameOptions(ParseTrackerOptions(text, "defaults.yaml"), defaults);
  CHECK_THAT(text, Catch::StartsWith("tracker:\n  mode: boxes\n  layout: coco17\n"));
  CHECK_THAT(text, Catch::Contains("\n  association:\n    lambda: 0.3\n"));

  std::mt19937 rng(1234);
  for (int i = 0; i < 200; ++i) {
    const TrackerOptions o = RandomOptions(&rng);
    std::string why;
    REQUIRE(o.Validate(&why));
    const std::string yaml = TrackerOptionsToYaml(o);
    INFO(yaml);
    const TrackerOptions back = ParseTrackerOptions(yaml, "random.yaml");
    RequireSameOptions(back, o);
    CHECK(TrackerOptionsToYaml(back) == yaml);
  }
}

TEST_CASE("ToYaml lists every option and the example documents exactly those", "[unit]") {
  std::set<std::string> written;
  CollectKeyPaths(YAML::Load(TrackerOptionsToYaml(TrackerOptions{})), "", &written);
  // 86 before issue 38; linking.unshared_link_distance_m removed (it changed no output on any
  // benchmark); refinement.fit_skeleton added (issue 40: the skeleton fit's ablation switch).
  CHECK(written.size() == 86);
  CHECK_THROWS_WITH(
      ParseTrackerOptions("tracker:\n  linking:\n    unshared_link_distance_m: 0.25\n", "r.yaml"),
      Catch::Contains("unshared_link_distance_m"));
  std::set<std::string> documented;
  CollectKeyPaths(YAML::LoadFile(ExamplePath()), "", &documented);
  CHECK(documented == written);
  // The example shows the defaults.
  RequireSameOptions(LoadTrackerOptionsFile(ExamplePath()), TrackerOptions{});
}

// A small valid file the strictness cases modify.
const std::string kBase =
    "# tracker options\n"
    "tracker:\n"
    "  mode: boxes\n"
    "  window_size: 30\n"
    "  sort:\n"
    "    max_age: 5\n"
    "  association:\n"
    "    lambda: 0.3\n"
    "    method: pdnc\n"
    "  triangulation:\n"
    "    method: cmmt\n"
    "    phi: 7\n"
    "  linking:\n"
    "    min_hits: 1\n";

TEST_CASE("The unknown-key message reads as specified", "[unit]") {
  std::string text = kBase;
  text.replace(text.find("lambda:"), 7, "lamda:");
  const ConfigError e = RequireConfigError([&] { ParseTrackerOptions(text, "config.yaml"); });
  const std::string expected = "config.yaml:" + std::to_string(LineOf(text, "lamda")) + ":" +
                               std::to_string(ColumnOf(text, "lamda")) +
                               ": tracker.association.lamda: unknown key (did you mean 'lambda'?)";
  CHECK(std::string(e.what()) == expected);
}

TEST_CASE("Options strictness: every error names file, line and key path", "[unit]") {
  struct Case {
    std::string name;
    std::string from;
    std::string to;
    std::string marker;
    std::string key_path;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"wrong type",
       "lambda: 0.3",
       "lambda: abc",
       "lambda",
       "tracker.association.lambda",
       "expected a number, got 'abc'"},
      {"quoted number",
       "lambda: 0.3",
       "lambda: \"0.3\"",
       "lambda",
       "tracker.association.lambda",
       "quoted string"},
      {"out of range",
       "  window_size: 30\n",
       "  window_size: 30\n  window_step: 0\n",
       "window_step",
       "tracker.window_step",
       "value 0 out of range: must be in [1, 10000]"},
      {"non-finite nan",
       "lambda: 0.3",
       "lambda: .nan",
       "lambda",
       "tracker.association.lambda",
       "non-finite number '.nan'"},
      {"non-finite inf",
       "phi: 7",
       "phi: 7\n    kappa_m: .inf",
       "kappa_m",
       "tracker.triangulation.kappa_m",
       "non-finite number '.inf'"},
      {"integer with fraction",
       "phi: 7",
       "phi: 7.5",
       "phi",
       "tracker.triangulation.phi",
       "expected an integer, got '7.5'"},
      {"max_views 1",
       "phi: 7",
       "max_views: 1",
       "max_views",
       "tracker.triangulation.max_views",
       "must be 0 (all views) or >= 2"},
      {"unknown enum",
       "method: pdnc",
       "method: pdcn",
       "pdcn",
       "tracker.association.method",
       "unknown value 'pdcn' (did you mean 'pdnc'?)"},
      {"unknown triangulation",
       "method: cmmt",
       "method: cmt",
       "cmt",
       "tracker.triangulation.method",
       "unknown value 'cmt' (did you mean 'cmmt'?)"},
      {"unknown mode",
       "mode: boxes",
       "mode: box",
       "mode",
       "tracker.mode",
       "unknown value 'box' (did you mean 'boxes'?)"},
      {"unknown mode far",
       "mode: boxes",
       "mode: skeletons",
       "mode",
       "tracker.mode",
       "expected one of 'boxes', 'poses'"},
      {"key in the wrong map",
       "  window_size: 30\n",
       "  window_size: 30\n  lambda: 0.2\n",
       "lambda: 0.2",
       "tracker.lambda",
       "unknown key (did you mean 'tracker.association.lambda'?)"},
      {"shared key in the wrong map",
       "  window_size: 30\n",
       "  window_size: 30\n  min_hits: 2\n",
       "min_hits: 2",
       "tracker.min_hits",
       "(did you mean 'tracker.sort.min_hits' or 'tracker.linking.min_hits'?)"},
      {"key of another section",
       "    max_age: 5\n",
       "    max_age: 5\n    kappa_m: 0.3\n",
       "kappa_m",
       "tracker.sort.kappa_m",
       "(did you mean 'tracker.triangulation.kappa_m'?)"},
      {"unknown key far from all",
       "    max_age: 5\n",
       "    max_age: 5\n    zzz: 1\n",
       "zzz",
       "tracker.sort.zzz",
       "allowed keys: 'max_age', 'min_hits', 'iou_threshold'"},
      {"duplicate key",
       "  mode: boxes\n",
       "  mode: boxes\n  mode: poses\n",
       "mode: poses",
       "tracker.mode",
       "duplicate key (first given at line 3)"},
      {"section not a map",
       "  sort:\n    max_age: 5\n",
       "  sort: [5]\n",
       "sort",
       "tracker.sort",
       "expected a map, got a list"},
      {"tracker not a map",
       kBase,
       "# c\ntracker: 3\n",
       "tracker",
       "tracker",
       "expected a map, got '3'"},
      {"iou 0",
       "    max_age: 5\n",
       "    iou_threshold: 0\n",
       "iou_threshold",
       "tracker.sort.iou_threshold",
       "must be in (0, 1]"},
      {"step above size (Validate)",
       "  window_size: 30\n",
       "  window_size: 30\n  window_step: 40\n",
       "window_step",
       "tracker.window_step",
       "invalid options: window_step (\xCE\xB4) must be in [1, window_size]"},
      {"size below default step (Validate)",
       "window_size: 30",
       "window_size: 10",
       "window_size",
       "tracker.window_size",
       "invalid options: window_step"},
      {"frame jump below window (Validate)",
       "  window_size: 30\n",
       "  window_size: 30\n  max_frame_jump: 10\n",
       "max_frame_jump",
       "tracker.max_frame_jump",
       "invalid options: max_frame_jump must be >= window_size"},
      {"pose mode without layout (Validate)",
       "mode: boxes",
       "mode: poses\n  layout: none",
       "mode",
       "tracker.mode",
       "invalid options: pose mode needs a keypoint layout"},
  };
  for (const Case& c : cases) {
    INFO("case: " << c.name);
    std::string text = kBase;
    const std::size_t pos = text.find(c.from);
    REQUIRE(pos != std::string::npos);
    text.replace(pos, c.from.size(), c.to);
    const ConfigError e = RequireConfigError([&] { ParseTrackerOptions(text, "options.yaml"); });
    CheckLocated(e, "options.yaml", LineOf(text, c.marker), c.key_path, c.reason);
  }
}

TEST_CASE("Config ranges agree with Validate at every boundary", "[unit]") {
  struct Boundary {
    std::string yaml;  // body of the tracker map (one or two lines)
    std::string key_path;
    bool valid;
    std::function<void(TrackerOptions&)> apply;  // the same setting, in code
  };
  using O = TrackerOptions;
  const std::vector<Boundary> cases = {
      {"window_size: 2\n  window_step: 1",
       "",
       true,
       [](O& o) {
         o.window_size = 2;
         o.window_step = 1;
       }},
      {"window_size: 1\n  window_step: 1",
       "tracker.window_size",
       false,
       [](O& o) {
         o.window_size = 1;
         o.window_step = 1;
       }},
      {"window_size: 10000\n  max_frame_jump: 10000",
       "",
       true,
       [](O& o) {
         o.window_size = 10000;
         o.max_frame_jump = 10000;
       }},
      {"window_size: 10001\n  max_frame_jump: 10001",
       "tracker.window_size",
       false,
       [](O& o) {
         o.window_size = 10001;
         o.max_frame_jump = 10001;
       }},
      {"window_step: 30", "", true, [](O& o) { o.window_step = 30; }},
      {"window_step: 31", "tracker.window_step", false, [](O& o) { o.window_step = 31; }},
      {"window_step: 0", "tracker.window_step", false, [](O& o) { o.window_step = 0; }},
      {"min_detection_score: 1", "", true, [](O& o) { o.min_detection_score = 1.0; }},
      {"min_detection_score: 1.0000001",
       "tracker.min_detection_score",
       false,
       [](O& o) { o.min_detection_score = 1.0000001; }},
      {"min_detection_score: -1e-9",
       "tracker.min_detection_score",
       false,
       [](O& o) { o.min_detection_score = -1e-9; }},
      {"min_keypoint_confidence: 0", "", true, [](O& o) { o.min_keypoint_confidence = 0.0; }},
      {"min_keypoint_confidence: 1.5",
       "tracker.min_keypoint_confidence",
       false,
       [](O& o) { o.min_keypoint_confidence = 1.5; }},
      {"min_pose_keypoints: 1", "", true, [](O& o) { o.min_pose_keypoints = 1; }},
      {"min_pose_keypoints: 0",
       "tracker.min_pose_keypoints",
       false,
       [](O& o) { o.min_pose_keypoints = 0; }},
      {"min_tracklet_length: 1", "", true, [](O& o) { o.min_tracklet_length = 1; }},
      {"min_tracklet_length: 0",
       "tracker.min_tracklet_length",
       false,
       [](O& o) { o.min_tracklet_length = 0; }},
      {"max_frame_jump: 30", "", true, [](O& o) { o.max_frame_jump = 30; }},
      {"max_frame_jump: 29", "tracker.max_frame_jump", false, [](O& o) { o.max_frame_jump = 29; }},
      {"box_margin_fraction: 0", "", true, [](O& o) { o.box_margin_fraction = 0.0; }},
      {"box_margin_fraction: 10", "", true, [](O& o) { o.box_margin_fraction = 10.0; }},
      {"box_margin_fraction: 10.5",
       "tracker.box_margin_fraction",
       false,
       [](O& o) { o.box_margin_fraction = 10.5; }},
      {"box_margin_fraction: -0.1",
       "tracker.box_margin_fraction",
       false,
       [](O& o) { o.box_margin_fraction = -0.1; }},
      {"max_detections_per_frame: 1", "", true, [](O& o) { o.max_detections_per_frame = 1; }},
      {"max_detections_per_frame: 0",
       "tracker.max_detections_per_frame",
       false,
       [](O& o) { o.max_detections_per_frame = 0; }},
      {"ground_height_m: -1000", "", true, [](O& o) { o.ground_height_m = -1000.0; }},
      {"sort: {max_age: 0}", "", true, [](O& o) { o.sort.max_age = 0; }},
      {"sort: {max_age: -1}", "tracker.sort.max_age", false, [](O& o) { o.sort.max_age = -1; }},
      {"sort: {min_hits: 1}", "", true, [](O& o) { o.sort.min_hits = 1; }},
      {"sort: {min_hits: 0}", "tracker.sort.min_hits", false, [](O& o) { o.sort.min_hits = 0; }},
      {"sort: {iou_threshold: 1}", "", true, [](O& o) { o.sort.iou_threshold = 1.0; }},
      {"sort: {iou_threshold: 1.01}",
       "tracker.sort.iou_threshold",
       false,
       [](O& o) { o.sort.iou_threshold = 1.01; }},
      {"sort: {iou_threshold: 0}",
       "tracker.sort.iou_threshold",
       false,
       [](O& o) { o.sort.iou_threshold = 0.0; }},
      {"association: {lambda: 1e-300}", "", true, [](O& o) { o.association.lambda = 1e-300; }},
      {"association: {lambda: 0}",
       "tracker.association.lambda",
       false,
       [](O& o) { o.association.lambda = 0.0; }},
      {"association: {min_confidence: 1}",
       "",
       true,
       [](O& o) { o.association.min_confidence = 1.0; }},
      {"association: {min_confidence: 1.5}",
       "tracker.association.min_confidence",
       false,
       [](O& o) { o.association.min_confidence = 1.5; }},
      {"association: {empty_upper_bound: 0}",
       "",
       true,
       [](O& o) { o.association.empty_upper_bound = 0.0; }},
      {"association: {empty_upper_bound: -0.1}",
       "tracker.association.empty_upper_bound",
       false,
       [](O& o) { o.association.empty_upper_bound = -0.1; }},
      {"triangulation: {phi: 0}", "", true, [](O& o) { o.triangulation.phi = 0; }},
      {"triangulation: {phi: -1}",
       "tracker.triangulation.phi",
       false,
       [](O& o) { o.triangulation.phi = -1; }},
      {"triangulation: {kappa_m: 1e-9}", "", true, [](O& o) { o.triangulation.kappa_m = 1e-9; }},
      {"triangulation: {kappa_m: 0}",
       "tracker.triangulation.kappa_m",
       false,
       [](O& o) { o.triangulation.kappa_m = 0.0; }},
      {"triangulation: {min_confidence: 0}",
       "",
       true,
       [](O& o) { o.triangulation.min_confidence = 0.0; }},
      {"triangulation: {min_confidence: -0.5}",
       "tracker.triangulation.min_confidence",
       false,
       [](O& o) { o.triangulation.min_confidence = -0.5; }},
      {"triangulation: {ransac_threshold_px: 1e-9}",
       "",
       true,
       [](O& o) { o.triangulation.ransac_threshold_px = 1e-9; }},
      {"triangulation: {ransac_threshold_px: 0}",
       "tracker.triangulation.ransac_threshold_px",
       false,
       [](O& o) { o.triangulation.ransac_threshold_px = 0.0; }},
      {"triangulation: {min_inliers: 1}", "", true, [](O& o) { o.triangulation.min_inliers = 1; }},
      {"triangulation: {min_inliers: 0}",
       "tracker.triangulation.min_inliers",
       false,
       [](O& o) { o.triangulation.min_inliers = 0; }},
      {"triangulation: {max_views: 0}", "", true, [](O& o) { o.triangulation.max_views = 0; }},
      {"triangulation: {max_views: 2}", "", true, [](O& o) { o.triangulation.max_views = 2; }},
      {"triangulation: {max_views: 1}",
       "tracker.triangulation.max_views",
       false,
       [](O& o) { o.triangulation.max_views = 1; }},
      {"triangulation: {max_views: -1}",
       "tracker.triangulation.max_views",
       false,
       [](O& o) { o.triangulation.max_views = -1; }},
      {"linking: {max_link_distance_m: 1e-9, duplicate_distance_m: 0}",
       "",
       true,
       [](O& o) {
         o.linking.max_link_distance_m = 1e-9;
         o.linking.duplicate_distance_m = 0.0;
       }},
      {"linking: {max_link_distance_m: 0}",
       "tracker.linking.max_link_distance_m",
       false,
       [](O& o) { o.linking.max_link_distance_m = 0.0; }},
      {"linking: {min_hits: 1}", "", true, [](O& o) { o.linking.min_hits = 1; }},
      {"linking: {min_hits: 0}",
       "tracker.linking.min_hits",
       false,
       [](O& o) { o.linking.min_hits = 0; }},
      {"linking: {max_lost_s: 0}", "", true, [](O& o) { o.linking.max_lost_s = 0.0; }},
      {"linking: {max_lost_s: -0.5}",
       "tracker.linking.max_lost_s",
       false,
       [](O& o) { o.linking.max_lost_s = -0.5; }},
      {"linking: {duplicate_distance_m: 0.5}",
       "",
       true,
       [](O& o) { o.linking.duplicate_distance_m = 0.5; }},
      {"linking: {duplicate_distance_m: 0.6}",
       "tracker.linking.duplicate_distance_m",
       false,
       [](O& o) { o.linking.duplicate_distance_m = 0.6; }},
      {"linking: {duplicate_distance_m: -0.1}",
       "tracker.linking.duplicate_distance_m",
       false,
       [](O& o) { o.linking.duplicate_distance_m = -0.1; }},
      {"linking: {duplicate_max_gap_s: 0}",
       "",
       true,
       [](O& o) { o.linking.duplicate_max_gap_s = 0.0; }},
      {"linking: {duplicate_max_gap_s: -0.1}",
       "tracker.linking.duplicate_max_gap_s",
       false,
       [](O& o) { o.linking.duplicate_max_gap_s = -0.1; }},
      {"linking: {strong_birth_cameras: 1}",
       "tracker.linking.strong_birth_cameras",
       false,
       [](O& o) { o.linking.strong_birth_cameras = 1; }},
      {"linking: {reid_gate_chi2: 0}", "", true, [](O& o) { o.linking.reid_gate_chi2 = 0.0; }},
      {"linking: {gap_gate_chi2: 0}",
       "tracker.linking.gap_gate_chi2",
       false,
       [](O& o) { o.linking.gap_gate_chi2 = 0.0; }},
      {"linking: {measurement_sigma_m: 0}",
       "tracker.linking.measurement_sigma_m",
       false,
       [](O& o) { o.linking.motion.measurement_sigma_m = 0.0; }},
  };
  for (const Boundary& c : cases) {
    INFO("tracker: " << c.yaml);
    TrackerOptions in_code;
    c.apply(in_code);
    CHECK(in_code.Validate(nullptr) == c.valid);
    const std::string text = "tracker:\n  " + c.yaml + "\n";
    if (c.valid) {
      RequireSameOptions(ParseTrackerOptions(text, "b.yaml"), in_code);
    } else {
      const ConfigError e = RequireConfigError([&] { ParseTrackerOptions(text, "b.yaml"); });
      CHECK(e.key_path() == c.key_path);
      CHECK(e.line() >= 2);
    }
  }
}

TEST_CASE("Options file-level errors", "[unit]") {
  const testing::TempDir dir;
  for (const std::string text : {"", "# nothing\n"}) {
    const std::string path = dir.Write("empty.yaml", text);
    const ConfigError e = RequireConfigError([&] { LoadTrackerOptionsFile(path); });
    CHECK(e.file() == path);
    CHECK_THAT(e.reason(), Catch::Contains("empty document"));
  }
  const std::string missing = dir.File("missing.yaml");
  CHECK(std::string(RequireConfigError([&] { LoadTrackerOptionsFile(missing); }).what()) ==
        missing + ": file does not exist");

  const std::string broken = "tracker:\n  sort: {max_age: 5\n  linking: {}\n";
  const std::string broken_path = dir.Write("broken.yaml", broken);
  const ConfigError syntax = RequireConfigError([&] { LoadTrackerOptionsFile(broken_path); });
  CHECK(syntax.file() == broken_path);
  CHECK(syntax.line() >= 2);
  CHECK_THAT(syntax.reason(), Catch::StartsWith("YAML syntax error"));

  CheckLocated(RequireConfigError([] { ParseTrackerOptions("{}\n", "o.yaml"); }),
               "o.yaml",
               1,
               "",
               "missing required key 'tracker'");
  CheckLocated(RequireConfigError([] { ParseTrackerOptions("window_size: 20\n", "o.yaml"); }),
               "o.yaml",
               1,
               "window_size",
               "unknown key (did you mean 'tracker.window_size'?)");

  // Errors from a file name the path given, and a valid file loads.
  const std::string bad_path = dir.Write("bad.yaml", "tracker:\n  window_step: 0\n");
  CheckLocated(RequireConfigError([&] { LoadTrackerOptionsFile(bad_path); }),
               bad_path,
               2,
               "tracker.window_step",
               "out of range");
  const std::string good_path = dir.Write("good.json", R"({"tracker": {"sort": {"max_age": 3}}})");
  CHECK(LoadTrackerOptionsFile(good_path).sort.max_age == 3);
}

TEST_CASE("The tracker map embeds in a larger document", "[unit]") {
  const std::string text =
      "daemon:\n"
      "  lcm_url: memq://\n"
      "pipeline:\n"
      "  tracker:\n"
      "    association:\n"
      "      lambda: 0.25\n";
  const internal::NodeRef root = internal::ParseDocument(text, "daemon.yaml");
  const internal::MapRef top(root, {"daemon", "pipeline"});
  const internal::MapRef pipeline(top.Get("pipeline"), {"tracker"});
  const TrackerOptions o = internal::ParseTrackerOptionsNode(pipeline.Get("tracker"));
  CHECK(o.association.lambda == 0.25);

  std::string bad = text;
  bad.replace(bad.find("lambda"), 6, "lamda");
  const internal::NodeRef bad_root = internal::ParseDocument(bad, "daemon.yaml");
  const internal::MapRef bad_top(bad_root, {"daemon", "pipeline"});
  const internal::MapRef bad_pipeline(bad_top.Get("pipeline"), {"tracker"});
  CheckLocated(
      RequireConfigError([&] { internal::ParseTrackerOptionsNode(bad_pipeline.Get("tracker")); }),
      "daemon.yaml",
      LineOf(bad, "lamda"),
      "pipeline.tracker.association.lamda",
      "did you mean 'lambda'?");

  // AppendTrackerOptionsYaml nests at any indentation and reads back exactly.
  std::mt19937 rng(99);
  const TrackerOptions random = RandomOptions(&rng);
  std::string nested = "pipeline:\n  tracker:\n";
  internal::AppendTrackerOptionsYaml(random, 4, &nested);
  const internal::NodeRef nested_root = internal::ParseDocument(nested, "n.yaml");
  const internal::MapRef nested_top(nested_root, {"pipeline"});
  const internal::MapRef nested_pipeline(nested_top.Get("pipeline"), {"tracker"});
  RequireSameOptions(internal::ParseTrackerOptionsNode(nested_pipeline.Get("tracker")), random);
}

}  // namespace
}  // namespace mvtrack::config
