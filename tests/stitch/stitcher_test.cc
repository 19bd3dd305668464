#include "stitch/stitcher.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::stitch {
namespace {

constexpr Utime kStart = 1'700'000'000'000'000;
constexpr Utime kPeriod = 33'333;  // 30 fps

// A zone track at (x, y) on the floor.
struct At {
  TrackId3D id;
  double x;
  double y;
};

tracker::Frame3D MakeFrame(FrameIndex f, std::vector<At> tracks, Utime skew_us = 0) {
  tracker::Frame3D frame;
  frame.frame = f;
  frame.utime = kStart + f * kPeriod + skew_us;
  for (const At& a : tracks) {
    tracker::Track3D t;
    t.id = a.id;
    t.position = Vec3(a.x, a.y, 0.0);
    t.cameras = {static_cast<CameraId>(a.id)};
    frame.tracks.push_back(t);
  }
  return frame;
}

// Zone names "z0", "z1", ... for `n` zones.
std::vector<std::string> Names(int n) {
  std::vector<std::string> names;
  for (int z = 0; z < n; ++z) names.push_back("z" + std::to_string(z));
  return names;
}

// The global id of the site track nearest (x, y) in `frame` (0: none within 0.2 m).
TrackId3D IdAt(const SiteFrame& frame, double x, double y) {
  for (const tracker::Track3D& t : frame.frame.tracks) {
    if ((t.position.head<2>() - Vec2(x, y)).norm() < 0.2) return t.id;
  }
  return 0;
}

// Stitches per-zone frame lists (one frame per zone and index, or none) in order.
std::vector<SiteFrame> StitchAll(Stitcher* stitcher,
                                 const std::vector<std::vector<tracker::Frame3D>>& zones) {
  std::vector<SiteFrame> out;
  for (const ZoneFrames& group : AlignZoneFrames(zones, kPeriod / 2)) {
    out.push_back(stitcher->Stitch(group));
  }
  return out;
}

TEST_CASE("stitch/a person crossing from zone to zone keeps one id") {
  // Zone 0 sees x < 6, zone 1 sees x > 4 (the border cameras' overlap 4..6); the person walks
  // from x = 0 to x = 10 at 1.2 m/s, each zone's footprint off by a few centimetres.
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 300; ++f) {
    const double x = 1.2 * static_cast<double>(f) / 30.0;
    std::vector<At> z0, z1;
    if (x < 6.0) z0.push_back({7, x + 0.03, 2.0});
    if (x > 4.0) z1.push_back({3, x - 0.02, 2.04});
    zones[0].push_back(MakeFrame(f, z0));
    zones[1].push_back(MakeFrame(f, z1, 2000));  // the zones' capture times differ by 2 ms
  }
  Stitcher stitcher(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  REQUIRE(site.size() == 300);
  std::set<TrackId3D> ids;
  bool both = false;
  for (const SiteFrame& s : site) {
    REQUIRE(s.frame.tracks.size() == 1);
    ids.insert(s.frame.tracks[0].id);
    if (s.frame.tracks[0].zones == std::vector<int>{0, 1}) {
      both = true;
      // The mean of the two zones' footprints.
      const double x = 1.2 * static_cast<double>(s.frame.frame) / 30.0;
      CHECK(s.frame.tracks[0].position.x() == Approx(x + 0.005));
      CHECK(s.frame.tracks[0].position.y() == Approx(2.02));
      CHECK(s.frame.tracks[0].cameras == std::vector<CameraId>{3, 7});
    }
  }
  CHECK(ids == std::set<TrackId3D>{1});
  CHECK(both);
  CHECK(site.back().frame.tracks[0].zones == std::vector<int>{1});
  CHECK(site.back().frame.zones == Names(2));
  CHECK(stitcher.stats().global_ids == 1);
  CHECK(stitcher.stats().joined_overlap == 1);
}

TEST_CASE("stitch/two people crossing the border side by side keep their ids") {
  // 1.0 m apart across the walking direction: each zone tracks both in the overlap.
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 300; ++f) {
    const double x = 1.2 * static_cast<double>(f) / 30.0;
    std::vector<At> z0, z1;
    if (x < 6.0) z0 = {{1, x, 2.0}, {2, x + 0.05, 3.0}};
    if (x > 4.0) z1 = {{5, x + 0.04, 3.02}, {6, x - 0.03, 1.97}};
    zones[0].push_back(MakeFrame(f, z0));
    zones[1].push_back(MakeFrame(f, z1));
  }
  Stitcher stitcher(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  for (const SiteFrame& s : site) {
    const double x = 1.2 * static_cast<double>(s.frame.frame) / 30.0;
    REQUIRE(s.frame.tracks.size() == 2);
    CHECK(IdAt(s, x, 2.0) == 1);
    CHECK(IdAt(s, x + 0.05, 3.0) + IdAt(s, x + 0.04, 3.02) >= 2);
    for (const tracker::Track3D& t : s.frame.tracks) CHECK(t.id <= 2);
  }
  CHECK(stitcher.stats().splits == 0);
}

TEST_CASE("stitch/a join of two people who go apart is undone after kSplitFrames") {
  // Zone 1's track starts 0.3 m from zone 0's person (joined), then walks away at 3 m/s.
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 40; ++f) {
    zones[0].push_back(MakeFrame(f, {{1, 5.0, 2.0}}));
    const double y = 2.3 + (f < 5 ? 0.0 : 3.0 * static_cast<double>(f - 5) / 30.0);
    zones[1].push_back(MakeFrame(f, {{9, 5.0, y}}));
  }
  Stitcher stitcher(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  CHECK(site[0].frame.tracks.size() == 1);  // one person: within kSamePersonApartM
  // The walker passes 1.0 m from the standing person at frame 5 + 7 = 12; three frames later
  // it is a person of its own.
  FrameIndex split_at = -1;
  for (const SiteFrame& s : site) {
    if (s.frame.tracks.size() == 2 && split_at < 0) split_at = s.frame.frame;
  }
  CHECK(split_at >= 12);
  CHECK(split_at <= 16);
  CHECK(stitcher.stats().splits == 1);
  CHECK(IdAt(site.back(), 5.0, 2.0) == 1);
  CHECK(stitcher.stats().global_ids == 2);
}

TEST_CASE("stitch/a zone's better track takes the global track from its worse one") {
  // Zone 1 has two tracks by zone 0's person: id 4, 0.35 m off, joined first; then id 5 at
  // 0.02 m appears. The nearer takes the global track, the other starts its own.
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 10; ++f) {
    zones[0].push_back(MakeFrame(f, {{1, 5.0, 2.0}}));
    std::vector<At> z1 = {{4, 5.0, 2.35}};
    if (f >= 3) z1.push_back({5, 5.0, 2.02});
    zones[1].push_back(MakeFrame(f, z1));
  }
  Stitcher stitcher(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  REQUIRE(site[2].frame.tracks.size() == 1);
  CHECK(site[2].frame.tracks[0].zones == std::vector<int>{0, 1});
  REQUIRE(site[3].frame.tracks.size() == 2);
  CHECK(IdAt(site[3], 5.0, 2.01) == 1);  // the mean of zone 0's 2.0 and zone 1's 2.02
  CHECK(IdAt(site[3], 5.0, 2.35) == 2);
  CHECK(IdAt(site.back(), 5.0, 2.01) == 1);
  // Not when the newcomer is nearer by less than the margin (0.2 m).
  std::vector<std::vector<tracker::Frame3D>> close(2);
  for (FrameIndex f = 0; f < 10; ++f) {
    close[0].push_back(MakeFrame(f, {{1, 5.0, 2.0}}));
    std::vector<At> z1 = {{4, 5.0, 2.15}};
    if (f >= 3) z1.push_back({5, 5.0, 1.98});
    close[1].push_back(MakeFrame(f, z1));
  }
  Stitcher again(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> kept = StitchAll(&again, close);
  CHECK(IdAt(kept.back(), 5.0, 2.075) == 1);  // zone 1's id 4 stays with the person
}

TEST_CASE("stitch/a person first seen by two zones in the same frame gets one id") {
  std::vector<std::vector<tracker::Frame3D>> zones(3);
  for (FrameIndex f = 0; f < 10; ++f) {
    zones[0].push_back(MakeFrame(f, {{4, 5.0, 2.0}}));
    zones[1].push_back(MakeFrame(f, {}));
    zones[2].push_back(MakeFrame(f, {{8, 5.1, 2.0}}));
  }
  Stitcher stitcher(Names(3), linking::LinkerOptions{});
  for (const SiteFrame& s : StitchAll(&stitcher, zones)) {
    REQUIRE(s.frame.tracks.size() == 1);
    CHECK(s.frame.tracks[0].id == 1);
    CHECK(s.frame.tracks[0].zones == std::vector<int>{0, 2});
    CHECK(s.frame.tracks[0].position.x() == Approx(5.05));
  }
}

TEST_CASE("stitch/two ids of one person seen apart at first merge into the older") {
  // The zones' first footprints are 0.8 m apart (too far to join), then agree.
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 20; ++f) {
    zones[0].push_back(MakeFrame(f, {{1, 5.0, 2.0}}));
    zones[1].push_back(MakeFrame(f, {{2, 5.0, f < 4 ? 2.8 : 2.1}}));
  }
  Stitcher stitcher(Names(2), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  CHECK(site[0].frame.tracks.size() == 2);
  // Close from frame 4 on: merged at the third close frame.
  CHECK(site[5].frame.tracks.size() == 2);
  REQUIRE(site[6].frame.tracks.size() == 1);
  CHECK(site[6].frame.tracks[0].id == 1);
  CHECK(site.back().frame.tracks[0].id == 1);
  CHECK(stitcher.stats().merges == 1);
  CHECK(stitcher.next_id() == 3);  // id 2 is never given out again
}

TEST_CASE("stitch/a gap between zones is bridged by motion only with re-identification on") {
  // The person leaves zone 0 at x = 5.0 and appears in zone 1 at x = 5.6, 0.5 s later.
  auto run = [](double reid_gate_chi2) {
    std::vector<std::vector<tracker::Frame3D>> zones(2);
    for (FrameIndex f = 0; f < 200; ++f) {
      const double x = 1.2 * static_cast<double>(f) / 30.0;
      std::vector<At> z0, z1;
      if (x <= 5.0) z0.push_back({1, x, 2.0});
      if (x >= 5.6) z1.push_back({1, x, 2.0});
      zones[0].push_back(MakeFrame(f, z0));
      zones[1].push_back(MakeFrame(f, z1));
    }
    linking::LinkerOptions options;
    options.reid_gate_chi2 = reid_gate_chi2;
    Stitcher stitcher(Names(2), options);
    std::set<TrackId3D> ids;
    for (const SiteFrame& s : StitchAll(&stitcher, zones)) {
      for (const tracker::Track3D& t : s.frame.tracks) ids.insert(t.id);
    }
    return std::make_pair(ids, stitcher.stats().joined_motion);
  };
  const auto off = run(0.0);
  CHECK(off.first == std::set<TrackId3D>{1, 2});
  CHECK(off.second == 0);
  const auto on = run(9.49);
  CHECK(on.first == std::set<TrackId3D>{1});
  CHECK(on.second == 1);
}

TEST_CASE("stitch/ids are forgotten after max_lost_s and never given out again") {
  std::vector<std::vector<tracker::Frame3D>> zones(1);
  for (FrameIndex f = 0; f < 400; ++f) {
    // The same zone id comes back after 5 s (> max_lost_s = 3 s): a new global id.
    std::vector<At> z0;
    if (f < 100 || f >= 250) z0.push_back({1, 5.0, 2.0});
    zones[0].push_back(MakeFrame(f, z0));
  }
  Stitcher stitcher(Names(1), linking::LinkerOptions{});
  const std::vector<SiteFrame> site = StitchAll(&stitcher, zones);
  CHECK(site[99].frame.tracks[0].id == 1);
  CHECK(site[150].frame.tracks.empty());
  CHECK(site[250].frame.tracks[0].id == 2);
  CHECK(site[250].frame.tracks[0].age_frames == 0);
  CHECK(site[399].frame.tracks[0].age_frames == 149);
}

TEST_CASE("stitch/AlignZoneFrames groups by capture time and leaves missing frames empty") {
  std::vector<std::vector<tracker::Frame3D>> zones(2);
  for (FrameIndex f = 0; f < 5; ++f) {
    zones[0].push_back(MakeFrame(f, {}));
    if (f != 2) zones[1].push_back(MakeFrame(f, {}, kPeriod / 3));
  }
  const std::vector<ZoneFrames> groups = AlignZoneFrames(zones, kPeriod / 2);
  REQUIRE(groups.size() == 5);
  for (std::size_t i = 0; i < groups.size(); ++i) {
    REQUIRE(groups[i][0] != nullptr);
    CHECK(groups[i][0]->frame == static_cast<FrameIndex>(i));
    CHECK((groups[i][1] == nullptr) == (i == 2));
  }
  // A skew beyond the tolerance makes two groups.
  const std::vector<ZoneFrames> strict = AlignZoneFrames(zones, kPeriod / 4);
  CHECK(strict.size() == 9);
  CHECK(HalfFramePeriod(zones[0]) == kPeriod / 2);
  CHECK_FALSE(HalfFramePeriod({}).has_value());
}

}  // namespace
}  // namespace mvtrack::stitch
