#pragma once
/// @file
/// Scene presets: SceneOptions sized for a given number of cameras and people, as `mvtrack sim`
/// and `mvtrack bench` use them (a room for small rigs, a store floor with a ceiling grid for
/// large ones). Stateless functions.

#include <cstdint>

#include "sim/scene_options.h"

namespace mvtrack::sim {

/// Floor area per person of SizedScene (m^2): a busy shop, not a queue.
inline constexpr double kPresetAreaPerPersonM2 = 4.0;
/// Smallest floor side of SizedScene (m): the 6 m x 6 m room of the default scene.
inline constexpr double kPresetMinSideM = 6.0;

/// A scene of `num_cameras` cameras and `num_people` people with a realistic detector model.
///
/// Floor: a square of side max(kPresetMinSideM, sqrt(kPresetAreaPerPersonM2 x num_people)).
/// Cameras: up to 8 cameras on a floor side <= 10 m: the ring (CameraLayout::kRing) at 3 m,
/// 1280 x 720 px, 80 deg horizontal field of view (f = 763 px, a typical 1/2.8" CCTV lens at
/// 3.6 mm), looking at the room centre at 1 m. Otherwise a store ceiling grid
/// (CameraLayout::kCeilingGrid) at 4 m, 1920 x 1080 px, 90 deg (f = 960 px), pitched 50 deg
/// down, so each camera sees the floor from under itself (0.8 m) to about 10 m away, as dense
/// store coverage does (a 40 deg pitch sees 20 m: more people per image, slower, and at 32 x 100
/// less accurate; docs/BENCHMARKS.md).
/// Detector: 1.5 px of noise, 5 % missed detections, 0.2 false positives per camera-frame,
/// occlusion by depth order with threshold 0.7, keypoint dropout 2 % (the `mvtrack demo`
/// detector plus dropout). `poses` selects COCO-17 poses with the boxes. People walk for the
/// whole run (no entering and leaving; set SceneOptions::enter_and_leave for that).
/// The result is valid for num_cameras in [1, 4096] and num_people in [0, 100000].
SceneOptions SizedScene(int num_cameras, int num_people, bool poses, std::uint64_t seed);

}  // namespace mvtrack::sim
