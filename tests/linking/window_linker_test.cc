#include "linking/window_linker.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::linking {
namespace {

// The paper's window geometry: size nu = 30, step delta = 20 (10 overlapping frames).
constexpr std::int64_t kNu = 30;
constexpr std::int64_t kDelta = 20;

using Trajectory = std::function<Vec3(FrameIndex)>;

// A synthetic person: a ground-truth trajectory of its body centre and the windows in which
// the 3D stage produced a tracklet for it.
struct Person {
  Trajectory centre;
  std::function<bool(std::int64_t)> present = [](std::int64_t) { return true; };
};

// Joint offsets from the body centre (a small "skeleton": head, chest, shoulders, feet).
const std::vector<Vec3>& SkeletonOffsets() {
  static const std::vector<Vec3> offsets = {Vec3(0.0, 0.0, 0.7),
                                            Vec3(0.0, 0.0, 0.3),
                                            Vec3(0.2, 0.0, 0.4),
                                            Vec3(-0.2, 0.0, 0.4),
                                            Vec3(0.0, 0.0, -0.9)};
  return offsets;
}

// Walks in a straight line from `start` with constant velocity (metres per frame).
Trajectory Straight(const Vec3& start, const Vec3& velocity_m_per_frame) {
  return [start, velocity_m_per_frame](FrameIndex t) {
    return Vec3(start + static_cast<double>(t) * velocity_m_per_frame);
  };
}

// The short-term tracklet of `person` in window k: frames [k*delta, k*delta + nu), every joint
// at its ground-truth position plus independent Gaussian noise (each window triangulates anew,
// so the overlapping frames of two windows disagree by the noise).
core::Tracklet3D MakeTracklet(const Trajectory& centre,
                              std::int64_t window,
                              const std::vector<Vec3>& offsets,
                              double noise_sigma_m,
                              std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, noise_sigma_m);
  core::Tracklet3D tracklet;
  for (FrameIndex t = window * kDelta; t < window * kDelta + kNu; ++t) {
    tracklet.frames.push_back(t);
    std::vector<std::optional<Vec3>> points;
    for (const Vec3& offset : offsets) {
      Vec3 p = centre(t) + offset;
      if (noise_sigma_m > 0.0) {
        // One draw per statement: argument evaluation order is unspecified.
        for (int axis = 0; axis < 3; ++axis) p[axis] += noise(*rng);
      }
      points.emplace_back(p);
    }
    tracklet.points.push_back(std::move(points));
  }
  return tracklet;
}

// One window of a scene: the tracklets in shuffled order and the person behind each.
struct SceneWindow {
  std::vector<core::Tracklet3D> tracklets;
  std::vector<int> person_of_tracklet;
};

SceneWindow MakeWindow(const std::vector<Person>& people,
                       std::int64_t window,
                       const std::vector<Vec3>& offsets,
                       double noise_sigma_m,
                       std::mt19937* rng) {
  std::vector<int> order;
  for (int p = 0; p < static_cast<int>(people.size()); ++p) {
    if (people[static_cast<std::size_t>(p)].present(window)) order.push_back(p);
  }
  // Index order must carry no identity.
  std::shuffle(order.begin(), order.end(), *rng);
  SceneWindow w;
  for (int p : order) {
    w.tracklets.push_back(
        MakeTracklet(people[static_cast<std::size_t>(p)].centre, window, offsets, noise_sigma_m, rng));
    w.person_of_tracklet.push_back(p);
  }
  return w;
}

const LinkedTrack* FindTrack(const WindowLinker& linker, TrackId3D id) {
  for (const LinkedTrack& t : linker.tracks()) {
    if (t.id == id) return &t;
  }
  return nullptr;
}

// Index of person `p` in a window, or -1.
int IndexOfPerson(const SceneWindow& w, int p) {
  const auto it = std::find(w.person_of_tracklet.begin(), w.person_of_tracklet.end(), p);
  return it == w.person_of_tracklet.end() ? -1
                                          : static_cast<int>(it - w.person_of_tracklet.begin());
}

bool IsSortedUnique(const std::vector<TrackId3D>& ids) {
  return std::adjacent_find(ids.begin(), ids.end(), [](TrackId3D a, TrackId3D b) {
           return a >= b;
         }) == ids.end();
}

// A single-point (box mode) tracklet over the given frames, all at `point`.
core::Tracklet3D ConstantTracklet(FrameIndex first, FrameIndex last, const Vec3& point) {
  core::Tracklet3D tracklet;
  for (FrameIndex t = first; t <= last; ++t) {
    tracklet.frames.push_back(t);
    tracklet.points.push_back({point});
  }
  return tracklet;
}

TEST_CASE("Eq. 8 distance on a hand-made case", "[unit]") {
  // a: frames 10..13, b: frames 11..14, two points per frame. The overlap is {11, 12, 13}.
  const Vec3 a0(1.0, 2.0, 3.0);
  const Vec3 a1(-1.0, 0.5, 1.5);
  core::Tracklet3D a;
  a.frames = {10, 11, 12, 13};
  a.points = {{a0, a1},
              {std::nullopt, a1},  // 11: only point 1
              {a0, a1},            // 12: both
              {a0, a1}};           // 13: both (b lacks point 0 here)
  core::Tracklet3D b;
  b.frames = {11, 12, 13, 14};
  const Vec3 off12_0(0.6, 0.8, 0.0);  // |.| = 1
  const Vec3 off12_1(0.0, 0.0, 3.0);  // |.| = 3
  const Vec3 off13_1(0.3, 0.0, 0.4);  // |.| = 0.5
  const double nan = std::numeric_limits<double>::quiet_NaN();
  b.points = {{a0, std::nullopt},                      // 11: only point 0 -> no common point
              {Vec3(a0 + off12_0), Vec3(a1 + off12_1)},  // 12: mean(1, 3) = 2
              {Vec3(nan, 0.0, 0.0), Vec3(a1 + off13_1)}, // 13: NaN point 0 is invalid -> 0.5
              {a0, a1}};
  // Frame 11 has no common point and is left out: (2 + 0.5) / 2 frames. Pooling all point
  // distances would give 1.5, dividing by the 3 overlapping frames 0.8333.
  const double expected = ((off12_0.norm() + off12_1.norm()) / 2.0 + off13_1.norm()) / 2.0;
  const auto d_ab = MeanOverlapDistance(a, b);
  const auto d_ba = MeanOverlapDistance(b, a);
  REQUIRE(d_ab.has_value());
  REQUIRE(d_ba.has_value());
  CHECK(*d_ab == Approx(expected).epsilon(1e-12));
  CHECK(expected == Approx(1.25));
  CHECK(*d_ba == Approx(*d_ab).epsilon(1e-12));
}

TEST_CASE("Eq. 8 distance is undefined without overlap or without common points", "[unit]") {
  const core::Tracklet3D early = ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0));
  const core::Tracklet3D late = ConstantTracklet(30, 59, Vec3(0.0, 0.0, 1.0));
  CHECK_FALSE(MeanOverlapDistance(early, late).has_value());
  CHECK_FALSE(MeanOverlapDistance(early, core::Tracklet3D{}).has_value());

  // Overlapping frames, but a has only point 0 and b only point 1.
  core::Tracklet3D a;
  core::Tracklet3D b;
  for (FrameIndex t = 0; t < 10; ++t) {
    a.frames.push_back(t);
    a.points.push_back({Vec3(0.0, 0.0, 1.0), std::nullopt});
    b.frames.push_back(t + 5);
    b.points.push_back({std::nullopt, Vec3(0.0, 0.0, 1.0)});
  }
  CHECK_FALSE(MeanOverlapDistance(a, b).has_value());
  // Giving b point 0 at one common frame (7) makes exactly that frame count.
  b.points[2][0] = Vec3(3.0, 4.0, 1.0);
  const auto d = MeanOverlapDistance(a, b);
  REQUIRE(d.has_value());
  CHECK(*d == Approx(5.0));
}

TEST_CASE("Gap measurement uses the last and first valid frames and common joints", "[unit]") {
  core::Tracklet3D from;
  from.frames = {0, 1, 2, 3};
  from.points = {{Vec3(9.0, 9.0, 9.0), Vec3(9.0, 9.0, 9.0), std::nullopt},
                 {Vec3(0.0, 0.0, 1.0), Vec3(1.0, 0.0, 1.0), std::nullopt},  // last valid frame
                 {std::nullopt, std::nullopt, std::nullopt},
                 {std::nullopt, std::nullopt, std::nullopt}};
  core::Tracklet3D to;
  to.frames = {10, 11, 12};
  to.points = {{std::nullopt, std::nullopt, std::nullopt},
               {std::nullopt, Vec3(1.0, 2.0, 1.0), Vec3(5.0, 5.0, 5.0)},  // first valid frame
               {Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.0)}};
  const auto gap = MeasureGap(from, to);
  REQUIRE(gap.has_value());
  CHECK(gap->gap_frames == 11 - 1);
  // Only point 1 is valid in both frames: |(1,2,1) - (1,0,1)| = 2 (all valid points would give
  // |mean{(1,2,1),(5,5,5)} - mean{(0,0,1),(1,0,1)}| instead).
  CHECK(gap->distance_m == Approx(2.0));

  // Without a common joint each frame's own valid points are used.
  to.points[1] = {std::nullopt, std::nullopt, Vec3(0.5, 3.0, 1.0)};
  const auto gap2 = MeasureGap(from, to);
  REQUIRE(gap2.has_value());
  CHECK(gap2->distance_m == Approx((Vec3(0.5, 3.0, 1.0) - Vec3(0.5, 0.0, 1.0)).norm()));

  core::Tracklet3D empty_points;
  empty_points.frames = {20};
  empty_points.points = {{std::nullopt}};
  CHECK_FALSE(MeasureGap(from, empty_points).has_value());
  CHECK_FALSE(MeasureGap(empty_points, to).has_value());
}

TEST_CASE("LinkerOptions::Validate rejects out-of-range settings", "[unit]") {
  std::string why;
  CHECK(LinkerOptions{}.Validate(&why));
  LinkerOptions o;
  o.max_link_distance_m = 0.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("max_link_distance_m") != std::string::npos);
  o = {};
  o.max_link_distance_m = std::numeric_limits<double>::infinity();
  CHECK_FALSE(o.Validate(nullptr));
  o = {};
  o.min_hits = 0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("min_hits") != std::string::npos);
  o = {};
  o.max_missed_windows = -1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("max_missed_windows") != std::string::npos);
  o = {};
  o.max_speed_m_per_frame = -0.1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("max_speed_m_per_frame") != std::string::npos);
}

TEST_CASE("Three walking people keep their identities, two passing 0.4 m apart", "[unit]") {
  // A and B walk towards each other on parallel lines 0.4 m apart (0.028 m/frame, ~0.84 m/s
  // at 30 fps) and pass at frame 125, inside the overlap of windows 5 and 6; C walks a circle.
  std::vector<Person> people(3);
  people[0].centre = Straight(Vec3(-3.5, 0.0, 1.0), Vec3(0.028, 0.0, 0.0));
  people[1].centre = Straight(Vec3(3.5, 0.4, 1.0), Vec3(-0.028, 0.0, 0.0));
  people[2].centre = [](FrameIndex t) {
    const double phase = 0.01 * static_cast<double>(t);
    return Vec3(2.0 * std::cos(phase), 3.0 + 2.0 * std::sin(phase), 1.0);
  };
  constexpr double kNoise = 0.02;
  constexpr std::int64_t kWindows = 12;
  std::mt19937 rng(20240531);
  WindowLinker linker;
  std::map<int, TrackId3D> id_of_person;
  SceneWindow previous;
  bool checked_crossing = false;
  for (std::int64_t k = 0; k < kWindows; ++k) {
    const SceneWindow w = MakeWindow(people, k, SkeletonOffsets(), kNoise, &rng);
    const LinkResult r = linker.Link(k, w.tracklets);
    REQUIRE(r.window_id == k);
    REQUIRE(r.track_of_tracklet.size() == w.tracklets.size());
    REQUIRE(r.link_distance_m.size() == w.tracklets.size());
    CHECK(r.died.empty());
    if (k == 0) {
      CHECK(r.born == std::vector<TrackId3D>{1, 2, 3});
      for (std::size_t i = 0; i < w.tracklets.size(); ++i) {
        id_of_person[w.person_of_tracklet[i]] = r.track_of_tracklet[i];
        CHECK(r.link_kind[i] == LinkKind::kBirth);
        CHECK(std::isnan(r.link_distance_m[i]));
      }
      CHECK(id_of_person.size() == 3);
    } else {
      CHECK(r.born.empty());
      for (std::size_t i = 0; i < w.tracklets.size(); ++i) {
        const int p = w.person_of_tracklet[i];
        CHECK(r.track_of_tracklet[i] == id_of_person.at(p));
        CHECK(r.link_kind[i] == LinkKind::kOverlap);
        CHECK(r.link_distance_m[i] < 0.1);
      }
    }
    if (k == 6) {
      // The crossing is a real test of the assignment: the swapped pairs are inside the gate
      // too, so only the minimum-cost assignment keeps A and B apart.
      const auto swap_ab = MeanOverlapDistance(
          previous.tracklets[static_cast<std::size_t>(IndexOfPerson(previous, 0))],
          w.tracklets[static_cast<std::size_t>(IndexOfPerson(w, 1))]);
      const auto swap_ba = MeanOverlapDistance(
          previous.tracklets[static_cast<std::size_t>(IndexOfPerson(previous, 1))],
          w.tracklets[static_cast<std::size_t>(IndexOfPerson(w, 0))]);
      REQUIRE(swap_ab.has_value());
      REQUIRE(swap_ba.has_value());
      CHECK(*swap_ab <= linker.options().max_link_distance_m);
      CHECK(*swap_ba <= linker.options().max_link_distance_m);
      checked_crossing = true;
    }
    REQUIRE(linker.tracks().size() == 3);
    for (const LinkedTrack& t : linker.tracks()) {
      CHECK(t.state == TrackState::kConfirmed);
      CHECK(t.hits == k + 1);
      CHECK(t.missed_windows == 0);
      CHECK(t.first_window == 0);
      CHECK(t.last_window == k);
      CHECK(t.last_tracklet.frames.front() == k * kDelta);
    }
    previous = w;
  }
  CHECK(checked_crossing);
  CHECK(std::is_sorted(linker.tracks().begin(),
                       linker.tracks().end(),
                       [](const LinkedTrack& x, const LinkedTrack& y) { return x.id < y.id; }));
}

TEST_CASE("Missing people: re-linked across a gap, or reborn after max_missed_windows",
          "[unit]") {
  // max_missed_windows = 2 (default). Windows 0-2: everyone. Then:
  //   P0 always present;
  //   P1 misses window 3 (1 window)   -> re-linked at window 4 by the gap rule;
  //   P3 misses windows 3-4 (2 = max) -> re-linked at window 5 by the gap rule;
  //   P2 misses windows 3-5 (3 > max) -> dies at window 5, new id at window 6;
  //   D appears at window 4, 1.2 m from P1's last seen position (inside P1's gap gate, but
  //     farther than P1's own tracklet) -> born.
  std::vector<Person> people(5);
  people[0].centre = Straight(Vec3(-3.0, 0.0, 1.0), Vec3(0.02, 0.0, 0.0));
  people[1].centre = Straight(Vec3(-3.0, 3.0, 1.0), Vec3(0.03, 0.0, 0.0));
  people[1].present = [](std::int64_t k) { return k != 3; };
  people[2].centre = Straight(Vec3(0.0, -6.0, 1.0), Vec3(0.0, 0.025, 0.0));
  people[2].present = [](std::int64_t k) { return k < 3 || k > 5; };
  people[3].centre = Straight(Vec3(0.0, -14.0, 1.0), Vec3(-0.025, 0.0, 0.0));
  people[3].present = [](std::int64_t k) { return k < 3 || k > 4; };
  const Vec3 d_position = people[1].centre(80) + Vec3(0.0, 1.2, 0.0);
  people[4].centre = [d_position](FrameIndex) { return d_position; };
  people[4].present = [](std::int64_t k) { return k >= 4; };

  constexpr double kNoise = 0.02;
  std::mt19937 rng(7);
  WindowLinker linker;
  std::map<int, TrackId3D> id_of_person;
  std::set<TrackId3D> all_ids;
  for (std::int64_t k = 0; k < 9; ++k) {
    const SceneWindow w = MakeWindow(people, k, SkeletonOffsets(), kNoise, &rng);
    const LinkResult r = linker.Link(k, w.tracklets);
    CHECK(IsSortedUnique(r.born));
    CHECK(IsSortedUnique(r.died));
    const auto id_at = [&](int p) {
      return r.track_of_tracklet[static_cast<std::size_t>(IndexOfPerson(w, p))];
    };
    const auto kind_at = [&](int p) {
      return r.link_kind[static_cast<std::size_t>(IndexOfPerson(w, p))];
    };
    if (k == 0) {
      for (int p = 0; p < 4; ++p) id_of_person[p] = id_at(p);
      CHECK(r.born == std::vector<TrackId3D>{1, 2, 3, 4});
    }
    if (k == 3) {
      CHECK(r.died.empty());
      for (int p : {1, 2, 3}) {
        const LinkedTrack* t = FindTrack(linker, id_of_person[p]);
        REQUIRE(t != nullptr);
        CHECK(t->state == TrackState::kLost);
        CHECK(t->missed_windows == 1);
        CHECK(t->last_window == 2);
      }
    }
    if (k == 4) {
      // P1 re-linked across its one-window gap; the distractor is born instead.
      CHECK(id_at(1) == id_of_person[1]);
      CHECK(kind_at(1) == LinkKind::kGap);
      const double truth = (people[1].centre(80) - people[1].centre(69)).norm();
      CHECK(r.link_distance_m[static_cast<std::size_t>(IndexOfPerson(w, 1))] ==
            Approx(truth).margin(0.06));
      const TrackId3D d_id = id_at(4);
      CHECK(all_ids.count(d_id) == 0);
      CHECK(r.born == std::vector<TrackId3D>{d_id});
      CHECK(kind_at(4) == LinkKind::kBirth);
      CHECK(FindTrack(linker, id_of_person[1])->state == TrackState::kConfirmed);
      // P2 and P3 have missed exactly max_missed_windows: lost but alive.
      CHECK(r.died.empty());
      for (int p : {2, 3}) {
        const LinkedTrack* t = FindTrack(linker, id_of_person[p]);
        REQUIRE(t != nullptr);
        CHECK(t->missed_windows == 2);
        CHECK(t->state == TrackState::kLost);
      }
    }
    if (k == 5) {
      // P3 re-linked after two missed windows; P2's third miss kills its track.
      CHECK(id_at(3) == id_of_person[3]);
      CHECK(kind_at(3) == LinkKind::kGap);
      CHECK(r.died == std::vector<TrackId3D>{id_of_person[2]});
      CHECK(FindTrack(linker, id_of_person[2]) == nullptr);
      CHECK(r.born.empty());
    }
    if (k == 6) {
      const TrackId3D reborn = id_at(2);
      CHECK(reborn != id_of_person[2]);
      CHECK(all_ids.count(reborn) == 0);
      CHECK(r.born == std::vector<TrackId3D>{reborn});
      CHECK(kind_at(2) == LinkKind::kBirth);
      id_of_person[2] = reborn;
    }
    if (k >= 5) {
      for (int p : {0, 1, 3}) CHECK(id_at(p) == id_of_person[p]);
    }
    if (k >= 7) {
      CHECK(r.born.empty());
      CHECK(r.died.empty());
      CHECK(id_at(2) == id_of_person[2]);
      CHECK(kind_at(2) == LinkKind::kOverlap);
    }
    CHECK(id_at(0) == id_of_person[0]);
    for (TrackId3D id : r.track_of_tracklet) all_ids.insert(id);
  }
  // Ids: 1-4 at window 0, D = 5 at window 4, P2 reborn = 6 at window 6; never reused.
  CHECK(all_ids == std::set<TrackId3D>{1, 2, 3, 4, 5, 6});
}

TEST_CASE("min_hits confirmation counts matched windows; a lost track keeps its hits",
          "[unit]") {
  LinkerOptions options;
  options.min_hits = 3;
  WindowLinker linker(options);
  const Trajectory walk = Straight(Vec3(0.0, 0.0, 1.0), Vec3(0.02, 0.0, 0.0));
  const Trajectory other = Straight(Vec3(0.0, 5.0, 1.0), Vec3(0.0, 0.02, 0.0));
  std::mt19937 rng(3);
  const std::vector<Vec3> box = {Vec3::Zero()};
  // `walk` present in windows 0,1,2,4; `other` in 0,2,3.
  const auto run = [&](std::int64_t k, bool with_walk, bool with_other) {
    std::vector<core::Tracklet3D> tracklets;
    if (with_walk) tracklets.push_back(MakeTracklet(walk, k, box, 0.01, &rng));
    if (with_other) tracklets.push_back(MakeTracklet(other, k, box, 0.01, &rng));
    return linker.Link(k, tracklets);
  };
  const LinkResult r0 = run(0, true, true);
  REQUIRE(r0.born == std::vector<TrackId3D>{1, 2});
  const auto state = [&](TrackId3D id) { return FindTrack(linker, id)->state; };
  const auto hits = [&](TrackId3D id) { return FindTrack(linker, id)->hits; };
  CHECK(state(1) == TrackState::kTentative);
  CHECK(hits(1) == 1);
  CHECK(state(2) == TrackState::kTentative);

  run(1, true, false);
  CHECK(state(1) == TrackState::kTentative);
  CHECK(hits(1) == 2);
  CHECK(state(2) == TrackState::kLost);
  CHECK(hits(2) == 1);

  const LinkResult r2 = run(2, true, true);
  CHECK(r2.track_of_tracklet == std::vector<TrackId3D>{1, 2});
  CHECK(r2.link_kind[1] == LinkKind::kGap);
  CHECK(state(1) == TrackState::kConfirmed);
  CHECK(hits(1) == 3);
  CHECK(state(2) == TrackState::kTentative);  // re-linked, 2 of 3 hits
  CHECK(hits(2) == 2);

  run(3, false, true);
  CHECK(state(1) == TrackState::kLost);
  CHECK(state(2) == TrackState::kConfirmed);
  CHECK(hits(2) == 3);

  const LinkResult r4 = run(4, true, false);
  CHECK(r4.track_of_tracklet == std::vector<TrackId3D>{1});
  CHECK(state(1) == TrackState::kConfirmed);  // confirmed tracks stay confirmed after a miss
  CHECK(hits(1) == 4);
  CHECK(state(2) == TrackState::kLost);
}

TEST_CASE("Skipped window ids count as windows without tracklets", "[unit]") {
  const Trajectory a = Straight(Vec3(0.0, 0.0, 1.0), Vec3(0.03, 0.0, 0.0));
  const Trajectory b = Straight(Vec3(0.0, 4.0, 1.0), Vec3(0.0, -0.01, 0.0));
  std::mt19937 rng(11);
  const std::vector<Vec3> box = {Vec3::Zero()};
  const auto window = [&](std::int64_t k) {
    return std::vector<core::Tracklet3D>{MakeTracklet(a, k, box, 0.01, &rng),
                                         MakeTracklet(b, k, box, 0.01, &rng)};
  };
  WindowLinker linker;  // max_missed_windows = 2
  REQUIRE(linker.Link(0, window(0)).born == std::vector<TrackId3D>{1, 2});

  // Window 1 skipped: one miss, then re-linked across the gap.
  const LinkResult r2 = linker.Link(2, window(2));
  CHECK(r2.track_of_tracklet == std::vector<TrackId3D>{1, 2});
  CHECK(r2.link_kind == std::vector<LinkKind>{LinkKind::kGap, LinkKind::kGap});
  CHECK(r2.born.empty());
  CHECK(r2.died.empty());
  CHECK(FindTrack(linker, 1)->hits == 2);
  CHECK(FindTrack(linker, 1)->last_window == 2);

  // Windows 3 and 4 skipped: exactly max_missed_windows, still linked.
  const LinkResult r5 = linker.Link(5, window(5));
  CHECK(r5.track_of_tracklet == std::vector<TrackId3D>{1, 2});
  CHECK(r5.died.empty());

  // An empty window is a miss as well.
  const LinkResult r6 = linker.Link(6, {});
  CHECK(r6.track_of_tracklet.empty());
  CHECK(FindTrack(linker, 1)->missed_windows == 1);
  CHECK(FindTrack(linker, 1)->state == TrackState::kLost);

  // Windows 7 and 8 skipped: 3 misses > 2, both die before linking window 9.
  const LinkResult r9 = linker.Link(9, window(9));
  CHECK(r9.died == std::vector<TrackId3D>{1, 2});
  CHECK(r9.born == std::vector<TrackId3D>{3, 4});
  CHECK(r9.track_of_tracklet == std::vector<TrackId3D>{3, 4});
  REQUIRE(linker.tracks().size() == 2);
  CHECK(linker.tracks()[0].id == 3);
  CHECK(linker.tracks()[0].first_window == 9);

  // A huge skip neither overflows nor keeps anyone alive.
  const std::int64_t far = std::numeric_limits<std::int64_t>::max();
  const LinkResult rfar = linker.Link(far, {});
  CHECK(rfar.died == std::vector<TrackId3D>{3, 4});
  CHECK(linker.tracks().empty());
}

TEST_CASE("An overlapping tracklet beyond the gate is born, never gap-linked", "[unit]") {
  WindowLinker linker;
  linker.Link(0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0))});
  // Overlaps frames 20-29 at 0.8 m > 0.5 m. Its centroid distance (0.8 m over |20 - 29| = 9
  // frames) would pass the gap gate, but overlapping pairs are judged by Eq. 8 only.
  const LinkResult r = linker.Link(1, {ConstantTracklet(20, 49, Vec3(0.8, 0.0, 1.0))});
  CHECK(r.born == std::vector<TrackId3D>{2});
  CHECK(r.link_kind[0] == LinkKind::kBirth);
  REQUIRE(FindTrack(linker, 1) != nullptr);
  CHECK(FindTrack(linker, 1)->missed_windows == 1);

  // Within the gate it links, with the Eq. 8 distance reported.
  const LinkResult r2 = linker.Link(2, {ConstantTracklet(40, 69, Vec3(0.8, 0.3, 1.0))});
  CHECK(r2.track_of_tracklet == std::vector<TrackId3D>{2});
  CHECK(r2.link_kind[0] == LinkKind::kOverlap);
  CHECK(r2.link_distance_m[0] == Approx(0.3));
}

TEST_CASE("Overlap matches take precedence over gap matches", "[unit]") {
  // P (track 1) at the origin, Q (track 2) 1.0 m away. Q misses window 1. In window 2 the
  // tracklet x continues P (Eq. 8 = 0.05 m) and a newcomer y stands 0.45 m on P's other side
  // (Eq. 8 to P = 0.45 m, inside the gate). x is inside Q's gap gate (0.5 + 0.05 * 11 = 1.05
  // m), y is not (1.45 m). A single matrix maximising the number of matches would give P's id
  // to y and Q's id to x; the staged assignment keeps P on x and starts a track for y.
  LinkerOptions options;
  options.max_speed_m_per_frame = 0.05;
  WindowLinker linker(options);
  const Vec3 p(0.0, 0.0, 1.0);
  const Vec3 q(1.0, 0.0, 1.0);
  REQUIRE(linker.Link(0, {ConstantTracklet(0, 29, p), ConstantTracklet(0, 29, q)}).born ==
          std::vector<TrackId3D>{1, 2});
  REQUIRE(linker.Link(1, {ConstantTracklet(20, 49, p)}).track_of_tracklet ==
          std::vector<TrackId3D>{1});
  const core::Tracklet3D y = ConstantTracklet(40, 69, Vec3(-0.45, 0.0, 1.0));
  const core::Tracklet3D x = ConstantTracklet(40, 69, Vec3(0.05, 0.0, 1.0));
  const LinkResult r = linker.Link(2, {y, x});
  CHECK(r.track_of_tracklet == std::vector<TrackId3D>{3, 1});
  CHECK(r.link_kind == std::vector<LinkKind>{LinkKind::kBirth, LinkKind::kOverlap});
  CHECK(r.link_distance_m[1] == Approx(0.05));
  CHECK(r.born == std::vector<TrackId3D>{3});
  CHECK(FindTrack(linker, 2)->missed_windows == 2);
}

TEST_CASE("Overlap stage minimises the total Eq. 8 cost (Eq. 9), not greedily", "[unit]") {
  // Track 1 at x = 0, track 2 at x = 0.42. New tracklets: u at x = 0.20 (0.20 from track 1,
  // 0.22 from track 2) and v at x = -0.25 (0.25 from track 1, 0.67 from track 2: gated out).
  // Nearest-first (per track or globally) gives u to track 1 and strands track 2; the optimal
  // assignment links 1-v and 2-u (total 0.47).
  WindowLinker linker;
  REQUIRE(linker
              .Link(0,
                    {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0)),
                     ConstantTracklet(0, 29, Vec3(0.42, 0.0, 1.0))})
              .born == std::vector<TrackId3D>{1, 2});
  const LinkResult r = linker.Link(1,
                                   {ConstantTracklet(20, 49, Vec3(0.20, 0.0, 1.0)),
                                    ConstantTracklet(20, 49, Vec3(-0.25, 0.0, 1.0))});
  CHECK(r.track_of_tracklet == std::vector<TrackId3D>{2, 1});
  CHECK(r.link_kind == std::vector<LinkKind>{LinkKind::kOverlap, LinkKind::kOverlap});
  CHECK(r.link_distance_m[0] == Approx(0.22));
  CHECK(r.link_distance_m[1] == Approx(0.25));
  CHECK(r.born.empty());
}

TEST_CASE("Gap stage picks the closest lost track and respects the speed gate", "[unit]") {
  // Two lost tracks, one tracklet between them: the nearer one takes it. A tracklet beyond
  // every gap gate is born.
  WindowLinker linker;
  linker.Link(0,
              {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0)),
               ConstantTracklet(0, 29, Vec3(3.0, 0.0, 1.0))});
  // Window 1: nobody. Window 2 (gap 40 - 29 = 11 frames, gate 0.5 + 0.15 * 11 = 2.15 m).
  linker.Link(1, {});
  const LinkResult r = linker.Link(2,
                                   {ConstantTracklet(40, 69, Vec3(20.0, 0.0, 1.0)),
                                    ConstantTracklet(40, 69, Vec3(1.9, 0.0, 1.0))});
  CHECK(r.track_of_tracklet == std::vector<TrackId3D>{3, 2});
  CHECK(r.link_kind == std::vector<LinkKind>{LinkKind::kBirth, LinkKind::kGap});
  CHECK(r.link_distance_m[1] == Approx(1.1));
  CHECK(FindTrack(linker, 1)->state == TrackState::kLost);
}

TEST_CASE("A tracklet without valid points is born and later linked by others only", "[unit]") {
  WindowLinker linker;
  core::Tracklet3D blank;
  blank.frames = {0, 1, 2};
  blank.points = {{std::nullopt}, {std::nullopt}, {std::nullopt}};
  const LinkResult r0 = linker.Link(0, {blank, ConstantTracklet(0, 29, Vec3(1.0, 1.0, 1.0))});
  CHECK(r0.born == std::vector<TrackId3D>{1, 2});
  const LinkResult r1 = linker.Link(1, {ConstantTracklet(20, 49, Vec3(1.0, 1.0, 1.0)), blank});
  CHECK(r1.track_of_tracklet == std::vector<TrackId3D>{2, 3});
  CHECK(r1.born == std::vector<TrackId3D>{3});
  CHECK(FindTrack(linker, 1)->missed_windows == 1);
}

}  // namespace
}  // namespace mvtrack::linking
