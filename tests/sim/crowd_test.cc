// People motion and skeletons: people stay in the room, never come closer than the minimum
// separation (also when they must pass each other in a corridor), walk at plausible speeds facing
// where they go, have rigid plausible bodies, and enter and leave through the walls on request.

#include "sim/crowd.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <vector>

#include "sim/body.h"

namespace mvtrack::sim {
namespace {

// COCO-17 indices used below.
constexpr int kNose = 0, kLEar = 3, kREar = 4, kLShoulder = 5, kRShoulder = 6, kLHip = 11,
              kRHip = 12, kLKnee = 13, kRKnee = 14, kLAnkle = 15, kRAnkle = 16;

double MinPairDistance(const FrameTruth& t) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < t.people.size(); ++i) {
    for (std::size_t j = i + 1; j < t.people.size(); ++j) {
      best = std::min(best, (t.people[i].footprint_m - t.people[j].footprint_m).norm());
    }
  }
  return best;
}

double DistanceToWall(const SceneOptions& o, const Vec3& p) {
  return std::min({p.x(), p.y(), o.room_width_m - p.x(), o.room_depth_m - p.y()});
}

TEST_CASE("a crowded room: everyone stays inside and at least 0.6 m apart", "[unit][sim]") {
  SceneOptions o;
  o.seed = 11;
  o.num_people = 12;  // one person per 3 m^2: frequent encounters
  o.num_frames = 600;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  REQUIRE(truth.size() == 600u);
  double closest = std::numeric_limits<double>::infinity();
  double closest_to_wall = std::numeric_limits<double>::infinity();
  int bad_ids = 0, off_floor = 0;
  std::map<int, double> path_m;
  for (std::size_t f = 0; f < truth.size(); ++f) {
    const FrameTruth& t = truth[f];
    REQUIRE(t.frame == static_cast<FrameIndex>(f));
    REQUIRE(t.people.size() == 12u);
    for (std::size_t i = 0; i < t.people.size(); ++i) {
      const PersonTruth& p = t.people[i];
      if (p.id != static_cast<int>(i)) ++bad_ids;  // sorted by id, ids 0..N-1
      if (p.footprint_m.z() != 0.0) ++off_floor;
      closest_to_wall = std::min(closest_to_wall, DistanceToWall(o, p.footprint_m));
      if (f > 0) path_m[p.id] += (p.footprint_m - truth[f - 1].people[i].footprint_m).norm();
    }
    closest = std::min(closest, MinPairDistance(t));
  }
  CHECK(bad_ids == 0);
  CHECK(off_floor == 0);
  CHECK(closest_to_wall >= 0.0);
  INFO("closest approach " << closest);
  CHECK(closest >= o.min_separation_m);
  CHECK(closest < o.min_separation_m + 0.1);  // the constraint is actually exercised
  // Nobody is stuck: everyone covers at least 4 m in 20 s.
  for (const auto& [id, metres] : path_m) {
    INFO("person " << id);
    CHECK(metres > 4.0);
  }
}

TEST_CASE("two people in a corridor pass each other without overlapping", "[unit][sim]") {
  SceneOptions o;
  o.room_width_m = 2.0;  // walkable width 1.6 m (0.2 m wall clearance), waypoints on a 1 m strip
  o.room_depth_m = 12.0;
  o.num_people = 2;
  o.num_frames = 2400;
  o.pause_probability = 0.0;
  int order_changes = 0;
  double closest = std::numeric_limits<double>::infinity();
  for (const std::uint64_t seed : {1u, 2u}) {
    o.seed = seed;
    const std::vector<FrameTruth> truth = SimulatePeople(o);
    int previous_order = 0;
    for (const FrameTruth& t : truth) {
      REQUIRE(t.people.size() == 2u);
      closest = std::min(closest, (t.people[0].footprint_m - t.people[1].footprint_m).norm());
      // Who is further along the corridor; it changes only when they pass each other.
      const double dy = t.people[0].footprint_m.y() - t.people[1].footprint_m.y();
      const int order = dy > 0.0 ? 1 : -1;
      if (previous_order != 0 && order != previous_order) ++order_changes;
      previous_order = order;
    }
  }
  INFO("closest " << closest << ", passes " << order_changes);
  CHECK(closest >= o.min_separation_m);
  CHECK(order_changes >= 3);
}

TEST_CASE("walking is plausible: speeds, facing, pauses", "[unit][sim]") {
  SceneOptions o;
  o.seed = 5;
  o.num_people = 4;
  o.num_frames = 1200;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  int samples = 0, moving = 0, facing = 0, still = 0, velocity_mismatch = 0;
  double speed_sum = 0.0, max_speed = 0.0;
  for (std::size_t f = 1; f < truth.size(); ++f) {
    for (std::size_t i = 0; i < truth[f].people.size(); ++i) {
      const PersonTruth& p = truth[f].people[i];
      const Vec3 step = p.footprint_m - truth[f - 1].people[i].footprint_m;
      const double speed = step.norm() * o.fps;
      if ((p.velocity_mps - step * o.fps).norm() > 1e-9) ++velocity_mismatch;
      max_speed = std::max(max_speed, speed);
      ++samples;
      speed_sum += speed;
      if (speed < 0.05) ++still;
      if (speed > 0.5) {
        ++moving;
        const Vec2 dir(std::cos(p.heading_rad), std::sin(p.heading_rad));
        const double cos_angle = dir.dot(Vec2(step.x(), step.y()).normalized());
        if (cos_angle > std::cos(30.0 * std::numbers::pi / 180.0)) ++facing;
      }
    }
  }
  const double mean_speed = speed_sum / samples;
  INFO("mean speed " << mean_speed << " m/s, still " << still << "/" << samples << ", facing "
                     << facing << "/" << moving);
  CHECK(velocity_mismatch == 0);
  CHECK(max_speed <= o.max_speed_mps + 1e-9);
  CHECK(mean_speed > 0.5);
  CHECK(mean_speed < 1.5);
  CHECK(facing > 0.9 * moving);  // people face where they walk
  CHECK(still > 0);              // pauses happen ...
  CHECK(still < samples / 4);    // ... but people mostly walk
}

TEST_CASE("skeletons are rigid, upright, sized and oriented plausibly", "[unit][sim]") {
  SceneOptions o;
  o.seed = 9;
  o.num_people = 5;
  o.num_frames = 150;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  const std::vector<std::pair<int, int>> bones = {{kLHip, kLKnee},
                                                  {kLKnee, kLAnkle},
                                                  {kRHip, kRKnee},
                                                  {kRKnee, kRAnkle},
                                                  {5, 7},
                                                  {7, 9},
                                                  {6, 8},
                                                  {8, 10},
                                                  {kLHip, kRHip},
                                                  {kLShoulder, kRShoulder},
                                                  {kLShoulder, kLHip},
                                                  {kLEar, kREar}};
  std::map<int, std::vector<double>> first_lengths;
  std::map<int, double> height_of;
  std::set<double> left_knee_heights;
  for (const FrameTruth& t : truth) {
    for (const PersonTruth& p : t.people) {
      REQUIRE(p.joints_m.size() == 17u);
      INFO("person " << p.id << " frame " << t.frame);
      CHECK(p.height_m >= o.min_height_m);
      CHECK(p.height_m <= o.max_height_m);
      if (height_of.count(p.id) != 0) CHECK(height_of[p.id] == p.height_m);
      height_of[p.id] = p.height_m;
      std::vector<double> lengths;
      for (const auto& [a, b] : bones) {
        lengths.push_back(
            (p.joints_m[static_cast<std::size_t>(a)] - p.joints_m[static_cast<std::size_t>(b)])
                .norm());
      }
      auto [it, inserted] = first_lengths.emplace(p.id, lengths);
      double worst_change = 0.0;
      for (std::size_t k = 0; k < lengths.size(); ++k) {
        worst_change = std::max(worst_change, std::abs(lengths[k] - it->second[k]));
      }
      CHECK(worst_change < 1e-9);
      CHECK(lengths[0] == Approx(0.24 * p.height_m));  // thigh
      CHECK(lengths[4] == Approx(0.18 * p.height_m));  // upper arm
      // Upright: head top highest, at the person's height; feet on or above the floor; the
      // pelvis above the footprint.
      CHECK(p.head_top_m.z() == Approx(p.height_m));
      double lowest = p.head_top_m.z(), highest = 0.0;
      for (const Vec3& j : p.joints_m) {
        lowest = std::min(lowest, j.z());
        highest = std::max(highest, j.z());
      }
      CHECK(lowest >= 0.0);
      CHECK(highest < p.head_top_m.z());
      const Vec3 pelvis = 0.5 * (p.joints_m[kLHip] + p.joints_m[kRHip]);
      CHECK((pelvis - p.footprint_m).head<2>().norm() < 1e-9);
      // Facing the heading, left on the left.
      const Vec3 forward(std::cos(p.heading_rad), std::sin(p.heading_rad), 0.0);
      const Vec3 left(-forward.y(), forward.x(), 0.0);
      const Vec3 ears = 0.5 * (p.joints_m[kLEar] + p.joints_m[kREar]);
      CHECK((p.joints_m[kNose] - ears).dot(forward) > 0.05);
      CHECK((p.joints_m[kLShoulder] - p.joints_m[kRShoulder]).dot(left) > 0.2);
      CHECK((p.joints_m[kLHip] - p.joints_m[kRHip]).dot(left) > 0.1);
      if (p.id == 0) left_knee_heights.insert(std::round(p.joints_m[kLKnee].z() * 1000.0));
    }
  }
  // The legs move with the gait: the knee height of a walking person varies.
  CHECK(left_knee_heights.size() > 10u);
}

TEST_CASE("enter_and_leave: people enter and leave through the walls", "[unit][sim]") {
  SceneOptions o;
  o.seed = 4;
  o.num_people = 3;
  o.num_frames = 900;
  o.enter_and_leave = true;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  std::map<int, std::size_t> first, last;
  std::map<int, Vec3> first_at, last_at;
  for (std::size_t f = 0; f < truth.size(); ++f) {
    const FrameTruth& t = truth[f];
    CHECK(t.people.size() <= 3u);
    CHECK(std::is_sorted(t.people.begin(),
                         t.people.end(),
                         [](const PersonTruth& a, const PersonTruth& b) { return a.id < b.id; }));
    if (t.people.size() >= 2) CHECK(MinPairDistance(t) >= o.min_separation_m);
    for (const PersonTruth& p : t.people) {
      CHECK(DistanceToWall(o, p.footprint_m) >= 0.0);
      if (first.count(p.id) == 0) {
        first[p.id] = f;
        first_at[p.id] = p.footprint_m;
      }
      last[p.id] = f;
      last_at[p.id] = p.footprint_m;
    }
  }
  int entered = 0, left = 0;
  for (const auto& [id, f] : first) {
    INFO("person " << id << " frames " << f << ".." << last[id]);
    // Everyone is present in one contiguous run of frames.
    for (std::size_t g = f; g <= last[id]; ++g) {
      CHECK(std::any_of(truth[g].people.begin(), truth[g].people.end(), [&](const PersonTruth& p) {
        return p.id == id;
      }));
    }
    if (f > 0) {  // entered during the run: first seen right behind a wall
      ++entered;
      CHECK(DistanceToWall(o, first_at[id]) < 0.1);
    }
    if (last[id] + 1 < truth.size()) {  // left during the run: last seen right at a wall
      ++left;
      CHECK(DistanceToWall(o, last_at[id]) < 0.1);
    }
  }
  CHECK(entered >= 2);
  CHECK(left >= 2);
  // New people get new ids.
  CHECK(first.size() == static_cast<std::size_t>(entered) + truth.front().people.size());
}

TEST_CASE("linger_spots: people stand at them for minutes, shifting a little", "[unit][sim]") {
  SceneOptions o;
  o.seed = 3;
  o.num_people = 6;
  o.num_frames = 30 * 240;
  o.enter_and_leave = true;
  o.linger_spots = {Vec2(2.0, 3.0), Vec2(4.0, 3.0)};
  o.mean_linger_s = 60.0;
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  // Per spot: the runs of frames in which one person stands within 0.4 m of it.
  for (const Vec2& spot : o.linger_spots) {
    INFO("spot " << spot.transpose());
    int run_id = -1;
    std::size_t run_start = 0;
    std::size_t longest = 0, stood = 0;
    double sway = 0.0;  // largest distance from the spot during runs of at least 20 s
    std::vector<double> run_distances;
    for (std::size_t f = 0; f < truth.size(); ++f) {
      int here = -1;
      double d = 0.0;
      for (const PersonTruth& p : truth[f].people) {
        const double dp = (p.footprint_m.head<2>() - spot).norm();
        if (dp < 0.4 && (here == -1 || dp < d)) {
          here = p.id;
          d = dp;
        }
      }
      if (here != run_id || f + 1 == truth.size()) {
        const std::size_t length = f - run_start;
        if (run_id >= 0 && length >= 20 * 30u) {
          sway = std::max(sway, *std::max_element(run_distances.begin(), run_distances.end()));
          stood += length;
        }
        longest = std::max(longest, run_id >= 0 ? length : 0u);
        run_id = here;
        run_start = f;
        run_distances.clear();
      }
      if (here >= 0) run_distances.push_back(d);
    }
    // Someone stands there for at least half the mean time (U[0.5, 1.5] x 60 s), the spot is
    // taken much of the run, and standing people stay within the sway radius (0.2 m) plus the
    // arrival radius (0.2 m) but do not stand stock still.
    CHECK(longest >= 30 * 30u);
    CHECK(stood >= truth.size() / 3);
    CHECK(sway <= 0.4);
    CHECK(sway >= 0.1);
  }
}

TEST_CASE("coarse frame rates are integrated in sub-steps", "[unit][sim]") {
  SceneOptions o;
  o.seed = 2;
  o.num_people = 8;
  o.num_frames = 60;
  o.fps = 2.0;  // 0.5 s between frames: ten 50 ms sub-steps each
  const std::vector<FrameTruth> truth = SimulatePeople(o);
  double closest = std::numeric_limits<double>::infinity(), longest_step = 0.0;
  for (std::size_t f = 1; f < truth.size(); ++f) {
    closest = std::min(closest, MinPairDistance(truth[f]));
    CHECK(truth[f].utime - truth[f - 1].utime == 500000);
    for (std::size_t i = 0; i < truth[f].people.size(); ++i) {
      const Vec3 step = truth[f].people[i].footprint_m - truth[f - 1].people[i].footprint_m;
      longest_step = std::max(longest_step, step.norm());
    }
  }
  CHECK(closest >= o.min_separation_m);
  CHECK(longest_step <= o.max_speed_mps / o.fps + 1e-9);
  CHECK(longest_step > 0.3);  // people do walk several sub-steps per frame
}

}  // namespace
}  // namespace mvtrack::sim
