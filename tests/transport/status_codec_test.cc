// tracker_status_t decoding from untrusted bytes (DecodeTrackerStatus), its encoder, and the
// flag names.

#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "transport/codec.h"

namespace mvtrack::transport {
namespace {

TrackerStatus Sample() {
  TrackerStatus s;
  s.utime = 1'700'000'000'000'000;
  s.period_us = 1'000'000;
  s.uptime_us = 12'000'000;
  s.version = "0.3.0";
  s.config_hash = "abc123";
  s.flags = 2 | 8;
  s.last_frame = 345;
  s.active_tracks = 4;
  s.confirmed_tracks = 3;
  s.num_latency_samples = 30;
  s.latency_p50_us = 10'000;
  s.latency_p99_us = 20'000;
  s.latency_max_us = 30'000;
  s.windows_processed = 17;
  s.jobs_failed = 1;
  s.executor_queue_depth = 2;
  s.kernel_drops = 5;
  s.embeddings_used = 123'456;
  s.embeddings_dropped = 78;
  s.tracks_revived = 9;
  s.gallery_bytes = 4'096'000;
  for (int i = 0; i < 3; ++i) {
    CameraStatus c;
    c.camera_id = 10 + i;
    c.flags = i == 2 ? 64 | 128 : 0;
    c.rate_hz = 29.5f;
    c.last_utime = s.utime - 40'000;
    c.last_receive_utime = s.utime - 30'000;
    c.received = 1000 + i;
    c.late = i;
    c.dropped = 2 * i;
    c.rejected = 3 * i;
    c.decode_errors = 4 * i;
    c.lost = 5 * i;
    c.clock_offset_us = i == 2 ? 250'000 : 0;
    c.embeddings_dropped = 6 * i;
    c.queue_depth = i;
    c.queue_capacity = 8;
    s.cameras.push_back(c);
  }
  return s;
}

TEST_CASE("status round trip keeps every field", "[unit]") {
  const TrackerStatus s = Sample();
  const std::vector<std::uint8_t> bytes = EncodeTrackerStatus(s);
  const StatusDecodeResult d = DecodeTrackerStatus(bytes.data(), bytes.size());
  REQUIRE(d.ok());
  const TrackerStatus& r = d.message;
  CHECK(r.utime == s.utime);
  CHECK(r.version == "0.3.0");
  CHECK(r.config_hash == "abc123");
  CHECK(r.flags == s.flags);
  CHECK(r.last_frame == 345);
  CHECK(r.kernel_drops == 5);
  CHECK(r.embeddings_used == 123'456);
  CHECK(r.embeddings_dropped == 78);
  CHECK(r.tracks_revived == 9);
  CHECK(r.gallery_bytes == 4'096'000);
  CHECK(r.executor_queue_depth == 2);
  REQUIRE(r.cameras.size() == 3);
  CHECK(r.cameras[2].camera_id == 12);
  CHECK(r.cameras[2].lost == 10);
  CHECK(r.cameras[2].clock_offset_us == 250'000);
  CHECK(r.cameras[2].embeddings_dropped == 12);
  CHECK(r.cameras[2].queue_capacity == 8);
  CHECK(r.cameras[1].decode_errors == 4);
  CHECK(r.cameras[0].rate_hz == 29.5f);
  // 104 bytes per camera (lcmtypes/README.md).
  TrackerStatus one = s;
  one.cameras.resize(1);
  CHECK(bytes.size() - EncodeTrackerStatus(one).size() == 2 * 104);
}

TEST_CASE("status truncations, other types and hostile counts are rejected", "[unit]") {
  const std::vector<std::uint8_t> bytes = EncodeTrackerStatus(Sample());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    INFO("prefix of " << n << " bytes");
    CHECK_FALSE(DecodeTrackerStatus(bytes.data(), n).ok());
  }
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  const StatusDecodeResult trailing = DecodeTrackerStatus(longer.data(), longer.size());
  CHECK(trailing.status == DecodeStatus::kMalformed);
  CHECK_THAT(trailing.reason, Catch::Contains("trailing"));
  std::vector<std::uint8_t> other = bytes;
  other[0] ^= 0xff;
  CHECK(DecodeTrackerStatus(other.data(), other.size()).status == DecodeStatus::kBadFingerprint);
  // num_cameras is the int16 just before the cameras: make it negative and huge.
  const std::size_t count_at = bytes.size() - 3 * 104 - 2;
  std::vector<std::uint8_t> negative = bytes;
  negative[count_at] = 0xff;
  negative[count_at + 1] = 0xff;
  CHECK_FALSE(DecodeTrackerStatus(negative.data(), negative.size()).ok());
  std::vector<std::uint8_t> huge = bytes;
  huge[count_at] = 0x7f;
  CHECK_FALSE(DecodeTrackerStatus(huge.data(), huge.size()).ok());
  DecodeLimits few;
  few.max_cameras = 2;
  CHECK(DecodeTrackerStatus(bytes.data(), bytes.size(), few).status ==
        DecodeStatus::kLimitExceeded);
}

TEST_CASE("5000 random mutations of a status message never crash", "[unit]") {
  const std::vector<std::uint8_t> bytes = EncodeTrackerStatus(Sample());
  std::mt19937 rng(7);
  int accepted = 0;
  for (int i = 0; i < 5000; ++i) {
    std::vector<std::uint8_t> m = bytes;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < flips; ++k) m[rng() % m.size()] = static_cast<std::uint8_t>(rng());
    accepted += DecodeTrackerStatus(m.data(), m.size()).ok() ? 1 : 0;
  }
  CHECK(accepted > 0);  // most flips hit plain numbers, which are valid
  CHECK(accepted < 5000);
}

SiteStatus SiteSample() {
  SiteStatus s;
  s.utime = 1'700'000'000'000'000;
  s.period_us = 1'000'000;
  s.uptime_us = 9'000'000;
  s.instance_id = "0011223344556677";
  s.start_utime = s.utime - s.uptime_us;
  s.sequence = 8;
  s.version = "0.6.0";
  s.flags = 1 | 4;
  s.last_frame = 270;
  s.site_frames = 271;
  s.active_tracks = 12;
  s.global_ids = 19;
  s.splits = 2;
  s.merges = 1;
  s.num_wait_samples = 30;
  s.wait_p50_us = 900;
  s.wait_p99_us = 3'100;
  s.wait_max_us = 4'000;
  for (int i = 0; i < 2; ++i) {
    ZoneStatus z;
    z.name = "zone" + std::to_string(i + 1);
    z.channel = "MVTRACK_TRACKS_ZONE" + std::to_string(i + 1);
    z.flags = i == 0 ? 16 : 2;
    z.frames = 271 - 100 * i;
    z.late = i;
    z.decode_errors = 2 * i;
    z.other_layer = 3;
    z.last_utime = s.utime - 200'000 - 3'000'000 * i;
    z.last_receive_utime = z.last_utime + 170'000;
    z.latency_us = 170'000 + i;
    z.tracks = 7 + i;
    z.daemon_health = static_cast<std::int8_t>(i == 0 ? 1 : 3);
    z.daemon_reasons = i == 0 ? "WARNING: camera 2 STALE" : "";
    z.daemon_instance_id = i == 0 ? "8899aabbccddeeff" : "";
    s.zones.push_back(z);
  }
  return s;
}

TEST_CASE("site status round trip keeps every field, bad bytes are rejected", "[unit]") {
  const SiteStatus s = SiteSample();
  const std::vector<std::uint8_t> bytes = EncodeSiteStatus(s);
  const SiteStatusDecodeResult d = DecodeSiteStatus(bytes.data(), bytes.size());
  REQUIRE(d.ok());
  const SiteStatus& r = d.message;
  CHECK(r.utime == s.utime);
  CHECK(r.instance_id == s.instance_id);
  CHECK(r.sequence == s.sequence);
  CHECK(r.version == s.version);
  CHECK(r.flags == s.flags);
  CHECK(r.last_frame == s.last_frame);
  CHECK(r.site_frames == s.site_frames);
  CHECK(r.active_tracks == s.active_tracks);
  CHECK(r.global_ids == s.global_ids);
  CHECK(r.splits == s.splits);
  CHECK(r.merges == s.merges);
  CHECK(r.num_wait_samples == s.num_wait_samples);
  CHECK(r.wait_p99_us == s.wait_p99_us);
  REQUIRE(r.zones.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const ZoneStatus& a = s.zones[i];
    const ZoneStatus& b = r.zones[i];
    CHECK(b.name == a.name);
    CHECK(b.channel == a.channel);
    CHECK(b.flags == a.flags);
    CHECK(b.frames == a.frames);
    CHECK(b.late == a.late);
    CHECK(b.decode_errors == a.decode_errors);
    CHECK(b.other_layer == a.other_layer);
    CHECK(b.last_utime == a.last_utime);
    CHECK(b.last_receive_utime == a.last_receive_utime);
    CHECK(b.latency_us == a.latency_us);
    CHECK(b.tracks == a.tracks);
    CHECK(b.daemon_health == a.daemon_health);
    CHECK(b.daemon_reasons == a.daemon_reasons);
    CHECK(b.daemon_instance_id == a.daemon_instance_id);
  }
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    INFO("prefix of " << n << " bytes");
    CHECK_FALSE(DecodeSiteStatus(bytes.data(), n).ok());
  }
  // A tracker's status is not a site's, and the other way round.
  const std::vector<std::uint8_t> tracker = EncodeTrackerStatus(Sample());
  CHECK(DecodeSiteStatus(tracker.data(), tracker.size()).status == DecodeStatus::kBadFingerprint);
  CHECK(DecodeTrackerStatus(bytes.data(), bytes.size()).status == DecodeStatus::kBadFingerprint);
  // daemon_health outside HEALTH_*: the last zone's is the byte before its two strings.
  const std::size_t health_at = bytes.size() - (4 + 1) - (4 + 1) - 1;
  std::vector<std::uint8_t> bad = bytes;
  bad[health_at] = 7;
  const SiteStatusDecodeResult unhealthy = DecodeSiteStatus(bad.data(), bad.size());
  CHECK(unhealthy.status == DecodeStatus::kMalformed);
  CHECK_THAT(unhealthy.reason, Catch::Contains("zone 1: daemon_health 7 is not one of"));
  // Reasons longer than kMaxDaemonReasons, and more zones than the limit.
  SiteStatus wordy = s;
  wordy.zones[0].daemon_reasons = std::string(kMaxDaemonReasons + 1, 'x');
  const std::vector<std::uint8_t> long_reasons = EncodeSiteStatus(wordy);
  CHECK(DecodeSiteStatus(long_reasons.data(), long_reasons.size()).status ==
        DecodeStatus::kLimitExceeded);
  DecodeLimits one;
  one.max_zones = 1;
  CHECK(DecodeSiteStatus(bytes.data(), bytes.size(), one).status == DecodeStatus::kLimitExceeded);
  std::mt19937 rng(11);
  for (int i = 0; i < 2000; ++i) {
    std::vector<std::uint8_t> m = bytes;
    for (int k = 0; k < 3; ++k) m[rng() % m.size()] = static_cast<std::uint8_t>(rng());
    (void)DecodeSiteStatus(m.data(), m.size());  // never crashes (ASan/UBSan builds)
  }
}

TEST_CASE("flag names spell the documented bits", "[unit]") {
  CHECK(SiteFlagNames(1 | 8) == std::vector<std::string>{"ZONE_MISSING", "NO_OUTPUT"});
  CHECK(ZoneFlagNames(2 | 16) == std::vector<std::string>{"STALE", "DEGRADED"});
  CHECK(ZoneFlagNames(32) == std::vector<std::string>{"BIT5"});
  CHECK(CameraFlagNames(0).empty());
  CHECK(CameraFlagNames(1 | 64 | 128) ==
        std::vector<std::string>{"NO_DATA", "CLOCK_OFFSET", "LOSING"});
  CHECK(CameraFlagNames(256) == std::vector<std::string>{"BAD_EMBEDDINGS"});
  CHECK(CameraFlagNames(std::int64_t{1} << 40) == std::vector<std::string>{"BIT40"});
  CHECK(TrackerFlagNames(2 | 16) == std::vector<std::string>{"INPUT_LOSS", "JOB_FAILURES"});
  CHECK(TrackerFlagNames(-1).size() == 64);
}

}  // namespace
}  // namespace mvtrack::transport
