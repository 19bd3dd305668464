#pragma once
// Shared by the daemon tests' log writers (make_fault_log.cc, make_clock_log.cc): the
// camera_detections_t messages of a clean recording, decoded, in log order.

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/detection.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"

namespace mvtrack::testing {

/// One detections message of the clean log.
struct CleanEvent {
  std::string channel;
  std::int64_t time_us = 0;
  std::vector<std::uint8_t> data;
  core::CameraFrame frame;
  int width = 0, height = 0;
};

/// The clean log's detections messages and its cameras (sorted).
struct CleanLog {
  std::vector<CleanEvent> events;
  std::vector<CameraId> cameras;
};

/// Reads `path`; throws std::runtime_error on a bad message or fewer than `min_cameras`.
inline CleanLog ReadCleanLog(const std::string& path, std::size_t min_cameras) {
  std::string why;
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(path, &why);
  if (!reader) throw std::runtime_error(why);
  CleanLog log;
  std::map<CameraId, bool> cameras;
  while (std::optional<transport::LogEvent> e = reader->Next()) {
    if (!transport::IsDetectionsChannel(e->channel)) continue;
    transport::DecodeResult d = transport::DecodeCameraDetections(e->data.data(), e->data.size());
    if (!d.ok()) throw std::runtime_error("the clean log has a bad message: " + d.reason);
    cameras[d.frame.camera_id] = true;
    log.events.push_back(CleanEvent{e->channel,
                                    e->timestamp_us,
                                    std::move(e->data),
                                    std::move(d.frame),
                                    d.image_width_px,
                                    d.image_height_px});
  }
  for (const auto& [id, unused] : cameras) log.cameras.push_back(id);
  if (log.events.empty() || log.cameras.size() < min_cameras) {
    throw std::runtime_error("need a log of >= " + std::to_string(min_cameras) + " cameras");
  }
  return log;
}

}  // namespace mvtrack::testing
