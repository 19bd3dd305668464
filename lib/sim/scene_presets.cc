#include "sim/scene_presets.h"

#include <algorithm>
#include <cmath>

namespace mvtrack::sim {

SceneOptions SizedScene(int num_cameras, int num_people, bool poses, std::uint64_t seed) {
  SceneOptions o;
  o.seed = seed;
  o.num_cameras = num_cameras;
  o.num_people = num_people;
  const double side = std::max(
      kPresetMinSideM, std::ceil(std::sqrt(kPresetAreaPerPersonM2 * std::max(num_people, 0))));
  o.room_width_m = side;
  o.room_depth_m = side;
  if (num_cameras <= 8 && side <= 10.0) {
    o.camera_layout = CameraLayout::kRing;
    o.camera_height_m = 3.0;
    o.image_width_px = 1280;
    o.image_height_px = 720;
    o.horizontal_fov_deg = 80.0;
    o.look_at_height_m = 1.0;
  } else {
    o.camera_layout = CameraLayout::kCeilingGrid;
    o.camera_height_m = 4.0;
    o.image_width_px = 1920;
    o.image_height_px = 1080;
    o.horizontal_fov_deg = 90.0;
    o.grid_pitch_deg = 50.0;
  }
  o.pixel_noise_px = 1.5;
  o.miss_rate = 0.05;
  o.false_positives_per_frame = 0.2;
  o.keypoint_dropout = 0.02;
  o.occlusion = true;
  o.occlusion_threshold = 0.7;
  o.poses = poses;
  return o;
}

}  // namespace mvtrack::sim
