// camera_detections_t <-> core::CameraFrame.

#include <climits>
#include <cstdint>
#include <exception>
#include <mvtrack/camera_detections_t.hpp>
#include <mvtrack/detection_t.hpp>
#include <mvtrack/keypoint2d_t.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "core/keypoint_layout.h"
#include "transport/codec.h"
#include "transport/internal/wire_walker.h"

namespace mvtrack::transport {
namespace {

using internal::kFloatBytes;
using internal::kInt16Bytes;
using internal::kInt32Bytes;
using internal::kInt64Bytes;
using internal::WireWalker;

// Smallest encodings (lcmtypes/README.md): keypoint2d_t = 3 floats; detection_t = 5 floats,
// two empty strings (4-byte length + NUL) and two int16 counts.
constexpr std::size_t kKeypointBytes = 3 * kFloatBytes;
constexpr std::size_t kEmptyStringBytes = kInt32Bytes + 1;
constexpr std::size_t kMinDetectionBytes =
    5 * kFloatBytes + 2 * kEmptyStringBytes + 2 * kInt16Bytes;

using internal::LayoutOfName;

// Walks one detection_t (without fingerprint; nested types carry none).
bool WalkDetection(WireWalker* w, const DecodeLimits& limits) {
  w->Skip("box and score", 5 * kFloatBytes);
  const std::size_t layout_at = w->position();
  std::string_view layout;
  if (!w->ReadString("keypoint_layout", limits.max_string, &layout)) return false;
  if (!LayoutOfName(layout)) {
    return w->Fail(DecodeStatus::kMalformed,
                   "unknown keypoint_layout \"" + std::string(layout) + "\"",
                   layout_at);
  }
  std::int32_t num_keypoints = 0;
  if (!w->ReadCount16("num_keypoints", limits.max_keypoints, kKeypointBytes, &num_keypoints)) {
    return false;
  }
  w->Skip("keypoints", static_cast<std::size_t>(num_keypoints) * kKeypointBytes);
  std::string_view model;
  if (!w->ReadString("embedding_model", limits.max_string, &model)) return false;
  std::int32_t num_embedding = 0;
  if (!w->ReadCount16("num_embedding", limits.max_embedding, kFloatBytes, &num_embedding)) {
    return false;
  }
  return w->Skip("embedding", static_cast<std::size_t>(num_embedding) * kFloatBytes);
}

// Walks a whole camera_detections_t message; on failure the walker holds status and reason.
bool WalkCameraDetections(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(w,
                                 mvtrack::camera_detections_t::getHash(),
                                 mvtrack::camera_detections_t::getTypeName())) {
    return false;
  }
  w->Skip("utime", kInt64Bytes);
  w->Skip("frame", kInt64Bytes);
  w->Skip("camera_id", kInt32Bytes);
  w->Skip("image_width", kInt32Bytes);
  w->Skip("image_height", kInt32Bytes);
  std::int32_t num_detections = 0;
  if (!w->ReadCount32(
          "num_detections", limits.max_detections, kMinDetectionBytes, &num_detections)) {
    return false;
  }
  for (std::int32_t i = 0; i < num_detections; ++i) {
    w->set_context("detection " + std::to_string(i));
    if (!WalkDetection(w, limits)) return false;
  }
  w->set_context("");
  if (w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return true;
}

core::Detection2D ToDetection2D(const mvtrack::detection_t& d) {
  core::Detection2D det;
  det.box.x_min = static_cast<double>(d.x_min);
  det.box.y_min = static_cast<double>(d.y_min);
  det.box.x_max = static_cast<double>(d.x_max);
  det.box.y_max = static_cast<double>(d.y_max);
  det.score = static_cast<double>(d.score);
  // The walk accepted the name, so it is known.
  det.layout = LayoutOfName(d.keypoint_layout).value_or(core::KeypointLayoutId::kNone);
  det.keypoints.reserve(d.keypoints.size());
  for (const mvtrack::keypoint2d_t& kp : d.keypoints) {
    core::Keypoint2D keypoint;
    keypoint.position_px = Vec2(static_cast<double>(kp.x), static_cast<double>(kp.y));
    keypoint.confidence = static_cast<double>(kp.confidence);
    det.keypoints.push_back(keypoint);
  }
  det.embedding = d.embedding;
  det.embedding_model = d.embedding_model;
  return det;
}

}  // namespace

DecodeResult DecodeCameraDetections(const void* data,
                                    std::size_t size,
                                    const DecodeLimits& limits) {
  DecodeResult result;
  const auto convert = [&](const mvtrack::camera_detections_t& msg) {
    result.frame.utime = msg.utime;
    result.frame.frame = msg.frame;
    result.frame.camera_id = msg.camera_id;
    result.image_width_px = msg.image_width;
    result.image_height_px = msg.image_height;
    result.frame.detections.reserve(msg.detections.size());
    for (const mvtrack::detection_t& d : msg.detections) {
      result.frame.detections.push_back(ToDetection2D(d));
    }
  };
  if (!internal::CheckedDecode<mvtrack::camera_detections_t>(
          data, size, limits, WalkCameraDetections, convert, &result.status, &result.reason)) {
    DecodeResult failed;  // nothing partially converted leaks out
    failed.status = result.status;
    failed.reason = std::move(result.reason);
    return failed;
  }
  return result;
}

std::vector<std::uint8_t> EncodeCameraDetections(const core::CameraFrame& frame,
                                                 int image_width_px,
                                                 int image_height_px) {
  using internal::NarrowToFloat;
  MVTRACK_CHECK_MSG(frame.detections.size() <= static_cast<std::size_t>(INT32_MAX),
                    "too many detections for camera_detections_t");
  mvtrack::camera_detections_t msg;
  msg.utime = frame.utime;
  msg.frame = frame.frame;
  msg.camera_id = frame.camera_id;
  msg.image_width = image_width_px;
  msg.image_height = image_height_px;
  msg.num_detections = static_cast<std::int32_t>(frame.detections.size());
  msg.detections.reserve(frame.detections.size());
  for (const core::Detection2D& det : frame.detections) {
    MVTRACK_CHECK_MSG(det.keypoints.size() <= static_cast<std::size_t>(INT16_MAX),
                      "too many keypoints for detection_t");
    MVTRACK_CHECK_MSG(det.embedding.size() <= static_cast<std::size_t>(INT16_MAX),
                      "embedding too long for detection_t");
    mvtrack::detection_t d;
    d.x_min = NarrowToFloat(det.box.x_min);
    d.y_min = NarrowToFloat(det.box.y_min);
    d.x_max = NarrowToFloat(det.box.x_max);
    d.y_max = NarrowToFloat(det.box.y_max);
    d.score = NarrowToFloat(det.score);
    d.keypoint_layout = det.layout == core::KeypointLayoutId::kNone
                            ? std::string()
                            : core::GetKeypointLayout(det.layout).name;
    d.num_keypoints = static_cast<std::int16_t>(det.keypoints.size());
    d.keypoints.reserve(det.keypoints.size());
    for (const core::Keypoint2D& kp : det.keypoints) {
      mvtrack::keypoint2d_t k;
      k.x = NarrowToFloat(kp.position_px.x());
      k.y = NarrowToFloat(kp.position_px.y());
      k.confidence = NarrowToFloat(kp.confidence);
      d.keypoints.push_back(k);
    }
    d.embedding_model = det.embedding.empty() ? std::string() : det.embedding_model;
    d.num_embedding = static_cast<std::int16_t>(det.embedding.size());
    d.embedding = det.embedding;
    msg.detections.push_back(std::move(d));
  }
  return internal::EncodeMessage(msg);
}

}  // namespace mvtrack::transport
