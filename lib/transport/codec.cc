#include "transport/codec.h"

#include <climits>
#include <string>

namespace mvtrack::transport {

bool DecodeLimits::Validate(std::string* why) const {
  auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = "DecodeLimits: " + message;
    return false;
  };
  if (max_message_bytes < 8) return fail("max_message_bytes must be >= 8 (the fingerprint)");
  if (max_message_bytes > static_cast<std::size_t>(INT32_MAX)) {
    return fail("max_message_bytes must be <= INT32_MAX (the generated decoder uses int)");
  }
  if (max_detections < 0) return fail("max_detections must be >= 0");
  if (max_keypoints < 0) return fail("max_keypoints must be >= 0");
  if (max_embedding < 0) return fail("max_embedding must be >= 0");
  if (max_string < 0) return fail("max_string must be >= 0");
  if (max_tracks < 0) return fail("max_tracks must be >= 0");
  if (max_cameras < 0) return fail("max_cameras must be >= 0");
  if (max_joints < 0) return fail("max_joints must be >= 0");
  if (max_site_items < 0) return fail("max_site_items must be >= 0");
  if (max_zones < 0) return fail("max_zones must be >= 0");
  return true;
}

const char* ToString(TracksLayer layer) {
  return layer == TracksLayer::kProvisional ? "provisional" : "final";
}

const char* ToString(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::kOk:
      return "ok";
    case DecodeStatus::kTooLarge:
      return "too large";
    case DecodeStatus::kBadFingerprint:
      return "bad fingerprint";
    case DecodeStatus::kTruncated:
      return "truncated";
    case DecodeStatus::kMalformed:
      return "malformed";
    case DecodeStatus::kLimitExceeded:
      return "limit exceeded";
  }
  return "unknown";
}

}  // namespace mvtrack::transport
