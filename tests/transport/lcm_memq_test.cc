// The raw-bytes receive path through real LCM (memq://): publish encoded bytes, receive them with
// a raw subscribeFunction handler, decode them with the safe decoders.

#include <catch2/catch.hpp>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <string>
#include <vector>

#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/test_messages.h"

namespace mvtrack::transport {
namespace {

// What the handler saw, in arrival order.
struct Received {
  std::string channel;
  std::optional<CameraId> channel_camera;
  DecodeResult detections;
};

// Raw handler: never lets anything escape into LCM's C code (DecodeCameraDetections does not
// throw), so no try/catch is needed here.
void OnDetections(const lcm::ReceiveBuffer* rbuf,
                  const std::string& channel,
                  std::vector<Received>* out) {
  Received r;
  r.channel = channel;
  r.channel_camera = CameraIdFromChannel(channel);
  r.detections = DecodeCameraDetections(rbuf->data, rbuf->data_size);
  out->push_back(std::move(r));
}

void OnTracks(const lcm::ReceiveBuffer* rbuf,
              const std::string&,
              std::vector<TracksDecodeResult>* out) {
  out->push_back(DecodeTracks(rbuf->data, rbuf->data_size));
}

TEST_CASE("memq:// carries encoded bytes to a raw handler that decodes them safely", "[unit]") {
  lcm::LCM lc("memq://");
  REQUIRE(lc.good());
  std::vector<Received> detections;
  std::vector<TracksDecodeResult> tracks;
  // Subscribe before publishing: memq:// drops messages on channels nobody subscribed to.
  REQUIRE(lc.subscribeFunction(kDetectionsChannelRegex, &OnDetections, &detections) != nullptr);
  REQUIRE(lc.subscribeFunction(kTracksChannel, &OnTracks, &tracks) != nullptr);

  core::CameraFrame cam2 = testing::MakeRealisticFrame(2);
  cam2.camera_id = 2;
  core::CameraFrame cam5 = testing::MakeRealisticFrame(5);
  cam5.camera_id = 5;
  const std::vector<std::uint8_t> bytes2 = EncodeCameraDetections(cam2, 640, 480);
  const std::vector<std::uint8_t> bytes5 = EncodeCameraDetections(cam5, 1280, 720);
  std::vector<std::uint8_t> corrupt = bytes2;
  corrupt.resize(corrupt.size() / 2);
  const tracker::Frame3D frame3d = testing::MakeTracksFrame(3, false);
  const std::vector<std::uint8_t> tracks_bytes =
      EncodeTracks(frame3d, core::KeypointLayoutId::kNone, 9, 1);

  auto publish = [&lc](const std::string& channel, const std::vector<std::uint8_t>& b) {
    REQUIRE(lc.publish(channel, b.data(), static_cast<unsigned int>(b.size())) == 0);
  };
  publish(DetectionsChannelForCamera(2), bytes2);
  publish(kDetectionsChannel, bytes5);
  publish(kTracksChannel, tracks_bytes);
  publish(DetectionsChannelForCamera(2), corrupt);
  publish(kStatusChannel, bytes2);  // nobody subscribed: dropped
  for (int i = 0; i < 4; ++i) REQUIRE(lc.handleTimeout(1000) > 0);
  CHECK(lc.handleTimeout(0) == 0);

  REQUIRE(detections.size() == 3);
  CHECK(detections[0].channel == "MVTRACK_DETECTIONS_2");
  CHECK(detections[0].channel_camera == 2);
  REQUIRE(detections[0].detections.ok());
  CHECK(testing::DiffCameraFrames(detections[0].detections.frame, cam2).empty());
  CHECK(detections[0].detections.image_width_px == 640);
  CHECK(detections[1].channel == kDetectionsChannel);
  CHECK_FALSE(detections[1].channel_camera.has_value());
  REQUIRE(detections[1].detections.ok());
  CHECK(detections[1].detections.frame.camera_id == 5);
  CHECK(detections[2].detections.status == DecodeStatus::kTruncated);

  REQUIRE(tracks.size() == 1);
  REQUIRE(tracks[0].ok());
  CHECK(tracks[0].message.frame.tracks.size() == frame3d.tracks.size());
}

}  // namespace
}  // namespace mvtrack::transport
