// camera_detections_t encoding and the safe decoding of untrusted bytes.

#include <catch2/catch.hpp>
#include <climits>
#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "transport/allocation_probe.h"
#include "transport/codec.h"
#include "transport/test_messages.h"

namespace mvtrack::transport {
namespace {

using testing::AllocationProbe;
using testing::DiffCameraFrames;
using testing::EncodeLcm;
using testing::MakeRealisticFrame;
using testing::OffsetsOf;
using testing::PutBigEndian;
using testing::ToLcm;

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;

// Decodes and checks the failure contract: the expected status, a reason containing `needle`,
// and no allocation anywhere near what a forged count would ask for.
void RequireRejected(const std::vector<std::uint8_t>& bytes,
                     DecodeStatus expected,
                     const std::string& needle,
                     const DecodeLimits& limits = {}) {
  DecodeResult result;
  std::size_t largest = 0;
  {
    AllocationProbe probe;
    result = DecodeCameraDetections(bytes.data(), bytes.size(), limits);
    largest = probe.largest();
  }
  INFO("reason: " << result.reason);
  CHECK(result.status == expected);
  CHECK_THAT(result.reason, Catch::Matchers::Contains(needle));
  CHECK(largest < 64 * 1024);
}

TEST_CASE("camera detections round trip through encode and decode", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(1);
  const std::vector<std::uint8_t> bytes = EncodeCameraDetections(frame, kWidth, kHeight);
  const DecodeResult result = DecodeCameraDetections(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  CHECK(result.reason.empty());
  CHECK(DiffCameraFrames(result.frame, frame).empty());
  CHECK(result.image_width_px == kWidth);
  CHECK(result.image_height_px == kHeight);
  // The layouts really are distinct on the wire (not all decoded as one).
  CHECK(result.frame.detections[0].layout == core::KeypointLayoutId::kNone);
  CHECK(result.frame.detections[1].layout == core::KeypointLayoutId::kCoco17);
  CHECK(result.frame.detections[3].layout == core::KeypointLayoutId::kBody25);
  CHECK(result.frame.detections[2].embedding.size() == 16);
}

TEST_CASE("the encoding is byte-identical to the generated encoder's", "[unit]") {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const core::CameraFrame frame = MakeRealisticFrame(seed);
    CHECK(EncodeCameraDetections(frame, kWidth, kHeight) ==
          EncodeLcm(ToLcm(frame, kWidth, kHeight)));
  }
}

TEST_CASE("an empty camera frame round trips", "[unit]") {
  core::CameraFrame frame;
  frame.utime = 42;
  frame.frame = -3;
  frame.camera_id = 9;
  const std::vector<std::uint8_t> bytes = EncodeCameraDetections(frame, 0, 0);
  CHECK(bytes.size() == 40);  // fingerprint + 2 int64 + 4 int32
  const DecodeResult result = DecodeCameraDetections(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  CHECK(DiffCameraFrames(result.frame, frame).empty());
}

TEST_CASE("encoding narrows doubles to floats as IEEE-754 does, without UB", "[unit]") {
  core::CameraFrame frame;
  core::Detection2D det;
  det.box = core::BoxPx{0.1, -1e300, 1e300, 3.4028235e38};  // FLT_MAX rounds to itself
  det.score = std::numeric_limits<double>::quiet_NaN();
  frame.detections.push_back(det);
  const std::vector<std::uint8_t> bytes = EncodeCameraDetections(frame, 0, 0);
  const DecodeResult result = DecodeCameraDetections(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  const core::BoxPx& box = result.frame.detections[0].box;
  CHECK(box.x_min == static_cast<double>(0.1f));
  CHECK(box.y_min == -std::numeric_limits<double>::infinity());
  CHECK(box.x_max == std::numeric_limits<double>::infinity());
  CHECK(box.y_max == static_cast<double>(std::numeric_limits<float>::max()));
  CHECK(std::isnan(result.frame.detections[0].score));
}

TEST_CASE("layout names: empty is box-only, aliases are accepted", "[unit]") {
  core::CameraFrame frame = MakeRealisticFrame(4);
  mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  msg.detections[1].keypoint_layout = "campus14";
  msg.detections[1].num_keypoints = 0;
  msg.detections[1].keypoints.clear();
  msg.detections[3].keypoint_layout = "none";
  const std::vector<std::uint8_t> bytes = EncodeLcm(msg);
  const DecodeResult result = DecodeCameraDetections(bytes.data(), bytes.size());
  REQUIRE(result.ok());
  CHECK(result.frame.detections[0].layout == core::KeypointLayoutId::kNone);
  CHECK(result.frame.detections[1].layout == core::KeypointLayoutId::kShelf14);
  CHECK(result.frame.detections[3].layout == core::KeypointLayoutId::kNone);
  // Structure only: 25 keypoints with layout "none" is the tracker's to reject, not ours.
  CHECK(result.frame.detections[3].keypoints.size() == 25);
}

TEST_CASE("a truncation at every byte offset is kTruncated and never throws", "[unit]") {
  const std::vector<std::uint8_t> bytes =
      EncodeCameraDetections(MakeRealisticFrame(5), kWidth, kHeight);
  REQUIRE(bytes.size() > 500);
  for (std::size_t len = 0; len < bytes.size(); ++len) {
    const std::vector<std::uint8_t> prefix(bytes.begin(),
                                           bytes.begin() + static_cast<std::ptrdiff_t>(len));
    DecodeResult result;
    REQUIRE_NOTHROW(result = DecodeCameraDetections(prefix.data(), prefix.size()));
    INFO("length " << len << ": " << result.reason);
    REQUIRE(result.status == DecodeStatus::kTruncated);
    REQUIRE(!result.reason.empty());
  }
  // A null pointer with size 0 is simply too short.
  CHECK(DecodeCameraDetections(nullptr, 0).status == DecodeStatus::kTruncated);
}

TEST_CASE("a foreign fingerprint is kBadFingerprint and names a known type", "[unit]") {
  std::vector<std::uint8_t> bytes = EncodeCameraDetections(MakeRealisticFrame(6), 0, 0);
  bytes[7] ^= 0x01;
  RequireRejected(bytes, DecodeStatus::kBadFingerprint, "another type or another version");

  tracker::Frame3D tracks;
  const std::vector<std::uint8_t> other = EncodeTracks(tracks, core::KeypointLayoutId::kNone, 0, 0);
  RequireRejected(other, DecodeStatus::kBadFingerprint, "the bytes are a mvtrack tracks3d_t");
}

TEST_CASE("negative counts are kMalformed and name field and element", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(7);
  const mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  const std::vector<std::uint8_t> good = EncodeLcm(msg);
  const testing::CameraDetectionsOffsets offsets = OffsetsOf(msg);
  REQUIRE(offsets.total == good.size());

  std::vector<std::uint8_t> bytes = good;
  PutBigEndian(&bytes, offsets.num_detections, static_cast<std::uint32_t>(-5), 4);
  RequireRejected(bytes, DecodeStatus::kMalformed, "num_detections -5 is negative (byte 36)");

  for (std::size_t i = 0; i < offsets.detections.size(); ++i) {
    const std::string prefix = "detection " + std::to_string(i) + ": ";
    bytes = good;
    PutBigEndian(&bytes, offsets.detections[i].num_keypoints, 0xFFFB, 2);  // -5
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_keypoints -5 is negative");
    bytes = good;
    PutBigEndian(&bytes, offsets.detections[i].num_embedding, 0x8000, 2);  // INT16_MIN
    RequireRejected(bytes, DecodeStatus::kMalformed, prefix + "num_embedding -32768 is negative");
  }
}

TEST_CASE("huge counts never allocate: over the limit or beyond the bytes", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(8);
  const mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  const std::vector<std::uint8_t> good = EncodeLcm(msg);
  const testing::CameraDetectionsOffsets offsets = OffsetsOf(msg);
  DecodeLimits unlimited;
  unlimited.max_detections = INT_MAX;
  unlimited.max_keypoints = INT_MAX;
  unlimited.max_embedding = INT_MAX;

  std::vector<std::uint8_t> bytes = good;
  PutBigEndian(&bytes, offsets.num_detections, INT32_MAX, 4);
  RequireRejected(
      bytes, DecodeStatus::kLimitExceeded, "num_detections 2147483647 exceeds the limit 1000");
  RequireRejected(
      bytes, DecodeStatus::kTruncated, "num_detections 2147483647 needs at least", unlimited);
  // The generated decoder alone would size a vector of 2^31 - 1 detection_t (~ 200 GB).
  PutBigEndian(&bytes, offsets.num_detections, 1001, 4);
  RequireRejected(bytes, DecodeStatus::kLimitExceeded, "exceeds the limit 1000");

  for (std::size_t i = 0; i < offsets.detections.size(); ++i) {
    const std::string prefix = "detection " + std::to_string(i) + ": ";
    bytes = good;
    PutBigEndian(&bytes, offsets.detections[i].num_keypoints, 32767, 2);
    RequireRejected(
        bytes, DecodeStatus::kLimitExceeded, prefix + "num_keypoints 32767 exceeds the limit 64");
    RequireRejected(
        bytes, DecodeStatus::kTruncated, prefix + "num_keypoints 32767 needs", unlimited);
    bytes = good;
    PutBigEndian(&bytes, offsets.detections[i].num_embedding, 4097, 2);
    RequireRejected(
        bytes, DecodeStatus::kLimitExceeded, prefix + "num_embedding 4097 exceeds the limit 4096");
    RequireRejected(
        bytes, DecodeStatus::kTruncated, prefix + "num_embedding 4097 needs", unlimited);
  }
}

TEST_CASE("the allocation probe sees what the generated decoder alone would allocate", "[unit]") {
  // The same forged count through both decoders: LCM's sizes the vector first (the probe must
  // see it, or the "no large allocation" checks above would be vacuous), ours does not.
  const core::CameraFrame frame = MakeRealisticFrame(14);
  const mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  std::vector<std::uint8_t> bytes = EncodeLcm(msg);
  PutBigEndian(&bytes, OffsetsOf(msg).detections[2].num_embedding, 32767, 2);
  std::size_t generated_largest = 0;
  {
    AllocationProbe probe;
    mvtrack::camera_detections_t raw;
    CHECK(raw.decode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0);
    generated_largest = probe.largest();
  }
  CHECK(generated_largest >= 32767 * sizeof(float));
  DecodeLimits limits;
  limits.max_embedding = 32767;
  RequireRejected(
      bytes, DecodeStatus::kTruncated, "detection 2: num_embedding 32767 needs", limits);
}

TEST_CASE("limits are enforced exactly at their value", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(9);  // 5 detections, <= 25 keypoints
  const std::vector<std::uint8_t> bytes = EncodeCameraDetections(frame, 0, 0);
  DecodeLimits limits;
  limits.max_detections = 5;
  limits.max_keypoints = 25;
  limits.max_embedding = 16;
  limits.max_string = 6;  // "coco17", "body25"
  CHECK(DecodeCameraDetections(bytes.data(), bytes.size(), limits).ok());
  limits.max_detections = 4;
  RequireRejected(
      bytes, DecodeStatus::kLimitExceeded, "num_detections 5 exceeds the limit 4", limits);
  limits.max_detections = 5;
  limits.max_keypoints = 24;
  RequireRejected(bytes,
                  DecodeStatus::kLimitExceeded,
                  "detection 3: num_keypoints 25 exceeds the limit 24",
                  limits);
  limits.max_keypoints = 25;
  limits.max_embedding = 15;
  RequireRejected(bytes,
                  DecodeStatus::kLimitExceeded,
                  "detection 2: num_embedding 16 exceeds the limit 15",
                  limits);
  limits.max_embedding = 16;
  limits.max_string = 5;
  RequireRejected(bytes,
                  DecodeStatus::kLimitExceeded,
                  "detection 1: keypoint_layout of 6 bytes exceeds the limit 5",
                  limits);
}

TEST_CASE("invalid string lengths are rejected before the generated decoder sees them", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(10);
  const mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  const std::vector<std::uint8_t> good = EncodeLcm(msg);
  const testing::CameraDetectionsOffsets offsets = OffsetsOf(msg);
  DecodeLimits unlimited_strings;
  unlimited_strings.max_string = INT_MAX;

  // Why the walk exists: LCM 1.3.1's generated decoder throws on a string length of 0.
  {
    std::vector<std::uint8_t> bytes = good;
    PutBigEndian(&bytes, offsets.detections[0].keypoint_layout, 0, 4);
    mvtrack::camera_detections_t raw;
    CHECK_THROWS_AS(raw.decode(bytes.data(), 0, static_cast<int>(bytes.size())), std::length_error);
  }
  for (std::size_t i = 0; i < offsets.detections.size(); ++i) {
    const std::string prefix = "detection " + std::to_string(i) + ": ";
    using Field = std::pair<std::string, std::size_t>;
    for (const auto& [field, offset] :
         {Field{"keypoint_layout", offsets.detections[i].keypoint_layout},
          Field{"embedding_model", offsets.detections[i].embedding_model}}) {
      std::vector<std::uint8_t> bytes = good;
      PutBigEndian(&bytes, offset, 0, 4);
      RequireRejected(bytes, DecodeStatus::kMalformed, prefix + field + " length 0 is invalid");
      PutBigEndian(&bytes, offset, static_cast<std::uint32_t>(-1), 4);
      RequireRejected(bytes, DecodeStatus::kMalformed, prefix + field + " length -1 is invalid");
      PutBigEndian(&bytes, offset, INT32_MAX, 4);
      RequireRejected(bytes,
                      DecodeStatus::kLimitExceeded,
                      prefix + field + " of 2147483646 bytes exceeds the limit 64");
      RequireRejected(bytes,
                      DecodeStatus::kTruncated,
                      prefix + field + " length 2147483647 exceeds the",
                      unlimited_strings);
    }
  }
}

TEST_CASE("string contents: NUL terminator, printable ASCII, known layout", "[unit]") {
  const core::CameraFrame frame = MakeRealisticFrame(11);
  const mvtrack::camera_detections_t msg = ToLcm(frame, kWidth, kHeight);
  const std::vector<std::uint8_t> good = EncodeLcm(msg);
  const testing::CameraDetectionsOffsets offsets = OffsetsOf(msg);
  const std::size_t layout_text = offsets.detections[1].keypoint_layout + 4;  // "coco17\0"
  REQUIRE(std::memcmp(good.data() + layout_text, "coco17", 7) == 0);

  std::vector<std::uint8_t> bytes = good;
  bytes[layout_text + 5] = '8';  // "coco18"
  RequireRejected(
      bytes, DecodeStatus::kMalformed, "detection 1: unknown keypoint_layout \"coco18\"");
  bytes = good;
  bytes[layout_text + 6] = 'x';  // terminator overwritten
  RequireRejected(
      bytes, DecodeStatus::kMalformed, "detection 1: keypoint_layout is not NUL-terminated");
  bytes = good;
  bytes[layout_text + 2] = 0;  // embedded NUL
  RequireRejected(bytes, DecodeStatus::kMalformed, "contains byte 0 at index 2");
  bytes = good;
  bytes[layout_text] = 0xC3;  // non-ASCII
  RequireRejected(bytes, DecodeStatus::kMalformed, "contains byte 195 at index 0");
}

TEST_CASE("oversize messages and trailing bytes are rejected", "[unit]") {
  const std::vector<std::uint8_t> good = EncodeCameraDetections(MakeRealisticFrame(12), 0, 0);
  DecodeLimits limits;
  limits.max_message_bytes = good.size();
  CHECK(DecodeCameraDetections(good.data(), good.size(), limits).ok());
  limits.max_message_bytes = good.size() - 1;
  RequireRejected(good,
                  DecodeStatus::kTooLarge,
                  "message of " + std::to_string(good.size()) + " bytes exceeds max_message_bytes",
                  limits);
  std::vector<std::uint8_t> longer = good;
  longer.push_back(0);
  RequireRejected(longer, DecodeStatus::kMalformed, "1 trailing bytes after the message");
}

TEST_CASE("DecodeLimits::Validate names the bad field", "[unit]") {
  std::string why;
  CHECK(DecodeLimits{}.Validate(&why));
  DecodeLimits limits;
  limits.max_message_bytes = 7;
  CHECK_FALSE(limits.Validate(&why));
  CHECK_THAT(why, Catch::Matchers::Contains("max_message_bytes"));
  limits = DecodeLimits{};
  limits.max_message_bytes = std::size_t{1} << 31;
  CHECK_FALSE(limits.Validate(&why));
  limits = DecodeLimits{};
  limits.max_embedding = -1;
  CHECK_FALSE(limits.Validate(&why));
  CHECK_THAT(why, Catch::Matchers::Contains("max_embedding"));
}

// One random structural mutation of `bytes`.
void Mutate(std::mt19937* rng, std::vector<std::uint8_t>* bytes) {
  auto pick = [rng](std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(*rng);
  };
  switch (pick(6)) {
    case 0: {  // flip one bit
      (*bytes)[pick(bytes->size())] ^= static_cast<std::uint8_t>(1u << pick(8));
      break;
    }
    case 1: {  // random byte
      (*bytes)[pick(bytes->size())] = static_cast<std::uint8_t>(pick(256));
      break;
    }
    case 2: {  // an extreme 2- or 4-byte value somewhere (hits counts and string lengths)
      const std::uint64_t extremes[] = {
          0, 0xFFFFFFFFu, 0x7FFFFFFFu, 0x80000000u, 1, 0x7FFFu, 0x8000u};
      const std::size_t width = pick(2) == 0 ? 2 : 4;
      if (bytes->size() < width) break;
      PutBigEndian(bytes, pick(bytes->size() - width + 1), extremes[pick(7)], width);
      break;
    }
    case 3: {  // truncate
      bytes->resize(pick(bytes->size()));
      break;
    }
    case 4: {  // insert a byte
      const auto at = static_cast<std::ptrdiff_t>(pick(bytes->size() + 1));
      bytes->insert(bytes->begin() + at, static_cast<std::uint8_t>(pick(256)));
      break;
    }
    default: {  // delete a byte
      bytes->erase(bytes->begin() + static_cast<std::ptrdiff_t>(pick(bytes->size())));
      break;
    }
  }
}

TEST_CASE("20000 random mutations never crash and every kOk re-encodes consistently", "[unit]") {
  std::mt19937 rng(20240611);
  // Box only, COCO-17 pose, COCO-17 pose + embedding, box only (the BODY-25 pose is dropped to
  // keep the loop fast: mutations then hit counts and strings more often, too).
  core::CameraFrame frame = MakeRealisticFrame(13);
  frame.detections.erase(frame.detections.begin() + 3);
  const std::vector<std::uint8_t> good = EncodeCameraDetections(frame, kWidth, kHeight);
  int ok = 0;
  std::size_t largest = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    std::vector<std::uint8_t> bytes = good;
    const int mutations = 1 + static_cast<int>(rng() % 3);
    for (int m = 0; m < mutations && !bytes.empty(); ++m) Mutate(&rng, &bytes);
    DecodeResult result;
    {
      AllocationProbe probe;
      result = DecodeCameraDetections(bytes.data(), bytes.size());
      largest = std::max(largest, probe.largest());
    }
    if (!result.ok()) {
      if (result.reason.empty()) FAIL("iteration " << iteration << ": failure without reason");
      continue;
    }
    ++ok;
    if (!result.reason.empty()) FAIL("iteration " << iteration << ": kOk with a reason");
    const std::vector<std::uint8_t> again =
        EncodeCameraDetections(result.frame, result.image_width_px, result.image_height_px);
    const DecodeResult second = DecodeCameraDetections(again.data(), again.size());
    if (!second.ok()) {
      FAIL("iteration " << iteration << ": re-encoded message fails: " << second.reason);
    }
    const std::string diff = DiffCameraFrames(second.frame, result.frame);
    if (!diff.empty()) FAIL("iteration " << iteration << ": re-encoding changed " << diff);
    if (second.image_width_px != result.image_width_px ||
        second.image_height_px != result.image_height_px) {
      FAIL("iteration " << iteration << ": image size changed");
    }
  }
  // Value-only mutations (floats, ids) decode fine: the loop really exercises both paths.
  CHECK(ok > 1000);
  CHECK(ok < 19000);
  CHECK(largest < 64 * 1024);
}

}  // namespace
}  // namespace mvtrack::transport
