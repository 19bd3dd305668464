// Encode/decode behaviour of the generated C++ types: lossless round trips, clean failure on
// truncated, foreign, corrupted and hostile input.

#include <catch2/catch.hpp>
#include <cstdint>
#include <functional>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "lcmtypes/sample_messages.h"

namespace mvtrack::lcmtypes_test {
namespace {

// One non-trivial sample per type (the nested types too: they are encodable on their own).
template <typename Msg>
Msg MakeSample();
template <>
keypoint2d_t MakeSample<keypoint2d_t>() {
  return MakeKeypoint2d(1);
}
template <>
detection_t MakeSample<detection_t>() {
  return MakeDetection(2, DetectionKind::kPoseAndEmbedding);
}
template <>
camera_detections_t MakeSample<camera_detections_t>() {
  return MakeCameraDetections(3, 4, 6);
}
template <>
joint3d_t MakeSample<joint3d_t>() {
  return MakeJoint3d(4, true);
}
template <>
track3d_t MakeSample<track3d_t>() {
  return MakeTrack3d(5, 42, track3d_t::STATE_CONFIRMED, 17);
}
template <>
tracks3d_t MakeSample<tracks3d_t>() {
  return MakeTracks3d(6, 5, true);
}
template <>
camera_status_t MakeSample<camera_status_t>() {
  return MakeCameraStatus(7, 3);
}
template <>
tracker_status_t MakeSample<tracker_status_t>() {
  return MakeTrackerStatus(8, 4);
}

template <>
zone_status_t MakeSample<zone_status_t>() {
  return MakeZoneStatus(9, "EAST", false);
}
template <>
site_status_t MakeSample<site_status_t>() {
  return MakeSiteStatus(10, 3);
}

// Decodes `bytes[0, len)` into a fresh message; returns decode()'s result.
template <typename Msg>
int DecodePrefix(const std::vector<std::uint8_t>& bytes, std::size_t len, Msg* msg) {
  return msg->decode(bytes.data(), 0, static_cast<int>(len));
}

// The encoded sample of every type, with a decoder that tries to read any bytes as that type.
struct TypeCase {
  std::string name;
  std::vector<std::uint8_t> bytes;
  std::function<int(const std::vector<std::uint8_t>&)> decode_as;
};

template <typename Msg>
TypeCase MakeTypeCase() {
  return {Msg::getTypeName(), Encode(MakeSample<Msg>()), [](const std::vector<std::uint8_t>& b) {
            Msg msg;
            return msg.decode(b.data(), 0, static_cast<int>(b.size()));
          }};
}

std::vector<TypeCase> AllTypeCases() {
  return {MakeTypeCase<keypoint2d_t>(),
          MakeTypeCase<detection_t>(),
          MakeTypeCase<camera_detections_t>(),
          MakeTypeCase<joint3d_t>(),
          MakeTypeCase<track3d_t>(),
          MakeTypeCase<tracks3d_t>(),
          MakeTypeCase<camera_status_t>(),
          MakeTypeCase<tracker_status_t>(),
          MakeTypeCase<zone_status_t>(),
          MakeTypeCase<site_status_t>()};
}

void WriteBigEndian16(std::vector<std::uint8_t>* bytes, std::size_t offset, std::int16_t v) {
  const auto u = static_cast<std::uint16_t>(v);
  (*bytes)[offset] = static_cast<std::uint8_t>(u >> 8);
  (*bytes)[offset + 1] = static_cast<std::uint8_t>(u & 0xffu);
}

void WriteBigEndian32(std::vector<std::uint8_t>* bytes, std::size_t offset, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (std::size_t i = 0; i < 4; ++i) {
    (*bytes)[offset + i] = static_cast<std::uint8_t>((u >> (8 * (3 - i))) & 0xffu);
  }
}

// True if decoding succeeded; a thrown std::length_error / std::bad_alloc counts as rejection
// (lcm-gen 1.3.1 resizes vectors from untrusted counts before checking the buffer length).
template <typename Msg>
bool DecodeAccepted(const std::vector<std::uint8_t>& bytes) {
  Msg msg;
  try {
    return msg.decode(bytes.data(), 0, static_cast<int>(bytes.size())) >= 0;
  } catch (const std::length_error&) {
    return false;
  } catch (const std::bad_alloc&) {
    return false;
  }
}

}  // namespace

TEMPLATE_TEST_CASE("encode/decode round trip preserves every field",
                   "[unit]",
                   keypoint2d_t,
                   detection_t,
                   camera_detections_t,
                   joint3d_t,
                   track3d_t,
                   tracks3d_t,
                   camera_status_t,
                   tracker_status_t,
                   zone_status_t,
                   site_status_t) {
  const TestType original = MakeSample<TestType>();
  const std::vector<std::uint8_t> bytes = Encode(original);
  REQUIRE(static_cast<int>(bytes.size()) == original.getEncodedSize());
  REQUIRE(bytes.size() > 8);  // more than the fingerprint

  TestType decoded;
  REQUIRE(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  CHECK(Dump(decoded) == Dump(original));
  CHECK(Encode(decoded) == bytes);
  // Decoding must not depend on where the message sits in a larger buffer.
  std::vector<std::uint8_t> padded(5, 0xab);
  padded.insert(padded.end(), bytes.begin(), bytes.end());
  padded.insert(padded.end(), 7, 0xcd);
  TestType decoded_at_offset;
  REQUIRE(decoded_at_offset.decode(padded.data(), 5, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  CHECK(Dump(decoded_at_offset) == Dump(original));
}

TEST_CASE("camera_detections_t round trip keeps poses, embeddings and box-only detections",
          "[unit]") {
  const camera_detections_t original = MakeCameraDetections(99, 5, 3);
  REQUIRE(original.detections.size() == 3);
  const std::vector<std::uint8_t> bytes = Encode(original);
  camera_detections_t decoded;
  REQUIRE(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));

  CHECK(decoded.utime == original.utime);
  CHECK(decoded.frame == original.frame);
  CHECK(decoded.camera_id == 5);
  REQUIRE(decoded.num_detections == 3);
  REQUIRE(decoded.detections.size() == 3);

  const detection_t& pose = decoded.detections[0];  // kPoseAndEmbedding
  CHECK(pose.keypoint_layout == "coco17");
  REQUIRE(pose.keypoints.size() == 17);
  CHECK(pose.keypoints[3].confidence == 0.0f);  // undetected joint survives as 0
  CHECK(pose.keypoints[4].x == original.detections[0].keypoints[4].x);
  CHECK(pose.keypoints[4].y == original.detections[0].keypoints[4].y);
  CHECK(pose.embedding_model == "osnet_x0_25@1");
  REQUIRE(pose.embedding.size() == 64);
  CHECK(pose.embedding == original.detections[0].embedding);
  CHECK(pose.x_min == original.detections[0].x_min);

  CHECK(decoded.detections[1].keypoint_layout == "body25");
  CHECK(decoded.detections[1].keypoints.size() == 25);
  CHECK(decoded.detections[1].embedding.empty());

  const detection_t& box_only = decoded.detections[2];
  CHECK(box_only.keypoint_layout.empty());
  CHECK(box_only.keypoints.empty());
  CHECK(box_only.embedding.empty());
  CHECK(box_only.y_max == original.detections[2].y_max);
}

TEMPLATE_TEST_CASE("decoding a truncated buffer fails cleanly",
                   "[unit]",
                   keypoint2d_t,
                   detection_t,
                   camera_detections_t,
                   joint3d_t,
                   track3d_t,
                   tracks3d_t,
                   camera_status_t,
                   tracker_status_t,
                   zone_status_t,
                   site_status_t) {
  const std::vector<std::uint8_t> bytes = Encode(MakeSample<TestType>());
  int accepted = 0;
  for (std::size_t len = 0; len < bytes.size(); ++len) {
    // Copy the prefix so an over-read would touch memory outside the vector (ASan finds it).
    const std::vector<std::uint8_t> prefix(bytes.begin(),
                                           bytes.begin() + static_cast<std::ptrdiff_t>(len));
    TestType msg;
    if (DecodePrefix(prefix, len, &msg) >= 0) ++accepted;
  }
  CHECK(accepted == 0);
}

TEST_CASE("another type's bytes fail the fingerprint check", "[unit]") {
  const std::vector<TypeCase> cases = AllTypeCases();
  for (const TypeCase& data : cases) {
    for (const TypeCase& as : cases) {
      INFO(data.name << " bytes decoded as " << as.name);
      if (data.name == as.name) {
        CHECK(as.decode_as(data.bytes) == static_cast<int>(data.bytes.size()));
      } else {
        CHECK(as.decode_as(data.bytes) < 0);
      }
    }
  }
}

TEST_CASE("every type has a distinct fingerprint", "[unit]") {
  const std::vector<std::int64_t> hashes = {keypoint2d_t::getHash(),
                                            detection_t::getHash(),
                                            camera_detections_t::getHash(),
                                            joint3d_t::getHash(),
                                            track3d_t::getHash(),
                                            tracks3d_t::getHash(),
                                            camera_status_t::getHash(),
                                            tracker_status_t::getHash(),
                                            zone_status_t::getHash(),
                                            site_status_t::getHash()};
  for (std::size_t i = 0; i < hashes.size(); ++i) {
    for (std::size_t j = i + 1; j < hashes.size(); ++j) {
      INFO("types " << i << " and " << j);
      CHECK(hashes[i] != hashes[j]);
    }
  }
}

TEST_CASE("a corrupted fingerprint is rejected", "[unit]") {
  for (const TypeCase& c : AllTypeCases()) {
    for (std::size_t bit = 0; bit < 64; ++bit) {
      std::vector<std::uint8_t> bytes = c.bytes;
      bytes[bit / 8] = static_cast<std::uint8_t>(bytes[bit / 8] ^ (1u << (bit % 8)));
      INFO(c.name << " with fingerprint bit " << bit << " flipped");
      CHECK(c.decode_as(bytes) < 0);
    }
  }
}

TEST_CASE("hostile counts and string lengths are never accepted", "[unit]") {
  // detection_t layout after the 8-byte fingerprint: 5 floats (20 bytes), then keypoint_layout
  // as int32 length (including the NUL) + bytes, then int16 num_keypoints.
  const detection_t det = MakeDetection(3, DetectionKind::kPoseAndEmbedding);
  const std::vector<std::uint8_t> good = Encode(det);
  const std::size_t layout_len_at = 8 + 20;
  const std::size_t num_keypoints_at = layout_len_at + 4 + det.keypoint_layout.size() + 1;
  REQUIRE(DecodeAccepted<detection_t>(good));

  SECTION("negative keypoint count") {
    std::vector<std::uint8_t> bad = good;
    WriteBigEndian16(&bad, num_keypoints_at, -1);
    CHECK_FALSE(DecodeAccepted<detection_t>(bad));
  }
  SECTION("keypoint count beyond the buffer") {
    std::vector<std::uint8_t> bad = good;
    WriteBigEndian16(&bad, num_keypoints_at, 32767);
    CHECK_FALSE(DecodeAccepted<detection_t>(bad));
  }
  SECTION("string length 0 (no room for the NUL)") {
    std::vector<std::uint8_t> bad = good;
    WriteBigEndian32(&bad, layout_len_at, 0);
    CHECK_FALSE(DecodeAccepted<detection_t>(bad));
  }
  SECTION("string length beyond the buffer") {
    std::vector<std::uint8_t> bad = good;
    WriteBigEndian32(&bad, layout_len_at, 0x7fffffff);
    CHECK_FALSE(DecodeAccepted<detection_t>(bad));
  }
  SECTION("negative detection count") {
    // camera_detections_t: fingerprint, utime, frame (int64), camera_id, image_width,
    // image_height (int32), then int32 num_detections.
    std::vector<std::uint8_t> bad = Encode(MakeCameraDetections(4, 1, 2));
    WriteBigEndian32(&bad, 8 + 8 + 8 + 4 + 4 + 4, -5);
    CHECK_FALSE(DecodeAccepted<camera_detections_t>(bad));
  }
}

}  // namespace mvtrack::lcmtypes_test
