#include "eval/bone_lengths.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace mvtrack::eval {

BoneLengthStability EvaluateBoneLengths(const EvalSequence& predictions,
                                        const core::KeypointLayout& layout,
                                        int min_frames,
                                        const std::vector<FrameRange>& frame_ranges) {
  BoneLengthStability out;
  out.min_frames = min_frames;
  const auto index = [&](const std::string& name) { return core::JointIndex(layout, name); };
  std::vector<std::pair<int, int>> limbs;
  for (const char* side : {"l_", "r_"}) {
    for (const auto& [a, b] : {std::pair<const char*, const char*>{"shoulder", "elbow"},
                               {"elbow", "wrist"},
                               {"hip", "knee"},
                               {"knee", "ankle"}}) {
      const int ia = index(side + std::string(a)), ib = index(side + std::string(b));
      if (ia < 0 || ib < 0) continue;
      limbs.emplace_back(ia, ib);
      out.limbs.push_back(side + std::string(a) + "-" + side + b);
    }
  }
  // Per track: frames, and per limb the sum and sum of squares of its lengths minus its first
  // length (the shifted-data variance: no cancellation for a constant length).
  struct Sums {
    int frames = 0;
    std::vector<int> n;
    std::vector<double> shift, sum, sum2;
  };
  std::map<std::int64_t, Sums> tracks;
  for (const EvalFrame& frame : predictions) {
    if (!InFrameRanges(frame.frame, frame_ranges)) continue;
    for (const EvalObject& o : frame.objects) {
      Sums& s = tracks[o.id];
      if (s.n.empty()) {
        s.n.assign(limbs.size(), 0);
        s.shift.assign(limbs.size(), 0.0);
        s.sum.assign(limbs.size(), 0.0);
        s.sum2.assign(limbs.size(), 0.0);
      }
      ++s.frames;
      for (std::size_t l = 0; l < limbs.size(); ++l) {
        const auto a = static_cast<std::size_t>(limbs[l].first);
        const auto b = static_cast<std::size_t>(limbs[l].second);
        if (a >= o.joints.size() || b >= o.joints.size() || !o.joints[a] || !o.joints[b]) continue;
        const double length = (*o.joints[a] - *o.joints[b]).norm();
        if (s.n[l] == 0) s.shift[l] = length;
        ++s.n[l];
        s.sum[l] += length - s.shift[l];
        s.sum2[l] += (length - s.shift[l]) * (length - s.shift[l]);
      }
    }
  }
  for (const auto& [id, s] : tracks) {
    if (s.frames < min_frames) continue;
    BoneLengthTrack t;
    t.id = id;
    t.num_frames = s.frames;
    int counted = 0;
    for (std::size_t l = 0; l < limbs.size(); ++l) {
      if (s.n[l] < 2) continue;
      const double shifted_mean = s.sum[l] / s.n[l];
      const double mean = s.shift[l] + shifted_mean;
      if (!(mean > 0.0)) continue;
      const double variance = std::max(0.0, s.sum2[l] / s.n[l] - shifted_mean * shifted_mean);
      const double cv = std::sqrt(variance) / mean;
      t.cv_mean += cv;
      t.cv_max = std::max(t.cv_max, cv);
      ++counted;
    }
    if (counted == 0) continue;
    t.cv_mean /= counted;
    out.tracks.push_back(t);
  }
  for (const BoneLengthTrack& t : out.tracks) {
    out.cv_mean += t.cv_mean / static_cast<double>(out.tracks.size());
    out.cv_worst_track = std::max(out.cv_worst_track, t.cv_mean);
    out.cv_max = std::max(out.cv_max, t.cv_max);
  }
  out.protocol =
      "per predicted track with >= " + std::to_string(min_frames) +
      " frames in the evaluated ranges, the coefficient of variation (std / mean) of each limb's "
      "length over the frames where both its joints are present (limbs: upper and lower arms "
      "and legs found in the layout by joint name; a limb needs >= 2 frames), cv_mean = mean "
      "over the limbs; summary: mean over tracks, the worst track's cv_mean, the largest limb "
      "CV.";
  return out;
}

}  // namespace mvtrack::eval
