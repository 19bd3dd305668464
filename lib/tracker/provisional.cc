#include "tracker/provisional.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/check.h"
#include "tracker/window_job.h"

namespace mvtrack::tracker {
namespace {

// ProvisionalEstimator::owner_ of a 2D track whose owner is not output (tentative).
constexpr std::size_t kNotOutput = static_cast<std::size_t>(-1);

}  // namespace

ProvisionalEstimator::ProvisionalEstimator(const geometry::CameraRig& rig,
                                           const TrackerOptions& options)
    : rig_(rig),
      mode_(options.mode),
      num_points_(NumPoints(options)),
      num_triangulated_points_(NumTriangulatedPoints(options)),
      footprint_points_(FootprintPoints(options)),
      ground_height_m_(options.ground_height_m),
      min_height_m_(options.ground_height_m + options.refinement.box_min_height_m),
      max_height_m_(options.ground_height_m + options.refinement.box_max_height_m),
      options_(options),
      triangulator_(options.triangulation) {}

void ProvisionalEstimator::OnLinked(const linking::WindowLinker& linker) {
  std::vector<Track> next;
  owner_.clear();
  // The latest frame each 2D track was seen in by its owner so far.
  std::map<std::pair<CameraId, TrackId2D>, FrameIndex> seen;
  seconds_per_frame_ = linker.seconds_per_frame();
  std::size_t old = 0;
  for (const linking::LinkedTrack& linked : linker.tracks()) {
    // Every track claims its 2D tracks (a tentative one too: a 2D track it took from a lost
    // track is not that track's any more), confirmed ones are output.
    std::size_t index = kNotOutput;
    if (linked.confirmed) index = next.size();
    for (const linking::TrackMember& m : linked.members) {
      const std::pair<CameraId, TrackId2D> key{m.camera_id, m.track_id};
      auto [it, inserted] = seen.try_emplace(key, m.last_frame);
      // Ties keep the lowest id (tracks come in increasing id).
      if (inserted || m.last_frame > it->second) {
        it->second = m.last_frame;
        owner_[key] = index;
      }
    }
    if (!linked.confirmed) continue;
    while (old < tracks_.size() && tracks_[old].id < linked.id) ++old;
    Track t{linked.id, linked.first_seen_frame, linked.last_seen_frame, linked.motion.position()};
    if (old < tracks_.size() && tracks_[old].id == linked.id &&
        tracks_[old].last_frame > linked.last_seen_frame) {
      t.last_frame = tracks_[old].last_frame;
      t.last_xy = tracks_[old].last_xy;
    }
    next.push_back(t);
  }
  tracks_ = std::move(next);
}

void ProvisionalEstimator::EndStream() {
  tracks_.clear();
  owner_.clear();
}

std::optional<std::vector<std::optional<Vec3>>> ProvisionalEstimator::Triangulate(
    FrameIndex frame) {
  cluster_.resize(tracklets_.size());
  for (std::size_t i = 0; i < cluster_.size(); ++i) cluster_[i] = static_cast<int>(i);
  core::Tracklet3D person = triangulator_.Triangulate(
      rig_, tracklets_, cluster_, frame, frame + 1, num_triangulated_points_, nullptr, num_points_);
  if (person.frames.empty()) return std::nullopt;
  std::vector<std::optional<Vec3>>& points = person.points.front();
  if (mode_ == InputMode::kBoxes) {
    // The window's height gate on the box point.
    for (std::optional<Vec3>& p : points) {
      if (p && (p->z() < min_height_m_ || p->z() > max_height_m_)) p.reset();
    }
  }
  if (std::none_of(points.begin(), points.end(), [](const auto& p) { return p.has_value(); })) {
    return std::nullopt;
  }
  return std::move(points);
}

Frame3D ProvisionalEstimator::Estimate(FrameIndex frame,
                                       Utime utime,
                                       const std::vector<FrameView>& views) {
  Frame3D out;
  out.frame = frame;
  out.utime = utime;
  views_of_track_.resize(tracks_.size());
  for (auto& v : views_of_track_) v.clear();
  for (const FrameView& view : views) {
    MVTRACK_CHECK(view.camera_index >= 0 && view.camera_index < rig_.size());
    const auto it = owner_.find({rig_.camera(view.camera_index).id, view.track_id});
    if (it != owner_.end() && it->second != kNotOutput) {
      views_of_track_[it->second].push_back(&view);
    }
  }
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    Track& track = tracks_[i];
    std::vector<const FrameView*>& seen = views_of_track_[i];
    std::sort(seen.begin(), seen.end(), [](const FrameView* a, const FrameView* b) {
      return std::pair(a->camera_index, a->track_id) < std::pair(b->camera_index, b->track_id);
    });
    Track3D t;
    t.id = track.id;
    t.age_frames = std::max<FrameIndex>(0, frame - track.first_frame);
    std::optional<std::vector<std::optional<Vec3>>> points;
    const bool two_cameras =
        !seen.empty() && seen.front()->camera_index != seen.back()->camera_index;
    if (two_cameras) {
      tracklets_.resize(seen.size());
      for (std::size_t v = 0; v < seen.size(); ++v) {
        core::Tracklet2D& tracklet = tracklets_[v];
        tracklet.camera_id = rig_.camera(seen[v]->camera_index).id;
        tracklet.track_id = seen[v]->track_id;
        tracklet.frames.assign(1, frame);
        tracklet.observations.assign(1, seen[v]->observation);
      }
      points = Triangulate(frame);
    }
    std::optional<Vec3> position;
    if (points) {
      const std::optional<Vec2> xy = linking::FrameFootprint(*points, footprint_points_);
      if (xy) {
        position = Vec3(xy->x(), xy->y(), ground_height_m_);
        int valid = 0;
        for (int k = 0; k < num_triangulated_points_; ++k) {
          valid += (*points)[static_cast<std::size_t>(k)] ? 1 : 0;
        }
        t.confidence = static_cast<double>(valid) / static_cast<double>(num_triangulated_points_);
        for (const FrameView* v : seen) t.cameras.push_back(rig_.camera(v->camera_index).id);
        if (mode_ == InputMode::kPoses) t.joints = *points;
      }
    }
    if (!seen.empty() && !two_cameras && mode_ == InputMode::kBoxes) {
      // One camera: the first of its views whose feet are on the floor.
      for (const FrameView* v : seen) {
        if (std::optional<Vec3> feet =
                FeetOnFloor(rig_.camera(v->camera_index), options_, v->observation)) {
          position = Vec3(feet->x(), feet->y(), ground_height_m_);
          t.cameras.push_back(rig_.camera(v->camera_index).id);
          break;
        }
      }
    }
    // Not placed (unseen; views of two or more cameras that do not meet: its 2D tracks may
    // show different people now; one camera in pose mode): not output.
    if (!position) continue;
    // Not farther from its latest footprint than a person can go (the linker's re-identification
    // bound): views that place it farther show somebody else now (a 2D track that changed person).
    const double dt =
        static_cast<double>(std::max<FrameIndex>(0, frame - track.last_frame)) * seconds_per_frame_;
    if ((position->head<2>() - track.last_xy).norm() >
        linking::kSamePersonApartM + linking::kMaxReidSpeedMps * dt) {
      continue;
    }
    track.last_frame = frame;
    track.last_xy = position->head<2>();
    std::sort(t.cameras.begin(), t.cameras.end());
    t.cameras.erase(std::unique(t.cameras.begin(), t.cameras.end()), t.cameras.end());
    t.position = *position;
    t.state = linking::TrackState::kConfirmed;
    if (mode_ == InputMode::kPoses && t.joints.empty()) {
      t.joints.assign(static_cast<std::size_t>(num_points_), std::nullopt);
    }
    out.tracks.push_back(std::move(t));
  }
  return out;
}

}  // namespace mvtrack::tracker
