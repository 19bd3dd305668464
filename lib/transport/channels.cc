#include "transport/channels.h"

#include <charconv>
#include <cstdint>

#include "core/check.h"

namespace mvtrack::transport {

std::string DetectionsChannelForCamera(CameraId camera_id) {
  MVTRACK_CHECK_MSG(camera_id >= 0, "camera ids are non-negative");
  return std::string(kDetectionsChannelPrefix) + std::to_string(camera_id);
}

std::optional<CameraId> CameraIdFromChannel(std::string_view channel) {
  const std::string_view prefix(kDetectionsChannelPrefix);
  if (channel.size() <= prefix.size() || channel.substr(0, prefix.size()) != prefix) {
    return std::nullopt;
  }
  const std::string_view digits = channel.substr(prefix.size());
  for (const char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  if (digits.size() > 1 && digits.front() == '0') return std::nullopt;  // not canonical
  CameraId id = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return id;
}

bool IsDetectionsChannel(std::string_view channel) {
  return channel == kDetectionsChannel || CameraIdFromChannel(channel).has_value();
}

}  // namespace mvtrack::transport
