#pragma once
/// @file
/// Internal: a bounds-checked reader over LCM-encoded bytes (big-endian, the LCM wire format)
/// that records the first structural problem with a reason naming field, element and byte
/// offset. Used by the Decode* functions to validate a message before the generated decoder
/// sees it. Single-owner, single-threaded; never allocates based on message contents.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/check.h"
#include "core/keypoint_layout.h"
#include "transport/codec.h"

namespace mvtrack::transport::internal {

/// The layout a message's keypoint_layout string names: "" is box-only (kNone); nullopt for a
/// name no layout has.
inline std::optional<core::KeypointLayoutId> LayoutOfName(std::string_view name) {
  if (name.empty()) return core::KeypointLayoutId::kNone;
  return core::KeypointLayoutFromName(name);
}

/// Wire sizes of the LCM primitive types, bytes.
inline constexpr std::size_t kInt8Bytes = 1;
inline constexpr std::size_t kInt16Bytes = 2;
inline constexpr std::size_t kInt32Bytes = 4;
inline constexpr std::size_t kInt64Bytes = 8;
inline constexpr std::size_t kFloatBytes = 4;
inline constexpr std::size_t kDoubleBytes = 8;
/// The smallest LCM string: its int32 length and the NUL.
inline constexpr std::size_t kMinStringBytes = kInt32Bytes + 1;

/// Walks encoded bytes front to back. Every Read* returns false once a problem was found (and
/// keeps returning false), so callers can chain reads and check once.
class WireWalker {
 public:
  /// Walks `data[0, size)`; the bytes must outlive the walker (ReadString views into them).
  WireWalker(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  /// Prefix of every reason, e.g. "detection 3" (empty for top-level fields).
  void set_context(std::string context) { context_ = std::move(context); }

  /// False once a problem was found; status() and reason() then describe the first one.
  bool ok() const { return ok_; }
  DecodeStatus status() const { return status_; }
  const std::string& reason() const { return reason_; }
  /// Offset of the next unread byte.
  std::size_t position() const { return pos_; }
  /// Bytes not yet read.
  std::size_t remaining() const { return size_ - pos_; }

  /// Big-endian signed integers.
  bool ReadInt8(std::string_view field, std::int8_t* value);
  bool ReadInt16(std::string_view field, std::int16_t* value);
  bool ReadInt32(std::string_view field, std::int32_t* value);
  bool ReadInt64(std::string_view field, std::int64_t* value);

  /// Skips `bytes` bytes of fixed-size fields (their values need no check).
  bool Skip(std::string_view field, std::size_t bytes);

  /// Reads an int16 or int32 element count and checks it: negative -> kMalformed, above
  /// `limit` -> kLimitExceeded, more than the remaining bytes can hold at `min_element_bytes`
  /// each -> kTruncated.
  bool ReadCount16(std::string_view field,
                   int limit,
                   std::size_t min_element_bytes,
                   std::int32_t* count);
  bool ReadCount32(std::string_view field,
                   int limit,
                   std::size_t min_element_bytes,
                   std::int32_t* count);

  /// Reads an LCM string (int32 length including the NUL terminator, the bytes, the NUL) and
  /// checks it: length < 1 -> kMalformed, content longer than `max_length` -> kLimitExceeded,
  /// length beyond the remaining bytes -> kTruncated, last byte not NUL or a content byte
  /// outside printable ASCII (0x20..0x7E, the rule of lcmtypes/README.md) -> kMalformed.
  /// `value` views the content (without the NUL) inside the walked buffer.
  bool ReadString(std::string_view field, int max_length, std::string_view* value);

  /// Records a problem found by the caller (e.g. an unknown enum value) at the current offset.
  /// `at` is the byte offset the reason names.
  bool Fail(DecodeStatus status, std::string_view what, std::size_t at);

 private:
  bool Need(std::string_view field, std::size_t bytes);
  bool ReadCount(std::string_view field,
                 std::int64_t raw,
                 std::size_t count_at,
                 int limit,
                 std::size_t min_element_bytes,
                 std::int32_t* count);
  std::uint64_t ReadBigEndian(std::size_t bytes);

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::string context_;
  bool ok_ = true;
  DecodeStatus status_ = DecodeStatus::kOk;
  std::string reason_;
};

/// Walks the 8-byte fingerprint at the start of a message and compares it with `expected`;
/// kTruncated when fewer than 8 bytes, kBadFingerprint (naming the actual type when it is
/// another mvtrack type) on mismatch.
bool WalkFingerprint(WireWalker* walker, std::int64_t expected, std::string_view type_name);

/// Checks the preconditions shared by every Decode*: limits valid (aborts otherwise), size
/// within max_message_bytes (kTooLarge), non-null data when size > 0 (kMalformed). Returns
/// false with status and reason set on failure.
bool CheckEnvelope(const void* data,
                   std::size_t size,
                   const DecodeLimits& limits,
                   DecodeStatus* status,
                   std::string* reason);

/// The decode sequence every message type shares: CheckEnvelope, the structure walk `walk`
/// (bool(WireWalker*, const DecodeLimits&)), then the generated decoder of `Message`, which must
/// consume exactly `size` bytes, and `convert(const Message&)`, both inside try/catch so no
/// exception escapes. Returns false with status and reason set on failure.
template <typename Message, typename Walk, typename Convert>
bool CheckedDecode(const void* data,
                   std::size_t size,
                   const DecodeLimits& limits,
                   Walk&& walk,
                   Convert&& convert,
                   DecodeStatus* status,
                   std::string* reason) {
  if (!CheckEnvelope(data, size, limits, status, reason)) return false;
  WireWalker walker(static_cast<const std::uint8_t*>(data), size);
  if (!walk(&walker, limits)) {
    *status = walker.status();
    *reason = walker.reason();
    return false;
  }
  try {
    Message msg;
    const int consumed = msg.decode(data, 0, static_cast<int>(size));
    if (consumed < 0 || static_cast<std::size_t>(consumed) != size) {
      *status = DecodeStatus::kMalformed;
      *reason = "the generated decoder disagrees with the structure walk (returned " +
                std::to_string(consumed) + " for " + std::to_string(size) + " bytes)";
      return false;
    }
    convert(msg);
  } catch (const std::exception& e) {
    *status = DecodeStatus::kMalformed;
    *reason = std::string("the generated decoder threw: ") + e.what();
    return false;
  }
  *status = DecodeStatus::kOk;
  return true;
}

/// A double as a float the way IEEE-754 narrowing does it (values beyond the float range
/// become +-infinity, NaN stays NaN) without the undefined behaviour of an out-of-range cast.
float NarrowToFloat(double value);

/// The bytes of a generated LCM message. Aborts (checked) when it is too large to encode (an
/// int32 size overflow) or its encoder does not write exactly getEncodedSize() bytes.
template <typename Message>
std::vector<std::uint8_t> EncodeMessage(const Message& msg) {
  const int size = msg.getEncodedSize();
  MVTRACK_CHECK_MSG(size > 0, "an LCM message too large to encode");
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  const int written = msg.encode(bytes.data(), 0, size);
  MVTRACK_CHECK_MSG(written == size, "LCM encode failed");
  return bytes;
}

/// `to` resized to `from` and `copy(from[i], &(*to)[i])` for each element: the nested structs of
/// a message copied field by field, in either direction.
template <typename From, typename To, typename Copy>
void CopyEach(const std::vector<From>& from, std::vector<To>* to, Copy copy) {
  to->resize(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) copy(from[i], &(*to)[i]);
}

}  // namespace mvtrack::transport::internal
