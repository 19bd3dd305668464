#include "stitch/stitcher.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "core/check.h"
#include "core/linear_assignment.h"

namespace mvtrack::stitch {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Rule 3: an open zone track takes a global track from the same zone's track only when it is
// nearer the other zones' tracks by at least this much (metres).
constexpr double kContestMarginM = 0.2;

bool Finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// Floor distance of two footprints; +infinity when either is not finite.
double FloorDistance(const Vec3& a, const Vec3& b) {
  if (!Finite(a) || !Finite(b)) return kInf;
  return (a.head<2>() - b.head<2>()).norm();
}

// One zone track present in the site frame.
struct Entry {
  int zone = 0;
  const tracker::Track3D* track = nullptr;
  TrackId3D global = 0;  // 0: not joined (yet)
};

// A global track present in the site frame: its entries and mean footprint.
struct Present {
  std::vector<int> entries;  // indices into the entries, zone order
  Vec3 position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  bool HasZone(const std::vector<Entry>& all, int zone) const {
    return std::any_of(entries.begin(), entries.end(), [&](int e) { return all[e].zone == zone; });
  }
};

Vec3 MeanPosition(const std::vector<Entry>& all, const std::vector<int>& entries) {
  Vec3 sum = Vec3::Zero();
  int n = 0;
  for (const int e : entries) {
    if (!Finite(all[e].track->position)) continue;
    sum += all[e].track->position;
    ++n;
  }
  return n > 0 ? Vec3(sum / n) : Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
}

}  // namespace

std::vector<ZoneFrames> AlignZoneFrames(const std::vector<std::vector<tracker::Frame3D>>& zones,
                                        Utime tolerance_us) {
  MVTRACK_CHECK(tolerance_us > 0);
  for (const std::vector<tracker::Frame3D>& frames : zones) {
    for (std::size_t i = 1; i < frames.size(); ++i) {
      MVTRACK_CHECK_MSG(frames[i].utime > frames[i - 1].utime, "zone frames out of order");
    }
  }
  std::vector<std::size_t> next(zones.size(), 0);
  std::vector<ZoneFrames> groups;
  while (true) {
    std::optional<Utime> open;
    for (std::size_t z = 0; z < zones.size(); ++z) {
      if (next[z] < zones[z].size() && (!open || zones[z][next[z]].utime < *open)) {
        open = zones[z][next[z]].utime;
      }
    }
    if (!open) break;
    ZoneFrames group(zones.size(), nullptr);
    for (std::size_t z = 0; z < zones.size(); ++z) {
      if (next[z] < zones[z].size() && zones[z][next[z]].utime - *open < tolerance_us) {
        group[z] = &zones[z][next[z]++];
      }
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

std::optional<Utime> HalfFramePeriod(const std::vector<tracker::Frame3D>& frames) {
  if (frames.size() < 2) return std::nullopt;
  std::vector<Utime> steps;
  steps.reserve(frames.size() - 1);
  for (std::size_t i = 1; i < frames.size(); ++i) {
    steps.push_back(frames[i].utime - frames[i - 1].utime);
  }
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return std::max<Utime>(1, *mid / 2);
}

Stitcher::Stitcher(std::vector<std::string> zone_names,
                   const linking::LinkerOptions& linker,
                   TrackId3D first_id)
    : num_zones_(static_cast<int>(zone_names.size())),
      zone_names_(std::move(zone_names)),
      linker_(linker),
      next_id_(first_id) {
  MVTRACK_CHECK(num_zones_ >= 1);
  for (const std::string& name : zone_names_)
    MVTRACK_CHECK_MSG(!name.empty(), "a zone needs a name");
  MVTRACK_CHECK(first_id >= 1);
  std::string why;
  MVTRACK_CHECK_MSG(linker_.Validate(&why), why.c_str());
}

double Stitcher::Seconds(Utime from, Utime to) const {
  return static_cast<double>(to - from) * 1e-6;
}

SiteFrame Stitcher::Stitch(const ZoneFrames& zone_frames) {
  MVTRACK_CHECK(static_cast<int>(zone_frames.size()) == num_zones_);
  const tracker::Frame3D* first = nullptr;
  for (const tracker::Frame3D* f : zone_frames) {
    if (f != nullptr && (first == nullptr || f->utime < first->utime)) first = f;
  }
  MVTRACK_CHECK_MSG(first != nullptr, "a site frame needs a zone frame");
  const Utime now = first->utime;
  MVTRACK_CHECK_MSG(!last_utime_ || now > *last_utime_, "site frames out of order");
  last_utime_ = now;
  ++stats_.frames;

  // Rule 1: joined zone tracks keep their global id.
  std::vector<Entry> entries;
  for (int z = 0; z < num_zones_; ++z) {
    if (zone_frames[z] == nullptr) continue;
    for (const tracker::Track3D& t : zone_frames[z]->tracks) {
      Entry e{z, &t, 0};
      if (const auto it = joins_.find({z, t.id}); it != joins_.end()) e.global = it->second.global;
      entries.push_back(e);
    }
  }
  // One zone track per zone and global track (a merge can leave two joins of one zone): the
  // earliest joined stays, the others leave.
  {
    std::map<std::pair<int, TrackId3D>, std::size_t> kept;  // (zone, global) -> entry
    const auto order = [&](std::size_t e) {
      return joins_.at({entries[e].zone, entries[e].track->id}).order;
    };
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (entries[i].global == 0) continue;
      const auto [it, first_of_pair] = kept.try_emplace({entries[i].zone, entries[i].global}, i);
      if (first_of_pair) continue;
      std::size_t later = i;
      if (order(i) < order(it->second)) std::swap(later, it->second);
      joins_.erase({entries[later].zone, entries[later].track->id});
      entries[later].global = 0;
    }
  }
  auto present_globals = [&] {
    std::map<TrackId3D, Present> present;
    for (int i = 0; i < static_cast<int>(entries.size()); ++i) {
      if (entries[i].global != 0) present[entries[i].global].entries.push_back(i);
    }
    for (auto& [id, p] : present) p.position = MeanPosition(entries, p.entries);
    return present;
  };

  // Rule 2: a join whose track disagrees with the global track's oldest join leaves.
  {
    const std::map<TrackId3D, Present> present = present_globals();
    for (const auto& [id, p] : present) {
      if (p.entries.size() < 2) continue;
      int oldest = p.entries.front();
      for (const int e : p.entries) {
        if (joins_.at({entries[e].zone, entries[e].track->id}).order <
            joins_.at({entries[oldest].zone, entries[oldest].track->id}).order) {
          oldest = e;
        }
      }
      for (const int e : p.entries) {
        if (e == oldest) continue;
        const Vec3& at = entries[e].track->position;
        const double own = FloorDistance(at, entries[oldest].track->position);
        double other = kInf;  // the nearest global track its zone does not see
        for (const auto& [other_id, q] : present) {
          if (other_id != id && !q.HasZone(entries, entries[e].zone)) {
            other = std::min(other, FloorDistance(at, q.position));
          }
        }
        const bool disagrees = own > 2.0 * linking::kSamePersonApartM ||
                               (other <= linking::kSamePersonApartM && other < own);
        Join& join = joins_.at({entries[e].zone, entries[e].track->id});
        join.far_frames = disagrees ? join.far_frames + 1 : 0;
        if (join.far_frames >= kSplitFrames) {
          joins_.erase({entries[e].zone, entries[e].track->id});
          entries[e].global = 0;
          ++stats_.splits;
        }
      }
    }
  }

  auto join = [&](int e, TrackId3D global) {
    const int zone = entries[e].zone;
    // One zone track per zone and global track: an earlier one of this zone (unseen now) leaves.
    for (auto it = joins_.begin(); it != joins_.end();) {
      it = (it->first.first == zone && it->second.global == global) ? joins_.erase(it)
                                                                    : std::next(it);
    }
    joins_[{zone, entries[e].track->id}] = Join{global, next_order_++, 0, now};
    entries[e].global = global;
  };

  // Rules 3-5, zone by zone.
  for (int z = 0; z < num_zones_; ++z) {
    std::vector<int> open;
    for (int i = 0; i < static_cast<int>(entries.size()); ++i) {
      if (entries[i].zone == z && entries[i].global == 0) open.push_back(i);
    }
    if (open.empty()) continue;
    // Rule 3: the global tracks other zones see now, within kSamePersonApartM; and those whose
    // track of this zone is clearly farther from the other zones' tracks than the open one
    // (contested: the zone has two tracks there, the wrong one joined first).
    const std::map<TrackId3D, Present> present = present_globals();
    std::vector<TrackId3D> candidates;
    std::vector<Vec3> reference;  // per candidate: the other zones' mean footprint
    std::vector<int> holder;      // per candidate: its entry of this zone, or -1
    for (const auto& [id, p] : present) {
      std::vector<int> others;
      int mine = -1;
      for (const int e : p.entries) {
        if (entries[e].zone == z) {
          mine = e;
        } else {
          others.push_back(e);
        }
      }
      if (others.empty()) continue;
      candidates.push_back(id);
      reference.push_back(mine < 0 ? p.position : MeanPosition(entries, others));
      holder.push_back(mine);
    }
    if (!candidates.empty()) {
      Eigen::MatrixXd cost(open.size(), candidates.size());
      for (std::size_t r = 0; r < open.size(); ++r) {
        for (std::size_t c = 0; c < candidates.size(); ++c) {
          double d = FloorDistance(entries[open[r]].track->position, reference[c]);
          if (holder[c] >= 0 &&
              !(d + kContestMarginM <
                FloorDistance(entries[holder[c]].track->position, reference[c]))) {
            d = kInf;
          }
          cost(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = d;
        }
      }
      const core::Assignment a = core::SolveAssignment(cost, linking::kSamePersonApartM);
      for (const auto& [r, c] : a.matches) {
        if (holder[static_cast<std::size_t>(c)] >= 0) {
          const int displaced = holder[static_cast<std::size_t>(c)];
          joins_.erase({entries[displaced].zone, entries[displaced].track->id});
          entries[displaced].global = 0;
          open.push_back(displaced);
          ++stats_.splits;
        }
        join(open[static_cast<std::size_t>(r)], candidates[static_cast<std::size_t>(c)]);
        ++stats_.joined_overlap;
      }
    }
    // Rule 4: re-identification by motion of a global track another zone lost.
    if (linker_.reid_gate_chi2 > 0.0) {
      std::vector<int> rest;
      for (const int e : open) {
        if (entries[e].global == 0 && Finite(entries[e].track->position)) rest.push_back(e);
      }
      const std::map<TrackId3D, Present> seen = present_globals();
      std::vector<TrackId3D> lost;
      for (const auto& [id, g] : globals_) {
        if (g.moving && seen.count(id) == 0 &&
            Seconds(g.last_seen, now) <= linker_.max_reid_gap_s &&
            std::find(g.last_zones.begin(), g.last_zones.end(), z) == g.last_zones.end()) {
          lost.push_back(id);
        }
      }
      if (!rest.empty() && !lost.empty()) {
        Eigen::MatrixXd d2(rest.size(), lost.size());
        for (std::size_t r = 0; r < rest.size(); ++r) {
          const linking::FloorMotion start = linking::FloorMotion::Start(
              entries[rest[r]].track->position.head<2>(), linker_.motion);
          for (std::size_t c = 0; c < lost.size(); ++c) {
            const Global& g = globals_.at(lost[c]);
            linking::FloorMotion predicted = g.motion;
            predicted.Predict(Seconds(g.motion_utime, now), linker_.motion);
            d2(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
                linking::StateDistanceSquared(predicted, start);
          }
        }
        for (Eigen::Index r = 0; r < d2.rows(); ++r) {
          Eigen::Index c = 0;
          const double best = d2.row(r).minCoeff(&c);
          if (!(best <= linker_.reid_gate_chi2) ||
              !linking::UnambiguousMinimum(d2, r, c, linker_.reid_margin_chi2)) {
            continue;
          }
          join(rest[static_cast<std::size_t>(r)], lost[static_cast<std::size_t>(c)]);
          ++stats_.joined_motion;
        }
      }
    }
    // Rule 5: births.
    for (const int e : open) {
      if (entries[e].global != 0) continue;
      const TrackId3D id = next_id_++;
      ++stats_.global_ids;
      Global g;
      g.first_frame = first->frame;
      globals_[id] = g;
      join(e, id);
    }
  }

  // Rule 6: global tracks of disjoint zones at one place in consecutive frames merge.
  {
    std::map<TrackId3D, Present> present = present_globals();
    std::map<std::pair<TrackId3D, TrackId3D>, int> close;
    std::vector<std::pair<TrackId3D, TrackId3D>> merge;
    for (auto a = present.begin(); a != present.end(); ++a) {
      for (auto b = std::next(a); b != present.end(); ++b) {
        if (!(FloorDistance(a->second.position, b->second.position) <=
              linking::kSamePersonApartM)) {
          continue;
        }
        bool disjoint = true;
        for (const int e : b->second.entries) {
          if (a->second.HasZone(entries, entries[e].zone)) disjoint = false;
        }
        if (!disjoint) continue;
        const auto key = std::make_pair(a->first, b->first);
        const auto it = close_pairs_.find(key);
        const int n = (it == close_pairs_.end() ? 0 : it->second) + 1;
        close[key] = n;
        if (n >= kSplitFrames) merge.push_back(key);
      }
    }
    close_pairs_ = std::move(close);
    std::vector<TrackId3D> merged;  // each global merges at most once per frame
    for (const auto& [older, younger] : merge) {
      if (std::find(merged.begin(), merged.end(), older) != merged.end() ||
          std::find(merged.begin(), merged.end(), younger) != merged.end()) {
        continue;
      }
      merged.push_back(older);
      merged.push_back(younger);
      for (Entry& e : entries) {
        if (e.global == younger) e.global = older;
      }
      for (auto& [key, j] : joins_) {
        if (j.global == younger) j = Join{older, next_order_++, 0, j.last_seen};
      }
      globals_.erase(younger);
      ++stats_.merges;
    }
  }

  // Output and state.
  SiteFrame out;
  out.frame.frame = first->frame;
  out.frame.utime = now;
  out.frame.zones = zone_names_;
  for (const auto& [id, p] : present_globals()) {
    Global& g = globals_.at(id);
    tracker::Track3D t;
    t.id = id;
    t.position = p.position;
    std::vector<int> zones;
    const tracker::Track3D* oldest = nullptr;
    std::int64_t oldest_order = std::numeric_limits<std::int64_t>::max();
    std::size_t joints = 0;
    for (const int e : p.entries) {
      const tracker::Track3D& zt = *entries[e].track;
      Join& j = joins_.at({entries[e].zone, zt.id});
      j.last_seen = now;
      if (j.order < oldest_order) {
        oldest_order = j.order;
        oldest = &zt;
      }
      zones.push_back(entries[e].zone);
      t.confidence = std::max(t.confidence, zt.confidence);
      t.cameras.insert(t.cameras.end(), zt.cameras.begin(), zt.cameras.end());
      joints = std::max(joints, zt.joints.size());
    }
    std::sort(t.cameras.begin(), t.cameras.end());
    t.cameras.erase(std::unique(t.cameras.begin(), t.cameras.end()), t.cameras.end());
    if (joints > 0) {
      t.joints.resize(joints);
      for (std::size_t j = 0; j < joints; ++j) {
        Vec3 sum = Vec3::Zero();
        int n = 0;
        for (const int e : p.entries) {
          const tracker::Track3D& zt = *entries[e].track;
          if (j < zt.joints.size() && zt.joints[j]) {
            sum += *zt.joints[j];
            ++n;
          }
        }
        if (n > 0) t.joints[j] = Vec3(sum / n);
      }
    }
    t.bone_lengths = oldest->bone_lengths;
    t.age_frames = std::max<FrameIndex>(0, first->frame - g.first_frame);
    t.state = linking::TrackState::kConfirmed;
    if (zones.size() > 1) ++stats_.multi_zone_track_frames;
    if (Finite(t.position)) {
      const Vec2 xy = t.position.head<2>();
      if (!g.moving) {
        g.motion = linking::FloorMotion::Start(xy, linker_.motion);
        g.moving = true;
      } else {
        g.motion.Predict(Seconds(g.motion_utime, now), linker_.motion);
        g.motion.Update(xy, linker_.motion);
      }
      g.motion_utime = now;
    }
    g.last_seen = now;
    std::sort(zones.begin(), zones.end());
    g.last_zones = zones;
    t.zones = std::move(zones);
    out.frame.tracks.push_back(std::move(t));
  }

  // Forget what has not been seen for max_lost_s.
  for (auto it = joins_.begin(); it != joins_.end();) {
    it = Seconds(it->second.last_seen, now) > linker_.max_lost_s ? joins_.erase(it) : std::next(it);
  }
  for (auto it = globals_.begin(); it != globals_.end();) {
    it = Seconds(it->second.last_seen, now) > linker_.max_lost_s ? globals_.erase(it)
                                                                 : std::next(it);
  }
  return out;
}

}  // namespace mvtrack::stitch
