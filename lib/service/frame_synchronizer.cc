#include "service/frame_synchronizer.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <utility>

#include "core/check.h"

namespace mvtrack::service {
namespace {

constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();

// Saturating int64 arithmetic: every time and frame value comes from the wire.
std::int64_t SatAdd(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (__builtin_add_overflow(a, b, &r)) return b > 0 ? kMax : kMin;
  return r;
}

std::int64_t SatSub(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (__builtin_sub_overflow(a, b, &r)) return b < 0 ? kMax : kMin;
  return r;
}

std::int64_t SatAbs(std::int64_t a) { return a == kMin ? kMax : (a < 0 ? -a : a); }

// |a - b|, saturated.
std::int64_t Distance(std::int64_t a, std::int64_t b) { return SatAbs(SatSub(a, b)); }

// Lower median of `v` (not empty); reorders it.
std::int64_t LowerMedian(std::vector<std::int64_t>* v) {
  const auto mid = v->begin() + static_cast<std::ptrdiff_t>((v->size() - 1) / 2);
  std::nth_element(v->begin(), mid, v->end());
  return *mid;
}

}  // namespace

const char* ToString(SyncRejection rejection) {
  switch (rejection) {
    case SyncRejection::kNone:
      return "accepted";
    case SyncRejection::kUnknownCamera:
      return "unknown camera";
    case SyncRejection::kBackwards:
      return "time backwards";
    case SyncRejection::kDuplicate:
      return "duplicate";
    case SyncRejection::kFarFuture:
      return "far future";
    case SyncRejection::kLate:
      return "late";
    case SyncRejection::kFlood:
      return "flood";
    case SyncRejection::kClockOffset:
      return "clock offset";
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

bool FrameSynchronizer::OutOfStep(const Camera& c) const {
  const int vote = std::min(options_.resync_after_rejections, kStreamVoteRejections);
  if (c.time_rejections >= vote) return true;
  return c.time_rejections >= std::min(vote, kStreamVoteMinRejections) &&
         SatSub(c.last_rejected_utime, c.first_rejected_utime) >= kStreamVoteSpanUs;
}

bool FrameSynchronizer::InQuorum(const Camera& c) const {
  // A camera whose newest camera-frames were rejected for their time is out of step: its last
  // accepted time is stale, and judging the others against it would flag them.
  return c.status.has_data && !c.status.excluded && !c.status.clock_flagged &&
         c.time_rejections == 0;
}

std::optional<std::pair<Utime, FrameIndex>> FrameSynchronizer::QuorumTime(
    int skip, std::size_t min_cameras) const {
  std::vector<std::int64_t> utimes;
  std::vector<std::int64_t> frames;
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    if (static_cast<int>(i) == skip || !InQuorum(cameras_[i])) continue;
    utimes.push_back(cameras_[i].status.last_utime);
    frames.push_back(cameras_[i].last_frame);
  }
  if (utimes.empty() || utimes.size() < min_cameras) return std::nullopt;
  return std::make_pair(LowerMedian(&utimes), LowerMedian(&frames));
}

void FrameSynchronizer::UpdateNow() {
  if (const auto q = QuorumTime(-1, 1)) {
    now_utime_ = q->first;
    now_frame_ = q->second;
  }
  // Without any camera in good standing the last time stays (a flagged camera cannot move it).
}

void FrameSynchronizer::UpdateClock(const core::CameraFrame& f, int index, SyncResult* result) {
  Camera& cam = cameras_[static_cast<std::size_t>(index)];
  // The quorum of the other cameras: at least two, so that one camera is never judged by one.
  const auto q = QuorumTime(index, 2);
  if (!q) return;
  cam.offset_us[cam.next_offset] = SatSub(f.utime, q->first);
  cam.offset_frames[cam.next_offset] = SatSub(f.frame, q->second);
  cam.next_offset = (cam.next_offset + 1) % kOffsetSamples;
  cam.num_offsets = std::min(cam.num_offsets + 1, kOffsetSamples);
  if (cam.num_offsets < kMinOffsetSamples) return;
  std::vector<std::int64_t> us(
      cam.offset_us.begin(), cam.offset_us.begin() + static_cast<std::ptrdiff_t>(cam.num_offsets));
  cam.status.offset_us = LowerMedian(&us);
  const bool by_frame = options_.mode == SyncMode::kFrameIndex;
  cam.status.offset_frames = 0;
  if (by_frame) {
    std::vector<std::int64_t> fr(
        cam.offset_frames.begin(),
        cam.offset_frames.begin() + static_cast<std::ptrdiff_t>(cam.num_offsets));
    cam.status.offset_frames = LowerMedian(&fr);
  }
  std::int64_t period = 0;
  if (cam.num_steps > 0) {
    std::vector<std::int64_t> steps(cam.steps.begin(),
                                    cam.steps.begin() + static_cast<std::ptrdiff_t>(cam.num_steps));
    period = LowerMedian(&steps);
  }
  const std::int64_t du = SatAbs(cam.status.offset_us);
  const std::int64_t df = SatAbs(cam.status.offset_frames);
  const bool off = du > SatAdd(options_.clock_tolerance_us, period) ||
                   (by_frame && df > options_.max_frame_offset);
  const bool back = du <= SatAdd(options_.clock_tolerance_us / 2, period) &&
                    (!by_frame || df <= options_.max_frame_offset / 2);
  if (cam.status.clock_flagged ? back : off) {
    cam.status.clock_flagged = !cam.status.clock_flagged;
    CameraTransition t;
    t.camera_id = cam.status.camera_id;
    t.kind = CameraTransition::Kind::kClock;
    t.excluded = cam.status.clock_flagged;
    t.offset_us = cam.status.offset_us;
    t.offset_frames = cam.status.offset_frames;
    result->transitions.push_back(t);
    UpdateNow();
  }
}

SyncRejection FrameSynchronizer::Check(const core::CameraFrame& f,
                                       int camera_index,
                                       std::string* reason,
                                       std::int64_t* key) const {
  const Camera& cam = cameras_[static_cast<std::size_t>(camera_index)];
  const std::string who = "camera " + std::to_string(f.camera_id) + " frame " +
                          std::to_string(f.frame) + " utime " + std::to_string(f.utime);
  const bool by_frame = options_.mode == SyncMode::kFrameIndex;
  if (cam.status.clock_flagged) {
    *reason = who + ": the camera's clock is " + std::to_string(cam.status.offset_us) + " us (" +
              std::to_string(cam.status.offset_frames) +
              " frames) off the other cameras' (clock_tolerance_us " +
              std::to_string(options_.clock_tolerance_us) + ")";
    return SyncRejection::kClockOffset;
  }
  if (now_utime_ && f.utime > SatAdd(*now_utime_, options_.max_future_us)) {
    *reason = who + " is " + std::to_string(SatSub(f.utime, *now_utime_)) +
              " us ahead of the stream's time (max_future_us " +
              std::to_string(options_.max_future_us) + ")";
    return SyncRejection::kFarFuture;
  }
  if (by_frame && now_frame_ && f.frame > SatAdd(*now_frame_, options_.max_frame_ahead)) {
    *reason = who + " is " + std::to_string(SatSub(f.frame, *now_frame_)) +
              " frames ahead of the stream's frame (max_frame_ahead " +
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
    const std::int64_t interval = SatSub(f.utime, cam.status.last_utime);
    if (options_.min_frame_interval_us > 0 && interval < options_.min_frame_interval_us) {
      *reason = who + " follows the camera's previous frame after " + std::to_string(interval) +
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
    // A camera that restarted alone may send a frame index it already delivered to a pending
    // frame; accepting it would overwrite that camera-frame (accepted, then in no counter).
    const auto pending = pending_.find(f.frame);
    if (pending != pending_.end() &&
        pending->second.members[static_cast<std::size_t>(camera_index)].has_value()) {
      *reason = who + " falls in a frame the camera already delivered to";
      return SyncRejection::kDuplicate;
    }
    return SyncRejection::kNone;
  }
  // By utime: the closest pending frame within the tolerance, else a new frame.
  std::optional<std::int64_t> best;
  auto consider = [&](std::map<std::int64_t, Group>::const_iterator it) {
    if (it == pending_.end()) return;
    const std::int64_t d = Distance(it->first, f.utime);
    if (d > options_.tolerance_us) return;
    if (!best || d < Distance(*best, f.utime)) best = it->first;
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
  if (last_released_key_ && f.utime <= SatAdd(*last_released_key_, options_.tolerance_us)) {
    *reason = who + " belongs to a frame at or before the released frame at utime " +
              std::to_string(*last_released_key_);
    return SyncRejection::kLate;
  }
  *key = f.utime;
  return SyncRejection::kNone;
}

void FrameSynchronizer::Resync(SyncResult* result) {
  Release(&result->actions, /*force_all=*/true);
  SyncAction end;
  end.kind = SyncAction::Kind::kEndStream;
  result->actions.push_back(std::move(end));
  for (Camera& c : cameras_) {
    c.status.has_data = false;
    c.status.last_utime = 0;
    c.last_frame = 0;
    c.order_rejections = 0;
    c.time_rejections = 0;
    c.num_offsets = 0;
    c.next_offset = 0;
    // Clock flags were judged against the old stream's time: every clock is judged again
    // against the new stream's quorum (a camera still off is flagged within kMinOffsetSamples
    // of its frames). Exclusions stay: cameras are re-included as they deliver.
    if (c.status.clock_flagged) {
      c.status.clock_flagged = false;
      CameraTransition t;
      t.camera_id = c.status.camera_id;
      t.kind = CameraTransition::Kind::kClock;
      t.excluded = false;
      result->transitions.push_back(t);
    }
    c.status.offset_us = 0;
    c.status.offset_frames = 0;
  }
  last_released_key_.reset();
  now_utime_.reset();
  now_frame_.reset();
  stream_start_utime_.reset();
  ++counters_.resyncs;
  result->resynced = true;
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
  UpdateClock(frame, index, &result);
  std::int64_t key = 0;
  SyncRejection why = Check(frame, index, &result.reason, &key);
  const bool order_rejection = why == SyncRejection::kBackwards || why == SyncRejection::kLate ||
                               why == SyncRejection::kFarFuture;
  const bool time_rejection = order_rejection || why == SyncRejection::kClockOffset;
  const int r = options_.resync_after_rejections;
  if (order_rejection) ++cam.order_rejections;
  if (time_rejection) {
    if (cam.time_rejections == 0) cam.first_rejected_utime = frame.utime;
    cam.last_rejected_utime = frame.utime;
    ++cam.time_rejections;
  }
  if (time_rejection && (OutOfStep(cam) || (order_rejection && cam.order_rejections % r == 0))) {
    // This camera restarted (its clock or frame counter was reset, or jumped). When more than
    // half of the cameras with data (or restarting) did, the stream restarted: release what is
    // pending, end the tracker's stream and start over with this camera-frame. A camera whose
    // frames are rejected for their clock counts too: when the whole rig's time steps, the
    // cameras disagree with the old stream's time, not with each other, and get flagged before
    // their order rejections add up. Otherwise it starts over alone (order rejections only: a
    // flagged clock stays flagged until it agrees with the others).
    int restarted = 0;
    int pool = 0;
    for (const Camera& c : cameras_) {
      const bool restarting = OutOfStep(c);
      if (!c.status.has_data && !restarting) continue;
      ++pool;
      if (restarting) ++restarted;
    }
    bool restarted_alone = false;
    if (2 * restarted > pool) {
      Resync(&result);
    } else if (order_rejection && cam.order_rejections % r == 0) {
      restarted_alone = true;
      cam.status.has_data = false;
      cam.status.last_utime = 0;
      cam.last_frame = 0;
      ++cam.status.restarts;
      CameraTransition t;
      t.camera_id = cam.status.camera_id;
      t.kind = CameraTransition::Kind::kRestart;
      result.transitions.push_back(t);
      UpdateNow();
      DropAhead(index);
    }
    if (result.resynced || restarted_alone) {
      result.reason.clear();
      why = Check(frame, index, &result.reason, &key);
    }
  }
  if (why != SyncRejection::kNone) {
    switch (why) {
      case SyncRejection::kBackwards:
        ++cam.status.backwards;
        break;
      case SyncRejection::kDuplicate:
        ++cam.status.duplicates;
        break;
      case SyncRejection::kFarFuture:
        ++cam.status.far_future;
        break;
      case SyncRejection::kLate:
        ++cam.status.late;
        break;
      case SyncRejection::kFlood:
        ++cam.status.flood;
        break;
      case SyncRejection::kClockOffset:
        ++cam.status.clock_offset;
        break;
      case SyncRejection::kNone:
      case SyncRejection::kUnknownCamera:
        break;
    }
    cam.status.detections_rejected += static_cast<std::int64_t>(frame.detections.size());
    result.rejection = why;
    return result;
  }
  cam.order_rejections = 0;
  cam.time_rejections = 0;
  Accept(std::move(frame), index, key, &result);
  return result;
}

void FrameSynchronizer::Accept(core::CameraFrame frame,
                               int camera_index,
                               std::int64_t key,
                               SyncResult* result) {
  Camera& cam = cameras_[static_cast<std::size_t>(camera_index)];
  if (cam.status.has_data) {
    const std::int64_t step = SatSub(frame.utime, cam.status.last_utime);  // > 0 (Check)
    if (options_.mode == SyncMode::kFrameIndex) {
      cam.status.lost = SatAdd(cam.status.lost,
                               std::max<std::int64_t>(0, SatSub(frame.frame, cam.last_frame) - 1));
    } else if (cam.num_steps >= cam.steps.size()) {
      std::vector<std::int64_t> steps(cam.steps.begin(), cam.steps.end());
      const std::int64_t period = LowerMedian(&steps);
      if (period > 0 && step > period + period / 2) {
        cam.status.lost = SatAdd(cam.status.lost, (step + period / 2) / period - 1);
      }
    }
    cam.steps[cam.next_step] = step;
    cam.next_step = (cam.next_step + 1) % cam.steps.size();
    cam.num_steps = std::min(cam.num_steps + 1, cam.steps.size());
  }
  ++cam.status.accepted;
  cam.status.has_data = true;
  cam.status.last_utime = frame.utime;
  cam.last_frame = frame.frame;
  const auto others = QuorumTime(camera_index, 1);
  cam.quorum_at_last = others ? others->first : frame.utime;
  if (cam.status.excluded) {
    cam.status.excluded = false;
    result->transitions.push_back(CameraTransition{cam.status.camera_id, false});
  }
  if (!stream_start_utime_) stream_start_utime_ = frame.utime;
  UpdateNow();
  auto [it, inserted] = pending_.try_emplace(key);
  Group& g = it->second;
  if (inserted) g.members.resize(cameras_.size());
  g.reference_utime = now_utime_ ? *now_utime_ : frame.utime;
  g.members[static_cast<std::size_t>(camera_index)] = std::move(frame);
  UpdateExclusions(&result->transitions);
  Release(&result->actions, /*force_all=*/false);
}

void FrameSynchronizer::UpdateExclusions(std::vector<CameraTransition>* transitions) {
  if (!now_utime_ || !stream_start_utime_) return;
  // The quorum's utimes, sorted once (and again after an exclusion): the lower median of the
  // other cameras' then costs O(log n) per camera instead of a QuorumTime each.
  std::vector<std::int64_t> sorted;
  const auto sort_quorum = [&] {
    sorted.clear();
    for (const Camera& c : cameras_) {
      if (InQuorum(c)) sorted.push_back(c.status.last_utime);
    }
    std::sort(sorted.begin(), sorted.end());
  };
  // QuorumTime(i, 1)->first: the lower median of the quorum without camera i.
  const auto others_median = [&](const Camera& c) -> std::optional<std::int64_t> {
    const bool member = InQuorum(c);
    const std::size_t m = sorted.size() - (member ? 1 : 0);
    if (m == 0) return std::nullopt;
    const std::size_t k = (m - 1) / 2;
    if (!member) return sorted[k];
    const auto p = static_cast<std::size_t>(
        std::lower_bound(sorted.begin(), sorted.end(), c.status.last_utime) - sorted.begin());
    return p > k ? sorted[k] : sorted[k + 1];
  };
  sort_quorum();
  bool changed = false;
  for (Camera& c : cameras_) {
    if (c.status.excluded) continue;
    // A camera not seen in this stream is waited for from the stream's first utime on; one
    // seen is silent once the others' quorum moved on by silent_after_us since it delivered.
    std::int64_t waited = SatSub(*now_utime_, *stream_start_utime_);
    if (c.status.has_data) {
      const std::optional<std::int64_t> others = others_median(c);
      waited = others ? SatSub(*others, c.quorum_at_last) : 0;
    }
    if (waited > options_.silent_after_us) {
      c.status.excluded = true;
      transitions->push_back(CameraTransition{c.status.camera_id, true});
      changed = true;
      sort_quorum();
    }
  }
  if (changed) UpdateNow();
}

void FrameSynchronizer::Release(std::vector<SyncAction>* actions, bool force_all) {
  while (!pending_.empty()) {
    const auto& [key, g] = *pending_.begin();
    bool complete = true;
    for (std::size_t c = 0; c < cameras_.size(); ++c) {
      if (!cameras_[c].status.excluded && !cameras_[c].status.clock_flagged &&
          !g.members[c].has_value()) {
        complete = false;
      }
    }
    // The deadline counts in the stream's time, and a frame ahead of the quorum's (one camera
    // early) is never released before the quorum gets there.
    const bool ahead = options_.mode == SyncMode::kFrameIndex ? now_frame_ && key > *now_frame_
                                                              : now_utime_ && key > *now_utime_;
    const bool deadline =
        now_utime_ && !ahead && SatSub(*now_utime_, g.reference_utime) >= options_.deadline_us;
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
      if (!cameras_[c].status.excluded && !cameras_[c].status.clock_flagged) {
        ++cameras_[c].status.missed;
      }
      continue;
    }
    SyncAction a;
    a.kind = SyncAction::Kind::kSubmit;
    a.frame = std::move(*g.members[c]);
    a.frame.frame = index;
    actions->push_back(std::move(a));
  }
}

void FrameSynchronizer::DropAhead(int camera_index) {
  // The camera's pending camera-frames farther ahead of the stream's time than the far-future
  // rule allows (accepted before the stream had a time, e.g. a first message an hour ahead)
  // belong to the timeline it left: none of the others will reach them, and releasing them
  // would publish a frame stamped in that future. Counted as far future, as they would have
  // been had the stream's time been known.
  const bool by_frame = options_.mode == SyncMode::kFrameIndex;
  Camera& cam = cameras_[static_cast<std::size_t>(camera_index)];
  const auto ci = static_cast<std::size_t>(camera_index);
  for (auto it = pending_.begin(); it != pending_.end();) {
    const bool ahead = by_frame
                           ? now_frame_ && it->first > SatAdd(*now_frame_, options_.max_frame_ahead)
                           : now_utime_ && it->first > SatAdd(*now_utime_, options_.max_future_us);
    std::optional<core::CameraFrame>& member = it->second.members[ci];
    if (ahead && member.has_value()) {
      --cam.status.accepted;  // each camera-frame is in exactly one counter
      ++cam.status.far_future;
      cam.status.detections_rejected += static_cast<std::int64_t>(member->detections.size());
      member.reset();
      const bool empty = std::none_of(it->second.members.begin(),
                                      it->second.members.end(),
                                      [](const auto& m) { return m.has_value(); });
      if (empty) {
        it = pending_.erase(it);
        continue;
      }
    }
    ++it;
  }
}

std::vector<SyncAction> FrameSynchronizer::Flush() {
  std::vector<SyncAction> actions;
  Release(&actions, /*force_all=*/true);
  now_utime_.reset();
  now_frame_.reset();
  stream_start_utime_.reset();
  last_released_key_.reset();
  for (Camera& c : cameras_) {
    c.order_rejections = 0;
    c.time_rejections = 0;
  }
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
