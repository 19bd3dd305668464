#include "transport/internal/wire_walker.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <mvtrack/camera_detections_t.hpp>
#include <mvtrack/camera_status_t.hpp>
#include <mvtrack/detection_t.hpp>
#include <mvtrack/joint3d_t.hpp>
#include <mvtrack/keypoint2d_t.hpp>
#include <mvtrack/track3d_t.hpp>
#include <mvtrack/tracker_status_t.hpp>
#include <mvtrack/tracks3d_t.hpp>
#include <string>

#include "core/check.h"

namespace mvtrack::transport::internal {
namespace {

std::string Hex64(std::uint64_t value) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text = "0x";
  for (int shift = 60; shift >= 0; shift -= 4) {
    text.push_back(kDigits[(value >> static_cast<unsigned>(shift)) & 0xFu]);
  }
  return text;
}

// The mvtrack type whose fingerprint is `hash`, or nullptr.
const char* MvtrackTypeOfHash(std::int64_t hash) {
  struct Entry {
    std::int64_t hash;
    const char* name;
  };
  const Entry entries[] = {
      {mvtrack::camera_detections_t::getHash(), mvtrack::camera_detections_t::getTypeName()},
      {mvtrack::camera_status_t::getHash(), mvtrack::camera_status_t::getTypeName()},
      {mvtrack::detection_t::getHash(), mvtrack::detection_t::getTypeName()},
      {mvtrack::joint3d_t::getHash(), mvtrack::joint3d_t::getTypeName()},
      {mvtrack::keypoint2d_t::getHash(), mvtrack::keypoint2d_t::getTypeName()},
      {mvtrack::track3d_t::getHash(), mvtrack::track3d_t::getTypeName()},
      {mvtrack::tracker_status_t::getHash(), mvtrack::tracker_status_t::getTypeName()},
      {mvtrack::tracks3d_t::getHash(), mvtrack::tracks3d_t::getTypeName()},
  };
  for (const Entry& entry : entries) {
    if (entry.hash == hash) return entry.name;
  }
  return nullptr;
}

}  // namespace

bool WireWalker::Fail(DecodeStatus status, std::string_view what, std::size_t at) {
  if (!ok_) return false;
  ok_ = false;
  status_ = status;
  reason_.clear();
  if (!context_.empty()) {
    reason_ += context_;
    reason_ += ": ";
  }
  reason_ += what;
  reason_ += " (byte ";
  reason_ += std::to_string(at);
  reason_ += ")";
  return false;
}

bool WireWalker::Need(std::string_view field, std::size_t bytes) {
  if (!ok_) return false;
  if (remaining() >= bytes) return true;
  return Fail(DecodeStatus::kTruncated,
              std::string(field) + " needs " + std::to_string(bytes) + " bytes but the message" +
                  " ends after " + std::to_string(remaining()),
              pos_);
}

std::uint64_t WireWalker::ReadBigEndian(std::size_t bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes; ++i) value = (value << 8u) | data_[pos_ + i];
  pos_ += bytes;
  return value;
}

bool WireWalker::ReadInt8(std::string_view field, std::int8_t* value) {
  if (!Need(field, kInt8Bytes)) return false;
  *value = static_cast<std::int8_t>(static_cast<std::uint8_t>(ReadBigEndian(kInt8Bytes)));
  return true;
}

bool WireWalker::ReadInt16(std::string_view field, std::int16_t* value) {
  if (!Need(field, kInt16Bytes)) return false;
  *value = static_cast<std::int16_t>(static_cast<std::uint16_t>(ReadBigEndian(kInt16Bytes)));
  return true;
}

bool WireWalker::ReadInt32(std::string_view field, std::int32_t* value) {
  if (!Need(field, kInt32Bytes)) return false;
  *value = static_cast<std::int32_t>(static_cast<std::uint32_t>(ReadBigEndian(kInt32Bytes)));
  return true;
}

bool WireWalker::ReadInt64(std::string_view field, std::int64_t* value) {
  if (!Need(field, kInt64Bytes)) return false;
  *value = static_cast<std::int64_t>(ReadBigEndian(kInt64Bytes));
  return true;
}

bool WireWalker::Skip(std::string_view field, std::size_t bytes) {
  if (!Need(field, bytes)) return false;
  pos_ += bytes;
  return true;
}

bool WireWalker::ReadCount(std::string_view field,
                           std::int64_t raw,
                           std::size_t count_at,
                           int limit,
                           std::size_t min_element_bytes,
                           std::int32_t* count) {
  const std::string name(field);
  if (raw < 0) {
    return Fail(
        DecodeStatus::kMalformed, name + " " + std::to_string(raw) + " is negative", count_at);
  }
  if (raw > limit) {
    return Fail(DecodeStatus::kLimitExceeded,
                name + " " + std::to_string(raw) + " exceeds the limit " + std::to_string(limit),
                count_at);
  }
  // raw <= limit <= INT_MAX and min_element_bytes is a small constant: no overflow.
  const std::size_t needed = static_cast<std::size_t>(raw) * min_element_bytes;
  if (needed > remaining()) {
    return Fail(DecodeStatus::kTruncated,
                name + " " + std::to_string(raw) + " needs at least " + std::to_string(needed) +
                    " bytes but only " + std::to_string(remaining()) + " remain",
                count_at);
  }
  *count = static_cast<std::int32_t>(raw);
  return true;
}

bool WireWalker::ReadCount16(std::string_view field,
                             int limit,
                             std::size_t min_element_bytes,
                             std::int32_t* count) {
  const std::size_t at = pos_;
  std::int16_t raw = 0;
  if (!ReadInt16(field, &raw)) return false;
  return ReadCount(field, raw, at, limit, min_element_bytes, count);
}

bool WireWalker::ReadCount32(std::string_view field,
                             int limit,
                             std::size_t min_element_bytes,
                             std::int32_t* count) {
  const std::size_t at = pos_;
  std::int32_t raw = 0;
  if (!ReadInt32(field, &raw)) return false;
  return ReadCount(field, raw, at, limit, min_element_bytes, count);
}

bool WireWalker::ReadString(std::string_view field, int max_length, std::string_view* value) {
  const std::size_t at = pos_;
  const std::string name(field);
  std::int32_t length = 0;
  if (!ReadInt32(name + " length", &length)) return false;
  if (length < 1) {
    return Fail(DecodeStatus::kMalformed,
                name + " length " + std::to_string(length) +
                    " is invalid (LCM string lengths include the NUL terminator, so >= 1)",
                at);
  }
  if (length - 1 > max_length) {
    return Fail(DecodeStatus::kLimitExceeded,
                name + " of " + std::to_string(length - 1) + " bytes exceeds the limit " +
                    std::to_string(max_length),
                at);
  }
  const auto bytes = static_cast<std::size_t>(length);
  if (bytes > remaining()) {
    return Fail(DecodeStatus::kTruncated,
                name + " length " + std::to_string(length) + " exceeds the " +
                    std::to_string(remaining()) + " remaining bytes",
                at);
  }
  const std::size_t begin = pos_;
  if (data_[begin + bytes - 1] != 0) {
    return Fail(DecodeStatus::kMalformed, name + " is not NUL-terminated", begin + bytes - 1);
  }
  for (std::size_t i = 0; i + 1 < bytes; ++i) {
    const std::uint8_t c = data_[begin + i];
    if (c < 0x20 || c > 0x7E) {
      return Fail(DecodeStatus::kMalformed,
                  name + " contains byte " + std::to_string(static_cast<int>(c)) + " at index " +
                      std::to_string(i) + " (strings must be printable ASCII)",
                  begin + i);
    }
  }
  *value = std::string_view(reinterpret_cast<const char*>(data_ + begin), bytes - 1);
  pos_ += bytes;
  return true;
}

bool WalkFingerprint(WireWalker* walker, std::int64_t expected, std::string_view type_name) {
  std::int64_t hash = 0;
  if (!walker->ReadInt64("fingerprint", &hash)) return false;
  if (hash == expected) return true;
  std::string what = "fingerprint " + Hex64(static_cast<std::uint64_t>(hash)) + " is not " +
                     std::string(type_name) + "'s " + Hex64(static_cast<std::uint64_t>(expected));
  if (const char* other = MvtrackTypeOfHash(hash)) {
    what += " (the bytes are a mvtrack ";
    what += other;
    what += ")";
  } else {
    what += " (another type or another version of the type)";
  }
  return walker->Fail(DecodeStatus::kBadFingerprint, what, 0);
}

bool CheckEnvelope(const void* data,
                   std::size_t size,
                   const DecodeLimits& limits,
                   DecodeStatus* status,
                   std::string* reason) {
  std::string why;
  MVTRACK_CHECK_MSG(limits.Validate(&why), why.c_str());
  if (size > limits.max_message_bytes) {
    *status = DecodeStatus::kTooLarge;
    *reason = "message of " + std::to_string(size) + " bytes exceeds max_message_bytes " +
              std::to_string(limits.max_message_bytes);
    return false;
  }
  if (data == nullptr && size > 0) {
    *status = DecodeStatus::kMalformed;
    *reason = "null data pointer with size " + std::to_string(size);
    return false;
  }
  return true;
}

float NarrowToFloat(double value) {
  constexpr double kMax = static_cast<double>(std::numeric_limits<float>::max());
  // In range (or NaN, which IEEE-754 narrowing keeps, sign included): the plain conversion.
  if (!(std::abs(value) > kMax)) return static_cast<float>(value);
  // Beyond FLT_MAX: round to nearest, ties to even, as the hardware would. Values below
  // FLT_MAX + half an ulp still round to FLT_MAX; the tie rounds to infinity (FLT_MAX's
  // significand is odd).
  const double half_ulp = std::ldexp(1.0, 127 - 24);
  const float magnitude = std::abs(value) < kMax + half_ulp
                              ? std::numeric_limits<float>::max()
                              : std::numeric_limits<float>::infinity();
  return value < 0.0 ? -magnitude : magnitude;
}

}  // namespace mvtrack::transport::internal
