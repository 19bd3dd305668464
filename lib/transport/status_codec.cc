// tracker_status_t <-> transport::TrackerStatus, and the names of the status flags.

#include <climits>
#include <cstdint>
#include <mvtrack/camera_status_t.hpp>
#include <mvtrack/site_status_t.hpp>
#include <mvtrack/tracker_status_t.hpp>
#include <mvtrack/zone_status_t.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "transport/codec.h"
#include "transport/internal/wire_walker.h"

namespace mvtrack::transport {
namespace {

using internal::kFloatBytes;
using internal::kInt32Bytes;
using internal::kInt64Bytes;
using internal::kInt8Bytes;
using internal::WireWalker;

// camera_status_t: camera_id, flags, rate_hz, 2 utimes, 8 counters, 2 queue fields.
constexpr std::size_t kCameraStatusBytes =
    kInt32Bytes + kInt64Bytes + kFloatBytes + 2 * kInt64Bytes + 8 * kInt64Bytes + 2 * kInt32Bytes;

bool WalkStatus(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(
          w, mvtrack::tracker_status_t::getHash(), mvtrack::tracker_status_t::getTypeName())) {
    return false;
  }
  w->Skip("utime, period_us, uptime_us", 3 * kInt64Bytes);
  std::string_view text;
  if (!w->ReadString("instance_id", limits.max_string, &text)) return false;
  w->Skip("start_utime, sequence", 2 * kInt64Bytes);
  if (!w->ReadString("version", limits.max_string, &text)) return false;
  if (!w->ReadString("config_hash", limits.max_string, &text)) return false;
  w->Skip("flags, last_frame", 2 * kInt64Bytes);
  w->Skip("active_tracks, confirmed_tracks, num_latency_samples", 3 * kInt32Bytes);
  w->Skip("latency, windows, jobs", 5 * kInt64Bytes);
  w->Skip("executor_queue_depth", kInt32Bytes);
  w->Skip("kernel_drops", kInt64Bytes);
  w->Skip("embeddings_used, embeddings_dropped, tracks_revived, gallery_bytes", 4 * kInt64Bytes);
  std::int32_t num_cameras = 0;
  if (!w->ReadCount16("num_cameras", limits.max_cameras, kCameraStatusBytes, &num_cameras)) {
    return false;
  }
  w->Skip("cameras", static_cast<std::size_t>(num_cameras) * kCameraStatusBytes);
  if (w->ok() && w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return w->ok();
}

// The smallest zone_status_t: three empty strings (int32 length and NUL each), 9 int64
// fields, tracks and daemon_health.
constexpr std::size_t kMinZoneStatusBytes =
    3 * internal::kMinStringBytes + 9 * kInt64Bytes + kInt32Bytes + kInt8Bytes;

bool IsHealth(std::int8_t health) {
  return health >= mvtrack::zone_status_t::HEALTH_OK &&
         health <= mvtrack::zone_status_t::HEALTH_UNKNOWN;
}

bool WalkSiteStatus(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(
          w, mvtrack::site_status_t::getHash(), mvtrack::site_status_t::getTypeName())) {
    return false;
  }
  w->Skip("utime, period_us, uptime_us", 3 * kInt64Bytes);
  std::string_view text;
  if (!w->ReadString("instance_id", limits.max_string, &text)) return false;
  w->Skip("start_utime, sequence", 2 * kInt64Bytes);
  if (!w->ReadString("version", limits.max_string, &text)) return false;
  w->Skip("flags, last_frame, site_frames", 3 * kInt64Bytes);
  w->Skip("active_tracks", kInt32Bytes);
  w->Skip("global_ids, splits, merges", 3 * kInt64Bytes);
  w->Skip("num_wait_samples", kInt32Bytes);
  w->Skip("wait_p50_us, wait_p99_us, wait_max_us", 3 * kInt64Bytes);
  std::int32_t num_zones = 0;
  if (!w->ReadCount16("num_zones", limits.max_zones, kMinZoneStatusBytes, &num_zones)) {
    return false;
  }
  for (std::int32_t i = 0; i < num_zones; ++i) {
    w->set_context("zone " + std::to_string(i));
    if (!w->ReadString("name", limits.max_string, &text)) return false;
    if (!w->ReadString("channel", limits.max_string, &text)) return false;
    w->Skip("flags, frames, late, decode_errors, other_layer", 5 * kInt64Bytes);
    w->Skip("last_utime, last_receive_utime, latency_us", 3 * kInt64Bytes);
    w->Skip("tracks", kInt32Bytes);
    const std::size_t health_at = w->position();
    std::int8_t health = 0;
    if (!w->ReadInt8("daemon_health", &health)) return false;
    if (!IsHealth(health)) {
      return w->Fail(DecodeStatus::kMalformed,
                     "daemon_health " + std::to_string(static_cast<int>(health)) +
                         " is not one of zone_status_t::HEALTH_* (0..3)",
                     health_at);
    }
    if (!w->ReadString("daemon_reasons", kMaxDaemonReasons, &text)) return false;
    if (!w->ReadString("daemon_instance_id", limits.max_string, &text)) return false;
  }
  w->set_context("");
  if (w->ok() && w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return w->ok();
}

// The fields zone_status_t and ZoneStatus share by name, copied in either direction.
template <typename From, typename To>
void CopyZoneFields(const From& z, To* out) {
  out->name = z.name;
  out->channel = z.channel;
  out->flags = z.flags;
  out->frames = z.frames;
  out->late = z.late;
  out->decode_errors = z.decode_errors;
  out->other_layer = z.other_layer;
  out->last_utime = z.last_utime;
  out->last_receive_utime = z.last_receive_utime;
  out->latency_us = z.latency_us;
  out->tracks = z.tracks;
  out->daemon_health = z.daemon_health;
  out->daemon_reasons = z.daemon_reasons;
  out->daemon_instance_id = z.daemon_instance_id;
}

// The fields site_status_t and SiteStatus share by name (all but the zones).
template <typename From, typename To>
void CopySiteFields(const From& msg, To* out) {
  out->utime = msg.utime;
  out->period_us = msg.period_us;
  out->uptime_us = msg.uptime_us;
  out->instance_id = msg.instance_id;
  out->start_utime = msg.start_utime;
  out->sequence = msg.sequence;
  out->version = msg.version;
  out->flags = msg.flags;
  out->last_frame = msg.last_frame;
  out->site_frames = msg.site_frames;
  out->active_tracks = msg.active_tracks;
  out->global_ids = msg.global_ids;
  out->splits = msg.splits;
  out->merges = msg.merges;
  out->num_wait_samples = msg.num_wait_samples;
  out->wait_p50_us = msg.wait_p50_us;
  out->wait_p99_us = msg.wait_p99_us;
  out->wait_max_us = msg.wait_max_us;
}

std::vector<std::string> FlagNames(std::int64_t flags, const std::vector<std::string_view>& names) {
  std::vector<std::string> out;
  for (int bit = 0; bit < 64; ++bit) {
    if ((static_cast<std::uint64_t>(flags) >> bit & 1u) == 0) continue;
    out.emplace_back(static_cast<std::size_t>(bit) < names.size()
                         ? std::string(names[static_cast<std::size_t>(bit)])
                         : "BIT" + std::to_string(bit));
  }
  return out;
}

// The fields camera_status_t and CameraStatus share by name, copied in either direction.
template <typename From, typename To>
void CopyCameraFields(const From& c, To* cs) {
  cs->camera_id = c.camera_id;
  cs->flags = c.flags;
  cs->rate_hz = c.rate_hz;
  cs->last_utime = c.last_utime;
  cs->last_receive_utime = c.last_receive_utime;
  cs->received = c.received;
  cs->late = c.late;
  cs->dropped = c.dropped;
  cs->rejected = c.rejected;
  cs->decode_errors = c.decode_errors;
  cs->lost = c.lost;
  cs->clock_offset_us = c.clock_offset_us;
  cs->embeddings_dropped = c.embeddings_dropped;
  cs->queue_depth = c.queue_depth;
  cs->queue_capacity = c.queue_capacity;
}

// The fields tracker_status_t and TrackerStatus share by name (all but the cameras).
template <typename From, typename To>
void CopyStatusFields(const From& msg, To* out) {
  out->utime = msg.utime;
  out->period_us = msg.period_us;
  out->uptime_us = msg.uptime_us;
  out->instance_id = msg.instance_id;
  out->start_utime = msg.start_utime;
  out->sequence = msg.sequence;
  out->version = msg.version;
  out->config_hash = msg.config_hash;
  out->flags = msg.flags;
  out->last_frame = msg.last_frame;
  out->active_tracks = msg.active_tracks;
  out->confirmed_tracks = msg.confirmed_tracks;
  out->num_latency_samples = msg.num_latency_samples;
  out->latency_p50_us = msg.latency_p50_us;
  out->latency_p99_us = msg.latency_p99_us;
  out->latency_max_us = msg.latency_max_us;
  out->windows_processed = msg.windows_processed;
  out->jobs_failed = msg.jobs_failed;
  out->executor_queue_depth = msg.executor_queue_depth;
  out->kernel_drops = msg.kernel_drops;
  out->embeddings_used = msg.embeddings_used;
  out->embeddings_dropped = msg.embeddings_dropped;
  out->tracks_revived = msg.tracks_revived;
  out->gallery_bytes = msg.gallery_bytes;
}

}  // namespace

StatusDecodeResult DecodeTrackerStatus(const void* data,
                                       std::size_t size,
                                       const DecodeLimits& limits) {
  StatusDecodeResult result;
  const auto convert = [&](const mvtrack::tracker_status_t& msg) {
    CopyStatusFields(msg, &result.message);
    internal::CopyEach(
        msg.cameras, &result.message.cameras, CopyCameraFields<camera_status_t, CameraStatus>);
  };
  internal::CheckedDecode<mvtrack::tracker_status_t>(
      data, size, limits, WalkStatus, convert, &result.status, &result.reason);
  return result;
}

std::vector<std::uint8_t> EncodeTrackerStatus(const TrackerStatus& s) {
  MVTRACK_CHECK(s.cameras.size() <= static_cast<std::size_t>(INT16_MAX));
  mvtrack::tracker_status_t msg;
  CopyStatusFields(s, &msg);
  internal::CopyEach(s.cameras, &msg.cameras, CopyCameraFields<CameraStatus, camera_status_t>);
  msg.num_cameras = static_cast<std::int16_t>(msg.cameras.size());
  return internal::EncodeMessage(msg);
}

SiteStatusDecodeResult DecodeSiteStatus(const void* data,
                                        std::size_t size,
                                        const DecodeLimits& limits) {
  SiteStatusDecodeResult result;
  const auto convert = [&](const mvtrack::site_status_t& msg) {
    CopySiteFields(msg, &result.message);
    internal::CopyEach(msg.zones, &result.message.zones, CopyZoneFields<zone_status_t, ZoneStatus>);
  };
  internal::CheckedDecode<mvtrack::site_status_t>(
      data, size, limits, WalkSiteStatus, convert, &result.status, &result.reason);
  return result;
}

std::vector<std::uint8_t> EncodeSiteStatus(const SiteStatus& s) {
  MVTRACK_CHECK(s.zones.size() <= static_cast<std::size_t>(INT16_MAX));
  mvtrack::site_status_t msg;
  CopySiteFields(s, &msg);
  for (const ZoneStatus& z : s.zones) MVTRACK_CHECK(IsHealth(z.daemon_health));
  internal::CopyEach(s.zones, &msg.zones, CopyZoneFields<ZoneStatus, zone_status_t>);
  msg.num_zones = static_cast<std::int16_t>(msg.zones.size());
  return internal::EncodeMessage(msg);
}

std::vector<std::string> SiteFlagNames(std::int64_t flags) {
  return FlagNames(flags, {"ZONE_MISSING", "INPUT_LOSS", "ZONE_DEGRADED", "NO_OUTPUT"});
}

std::vector<std::string> ZoneFlagNames(std::int64_t flags) {
  return FlagNames(flags, {"NO_DATA", "STALE", "LATE", "DECODE_ERRORS", "DEGRADED"});
}

std::vector<std::string> CameraFlagNames(std::int64_t flags) {
  return FlagNames(flags,
                   {"NO_DATA",
                    "STALE",
                    "LATE",
                    "DROPPING",
                    "REJECTING",
                    "DECODE_ERRORS",
                    "CLOCK_OFFSET",
                    "LOSING",
                    "BAD_EMBEDDINGS"});
}

std::vector<std::string> TrackerFlagNames(std::int64_t flags) {
  return FlagNames(
      flags,
      {"CAMERA_MISSING", "INPUT_LOSS", "BACKLOG", "LATENCY_HIGH", "JOB_FAILURES", "NO_OUTPUT"});
}

}  // namespace mvtrack::transport
