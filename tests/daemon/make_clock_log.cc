// Test helper of the daemon clock-fault test: copies a clean detections log (from
// mvtrack_make_sim_log, >= 3 cameras) with one camera's time broken (cameras sorted; "a" is the
// first, "b" the second; frame k counts from the log's first frame):
//
//   make_clock_log CLEAN.lcmlog OUT.lcmlog KIND
//
//   skew:US       camera a's utimes shifted by US microseconds (signed) from frame 10 on
//   first_future  camera a's message of the first frame is sent first with its utime 1 h ahead
//   stale_future  at frame 100 camera b re-sends its 99 messages of frames 1-99, then one
//                 message 1 h ahead, then goes on normally
//   burst         at frame 100 camera b re-sends its 100 messages of frames 0-99 (out of order)
//   fast_counter  camera a's frame index runs ten times fast from frame 10 on
//   drop          camera a's messages removed (the reference: the other cameras alone)
//   flood         from frame 10 on, camera a sends 9 extra messages per frame, each with 10,000
//                 box detections (~340 kB, over input.max_detections) and its utime spread over
//                 the frame period: a misconfigured publisher flooding the group
// Faults of the whole rig (every camera at once, from the middle frame of the log on, "the
// step"):
//   rig_skew:US   every camera's utimes shifted by US microseconds (an NTP step, a PTP master
//                 change)
//   rig_reset     every camera's frame index starts again at 0 (a power cycle of the rig; the
//                 utimes go on)
//   forged_stale  at frame 100 one publisher sends, in one burst, 30 stale messages for each
//                 camera id (copies of that camera's frames 0-29), then the log goes on
// Exit status 0 on success, 1 on failure, 2 on usage errors.

#include <cstdint>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "clean_log.h"
#include "core/detection.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"

namespace {

namespace transport = mvtrack::transport;
using mvtrack::core::CameraFrame;

constexpr std::int64_t kHourUs = std::int64_t{3600} * 1000000;

using Event = mvtrack::testing::CleanEvent;

int Run(int argc, char** argv) {
  if (argc != 4) {
    std::cerr
        << "usage: make_clock_log CLEAN.lcmlog OUT.lcmlog "
           "skew:US|first_future|stale_future|burst|fast_counter|drop|flood|rig_skew:US|rig_reset|"
           "forged_stale\n";
    return 2;
  }
  const std::string kind = argv[3];
  std::optional<std::int64_t> skew;
  std::optional<std::int64_t> rig_skew;
  if (kind.rfind("skew:", 0) == 0) skew = std::stoll(kind.substr(5));
  if (kind.rfind("rig_skew:", 0) == 0) rig_skew = std::stoll(kind.substr(9));
  if (!skew && !rig_skew && kind != "first_future" && kind != "stale_future" && kind != "burst" &&
      kind != "fast_counter" && kind != "drop" && kind != "flood" && kind != "rig_reset" &&
      kind != "forged_stale") {
    std::cerr << "make_clock_log: unknown kind '" << kind << "'\n";
    return 2;
  }
  std::string why;
  const mvtrack::testing::CleanLog log = mvtrack::testing::ReadCleanLog(argv[1], 3);
  const std::vector<Event>& events = log.events;
  const mvtrack::CameraId cam_a = log.cameras[0];
  const mvtrack::CameraId cam_b = log.cameras[1];
  const mvtrack::FrameIndex first = events.front().frame.frame;
  const mvtrack::FrameIndex step = (events.back().frame.frame - first) / 2;  // the rig's step
  std::vector<const Event*> b_history;
  std::map<mvtrack::CameraId, std::vector<const Event*>> history;  // forged_stale

  std::unique_ptr<transport::LogWriter> out = transport::LogWriter::Open(argv[2], &why);
  if (!out) throw std::runtime_error(why);
  auto write = [&](const Event& e, const CameraFrame& f) {
    if (!out->Write(
            e.channel, e.time_us, transport::EncodeCameraDetections(f, e.width, e.height), &why)) {
      throw std::runtime_error(why);
    }
  };
  bool first_sent = false;
  for (const Event& e : events) {
    const std::int64_t k = e.frame.frame - first;
    const mvtrack::CameraId cam = e.frame.camera_id;
    CameraFrame f = e.frame;
    if (kind == "first_future" && !first_sent) {
      CameraFrame ahead = f;
      ahead.camera_id = cam_a;
      ahead.utime += kHourUs;
      write(e, ahead);
      first_sent = true;
    }
    if (cam == cam_b && k == 100 && (kind == "stale_future" || kind == "burst")) {
      const std::size_t from = kind == "burst" ? 0 : 1;
      for (std::size_t i = from; i < b_history.size() && i < 100; ++i) {
        write(*b_history[i], b_history[i]->frame);
      }
      if (kind == "stale_future") {
        CameraFrame ahead = f;
        ahead.utime += kHourUs;
        write(e, ahead);
      }
    }
    if (cam == cam_b) b_history.push_back(&e);
    if (kind == "forged_stale" && k == 100 && cam == cam_a) {
      // One publisher, one burst: 30 stale messages for every camera id.
      for (const auto& [id, frames] : history) {
        for (std::size_t i = 0; i < frames.size() && i < 30; ++i)
          write(*frames[i], frames[i]->frame);
      }
    }
    history[cam].push_back(&e);
    if (k >= step) {
      if (rig_skew) f.utime += *rig_skew;
      if (kind == "rig_reset") f.frame = k - step;
    }
    if (cam == cam_a && kind == "flood" && k >= 10) {
      for (int copy = 1; copy <= 9; ++copy) {
        CameraFrame big = f;
        big.utime += copy * 3000;
        big.detections.assign(10000, mvtrack::core::Detection2D{});
        for (std::size_t i = 0; i < big.detections.size(); ++i) {
          const double x = static_cast<double>(i % 100) * 10.0;
          big.detections[i].box = {x, 100.0, x + 8.0, 120.0};
        }
        write(e, big);
      }
    }
    if (cam == cam_a) {
      if (kind == "drop") continue;
      if (skew && k >= 10) f.utime += *skew;
      if (kind == "fast_counter" && k >= 10) f.frame = first + 10 + (k - 10) * 10;
    }
    write(e, f);
  }
  if (!out->Flush(&why)) throw std::runtime_error(why);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "make_clock_log: " << e.what() << "\n";
    return 1;
  }
}
