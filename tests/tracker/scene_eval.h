#pragma once
// Scores a Tracker run against a simulated scene's ground truth (test support only).

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "core/linear_assignment.h"
#include "sim/synthetic_scene.h"
#include "tracker/tracker.h"

namespace mvtrack::testing {

struct SceneScore {
  int gt_instances = 0;  ///< (frame, person) pairs in the scored frames
  int matched = 0;       ///< matched within the gate
  int false_tracks = 0;  ///< track instances matched to nobody
  int id_switches = 0;   ///< a person's matched track id changed
  std::map<int, std::set<TrackId3D>> ids_of_person;
  double mean_position_error_m = 0.0;
  double mean_joint_error_m = 0.0;  ///< pose mode: mean over valid joints (MPJPE)
  int frames_output = 0;
};

/// Per frame, matches persons to tracks by footprint distance (Hungarian, gate `gate_m`), and
/// accumulates identity consistency and errors over frames >= first_scored_frame.
inline SceneScore ScoreRun(const sim::Scene& scene,
                           const std::vector<tracker::Frame3D>& frames,
                           FrameIndex first_scored_frame,
                           double gate_m = 0.5) {
  SceneScore s;
  std::map<FrameIndex, const tracker::Frame3D*> by_frame;
  for (const auto& f : frames) by_frame[f.frame] = &f;
  s.frames_output = static_cast<int>(frames.size());
  std::map<int, TrackId3D> last_id;
  double pos_sum = 0.0, joint_sum = 0.0;
  int joint_n = 0;
  for (const sim::FrameTruth& truth : scene.truth) {
    if (truth.frame < first_scored_frame) continue;
    auto it = by_frame.find(truth.frame);
    static const std::vector<tracker::Track3D> kNone;
    const std::vector<tracker::Track3D>& tracks = it == by_frame.end() ? kNone : it->second->tracks;
    Eigen::MatrixXd cost(static_cast<Eigen::Index>(truth.people.size()),
                         static_cast<Eigen::Index>(tracks.size()));
    for (std::size_t p = 0; p < truth.people.size(); ++p) {
      for (std::size_t t = 0; t < tracks.size(); ++t) {
        Vec3 gt = truth.people[p].footprint_m;
        Vec3 est = tracks[t].position;
        gt.z() = 0.0;
        est.z() = 0.0;
        cost(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(t)) = (gt - est).norm();
      }
    }
    const core::Assignment a = core::SolveAssignment(cost, gate_m);
    s.gt_instances += static_cast<int>(truth.people.size());
    s.matched += static_cast<int>(a.matches.size());
    s.false_tracks += static_cast<int>(a.unmatched_cols.size());
    for (const auto& [p, t] : a.matches) {
      const auto& person = truth.people[static_cast<std::size_t>(p)];
      const auto& track = tracks[static_cast<std::size_t>(t)];
      s.ids_of_person[person.id].insert(track.id);
      auto last = last_id.find(person.id);
      if (last != last_id.end() && last->second != track.id) ++s.id_switches;
      last_id[person.id] = track.id;
      pos_sum += cost(p, t);
      for (std::size_t j = 0; j < track.joints.size() && j < person.joints_m.size(); ++j) {
        if (!track.joints[j]) continue;
        joint_sum += (*track.joints[j] - person.joints_m[j]).norm();
        ++joint_n;
      }
    }
  }
  s.mean_position_error_m = s.matched > 0 ? pos_sum / s.matched : 0.0;
  s.mean_joint_error_m = joint_n > 0 ? joint_sum / joint_n : 0.0;
  return s;
}

/// Runs a whole scene through a tracker (all cameras of a frame, in the given camera order).
inline std::vector<tracker::Frame3D> RunScene(tracker::Tracker* t,
                                              const sim::Scene& scene,
                                              bool reverse_camera_order = false) {
  std::vector<tracker::Frame3D> out;
  for (const auto& cams : scene.detections) {
    std::vector<const core::CameraFrame*> order;
    for (const auto& cf : cams) order.push_back(&cf);
    if (reverse_camera_order) std::reverse(order.begin(), order.end());
    for (const core::CameraFrame* cf : order) {
      tracker::AddResult r = t->Add(*cf);
      for (auto& f : r.finalized) out.push_back(std::move(f));
    }
  }
  for (auto& f : t->Flush()) out.push_back(std::move(f));
  return out;
}

}  // namespace mvtrack::testing
