#include "analytics/site_analytics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

#include "core/check.h"

namespace mvtrack::analytics {
namespace {

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double SegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double u = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + u * ab)).norm();
}

// Whether segments [a, b] and [c, d] share a point (touching counts).
bool SegmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const auto orientation = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    const double v = Cross(q - p, r - p);
    return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0);
  };
  const auto on_segment = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // r on [p, q]
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
  };
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

bool Finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// The time at which a quantity going from `before` (<= 0) at `t0` to `after` (> 0) at `t1`
// crossed zero, linearly.
double CrossingTime(double t0, double before, double t1, double after) {
  return t0 + (t1 - t0) * (-before) / (after - before);
}

}  // namespace

const char* ToString(Event::Kind kind) {
  switch (kind) {
    case Event::Kind::kEnter:
      return "enter";
    case Event::Kind::kExit:
      return "exit";
    case Event::Kind::kCrossing:
      return "crossing";
  }
  return "?";
}

const char* ToString(Event::Direction direction) {
  return direction == Event::Direction::kLeftToRight ? "left_to_right" : "right_to_left";
}

double SignedDistance(const std::vector<Vec2>& polygon, const Vec2& p) {
  double distance = std::numeric_limits<double>::infinity();
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    distance = std::min(distance, SegmentDistance(p, a, b));
    // Even-odd rule: a ray from p towards +x crosses edge (a, b).
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside ? distance : -distance;
}

std::optional<std::string> ValidateName(const std::string& name) {
  if (name.empty()) return "the name is empty";
  if (name.size() > static_cast<std::size_t>(kMaxNameLength)) {
    return "the name is longer than " + std::to_string(kMaxNameLength) + " characters";
  }
  for (const char c : name) {
    if (c < 0x20 || c > 0x7E) return "the name has a character that is not printable ASCII";
  }
  return std::nullopt;
}

std::optional<std::string> ValidatePolygon(const std::vector<Vec2>& p) {
  if (p.size() < 3) return "a polygon needs at least 3 vertices";
  if (p.size() > static_cast<std::size_t>(kMaxPolygonVertices)) {
    return "more than " + std::to_string(kMaxPolygonVertices) + " vertices";
  }
  double area2 = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!Finite(p[i])) return "vertex " + std::to_string(i) + " is not finite";
    area2 += Cross(p[i], p[(i + 1) % p.size()]);
  }
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      // Edges i and j share a vertex when adjacent: only the others may not meet.
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;
      if (SegmentsIntersect(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) {
        return "edges " + std::to_string(i) + " and " + std::to_string(j) +
               " cross (the polygon must be simple)";
      }
    }
  }
  if (!(std::abs(area2) > 1e-9)) return "the polygon has no area";
  return std::nullopt;
}

std::optional<std::string> ValidateSite(const Site& site) {
  const AnalyticsOptions& o = site.options;
  if (!(o.hysteresis_m >= 0.0 && o.hysteresis_m <= 100.0)) {
    return "hysteresis_m must be in [0, 100] metres";
  }
  if (!(o.hold_s >= 0.0 && o.hold_s <= 3600.0)) return "hold_s must be in [0, 3600] seconds";
  if (!(o.max_gap_s > 0.0 && o.max_gap_s <= 3600.0)) {
    return "max_gap_s must be in (0, 3600] seconds";
  }
  if (site.regions.size() > static_cast<std::size_t>(kMaxRegions)) {
    return "more than " + std::to_string(kMaxRegions) + " regions";
  }
  if (site.lines.size() > static_cast<std::size_t>(kMaxLines)) {
    return "more than " + std::to_string(kMaxLines) + " lines";
  }
  std::set<std::string> names;
  for (std::size_t r = 0; r < site.regions.size(); ++r) {
    const Region& region = site.regions[r];
    const std::string where = "regions[" + std::to_string(r) + "] '" + region.name + "': ";
    if (const std::optional<std::string> why = ValidateName(region.name)) {
      return "regions[" + std::to_string(r) + "]: " + *why;
    }
    if (!names.insert(region.name).second) return where + "another region has this name";
    if (const std::optional<std::string> why = ValidatePolygon(region.polygon)) {
      return where + *why;
    }
  }
  names.clear();
  for (std::size_t l = 0; l < site.lines.size(); ++l) {
    const Line& line = site.lines[l];
    const std::string where = "lines[" + std::to_string(l) + "] '" + line.name + "': ";
    if (const std::optional<std::string> why = ValidateName(line.name)) {
      return "lines[" + std::to_string(l) + "]: " + *why;
    }
    if (!names.insert(line.name).second) return where + "another line has this name";
    if (!Finite(line.from) || !Finite(line.to)) return where + "an end is not finite";
    if (!((line.to - line.from).norm() > 1e-6)) return where + "the line has no length";
  }
  return std::nullopt;
}

void SortEvents(std::vector<Event>* events) {
  std::stable_sort(events->begin(), events->end(), [](const Event& a, const Event& b) {
    return std::make_tuple(a.time_s, static_cast<int>(a.kind), a.region, a.line, a.track) <
           std::make_tuple(b.time_s, static_cast<int>(b.kind), b.region, b.line, b.track);
  });
}

SiteAnalytics::SiteAnalytics(Site site) : site_(std::move(site)) {
  const std::optional<std::string> why = ValidateSite(site_);
  MVTRACK_CHECK_MSG(!why, why ? why->c_str() : "");
  region_counts_.resize(site_.regions.size());
  line_counts_.resize(site_.lines.size());
}

// The one rule, for a region or a line: `d` is the signed distance now (a region: positive
// inside; a line: positive on its left), `confirmed` the side the track has. Returns true when a
// change of side has now held for hold_s; `crossed_now` (when given): whether the border was
// crossed towards the other side between the previous sample and this one.
bool SiteAnalytics::Step(SideState* state,
                         double d,
                         double previous_time_s,
                         double time_s,
                         bool first,
                         bool* crossed_now) const {
  const double half = 0.5 * site_.options.hysteresis_m;
  // Distances towards the side the track is not on: positive = past the border.
  const double e = state->confirmed ? -d : d;
  const double e_before = state->confirmed ? -state->last_distance : state->last_distance;
  state->last_distance = d;
  if (!state->pending) {
    if (e > 0.0 && (first || e_before <= 0.0)) {
      // When the border was crossed; a track appearing on the far side crossed "now".
      state->cross_time_s = first ? time_s : CrossingTime(previous_time_s, e_before, time_s, e);
      if (crossed_now != nullptr) *crossed_now = !first;
    }
    if (e > half) state->pending = true;
  } else if (e < -half) {
    state->pending = false;  // back past the band on its own side: not a change
  }
  // Held: past the band once, on the new side of the border now, for hold_s since crossing it.
  return state->pending && e > 0.0 && time_s - state->cross_time_s >= site_.options.hold_s;
}

void SiteAnalytics::Confirm(TrackId3D id,
                            std::size_t r,
                            SideState* state,
                            double time_s,
                            bool track_ended,
                            std::vector<Event>* events) {
  Event event;
  event.region = static_cast<int>(r);
  event.track = id;
  event.time_s = time_s;
  event.track_ended = track_ended;
  RegionCounts& counts = region_counts_[r];
  if (!state->confirmed) {
    event.kind = Event::Kind::kEnter;
    event.enter_time_s = time_s;
    state->enter_time_s = time_s;
    ++counts.occupancy;
    ++counts.entries;
  } else {
    event.kind = Event::Kind::kExit;
    event.enter_time_s = state->enter_time_s;
    --counts.occupancy;
    ++counts.exits;
  }
  state->confirmed = !state->confirmed;
  state->pending = false;
  events->push_back(event);
}

void SiteAnalytics::ConfirmCrossing(TrackId3D id,
                                    std::size_t l,
                                    SideState* state,
                                    std::vector<Event>* events) {
  if (state->counted) {
    Event event;
    event.kind = Event::Kind::kCrossing;
    event.line = static_cast<int>(l);
    event.track = id;
    event.time_s = state->cross_time_s;
    // Left of the line = positive: leaving the left is crossing to the right.
    event.direction =
        state->confirmed ? Event::Direction::kLeftToRight : Event::Direction::kRightToLeft;
    LineCounts& counts = line_counts_[l];
    ++(state->confirmed ? counts.left_to_right : counts.right_to_left);
    events->push_back(event);
  }
  state->confirmed = !state->confirmed;
  state->pending = false;
}

void SiteAnalytics::UpdateTrack(TrackId3D id,
                                TrackState* track,
                                const Vec2& floor,
                                double time_s,
                                bool first,
                                std::vector<Event>* events) {
  for (std::size_t r = 0; r < site_.regions.size(); ++r) {
    SideState& state = track->regions[r];
    const double d = SignedDistance(site_.regions[r].polygon, floor);
    if (Step(&state, d, track->last_seen_s, time_s, first)) {
      Confirm(id, r, &state, state.cross_time_s, /*track_ended=*/false, events);
    }
  }
  const double half = 0.5 * site_.options.hysteresis_m;
  for (std::size_t l = 0; l < site_.lines.size(); ++l) {
    SideState& state = track->lines[l];
    const Line& line = site_.lines[l];
    const Vec2 along = line.to - line.from;
    const double d = Cross(along, floor - line.from) / along.norm();
    if (!state.known) {
      // The first side: once out of the band (no crossing is counted for it).
      state.last_distance = d;
      if (std::abs(d) > half) {
        state.known = true;
        state.confirmed = d > 0.0;
      }
      continue;
    }
    bool crossed_now = false;
    const bool done = Step(&state, d, track->last_seen_s, time_s, /*first=*/false, &crossed_now);
    if (crossed_now) {
      // Counted only when the path crossed the segment itself, not the line beyond its ends.
      const double t = time_s > track->last_seen_s ? (state.cross_time_s - track->last_seen_s) /
                                                         (time_s - track->last_seen_s)
                                                   : 1.0;
      const Vec2 at = track->last_floor + t * (floor - track->last_floor);
      const double u = (at - line.from).dot(along) / along.squaredNorm();
      state.counted = u >= 0.0 && u <= 1.0;
    }
    if (done) ConfirmCrossing(id, l, &state, events);
  }
  track->last_floor = floor;
  track->last_seen_s = time_s;
}

void SiteAnalytics::EndTrack(TrackId3D id, TrackState* track, std::vector<Event>* events) {
  // A pending exit or crossing counts (the track did not come back); a pending entry does not
  // (a visit shorter than hold_s is no visit); an open visit ends where the track was last seen.
  for (std::size_t r = 0; r < site_.regions.size(); ++r) {
    SideState& state = track->regions[r];
    if (!state.confirmed) continue;
    if (state.pending) {
      Confirm(id, r, &state, state.cross_time_s, /*track_ended=*/false, events);
    } else {
      Confirm(id, r, &state, track->last_seen_s, /*track_ended=*/true, events);
    }
  }
  for (std::size_t l = 0; l < site_.lines.size(); ++l) {
    SideState& state = track->lines[l];
    if (state.known && state.pending) ConfirmCrossing(id, l, &state, events);
  }
}

std::vector<Event> SiteAnalytics::Update(double time_s, const std::vector<TrackPosition>& tracks) {
  std::vector<Event> events;
  if (!std::isfinite(time_s) || (last_time_s_ && time_s < *last_time_s_)) {
    ++ignored_messages_;
    return events;
  }
  last_time_s_ = time_s;
  // Tracks not seen for max_gap_s have ended.
  const auto ended = [&](const std::pair<TrackId3D, TrackState>& entry) {
    return time_s - entry.second.last_seen_s > site_.options.max_gap_s;
  };
  for (auto& entry : tracks_) {
    if (ended(entry)) EndTrack(entry.first, &entry.second, &events);
  }
  std::erase_if(tracks_, ended);
  // This message's tracks, by id (a repeated id or a non-finite position is skipped).
  std::vector<const TrackPosition*> order;
  order.reserve(tracks.size());
  for (const TrackPosition& t : tracks) {
    if (Finite(t.floor)) order.push_back(&t);
  }
  std::stable_sort(order.begin(), order.end(), [](const TrackPosition* a, const TrackPosition* b) {
    return a->id < b->id;
  });
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && order[i]->id == order[i - 1]->id) continue;
    const TrackId3D id = order[i]->id;
    auto it = std::lower_bound(
        tracks_.begin(), tracks_.end(), id, [](const auto& entry, TrackId3D wanted) {
          return entry.first < wanted;
        });
    const bool first = it == tracks_.end() || it->first != id;
    if (first) {
      TrackState state;
      state.regions.resize(site_.regions.size());
      state.lines.resize(site_.lines.size());
      state.last_seen_s = time_s;
      state.last_floor = order[i]->floor;
      it = tracks_.insert(it, {id, std::move(state)});
    }
    UpdateTrack(id, &it->second, order[i]->floor, time_s, first, &events);
  }
  SortEvents(&events);
  return events;
}

std::vector<Event> SiteAnalytics::Finish() {
  std::vector<Event> events;
  for (auto& [id, track] : tracks_) EndTrack(id, &track, &events);
  tracks_.clear();
  SortEvents(&events);
  return events;
}

}  // namespace mvtrack::analytics
