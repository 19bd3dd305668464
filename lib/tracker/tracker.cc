#include "tracker/tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/check.h"

namespace mvtrack::tracker {
namespace {

int JointIndex(const core::KeypointLayout& layout, const char* name) {
  for (int i = 0; i < layout.num_joints(); ++i) {
    if (layout.joints[static_cast<std::size_t>(i)] == name) return i;
  }
  return -1;
}

}  // namespace

const char* ToString(FrameRejection rejection) {
  switch (rejection) {
    case FrameRejection::kNone: return "none";
    case FrameRejection::kUnknownCamera: return "unknown_camera";
    case FrameRejection::kStaleFrame: return "stale_frame";
    case FrameRejection::kDuplicateCamera: return "duplicate_camera";
    case FrameRejection::kTooManyDetections: return "too_many_detections";
  }
  return "?";
}

bool TrackerOptions::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (window_size < 2 || window_size > 10000) return fail("window_size (ν) must be in [2, 10000]");
  if (window_step < 1 || window_step > window_size) {
    return fail("window_step (δ) must be in [1, window_size]");
  }
  if (mode == InputMode::kPoses &&
      (layout == core::KeypointLayoutId::kNone || core::GetKeypointLayout(layout).num_joints() == 0)) {
    return fail("pose mode needs a keypoint layout");
  }
  if (!std::isfinite(ground_height_m)) return fail("ground_height_m must be finite");
  if (!(min_detection_score >= 0.0 && min_detection_score <= 1.0)) {
    return fail("min_detection_score must be in [0, 1]");
  }
  if (!(min_keypoint_confidence >= 0.0 && min_keypoint_confidence <= 1.0)) {
    return fail("min_keypoint_confidence must be in [0, 1]");
  }
  if (min_pose_keypoints < 1) return fail("min_pose_keypoints must be >= 1");
  if (min_tracklet_length < 1) return fail("min_tracklet_length must be >= 1");
  if (max_frame_jump < window_size) return fail("max_frame_jump must be >= window_size");
  if (!(box_margin_fraction >= 0.0 && box_margin_fraction <= 10.0)) {
    return fail("box_margin_fraction must be in [0, 10]");
  }
  if (max_detections_per_frame < 1) return fail("max_detections_per_frame must be >= 1");
  std::string nested;
  if (!sort.Validate(&nested)) return fail("sort: " + nested);
  if (!association.Validate(&nested)) return fail("association: " + nested);
  if (!triangulation.Validate(&nested)) return fail("triangulation: " + nested);
  if (!linking.Validate(&nested)) return fail("linking: " + nested);
  return true;
}

std::unique_ptr<Tracker> Tracker::Create(geometry::CameraRig rig, TrackerOptions options,
                                         std::string* why) {
  if (!options.Validate(why)) return nullptr;
  if (rig.size() < 2) {
    if (why != nullptr) {
      *why = "the camera rig has " + std::to_string(rig.size()) +
             " camera(s); at least 2 are needed to triangulate";
    }
    return nullptr;
  }
  return std::unique_ptr<Tracker>(new Tracker(std::move(rig), std::move(options)));
}

Tracker::Tracker(geometry::CameraRig rig, TrackerOptions options)
    : rig_(std::move(rig)), options_(std::move(options)), linker_(options_.linking) {
  num_points_ = options_.mode == InputMode::kPoses
                    ? core::GetKeypointLayout(options_.layout).num_joints()
                    : 1;
  for (int i = 0; i < rig_.size(); ++i) cameras_.push_back(CameraState{tracking2d::SortTracker(options_.sort), {}, {}});
  open_cameras_.assign(static_cast<std::size_t>(rig_.size()), false);
  if (options_.mode == InputMode::kPoses) {
    for (core::KeypointLayoutId from : core::AllKeypointLayouts()) {
      mappings_[from] = core::MakeKeypointMapping(from, options_.layout);
    }
  }
}

std::optional<core::Observation2D> Tracker::MakeObservation(const geometry::CameraModel& camera,
                                                            const core::Detection2D& detection,
                                                            core::BoxPx* sort_box) const {
  if (detection.score < options_.min_detection_score) return std::nullopt;
  core::Observation2D obs;
  if (options_.mode == InputMode::kBoxes) {
    const Vec2 raw = options_.box_point == BoxPoint::kCenter ? detection.box.center()
                                                             : detection.box.bottom_center();
    obs.points_px.push_back(camera.UndistortPixel(raw));
    obs.confidence.push_back(1.0);
    obs.scale_px = detection.box.width() + detection.box.height();
    *sort_box = detection.box;
    return obs;
  }
  // Pose mode: map the detector's layout to ours, undistorting each source keypoint first.
  auto it = mappings_.find(detection.layout);
  if (it == mappings_.end() || detection.keypoints.empty()) return std::nullopt;
  const core::KeypointMapping& mapping = it->second;
  const double min_conf = options_.min_keypoint_confidence;
  obs.points_px.assign(static_cast<std::size_t>(num_points_), Vec2::Zero());
  obs.confidence.assign(static_cast<std::size_t>(num_points_), 0.0);
  int usable = 0;
  for (std::size_t j = 0; j < mapping.targets.size(); ++j) {
    const auto& sources = mapping.targets[j];
    if (sources.empty()) continue;
    Vec2 sum = Vec2::Zero();
    double conf = 1.0;
    for (const core::JointSource& s : sources) {
      const core::Keypoint2D& kp = detection.keypoints[static_cast<std::size_t>(s.source_joint)];
      conf = std::min(conf, kp.confidence);
      if (conf < min_conf) break;
      sum += s.weight * camera.UndistortPixel(kp.position_px);
    }
    if (conf < min_conf) continue;
    obs.points_px[j] = sum;
    obs.confidence[j] = conf;
    ++usable;
  }
  if (usable < options_.min_pose_keypoints) return std::nullopt;
  // The pose's box encloses its usable (raw) keypoints.
  core::BoxPx box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const core::Keypoint2D& kp : detection.keypoints) {
    if (kp.confidence < min_conf) continue;
    box.x_min = std::min(box.x_min, kp.position_px.x());
    box.y_min = std::min(box.y_min, kp.position_px.y());
    box.x_max = std::max(box.x_max, kp.position_px.x());
    box.y_max = std::max(box.y_max, kp.position_px.y());
  }
  if (!(box.width() + box.height() > 1.0)) return std::nullopt;
  obs.scale_px = box.width() + box.height();
  *sort_box = box;
  return obs;
}

AddResult Tracker::Add(const core::CameraFrame& frame) {
  AddResult result;
  auto reject = [&](FrameRejection why, std::string reason) {
    result.rejection = why;
    result.reason = std::move(reason);
    ++stats_.camera_frames_rejected;
    ++stats_.rejections[why];
    return result;
  };
  const std::optional<int> index = rig_.IndexOf(frame.camera_id);
  if (!index) {
    return reject(FrameRejection::kUnknownCamera,
                  "camera " + std::to_string(frame.camera_id) + " is not in the rig");
  }
  const auto cam = static_cast<std::size_t>(*index);
  if (static_cast<std::int64_t>(frame.detections.size()) > options_.max_detections_per_frame) {
    return reject(FrameRejection::kTooManyDetections,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + ": " + std::to_string(frame.detections.size()) +
                      " detections > max_detections_per_frame " +
                      std::to_string(options_.max_detections_per_frame));
  }
  if (open_frame_ && frame.frame < *open_frame_) {
    return reject(FrameRejection::kStaleFrame,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + " is older than the open frame " +
                      std::to_string(*open_frame_));
  }
  if (!open_frame_ && last_closed_frame_ && frame.frame <= *last_closed_frame_) {
    return reject(FrameRejection::kStaleFrame,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + " is not newer than the last closed frame " +
                      std::to_string(*last_closed_frame_));
  }
  if (open_frame_ && frame.frame == *open_frame_ && open_cameras_[cam]) {
    return reject(FrameRejection::kDuplicateCamera,
                  "camera " + std::to_string(frame.camera_id) + " already delivered frame " +
                      std::to_string(frame.frame));
  }

  // A later frame closes the open one (and a large jump re-anchors the window grid).
  if (open_frame_ && frame.frame > *open_frame_) {
    CloseOpenFrame(&result.finalized);
  }
  if (last_closed_frame_ && frame.frame - *last_closed_frame_ > options_.max_frame_jump) {
    Reanchor(&result.finalized);
  }
  if (!open_frame_) {
    open_frame_ = frame.frame;
    open_utime_ = frame.utime;
    std::fill(open_cameras_.begin(), open_cameras_.end(), false);
    if (!grid_origin_) grid_origin_ = frame.frame;
    // Frames skipped since the last closed one complete the windows that end before this one.
    ProcessWindowsUpTo(frame.frame - 1, /*flushing=*/false, &result.finalized);
  }
  open_cameras_[cam] = true;
  open_utime_ = std::min(open_utime_, frame.utime);
  ++stats_.camera_frames_accepted;

  // Validate, convert, and run this camera's SORT.
  const geometry::CameraModel& camera = rig_.camera(*index);
  core::DetectionLimits limits;
  limits.image_width_px = camera.width_px;
  limits.image_height_px = camera.height_px;
  limits.box_margin_fraction = options_.box_margin_fraction;
  std::vector<core::BoxPx> boxes;
  std::vector<core::Observation2D> observations;
  boxes.reserve(frame.detections.size());
  observations.reserve(frame.detections.size());
  for (const core::Detection2D& original : frame.detections) {
    core::Detection2D detection = original;
    const core::DetectionCheck check = core::ValidateDetection(&detection, limits);
    if (check.verdict == core::DetectionVerdict::kRejected) {
      ++result.detections_rejected;
      if (result.reason.empty()) result.reason = check.reason;
      continue;
    }
    if (check.verdict == core::DetectionVerdict::kAcceptedRepaired) ++result.detections_repaired;
    core::BoxPx sort_box;
    std::optional<core::Observation2D> obs = MakeObservation(camera, detection, &sort_box);
    if (!obs) {
      ++result.detections_filtered;
      continue;
    }
    boxes.push_back(sort_box);
    observations.push_back(std::move(*obs));
  }
  CameraState& state = cameras_[cam];
  const std::vector<tracking2d::TrackedDetection> tracked = state.sort.Update(frame.frame, boxes);
  state.last_frame = frame.frame;
  for (const tracking2d::TrackedDetection& td : tracked) {
    state.tracks[td.track_id].push_back(
        TimedObservation{frame.frame, observations[static_cast<std::size_t>(td.detection_index)]});
  }
  result.detections_used = static_cast<int>(observations.size());
  stats_.detections_used += result.detections_used;
  stats_.detections_rejected += result.detections_rejected;
  stats_.detections_repaired += result.detections_repaired;
  stats_.detections_filtered += result.detections_filtered;
  return result;
}

void Tracker::CloseOpenFrame(std::vector<Frame3D>* out) {
  if (!open_frame_) return;
  const FrameIndex f = *open_frame_;
  pending_[f] = PendingFrame{f, open_utime_, {}, false};
  last_closed_frame_ = f;
  open_frame_.reset();
  ProcessWindowsUpTo(f, /*flushing=*/false, out);
}

void Tracker::ProcessWindowsUpTo(FrameIndex complete_through, bool flushing,
                                 std::vector<Frame3D>* out) {
  if (!grid_origin_) return;
  const FrameIndex origin = *grid_origin_;
  const std::int64_t nu = options_.window_size;
  const std::int64_t delta = options_.window_step;
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
    ProcessWindow(window_id_offset_ + next_window_, begin, complete ? end : *last_closed_frame_ + 1,
                  finalize_from, finalize_to, out);
    ++next_window_;
  }
}

Vec3 Tracker::FootprintOf(const std::vector<std::optional<Vec3>>& points) const {
  Vec3 p = Vec3::Zero();
  if (options_.mode == InputMode::kPoses) {
    const core::KeypointLayout& layout = core::GetKeypointLayout(options_.layout);
    const int lh = JointIndex(layout, "l_hip");
    const int rh = JointIndex(layout, "r_hip");
    if (lh >= 0 && rh >= 0 && points[static_cast<std::size_t>(lh)] &&
        points[static_cast<std::size_t>(rh)]) {
      p = 0.5 * (*points[static_cast<std::size_t>(lh)] + *points[static_cast<std::size_t>(rh)]);
    } else {
      int n = 0;
      for (const auto& q : points) {
        if (q) {
          p += *q;
          ++n;
        }
      }
      if (n > 0) p /= n;
    }
  } else if (!points.empty() && points.front()) {
    p = *points.front();
  }
  p.z() = options_.ground_height_m;
  return p;
}

void Tracker::ProcessWindow(std::int64_t window_id, FrameIndex begin, FrameIndex end,
                            FrameIndex finalize_from, FrameIndex finalize_to,
                            std::vector<Frame3D>* out) {
  WindowOutput w;
  w.window_id = window_id;
  w.begin = begin;
  w.end = end;
  // 1. Crop every camera's 2D tracks to the window (cameras in rig order, tracks by id).
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    for (const auto& [track_id, observations] : cameras_[c].tracks) {
      core::Tracklet2D t;
      t.camera_id = rig_.camera(static_cast<int>(c)).id;
      t.track_id = track_id;
      for (const TimedObservation& o : observations) {
        if (o.frame < begin || o.frame >= end) continue;
        t.frames.push_back(o.frame);
        t.observations.push_back(o.observation);
      }
      if (static_cast<int>(t.frames.size()) >= options_.min_tracklet_length) {
        w.tracklets.push_back(std::move(t));
      }
    }
  }
  // 2. Cross-view association (Eq. 2-4, PDNC).
  w.clusters = association::AssociateTracklets(rig_, w.tracklets, options_.association);
  // 3. CMMT per person seen by at least two cameras.
  for (const std::vector<int>& cluster : w.clusters) {
    std::vector<CameraId> cams;
    for (int i : cluster) cams.push_back(w.tracklets[static_cast<std::size_t>(i)].camera_id);
    std::sort(cams.begin(), cams.end());
    if (std::unique(cams.begin(), cams.end()) - cams.begin() < 2) continue;
    core::Tracklet3D person = triangulation::TriangulatePerson(
        rig_, w.tracklets, cluster, begin, end, num_points_, options_.triangulation);
    if (!person.frames.empty()) w.persons.push_back(std::move(person));
  }
  // 4. Link to long-term tracks (Eq. 8-9).
  w.link = linker_.Link(window_id, w.persons);
  stats_.windows_processed += 1;
  stats_.tracks_born += static_cast<std::int64_t>(w.link.born.size());
  std::map<TrackId3D, const linking::LinkedTrack*> alive;
  for (const linking::LinkedTrack& t : linker_.tracks()) alive[t.id] = &t;
  for (std::size_t i = 0; i < w.persons.size(); ++i) {
    const core::Tracklet3D& person = w.persons[i];
    const TrackId3D id = w.link.track_of_tracklet[i];
    auto first = first_frame_of_track_.try_emplace(id, person.frames.front()).first;
    first->second = std::min(first->second, person.frames.front());
    auto it = alive.find(id);
    if (it == alive.end() || it->second->state == linking::TrackState::kTentative) continue;
    for (std::size_t f = 0; f < person.frames.size(); ++f) {
      const FrameIndex frame = person.frames[f];
      if (frame < finalize_from || frame >= finalize_to) continue;
      auto pending = pending_.find(frame);
      if (pending == pending_.end() || pending->second.final) continue;
      Track3D track;
      track.id = id;
      const auto& points = person.points[f];
      int valid = 0;
      for (const auto& p : points) valid += p ? 1 : 0;
      if (valid == 0) continue;
      if (options_.mode == InputMode::kPoses) track.joints = points;
      track.position = FootprintOf(points);
      track.confidence = static_cast<double>(valid) / static_cast<double>(num_points_);
      track.cameras = person.cameras;
      track.age_frames = frame - first->second;
      track.state = it->second->state;
      pending->second.tracks.push_back(std::move(track));
    }
  }
  for (TrackId3D id : w.link.died) first_frame_of_track_.erase(id);
  for (auto& [frame, p] : pending_) {
    if (frame >= finalize_from && frame < finalize_to) p.final = true;
  }
  EmitFinal(finalize_to, out);

  // Trim observations no later window needs.
  const FrameIndex keep_from = begin + options_.window_step;
  for (CameraState& cs : cameras_) {
    for (auto it = cs.tracks.begin(); it != cs.tracks.end();) {
      auto& obs = it->second;
      obs.erase(obs.begin(), std::find_if(obs.begin(), obs.end(), [&](const TimedObservation& o) {
                  return o.frame >= keep_from;
                }));
      it = obs.empty() ? cs.tracks.erase(it) : std::next(it);
    }
  }
  last_window_ = std::move(w);
}

void Tracker::EmitFinal(FrameIndex up_to, std::vector<Frame3D>* out) {
  while (!pending_.empty() && pending_.begin()->first < up_to) {
    PendingFrame& p = pending_.begin()->second;
    Frame3D f;
    f.frame = p.frame;
    f.utime = p.utime;
    f.tracks = std::move(p.tracks);
    std::sort(f.tracks.begin(), f.tracks.end(),
              [](const Track3D& a, const Track3D& b) { return a.id < b.id; });
    out->push_back(std::move(f));
    ++stats_.frames_finalized;
    pending_.erase(pending_.begin());
  }
}

void Tracker::Reanchor(std::vector<Frame3D>* out) {
  EndStream(out);
  ++stats_.reanchors;
}

void Tracker::EndStream(std::vector<Frame3D>* out) {
  ProcessWindowsUpTo(last_closed_frame_ ? *last_closed_frame_ : 0, /*flushing=*/true, out);
  if (last_closed_frame_) EmitFinal(*last_closed_frame_ + 1, out);
  // A gap of more than max_missed_windows windows ends every live track in the linker.
  window_id_offset_ += next_window_ + options_.linking.max_missed_windows + 2;
  next_window_ = 0;
  grid_origin_.reset();
  last_closed_frame_.reset();
  for (CameraState& cs : cameras_) cs = CameraState{tracking2d::SortTracker(options_.sort), {}, {}};
}

std::vector<Frame3D> Tracker::Flush() {
  std::vector<Frame3D> out;
  if (open_frame_) {
    const FrameIndex f = *open_frame_;
    pending_[f] = PendingFrame{f, open_utime_, {}, false};
    last_closed_frame_ = f;
    open_frame_.reset();
  }
  if (last_closed_frame_) EndStream(&out);
  return out;
}

}  // namespace mvtrack::tracker
