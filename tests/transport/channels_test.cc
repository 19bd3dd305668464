// Channel names and the per-camera detections convention.

#include "transport/channels.h"

#include <catch2/catch.hpp>
#include <climits>
#include <regex>
#include <string>

namespace mvtrack::transport {
namespace {

TEST_CASE("channel names are the documented constants", "[unit]") {
  CHECK(std::string(kDetectionsChannel) == "MVTRACK_DETECTIONS");
  CHECK(std::string(kDetectionsChannelPrefix) == "MVTRACK_DETECTIONS_");
  CHECK(std::string(kTracksChannel) == "MVTRACK_TRACKS");
  CHECK(std::string(kStatusChannel) == "MVTRACK_STATUS");
}

TEST_CASE("per-camera channels map to camera ids and back", "[unit]") {
  for (const CameraId id : {0, 1, 7, 42, 1000, INT32_MAX}) {
    const std::string channel = DetectionsChannelForCamera(id);
    CHECK(channel == "MVTRACK_DETECTIONS_" + std::to_string(id));
    CHECK(CameraIdFromChannel(channel) == id);
    CHECK(IsDetectionsChannel(channel));
  }
}

TEST_CASE("CameraIdFromChannel rejects everything but canonical per-camera names", "[unit]") {
  for (const char* channel : {"MVTRACK_DETECTIONS",
                              "MVTRACK_DETECTIONS_",
                              "MVTRACK_DETECTIONS_-1",
                              "MVTRACK_DETECTIONS_+1",
                              "MVTRACK_DETECTIONS_07",
                              "MVTRACK_DETECTIONS_00",
                              "MVTRACK_DETECTIONS_1a",
                              "MVTRACK_DETECTIONS_ 1",
                              "MVTRACK_DETECTIONS_2147483648",
                              "MVTRACK_DETECTIONS_99999999999999999999",
                              "MVTRACK_DETECTIONS__1",
                              "MVTRACK_TRACKS",
                              "mvtrack_detections_1",
                              "XMVTRACK_DETECTIONS_1",
                              ""}) {
    INFO(channel);
    CHECK_FALSE(CameraIdFromChannel(channel).has_value());
  }
  CHECK(IsDetectionsChannel(kDetectionsChannel));
  CHECK_FALSE(IsDetectionsChannel(kTracksChannel));
  CHECK_FALSE(IsDetectionsChannel("MVTRACK_DETECTIONS_07"));
}

TEST_CASE("the subscription regex covers the shared and per-camera channels", "[unit]") {
  // LCM anchors subscription regexes: std::regex_match has the same semantics.
  const std::regex regex(kDetectionsChannelRegex);
  CHECK(std::regex_match(std::string(kDetectionsChannel), regex));
  CHECK(std::regex_match(DetectionsChannelForCamera(0), regex));
  CHECK(std::regex_match(DetectionsChannelForCamera(123), regex));
  CHECK_FALSE(std::regex_match(std::string(kTracksChannel), regex));
  CHECK_FALSE(std::regex_match(std::string("MVTRACK_DETECTIONS_"), regex));
  CHECK_FALSE(std::regex_match(std::string("MVTRACK_DETECTIONS_X"), regex));
}

}  // namespace
}  // namespace mvtrack::transport
