// StitchService (issue 43): zone tracks messages in, site frames out; bad messages and the
// provisional layer counted and left out; global ids never repeat across restarts with a state
// directory.

#include "service/stitch_service.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "config/config_test_util.h"
#include "transport/codec.h"

namespace mvtrack::service {
namespace {

using config::testing::TempDir;

constexpr Utime kStart = 1'700'000'000'000'000;
constexpr Utime kPeriod = 33'333;

StitchConfig TwoZones() {
  StitchConfig c;
  config::Zone a, b;
  a.name = "east";
  a.cameras = {0, 1};
  b.name = "west";
  b.cameras = {2, 3};
  c.zones = {a, b};
  c.aligner.tolerance_us = kPeriod / 2;
  return c;
}

// A zone's frame f with one track `id` at (x, 2).
std::vector<std::uint8_t> Message(FrameIndex f,
                                  TrackId3D id,
                                  double x,
                                  transport::TracksLayer layer = transport::TracksLayer::kFinal) {
  tracker::Frame3D frame;
  frame.frame = f;
  frame.utime = kStart + f * kPeriod;
  tracker::Track3D t;
  t.id = id;
  t.position = Vec3(x, 2.0, 0.0);
  frame.tracks.push_back(t);
  return transport::EncodeTracks(frame, core::KeypointLayoutId::kNone, frame.utime, 0, layer);
}

// Feeds both zones `n` frames of one person they both see (zone ids 7 and 9), from `first`.
std::vector<stitch::SiteFrame> Feed(StitchService* s, FrameIndex first, int n) {
  std::vector<stitch::SiteFrame> out;
  for (FrameIndex f = first; f < first + n; ++f) {
    const std::int64_t now = kStart + f * kPeriod + 100'000;
    const std::vector<std::uint8_t> a = Message(f, 7, 0.1 * static_cast<double>(f));
    const std::vector<std::uint8_t> b = Message(f, 9, 0.1 * static_cast<double>(f) + 0.05);
    s->OnMessage(0, a.data(), a.size(), now);
    s->OnMessage(1, b.data(), b.size(), now);
    for (stitch::SiteFrame& sf : s->Poll(now)) out.push_back(std::move(sf));
  }
  return out;
}

TEST_CASE("StitchService: two zones' tracks of one person are one global track", "[unit]") {
  std::string why;
  std::unique_ptr<StitchService> s = StitchService::Create(TwoZones(), &why);
  REQUIRE(s);
  CHECK(s->channels() == std::vector<std::string>{"MVTRACK_TRACKS_EAST", "MVTRACK_TRACKS_WEST"});
  const std::vector<stitch::SiteFrame> out = Feed(s.get(), 0, 30);
  REQUIRE(out.size() == 30);
  for (const stitch::SiteFrame& f : out) {
    REQUIRE(f.frame.tracks.size() == 1);
    CHECK(f.frame.tracks[0].id == 1);
    CHECK(f.frame.tracks[0].zones == std::vector<int>{0, 1});
    CHECK(f.frame.zones == std::vector<std::string>{"east", "west"});
  }
  const transport::SiteStatus st = s->Status(kStart + 30 * kPeriod + 100'000);
  CHECK(st.site_frames == 30);
  CHECK(st.last_frame == 29);
  CHECK(st.active_tracks == 1);
  CHECK(st.global_ids == 1);
  CHECK(st.num_wait_samples == 30);
  CHECK(st.zones[1].frames == 30);
  CHECK(st.zones[1].latency_us == 100'000);
  CHECK(st.zones[0].flags == 0);
  CHECK(st.flags == 0);
  CHECK(st.zones[0].daemon_health == static_cast<std::int8_t>(Health::kUnknown));
  // The site_status_t on the wire carries all of it.
  const std::vector<std::uint8_t> wire = transport::EncodeSiteStatus(st);
  const transport::SiteStatusDecodeResult back =
      transport::DecodeSiteStatus(wire.data(), wire.size());
  REQUIRE(back.ok());
  CHECK(back.message.zones.size() == 2);
  CHECK(back.message.zones[1].channel == "MVTRACK_TRACKS_WEST");
  CHECK(back.message.zones[1].frames == 30);
  CHECK(back.message.instance_id == st.instance_id);
  CHECK(back.message.sequence == st.sequence);
  const std::string json = SiteStatusJson(st);
  CHECK(json.find("\"name\":\"west\",\"channel\":\"MVTRACK_TRACKS_WEST\",\"state\":\"live\"") !=
        std::string::npos);
  CHECK(json.find("\"latency_ms\":100.0") != std::string::npos);
  // 2 s without a word: stale.
  const transport::SiteStatus late = s->Status(kStart + 30 * kPeriod + 2'200'000);
  CHECK(transport::ZoneFlagNames(late.zones[0].flags) == std::vector<std::string>{"STALE"});
  CHECK(transport::SiteFlagNames(late.flags) == std::vector<std::string>{"ZONE_MISSING"});
  CHECK(late.sequence == st.sequence + 1);
}

TEST_CASE("StitchService: bad bytes and the provisional layer are counted, not stitched",
          "[unit]") {
  std::string why;
  std::unique_ptr<StitchService> s = StitchService::Create(TwoZones(), &why);
  REQUIRE(s);
  const std::vector<std::uint8_t> junk = {1, 2, 3, 4, 5};
  s->OnMessage(0, junk.data(), junk.size(), kStart);
  std::vector<std::uint8_t> cut = Message(0, 7, 1.0);
  cut.resize(cut.size() / 2);
  s->OnMessage(0, cut.data(), cut.size(), kStart);
  const std::vector<std::uint8_t> now = Message(0, 7, 1.0, transport::TracksLayer::kProvisional);
  s->OnMessage(1, now.data(), now.size(), kStart);
  const transport::SiteStatus st = s->Status(kStart, /*end_period=*/true);
  CHECK(st.zones[0].decode_errors == 2);
  CHECK(st.zones[1].other_layer == 1);
  CHECK(st.zones[0].frames == 0);
  CHECK(transport::ZoneFlagNames(st.zones[0].flags) ==
        std::vector<std::string>{"NO_DATA", "DECODE_ERRORS"});
  CHECK(transport::SiteFlagNames(st.flags) ==
        std::vector<std::string>{"ZONE_MISSING", "INPUT_LOSS"});
  // DECODE_ERRORS is a flag of the period: the next period has none.
  CHECK(transport::ZoneFlagNames(s->Status(kStart + 1).zones[0].flags) ==
        std::vector<std::string>{"NO_DATA"});
  CHECK(s->Poll(kStart + 1, true).empty());
  // The good messages after them are stitched.
  CHECK(Feed(s.get(), 1, 5).size() == 5);
}

TEST_CASE("StitchService: a zone daemon's own status is the zone's health in the site status",
          "[unit]") {
  std::string why;
  std::unique_ptr<StitchService> s = StitchService::Create(TwoZones(), &why);
  REQUIRE(s);
  CHECK(s->status_channels() ==
        std::vector<std::string>{"MVTRACK_STATUS_EAST", "MVTRACK_STATUS_WEST"});
  Feed(s.get(), 0, 10);
  const std::int64_t now = kStart + 10 * kPeriod + 100'000;
  transport::TrackerStatus daemon;
  daemon.utime = now;
  daemon.period_us = 1'000'000;
  daemon.instance_id = "00112233aabbccdd";
  transport::CameraStatus good, other, stale;
  good.camera_id = 2;
  good.last_receive_utime = now;
  good.received = 100;
  other = good;
  other.camera_id = 4;
  stale.camera_id = 3;
  stale.flags = 2;   // camera_status_t::FLAG_STALE
  daemon.flags = 1;  // tracker_status_t::FLAG_CAMERA_MISSING
  daemon.cameras = {good, stale, other};
  const std::vector<std::uint8_t> bytes = transport::EncodeTrackerStatus(daemon);
  s->OnZoneStatus(1, bytes.data(), bytes.size(), now);
  const std::vector<std::uint8_t> junk = {9, 9, 9};
  s->OnZoneStatus(0, junk.data(), junk.size(), now);

  const transport::SiteStatus st = s->Status(now);
  CHECK(st.zones[1].daemon_health == static_cast<std::int8_t>(Health::kWarning));
  CHECK(st.zones[1].daemon_reasons == HealthLine(AssessStatus(daemon)));
  CHECK(st.zones[1].daemon_reasons.find("camera 3 STALE") != std::string::npos);
  CHECK(st.zones[1].daemon_instance_id == "00112233aabbccdd");
  CHECK(transport::ZoneFlagNames(st.zones[1].flags) == std::vector<std::string>{"DEGRADED"});
  CHECK(st.zones[0].decode_errors == 1);
  CHECK(transport::SiteFlagNames(st.flags) ==
        std::vector<std::string>{"INPUT_LOSS", "ZONE_DEGRADED"});
  const std::string json = SiteStatusJson(st);
  CHECK(json.find("\"daemon\":\"WARNING\"") != std::string::npos);
  // Three of its periods without a status: unknown, no longer degraded.
  Feed(s.get(), 10, 100);
  const transport::SiteStatus later = s->Status(now + 3'100'000);
  CHECK(later.zones[1].daemon_health == static_cast<std::int8_t>(Health::kUnknown));
  CHECK(later.zones[1].daemon_reasons.empty());
  CHECK((later.zones[1].flags & 16) == 0);
}

TEST_CASE("StitchService: a restart with the state directory never gives an id out again",
          "[unit]") {
  TempDir dir;
  StitchConfig c = TwoZones();
  c.state_dir = dir.File("state");  // created
  std::string why;
  TrackId3D last = 0;
  {
    std::unique_ptr<StitchService> s = StitchService::Create(c, &why);
    REQUIRE(s);
    const std::vector<stitch::SiteFrame> out = Feed(s.get(), 0, 5);
    last = out.back().frame.tracks.at(0).id;
  }
  std::unique_ptr<StitchService> again = StitchService::Create(c, &why);
  REQUIRE(again);
  const std::vector<stitch::SiteFrame> out = Feed(again.get(), 0, 5);
  CHECK(out.back().frame.tracks.at(0).id > last);
  StitchConfig none;
  CHECK(StitchService::Create(none, &why) == nullptr);
  CHECK(why == "a site needs at least one zone");
}

}  // namespace
}  // namespace mvtrack::service
