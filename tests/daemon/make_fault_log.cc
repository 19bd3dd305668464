// Test helper of the daemon fault-injection test: copies a clean detections log (from
// mvtrack_make_sim_log) and injects bad input around the good messages, which all stay in
// place and unchanged except for extra invalid detections appended to some of them:
//
//   make_fault_log CLEAN.lcmlog OUT.lcmlog COUNTS.txt
//
// Injected (frame indices count from the log's first frame; cameras are the log's, sorted):
//   truncated     every 10th frame: a copy of the first camera's message cut to half its size
//   foreign       every 10th frame (+3): a tracks3d_t (another type) on the second camera's
//                 detections channel
//   oversized     frame 100: 10,000 detections in one message of the first camera, before its
//                 genuine message (over the daemon's max_detections: rejected at decode)
//   nan           every 7th frame: the second camera's message gets a detection with a NaN box
//                 and one with an infinite score
//   outside       every 7th frame (+2): the third camera's message gets a box far outside the
//                 image
//   unknown       every 25th frame: a camera-frame of camera 77 (not in the calibration)
//   flood         frames 120-159: the third camera sends 9 extra copies of each message (10x
//                 its rate) with the same frame index and utimes spread over the frame period
//   backwards     frames 60-64: the second camera re-sends its message of 30 frames earlier
//   far_future    frame 80: the first camera sends a frame 100000 frames and 1000 s ahead
//   duplicate     frame 90: the second camera's message is sent twice
// COUNTS.txt gets one "key=value" line per kind (messages, or detections for nan/outside).
// Exit status 0 on success, 1 on failure, 2 on usage errors.

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "clean_log.h"
#include "core/detection.h"
#include "tracker/types.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"

namespace {

namespace transport = mvtrack::transport;
using mvtrack::core::CameraFrame;
using mvtrack::core::Detection2D;

constexpr mvtrack::CameraId kUnknownCamera = 77;
constexpr int kOversizedDetections = 10000;

using Event = mvtrack::testing::CleanEvent;

Detection2D Box(double x0, double y0, double x1, double y1, double score) {
  Detection2D d;
  d.box.x_min = x0;
  d.box.y_min = y0;
  d.box.x_max = x1;
  d.box.y_max = y1;
  d.score = score;
  return d;
}

int Run(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: make_fault_log CLEAN.lcmlog OUT.lcmlog COUNTS.txt\n";
    return 2;
  }
  std::string why;
  const mvtrack::testing::CleanLog log = mvtrack::testing::ReadCleanLog(argv[1], 3);
  const std::vector<Event>& events = log.events;
  const mvtrack::CameraId cam_a = log.cameras[0], cam_b = log.cameras[1], cam_c = log.cameras[2];
  const mvtrack::FrameIndex first = events.front().frame.frame;
  // Frame period from the first two distinct frames of camera a.
  std::int64_t period_us = 40000;
  {
    std::optional<std::int64_t> t0;
    for (const Event& e : events) {
      if (e.frame.camera_id != cam_a) continue;
      if (!t0) {
        t0 = e.frame.utime;
      } else {
        period_us = std::max<std::int64_t>(10, e.frame.utime - *t0);
        break;
      }
    }
  }
  std::map<std::pair<mvtrack::CameraId, mvtrack::FrameIndex>, const Event*> by_key;
  for (const Event& e : events) by_key[{e.frame.camera_id, e.frame.frame}] = &e;

  std::unique_ptr<transport::LogWriter> out = transport::LogWriter::Open(argv[2], &why);
  if (!out) throw std::runtime_error(why);
  std::map<std::string, std::int64_t> counts;
  auto write = [&](const std::string& channel, std::int64_t t, const std::vector<std::uint8_t>& b) {
    if (!out->Write(channel, t, b, &why)) throw std::runtime_error(why);
  };
  auto encode = [](const CameraFrame& f, int w, int h) {
    return transport::EncodeCameraDetections(f, w, h);
  };

  for (const Event& e : events) {
    const std::int64_t k = e.frame.frame - first;
    const mvtrack::CameraId cam = e.frame.camera_id;
    if (cam == cam_a && k == 100) {
      CameraFrame big = e.frame;
      big.detections.clear();
      for (int i = 0; i < kOversizedDetections; ++i) {
        big.detections.push_back(Box(10.0 + i % 100, 10.0, 60.0 + i % 100, 120.0, 0.9));
      }
      write(e.channel, e.time_us, encode(big, e.width, e.height));
      ++counts["oversized"];
    }
    // The genuine message (with invalid detections appended on some frames).
    if (cam == cam_b && k % 7 == 0) {
      CameraFrame f = e.frame;
      f.detections.push_back(Box(std::numeric_limits<double>::quiet_NaN(), 10, 50, 100, 0.9));
      f.detections.push_back(Box(20, 20, 80, 160, std::numeric_limits<double>::infinity()));
      counts["nan"] += 2;
      write(e.channel, e.time_us, encode(f, e.width, e.height));
    } else if (cam == cam_c && k % 7 == 2) {
      CameraFrame f = e.frame;
      f.detections.push_back(Box(-90000, -90000, -89000, -88000, 0.9));
      counts["outside"] += 1;
      write(e.channel, e.time_us, encode(f, e.width, e.height));
    } else {
      write(e.channel, e.time_us, e.data);
    }
    if (cam == cam_a && k % 10 == 0) {
      std::vector<std::uint8_t> half(
          e.data.begin(), e.data.begin() + static_cast<std::ptrdiff_t>(e.data.size() / 2));
      write(e.channel, e.time_us, half);
      ++counts["truncated"];
    }
    if (cam == cam_b && k % 10 == 3) {
      mvtrack::tracker::Frame3D tracks;
      tracks.frame = e.frame.frame;
      tracks.utime = e.frame.utime;
      write(e.channel,
            e.time_us,
            transport::EncodeTracks(tracks, mvtrack::core::KeypointLayoutId::kNone, e.time_us, 0));
      ++counts["foreign"];
    }
    if (cam == cam_c && k % 25 == 0) {
      CameraFrame f = e.frame;
      f.camera_id = kUnknownCamera;
      write(transport::kDetectionsChannel, e.time_us, encode(f, e.width, e.height));
      ++counts["unknown"];
    }
    if (cam == cam_c && k >= 120 && k < 160) {
      for (int i = 1; i <= 9; ++i) {
        CameraFrame f = e.frame;
        f.utime += i * period_us / 10;
        write(e.channel, e.time_us + i * period_us / 10, encode(f, e.width, e.height));
        ++counts["flood"];
      }
    }
    if (cam == cam_b && k >= 60 && k < 65) {
      const auto old = by_key.find({cam_b, e.frame.frame - 30});
      if (old != by_key.end()) {
        write(old->second->channel, e.time_us, old->second->data);
        ++counts["backwards"];
      }
    }
    if (cam == cam_a && k == 80) {
      CameraFrame f = e.frame;
      f.frame += 100000;
      f.utime += 1000000000;
      write(e.channel, e.time_us, encode(f, e.width, e.height));
      ++counts["far_future"];
    }
    if (cam == cam_b && k == 90) {
      write(e.channel, e.time_us, e.data);
      ++counts["duplicate"];
    }
  }
  if (!out->Flush(&why)) throw std::runtime_error(why);
  std::ofstream txt(argv[3], std::ios::trunc);
  for (const char* key : {"truncated",
                          "foreign",
                          "oversized",
                          "nan",
                          "outside",
                          "unknown",
                          "flood",
                          "backwards",
                          "far_future",
                          "duplicate"}) {
    txt << key << "=" << counts[key] << "\n";
  }
  txt.close();
  if (!txt) throw std::runtime_error(std::string(argv[3]) + ": write error");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "make_fault_log: " << e.what() << "\n";
    return 1;
  }
}
