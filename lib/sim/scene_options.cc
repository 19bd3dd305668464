#include "sim/scene_options.h"

#include <algorithm>
#include <cmath>

namespace mvtrack::sim {
namespace {

constexpr double kInitialJitterM = 0.1;

// Grid points per axis over an interval of length `extent` at `pitch` (both ends included).
int GridCount(double extent, double pitch) {
  return static_cast<int>(std::floor(extent / pitch + 1e-9)) + 1;
}

}  // namespace

double InitialGridPitch(const SceneOptions& options) {
  return options.min_separation_m + 2.0 * kInitialJitterM + 0.1;
}

int InitialCapacity(const SceneOptions& options) {
  const double w = options.room_width_m - 2.0 * options.waypoint_margin_m;
  const double d = options.room_depth_m - 2.0 * options.waypoint_margin_m;
  if (!(w >= 0.0) || !(d >= 0.0)) return 0;
  const double pitch = InitialGridPitch(options);
  const long long n = static_cast<long long>(GridCount(w, pitch)) * GridCount(d, pitch);
  return n > 1000000 ? 1000000 : static_cast<int>(n);
}

bool SceneOptions::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = "SceneOptions: " + reason;
    return false;
  };
  auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(room_width_m) || !finite(room_depth_m) || room_width_m < 2.0 || room_depth_m < 2.0 ||
      room_width_m > 1000.0 || room_depth_m > 1000.0) {
    return fail("room_width_m and room_depth_m must be in [2, 1000]");
  }
  if (num_cameras < 1 || num_cameras > 4096) return fail("num_cameras must be in [1, 4096]");
  if (camera_layout != CameraLayout::kRing && camera_layout != CameraLayout::kCeilingGrid &&
      camera_layout != CameraLayout::kCorridor) {
    return fail("camera_layout is not a known CameraLayout");
  }
  if (!finite(camera_height_m) || camera_height_m < 0.5 || camera_height_m > 100.0) {
    return fail("camera_height_m must be in [0.5, 100]");
  }
  if (image_width_px < 16 || image_height_px < 16 || image_width_px > 100000 ||
      image_height_px > 100000) {
    return fail("image_width_px and image_height_px must be in [16, 100000]");
  }
  if (!finite(horizontal_fov_deg) || horizontal_fov_deg < 10.0 || horizontal_fov_deg > 160.0) {
    return fail("horizontal_fov_deg must be in [10, 160]");
  }
  if (!finite(look_at_height_m) || look_at_height_m < 0.0 ||
      std::abs(look_at_height_m - camera_height_m) < 0.1) {
    return fail("look_at_height_m must be >= 0 and differ from camera_height_m by >= 0.1");
  }
  if (!finite(grid_pitch_deg) || grid_pitch_deg < 10.0 || grid_pitch_deg > 90.0) {
    return fail("grid_pitch_deg must be in [10, 90]");
  }
  if (num_people < 0) return fail("num_people must be >= 0");
  if (num_frames < 0) return fail("num_frames must be >= 0");
  if (!finite(fps) || fps < 0.1 || fps > 1000.0) return fail("fps must be in [0.1, 1000]");
  if (start_utime < 0) return fail("start_utime must be >= 0");
  if (!finite(mean_stay_s) || mean_stay_s < 0.1) return fail("mean_stay_s must be >= 0.1");
  if (!finite(mean_absence_s) || mean_absence_s < 0.0) {
    return fail("mean_absence_s must be >= 0");
  }
  if (!finite(min_speed_mps) || !finite(max_speed_mps) || min_speed_mps < 0.1 ||
      max_speed_mps < min_speed_mps || max_speed_mps > 3.0) {
    return fail("need 0.1 <= min_speed_mps <= max_speed_mps <= 3");
  }
  if (!finite(min_height_m) || !finite(max_height_m) || min_height_m < 0.5 ||
      max_height_m < min_height_m || max_height_m > 2.5) {
    return fail("need 0.5 <= min_height_m <= max_height_m <= 2.5");
  }
  if (!finite(min_separation_m) || min_separation_m < 0.2 || min_separation_m > 3.0) {
    return fail("min_separation_m must be in [0.2, 3]");
  }
  if (!finite(waypoint_margin_m) || waypoint_margin_m < 0.3 ||
      2.0 * waypoint_margin_m > std::min(room_width_m, room_depth_m) - 0.5) {
    return fail(
        "waypoint_margin_m must be >= 0.3 and leave at least 0.5 m of walkable width and depth");
  }
  if (!finite(pause_probability) || pause_probability < 0.0 || pause_probability > 1.0) {
    return fail("pause_probability must be in [0, 1]");
  }
  if (!finite(max_pause_s) || max_pause_s < 0.5) return fail("max_pause_s must be >= 0.5");
  if (!finite(pixel_noise_px) || pixel_noise_px < 0.0 || pixel_noise_px > 100.0) {
    return fail("pixel_noise_px must be in [0, 100]");
  }
  if (!finite(keypoint_dropout) || keypoint_dropout < 0.0 || keypoint_dropout > 1.0) {
    return fail("keypoint_dropout must be in [0, 1]");
  }
  if (!finite(miss_rate) || miss_rate < 0.0 || miss_rate > 1.0) {
    return fail("miss_rate must be in [0, 1]");
  }
  if (!finite(false_positives_per_frame) || false_positives_per_frame < 0.0 ||
      false_positives_per_frame > 50.0) {
    return fail("false_positives_per_frame must be in [0, 50]");
  }
  if (!finite(occlusion_threshold) || !(occlusion_threshold > 0.0) || occlusion_threshold > 1.0) {
    return fail("occlusion_threshold must be in (0, 1]");
  }
  if (embedding_dim < 0 || embedding_dim > 4096) return fail("embedding_dim must be in [0, 4096]");
  const auto unit = [&](double v) { return finite(v) && v >= 0.0 && v <= 1.0; };
  const auto non_negative = [&](double v) { return finite(v) && v >= 0.0 && v <= 100.0; };
  if (!non_negative(embedding_noise)) return fail("embedding_noise must be in [0, 100]");
  if (!non_negative(embedding_view_drift)) return fail("embedding_view_drift must be in [0, 100]");
  if (!unit(embedding_population_similarity) || embedding_population_similarity >= 1.0) {
    return fail("embedding_population_similarity must be in [0, 1)");
  }
  if (!unit(look_alike_fraction)) return fail("look_alike_fraction must be in [0, 1]");
  if (!non_negative(look_alike_spread)) return fail("look_alike_spread must be in [0, 100]");
  if (!unit(reentry_probability)) return fail("reentry_probability must be in [0, 1]");
  if (!finite(min_reentry_absence_s) || min_reentry_absence_s < 0.0) {
    return fail("min_reentry_absence_s must be >= 0");
  }
  if (!finite(max_reentry_absence_s) || max_reentry_absence_s < min_reentry_absence_s) {
    return fail("max_reentry_absence_s must be >= min_reentry_absence_s");
  }
  if (linger_spots.size() > 64) return fail("at most 64 linger_spots");
  for (const Vec2& spot : linger_spots) {
    if (!finite(spot.x()) || !finite(spot.y()) || spot.x() < 0.2 || spot.y() < 0.2 ||
        spot.x() > room_width_m - 0.2 || spot.y() > room_depth_m - 0.2) {
      return fail("linger_spots must be at least 0.2 m inside the room");
    }
  }
  if (!finite(mean_linger_s) || mean_linger_s <= 0.0 || mean_linger_s > 1e6) {
    return fail("mean_linger_s must be in (0, 1e6]");
  }
  const int capacity = InitialCapacity(*this);
  if (num_people > capacity) {
    return fail("num_people = " + std::to_string(num_people) + " do not fit in the room: at most " +
                std::to_string(capacity) + " at the initial spacing of " +
                std::to_string(InitialGridPitch(*this)) + " m (enlarge the room)");
  }
  return true;
}

}  // namespace mvtrack::sim
