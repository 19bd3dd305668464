#pragma once
/// @file
/// People motion of the synthetic scene: people walking between random waypoints in a room,
/// avoiding each other, optionally entering and leaving. Produces the per-frame ground truth.
/// CrowdSimulator is a single-owner, single-threaded object; everything else is stateless.

#include <cstdint>
#include <memory>
#include <vector>

#include "core/types.h"
#include "sim/appearance.h"
#include "sim/body.h"
#include "sim/scene_options.h"

namespace mvtrack::sim {

/// Ground truth of one person at one frame.
struct PersonTruth {
  /// Unique per person. A person entering again gets a new id, except a re-entry
  /// (SceneOptions::reentry_probability), which keeps the id it had.
  int id = 0;
  Vec3 footprint_m = Vec3::Zero();   ///< ground point under the pelvis (z = 0), world frame
  std::vector<Vec3> joints_m;        ///< 17 COCO joints (core::KeypointLayoutId::kCoco17), world
  Vec3 head_top_m = Vec3::Zero();    ///< top of the head, world
  Vec3 velocity_mps = Vec3::Zero();  ///< footprint velocity over the last frame (z = 0)
  double heading_rad = 0.0;          ///< facing direction, counter-clockwise from world +x
  double height_m = 0.0;             ///< standing height
  /// Its appearance (SceneOptions::embedding_dim > 0), else null. Shared, immutable.
  std::shared_ptr<const PersonAppearance> appearance;
};

/// Ground truth of one frame.
struct FrameTruth {
  FrameIndex frame = 0;
  Utime utime = 0;                  ///< µs
  std::vector<PersonTruth> people;  ///< sorted by id; only people inside the room [0,W]x[0,D]
};

/// The box-bounding points of `person` (see BoxPoints in body.h).
std::vector<Vec3> BoxPoints(const PersonTruth& person);

/// utime of `frame` under `options`: start_utime + round(frame * 1e6 / fps).
Utime FrameUtime(const SceneOptions& options, FrameIndex frame);

/// Simulates the people of a scene frame by frame (O(people) per frame with a neighbour grid;
/// memory independent of the number of frames, so it suits arbitrarily long runs).
///
/// Walk model: each person walks at a preferred speed (uniform in [min_speed_mps,
/// max_speed_mps]) towards a random waypoint at least waypoint_margin_m from the walls, slowing
/// down within 0.6 m of it; on arrival picks a new waypoint, pausing first with probability
/// pause_probability. Steering follows the social-force model (Helbing & Molnar 1995): an
/// exponential repulsion from people within 2 m (weighted towards people ahead) plus a sidestep to
/// the right of people ahead; accelerations are limited to 3 m/s^2 and turning of the body to
/// 6 rad/s. A hard constraint then guarantees the separation: a step that would bring the person
/// within min_separation_m of anyone, or out of its region (people walking in the room keep
/// 0.2 m from the walls; entering people do not turn back once in the room, leaving people do
/// not come back once out), is replaced by the first admissible of the step rotated by
/// +-25/50/75/100 deg, then the same at half speed, else the person waits. People blocked for
/// more than 2 s pick a new goal. The motion is integrated with sub-steps of at most 50 ms, so a
/// step (< 0.15 m) can never jump over another person.
///
/// enter_and_leave: each of the num_people slots starts occupied (the first half, rounded up) or
/// empty; an empty slot waits U[0, 2] x mean_absence_s, then a new person (next id) appears
/// 0.5 m outside a random point of the walls (at least 0.5 m from the corners) as soon as that
/// spot is free, and walks in to a random waypoint; after U[0.5, 1.5] x mean_stay_s in the room
/// the person walks to a point 0.8 m outside a random wall and vanishes 0.4 m outside the room.
/// People outside the room take part in the avoidance but are not in the truth.
class CrowdSimulator {
 public:
  /// `options` must be valid (checked).
  explicit CrowdSimulator(const SceneOptions& options);
  /// Movable, not copyable.
  ~CrowdSimulator();
  CrowdSimulator(CrowdSimulator&&) noexcept;
  CrowdSimulator& operator=(CrowdSimulator&&) noexcept;

  /// The truth of frame next_frame(), then advances the simulation by one frame (1 / fps).
  /// Frames are numbered from 0 and are not limited by options.num_frames.
  FrameTruth Next();
  /// Index of the frame the next call to Next() returns.
  FrameIndex next_frame() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The truth of frames 0..options.num_frames-1 (people motion only; no cameras or detections).
std::vector<FrameTruth> SimulatePeople(const SceneOptions& options);

}  // namespace mvtrack::sim
