#include "tracker/window_builder.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "core/check.h"

namespace mvtrack::tracker {

WindowBuilder::WindowBuilder(const geometry::CameraRig& rig,
                             const TrackerOptions& options,
                             bool keep_frame_views)
    : options_(options),
      window_size_(options.window_size),
      window_step_(options.window_step),
      min_tracklet_length_(options.min_tracklet_length),
      keep_frame_views_(keep_frame_views) {
  for (int i = 0; i < rig.size(); ++i) camera_ids_.push_back(rig.camera(i).id);
  tracks_.resize(camera_ids_.size());
}

void WindowBuilder::RememberClosed(FrameIndex frame, Utime utime) { period_.Add(frame, utime); }

void WindowBuilder::FixGeometry() {
  const TrackerOptions o = AtFrameRate(options_, SecondsPerFrame());
  window_size_ = o.window_size;
  window_step_ = o.window_step;
  min_tracklet_length_ = o.min_tracklet_length;
  geometry_fixed_ = true;
  // The grid starts at the multiple of δ at or before the stream's first frame, so trackers of
  // one camera stream that started at different frames (a site's zone daemons, a restarted
  // daemon) close the same windows at the same time. No window has begun yet.
  if (grid_origin_) {
    const FrameIndex r = *grid_origin_ % window_step_;
    grid_origin_ = *grid_origin_ - (r < 0 ? r + window_step_ : r);
  }
}

std::size_t WindowBuilder::num_stored_observations() const {
  std::size_t n = 0;
  for (const auto& camera : tracks_) {
    for (const auto& [id, observations] : camera) n += observations.size();
  }
  return n;
}

void WindowBuilder::Add(const FrameEvents& events,
                        TrackedCameraFrame frame,
                        std::vector<BuilderOutput>* out) {
  MVTRACK_CHECK(out != nullptr);
  MVTRACK_CHECK(frame.camera_index >= 0 &&
                frame.camera_index < static_cast<int>(camera_ids_.size()));
  if (events.close_open_frame) {
    MVTRACK_CHECK_MSG(open_frame_ && frame.frame > *open_frame_,
                      "close_open_frame needs an open frame older than this camera-frame");
    CloseOpenFrame(out);
  }
  if (events.reanchor) {
    MVTRACK_CHECK_MSG(last_closed_frame_ && !open_frame_, "reanchor needs a closed stream");
    EndStream(out);
  }
  if (events.open_frame) {
    MVTRACK_CHECK_MSG(!open_frame_, "open_frame while a frame is open");
    open_frame_ = frame.frame;
    open_utime_ = frame.utime;
    if (!grid_origin_) grid_origin_ = frame.frame;
    // Frames skipped since the last closed one complete the windows that end before this one.
    EmitWindowsUpTo(frame.frame - 1, /*flushing=*/false, out);
  } else {
    MVTRACK_CHECK_MSG(open_frame_ && *open_frame_ == frame.frame,
                      "a camera-frame of another frame than the open one without events");
  }
  open_utime_ = std::min(open_utime_, frame.utime);
  auto& camera_tracks = tracks_[static_cast<std::size_t>(frame.camera_index)];
  for (auto& [track_id, observation] : frame.observations) {
    if (keep_frame_views_)
      open_views_.push_back(FrameView{frame.camera_index, track_id, observation});
    camera_tracks[track_id].push_back(TimedObservation{frame.frame, std::move(observation)});
  }
  if (events.close_after) CloseOpenFrame(out);
}

void WindowBuilder::Flush(std::vector<BuilderOutput>* out) {
  MVTRACK_CHECK(out != nullptr);
  if (open_frame_) {
    // Closed without the non-flushing pass: at a flush every window is emitted by EndStream.
    out->push_back(ClosedFrame{*open_frame_, open_utime_, std::move(open_views_)});
    open_views_.clear();
    RememberClosed(*open_frame_, open_utime_);
    last_closed_frame_ = *open_frame_;
    open_frame_.reset();
  }
  if (last_closed_frame_) EndStream(out);
}

void WindowBuilder::CloseOpenFrame(std::vector<BuilderOutput>* out) {
  const FrameIndex f = *open_frame_;
  out->push_back(ClosedFrame{f, open_utime_, std::move(open_views_)});
  open_views_.clear();
  RememberClosed(f, open_utime_);
  last_closed_frame_ = f;
  open_frame_.reset();
  EmitWindowsUpTo(f, /*flushing=*/false, out);
}

void WindowBuilder::EmitWindowsUpTo(FrameIndex complete_through,
                                    bool flushing,
                                    std::vector<BuilderOutput>* out) {
  if (!grid_origin_) return;
  // Three closed frames give two periods; their median is the larger, so one late frame among
  // them can only shorten the windows. A stream that ends earlier uses what it has.
  constexpr std::size_t kFramesToFixGeometry = 3;
  if (!geometry_fixed_) {
    if (period_.size() < kFramesToFixGeometry && !flushing) return;
    FixGeometry();
  }
  const FrameIndex origin = *grid_origin_;
  const std::int64_t nu = window_size_;
  const std::int64_t delta = window_step_;
  const std::int64_t half_overlap = (nu - delta) / 2;
  while (true) {
    const FrameIndex begin = origin + next_window_ * delta;
    const FrameIndex end = begin + nu;
    const bool complete = end - 1 <= complete_through;
    if (!complete) {
      if (!flushing || !last_closed_frame_ || begin > *last_closed_frame_) break;
    }
    const FrameIndex finalize_from = next_window_ == 0 ? begin : begin + half_overlap;
    FrameIndex finalize_to = begin + half_overlap + delta;
    if (flushing && last_closed_frame_ && begin + delta > *last_closed_frame_) {
      finalize_to = *last_closed_frame_ + 1;  // the last window finalizes the tail
    }
    EmitWindow(window_id_offset_ + next_window_,
               begin,
               complete ? end : *last_closed_frame_ + 1,
               finalize_from,
               finalize_to,
               out);
    ++next_window_;
  }
}

void WindowBuilder::EmitWindow(std::int64_t window_id,
                               FrameIndex begin,
                               FrameIndex end,
                               FrameIndex finalize_from,
                               FrameIndex finalize_to,
                               std::vector<BuilderOutput>* out) {
  WindowJob job;
  job.window_id = window_id;
  job.begin = begin;
  job.end = end;
  job.finalize_from = finalize_from;
  job.finalize_to = finalize_to;
  job.seconds_per_frame = SecondsPerFrame();
  // Observations before keep_from are dropped right after this window (no later window needs
  // them), so the window takes them by move; only the overlap with the next window is copied.
  const FrameIndex keep_from = begin + window_step_;
  std::size_t num_tracks = 0;
  for (const auto& camera_tracks : tracks_) num_tracks += camera_tracks.size();
  job.tracklets.reserve(num_tracks);
  // Crop every camera's 2D tracks to the window (cameras in rig order, tracks by id).
  for (std::size_t c = 0; c < tracks_.size(); ++c) {
    for (auto& [track_id, observations] : tracks_[c]) {
      // Observations are in frame order: the window's are one contiguous run. Tracklets too
      // short for the window are skipped before copying anything.
      const auto first =
          std::lower_bound(observations.begin(),
                           observations.end(),
                           begin,
                           [](const TimedObservation& o, FrameIndex f) { return o.frame < f; });
      const auto last = std::lower_bound(
          first, observations.end(), end, [](const TimedObservation& o, FrameIndex f) {
            return o.frame < f;
          });
      const auto count = static_cast<std::size_t>(last - first);
      if (count == 0) continue;
      job.live_tracks.push_back(
          {camera_ids_[c], track_id, first->frame, (last - 1)->frame, static_cast<int>(count)});
      if (static_cast<int>(count) < min_tracklet_length_) continue;
      core::Tracklet2D& t = job.tracklets.emplace_back();
      t.camera_id = camera_ids_[c];
      t.track_id = track_id;
      t.frames.reserve(count);
      t.observations.reserve(count);
      for (auto it = first; it != last; ++it) {
        t.frames.push_back(it->frame);
        if (it->frame < keep_from) {
          t.observations.push_back(std::move(it->observation));
        } else {
          t.observations.push_back(it->observation);
        }
      }
    }
  }
  std::sort(job.live_tracks.begin(),
            job.live_tracks.end(),
            [](const core::TrackletMember& a, const core::TrackletMember& b) {
              return a.camera_id != b.camera_id ? a.camera_id < b.camera_id
                                                : a.track_id < b.track_id;
            });
  out->push_back(std::move(job));

  // Trim observations no later window needs (the next window begins at begin + δ); those in
  // this window were moved out above.
  for (auto& camera_tracks : tracks_) {
    for (auto it = camera_tracks.begin(); it != camera_tracks.end();) {
      auto& obs = it->second;
      obs.erase(obs.begin(), std::find_if(obs.begin(), obs.end(), [&](const TimedObservation& o) {
                  return o.frame >= keep_from;
                }));
      it = obs.empty() ? camera_tracks.erase(it) : std::next(it);
    }
  }
}

void WindowBuilder::EndStream(std::vector<BuilderOutput>* out) {
  EmitWindowsUpTo(last_closed_frame_ ? *last_closed_frame_ : 0, /*flushing=*/true, out);
  out->push_back(StreamEnd{});
  // Window ids continue (the StreamEnd makes the finalizer end every track).
  window_id_offset_ += next_window_;
  next_window_ = 0;
  grid_origin_.reset();
  last_closed_frame_.reset();
  period_.Clear();  // the next stream may run at another rate
  geometry_fixed_ = false;
  for (auto& camera_tracks : tracks_) camera_tracks.clear();
}

}  // namespace mvtrack::tracker
