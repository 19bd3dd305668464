// Test helper of the status-source test (issue 39): publishes tracker_status_t messages over
// real LCM as another daemon, or a forger, would. Each is a healthy-looking status (three
// cameras delivering, no flag) of instance INSTANCE, with sequences FIRST, FIRST+1, ...:
//
//   publish_status URL CHANNEL INSTANCE FIRST COUNT PERIOD_MS
//
// COUNT messages, PERIOD_MS apart, stamped with the wall clock. Exit status 0 on success, 1 when
// LCM fails, 2 on usage errors.

#include <chrono>
#include <cstdint>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <vector>

#include "transport/codec.h"

namespace {

std::int64_t WallMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::cerr << "usage: publish_status URL CHANNEL INSTANCE FIRST COUNT PERIOD_MS\n";
    return 2;
  }
  std::int64_t first = 0, count = 0, period_ms = 0;
  try {
    first = std::stoll(argv[4]);
    count = std::stoll(argv[5]);
    period_ms = std::stoll(argv[6]);
  } catch (const std::exception&) {
    std::cerr << "publish_status: FIRST, COUNT and PERIOD_MS must be integers\n";
    return 2;
  }
  if (count < 1 || period_ms < 1) {
    std::cerr << "publish_status: COUNT and PERIOD_MS must be >= 1\n";
    return 2;
  }
  lcm::LCM lcm(argv[1]);
  if (!lcm.good()) {
    std::cerr << "publish_status: cannot open LCM " << argv[1] << "\n";
    return 1;
  }
  const std::int64_t start = WallMicros();
  for (std::int64_t i = 0; i < count; ++i) {
    if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
    mvtrack::transport::TrackerStatus s;
    s.utime = WallMicros();
    s.period_us = period_ms * 1000;
    s.uptime_us = s.utime - start;
    s.instance_id = argv[3];
    s.start_utime = start;
    s.sequence = first + i;
    s.version = "forged";
    s.last_frame = i;
    s.num_latency_samples = 1;
    for (int c = 0; c < 3; ++c) {
      mvtrack::transport::CameraStatus cs;
      cs.camera_id = c;
      cs.received = 100 + i;
      cs.rate_hz = 30.0f;
      cs.last_utime = s.utime;
      cs.last_receive_utime = s.utime;
      s.cameras.push_back(cs);
    }
    const std::vector<std::uint8_t> bytes = mvtrack::transport::EncodeTrackerStatus(s);
    if (lcm.publish(argv[2], bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
      std::cerr << "publish_status: publish failed\n";
      return 1;
    }
  }
  return 0;
}
