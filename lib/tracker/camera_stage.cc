#include "tracker/camera_stage.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "core/check.h"

namespace mvtrack::tracker {

CameraStage::CameraStage(geometry::CameraModel camera, int camera_index,
                         const TrackerOptions& options)
    : camera_(std::move(camera)),
      camera_index_(camera_index),
      options_(options),
      num_points_(NumPoints(options)),
      sort_(options.sort) {
  if (options_.mode == InputMode::kPoses) {
    for (core::KeypointLayoutId from : core::AllKeypointLayouts()) {
      mappings_[from] = core::MakeKeypointMapping(from, options_.layout);
    }
  }
}

std::optional<core::Observation2D> CameraStage::MakeObservation(
    const core::Detection2D& detection, core::BoxPx* sort_box) const {
  if (detection.score < options_.min_detection_score) return std::nullopt;
  core::Observation2D obs;
  if (options_.mode == InputMode::kBoxes) {
    const Vec2 raw = options_.box_point == BoxPoint::kCenter ? detection.box.center()
                                                             : detection.box.bottom_center();
    obs.points_px.push_back(camera_.UndistortPixel(raw));
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
      sum += s.weight * camera_.UndistortPixel(kp.position_px);
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

TrackedCameraFrame CameraStage::Process(const core::CameraFrame& frame, std::int64_t stream_epoch,
                                        CameraStageCounters* counters) {
  MVTRACK_CHECK(counters != nullptr);
  MVTRACK_CHECK_MSG(stream_epoch >= stream_epoch_, "stream epochs must not decrease");
  *counters = CameraStageCounters{};
  if (stream_epoch != stream_epoch_) {
    // The stream ended (re-anchor or flush) since this camera's last frame: SORT restarts.
    sort_ = tracking2d::SortTracker(options_.sort);
    stream_epoch_ = stream_epoch;
  }
  core::DetectionLimits limits;
  limits.image_width_px = camera_.width_px;
  limits.image_height_px = camera_.height_px;
  limits.box_margin_fraction = options_.box_margin_fraction;
  std::vector<core::BoxPx>& boxes = boxes_;
  std::vector<core::Observation2D>& observations = observations_;
  boxes.clear();
  observations.clear();
  boxes.reserve(frame.detections.size());
  observations.reserve(frame.detections.size());
  for (const core::Detection2D& original : frame.detections) {
    core::Detection2D detection = original;
    const core::DetectionCheck check = core::ValidateDetection(&detection, limits);
    if (check.verdict == core::DetectionVerdict::kRejected) {
      ++counters->detections_rejected;
      if (counters->first_rejection_reason.empty()) counters->first_rejection_reason = check.reason;
      continue;
    }
    if (check.verdict == core::DetectionVerdict::kAcceptedRepaired) ++counters->detections_repaired;
    core::BoxPx sort_box;
    std::optional<core::Observation2D> obs = MakeObservation(detection, &sort_box);
    if (!obs) {
      ++counters->detections_filtered;
      continue;
    }
    boxes.push_back(sort_box);
    observations.push_back(std::move(*obs));
  }
  counters->detections_used = static_cast<int>(observations.size());

  TrackedCameraFrame out;
  out.camera_index = camera_index_;
  out.frame = frame.frame;
  out.utime = frame.utime;
  const std::vector<tracking2d::TrackedDetection> tracked = sort_.Update(frame.frame, boxes);
  out.observations.reserve(tracked.size());
  // Each detection belongs to at most one track, so its observation can be moved out.
  for (const tracking2d::TrackedDetection& td : tracked) {
    out.observations.emplace_back(
        td.track_id, std::move(observations[static_cast<std::size_t>(td.detection_index)]));
  }
  return out;
}

}  // namespace mvtrack::tracker
