// SceneOptions::Validate: defaults are valid, each bad field is rejected with a reason naming it,
// and the people-capacity check matches what the simulator can actually place.

#include "sim/scene_options.h"

#include <catch2/catch.hpp>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "sim/crowd.h"

namespace mvtrack::sim {
namespace {

TEST_CASE("default scene options are valid", "[unit][sim]") {
  std::string why;
  CHECK(SceneOptions{}.Validate(&why));
  CHECK(why.empty());
}

TEST_CASE("invalid scene options are rejected with the field named", "[unit][sim]") {
  struct Case {
    std::string field;
    std::function<void(SceneOptions*)> break_it;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
      {"room_width_m", [](SceneOptions* o) { o->room_width_m = 1.0; }},
      {"room_width_m", [&](SceneOptions* o) { o->room_depth_m = nan; }},
      {"num_cameras", [](SceneOptions* o) { o->num_cameras = 0; }},
      {"camera_height_m", [](SceneOptions* o) { o->camera_height_m = -1.0; }},
      {"image_width_px", [](SceneOptions* o) { o->image_height_px = 0; }},
      {"horizontal_fov_deg", [](SceneOptions* o) { o->horizontal_fov_deg = 180.0; }},
      {"look_at_height_m", [](SceneOptions* o) { o->look_at_height_m = o->camera_height_m; }},
      {"grid_pitch_deg", [](SceneOptions* o) { o->grid_pitch_deg = 95.0; }},
      {"num_people", [](SceneOptions* o) { o->num_people = -1; }},
      {"num_frames", [](SceneOptions* o) { o->num_frames = -5; }},
      {"fps", [](SceneOptions* o) { o->fps = 0.0; }},
      {"start_utime", [](SceneOptions* o) { o->start_utime = -1; }},
      {"mean_stay_s", [](SceneOptions* o) { o->mean_stay_s = 0.0; }},
      {"mean_absence_s", [](SceneOptions* o) { o->mean_absence_s = -1.0; }},
      {"min_speed_mps", [](SceneOptions* o) { o->max_speed_mps = 0.5; }},
      {"min_height_m", [](SceneOptions* o) { o->min_height_m = 2.0; }},
      {"min_separation_m", [](SceneOptions* o) { o->min_separation_m = 0.1; }},
      {"waypoint_margin_m", [](SceneOptions* o) { o->waypoint_margin_m = 2.9; }},
      {"pause_probability", [](SceneOptions* o) { o->pause_probability = 1.5; }},
      {"max_pause_s", [](SceneOptions* o) { o->max_pause_s = 0.1; }},
      {"pixel_noise_px", [](SceneOptions* o) { o->pixel_noise_px = -1.0; }},
      {"keypoint_dropout", [](SceneOptions* o) { o->keypoint_dropout = 1.1; }},
      {"miss_rate", [&](SceneOptions* o) { o->miss_rate = nan; }},
      {"false_positives_per_frame", [](SceneOptions* o) { o->false_positives_per_frame = -0.1; }},
      {"occlusion_threshold", [](SceneOptions* o) { o->occlusion_threshold = 0.0; }},
      {"num_people", [](SceneOptions* o) { o->num_people = 100; }},  // 6 x 6 m room is too small
      {"linger_spots", [](SceneOptions* o) { o->linger_spots = {Vec2(0.1, 3.0)}; }},
      {"linger_spots", [&](SceneOptions* o) { o->linger_spots = {Vec2(3.0, nan)}; }},
      {"linger_spots", [](SceneOptions* o) { o->linger_spots.assign(65, Vec2(3.0, 3.0)); }},
      {"mean_linger_s", [](SceneOptions* o) { o->mean_linger_s = 0.0; }},
  };
  for (const Case& c : cases) {
    SceneOptions o;
    c.break_it(&o);
    std::string why;
    INFO("expected a complaint about " << c.field);
    CHECK_FALSE(o.Validate(&why));
    CHECK_THAT(why, Catch::Contains(c.field));
    CHECK_FALSE(o.Validate(nullptr));  // a null reason pointer is allowed
  }
}

TEST_CASE("the people capacity is the size of the initial grid and is reachable", "[unit][sim]") {
  SceneOptions o;  // 6 x 6 m, margin 0.5 m: 5 m at a 0.9 m pitch gives 6 points per axis
  REQUIRE(InitialGridPitch(o) == Approx(0.9));
  CHECK(InitialCapacity(o) == 36);
  o.num_people = InitialCapacity(o);
  CHECK(o.Validate(nullptr));
  o.num_people += 1;
  CHECK_FALSE(o.Validate(nullptr));

  // A full room starts with everyone at least min_separation_m + 0.1 apart.
  o.num_people = InitialCapacity(o);
  o.num_frames = 1;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  REQUIRE(truth.size() == 1);
  REQUIRE(truth[0].people.size() == 36u);
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < truth[0].people.size(); ++i) {
    for (std::size_t j = i + 1; j < truth[0].people.size(); ++j) {
      closest = std::min(closest,
                         (truth[0].people[i].footprint_m - truth[0].people[j].footprint_m).norm());
    }
  }
  CHECK(closest >= o.min_separation_m + 0.1 - 1e-9);
}

}  // namespace
}  // namespace mvtrack::sim
