#include "tracker/frame_gate.h"

#include <algorithm>
#include <utility>

namespace mvtrack::tracker {

FrameGate::FrameGate(const geometry::CameraRig& rig, const TrackerOptions& options)
    : max_detections_per_frame_(options.max_detections_per_frame),
      max_frame_jump_(options.max_frame_jump) {
  for (int i = 0; i < rig.size(); ++i) index_of_camera_[rig.camera(i).id] = i;
  open_cameras_.assign(static_cast<std::size_t>(rig.size()), false);
}

FrameAdmission FrameGate::Admit(const core::CameraFrame& frame) {
  FrameAdmission a;
  auto reject = [&](FrameRejection why, std::string reason) {
    a.rejection = why;
    a.reason = std::move(reason);
    a.stream_epoch = stream_epoch_;
    return a;
  };
  const auto known = index_of_camera_.find(frame.camera_id);
  if (known == index_of_camera_.end()) {
    return reject(FrameRejection::kUnknownCamera,
                  "camera " + std::to_string(frame.camera_id) + " is not in the rig");
  }
  a.camera_index = known->second;
  const auto cam = static_cast<std::size_t>(known->second);
  if (static_cast<std::int64_t>(frame.detections.size()) > max_detections_per_frame_) {
    return reject(FrameRejection::kTooManyDetections,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + ": " + std::to_string(frame.detections.size()) +
                      " detections > max_detections_per_frame " +
                      std::to_string(max_detections_per_frame_));
  }
  if (frame.frame < 0 || frame.frame > kMaxFrameIndex) {
    return reject(FrameRejection::kBadFrameIndex,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + " is outside [0, 2^53]");
  }
  if (open_frame_ && frame.frame < *open_frame_) {
    return reject(FrameRejection::kStaleFrame,
                  "camera " + std::to_string(frame.camera_id) + " frame " +
                      std::to_string(frame.frame) + " is older than the open frame " +
                      std::to_string(*open_frame_));
  }
  if (!open_frame_ && last_closed_frame_ && closed_complete_ &&
      frame.frame == *last_closed_frame_) {
    return reject(FrameRejection::kDuplicateCamera,
                  "camera " + std::to_string(frame.camera_id) + " already delivered frame " +
                      std::to_string(frame.frame));
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
    a.events.close_open_frame = true;
    last_closed_frame_ = *open_frame_;
    closed_complete_ = false;
    open_frame_.reset();
  }
  if (last_closed_frame_ && frame.frame - *last_closed_frame_ > max_frame_jump_) {
    a.events.reanchor = true;
    last_closed_frame_.reset();
    ++stream_epoch_;
  }
  if (!open_frame_) {
    a.events.open_frame = true;
    open_frame_ = frame.frame;
    std::fill(open_cameras_.begin(), open_cameras_.end(), false);
  }
  open_cameras_[cam] = true;
  if (std::all_of(open_cameras_.begin(), open_cameras_.end(), [](bool d) { return d; })) {
    a.events.close_after = true;
    last_closed_frame_ = *open_frame_;
    closed_complete_ = true;
    open_frame_.reset();
  }
  a.stream_epoch = stream_epoch_;
  return a;
}

bool FrameGate::Flush() {
  if (open_frame_) {
    last_closed_frame_ = *open_frame_;
    open_frame_.reset();
  }
  closed_complete_ = false;
  if (!last_closed_frame_) return false;
  last_closed_frame_.reset();
  ++stream_epoch_;
  return true;
}

}  // namespace mvtrack::tracker
