// analytics_event_t and site_counts_t <-> lib/analytics' events and counts (issue 41).

#include <climits>
#include <cmath>
#include <cstdint>
#include <mvtrack/analytics_event_t.hpp>
#include <mvtrack/site_counts_t.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "transport/codec.h"
#include "transport/internal/wire_walker.h"

namespace mvtrack::transport {
namespace {

using internal::kInt32Bytes;
using internal::kInt64Bytes;
using internal::kInt8Bytes;
using internal::WireWalker;

using internal::kMinStringBytes;

bool WalkEvent(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(
          w, mvtrack::analytics_event_t::getHash(), mvtrack::analytics_event_t::getTypeName())) {
    return false;
  }
  w->Skip("utime, publish_utime", 2 * kInt64Bytes);
  std::int8_t kind = 0;
  if (!w->ReadInt8("kind", &kind)) return false;
  if (kind < mvtrack::analytics_event_t::KIND_ENTER ||
      kind > mvtrack::analytics_event_t::KIND_CROSSING) {
    return w->Fail(DecodeStatus::kMalformed,
                   "kind " + std::to_string(kind) + " is not a KIND_*",
                   w->position() - 1);
  }
  std::string_view name;
  if (!w->ReadString("name", limits.max_string, &name)) return false;
  w->Skip("track_id, enter_utime", 2 * kInt64Bytes);
  std::int8_t direction = 0;
  if (!w->ReadInt8("direction", &direction)) return false;
  if (direction != mvtrack::analytics_event_t::DIRECTION_LEFT_TO_RIGHT &&
      direction != mvtrack::analytics_event_t::DIRECTION_RIGHT_TO_LEFT) {
    return w->Fail(DecodeStatus::kMalformed,
                   "direction " + std::to_string(direction) + " is not a DIRECTION_*",
                   w->position() - 1);
  }
  w->Skip("track_ended", kInt8Bytes);
  if (w->ok() && w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return w->ok();
}

bool WalkCounts(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(
          w, mvtrack::site_counts_t::getHash(), mvtrack::site_counts_t::getTypeName())) {
    return false;
  }
  w->Skip("utime, publish_utime", 2 * kInt64Bytes);
  std::string_view name;
  std::int32_t regions = 0;
  if (!w->ReadCount16("num_regions",
                      limits.max_site_items,
                      kMinStringBytes + kInt32Bytes + 2 * kInt64Bytes,
                      &regions)) {
    return false;
  }
  for (std::int32_t i = 0; i < regions; ++i) {
    if (!w->ReadString("region_names", limits.max_string, &name)) return false;
  }
  w->Skip("occupancy", static_cast<std::size_t>(regions) * kInt32Bytes);
  w->Skip("entries, exits", 2 * static_cast<std::size_t>(regions) * kInt64Bytes);
  std::int32_t lines = 0;
  if (!w->ReadCount16(
          "num_lines", limits.max_site_items, kMinStringBytes + 2 * kInt64Bytes, &lines)) {
    return false;
  }
  for (std::int32_t i = 0; i < lines; ++i) {
    if (!w->ReadString("line_names", limits.max_string, &name)) return false;
  }
  w->Skip("left_to_right, right_to_left", 2 * static_cast<std::size_t>(lines) * kInt64Bytes);
  if (w->ok() && w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return w->ok();
}

Utime ToUtime(double seconds) { return static_cast<Utime>(std::llround(seconds * 1e6)); }

}  // namespace

AnalyticsEventDecodeResult DecodeAnalyticsEvent(const void* data,
                                                std::size_t size,
                                                const DecodeLimits& limits) {
  AnalyticsEventDecodeResult result;
  const auto convert = [&](const mvtrack::analytics_event_t& msg) {
    AnalyticsEventMessage& m = result.message;
    m.utime = msg.utime;
    m.publish_utime = msg.publish_utime;
    m.kind = static_cast<analytics::Event::Kind>(msg.kind);
    m.name = msg.name;
    m.track_id = msg.track_id;
    m.enter_utime = msg.enter_utime;
    m.direction = msg.direction == mvtrack::analytics_event_t::DIRECTION_LEFT_TO_RIGHT
                      ? analytics::Event::Direction::kLeftToRight
                      : analytics::Event::Direction::kRightToLeft;
    m.track_ended = msg.track_ended;
  };
  internal::CheckedDecode<mvtrack::analytics_event_t>(
      data, size, limits, WalkEvent, convert, &result.status, &result.reason);
  return result;
}

std::vector<std::uint8_t> EncodeAnalyticsEvent(const AnalyticsEventMessage& e) {
  mvtrack::analytics_event_t msg;
  msg.utime = e.utime;
  msg.publish_utime = e.publish_utime;
  switch (e.kind) {
    case analytics::Event::Kind::kEnter:
      msg.kind = mvtrack::analytics_event_t::KIND_ENTER;
      break;
    case analytics::Event::Kind::kExit:
      msg.kind = mvtrack::analytics_event_t::KIND_EXIT;
      break;
    case analytics::Event::Kind::kCrossing:
      msg.kind = mvtrack::analytics_event_t::KIND_CROSSING;
      break;
  }
  msg.name = e.name;
  msg.track_id = e.track_id;
  msg.enter_utime = e.enter_utime;
  msg.direction = e.direction == analytics::Event::Direction::kLeftToRight
                      ? mvtrack::analytics_event_t::DIRECTION_LEFT_TO_RIGHT
                      : mvtrack::analytics_event_t::DIRECTION_RIGHT_TO_LEFT;
  msg.track_ended = e.track_ended;
  return internal::EncodeMessage(msg);
}

AnalyticsEventMessage ToAnalyticsEventMessage(const analytics::Event& event,
                                              const analytics::Site& site,
                                              Utime publish_utime) {
  AnalyticsEventMessage m;
  m.utime = ToUtime(event.time_s);
  m.publish_utime = publish_utime;
  m.kind = event.kind;
  m.name = event.kind == analytics::Event::Kind::kCrossing
               ? site.lines[static_cast<std::size_t>(event.line)].name
               : site.regions[static_cast<std::size_t>(event.region)].name;
  m.track_id = event.track;
  m.enter_utime =
      event.kind == analytics::Event::Kind::kExit ? ToUtime(event.enter_time_s) : m.utime;
  m.direction = event.kind == analytics::Event::Kind::kCrossing
                    ? event.direction
                    : analytics::Event::Direction::kLeftToRight;
  m.track_ended = event.kind == analytics::Event::Kind::kExit && event.track_ended;
  return m;
}

SiteCountsDecodeResult DecodeSiteCounts(const void* data,
                                        std::size_t size,
                                        const DecodeLimits& limits) {
  SiteCountsDecodeResult result;
  const auto convert = [&](const mvtrack::site_counts_t& msg) {
    SiteCounts& c = result.message;
    c.utime = msg.utime;
    c.publish_utime = msg.publish_utime;
    c.region_names = msg.region_names;
    c.regions.resize(msg.region_names.size());
    for (std::size_t i = 0; i < c.regions.size(); ++i) {
      c.regions[i].occupancy = msg.occupancy[i];
      c.regions[i].entries = msg.entries[i];
      c.regions[i].exits = msg.exits[i];
    }
    c.line_names = msg.line_names;
    c.lines.resize(msg.line_names.size());
    for (std::size_t i = 0; i < c.lines.size(); ++i) {
      c.lines[i].left_to_right = msg.left_to_right[i];
      c.lines[i].right_to_left = msg.right_to_left[i];
    }
  };
  internal::CheckedDecode<mvtrack::site_counts_t>(
      data, size, limits, WalkCounts, convert, &result.status, &result.reason);
  return result;
}

std::vector<std::uint8_t> EncodeSiteCounts(const SiteCounts& c) {
  MVTRACK_CHECK(c.region_names.size() == c.regions.size());
  MVTRACK_CHECK(c.line_names.size() == c.lines.size());
  MVTRACK_CHECK(c.regions.size() <= static_cast<std::size_t>(INT16_MAX));
  MVTRACK_CHECK(c.lines.size() <= static_cast<std::size_t>(INT16_MAX));
  mvtrack::site_counts_t msg;
  msg.utime = c.utime;
  msg.publish_utime = c.publish_utime;
  msg.num_regions = static_cast<std::int16_t>(c.regions.size());
  msg.region_names = c.region_names;
  for (const analytics::RegionCounts& r : c.regions) {
    msg.occupancy.push_back(r.occupancy);
    msg.entries.push_back(r.entries);
    msg.exits.push_back(r.exits);
  }
  msg.num_lines = static_cast<std::int16_t>(c.lines.size());
  msg.line_names = c.line_names;
  for (const analytics::LineCounts& l : c.lines) {
    msg.left_to_right.push_back(l.left_to_right);
    msg.right_to_left.push_back(l.right_to_left);
  }
  return internal::EncodeMessage(msg);
}

}  // namespace mvtrack::transport
