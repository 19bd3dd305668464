#include "sim/crowd.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include "core/check.h"
#include "sim/random.h"

namespace mvtrack::sim {
namespace {

using internal::DeriveSeed;
using internal::Random;
using internal::Stream;

constexpr double kPi = std::numbers::pi;
constexpr double kMaxSubstepS = 0.05;        // integration step bound (see the class comment)
constexpr double kInteractionRadiusM = 2.0;  // social-force neighbourhood
constexpr double kRepulsionMps = 1.2;        // social-force strength A
constexpr double kRepulsionRangeM = 0.3;     // social-force range B
constexpr double kMaxAccelerationMps2 = 3.0;
constexpr double kMaxTurnRateRadps = 6.0;
constexpr double kArrivalRadiusM = 0.2;
constexpr double kSlowdownRadiusM = 0.6;
constexpr double kBlockedTimeoutS = 2.0;
constexpr double kWallClearanceM = 0.2;    // people inside keep their footprint this far in
constexpr double kOutsideBandM = 1.5;      // entering/leaving people stay within this band
constexpr double kSpawnDistanceM = 0.5;    // spawn this far outside a wall
constexpr double kExitDistanceM = 0.8;     // exit goals this far outside a wall
constexpr double kDespawnDistanceM = 0.4;  // leaving people vanish this far outside the room
constexpr double kCornerAvoidanceM = 0.5;  // doors keep this far from the corners
constexpr double kLingerSwayM = 0.2;       // people standing at a linger spot shift within this
constexpr double kMinSwayS = 2.0;          // ... choosing a new place to stand every 2-6 s
constexpr double kMaxSwayS = 6.0;

enum class Mode { kEntering, kInside, kLeaving };

Vec2 Rotate(const Vec2& v, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double WrapAngle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

}  // namespace

struct CrowdSimulator::State {
  struct Walker {
    int id = 0;
    Vec2 position = Vec2::Zero();
    Vec2 velocity = Vec2::Zero();
    Vec2 frame_start_position = Vec2::Zero();
    Vec2 frame_velocity = Vec2::Zero();
    double heading_rad = 0.0;
    double phase_rad = 0.0;
    double amplitude = 0.0;
    double height_m = 1.75;
    double preferred_speed_mps = 1.0;
    Vec2 goal = Vec2::Zero();
    Mode mode = Mode::kInside;
    double pause_left_s = 0.0;
    double blocked_s = 0.0;
    double stay_left_s = 0.0;  // enter_and_leave only
    int spot = -1;             // the linger spot it walks to or stands at, else -1
    bool lingering = false;    // standing at `spot` (arrived)
    double linger_left_s = 0.0;
    double sway_left_s = 0.0;
    Random rng{0};
    std::shared_ptr<const PersonAppearance> appearance;  // embedding_dim > 0 only
    int visits = 0;                                      // earlier visits of this id (re-entries)
  };
  // Someone who left (re-entry candidates; reentry_probability > 0 only).
  struct Departed {
    int id = 0;
    int visits = 0;  // visits so far
    double height_m = 0.0;
    double left_at_s = 0.0;
  };
  struct Slot {
    std::optional<Walker> walker;
    double absence_left_s = 0.0;
  };

  explicit State(const SceneOptions& options)
      : o(options),
        population(DeriveSeed(options.seed, Stream::kPopulation)),
        reentry(DeriveSeed(options.seed, Stream::kReentry)) {}

  SceneOptions o;
  FrameIndex frame = 0;
  int next_id = 0;
  Random population;
  Random reentry;
  std::vector<Departed> departed;  // in order of leaving
  double time_s = 0.0;             // simulated time (sum of sub-steps)
  std::vector<Slot> slots;
  std::vector<char> spot_taken;  // per linger spot: someone stands at or walks to it
  int substeps = 1;
  double substep_s = 0.0;

  // Neighbour grid over [-band - 1, W + band + 1] x [...], rebuilt every sub-step.
  double cell_m = 1.0;
  int grid_nx = 1, grid_ny = 1;
  double grid_x0 = 0.0, grid_y0 = 0.0;
  std::vector<std::vector<int>> cells;
  std::vector<Walker*> active;
  std::vector<int> neighbours;

  Vec2 RandomWaypoint(Random* rng) const {
    const double m = o.waypoint_margin_m;
    const double x = rng->Uniform(m, o.room_width_m - m);
    const double y = rng->Uniform(m, o.room_depth_m - m);
    return {x, y};
  }

  // A point `distance` outside a wall, uniformly along the walls' perimeter (corners avoided).
  Vec2 WallPoint(Random* rng, double distance) const {
    const double w = o.room_width_m, d = o.room_depth_m;
    const double usable_w = w - 2.0 * kCornerAvoidanceM, usable_d = d - 2.0 * kCornerAvoidanceM;
    double u = rng->Uniform(0.0, 2.0 * (usable_w + usable_d));
    if (u < usable_w) return {kCornerAvoidanceM + u, -distance};
    u -= usable_w;
    if (u < usable_w) return {kCornerAvoidanceM + u, d + distance};
    u -= usable_w;
    if (u < usable_d) return {-distance, kCornerAvoidanceM + u};
    u -= usable_d;
    return {w + distance, kCornerAvoidanceM + std::min(u, usable_d)};
  }

  bool InRoom(const Vec2& p, double inset) const {
    return p.x() >= inset && p.y() >= inset && p.x() <= o.room_width_m - inset &&
           p.y() <= o.room_depth_m - inset;
  }

  double OutsideDistance(const Vec2& p) const {
    const double dx = std::max({0.0, -p.x(), p.x() - o.room_width_m});
    const double dy = std::max({0.0, -p.y(), p.y() - o.room_depth_m});
    return std::hypot(dx, dy);
  }

  // A new person (returning == null) or the next visit of one who left.
  Walker MakeWalker(const Vec2& position, Mode mode, const Departed* returning = nullptr) {
    Walker w;
    w.id = returning != nullptr ? returning->id : next_id++;
    w.visits = returning != nullptr ? returning->visits : 0;
    w.rng = Random(DeriveSeed(o.seed,
                              Stream::kPerson,
                              static_cast<std::uint64_t>(w.id),
                              static_cast<std::uint64_t>(w.visits)));
    w.height_m = w.rng.Uniform(o.min_height_m, o.max_height_m);
    if (returning != nullptr) w.height_m = returning->height_m;
    if (o.embedding_dim > 0) w.appearance = MakePersonAppearance(o, w.id);
    w.preferred_speed_mps = w.rng.Uniform(o.min_speed_mps, o.max_speed_mps);
    w.phase_rad = w.rng.Uniform(0.0, 2.0 * kPi);
    w.stay_left_s = w.rng.Uniform(0.5, 1.5) * o.mean_stay_s;
    w.goal = RandomWaypoint(&w.rng);
    w.position = position;
    w.frame_start_position = position;
    w.mode = mode;
    const Vec2 to_goal = w.goal - position;
    w.heading_rad = to_goal.norm() > 1e-9 ? std::atan2(to_goal.y(), to_goal.x()) : 0.0;
    return w;
  }

  void Initialize() {
    MVTRACK_CHECK(o.fps > 0.0);
    substeps = std::max(1, static_cast<int>(std::ceil((1.0 / o.fps) / kMaxSubstepS - 1e-9)));
    substep_s = 1.0 / o.fps / substeps;
    cell_m = std::max(kInteractionRadiusM, o.min_separation_m) + 0.5;
    grid_x0 = -kOutsideBandM - 1.0;
    grid_y0 = -kOutsideBandM - 1.0;
    grid_nx = static_cast<int>(std::ceil((o.room_width_m + 2.0 * kOutsideBandM + 2.0) / cell_m));
    grid_ny = static_cast<int>(std::ceil((o.room_depth_m + 2.0 * kOutsideBandM + 2.0) / cell_m));
    cells.assign(static_cast<std::size_t>(grid_nx) * static_cast<std::size_t>(grid_ny), {});
    spot_taken.assign(o.linger_spots.size(), 0);

    // Initial positions: a shuffled, jittered grid over the waypoint area (see
    // InitialGridPitch), which keeps everyone at least min_separation_m + 0.1 apart.
    const double m = o.waypoint_margin_m;
    const double pitch = InitialGridPitch(o);
    const double w = o.room_width_m - 2.0 * m, d = o.room_depth_m - 2.0 * m;
    const int nx = static_cast<int>(std::floor(w / pitch + 1e-9)) + 1;
    const int ny = static_cast<int>(std::floor(d / pitch + 1e-9)) + 1;
    const double x0 = m + 0.5 * (w - (nx - 1) * pitch);
    const double y0 = m + 0.5 * (d - (ny - 1) * pitch);
    std::vector<Vec2> spots;
    for (int iy = 0; iy < ny; ++iy) {
      for (int ix = 0; ix < nx; ++ix) spots.emplace_back(x0 + ix * pitch, y0 + iy * pitch);
    }
    for (std::size_t i = spots.size(); i > 1; --i) {  // Fisher-Yates
      std::swap(spots[i - 1], spots[population.Index(i)]);
    }
    const int initially_inside = o.enter_and_leave ? (o.num_people + 1) / 2 : o.num_people;
    MVTRACK_CHECK(static_cast<std::size_t>(initially_inside) <= spots.size());
    slots.resize(static_cast<std::size_t>(o.num_people));
    for (int i = 0; i < o.num_people; ++i) {
      Slot& slot = slots[static_cast<std::size_t>(i)];
      if (i < initially_inside) {
        const Vec2 jitter(population.Uniform(-0.1, 0.1), population.Uniform(-0.1, 0.1));
        slot.walker = MakeWalker(spots[static_cast<std::size_t>(i)] + jitter, Mode::kInside);
      } else {
        slot.absence_left_s = population.Uniform(0.0, 2.0) * o.mean_absence_s;
      }
    }
  }

  // --- neighbour grid ------------------------------------------------------------------------
  std::pair<int, int> CellOf(const Vec2& p) const {
    const int cx =
        std::clamp(static_cast<int>(std::floor((p.x() - grid_x0) / cell_m)), 0, grid_nx - 1);
    const int cy =
        std::clamp(static_cast<int>(std::floor((p.y() - grid_y0) / cell_m)), 0, grid_ny - 1);
    return {cx, cy};
  }
  // The list of cell (x, y), indexed in std::size_t like the allocation of `cells`.
  std::vector<int>& Cell(int x, int y) {
    return cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(grid_nx) +
                 static_cast<std::size_t>(x)];
  }

  void BuildGrid() {
    for (auto& c : cells) c.clear();
    active.clear();
    for (Slot& s : slots) {
      if (s.walker) active.push_back(&*s.walker);
    }
    for (std::size_t i = 0; i < active.size(); ++i) {
      const auto [cx, cy] = CellOf(active[i]->position);
      Cell(cx, cy).push_back(static_cast<int>(i));
    }
  }

  // Indices into `active` of everyone in the 3x3 cells around `p` (sorted, so that sums over
  // neighbours are in a fixed order).
  void GatherNeighbours(const Vec2& p) {
    neighbours.clear();
    const auto [cx, cy] = CellOf(p);
    for (int y = std::max(0, cy - 1); y <= std::min(grid_ny - 1, cy + 1); ++y) {
      for (int x = std::max(0, cx - 1); x <= std::min(grid_nx - 1, cx + 1); ++x) {
        const auto& c = Cell(x, y);
        neighbours.insert(neighbours.end(), c.begin(), c.end());
      }
    }
    std::sort(neighbours.begin(), neighbours.end());
  }

  // Whether a walker `self` may stand at `p`: inside its region and clear of everyone.
  bool Admissible(const Walker& self, const Vec2& p) const {
    // Regions: people inside keep clear of the walls; entering people do not turn back once in
    // the room, leaving people do not come back once out of it (so everyone's truth is one
    // contiguous run of frames).
    switch (self.mode) {
      case Mode::kInside:
        if (!InRoom(p, kWallClearanceM)) return false;
        break;
      case Mode::kEntering:
        if (InRoom(self.position, 0.0) ? !InRoom(p, 0.0) : !InRoom(p, -kOutsideBandM)) {
          return false;
        }
        break;
      case Mode::kLeaving:
        if (!InRoom(p, -kOutsideBandM) || (!InRoom(self.position, 0.0) && InRoom(p, 0.0))) {
          return false;
        }
        break;
    }
    const double min_sq = o.min_separation_m * o.min_separation_m;
    const double px = p.x(), py = p.y();
    for (const int j : neighbours) {
      const Walker* other = active[static_cast<std::size_t>(j)];
      if (other == &self) continue;
      const double dx = other->position.x() - px, dy = other->position.y() - py;
      if (dx * dx + dy * dy < min_sq) return false;
    }
    return true;
  }

  // Gives up the walker's linger spot (if any): it stands there no longer.
  void ReleaseSpot(Walker* w) {
    if (w->spot >= 0) spot_taken[static_cast<std::size_t>(w->spot)] = 0;
    w->spot = -1;
    w->lingering = false;
  }

  // A place to stand within kLingerSwayM of the walker's spot (uniform over the disc).
  Vec2 SwayGoal(Walker* w) {
    const double r = kLingerSwayM * std::sqrt(w->rng.Uniform());
    const double a = w->rng.Uniform(0.0, 2.0 * kPi);
    return o.linger_spots[static_cast<std::size_t>(w->spot)] +
           Vec2(r * std::cos(a), r * std::sin(a));
  }

  void NewGoal(Walker* w) {
    w->blocked_s = 0.0;
    if (w->lingering) {  // blocked while shifting about: stand somewhere else near the spot
      w->goal = SwayGoal(w);
      return;
    }
    const bool had_spot = w->spot >= 0;
    ReleaseSpot(w);  // blocked on the way, or leaving: someone else may take it
    if (w->mode != Mode::kLeaving) {
      // A free linger spot if there is one (not the one just given up), else a random waypoint.
      std::vector<std::size_t> free;
      for (std::size_t i = 0; i < spot_taken.size() && !had_spot; ++i) {
        if (spot_taken[i] == 0) free.push_back(i);
      }
      if (free.empty()) {
        w->goal = RandomWaypoint(&w->rng);
        return;
      }
      const std::size_t i = free[w->rng.Index(free.size())];
      spot_taken[i] = 1;
      w->spot = static_cast<int>(i);
      w->goal = o.linger_spots[i];
      return;
    }
    if (InRoom(w->position, 0.0)) {
      w->goal = WallPoint(&w->rng, kExitDistanceM);
      return;
    }
    // Already out of the room: straight away from it.
    const Vec2 closest(std::clamp(w->position.x(), 0.0, o.room_width_m),
                       std::clamp(w->position.y(), 0.0, o.room_depth_m));
    const Vec2 out = w->position - closest;
    w->goal = w->position +
              kExitDistanceM * (out.norm() > 1e-9 ? Vec2(out.normalized()) : Vec2(0.0, -1.0));
  }

  void StepWalker(Walker* w, double dt) {
    GatherNeighbours(w->position);
    if (w->lingering) {
      w->linger_left_s -= dt;
      w->sway_left_s -= dt;
      if (w->linger_left_s <= 0.0) {
        ReleaseSpot(w);
        w->goal = RandomWaypoint(&w->rng);
      } else if (w->sway_left_s <= 0.0) {
        w->goal = SwayGoal(w);
        w->sway_left_s = w->rng.Uniform(kMinSwayS, kMaxSwayS);
      }
    }
    if (o.enter_and_leave && w->mode == Mode::kInside && !w->lingering) {
      w->stay_left_s -= dt;
      if (w->stay_left_s <= 0.0) {
        w->mode = Mode::kLeaving;
        w->pause_left_s = 0.0;
        NewGoal(w);
      }
    }
    const double amplitude_rate = std::min(1.0, dt / 0.25);
    if (w->pause_left_s > 0.0) {
      w->pause_left_s -= dt;
      w->velocity.setZero();
      w->amplitude -= w->amplitude * amplitude_rate;
      return;
    }
    Vec2 to_goal = w->goal - w->position;
    if (w->mode == Mode::kInside && w->spot >= 0 && !w->lingering &&
        to_goal.norm() < kArrivalRadiusM) {
      w->lingering = true;
      w->linger_left_s = w->rng.Uniform(0.5, 1.5) * o.mean_linger_s;
      w->sway_left_s = w->rng.Uniform(kMinSwayS, kMaxSwayS);
    }
    if (w->mode == Mode::kInside && !w->lingering && to_goal.norm() < kArrivalRadiusM) {
      const bool pause = w->rng.Bernoulli(o.pause_probability);
      const double pause_s = w->rng.Uniform(0.5, o.max_pause_s);
      NewGoal(w);
      if (pause) {
        w->pause_left_s = pause_s;
        w->velocity.setZero();
        return;
      }
      to_goal = w->goal - w->position;
    }
    const double distance = to_goal.norm();
    const Vec2 direction = distance > 1e-9
                               ? Vec2(to_goal / distance)
                               : Vec2(std::cos(w->heading_rad), std::sin(w->heading_rad));
    const double slowdown =
        w->mode == Mode::kInside ? std::min(1.0, distance / kSlowdownRadiusM) : 1.0;
    const double desired_speed = w->preferred_speed_mps * slowdown;
    const Vec2 desired = desired_speed * direction;

    // Social force (Helbing & Molnar 1995): exponential repulsion, anisotropic (people ahead
    // count more), plus a sidestep to the right of people ahead to break head-on symmetry.
    // (Scalar arithmetic: this loop is the simulator's inner loop.)
    double fx = 0.0, fy = 0.0;
    const double ex = direction.x(), ey = direction.y();  // right of the direction: (ey, -ex)
    for (const int j : neighbours) {
      const Walker* other = active[static_cast<std::size_t>(j)];
      if (other == w) continue;
      const double ax = w->position.x() - other->position.x();
      const double ay = w->position.y() - other->position.y();
      const double dist = std::sqrt(ax * ax + ay * ay);
      if (dist > kInteractionRadiusM || dist < 1e-9) continue;
      const double nx = ax / dist, ny = ay / dist;
      const double cos_ahead = -(nx * ex + ny * ey);
      const double anisotropy = 0.3 + 0.7 * 0.5 * (1.0 + cos_ahead);
      const double magnitude =
          kRepulsionMps * std::exp((o.min_separation_m - dist) / kRepulsionRangeM) * anisotropy;
      fx += magnitude * nx;
      fy += magnitude * ny;
      if (cos_ahead > 0.3) {
        fx += 0.6 * magnitude * ey;
        fy -= 0.6 * magnitude * ex;
      }
    }
    const Vec2 force(fx, fy);
    Vec2 target = desired + force;
    if (target.norm() > w->preferred_speed_mps) target *= w->preferred_speed_mps / target.norm();
    Vec2 dv = target - w->velocity;
    const double max_dv = kMaxAccelerationMps2 * dt;
    if (dv.norm() > max_dv) dv *= max_dv / dv.norm();
    const Vec2 wanted = w->velocity + dv;

    // Hard separation constraint: first admissible of the step, rotated steps, half-speed steps.
    static constexpr std::array<double, 9> kTurnsDeg = {0, -25, 25, -50, 50, -75, 75, -100, 100};
    Vec2 chosen = Vec2::Zero();
    bool moved = false;
    if (wanted.norm() > 1e-6) {
      for (const double scale : {1.0, 0.5}) {
        for (const double turn : kTurnsDeg) {
          const Vec2 v = scale * Rotate(wanted, turn * kPi / 180.0);
          if (Admissible(*w, w->position + v * dt)) {
            chosen = v;
            moved = true;
            break;
          }
        }
        if (moved) break;
      }
    }
    const Vec2 step = chosen * dt;
    w->position += step;
    w->velocity = chosen;

    // Blocked people (little progress towards the goal for too long) choose another goal.
    const double progress = distance > 1e-9 ? step.dot(to_goal) / distance : 0.0;
    if (desired_speed > 0.1 && progress < 0.25 * desired_speed * dt) {
      w->blocked_s += dt;
      if (w->blocked_s > kBlockedTimeoutS) NewGoal(w);
    } else {
      w->blocked_s = 0.0;
    }

    // Gait and facing.
    const double speed = chosen.norm();
    w->phase_rad =
        std::fmod(w->phase_rad + 2.0 * kPi * step.norm() / (0.8 * w->height_m), 2.0 * kPi);
    w->amplitude += (std::min(1.0, speed / 1.1) - w->amplitude) * amplitude_rate;
    if (speed > 0.05) {
      const double turn = WrapAngle(std::atan2(chosen.y(), chosen.x()) - w->heading_rad);
      const double max_turn = kMaxTurnRateRadps * dt;
      w->heading_rad = WrapAngle(w->heading_rad + std::clamp(turn, -max_turn, max_turn));
    }
    if (w->mode == Mode::kEntering && InRoom(w->position, kWallClearanceM)) {
      w->mode = Mode::kInside;
    }
  }

  void Spawn(Slot* slot, double dt) {
    slot->absence_left_s -= dt;
    if (slot->absence_left_s > 0.0) return;
    const Vec2 p = WallPoint(&population, kSpawnDistanceM);
    const double clear = o.min_separation_m + 0.2;
    for (const Slot& s : slots) {
      if (s.walker && (s.walker->position - p).norm() < clear) return;  // retry next sub-step
    }
    const Departed* returning = nullptr;
    if (o.reentry_probability > 0.0) {
      // Forget who has been away too long, then maybe bring back the longest-absent person
      // who has been away long enough.
      std::erase_if(departed, [&](const Departed& d) {
        return time_s - d.left_at_s > o.max_reentry_absence_s;
      });
      if (reentry.Uniform() < o.reentry_probability) {
        for (const Departed& d : departed) {
          if (time_s - d.left_at_s >= o.min_reentry_absence_s) {
            returning = &d;
            break;
          }
        }
      }
    }
    slot->walker = MakeWalker(p, Mode::kEntering, returning);
    if (returning != nullptr) {
      departed.erase(departed.begin() + (returning - departed.data()));
    }
  }

  void Substep(double dt) {
    if (o.enter_and_leave) {
      for (Slot& s : slots) {
        if (!s.walker) Spawn(&s, dt);
      }
    }
    BuildGrid();
    for (Walker* w : active) StepWalker(w, dt);
    time_s += dt;
    if (o.enter_and_leave) {
      for (Slot& s : slots) {
        if (s.walker && s.walker->mode == Mode::kLeaving &&
            OutsideDistance(s.walker->position) >= kDespawnDistanceM) {
          if (o.reentry_probability > 0.0) {
            departed.push_back({s.walker->id, s.walker->visits + 1, s.walker->height_m, time_s});
          }
          s.walker.reset();
          s.absence_left_s = population.Uniform(0.0, 2.0) * o.mean_absence_s;
        }
      }
    }
  }

  FrameTruth Truth() const {
    FrameTruth t;
    t.frame = frame;
    t.utime = FrameUtime(o, frame);
    for (const Slot& s : slots) {
      if (!s.walker || !InRoom(s.walker->position, 0.0)) continue;
      const Walker& w = *s.walker;
      BodyState body;
      body.footprint_m = Vec3(w.position.x(), w.position.y(), 0.0);
      body.heading_rad = w.heading_rad;
      body.height_m = w.height_m;
      body.walk_phase_rad = w.phase_rad;
      body.gait_amplitude = w.amplitude;
      PersonTruth p;
      p.id = w.id;
      p.footprint_m = body.footprint_m;
      const auto joints = Coco17Joints(body);
      p.joints_m.assign(joints.begin(), joints.end());
      p.head_top_m = HeadTop(body);
      p.velocity_mps = Vec3(w.frame_velocity.x(), w.frame_velocity.y(), 0.0);
      p.heading_rad = w.heading_rad;
      p.height_m = w.height_m;
      p.appearance = w.appearance;
      t.people.push_back(std::move(p));
    }
    std::sort(t.people.begin(), t.people.end(), [](const PersonTruth& a, const PersonTruth& b) {
      return a.id < b.id;
    });
    return t;
  }

  void Advance() {
    for (Slot& s : slots) {
      if (s.walker) s.walker->frame_start_position = s.walker->position;
    }
    for (int i = 0; i < substeps; ++i) Substep(substep_s);
    for (Slot& s : slots) {
      if (!s.walker) continue;
      s.walker->frame_velocity = (s.walker->position - s.walker->frame_start_position) * o.fps;
    }
    ++frame;
  }
};

std::vector<Vec3> BoxPoints(const PersonTruth& person) {
  return BoxPoints(person.joints_m, person.head_top_m, person.heading_rad, person.height_m);
}

Utime FrameUtime(const SceneOptions& options, FrameIndex frame) {
  return options.start_utime +
         static_cast<Utime>(std::llround(static_cast<double>(frame) * 1e6 / options.fps));
}

CrowdSimulator::CrowdSimulator(const SceneOptions& options)
    : state_(std::make_unique<State>(options)) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  state_->Initialize();
}

CrowdSimulator::~CrowdSimulator() = default;
CrowdSimulator::CrowdSimulator(CrowdSimulator&&) noexcept = default;
CrowdSimulator& CrowdSimulator::operator=(CrowdSimulator&&) noexcept = default;

FrameTruth CrowdSimulator::Next() {
  FrameTruth truth = state_->Truth();
  state_->Advance();
  return truth;
}

FrameIndex CrowdSimulator::next_frame() const { return state_->frame; }

std::vector<FrameTruth> SimulatePeople(const SceneOptions& options) {
  CrowdSimulator crowd(options);
  std::vector<FrameTruth> truth;
  truth.reserve(static_cast<std::size_t>(options.num_frames));
  for (int f = 0; f < options.num_frames; ++f) truth.push_back(crowd.Next());
  return truth;
}

}  // namespace mvtrack::sim
