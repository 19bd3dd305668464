#include "service/frame_synchronizer.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "core/check.h"

namespace mvtrack::service {

const char* ToString(SyncRejection rejection) {
  switch (rejection) {
    case SyncRejection::kNone: return "accepted";
    case SyncRejection::kUnknownCamera: return "unknown camera";
    case SyncRejection::kBackwards: return "time backwards";
    case SyncRejection::kDuplicate: return "duplicate";
    case SyncRejection::kFarFuture: return "far future";
    case SyncRejection::kLate: return "late";
    case SyncRejection::kFlood: return "flood";
  }
  return "?";
}

FrameSynchronizer::FrameSynchronizer(std::vector<CameraId> camera_ids, const SyncOptions& options)
    : options_(options) {
  std::sort(camera_ids.begin(), camera_ids.end());
  MVTRACK_CHECK(std::adjacent_find(camera_ids.begin(), camera_ids.end()) == camera_ids.end());
  for (const CameraId id : camera_ids) {
    index_of_[id] = static_cast<int>(cameras_.size());
    Camera c;
    c.status.camera_id = id;
    cameras_.push_back(c);
  }
}

SyncRejection FrameSynchronizer::Check(const core::CameraFrame& f, int camera_index,
                                       std::string* reason, std::int64_t* key) const {
  const Camera& cam = cameras_[static_cast<std::size_t>(camera_index)];
  const std::string who = "camera " + std::to_string(f.camera_id) + " frame " +
                          std::to_string(f.frame) + " utime " + std::to_string(f.utime);
  const bool by_frame = options_.mode == SyncMode::kFrameIndex;
  if (newest_utime_ && f.utime > *newest_utime_ + options_.max_future_us) {
    *reason = who + " is " + std::to_string(f.utime - *newest_utime_) +
              " us ahead of the newest accepted utime (max_future_us " +
              std::to_string(options_.max_future_us) + ")";
    return SyncRejection::kFarFuture;
  }
  if (by_frame && newest_frame_ && f.frame > *newest_frame_ + options_.max_frame_ahead) {
    *reason = who + " is " + std::to_string(f.frame - *newest_frame_) +
              " frames ahead of the newest accepted frame (max_frame_ahead " +
              std::to_string(options_.max_frame_ahead) + ")";
    return SyncRejection::kFarFuture;
  }
  if (cam.status.has_data) {
    if (f.utime < cam.status.last_utime || (by_frame && f.frame < cam.last_frame)) {
      *reason = who + " is older than the camera's previous frame " +
                std::to_string(cam.last_frame) + " utime " + std::to_string(cam.status.last_utime);
      return SyncRejection::kBackwards;
    }
    if (f.utime == cam.status.last_utime || (by_frame && f.frame == cam.last_frame)) {
      *reason = who + " repeats the camera's previous frame";
      return SyncRejection::kDuplicate;
    }
    if (options_.min_frame_interval_us > 0 &&
        f.utime - cam.status.last_utime < options_.min_frame_interval_us) {
      *reason = who + " follows the camera's previous frame after " +
                std::to_string(f.utime - cam.status.last_utime) +
                " us (min_frame_interval_us " + std::to_string(options_.min_frame_interval_us) +
                ")";
      return SyncRejection::kFlood;
    }
  }
  if (by_frame) {
    *key = f.frame;
    if (last_released_key_ && f.frame <= *last_released_key_) {
      *reason = who + ": frame " + std::to_string(f.frame) + " was already released (newest " +
                std::to_string(*last_released_key_) + ")";
      return SyncRejection::kLate;
    }
    return SyncRejection::kNone;
  }
  // By utime: the closest pending frame within the tolerance, else a new frame.
  std::optional<std::int64_t> best;
  auto consider = [&](std::map<std::int64_t, Group>::const_iterator it) {
    if (it == pending_.end()) return;
    const std::int64_t d = it->first > f.utime ? it->first - f.utime : f.utime - it->first;
    if (d > options_.tolerance_us) return;
    if (!best || d < (*best > f.utime ? *best - f.utime : f.utime - *best)) best = it->first;
  };
  auto it = pending_.lower_bound(f.utime);
  consider(it);
  if (it != pending_.begin()) consider(std::prev(it));
  if (best) {
    if (pending_.at(*best).members[static_cast<std::size_t>(camera_index)].has_value()) {
      *reason = who + " falls in a frame the camera already delivered to";
      return SyncRejection::kDuplicate;
    }
    *key = *best;
    return SyncRejection::kNone;
  }
  if (last_released_key_ && f.utime <= *last_released_key_ + options_.tolerance_us) {
    *reason = who + " belongs to a frame at or before the released frame at utime " +
              std::to_string(*last_released_key_);
    return SyncRejection::kLate;
  }
  *key = f.utime;
  return SyncRejection::kNone;
}

SyncResult FrameSynchronizer::Add(core::CameraFrame frame) {
  SyncResult result;
  const auto known = index_of_.find(frame.camera_id);
  if (known == index_of_.end()) {
    ++counters_.unknown_camera;
    result.rejection = SyncRejection::kUnknownCamera;
    result.reason = "camera " + std::to_string(frame.camera_id) + " is not configured";
    return result;
  }
  const int index = known->second;
  Camera& cam = cameras_[static_cast<std::size_t>(index)];
  std::int64_t key = 0;
  SyncRejection why = Check(frame, index, &result.reason, &key);
  const bool order_rejection = why == SyncRejection::kBackwards || why == SyncRejection::kLate ||
                               why == SyncRejection::kFarFuture;
  if (order_rejection && consecutive_order_rejections_ + 1 >= options_.resync_after_rejections) {
    // The stream restarted (clock or frame counter reset, or a jump): release what is pending,
    // end the tracker's stream and start over with this camera-frame.
    Release(&result.actions, /*force_all=*/true);
    SyncAction end;
    end.kind = SyncAction::Kind::kEndStream;
    result.actions.push_back(std::move(end));
    for (Camera& c : cameras_) {
      c.status.has_data = false;
      c.status.last_utime = 0;
      c.last_frame = 0;
      // Exclusion flags stay: cameras are re-included as they deliver.
    }
    last_released_key_.reset();
    newest_utime_.reset();
    newest_frame_.reset();
    stream_start_utime_.reset();
    consecutive_order_rejections_ = 0;
    ++counters_.resyncs;
    result.resynced = true;
    result.reason.clear();
    why = Check(frame, index, &result.reason, &key);
    MVTRACK_CHECK(why == SyncRejection::kNone);
  }
  if (why != SyncRejection::kNone) {
    if (order_rejection) ++consecutive_order_rejections_;
    switch (why) {
      case SyncRejection::kBackwards: ++cam.status.backwards; break;
      case SyncRejection::kDuplicate: ++cam.status.duplicates; break;
      case SyncRejection::kFarFuture: ++cam.status.far_future; break;
      case SyncRejection::kLate: ++cam.status.late; break;
      case SyncRejection::kFlood: ++cam.status.flood; break;
      case SyncRejection::kNone:
      case SyncRejection::kUnknownCamera: break;
    }
    cam.status.detections_rejected += static_cast<std::int64_t>(frame.detections.size());
    result.rejection = why;
    return result;
  }
  consecutive_order_rejections_ = 0;
  Accept(std::move(frame), index, key, &result);
  return result;
}

void FrameSynchronizer::Accept(core::CameraFrame frame, int camera_index, std::int64_t key,
                               SyncResult* result) {
  Camera& cam = cameras_[static_cast<std::size_t>(camera_index)];
  ++cam.status.accepted;
  cam.status.has_data = true;
  cam.status.last_utime = frame.utime;
  cam.last_frame = frame.frame;
  if (cam.status.excluded) {
    cam.status.excluded = false;
    result->transitions.push_back(CameraTransition{cam.status.camera_id, false});
  }
  newest_utime_ = newest_utime_ ? std::max(*newest_utime_, frame.utime) : frame.utime;
  if (!stream_start_utime_) stream_start_utime_ = frame.utime;
  if (options_.mode == SyncMode::kFrameIndex) {
    newest_frame_ = newest_frame_ ? std::max(*newest_frame_, frame.frame) : frame.frame;
  }
  auto [it, inserted] = pending_.try_emplace(key);
  Group& g = it->second;
  if (inserted) {
    g.utime_min = frame.utime;
    g.members.resize(cameras_.size());
  }
  g.utime_min = std::min(g.utime_min, frame.utime);
  g.members[static_cast<std::size_t>(camera_index)] = std::move(frame);
  UpdateExclusions(&result->transitions);
  Release(&result->actions, /*force_all=*/false);
}

void FrameSynchronizer::UpdateExclusions(std::vector<CameraTransition>* transitions) {
  if (!newest_utime_ || !stream_start_utime_) return;
  for (Camera& c : cameras_) {
    if (c.status.excluded) continue;
    // A camera not seen in this stream is waited for from the stream's first utime on.
    const Utime last = c.status.has_data ? c.status.last_utime : *stream_start_utime_;
    if (*newest_utime_ - last > options_.silent_after_us) {
      c.status.excluded = true;
      transitions->push_back(CameraTransition{c.status.camera_id, true});
    }
  }
}

void FrameSynchronizer::Release(std::vector<SyncAction>* actions, bool force_all) {
  while (!pending_.empty()) {
    const Group& g = pending_.begin()->second;
    bool complete = true;
    for (std::size_t c = 0; c < cameras_.size(); ++c) {
      if (!cameras_[c].status.excluded && !g.members[c].has_value()) complete = false;
    }
    const bool deadline = newest_utime_ && *newest_utime_ - g.utime_min >= options_.deadline_us;
    const bool bound = pending_.size() > static_cast<std::size_t>(options_.max_pending_frames);
    if (complete) {
      ++counters_.released_complete;
    } else if (force_all) {
      ++counters_.released_by_flush;
    } else if (deadline) {
      ++counters_.released_by_deadline;
    } else if (bound) {
      ++counters_.released_by_bound;
    } else {
      return;
    }
    ReleaseOldest(actions);
  }
}

void FrameSynchronizer::ReleaseOldest(std::vector<SyncAction>* actions) {
  auto node = pending_.extract(pending_.begin());
  Group& g = node.mapped();
  last_released_key_ = node.key();
  const FrameIndex index =
      options_.mode == SyncMode::kUtime ? next_frame_index_++ : static_cast<FrameIndex>(node.key());
  ++counters_.frames_released;
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    if (!g.members[c].has_value()) {
      if (!cameras_[c].status.excluded) ++cameras_[c].status.missed;
      continue;
    }
    SyncAction a;
    a.kind = SyncAction::Kind::kSubmit;
    a.frame = std::move(*g.members[c]);
    a.frame.frame = index;
    actions->push_back(std::move(a));
  }
}

std::vector<SyncAction> FrameSynchronizer::Flush() {
  std::vector<SyncAction> actions;
  Release(&actions, /*force_all=*/true);
  newest_utime_.reset();
  newest_frame_.reset();
  stream_start_utime_.reset();
  last_released_key_.reset();
  consecutive_order_rejections_ = 0;
  return actions;
}

SyncStatus FrameSynchronizer::Status() const {
  SyncStatus s = counters_;
  s.cameras.clear();
  for (const Camera& c : cameras_) s.cameras.push_back(c.status);
  s.pending_frames = pending_.size();
  return s;
}

}  // namespace mvtrack::service
