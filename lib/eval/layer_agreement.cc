#include "eval/layer_agreement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace mvtrack::eval {
namespace {

// The q-quantile of sorted `v` (nearest rank below), NaN when empty.
double Quantile(const std::vector<double>& v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto i = static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1)));
  return v[i];
}

}  // namespace

double LayerAgreement::same_id_fraction() const {
  return provisional_track_frames > 0
             ? static_cast<double>(same_id) / static_cast<double>(provisional_track_frames)
             : 1.0;
}

double LayerAgreement::coverage() const {
  return final_track_frames > 0
             ? static_cast<double>(final_covered) / static_cast<double>(final_track_frames)
             : 1.0;
}

LayerAgreement CompareLayers(const EvalSequence& final_output, const EvalSequence& provisional) {
  LayerAgreement a;
  std::map<FrameIndex, const EvalFrame*> final_by_frame;
  for (const EvalFrame& f : final_output) {
    final_by_frame[f.frame] = &f;
    a.final_track_frames += static_cast<std::int64_t>(f.objects.size());
  }
  std::vector<double> distances;
  for (const EvalFrame& f : provisional) {
    a.provisional_track_frames += static_cast<std::int64_t>(f.objects.size());
    const auto it = final_by_frame.find(f.frame);
    if (it == final_by_frame.end()) continue;
    for (const EvalObject& p : f.objects) {
      for (const EvalObject& q : it->second->objects) {
        if (q.id != p.id) continue;
        ++a.same_id;
        distances.push_back((p.position.head<2>() - q.position.head<2>()).norm());
        break;
      }
    }
  }
  a.final_covered = a.same_id;  // ids are unique within a frame on both sides
  std::sort(distances.begin(), distances.end());
  a.median_distance_m = Quantile(distances, 0.5);
  a.p90_distance_m = Quantile(distances, 0.9);
  a.max_distance_m =
      distances.empty() ? std::numeric_limits<double>::quiet_NaN() : distances.back();
  return a;
}

}  // namespace mvtrack::eval
