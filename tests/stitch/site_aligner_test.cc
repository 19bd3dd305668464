#include "stitch/site_aligner.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

namespace mvtrack::stitch {
namespace {

constexpr Utime kStart = 1'700'000'000'000'000;
constexpr Utime kPeriod = 33'333;

tracker::Frame3D At(FrameIndex f, Utime skew = 0) {
  tracker::Frame3D frame;
  frame.frame = f;
  frame.utime = kStart + f * kPeriod + skew;
  return frame;
}

AlignerOptions Options() {
  AlignerOptions o;
  o.tolerance_us = kPeriod / 2;
  o.wait_us = 500'000;
  o.stale_after_us = 2'000'000;
  return o;
}

// Which zones a group holds.
std::vector<bool> Members(const ZoneFrameGroup& g) {
  std::vector<bool> m;
  for (const auto& f : g) m.push_back(f.has_value());
  return m;
}

TEST_CASE("stitch/SiteAligner releases a capture time once every live zone delivered it") {
  SiteAligner a(2, Options());
  std::int64_t now = kStart + 600'000;
  a.Push(0, At(0), now);
  a.Push(1, At(0, 1'000), now);  // both live now
  CHECK(a.Pop(now).size() == 1);
  a.Push(0, At(1), now + 10);
  CHECK(a.Pop(now + 10).empty());  // zone 1 is live and has not delivered frame 1
  a.Push(1, At(1, 2'000), now + 20'000);
  const std::vector<ZoneFrameGroup> g = a.Pop(now + 20'000);
  REQUIRE(g.size() == 1);
  CHECK(Members(g[0]) == std::vector<bool>{true, true});
  CHECK(g[0][1]->frame == 1);
  CHECK(a.zones()[1].latency_us == now + 20'000 - (kStart + kPeriod + 2'000));
}

TEST_CASE("stitch/SiteAligner waits for a late zone at most wait_us") {
  SiteAligner a(2, Options());
  std::int64_t now = kStart;
  a.Push(0, At(0), now);
  a.Push(1, At(0), now);
  CHECK(a.Pop(now).size() == 1);
  a.Push(0, At(1), now + 100);
  CHECK(a.Pop(now + 499'000).empty());
  const std::vector<ZoneFrameGroup> g = a.Pop(now + 500'100);
  REQUIRE(g.size() == 1);
  CHECK(Members(g[0]) == std::vector<bool>{true, false});
  // Zone 1's frame 1 now comes too late: dropped and counted.
  a.Push(1, At(1), now + 600'000);
  CHECK(a.zones()[1].late == 1);
  CHECK(a.Pop(now + 600'000).empty());
  // A zone that skipped a capture time but delivered a later one is not waited for.
  a.Push(0, At(2), now + 700'000);
  a.Push(1, At(3), now + 700'000);
  const std::vector<ZoneFrameGroup> next = a.Pop(now + 700'000);
  REQUIRE(next.size() == 1);
  CHECK(Members(next[0]) == std::vector<bool>{true, false});
}

TEST_CASE("stitch/SiteAligner does not wait for a stale zone and takes it back when it returns") {
  SiteAligner a(2, Options());
  std::int64_t now = kStart;
  a.Push(0, At(0), now);
  a.Push(1, At(0), now);
  CHECK(a.Pop(now).size() == 1);
  // Zone 1 falls silent: after stale_after_us it is stale and zone 0's frames go out at once.
  FrameIndex f = 1;
  for (; now < kStart + 3'000'000; now += kPeriod, ++f) {
    a.Push(0, At(f), now);
    a.Pop(now);
  }
  CHECK(a.zones()[1].stale);
  CHECK_FALSE(a.zones()[0].stale);
  a.Push(0, At(f), now);
  CHECK(a.Pop(now).size() == 1);
  // It returns: live again, waited for.
  ++f;
  a.Push(1, At(f), now + 1);
  CHECK_FALSE(a.zones()[1].stale);
  CHECK(a.Pop(now + 1).empty());  // zone 0 has not delivered frame f yet
  a.Push(0, At(f), now + 2);
  const std::vector<ZoneFrameGroup> g = a.Pop(now + 2);
  REQUIRE(g.size() == 1);
  CHECK(Members(g[0]) == std::vector<bool>{true, true});
}

TEST_CASE("stitch/SiteAligner waits for a zone not heard from yet, as long as for a silent one") {
  AlignerOptions o = Options();
  o.wait_us = 10'000'000;  // longer than stale_after_us: staleness decides
  SiteAligner a(2, o);
  a.Push(0, At(0), kStart);
  CHECK(a.Pop(kStart + 1'000'000).empty());  // zone 1 may still come
  CHECK_FALSE(a.zones()[1].stale);
  const std::vector<ZoneFrameGroup> g = a.Pop(kStart + 2'000'000);
  REQUIRE(g.size() == 1);  // 2 s without a word from zone 1: stale, not waited for
  CHECK(a.zones()[1].stale);
  CHECK(Members(g[0]) == std::vector<bool>{true, false});
}

TEST_CASE("stitch/SiteAligner drops frames out of order and bounds what it keeps, flush empties") {
  AlignerOptions o = Options();
  o.max_pending = 3;
  SiteAligner a(2, o);
  a.Push(1, At(0), kStart);  // zone 0 is live and never delivers: everything waits
  a.Push(0, At(5), kStart);
  a.Push(0, At(4), kStart);  // out of order
  CHECK(a.zones()[0].late == 1);
  for (FrameIndex f = 6; f < 10; ++f) a.Push(0, At(f), kStart);
  CHECK(a.zones()[0].late == 3);  // 5 and 6 dropped to keep 3
  const std::vector<ZoneFrameGroup> all = a.Pop(kStart + 1, /*flush=*/true);
  REQUIRE(all.size() == 4);  // zone 1's frame 0, then zone 0's 7, 8, 9
  CHECK(all[1][0]->frame == 7);
  CHECK(a.Pop(kStart + 2, true).empty());
  std::string why;
  o.tolerance_us = 0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why == "tolerance_us must be > 0");
}

}  // namespace
}  // namespace mvtrack::stitch
