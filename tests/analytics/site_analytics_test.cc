// lib/analytics: regions, lines, visits and crossings from a stream of track positions, and the
// rules that keep a border, a short loss and a ghost from being counted wrong.

#include "analytics/site_analytics.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace mvtrack::analytics {
namespace {

// A 4 m x 4 m room [0, 4] x [0, 4] and a door line on x = 0 from (0, 1) to (0, 3): seen from
// (0, 1) looking at (0, 3), the room (+x) is on the right, so walking in crosses left to right.
Site Room() {
  Site site;
  site.regions.push_back({"room", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}});
  site.lines.push_back({"door", {0, 1}, {0, 3}});
  site.options.hold_s = 1.0;  // the tests' times below assume 1 s, whatever the default
  return site;
}

// Feeds one track along `path` (one position per sample, `dt` apart from t0); returns every
// event, Finish() included.
std::vector<Event> Walk(SiteAnalytics* analytics,
                        const std::vector<Vec2>& path,
                        double dt = 0.1,
                        double t0 = 0.0,
                        TrackId3D id = 1,
                        bool finish = true) {
  std::vector<Event> all;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::vector<Event> e =
        analytics->Update(t0 + dt * static_cast<double>(i), {{id, path[i]}});
    all.insert(all.end(), e.begin(), e.end());
  }
  if (finish) {
    const std::vector<Event> e = analytics->Finish();
    all.insert(all.end(), e.begin(), e.end());
  }
  return all;
}

// A straight walk from `a` to `b` at `speed` m/s, sampled every `dt`.
std::vector<Vec2> Straight(const Vec2& a, const Vec2& b, double speed = 1.0, double dt = 0.1) {
  const int n = static_cast<int>(std::ceil((b - a).norm() / (speed * dt)));
  std::vector<Vec2> path;
  for (int i = 0; i <= n; ++i) path.push_back(a + (b - a) * (static_cast<double>(i) / n));
  return path;
}

std::vector<Vec2> Concat(std::vector<Vec2> a, const std::vector<Vec2>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("analytics: signed distance to a polygon, and what a site may not be", "[unit]") {
  const std::vector<Vec2> square = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  CHECK(SignedDistance(square, {2, 2}) == Approx(2.0));
  CHECK(SignedDistance(square, {1, 2}) == Approx(1.0));
  CHECK(SignedDistance(square, {-1, 2}) == Approx(-1.0));
  CHECK(SignedDistance(square, {5, 5}) == Approx(-std::sqrt(2.0)));
  // Orientation does not matter; a concave polygon (an L).
  const std::vector<Vec2> l_shape = {{0, 0}, {0, 4}, {1, 4}, {1, 1}, {4, 1}, {4, 0}};
  CHECK(SignedDistance(l_shape, {0.5, 3}) == Approx(0.5));
  CHECK(SignedDistance(l_shape, {3, 3}) == Approx(-2.0));

  CHECK_FALSE(ValidateSite(Room()).has_value());
  Site bow_tie = Room();
  bow_tie.regions[0].polygon = {{0, 0}, {4, 4}, {4, 0}, {0, 4}};
  REQUIRE(ValidateSite(bow_tie).has_value());
  INFO(*ValidateSite(bow_tie));
  CHECK(ValidateSite(bow_tie)->find("regions[0] 'room': edges") == 0);
  CHECK(ValidateSite(bow_tie)->find("cross (the polygon must be simple)") != std::string::npos);
  Site twice = Room();
  twice.regions.push_back(twice.regions[0]);
  CHECK(ValidateSite(twice)->find("another region has this name") != std::string::npos);
  Site flat = Room();
  flat.regions[0].polygon = {{0, 0}, {1, 1}, {2, 2}};
  CHECK(ValidateSite(flat)->find("no area") != std::string::npos);
  Site point = Room();
  point.lines[0].to = point.lines[0].from;
  CHECK(ValidateSite(point)->find("lines[0] 'door': the line has no length") == 0);
  Site nan = Room();
  nan.regions[0].polygon[2].x() = std::nan("");
  CHECK(ValidateSite(nan)->find("vertex 2 is not finite") != std::string::npos);
  Site options = Room();
  options.options.max_gap_s = 0.0;
  CHECK(ValidateSite(options)->find("max_gap_s") == 0);
}

TEST_CASE("analytics: a walk in and out is one visit, its times when the border was crossed",
          "[unit]") {
  SiteAnalytics analytics(Room());
  // From (-2, 2) to (2, 2) at 1 m/s (border at t = 2.0), stays 5 s, back out (border at 11.0).
  std::vector<Vec2> path = Straight({-2, 2}, {2, 2});
  for (int i = 0; i < 50; ++i) path.push_back({2, 2});
  path = Concat(path, Straight({2, 2}, {-2, 2}));
  const std::vector<Event> events = Walk(&analytics, path);
  REQUIRE(events.size() == 4);
  CHECK(events[0].kind == Event::Kind::kEnter);
  CHECK(events[0].time_s == Approx(2.0));
  CHECK(events[1].kind == Event::Kind::kCrossing);
  CHECK(events[1].direction == Event::Direction::kLeftToRight);
  CHECK(events[1].time_s == Approx(2.0));
  CHECK(events[2].kind == Event::Kind::kExit);
  CHECK(events[2].time_s == Approx(11.1));
  CHECK(events[2].dwell_s() == Approx(9.1));
  CHECK_FALSE(events[2].track_ended);
  CHECK(events[3].kind == Event::Kind::kCrossing);
  CHECK(events[3].direction == Event::Direction::kRightToLeft);
  CHECK(analytics.region_counts()[0].entries == 1);
  CHECK(analytics.region_counts()[0].exits == 1);
  CHECK(analytics.region_counts()[0].occupancy == 0);
  CHECK(analytics.line_counts()[0].left_to_right == 1);
  CHECK(analytics.line_counts()[0].right_to_left == 1);
}

TEST_CASE("analytics: the entry is published hold_s after the border, occupancy then counts it",
          "[unit]") {
  SiteAnalytics analytics(Room());
  const std::vector<Vec2> path = Straight({-1, 2}, {3, 2});  // border at t = 1.0
  bool seen = false;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double t = 0.1 * static_cast<double>(i);
    const std::vector<Event> e = analytics.Update(t, {{7, path[i]}});
    if (!e.empty() && e[0].kind == Event::Kind::kEnter) {
      CHECK(t == Approx(2.0));  // 1.0 + hold_s
      CHECK(e[0].time_s == Approx(1.0));
      seen = true;
    }
    CHECK(analytics.region_counts()[0].occupancy == (t >= 2.0 - 1e-9 ? 1 : 0));
  }
  CHECK(seen);
}

TEST_CASE("analytics: standing on the border for minutes is at most one entry", "[unit]") {
  Site site = Room();
  SiteAnalytics analytics(site);
  // Walks up to the room's border and lingers on it for 5 minutes, jittering 10 cm either side
  // (within the 0.3 m band), then leaves.
  std::vector<Vec2> path = Straight({-2, 2}, {0, 2});
  for (int i = 0; i < 3000; ++i) path.push_back({0.1 * std::sin(0.7 * i), 2});
  path = Concat(path, Straight({0, 2}, {-2, 2}));
  const std::vector<Event> events = Walk(&analytics, path);
  CHECK(analytics.region_counts()[0].entries == 0);
  // The same with jitter of 40 cm, past the band on both sides, changing side every few
  // samples: every change is undone before it holds for hold_s.
  SiteAnalytics again(site);
  path = Straight({-2, 2}, {0, 2});
  for (int i = 0; i < 3000; ++i) path.push_back({(i / 3) % 2 == 0 ? 0.4 : -0.4, 2});
  Walk(&again, path);
  CHECK(again.region_counts()[0].entries == 0);
  CHECK(again.line_counts()[0].left_to_right + again.line_counts()[0].right_to_left == 0);
  // Lingering just inside (20 cm in, 10 cm of jitter): one entry, once, when the border was
  // first crossed.
  SiteAnalytics inside(site);
  path = Straight({-2, 2}, {0.2, 2});
  for (int i = 0; i < 3000; ++i) path.push_back({0.2 + 0.1 * std::sin(0.7 * i), 2});
  const std::vector<Event> e = Walk(&inside, path);
  CHECK(inside.region_counts()[0].entries == 1);
  REQUIRE_FALSE(e.empty());
  CHECK(e[0].time_s == Approx(2.0));
}

TEST_CASE("analytics: a change holds only on the new side of the border", "[unit]") {
  // Appears 0.6 m inside (past the band), walks out over the border 0.4 s later and stays just
  // outside, within the band, for longer than hold_s: it never held the inside, no visit (it
  // was once confirmed with a visit of zero dwell).
  SiteAnalytics analytics(Room());
  std::vector<Vec2> path = Straight({0.6, 2}, {-0.1, 2});
  for (int i = 0; i < 30; ++i) path.push_back({-0.1, 2});
  path = Concat(path, Straight({-0.1, 2}, {-2, 2}));
  Walk(&analytics, path);
  CHECK(analytics.region_counts()[0].entries == 0);
  // Back inside after standing in the band: the visit counts from the first crossing.
  SiteAnalytics back(Room());
  path = Straight({0.6, 2}, {-0.1, 2});
  for (int i = 0; i < 30; ++i) path.push_back({-0.1, 2});
  path = Concat(path, Straight({-0.1, 2}, {2, 2}));
  const std::vector<Event> e = Walk(&back, path);
  CHECK(back.region_counts()[0].entries == 1);
  REQUIRE_FALSE(e.empty());
  CHECK(e[0].time_s == Approx(0.0));
}

TEST_CASE("analytics: a track lost for a moment is one visit, lost for longer it ended", "[unit]") {
  Site site = Room();
  SiteAnalytics analytics(site);
  std::vector<Event> events;
  const auto feed = [&](double t, Vec2 p) {
    const auto e = analytics.Update(t, {{3, p}});
    events.insert(events.end(), e.begin(), e.end());
  };
  const auto nobody = [&](double t) {
    const auto e = analytics.Update(t, {});
    events.insert(events.end(), e.begin(), e.end());
  };
  for (int i = 0; i <= 30; ++i) feed(0.1 * i, {2, 2});   // inside from t = 0
  for (int i = 31; i < 60; ++i) nobody(0.1 * i);         // 2.9 s without it
  for (int i = 60; i <= 80; ++i) feed(0.1 * i, {2, 2});  // back under its id
  CHECK(analytics.region_counts()[0].entries == 1);
  CHECK(analytics.region_counts()[0].occupancy == 1);
  for (int i = 81; i <= 140; ++i) nobody(0.1 * i);  // gone for good: ends after max_gap_s
  CHECK(analytics.region_counts()[0].occupancy == 0);
  REQUIRE(events.size() == 2);
  CHECK(events[1].kind == Event::Kind::kExit);
  CHECK(events[1].track_ended);
  CHECK(events[1].time_s == Approx(8.0));  // where it was last seen
  CHECK(events[1].enter_time_s == Approx(0.0));
}

TEST_CASE("analytics: a ghost shorter than hold_s is no visit, and crossings need the segment",
          "[unit]") {
  Site site = Room();
  SiteAnalytics analytics(site);
  for (int i = 0; i < 5; ++i) analytics.Update(0.1 * i, {{9, {2, 2}}});  // 0.4 s, then gone
  for (int i = 5; i < 100; ++i) analytics.Update(0.1 * i, {});
  analytics.Finish();
  CHECK(analytics.region_counts()[0].entries == 0);
  // Walking into the room beside the door (y = 0.5, the door spans y in [1, 3]) crosses the
  // line's extension, not the door: the room counts an entry, the door nothing.
  SiteAnalytics beside(site);
  Walk(&beside, Straight({-2, 0.5}, {2, 0.5}));
  CHECK(beside.region_counts()[0].entries == 1);
  CHECK(beside.line_counts()[0].right_to_left + beside.line_counts()[0].left_to_right == 0);
}

TEST_CASE(
    "analytics: time going backwards is ignored and counted, the input's order of tracks "
    "does not matter",
    "[unit]") {
  SiteAnalytics a(Room()), b(Room());
  std::vector<Event> from_a, from_b;
  for (int i = 0; i < 60; ++i) {
    const double t = 0.1 * i;
    const Vec2 p1(-1 + 0.1 * i, 2), p2(-1 + 0.08 * i, 1.5);
    auto e = a.Update(t, {{1, p1}, {2, p2}});
    from_a.insert(from_a.end(), e.begin(), e.end());
    e = b.Update(t, {{2, p2}, {1, p1}, {2, {100, 100}}});  // a repeated id is skipped
    from_b.insert(from_b.end(), e.begin(), e.end());
  }
  REQUIRE(from_a.size() == from_b.size());
  for (std::size_t i = 0; i < from_a.size(); ++i) {
    CHECK(from_a[i].track == from_b[i].track);
    CHECK(from_a[i].time_s == from_b[i].time_s);
  }
  CHECK(a.Update(1.0, {{1, {2, 2}}}).empty());
  CHECK(a.Update(std::nan(""), {{1, {2, 2}}}).empty());
  CHECK(a.ignored_messages() == 2);
}

}  // namespace mvtrack::analytics
