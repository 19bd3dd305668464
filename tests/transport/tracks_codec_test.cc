// tracks3d_t encoding and safe decoding.

#include <algorithm>
#include <catch2/catch.hpp>
#include <climits>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "transport/allocation_probe.h"
#include "transport/codec.h"
#include "transport/test_messages.h"

namespace mvtrack::transport {
namespace {

using testing::AllocationProbe;
using testing::DiffFrames3D;
using testing::EncodeLcm;
using testing::MakeTracksFrame;
using testing::OffsetsOf;
using testing::PutBigEndian;

// The frame as the encoder must write it: tracks by id, cameras ascending and unique.
tracker::Frame3D Canonical(tracker::Frame3D frame) {
  std::stable_sort(
      frame.tracks.begin(),
      frame.tracks.end(),
      [](const tracker::Track3D& a, const tracker::Track3D& b) { return a.id < b.id; });
  for (tracker::Track3D& t : frame.tracks) {
    std::sort(t.cameras.begin(), t.cameras.end());
    t.cameras.erase(std::unique(t.cameras.begin(), t.cameras.end()), t.cameras.end());
    std::sort(t.zones.begin(), t.zones.end());
    t.zones.erase(std::unique(t.zones.begin(), t.zones.end()), t.zones.end());
  }
  return frame;
}

// Reference tracks3d_t of `frame` built field by field from the .lcm documentation.
mvtrack::tracks3d_t ReferenceMessage(const tracker::Frame3D& canonical,
                                     const std::string& layout,
                                     std::int64_t publish_utime,
                                     std::int64_t latency_us) {
  mvtrack::tracks3d_t msg;
  msg.utime = canonical.utime;
  msg.frame = canonical.frame;
  msg.publish_utime = publish_utime;
  msg.latency_us = latency_us;
  msg.layer = mvtrack::tracks3d_t::LAYER_FINAL;
  msg.keypoint_layout = layout;
  msg.num_zones = static_cast<std::int16_t>(canonical.zones.size());
  msg.zones = canonical.zones;
  msg.num_tracks = static_cast<std::int32_t>(canonical.tracks.size());
  for (const tracker::Track3D& track : canonical.tracks) {
    mvtrack::track3d_t t;
    t.id = track.id;
    t.state = track.state == linking::TrackState::kTentative   ? mvtrack::track3d_t::STATE_TENTATIVE
              : track.state == linking::TrackState::kConfirmed ? mvtrack::track3d_t::STATE_CONFIRMED
                                                               : mvtrack::track3d_t::STATE_LOST;
    for (int c = 0; c < 3; ++c) t.position[c] = track.position[c];
    t.confidence = static_cast<float>(track.confidence);
    t.age_frames = static_cast<std::int32_t>(track.age_frames);
    t.missed_frames = 0;
    t.num_cameras = static_cast<std::int16_t>(track.cameras.size());
    t.camera_ids = track.cameras;
    t.num_joints = static_cast<std::int16_t>(track.joints.size());
    for (const auto& joint : track.joints) {
      mvtrack::joint3d_t j;
      for (int c = 0; c < 3; ++c) j.position[c] = joint ? (*joint)[c] : 0.0;
      j.confidence = joint ? 1.0f : 0.0f;
      j.valid = joint ? 1 : 0;
      t.joints.push_back(j);
    }
    t.num_bones = static_cast<std::int16_t>(track.bone_lengths.size());
    for (const double b : track.bone_lengths) t.bone_lengths.push_back(static_cast<float>(b));
    t.num_zones = static_cast<std::int16_t>(track.zones.size());
    for (const int z : track.zones) t.zones.push_back(static_cast<std::int16_t>(z));
    msg.tracks.push_back(t);
  }
  return msg;
}

void RequireRejected(const std::vector<std::uint8_t>& bytes,
                     DecodeStatus expected,
                     const std::string& needle,
                     const DecodeLimits& limits = {}) {
  TracksDecodeResult result;
  std::size_t largest = 0;
  {
    AllocationProbe probe;
    result = DecodeTracks(bytes.data(), bytes.size(), limits);
    largest = probe.largest();
  }
  INFO("reason: " << result.reason);
  CHECK(result.status == expected);
  CHECK_THAT(result.reason, Catch::Matchers::Contains(needle));
  CHECK(largest < 64 * 1024);
}

TEST_CASE("tracks round trip in pose and box mode", "[unit]") {
  for (const bool pose : {true, false}) {
    INFO("pose mode " << pose);
    const tracker::Frame3D frame = MakeTracksFrame(1, pose);
    const core::KeypointLayoutId layout =
        pose ? core::KeypointLayoutId::kCoco17 : core::KeypointLayoutId::kNone;
    const std::vector<std::uint8_t> bytes = EncodeTracks(frame, layout, 123456789, 4321);
    const TracksDecodeResult result = DecodeTracks(bytes.data(), bytes.size());
    REQUIRE(result.ok());
    const TracksMessage& msg = result.message;
    CHECK(DiffFrames3D(msg.frame, Canonical(frame)).empty());
    CHECK(msg.layout == layout);
    CHECK(msg.publish_utime == 123456789);
    CHECK(msg.latency_us == 4321);
    REQUIRE(msg.info.size() == frame.tracks.size());
    // Ids 3, 5, 7, 12 with states tentative, confirmed, confirmed, lost.
    CHECK(msg.frame.tracks[0].id == 3);
    CHECK(msg.info[0].state == WireTrackState::kTentative);
    CHECK(msg.info[2].state == WireTrackState::kConfirmed);
    CHECK(msg.info[3].state == WireTrackState::kLost);
    for (const WireTrackInfo& info : msg.info) CHECK(info.missed_frames == 0);
  }
}

TEST_CASE("the tracks encoding is byte-identical to the documented wire form", "[unit]") {
  for (const bool pose : {true, false}) {
    // Seed 3: a stitched site's frame, with zones.
    for (const std::uint32_t seed : {2u, 3u}) {
      const tracker::Frame3D frame = MakeTracksFrame(seed, pose);
      const std::vector<std::uint8_t> ours = EncodeTracks(
          frame, pose ? core::KeypointLayoutId::kCoco17 : core::KeypointLayoutId::kNone, 77, 5);
      const std::vector<std::uint8_t> reference =
          EncodeLcm(ReferenceMessage(Canonical(frame), pose ? "coco17" : "", 77, 5));
      CHECK(ours == reference);
    }
  }
}

TEST_CASE("age saturates to int32 and equal ids keep their order", "[unit]") {
  tracker::Frame3D frame;
  tracker::Track3D a;
  a.id = 4;
  a.age_frames = std::int64_t{1} << 40;
  tracker::Track3D b = a;
  b.age_frames = -(std::int64_t{1} << 40);
  b.position = Vec3(1.0, 0.0, 0.0);
  frame.tracks = {a, b};
  const std::vector<std::uint8_t> bytes = EncodeTracks(frame, core::KeypointLayoutId::kNone, 0, 0);
  const TracksDecodeResult result = DecodeTracks(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  REQUIRE(result.message.frame.tracks.size() == 2);
  CHECK(result.message.frame.tracks[0].age_frames == INT32_MAX);
  CHECK(result.message.frame.tracks[1].age_frames == INT32_MIN);
  CHECK(result.message.frame.tracks[1].position.x() == 1.0);
}

TEST_CASE("STATE_ENDED and missed_frames survive decoding", "[unit]") {
  mvtrack::tracks3d_t msg = ReferenceMessage(Canonical(MakeTracksFrame(3, false)), "", 0, 0);
  msg.tracks[1].state = mvtrack::track3d_t::STATE_ENDED;
  msg.tracks[1].missed_frames = 42;
  const std::vector<std::uint8_t> bytes = EncodeLcm(msg);
  const TracksDecodeResult result = DecodeTracks(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  CHECK(result.message.info[1].state == WireTrackState::kEnded);
  CHECK(result.message.info[1].missed_frames == 42);
  CHECK(result.message.frame.tracks[1].state == linking::TrackState::kLost);
}

TEST_CASE("a tracks truncation at every byte offset is kTruncated", "[unit]") {
  const std::vector<std::uint8_t> bytes =
      EncodeTracks(MakeTracksFrame(4, true), core::KeypointLayoutId::kCoco17, 1, 2);
  for (std::size_t len = 0; len < bytes.size(); ++len) {
    TracksDecodeResult result;
    REQUIRE_NOTHROW(result = DecodeTracks(bytes.data(), len));
    INFO("length " << len << ": " << result.reason);
    REQUIRE(result.status == DecodeStatus::kTruncated);
    REQUIRE(!result.reason.empty());
  }
}

TEST_CASE("track structure errors name the track and field", "[unit]") {
  const tracker::Frame3D frame = Canonical(MakeTracksFrame(5, true));
  const mvtrack::tracks3d_t msg = ReferenceMessage(frame, "coco17", 0, 0);
  const std::vector<std::uint8_t> good = EncodeLcm(msg);
  const testing::Tracks3dOffsets offsets = OffsetsOf(msg);
  REQUIRE(offsets.total == good.size());
  DecodeLimits unlimited;
  unlimited.max_tracks = INT_MAX;
  unlimited.max_cameras = INT_MAX;
  unlimited.max_joints = INT_MAX;

  std::vector<std::uint8_t> bytes = good;
  bytes[offsets.keypoint_layout - 1] = 2;  // layer
  RequireRejected(bytes, DecodeStatus::kMalformed, "layer 2 is not LAYER_FINAL (0) or");
  bytes[offsets.keypoint_layout - 1] =
      static_cast<std::uint8_t>(mvtrack::tracks3d_t::LAYER_PROVISIONAL);
  const TracksDecodeResult provisional = DecodeTracks(bytes.data(), bytes.size());
  REQUIRE(provisional.ok());
  CHECK(provisional.message.layer == TracksLayer::kProvisional);
  CHECK(DecodeTracks(good.data(), good.size()).message.layer == TracksLayer::kFinal);
  const std::vector<std::uint8_t> encoded =
      EncodeTracks(frame, core::KeypointLayoutId::kCoco17, 0, 0, TracksLayer::kProvisional);
  CHECK(encoded == bytes);

  bytes = good;
  PutBigEndian(&bytes, offsets.num_tracks, static_cast<std::uint32_t>(-1), 4);
  RequireRejected(bytes, DecodeStatus::kMalformed, "num_tracks -1 is negative");
  PutBigEndian(&bytes, offsets.num_tracks, INT32_MAX, 4);
  RequireRejected(bytes, DecodeStatus::kLimitExceeded, "num_tracks 2147483647 exceeds the limit");
  RequireRejected(
      bytes, DecodeStatus::kTruncated, "num_tracks 2147483647 needs at least", unlimited);

  for (std::size_t i = 0; i < offsets.tracks.size(); ++i) {
    const std::string prefix =
        "track " + std::to_string(i) + " (id " + std::to_string(frame.tracks[i].id) + "): ";
    bytes = good;
    bytes[offsets.tracks[i].state] = 7;
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "state 7 is not one of");
    bytes = good;
    PutBigEndian(&bytes, offsets.tracks[i].num_cameras, 0xFFFF, 2);
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_cameras -1 is negative");
    PutBigEndian(&bytes, offsets.tracks[i].num_cameras, 32767, 2);
    RequireRejected(bytes, DecodeStatus::kLimitExceeded, prefix + "num_cameras 32767 exceeds");
    RequireRejected(bytes, DecodeStatus::kTruncated, prefix + "num_cameras 32767 needs", unlimited);
    bytes = good;
    PutBigEndian(&bytes, offsets.tracks[i].num_joints, 0x8000, 2);
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_joints -32768 is negative");
    PutBigEndian(&bytes, offsets.tracks[i].num_joints, 32767, 2);
    RequireRejected(bytes, DecodeStatus::kLimitExceeded, prefix + "num_joints 32767 exceeds");
    RequireRejected(bytes, DecodeStatus::kTruncated, prefix + "num_joints 32767 needs", unlimited);
    PutBigEndian(&bytes, offsets.tracks[i].num_joints, 1, 2);
    RequireRejected(
        bytes, DecodeStatus::kMalformed, prefix + "num_joints 1 is neither 0 nor the 17 joints");
    bytes = good;
    PutBigEndian(&bytes, offsets.tracks[i].num_bones, 0x8000, 2);
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_bones -32768 is negative");
    PutBigEndian(&bytes, offsets.tracks[i].num_bones, 32767, 2);
    RequireRejected(bytes, DecodeStatus::kLimitExceeded, prefix + "num_bones 32767 exceeds");
    PutBigEndian(&bytes, offsets.tracks[i].num_bones, 18, 2);
    RequireRejected(
        bytes, DecodeStatus::kMalformed, prefix + "num_bones 18 is neither 0 nor the 19 bones");
    bytes = good;
    PutBigEndian(&bytes, offsets.tracks[i].num_zones, 0xFFFF, 2);
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_zones -1 is negative");
    PutBigEndian(&bytes, offsets.tracks[i].num_zones, 300, 2);
    RequireRejected(bytes, DecodeStatus::kLimitExceeded, prefix + "num_zones 300 exceeds");
    if (!frame.tracks[i].zones.empty()) {
      bytes = good;
      PutBigEndian(&bytes, offsets.tracks[i].num_zones + 2, 3, 2);
      RequireRejected(bytes,
                      DecodeStatus::kMalformed,
                      prefix + "zones[0] = 3 is not an index of the message's 3 zones");
    }
    if (frame.tracks[i].zones.size() >= 2) {
      bytes = good;
      PutBigEndian(&bytes,
                   offsets.tracks[i].num_zones + 4,
                   static_cast<std::uint64_t>(frame.tracks[i].zones[0]),
                   2);
      RequireRejected(bytes,
                      DecodeStatus::kMalformed,
                      prefix + "zones[1] = " + std::to_string(frame.tracks[i].zones[0]) +
                          " is not ascending without duplicates");
    }
  }
  // The site's zones (seed 5 makes a stitched frame: 3 zones, tracks seen by 0 to 2 of them).
  REQUIRE(msg.zones.size() == 3);
  bytes = good;
  PutBigEndian(&bytes, offsets.num_zones, 0xFFFF, 2);
  RequireRejected(bytes, DecodeStatus::kMalformed, "num_zones -1 is negative");
  PutBigEndian(&bytes, offsets.num_zones, 257, 2);
  RequireRejected(bytes, DecodeStatus::kLimitExceeded, "num_zones 257 exceeds");
  mvtrack::tracks3d_t unnamed = msg;
  unnamed.zones[1] = "";
  bytes = EncodeLcm(unnamed);
  RequireRejected(bytes, DecodeStatus::kMalformed, "zones[1] is an empty zone name");
  const TracksDecodeResult zoned = DecodeTracks(good.data(), good.size());
  REQUIRE(zoned.ok());
  CHECK(zoned.message.frame.zones == msg.zones);
  CHECK(DiffFrames3D(zoned.message.frame, frame).empty());

  // A joint count that does not match the layout: 17 joints in a box-mode message.
  mvtrack::tracks3d_t box = msg;
  box.keypoint_layout = "";
  bytes = EncodeLcm(box);
  RequireRejected(bytes, DecodeStatus::kMalformed, "num_joints 17 is neither 0 nor the 0 joints");
  // Unknown layout name.
  box.keypoint_layout = "coco18";
  bytes = EncodeLcm(box);
  RequireRejected(bytes, DecodeStatus::kMalformed, "unknown keypoint_layout \"coco18\"");
  // Trailing bytes and a foreign fingerprint.
  bytes = good;
  bytes.push_back(1);
  RequireRejected(bytes, DecodeStatus::kMalformed, "1 trailing bytes");
  const std::vector<std::uint8_t> detections =
      EncodeCameraDetections(testing::MakeRealisticFrame(1), 0, 0);
  RequireRejected(detections, DecodeStatus::kBadFingerprint, "camera_detections_t");
  // Pose-mode tracks may come without joints (num_joints 0).
  mvtrack::tracks3d_t jointless = msg;
  jointless.tracks[0].num_joints = 0;
  jointless.tracks[0].joints.clear();
  bytes = EncodeLcm(jointless);
  CHECK(DecodeTracks(bytes.data(), bytes.size()).ok());
}

TEST_CASE("5000 random mutations of a tracks message never crash", "[unit]") {
  std::mt19937 rng(777);
  // Two pose tracks (ids 7 and 3: unsorted) keep the loop fast.
  tracker::Frame3D frame = MakeTracksFrame(6, true);
  frame.tracks.resize(2);
  const std::vector<std::uint8_t> good = EncodeTracks(frame, core::KeypointLayoutId::kCoco17, 1, 2);
  int ok = 0;
  for (int iteration = 0; iteration < 5000; ++iteration) {
    std::vector<std::uint8_t> bytes = good;
    const std::size_t at = rng() % bytes.size();
    if (rng() % 2 == 0) {
      bytes[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    } else {
      bytes[at] = static_cast<std::uint8_t>(rng());
    }
    if (rng() % 4 == 0) bytes.resize(rng() % bytes.size());
    TracksDecodeResult result;
    {
      AllocationProbe probe;
      result = DecodeTracks(bytes.data(), bytes.size());
      if (probe.largest() >= 64 * 1024) FAIL("iteration " << iteration << ": large allocation");
    }
    if (!result.ok()) {
      if (result.reason.empty()) FAIL("iteration " << iteration << ": failure without reason");
      continue;
    }
    ++ok;
    const std::vector<std::uint8_t> again = EncodeTracks(result.message.frame,
                                                         result.message.layout,
                                                         result.message.publish_utime,
                                                         result.message.latency_us);
    const TracksDecodeResult second = DecodeTracks(again.data(), again.size());
    if (!second.ok()) FAIL("iteration " << iteration << ": " << second.reason);
    // Re-encoding sorts by id and canonicalizes cameras; ENDED is written as LOST.
    const std::string diff = DiffFrames3D(second.message.frame, Canonical(result.message.frame));
    if (!diff.empty()) FAIL("iteration " << iteration << ": re-encoding changed " << diff);
  }
  CHECK(ok > 500);
}

}  // namespace
}  // namespace mvtrack::transport
