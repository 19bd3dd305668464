// The generated types through real LCM: in-process memq:// publish/subscribe with typed
// handlers, and a file:// log written in mode=w and read back with lcm::LogFile.

#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "lcmtypes/sample_messages.h"

namespace mvtrack::lcmtypes_test {
namespace {

// What typed subscriptions received, in arrival order.
struct Recorder {
  std::vector<std::string> received;  // "<channel>\n<dump>"
  std::vector<std::vector<std::uint8_t>> bytes;
};

// Typed handler for subscribeFunction(). LCM 1.3.1's member-function subscribe() overloads are
// avoided on purpose: under GCC 12 -fsanitize=undefined (vptr) their callbacks crash.
template <typename Msg>
void Record(const lcm::ReceiveBuffer* rbuf,
            const std::string& channel,
            const Msg* msg,
            Recorder* recorder) {
  recorder->received.push_back(channel + "\n" + Dump(*msg));
  const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
  recorder->bytes.emplace_back(data, data + rbuf->data_size);
}

// A log path unique to this process and test, removed again on destruction.
class TempLog {
 public:
  explicit TempLog(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("mvtrack_lcmtypes_" + std::to_string(::getpid()) + "_" + name + ".lcmlog")) {
    std::filesystem::remove(path_);
  }
  ~TempLog() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TempLog(const TempLog&) = delete;
  TempLog& operator=(const TempLog&) = delete;

  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace

TEST_CASE("memq:// delivers every top-level type intact and in order", "[unit]") {
  lcm::LCM lc("memq://");
  REQUIRE(lc.good());
  Recorder recorder;
  // memq:// drops publishes on channels nobody subscribed to yet: subscribe first.
  lc.subscribeFunction("DETECTIONS", &Record<camera_detections_t>, &recorder);
  lc.subscribeFunction("TRACKS3D", &Record<tracks3d_t>, &recorder);
  lc.subscribeFunction("STATUS", &Record<tracker_status_t>, &recorder);

  const camera_detections_t detections_a = MakeCameraDetections(101, 1, 4);
  const camera_detections_t detections_b = MakeCameraDetections(102, 2, 0);
  const tracks3d_t tracks = MakeTracks3d(103, 6, true);
  const tracker_status_t status = MakeTrackerStatus(104, 3);
  REQUIRE(lc.publish("DETECTIONS", &detections_a) == 0);
  REQUIRE(lc.publish("TRACKS3D", &tracks) == 0);
  REQUIRE(lc.publish("DETECTIONS", &detections_b) == 0);
  REQUIRE(lc.publish("STATUS", &status) == 0);
  REQUIRE(lc.publish("UNSUBSCRIBED", &status) == 0);  // must not reach any handler

  for (int i = 0; i < 4; ++i) REQUIRE(lc.handleTimeout(1000) > 0);
  CHECK(lc.handleTimeout(0) == 0);  // nothing else is queued

  const std::vector<std::string> expected = {"DETECTIONS\n" + Dump(detections_a),
                                             "TRACKS3D\n" + Dump(tracks),
                                             "DETECTIONS\n" + Dump(detections_b),
                                             "STATUS\n" + Dump(status)};
  CHECK(recorder.received == expected);
  REQUIRE(recorder.bytes.size() == 4);
  CHECK(recorder.bytes[0] == Encode(detections_a));
  CHECK(recorder.bytes[1] == Encode(tracks));
  CHECK(recorder.bytes[2] == Encode(detections_b));
  CHECK(recorder.bytes[3] == Encode(status));
}

TEST_CASE("a file:// log written in mode=w reads back with lcm::LogFile", "[unit]") {
  TempLog log("file_roundtrip");
  const std::vector<SampleEvent> events = MakeSampleEvents();
  REQUIRE(events.size() >= 8);
  {
    lcm::LCM lc("file://" + log.path() + "?mode=w");
    REQUIRE(lc.good());
    for (const SampleEvent& event : events) {
      REQUIRE(lc.publish(event.channel,
                         event.bytes.data(),
                         static_cast<unsigned int>(event.bytes.size())) == 0);
    }
  }  // closes the log

  lcm::LogFile file(log.path(), "r");
  REQUIRE(file.good());
  std::size_t index = 0;
  std::int64_t previous_eventnum = -1;
  while (const lcm::LogEvent* event = file.readNextEvent()) {
    REQUIRE(index < events.size());
    const SampleEvent& want = events[index];
    INFO("event " << index << " on " << want.channel << " (" << want.type_name << ")");
    CHECK(event->eventnum > previous_eventnum);
    previous_eventnum = event->eventnum;
    CHECK(event->channel == want.channel);
    REQUIRE(event->datalen == static_cast<std::int32_t>(want.bytes.size()));
    const auto* data = static_cast<const std::uint8_t*>(event->data);
    CHECK(std::vector<std::uint8_t>(data, data + event->datalen) == want.bytes);

    // Decode by fingerprint, as a log reader that does not trust channel names would.
    std::int64_t fingerprint = 0;
    REQUIRE(__int64_t_decode_array(event->data, 0, event->datalen, &fingerprint, 1) == 8);
    REQUIRE(fingerprint == want.fingerprint);
    std::string dump;
    int decoded = -1;
    auto try_decode = [&](auto msg) {
      if (fingerprint != decltype(msg)::getHash()) return;
      decoded = msg.decode(event->data, 0, event->datalen);
      dump = Dump(msg);
    };
    try_decode(keypoint2d_t{});
    try_decode(detection_t{});
    try_decode(camera_detections_t{});
    try_decode(joint3d_t{});
    try_decode(track3d_t{});
    try_decode(tracks3d_t{});
    try_decode(camera_status_t{});
    try_decode(tracker_status_t{});
    try_decode(zone_status_t{});
    try_decode(site_status_t{});
    CHECK(decoded == event->datalen);
    CHECK(dump == want.dump);
    ++index;
  }
  CHECK(index == events.size());
}

}  // namespace mvtrack::lcmtypes_test
