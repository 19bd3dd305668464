#include "tracker/window_finalizer.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <optional>
#include <utility>

#include "core/check.h"

namespace mvtrack::tracker {
namespace {

// Gaps of tracks younger than this (seconds from their first frame to the frame that ends the
// gap) are not bridged: short-lived tracks are mostly duplicates or ghosts, whose gaps are their
// absence (docs/ACCURACY.md "Bridging short gaps": 1.0 s loses the Campus hard level's gain, 0 adds
// false positives on the 16-camera store).
constexpr double kBridgeMinAgeS = 0.5;

// The linker's view of the scene: the footprint joints (FootprintPoints).
linking::LinkerContext MakeLinkerContext(const TrackerOptions& options) {
  linking::LinkerContext context;
  context.footprint_points = FootprintPoints(options);
  return context;
}

// The linker's options: the wait of fragment births and the merge of one person linked twice
// are box-mode rules (LinkerOptions::fragment_births_wait, merge_linked_duplicates; in pose
// mode each costs Campus at the hard corruption level a person's frames and gains nothing,
// docs/DECISIONS.md "Window linking").
linking::LinkerOptions MakeLinkerOptions(const TrackerOptions& options) {
  linking::LinkerOptions o = options.linking;
  if (options.mode != InputMode::kBoxes) {
    o.fragment_births_wait = false;
    o.merge_linked_duplicates = false;
  }
  return o;
}

}  // namespace

WindowFinalizer::WindowFinalizer(const geometry::CameraRig& rig, const TrackerOptions& options)
    : mode_(options.mode),
      ground_height_m_(options.ground_height_m),
      num_points_(NumPoints(options)),
      linker_(MakeLinkerOptions(options), MakeLinkerContext(options), options.appearance),
      bridge_max_gap_s_(options.bridge_max_gap_s),
      fit_skeleton_(options.mode == InputMode::kPoses && options.refinement.fit_skeleton) {
  if (!fit_skeleton_) return;
  for (int c = 0; c < rig.size(); ++c) projections_.push_back(rig.camera(c).ProjectionMatrix());
  layout_ = core::GetKeypointLayout(options.layout);
  fit_options_.min_confidence = options.triangulation.min_confidence;
}

void WindowFinalizer::AddClosedFrame(const ClosedFrame& frame) {
  pending_[frame.frame] = PendingFrame{frame.frame, frame.utime, {}, false};
}

Vec3 WindowFinalizer::FootprintOf(const std::vector<std::optional<Vec3>>& points) const {
  // The linker's footprint rule (pose mode: the hip midpoint, else the centroid of the
  // triangulated joints; box mode: the box point, else the box ends), on the floor.
  const std::optional<Vec2> xy =
      linking::FrameFootprint(points, linker_.context().footprint_points);
  Vec3 p = Vec3::Zero();
  if (xy) p.head<2>() = *xy;
  p.z() = ground_height_m_;
  return p;
}

Track3D WindowFinalizer::MakeTrack(TrackId3D id,
                                   const std::vector<std::optional<Vec3>>& points,
                                   FrameIndex frame,
                                   FrameIndex first_frame,
                                   linking::TrackState state) const {
  Track3D track;
  track.id = id;
  int valid = 0;
  for (const auto& p : points) valid += p ? 1 : 0;
  if (mode_ == InputMode::kPoses) track.joints = points;
  if (fit_skeleton_) {
    track.bone_lengths.assign(layout_.bones.size(), 0.0);
    if (const auto lengths = bone_lengths_.find(id); lengths != bone_lengths_.end()) {
      for (std::size_t b = 0; b < layout_.bones.size(); ++b) {
        track.bone_lengths[b] = lengths->second.lengths()[b].value_or(0.0);
      }
    }
  }
  track.position = FootprintOf(points);
  track.confidence = static_cast<double>(valid) / static_cast<double>(num_points_);
  track.age_frames = frame - first_frame;
  track.state = state;
  return track;
}

linking::LinkResult WindowFinalizer::Finalize(const WindowResult& result,
                                              std::vector<Frame3D>* out) {
  MVTRACK_CHECK(out != nullptr);
  // Link to long-term tracks (Eq. 8-9).
  linking::LinkResult link = linker_.Link(result.window_id,
                                          result.begin,
                                          result.seconds_per_frame,
                                          result.persons,
                                          result.live_tracks,
                                          result.monocular);
  counters_.windows_processed += 1;
  counters_.tracks_born += static_cast<std::int64_t>(link.born.size());
  counters_.tracks_revived += static_cast<std::int64_t>(link.revived.size());
  counters_.gallery_bytes = static_cast<std::int64_t>(linker_.gallery_bytes());
  // The linker's alive tracks, sorted by id (WindowLinker::tracks()): looked up by bisection.
  const std::vector<linking::LinkedTrack>& alive = linker_.tracks();
  // The longest gap bridged, in frames of this stream (0 when bridging is off).
  const auto max_bridge_frames =
      static_cast<FrameIndex>(std::floor(bridge_max_gap_s_ / result.seconds_per_frame + 1e-9));
  // The persons of the window, a person's duplicates (LinkKind::kDuplicate) after everybody
  // else: they only fill frames their person's linked tracklet does not have.
  std::vector<std::size_t> order(result.persons.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_partition(order.begin(), order.end(), [&](std::size_t i) {
    return link.link_kind[i] != linking::LinkKind::kDuplicate;
  });
  // Each output track's frames of this window (from its tracklet and its duplicates), for
  // bridging once all are placed.
  struct Placed {
    FrameIndex frame = 0;
    const std::vector<std::optional<Vec3>>* points = nullptr;
  };
  struct TrackFrames {
    linking::TrackState state = linking::TrackState::kTentative;
    std::vector<Placed> frames;
  };
  std::map<TrackId3D, TrackFrames> placed;
  // The skeleton fit: each track's bone lengths with the samples of this window's finalized
  // frames (a person linked as a duplicate is not sampled: it may be a fragment), then the
  // fitted joints of the frames placed below, by (track, frame).
  std::map<std::pair<TrackId3D, FrameIndex>, std::vector<std::optional<Vec3>>> fitted;
  const std::vector<std::optional<double>> unknown_lengths(layout_.bones.size());
  if (fit_skeleton_) {
    std::vector<TrackId3D> sampled;
    for (std::size_t i = 0; i < result.persons.size(); ++i) {
      const TrackId3D id = link.track_of_tracklet[i];
      if (id == 0 || link.link_kind[i] == linking::LinkKind::kDuplicate) continue;
      const core::Tracklet3D& person = result.persons[i];
      body::BoneLengths& lengths = bone_lengths_.try_emplace(id, layout_).first->second;
      for (std::size_t f = 0; f < person.frames.size(); ++f) {
        if (person.frames[f] < result.finalize_from || person.frames[f] >= result.finalize_to) {
          continue;
        }
        lengths.AddFrame(person.points[f],
                         f < person.views.size() ? &person.views[f] : nullptr,
                         fit_options_.min_confidence);
      }
      sampled.push_back(id);
    }
    for (const TrackId3D id : sampled) bone_lengths_.at(id).Update();
  }
  // Places `person`'s frames of this window under track `id`; `fill` (a duplicate or a single
  // camera's view): only frames the track does not have yet.
  const auto place = [&](const core::Tracklet3D& person, TrackId3D id, bool fill) {
    auto first = first_frame_of_track_.try_emplace(id, person.frames.front()).first;
    first->second = std::min(first->second, person.frames.front());
    const auto it = std::lower_bound(
        alive.begin(), alive.end(), id, [](const linking::LinkedTrack& t, TrackId3D wanted) {
          return t.id < wanted;
        });
    if (it == alive.end() || it->id != id || it->state == linking::TrackState::kTentative) return;
    TrackFrames& mine = placed[id];
    mine.state = it->state;
    for (std::size_t f = 0; f < person.frames.size(); ++f) {
      const FrameIndex frame = person.frames[f];
      if (frame < result.finalize_from || frame >= result.finalize_to) continue;
      auto pending = pending_.find(frame);
      if (pending == pending_.end() || pending->second.final) continue;
      if (fill && std::any_of(pending->second.tracks.begin(),
                              pending->second.tracks.end(),
                              [&](const Track3D& t) { return t.id == id; })) {
        continue;
      }
      const std::vector<std::optional<Vec3>>* points = &person.points[f];
      int valid = 0;
      for (const auto& p : *points) valid += p ? 1 : 0;
      if (valid == 0) continue;
      if (fit_skeleton_ && f < person.views.size()) {
        // Near the track's previous frame when that is the frame just before.
        const std::vector<std::optional<Vec3>>* previous = nullptr;
        if (const auto before = fitted.find({id, frame - 1}); before != fitted.end()) {
          previous = &before->second;
        } else if (const auto last = last_output_.find(id);
                   last != last_output_.end() && last->second.frame == frame - 1) {
          previous = &last->second.points;
        }
        const auto lengths = bone_lengths_.find(id);
        points =
            &(fitted[{id, frame}] = body::FitJoints(
                  *points,
                  person.views[f],
                  projections_,
                  layout_.bones,
                  lengths != bone_lengths_.end() ? lengths->second.lengths() : unknown_lengths,
                  previous,
                  fit_options_,
                  lengths != bone_lengths_.end() ? &lengths->second.uncertainties() : nullptr));
      }
      Track3D track = MakeTrack(id, *points, frame, first->second, it->state);
      track.cameras = person.cameras;
      // All of a frame's tracks come from the one window that finalizes it: at most one per
      // person of that window.
      if (pending->second.tracks.empty()) pending->second.tracks.reserve(result.persons.size());
      pending->second.tracks.push_back(std::move(track));
      mine.frames.push_back(Placed{frame, points});
    }
  };
  for (const std::size_t i : order) {
    place(result.persons[i],
          link.track_of_tracklet[i],
          link.link_kind[i] == linking::LinkKind::kDuplicate);
  }
  // Frames only one camera saw, after every person (LinkerOptions::monocular_max_s).
  for (std::size_t i = 0; i < result.monocular.size(); ++i) {
    if (link.track_of_monocular[i] != 0) {
      place(result.monocular[i], link.track_of_monocular[i], true);
    }
  }
  // Short gaps of a track (no camera pair could place the person, e.g. a camera dark and two
  // people along the other pair's epipolar line), between its last output frame before this
  // window and its frames here, or between its frames here: bridged by interpolating each point
  // between the frames on both sides, once the track is old enough at the gap's far side.
  for (auto& [id, mine] : placed) {
    if (mine.frames.empty()) continue;
    std::sort(mine.frames.begin(), mine.frames.end(), [](const Placed& a, const Placed& b) {
      return a.frame < b.frame;
    });
    const FrameIndex first = first_frame_of_track_.at(id);
    const auto last = last_output_.find(id);
    std::optional<Placed> before;
    if (last != last_output_.end() && last->second.frame < mine.frames.front().frame) {
      before = Placed{last->second.frame, &last->second.points};
    }
    for (const Placed& after : mine.frames) {
      if (before && after.frame - before->frame > 1 &&
          after.frame - before->frame - 1 <= max_bridge_frames &&
          static_cast<double>(after.frame - first) * result.seconds_per_frame >= kBridgeMinAgeS) {
        const auto& p0 = *before->points;
        const auto& p1 = *after.points;
        for (FrameIndex g = std::max(before->frame + 1, result.finalize_from); g < after.frame;
             ++g) {
          auto gap = pending_.find(g);
          if (gap == pending_.end() || gap->second.final) continue;
          const double t = static_cast<double>(g - before->frame) /
                           static_cast<double>(after.frame - before->frame);
          std::vector<std::optional<Vec3>> bridged(p1.size());
          bool any = false;
          for (std::size_t k = 0; k < p1.size() && k < p0.size(); ++k) {
            if (p1[k] && p0[k]) {
              bridged[k] = (1.0 - t) * *p0[k] + t * *p1[k];
              any = true;
            }
          }
          if (!any) continue;
          // cameras empty: no view saw it
          gap->second.tracks.push_back(MakeTrack(id, bridged, g, first, mine.state));
        }
      }
      before = after;
    }
    last_output_[id] = LastOutput{mine.frames.back().frame, *mine.frames.back().points};
  }
  for (TrackId3D id : link.died) {
    first_frame_of_track_.erase(id);
    last_output_.erase(id);
    bone_lengths_.erase(id);
  }
  for (auto& [frame, p] : pending_) {
    if (frame >= result.finalize_from && frame < result.finalize_to) p.final = true;
  }
  EmitFinal(result.finalize_to, out);
  return link;
}

void WindowFinalizer::EndStream(std::vector<Frame3D>* out) {
  MVTRACK_CHECK(out != nullptr);
  // Every track ends with the stream (a re-anchor or a flush): ids are never reused.
  for (const linking::EndedTrack& ended : linker_.EndStream()) {
    first_frame_of_track_.erase(ended.id);
    last_output_.erase(ended.id);
    bone_lengths_.erase(ended.id);
  }
  if (pending_.empty()) return;
  EmitFinal(pending_.rbegin()->first + 1, out);
}

void WindowFinalizer::EmitFinal(FrameIndex up_to, std::vector<Frame3D>* out) {
  // Room for every frame emitted below at once (geometric growth kept for long-lived outputs).
  const auto count =
      static_cast<std::size_t>(std::distance(pending_.begin(), pending_.lower_bound(up_to)));
  const std::size_t needed = out->size() + count;
  if (needed > out->capacity()) out->reserve(std::max(needed, 2 * out->capacity()));
  while (!pending_.empty() && pending_.begin()->first < up_to) {
    PendingFrame& p = pending_.begin()->second;
    Frame3D f;
    f.frame = p.frame;
    f.utime = p.utime;
    f.tracks = std::move(p.tracks);
    std::sort(f.tracks.begin(), f.tracks.end(), [](const Track3D& a, const Track3D& b) {
      return a.id < b.id;
    });
    out->push_back(std::move(f));
    ++counters_.frames_finalized;
    pending_.erase(pending_.begin());
  }
}

}  // namespace mvtrack::tracker
