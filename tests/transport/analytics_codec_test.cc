// analytics_event_t and site_counts_t (issue 41): round trips, every truncation, other types,
// unknown enum values, hostile counts and random mutations.

#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "transport/codec.h"

namespace mvtrack::transport {
namespace {

AnalyticsEventMessage SampleEvent() {
  AnalyticsEventMessage e;
  e.utime = 1'700'000'012'345'678;
  e.publish_utime = 1'700'000'013'400'000;
  e.kind = analytics::Event::Kind::kExit;
  e.name = "shelf 3";
  e.track_id = 42;
  e.enter_utime = 1'700'000'002'000'000;
  e.track_ended = true;
  return e;
}

SiteCounts SampleCounts() {
  SiteCounts c;
  c.utime = 1'700'000'012'345'678;
  c.publish_utime = 1'700'000'013'000'000;
  c.region_names = {"room", "shelf 3"};
  c.regions = {{4, 120, 116}, {1, 30, 29}};
  c.line_names = {"door"};
  c.lines = {{61, 58}};
  return c;
}

}  // namespace

TEST_CASE("analytics event and site counts round trips keep every field", "[unit]") {
  const AnalyticsEventMessage e = SampleEvent();
  const AnalyticsEventDecodeResult d =
      DecodeAnalyticsEvent(EncodeAnalyticsEvent(e).data(), EncodeAnalyticsEvent(e).size());
  REQUIRE(d.ok());
  CHECK(d.message.utime == e.utime);
  CHECK(d.message.publish_utime == e.publish_utime);
  CHECK(d.message.kind == analytics::Event::Kind::kExit);
  CHECK(d.message.name == "shelf 3");
  CHECK(d.message.track_id == 42);
  CHECK(d.message.enter_utime == e.enter_utime);
  CHECK(d.message.track_ended);
  AnalyticsEventMessage crossing = e;
  crossing.kind = analytics::Event::Kind::kCrossing;
  crossing.direction = analytics::Event::Direction::kRightToLeft;
  const std::vector<std::uint8_t> cb = EncodeAnalyticsEvent(crossing);
  CHECK(DecodeAnalyticsEvent(cb.data(), cb.size()).message.direction ==
        analytics::Event::Direction::kRightToLeft);

  const std::vector<std::uint8_t> bytes = EncodeSiteCounts(SampleCounts());
  const SiteCountsDecodeResult c = DecodeSiteCounts(bytes.data(), bytes.size());
  REQUIRE(c.ok());
  CHECK(c.message.utime == SampleCounts().utime);
  CHECK(c.message.region_names == SampleCounts().region_names);
  REQUIRE(c.message.regions.size() == 2);
  CHECK(c.message.regions[1].occupancy == 1);
  CHECK(c.message.regions[1].entries == 30);
  CHECK(c.message.regions[1].exits == 29);
  CHECK(c.message.line_names == std::vector<std::string>{"door"});
  CHECK(c.message.lines[0].left_to_right == 61);
  CHECK(c.message.lines[0].right_to_left == 58);
}

TEST_CASE("analytics messages: truncations, other types, bad values and counts are rejected",
          "[unit]") {
  const std::vector<std::uint8_t> event = EncodeAnalyticsEvent(SampleEvent());
  const std::vector<std::uint8_t> counts = EncodeSiteCounts(SampleCounts());
  for (std::size_t n = 0; n < event.size(); ++n) {
    CHECK_FALSE(DecodeAnalyticsEvent(event.data(), n).ok());
  }
  for (std::size_t n = 0; n < counts.size(); ++n) {
    CHECK_FALSE(DecodeSiteCounts(counts.data(), n).ok());
  }
  // Each decoder refuses the other's bytes.
  CHECK(DecodeAnalyticsEvent(counts.data(), counts.size()).status == DecodeStatus::kBadFingerprint);
  CHECK(DecodeSiteCounts(event.data(), event.size()).status == DecodeStatus::kBadFingerprint);
  // kind is the byte after the fingerprint and the two int64 times.
  std::vector<std::uint8_t> kind = event;
  kind[8 + 16] = 7;
  const AnalyticsEventDecodeResult bad_kind = DecodeAnalyticsEvent(kind.data(), kind.size());
  CHECK(bad_kind.status == DecodeStatus::kMalformed);
  CHECK_THAT(bad_kind.reason, Catch::Contains("kind 7 is not a KIND_*"));
  std::vector<std::uint8_t> longer = event;
  longer.push_back(0);
  CHECK_THAT(DecodeAnalyticsEvent(longer.data(), longer.size()).reason,
             Catch::Contains("trailing"));
  // num_regions (int16 after the fingerprint and the two times): negative, huge, over a limit.
  std::vector<std::uint8_t> negative = counts;
  negative[24] = 0xff;
  negative[25] = 0xff;
  CHECK_FALSE(DecodeSiteCounts(negative.data(), negative.size()).ok());
  std::vector<std::uint8_t> huge = counts;
  huge[24] = 0x7f;
  CHECK_FALSE(DecodeSiteCounts(huge.data(), huge.size()).ok());
  DecodeLimits one;
  one.max_site_items = 1;
  CHECK(DecodeSiteCounts(counts.data(), counts.size(), one).status == DecodeStatus::kLimitExceeded);
}

TEST_CASE("5000 random mutations of analytics messages never crash", "[unit]") {
  std::mt19937 rng(41);
  for (const std::vector<std::uint8_t>& bytes :
       {EncodeAnalyticsEvent(SampleEvent()), EncodeSiteCounts(SampleCounts())}) {
    int accepted = 0;
    for (int i = 0; i < 5000; ++i) {
      std::vector<std::uint8_t> m = bytes;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < flips; ++k) m[rng() % m.size()] = static_cast<std::uint8_t>(rng());
      accepted += (DecodeAnalyticsEvent(m.data(), m.size()).ok() ||
                   DecodeSiteCounts(m.data(), m.size()).ok())
                      ? 1
                      : 0;
    }
    CHECK(accepted > 0);
    CHECK(accepted < 5000);
  }
}

}  // namespace mvtrack::transport
