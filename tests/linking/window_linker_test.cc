#include "linking/window_linker.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::linking {
namespace {

// The paper's window geometry: size nu = 30, step delta = 20 (10 overlapping frames), 30 fps.
constexpr std::int64_t kNu = 30;
constexpr std::int64_t kDelta = 20;
constexpr double kSpf = 1.0 / 30.0;

using Trajectory = std::function<Vec3(FrameIndex)>;

// A synthetic person: a ground-truth trajectory of its body centre, the windows in which the
// 3D stage produced a tracklet for it, and the 2D tracks (one per camera 0 and 1) that
// tracklet is built from in a window: by default the same two for the whole run, as when both
// cameras keep tracking the person.
struct Person {
  Trajectory centre;
  std::function<bool(std::int64_t)> present = [](std::int64_t) { return true; };
  std::function<std::vector<TrackId2D>(std::int64_t)> tracks;  // per camera; empty = default
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

// Members (camera c, track tracks[c]) spanning [first, last], sorted by camera.
std::vector<core::TrackletMember> Members(const std::vector<TrackId2D>& tracks,
                                          FrameIndex first,
                                          FrameIndex last) {
  std::vector<core::TrackletMember> m;
  for (std::size_t c = 0; c < tracks.size(); ++c) {
    m.push_back(
        {static_cast<CameraId>(c), tracks[c], first, last, static_cast<int>(last - first + 1)});
  }
  return m;
}

// All 2D tracks of the window as live tracks (sorted by camera, then track).
std::vector<core::TrackletMember> LiveOf(const std::vector<core::Tracklet3D>& tracklets) {
  std::vector<core::TrackletMember> live;
  for (const core::Tracklet3D& t : tracklets)
    live.insert(live.end(), t.members.begin(), t.members.end());
  std::sort(live.begin(), live.end(), [](const auto& a, const auto& b) {
    return a.camera_id != b.camera_id ? a.camera_id < b.camera_id : a.track_id < b.track_id;
  });
  return live;
}

// The short-term tracklet of a trajectory in window k: frames [k*delta, k*delta + nu), every
// joint at its ground-truth position plus independent Gaussian noise.
core::Tracklet3D MakeTracklet(const Trajectory& centre,
                              std::int64_t window,
                              const std::vector<Vec3>& offsets,
                              double noise_sigma_m,
                              std::mt19937* rng,
                              const std::vector<TrackId2D>& tracks) {
  std::normal_distribution<double> noise(0.0, noise_sigma_m);
  core::Tracklet3D tracklet;
  for (FrameIndex t = window * kDelta; t < window * kDelta + kNu; ++t) {
    tracklet.frames.push_back(t);
    std::vector<std::optional<Vec3>> points;
    for (const Vec3& offset : offsets) {
      Vec3 p = centre(t) + offset;
      if (noise_sigma_m > 0.0) {
        for (int axis = 0; axis < 3; ++axis) p[axis] += noise(*rng);  // one draw per statement
      }
      points.emplace_back(p);
    }
    tracklet.points.push_back(std::move(points));
  }
  for (std::size_t c = 0; c < tracks.size(); ++c)
    tracklet.cameras.push_back(static_cast<CameraId>(c));
  tracklet.members = Members(tracks, window * kDelta, window * kDelta + kNu - 1);
  return tracklet;
}

struct SceneWindow {
  std::vector<core::Tracklet3D> tracklets;
  std::vector<int> person_of_tracklet;
};

SceneWindow MakeWindow(const std::vector<Person>& people,
                       std::int64_t window,
                       double noise_sigma_m,
                       std::mt19937* rng) {
  std::vector<int> order;
  for (int p = 0; p < static_cast<int>(people.size()); ++p) {
    if (people[static_cast<std::size_t>(p)].present(window)) order.push_back(p);
  }
  std::shuffle(order.begin(), order.end(), *rng);  // index order carries no identity
  SceneWindow w;
  for (int p : order) {
    const Person& person = people[static_cast<std::size_t>(p)];
    const std::vector<TrackId2D> tracks =
        person.tracks ? person.tracks(window) : std::vector<TrackId2D>{1000 + p, 2000 + p};
    w.tracklets.push_back(
        MakeTracklet(person.centre, window, SkeletonOffsets(), noise_sigma_m, rng, tracks));
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

// A single-point (box mode) tracklet at a fixed place, with members `tracks` (cameras 0, 1, ...).
core::Tracklet3D ConstantTracklet(FrameIndex first,
                                  FrameIndex last,
                                  const Vec3& point,
                                  const std::vector<TrackId2D>& tracks = {1, 2}) {
  core::Tracklet3D tracklet;
  for (FrameIndex t = first; t <= last; ++t) {
    tracklet.frames.push_back(t);
    tracklet.points.push_back({point});
  }
  for (std::size_t c = 0; c < tracks.size(); ++c)
    tracklet.cameras.push_back(static_cast<CameraId>(c));
  tracklet.members = Members(tracks, first, last);
  return tracklet;
}

// A single-point tracklet moving along `centre` over [first, last].
core::Tracklet3D MovingTracklet(FrameIndex first,
                                FrameIndex last,
                                const Trajectory& centre,
                                const std::vector<TrackId2D>& tracks) {
  core::Tracklet3D tracklet = ConstantTracklet(first, last, Vec3::Zero(), tracks);
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    tracklet.points[f][0] = centre(tracklet.frames[f]);
  }
  return tracklet;
}

LinkResult LinkWindow(WindowLinker* linker,
                      std::int64_t k,
                      const std::vector<core::Tracklet3D>& tracklets) {
  return linker->Link(k, k * kDelta, kSpf, tracklets, LiveOf(tracklets));
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
  b.points = {{a0, std::nullopt},                         // 11: only point 0 -> no common point
              {Vec3(a0 + off12_0), Vec3(a1 + off12_1)},   // 12: mean(1, 3) = 2
              {Vec3(nan, 0.0, 0.0), Vec3(a1 + off13_1)},  // 13: NaN point 0 is invalid -> 0.5
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

TEST_CASE("Footprints: the footprint points' mean, else the valid points' mean", "[unit]") {
  const std::vector<std::optional<Vec3>> points = {
      Vec3(0.0, 0.0, 1.0), Vec3(2.0, 0.0, 1.0), std::nullopt, Vec3(4.0, 6.0, 9.0)};
  const std::optional<Vec2> hips = FrameFootprint(points, {0, 1});
  REQUIRE(hips.has_value());
  CHECK(hips->x() == Approx(1.0));
  CHECK(hips->y() == Approx(0.0));
  // A footprint point missing: the mean of the valid points (x, y only).
  const std::optional<Vec2> all = FrameFootprint(points, {0, 2});
  REQUIRE(all.has_value());
  CHECK(all->x() == Approx(2.0));
  CHECK(all->y() == Approx(2.0));
  CHECK(FrameFootprint(points, {}) == all);
  CHECK_FALSE(FrameFootprint({std::nullopt, std::nullopt}, {0}).has_value());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(FrameFootprint({Vec3(nan, 0.0, 0.0)}, {}).has_value());
}

TEST_CASE("Shared members count equal (camera, 2D track) pairs", "[unit]") {
  core::Tracklet3D t;
  t.members = {{0, 5, 0, 9, 10}, {1, 7, 0, 9, 10}, {2, 3, 0, 9, 10}};
  CHECK(SharedMembers({{0, 5, 9}, {1, 8, 9}, {2, 3, 9}}, t) == 2);
  CHECK(SharedMembers({{0, 7, 9}, {1, 5, 9}}, t) == 0);  // same ids, other cameras
  CHECK(SharedMembers({}, t) == 0);
}

TEST_CASE("LinkerOptions::Validate rejects out-of-range settings", "[unit]") {
  std::string why;
  CHECK(LinkerOptions{}.Validate(&why));
  const auto rejects = [](const std::function<void(LinkerOptions*)>& change, const char* name) {
    LinkerOptions o;
    change(&o);
    std::string reason;
    CHECK_FALSE(o.Validate(&reason));
    CHECK(reason.find(name) != std::string::npos);
  };
  rejects([](LinkerOptions* o) { o->max_link_distance_m = 0.0; }, "max_link_distance_m");
  rejects([](LinkerOptions* o) { o->max_link_distance_m = INFINITY; }, "max_link_distance_m");
  rejects([](LinkerOptions* o) { o->duplicate_distance_m = 0.6; }, "duplicate_distance_m");
  rejects([](LinkerOptions* o) { o->duplicate_distance_m = -1.0; }, "duplicate_distance_m");
  rejects([](LinkerOptions* o) { o->min_hits = 0; }, "min_hits");
  rejects([](LinkerOptions* o) { o->strong_birth_cameras = 1; }, "strong_birth_cameras");
  rejects([](LinkerOptions* o) { o->fragment_min_hits = 0; }, "fragment_min_hits");
  rejects([](LinkerOptions* o) { o->isolated_birth_distance_m = -1.0; },
          "isolated_birth_distance_m");
  rejects([](LinkerOptions* o) { o->max_lost_s = NAN; }, "max_lost_s");
  rejects([](LinkerOptions* o) { o->gap_gate_chi2 = 0.0; }, "gap_gate_chi2");
  rejects([](LinkerOptions* o) { o->reid_gate_chi2 = -1.0; }, "reid_gate_chi2");
  rejects([](LinkerOptions* o) { o->reid_margin_chi2 = -1.0; }, "reid_margin_chi2");
  rejects([](LinkerOptions* o) { o->max_reid_gap_s = -0.5; }, "max_reid_gap_s");
  rejects([](LinkerOptions* o) { o->motion.measurement_sigma_m = 0.0; }, "measurement_sigma_m");
  rejects([](LinkerOptions* o) { o->motion.acceleration_sigma_mps2 = -1.0; },
          "acceleration_sigma_mps2");
}

TEST_CASE("Three walking people keep their identities, two passing 0.4 m apart", "[unit]") {
  // A and B walk towards each other on parallel lines 0.4 m apart (0.028 m/frame, ~0.84 m/s)
  // and pass at frame 125, inside the overlap of windows 5 and 6; C walks a circle.
  std::vector<Person> people(3);
  people[0].centre = Straight(Vec3(-3.5, 0.0, 1.0), Vec3(0.028, 0.0, 0.0));
  people[1].centre = Straight(Vec3(3.5, 0.4, 1.0), Vec3(-0.028, 0.0, 0.0));
  people[2].centre = [](FrameIndex t) {
    const double phase = 0.01 * static_cast<double>(t);
    return Vec3(2.0 * std::cos(phase), 3.0 + 2.0 * std::sin(phase), 1.0);
  };
  std::mt19937 rng(20240531);
  WindowLinker linker;
  std::map<int, TrackId3D> id_of_person;
  for (std::int64_t k = 0; k < 12; ++k) {
    const SceneWindow w = MakeWindow(people, k, 0.02, &rng);
    const LinkResult r = LinkWindow(&linker, k, w.tracklets);
    REQUIRE(r.window_id == k);
    REQUIRE(r.track_of_tracklet.size() == w.tracklets.size());
    CHECK(r.died.empty());
    for (std::size_t i = 0; i < w.tracklets.size(); ++i) {
      const int p = w.person_of_tracklet[i];
      if (k == 0) {
        CHECK(r.link_kind[i] == LinkKind::kBirth);
        id_of_person[p] = r.track_of_tracklet[i];
      } else {
        CHECK(r.track_of_tracklet[i] == id_of_person.at(p));
        CHECK(r.link_kind[i] == LinkKind::kOverlap);
        CHECK(r.link_distance_m[i] < 0.1);
        CHECK(r.shared_members[i] == 2);
      }
    }
    REQUIRE(linker.tracks().size() == 3);
    for (const LinkedTrack& t : linker.tracks()) {
      // Two cameras, but at birth nobody within 2 m of anybody: isolated births, confirmed.
      CHECK(t.state == TrackState::kConfirmed);
      CHECK(t.hits == k + 1);
      CHECK(t.members.size() == 2);
    }
  }
  CHECK(id_of_person.size() == 3);
}

TEST_CASE("Shared 2D tracks outweigh Eq. 8: a track keeps the tracklet that continues it",
          "[unit]") {
  WindowLinker linker;
  LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  // Window 1: the person appears twice (split into two clusters): one tracklet continues both
  // 2D tracks 0.2 m off, the other shares one 2D track and lies right on the old track.
  const core::Tracklet3D continues = ConstantTracklet(20, 49, Vec3(0.2, 0.0, 1.0), {1, 2});
  const core::Tracklet3D fragment = ConstantTracklet(20, 49, Vec3(0.0, 0.0, 1.0), {1, 9});
  const LinkResult r = LinkWindow(&linker, 1, {fragment, continues});
  CHECK(r.track_of_tracklet[1] == 1);
  CHECK(r.link_kind[1] == LinkKind::kOverlap);
  // The fragment, 0.2 m from the tracklet track 1 took, is that person seen twice.
  CHECK(r.track_of_tracklet[0] == 1);
  CHECK(r.link_kind[0] == LinkKind::kDuplicate);
  CHECK(r.link_distance_m[0] == Approx(0.2));
  CHECK(r.born.empty());
  // Without duplicate detection it would have been born.
  LinkerOptions no_duplicates;
  no_duplicates.duplicate_distance_m = 0.0;
  WindowLinker plain(no_duplicates);
  LinkWindow(&plain, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  const LinkResult p = LinkWindow(&plain, 1, {fragment, continues});
  CHECK(p.track_of_tracklet[1] == 1);
  CHECK(p.track_of_tracklet[0] == 2);
  CHECK(p.link_kind[0] == LinkKind::kBirth);
}

TEST_CASE("Each shared 2D track is worth max_link_distance_m of Eq. 8 in the gate", "[unit]") {
  // Window 0: track 1 at the origin, seen by three cameras. Window 1: the same 2D tracks, but a
  // view that joined or left moved the triangulation by `offset`.
  const auto link = [](double offset, const std::vector<TrackId2D>& tracks) {
    WindowLinker linker;
    LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2, 3})});
    return LinkWindow(&linker, 1, {ConstantTracklet(20, 49, Vec3(offset, 0.0, 1.0), tracks)});
  };
  // One shared 2D track (the others changed): the plain 0.5 m gate.
  CHECK(link(0.45, {1, 8, 9}).link_kind[0] == LinkKind::kOverlap);
  CHECK(link(0.55, {1, 8, 9}).link_kind[0] == LinkKind::kBirth);
  // Two: 1.0 m; three: 1.5 m.
  CHECK(link(0.9, {1, 2, 9}).link_kind[0] == LinkKind::kOverlap);
  CHECK(link(1.1, {1, 2, 9}).link_kind[0] == LinkKind::kBirth);
  const LinkResult three = link(1.4, {1, 2, 3});
  CHECK(three.link_kind[0] == LinkKind::kOverlap);
  CHECK(three.track_of_tracklet[0] == 1);
  CHECK(three.link_distance_m[0] == Approx(1.4));
  CHECK(link(1.6, {1, 2, 3}).link_kind[0] == LinkKind::kBirth);
}

TEST_CASE("A person seen twice keeps one id: the duplicate's 2D tracks join the track", "[unit]") {
  WindowLinker linker;
  LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  // Window 1: the track continues in {1, 2}; cameras 0 and 1 also have a second pair of 2D
  // tracks {5, 6} on the same person, 0.3 m off (a cannot-link pair, so a second cluster).
  const LinkResult r1 = LinkWindow(&linker,
                                   1,
                                   {ConstantTracklet(20, 49, Vec3(0.0, 0.0, 1.0), {1, 2}),
                                    ConstantTracklet(35, 49, Vec3(0.3, 0.0, 1.0), {5, 6})});
  CHECK(r1.link_kind[1] == LinkKind::kDuplicate);
  CHECK(r1.track_of_tracklet[1] == 1);
  const LinkedTrack* track = FindTrack(linker, 1);
  REQUIRE(track != nullptr);
  CHECK(track->members.size() == 4);
  // Window 2: only the duplicate's 2D tracks continue: the person keeps id 1.
  const LinkResult r2 =
      LinkWindow(&linker, 2, {ConstantTracklet(40, 69, Vec3(0.3, 0.0, 1.0), {5, 6})});
  CHECK(r2.track_of_tracklet[0] == 1);
  CHECK(r2.link_kind[0] == LinkKind::kOverlap);
  // A second person 0.45 m away (beyond the 0.4 m default) is born.
  const LinkResult r3 = LinkWindow(&linker,
                                   3,
                                   {ConstantTracklet(60, 89, Vec3(0.3, 0.0, 1.0), {5, 6}),
                                    ConstantTracklet(60, 89, Vec3(0.75, 0.0, 1.0), {8, 9})});
  CHECK(r3.track_of_tracklet[0] == 1);
  CHECK(r3.link_kind[1] == LinkKind::kBirth);
  CHECK(r3.track_of_tracklet[1] == 2);
  // Two unmatched tracklets are never duplicates of each other: both are born.
  WindowLinker fresh;
  const LinkResult b = LinkWindow(&fresh,
                                  0,
                                  {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2}),
                                   ConstantTracklet(0, 29, Vec3(0.1, 0.0, 1.0), {3, 4})});
  CHECK(b.born.size() == 2);
}

TEST_CASE("A duplicate is judged on the median over common frames, not the mean", "[unit]") {
  // Window 1: the track continues in {1, 2}; a second tracklet {5, 6} on the same person,
  // 0.1 m off in 12 of its 15 frames and 2.5 m off in 3 (triangulated from a wrong view):
  // mean 0.58 m (beyond the 0.4 m gate), median 0.1 m -> the person seen twice.
  WindowLinker linker;
  LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  core::Tracklet3D twice = ConstantTracklet(35, 49, Vec3(0.1, 0.0, 1.0), {5, 6});
  for (std::size_t f = 12; f < 15; ++f) twice.points[f][0] = Vec3(2.6, 0.0, 1.0);
  const core::Tracklet3D track = ConstantTracklet(20, 49, Vec3(0.0, 0.0, 1.0), {1, 2});
  REQUIRE(MeanOverlapDistance(track, twice).value() > 0.4);
  const LinkResult r = LinkWindow(&linker, 1, {track, twice});
  CHECK(r.link_kind[1] == LinkKind::kDuplicate);
  CHECK(r.track_of_tracklet[1] == 1);
  CHECK(r.link_distance_m[1] == Approx(0.1));
  // A second person 0.45 m away who comes within 0.05 m in 3 of 15 frames (a crossing) has
  // median 0.45 m: born.
  WindowLinker other;
  LinkWindow(&other, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  core::Tracklet3D passer = ConstantTracklet(35, 49, Vec3(0.45, 0.0, 1.0), {5, 6});
  for (std::size_t f = 6; f < 9; ++f) passer.points[f][0] = Vec3(0.05, 0.0, 1.0);
  const LinkResult b = LinkWindow(&other, 1, {track, passer});
  CHECK(b.link_kind[1] == LinkKind::kBirth);
  CHECK(b.track_of_tracklet[1] == 2);
}

TEST_CASE("Overlap without a shared 2D track: a new candidate", "[unit]") {
  // Window 0: track 1 at the origin with 2D tracks {1, 2}. Window 1: a tracklet 0.1 m away
  // whose 2D tracks all changed: no 2D track ties it to the track, so it is a new candidate
  // (the stage that linked such tracklets within 0.25 m changed no output on any benchmark and
  // was removed, issue 38), even when nobody continues the old 2D tracks.
  WindowLinker linker;
  LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  const LinkResult r =
      LinkWindow(&linker, 1, {ConstantTracklet(20, 49, Vec3(0.1, 0.0, 1.0), {7, 8})});
  CHECK(r.link_kind[0] == LinkKind::kBirth);
  CHECK(r.track_of_tracklet[0] == 2);
  CHECK(r.shared_members[0] == 0);
  // The same tracklet with one of the old 2D tracks is the old person.
  WindowLinker other;
  LinkWindow(&other, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  const LinkResult s =
      LinkWindow(&other, 1, {ConstantTracklet(20, 49, Vec3(0.1, 0.0, 1.0), {1, 8})});
  CHECK(s.link_kind[0] == LinkKind::kOverlap);
  CHECK(s.track_of_tracklet[0] == 1);
}

TEST_CASE("A gap is bridged by a 2D track that continued, within the motion gate", "[unit]") {
  // A person walks at 1.2 m/s along x; window 1 has no 3D tracklet for them (one camera only),
  // but camera 0's 2D track 1 stays alive; window 2 brings it back with a new camera 1 track.
  const Trajectory walk = Straight(Vec3(0.0, 0.0, 1.0), Vec3(0.04, 0.0, 0.0));
  WindowLinker linker;
  LinkWindow(&linker, 0, {MovingTracklet(0, 29, walk, {1, 2})});
  const std::vector<core::TrackletMember> alive = {{0, 1, 20, 49, 30}};
  LinkResult r1 = linker.Link(1, 20, kSpf, {}, alive);
  CHECK(r1.died.empty());
  REQUIRE(FindTrack(linker, 1) != nullptr);
  CHECK(FindTrack(linker, 1)->state == TrackState::kLost);
  // Window 2 starts at 40; the tracklet only from frame 45 on (no overlap with frames <= 29).
  const LinkResult r2 = LinkWindow(&linker, 2, {MovingTracklet(45, 69, walk, {1, 5})});
  CHECK(r2.track_of_tracklet[0] == 1);
  CHECK(r2.link_kind[0] == LinkKind::kGap);
  CHECK(r2.shared_members[0] == 1);
  CHECK(r2.link_distance_m[0] < 3.0);  // the chi-square test statistic of a good continuation
  CHECK(FindTrack(linker, 1)->state == TrackState::kConfirmed);

  // The same, but the tracklet that comes back is 3 m away from where the person could be:
  // a 2D track that jumped to somebody else. Born, and the old track waits.
  WindowLinker other;
  LinkWindow(&other, 0, {MovingTracklet(0, 29, walk, {1, 2})});
  other.Link(1, 20, kSpf, {}, alive);
  const Trajectory elsewhere = Straight(Vec3(0.0, 3.0, 1.0), Vec3(0.04, 0.0, 0.0));
  const LinkResult r3 = LinkWindow(&other, 2, {MovingTracklet(45, 69, elsewhere, {1, 5})});
  CHECK(r3.link_kind[0] == LinkKind::kBirth);
  CHECK(r3.track_of_tracklet[0] == 2);
  REQUIRE(FindTrack(other, 1) != nullptr);
}

TEST_CASE("The motion gate grows with the gap in seconds, not frames", "[unit]") {
  // After a gap of 5 frames the person is 1.5 m further than a constant-velocity prediction:
  // impossible in 0.17 s at 30 fps, plausible in 2.5 s at 2 fps.
  const auto run = [&](double spf) {
    const double v = 1.2 * spf;  // 1.2 m/s in metres per frame
    const Trajectory walk = Straight(Vec3(0.0, 0.0, 1.0), Vec3(v, 0.0, 0.0));
    WindowLinker linker;
    const core::Tracklet3D first = MovingTracklet(0, 29, walk, {1, 2});
    linker.Link(0, 0, spf, {first}, LiveOf({first}));
    const Trajectory later = [&](FrameIndex t) { return Vec3(walk(t) + Vec3(1.5, 0.0, 0.0)); };
    const core::Tracklet3D back = MovingTracklet(34, 49, later, {1, 3});
    return linker.Link(1, 20, spf, {back}, LiveOf({back})).link_kind[0];
  };
  CHECK(run(1.0 / 30.0) == LinkKind::kBirth);
  CHECK(run(0.5) == LinkKind::kGap);
}

TEST_CASE("A lost track ends when none of its 2D tracks continues, or after max_lost_s", "[unit]") {
  WindowLinker linker;
  LinkWindow(&linker, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  // Window 1: nobody in 3D, camera 1's track 2 still alive.
  LinkResult r = linker.Link(1, 20, kSpf, {}, {{1, 2, 20, 49, 30}});
  CHECK(r.died.empty());
  // Window 2: no 2D track of it left (the person walked out of every camera's view).
  r = linker.Link(2, 40, kSpf, {}, {{0, 77, 40, 69, 30}});
  CHECK(r.died == std::vector<TrackId3D>{1});
  REQUIRE(r.died_reason.size() == 1);
  CHECK(r.died_reason[0] == EndReason::kLeftView);
  CHECK(linker.tracks().empty());
  // Whoever appears there next is somebody new.
  r = LinkWindow(&linker, 3, {ConstantTracklet(60, 89, Vec3(0.0, 0.0, 1.0), {5, 6})});
  CHECK(r.track_of_tracklet[0] == 2);

  // With a 2D track alive, the track still ends max_lost_s after its last footprint.
  LinkerOptions o;
  o.max_lost_s = 2.0;
  WindowLinker waiting(o);
  LinkWindow(&waiting, 0, {ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2})});
  const std::vector<core::TrackletMember> alive = {{0, 1, 0, 100, 100}};
  for (std::int64_t k = 1; k <= 4; ++k) {
    r = waiting.Link(k, k * kDelta, kSpf, {}, alive);
    CHECK(r.died.empty());  // window 4 starts 51 frames (1.7 s) after the last footprint (29)
  }
  r = waiting.Link(5, 5 * kDelta, kSpf, {}, alive);  // 71 frames: 2.37 s
  CHECK(r.died == std::vector<TrackId3D>{1});
  CHECK(r.died_reason[0] == EndReason::kLostTooLong);
}

TEST_CASE("Weak births wait for a second window, strong ones are confirmed at once", "[unit]") {
  WindowLinker linker;
  // Two cameras 1.2 m from another person: weak (possibly a duplicate split off that person).
  // Three cameras: strong. Two cameras, 4.8 m from anybody: strong (isolated).
  core::Tracklet3D weak = ConstantTracklet(26, 29, Vec3(0.0, 0.0, 1.0), {1, 2});
  const core::Tracklet3D three = ConstantTracklet(26, 29, Vec3(1.2, 0.0, 1.0), {1, 2, 3});
  const core::Tracklet3D isolated = ConstantTracklet(0, 29, Vec3(6.0, 0.0, 1.0), {4, 5});
  LinkWindow(&linker, 0, {weak, three, isolated});
  CHECK(FindTrack(linker, 1)->state == TrackState::kTentative);
  CHECK(FindTrack(linker, 2)->state == TrackState::kConfirmed);
  CHECK(FindTrack(linker, 3)->state == TrackState::kConfirmed);
  // Linked again: confirmed (min_hits 2).
  LinkWindow(&linker, 1, {ConstantTracklet(20, 49, Vec3(0.0, 0.0, 1.0), {1, 2})});
  CHECK(FindTrack(linker, 1)->state == TrackState::kConfirmed);
  CHECK(FindTrack(linker, 1)->hits == 2);

  LinkerOptions o;
  o.isolated_birth_distance_m = 0.0;  // the camera rule only
  WindowLinker strict(o);
  LinkWindow(&strict, 0, {isolated});
  CHECK(strict.tracks().front().state == TrackState::kTentative);
  o.min_hits = 1;  // every birth is output at once
  WindowLinker eager(o);
  LinkWindow(&eager, 0, {weak});
  CHECK(eager.tracks().front().state == TrackState::kConfirmed);
}

TEST_CASE("A birth that carries a 2D track of an alive track waits unless isolated", "[unit]") {
  // Track 1: three cameras (camera c, 2D track tracks[c]). In window 1 its person continues on
  // two of its 2D tracks; a three-camera tracklet 1 m away carries its third (camera 0,
  // track 1): a piece of a tracked person, born tentative. 5 m away it is isolated: confirmed.
  // (Window k starts at frame 20 k.)
  const core::Tracklet3D first = ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2, 3});
  const core::Tracklet3D next = ConstantTracklet(20, 49, Vec3(0.0, 0.0, 1.0), {5, 2, 3});
  const core::Tracklet3D piece = ConstantTracklet(40, 49, Vec3(1.0, 0.0, 1.0), {1, 8, 9});
  const core::Tracklet3D far = ConstantTracklet(40, 49, Vec3(5.0, 0.0, 1.0), {1, 8, 9});
  const auto born_state = [&](const LinkerOptions& o, const core::Tracklet3D& other) {
    WindowLinker linker(o);
    LinkWindow(&linker, 0, {first});
    const LinkResult r = LinkWindow(&linker, 1, {next, other});
    REQUIRE(r.track_of_tracklet[0] == 1);
    REQUIRE(r.link_kind[1] == LinkKind::kBirth);
    REQUIRE(r.shared_members[0] == 2);
    return FindTrack(linker, r.track_of_tracklet[1])->state;
  };
  LinkerOptions o;
  CHECK(born_state(o, piece) == TrackState::kTentative);
  CHECK(born_state(o, far) == TrackState::kConfirmed);
  o.fragment_births_wait = false;  // the camera rule alone
  CHECK(born_state(o, piece) == TrackState::kConfirmed);

  // Appearance on and a descriptor, the piece linked again is confirmed in its
  // fragment_min_hits-th (3rd) window (it may still be re-identified meanwhile); appearance off
  // or no descriptor, in its min_hits-th (2nd).
  const auto looking = [](core::Tracklet3D t, int axis) {
    t.appearance.assign(8, 0.0f);
    t.appearance[static_cast<std::size_t>(axis)] = 1.0f;
    t.appearance_count = 40;
    return t;
  };
  for (const auto& [appearance, descriptors] :
       {std::pair{true, true}, std::pair{true, false}, std::pair{false, true}}) {
    core::AppearanceOptions ao;
    ao.enabled = appearance;
    const auto seen = [&](const core::Tracklet3D& t, int axis) {
      return descriptors ? looking(t, axis) : t;
    };
    WindowLinker linker(LinkerOptions{}, LinkerContext{}, ao);
    LinkWindow(&linker, 0, {seen(first, 0)});
    const LinkResult born = LinkWindow(&linker, 1, {seen(next, 0), seen(piece, 1)});
    const TrackId3D id = born.track_of_tracklet[1];
    for (std::int64_t k = 2; k <= 3; ++k) {
      const FrameIndex from = 20 * k;
      const LinkResult r =
          LinkWindow(&linker,
                     k,
                     {seen(ConstantTracklet(from, from + 29, Vec3(0.0, 0.0, 1.0), {5, 2, 3}), 0),
                      seen(ConstantTracklet(from, from + 29, Vec3(1.0, 0.0, 1.0), {1, 8, 9}), 1)});
      REQUIRE(r.track_of_tracklet[1] == id);
      CHECK(FindTrack(linker, id)->hits == k);
      const int needed = appearance && descriptors ? 3 : 2;
      CHECK(FindTrack(linker, id)->state ==
            (k < needed ? TrackState::kTentative : TrackState::kConfirmed));
    }
  }
}

TEST_CASE("Re-identification by motion alone is off by default, when on, only unambiguous",
          "[unit]") {
  // Track 1 walks at 1.2 m/s and vanishes (every 2D track lost) after frame 29; a tracklet with
  // new 2D tracks appears on its predicted path after a 16-frame gap.
  const Trajectory walk = Straight(Vec3(0.0, 0.0, 1.0), Vec3(0.04, 0.0, 0.0));
  const core::Tracklet3D first = MovingTracklet(0, 29, walk, {1, 2});
  const core::Tracklet3D back = MovingTracklet(46, 69, walk, {7, 8});
  {
    WindowLinker linker;
    linker.Link(0, 0, kSpf, {first}, LiveOf({first}));
    const LinkResult r = linker.Link(1, 40, kSpf, {back}, LiveOf({back}));
    CHECK(r.link_kind[0] == LinkKind::kBirth);
    // No 2D track of track 1 continues and nothing can re-identify it: it ends before the
    // next window is linked.
    const LinkResult r2 = linker.Link(2, 60, kSpf, {}, LiveOf({back}));
    CHECK(r2.died == std::vector<TrackId3D>{1});
  }
  LinkerOptions o;
  o.reid_gate_chi2 = 9.49;
  {
    WindowLinker linker(o);
    linker.Link(0, 0, kSpf, {first}, LiveOf({first}));
    const LinkResult r = linker.Link(1, 40, kSpf, {back}, LiveOf({back}));
    CHECK(r.link_kind[0] == LinkKind::kReidentified);
    CHECK(r.track_of_tracklet[0] == 1);
  }
  {
    // Two tracklets on the path, 0.1 m apart: ambiguous, both born.
    const core::Tracklet3D twin = MovingTracklet(
        46, 69, [&](FrameIndex t) { return Vec3(walk(t) + Vec3(0.0, 0.1, 0.0)); }, {9, 10});
    WindowLinker linker(o);
    linker.Link(0, 0, kSpf, {first}, LiveOf({first}));
    const LinkResult r = linker.Link(1, 40, kSpf, {back, twin}, LiveOf({back, twin}));
    CHECK(r.link_kind[0] == LinkKind::kBirth);
    CHECK(r.link_kind[1] == LinkKind::kBirth);
  }
}

TEST_CASE("Skipped window ids count as missed windows, the stream end ends every track", "[unit]") {
  WindowLinker linker;
  const core::Tracklet3D a = ConstantTracklet(0, 29, Vec3(0.0, 0.0, 1.0), {1, 2});
  LinkWindow(&linker, 0, {a});
  linker.Link(3, 60, kSpf, {}, {{0, 1, 60, 89, 30}});  // windows 1, 2 skipped
  REQUIRE(FindTrack(linker, 1) != nullptr);
  CHECK(FindTrack(linker, 1)->missed_windows == 3);
  const std::vector<EndedTrack> ended = linker.EndStream();
  REQUIRE(ended.size() == 1);
  CHECK(ended[0].id == 1);
  CHECK(ended[0].reason == EndReason::kStreamEnd);
  CHECK(linker.tracks().empty());
  // Ids continue after the stream end.
  const LinkResult r = LinkWindow(&linker, 4, {a});
  CHECK(r.born == std::vector<TrackId3D>{2});
}

TEST_CASE("A tracklet without valid points is born and later linked by others only", "[unit]") {
  WindowLinker linker;
  core::Tracklet3D blank;
  blank.frames = {0, 1, 2};
  blank.points = {{std::nullopt}, {std::nullopt}, {std::nullopt}};
  const LinkResult r0 =
      LinkWindow(&linker, 0, {blank, ConstantTracklet(0, 29, Vec3(1.0, 1.0, 1.0))});
  CHECK(r0.born == std::vector<TrackId3D>{1, 2});
  const LinkResult r1 =
      LinkWindow(&linker, 1, {ConstantTracklet(20, 49, Vec3(1.0, 1.0, 1.0)), blank});
  CHECK(r1.track_of_tracklet == std::vector<TrackId3D>{2, 3});
  CHECK(r1.born == std::vector<TrackId3D>{3});
  // The blank track has no footprint to wait at: it ends before the next window is linked.
  const LinkResult r2 = LinkWindow(&linker, 2, {ConstantTracklet(40, 69, Vec3(1.0, 1.0, 1.0))});
  CHECK(std::find(r2.died.begin(), r2.died.end(), 1) != r2.died.end());
}

}  // namespace
}  // namespace mvtrack::linking

namespace mvtrack::linking {
namespace {

// A unit appearance vector along axis `k` of 8, tilted by `tilt` towards axis 7.
std::vector<float> Look(int k, double tilt = 0.0) {
  std::vector<float> v(8, 0.0f);
  v[static_cast<std::size_t>(k)] = static_cast<float>(std::cos(tilt));
  v[7] += static_cast<float>(std::sin(tilt));
  return v;
}

core::Tracklet3D Looking(core::Tracklet3D t, const std::vector<float>& look) {
  t.appearance = look;
  t.appearance_count = 40;
  return t;
}

core::AppearanceOptions AppearanceOn() {
  core::AppearanceOptions a;
  a.enabled = true;
  return a;
}

core::AppearanceOptions AppearanceOff() {
  core::AppearanceOptions a;
  a.enabled = false;
  return a;
}

// Person A walks in windows 0-1 and leaves every view; `back` comes at window `k` (~13 s
// later at 20 frames per window) with tracks {tracks}.
TEST_CASE("Appearance: a person who left comes back with the old id", "[unit]") {
  WindowLinker linker({}, {}, AppearanceOn());
  const Vec3 at(1.0, 1.0, 1.0);
  LinkResult r = LinkWindow(&linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0))});
  REQUIRE(r.track_of_tracklet[0] == 1);
  LinkWindow(&linker, 1, {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0, 0.1))});
  // Gone from every view: lost in window 2, ended (and remembered) in window 3.
  r = linker.Link(2, 40, kSpf, {}, {});
  CHECK(r.died.empty());
  r = linker.Link(3, 60, kSpf, {}, {});
  CHECK(r.died == std::vector<TrackId3D>{1});
  REQUIRE(linker.departed().size() == 1);
  CHECK(linker.departed()[0].gallery.size() == 2);
  CHECK(linker.gallery_bytes() == 2 * 8 * sizeof(float));
  for (std::int64_t k = 4; k < 20; ++k) linker.Link(k, k * kDelta, kSpf, {}, {});
  // Back 3 m away after about 12 s, new 2D tracks, the same look (slightly different view);
  // and a stranger entering in the same window.
  r = LinkWindow(&linker,
                 20,
                 {Looking(ConstantTracklet(400, 429, Vec3(4.0, 1.0, 1.0), {7, 8}), Look(3)),
                  Looking(ConstantTracklet(400, 429, Vec3(1.0, 4.0, 1.0), {5, 6}), Look(0, 0.3))});
  CHECK(r.track_of_tracklet[1] == 1);
  CHECK(r.link_kind[1] == LinkKind::kAppearance);
  CHECK(r.link_distance_m[1] < 0.1);
  CHECK(r.revived == std::vector<TrackId3D>{1});
  CHECK(r.track_of_tracklet[0] == 2);
  CHECK(r.link_kind[0] == LinkKind::kBirth);
  const LinkedTrack* back = FindTrack(linker, 1);
  REQUIRE(back != nullptr);
  CHECK(back->confirmed);
  CHECK(back->gallery.size() == 3);
  CHECK(linker.departed().empty());
}

// A comes back as a weak birth (two cameras, 1.2 m from B who is seen by three): with
// defer_weak_reid it is born tentative (not output) and re-identified when linked again; the
// tentative track ends. Without, it is re-identified at birth.
TEST_CASE("Appearance: a weak birth is re-identified when its track is linked again", "[unit]") {
  const Vec3 at(1.0, 1.0, 1.0);
  const Vec3 b_at(2.2, 1.0, 1.0);
  for (const bool defer : {true, false}) {
    core::AppearanceOptions a = AppearanceOn();
    a.defer_weak_reid = defer;
    REQUIRE(core::AppearanceOptions{}.defer_weak_reid);  // the default
    WindowLinker linker({}, {}, a);
    LinkWindow(&linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0))});
    LinkWindow(&linker, 1, {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0))});
    linker.Link(2, 40, kSpf, {}, {});
    linker.Link(3, 60, kSpf, {}, {});
    REQUIRE(linker.departed().size() == 1);
    for (std::int64_t k = 4; k < 20; ++k) linker.Link(k, k * kDelta, kSpf, {}, {});
    const auto window = [&](std::int64_t k) {
      const FrameIndex first = k * kDelta;
      return LinkWindow(
          &linker,
          k,
          {Looking(ConstantTracklet(first, first + 29, at, {7, 8}), Look(0, 0.1)),
           Looking(ConstantTracklet(first, first + 29, b_at, {11, 12, 13}), Look(4))});
    };
    LinkResult r = window(20);
    CHECK(r.track_of_tracklet[1] == (defer ? 3 : 2));  // B: a strong birth, a new person
    if (!defer) {
      CHECK(r.track_of_tracklet[0] == 1);
      CHECK(r.link_kind[0] == LinkKind::kAppearance);
      CHECK(r.revived == std::vector<TrackId3D>{1});
      continue;
    }
    CHECK(r.link_kind[0] == LinkKind::kBirth);
    CHECK(r.track_of_tracklet[0] == 2);
    CHECK(FindTrack(linker, 2)->state == TrackState::kTentative);
    r = window(21);
    CHECK(r.track_of_tracklet[0] == 1);
    CHECK(r.link_kind[0] == LinkKind::kAppearance);
    CHECK(r.revived == std::vector<TrackId3D>{1});
    CHECK(r.track_of_tracklet[1] == 3);
    CHECK(r.died == std::vector<TrackId3D>{2});
    CHECK(r.died_reason == std::vector<EndReason>{EndReason::kReidentified});
    CHECK(FindTrack(linker, 2) == nullptr);
    REQUIRE(FindTrack(linker, 1) != nullptr);
    CHECK(FindTrack(linker, 1)->confirmed);
    CHECK(linker.departed().empty());
    // The revived track goes on by its 2D tracks.
    r = window(22);
    CHECK(r.track_of_tracklet[0] == 1);
    CHECK(r.link_kind[0] == LinkKind::kOverlap);
  }
}

TEST_CASE("Appearance: ambiguous, too far, too fast or off means a new id", "[unit]") {
  const Vec3 at(1.0, 1.0, 1.0);
  // Two people leave who look alike; one comes back: ambiguous.
  {
    WindowLinker linker({}, {}, AppearanceOn());
    LinkWindow(&linker,
               0,
               {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0)),
                Looking(ConstantTracklet(0, 29, Vec3(3.0, 1.0, 1.0), {3, 4}), Look(0, 0.2))});
    LinkWindow(&linker,
               1,
               {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0)),
                Looking(ConstantTracklet(20, 49, Vec3(3.0, 1.0, 1.0), {3, 4}), Look(0, 0.2))});
    linker.Link(2, 40, kSpf, {}, {});
    linker.Link(3, 60, kSpf, {}, {});
    REQUIRE(linker.departed().size() == 2);
    for (std::int64_t k = 4; k < 20; ++k) linker.Link(k, k * kDelta, kSpf, {}, {});
    const LinkResult r =
        LinkWindow(&linker, 20, {Looking(ConstantTracklet(400, 429, at, {7, 8}), Look(0, 0.1))});
    CHECK(r.link_kind[0] == LinkKind::kBirth);
    CHECK(r.track_of_tracklet[0] == 3);
  }
  // Someone else (distance > reid_max_distance); then the person, but from 30 m away after
  // 2 s (faster than kMaxReidSpeedMps).
  {
    WindowLinker linker({}, {}, AppearanceOn());
    LinkWindow(&linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0))});
    LinkWindow(&linker, 1, {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0))});
    linker.Link(2, 40, kSpf, {}, {});
    LinkResult r =
        LinkWindow(&linker, 4, {Looking(ConstantTracklet(80, 109, at, {7, 8}), Look(0, 0.9))});
    CHECK(r.link_kind[0] == LinkKind::kBirth);
    r = LinkWindow(
        &linker, 5, {Looking(ConstantTracklet(100, 129, Vec3(31.0, 1.0, 1.0), {9, 10}), Look(0))});
    CHECK(r.link_kind[0] == LinkKind::kBirth);
  }
  // Appearance off: the same inputs never revive anybody, and nothing is remembered.
  {
    WindowLinker linker({}, {}, AppearanceOff());
    LinkWindow(&linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0))});
    LinkWindow(&linker, 1, {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0))});
    linker.Link(2, 40, kSpf, {}, {});
    CHECK(linker.departed().empty());
    const LinkResult r =
        LinkWindow(&linker, 20, {Looking(ConstantTracklet(400, 429, at, {7, 8}), Look(0))});
    CHECK(r.track_of_tracklet[0] == 2);
  }
}

TEST_CASE("Appearance: departed tracks are bounded in number and in time", "[unit]") {
  core::AppearanceOptions a = AppearanceOn();
  a.max_departed = 2;
  a.max_reid_s = 5.0;
  a.gallery_size = 1;
  WindowLinker linker({}, {}, a);
  // Three people, each seen in one confirmed stretch and leaving.
  std::int64_t k = 0;
  for (int p = 0; p < 3; ++p, k += 3) {
    const Vec3 at(static_cast<double>(p), 0.0, 1.0);
    const TrackId2D t = 10 * (p + 1);
    LinkWindow(&linker,
               k,
               {Looking(ConstantTracklet(k * kDelta, k * kDelta + 29, at, {t, t + 1}), Look(p))});
    LinkWindow(&linker,
               k + 1,
               {Looking(ConstantTracklet((k + 1) * kDelta, (k + 1) * kDelta + 29, at, {t, t + 1}),
                        Look(p))});
    linker.Link(k + 2, (k + 2) * kDelta, kSpf, {}, {});
  }
  linker.Link(k, k * kDelta, kSpf, {}, {});  // the last one ends
  ++k;
  REQUIRE(linker.departed().size() == 2);  // the oldest was forgotten
  CHECK(linker.departed()[0].id == 2);
  CHECK(linker.departed()[1].id == 3);
  CHECK(linker.departed()[0].gallery.size() == 1);  // gallery_size
  // 5 s later every one of them is forgotten.
  for (std::int64_t w = k; w < k + 10; ++w) linker.Link(w, w * kDelta, kSpf, {}, {});
  CHECK(linker.departed().empty());
  CHECK(linker.gallery_bytes() == 0);
}

TEST_CASE("A person whose cluster splits in time within a window keeps one id", "[unit]") {
  // Window 1: the track continues in {1, 2} until frame 34; from frame 39 (5 frames = 0.17 s
  // later) the person is seen by 2D tracks {5, 6} only, 0.3 m on (within 0.5 m + 3 m/s x the
  // gap) and looking alike: the same person, a duplicate, not a birth.
  const auto alike = Look(0, 0.1);
  const auto at = [](FrameIndex first,
                     FrameIndex last,
                     double x,
                     std::vector<TrackId2D> tracks,
                     const std::vector<float>& look) {
    return Looking(ConstantTracklet(first, last, Vec3(x, 0.0, 1.0), std::move(tracks)), look);
  };
  const core::Tracklet3D head = at(20, 34, 0.0, {1, 2}, Look(0));
  const auto run = [&](WindowLinker* linker, const core::Tracklet3D& piece) {
    LinkWindow(linker, 0, {at(0, 29, 0.0, {1, 2}, Look(0))});
    return LinkWindow(linker, 1, {head, piece});
  };
  REQUIRE(LinkerOptions{}.duplicate_max_gap_s == 0.5);  // the default
  WindowLinker linker({}, {}, AppearanceOn());
  const LinkResult r = run(&linker, at(39, 49, 0.3, {5, 6}, alike));
  CHECK(r.link_kind[1] == LinkKind::kDuplicate);
  CHECK(r.track_of_tracklet[1] == 1);
  CHECK(r.link_distance_m[1] == Approx(0.3));
  CHECK(r.born.empty());
  REQUIRE(FindTrack(linker, 1) != nullptr);
  CHECK(FindTrack(linker, 1)->members.size() == 4);
  // Window 2: only {5, 6} continue: the person keeps id 1 (the gap stage, a shared 2D track).
  const LinkResult r2 = LinkWindow(&linker, 2, {at(40, 69, 0.3, {5, 6}, alike)});
  CHECK(r2.track_of_tracklet[0] == 1);
  // The piece may also come first: it ends before the linked tracklet begins.
  WindowLinker before({}, {}, AppearanceOn());
  LinkWindow(&before, 0, {at(0, 29, 0.0, {1, 2}, Look(0))});
  const LinkResult b =
      LinkWindow(&before, 1, {at(38, 49, 0.0, {1, 2}, Look(0)), at(30, 34, 0.3, {5, 6}, alike)});
  CHECK(b.link_kind[1] == LinkKind::kDuplicate);
  CHECK(b.track_of_tracklet[1] == 1);
  // Born: a piece 0.6 s after the end (beyond 0.5 s), one out of walking reach (1.5 m in
  // 0.17 s), one that overlaps the linked tracklet farther than duplicate_distance_m.
  WindowLinker late({}, {}, AppearanceOn());
  CHECK(run(&late, at(53, 60, 0.3, {5, 6}, alike)).born.size() == 1);
  WindowLinker far({}, {}, AppearanceOn());
  CHECK(run(&far, at(39, 49, 1.5, {5, 6}, alike)).born.size() == 1);
  WindowLinker beside({}, {}, AppearanceOn());
  CHECK(run(&beside, at(30, 49, 0.6, {5, 6}, alike)).born.size() == 1);
  // Off.
  LinkerOptions off;
  off.duplicate_max_gap_s = 0.0;
  WindowLinker plain(off, {}, AppearanceOn());
  CHECK(run(&plain, at(39, 49, 0.3, {5, 6}, alike)).born.size() == 1);
  // Only the look can vouch for a piece no 2D track ties to the track: appearance off, or a
  // piece without a descriptor, is born.
  WindowLinker blind({}, {}, AppearanceOff());
  CHECK(run(&blind, at(39, 49, 0.3, {5, 6}, alike)).born.size() == 1);
  WindowLinker faceless({}, {}, AppearanceOn());
  CHECK(run(&faceless, ConstantTracklet(39, 49, Vec3(0.3, 0.0, 1.0), {5, 6})).born.size() == 1);
  // A piece that looks like somebody else is born.
  WindowLinker stranger({}, {}, AppearanceOn());
  CHECK(run(&stranger, at(39, 49, 0.3, {5, 6}, Look(3))).born.size() == 1);
  // Cosine distance 1 - cos(0.8) = 0.30: no veto (link_max_distance 0.4), but not the look of
  // a re-identification (reid_max_distance 0.2) either.
  REQUIRE(core::CosineDistance(Look(0), Look(0, 0.8)) == Approx(0.3033).epsilon(1e-3));
  WindowLinker unsure({}, {}, AppearanceOn());
  CHECK(run(&unsure, at(39, 49, 0.3, {5, 6}, Look(0, 0.8))).born.size() == 1);
}

// Window 1 gives a second person 0.45 m from track 1 (born: beyond the duplicate gate); in
// window 2 that track's tracklet comes within 0.3 m of track 1's: one person linked twice.
TEST_CASE("One person linked twice: the younger track ends, its tracklet a duplicate", "[unit]") {
  const auto run =
      [](WindowLinker* linker, const std::vector<float>& look_1, const std::vector<float>& look_2) {
        const Vec3 at(0.0, 0.0, 1.0);
        LinkWindow(linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), look_1)});
        const LinkResult r1 =
            LinkWindow(linker,
                       1,
                       {Looking(ConstantTracklet(20, 49, at, {1, 2}), look_1),
                        Looking(ConstantTracklet(35, 49, Vec3(0.45, 0.0, 1.0), {5, 6}), look_2)});
        REQUIRE(r1.born == std::vector<TrackId3D>{2});
        return LinkWindow(linker,
                          2,
                          {Looking(ConstantTracklet(40, 69, at, {1, 2}), look_1),
                           Looking(ConstantTracklet(40, 69, Vec3(0.3, 0.0, 1.0), {5, 6}), look_2)});
      };
  REQUIRE(LinkerOptions{}.merge_linked_duplicates);  // the default
  WindowLinker linker;
  const LinkResult r = run(&linker, {}, {});
  CHECK(r.track_of_tracklet == std::vector<TrackId3D>{1, 1});
  CHECK(r.link_kind[0] == LinkKind::kOverlap);
  CHECK(r.link_kind[1] == LinkKind::kDuplicate);
  CHECK(r.link_distance_m[1] == Approx(0.3));
  CHECK(r.died == std::vector<TrackId3D>{2});
  CHECK(r.died_reason == std::vector<EndReason>{EndReason::kDuplicate});
  REQUIRE(FindTrack(linker, 1) != nullptr);
  CHECK(FindTrack(linker, 1)->members.size() == 4);
  CHECK(FindTrack(linker, 2) == nullptr);
  // Off: each track keeps its tracklet.
  LinkerOptions off;
  off.merge_linked_duplicates = false;
  WindowLinker plain(off);
  const LinkResult p = run(&plain, {}, {});
  CHECK(p.track_of_tracklet == std::vector<TrackId3D>{1, 2});
  CHECK(p.died.empty());
  // Appearance on: two people who look different stay two, two who look alike are merged.
  WindowLinker strangers({}, {}, AppearanceOn());
  const LinkResult s = run(&strangers, Look(0), Look(3));
  CHECK(s.track_of_tracklet == std::vector<TrackId3D>{1, 2});
  CHECK(s.died.empty());
  WindowLinker same({}, {}, AppearanceOn());
  const LinkResult m = run(&same, Look(0), Look(0, 0.1));
  CHECK(m.track_of_tracklet == std::vector<TrackId3D>{1, 1});
  CHECK(m.died == std::vector<TrackId3D>{2});
}

// The tracklet of one camera (camera 0, 2D track `track`) along `centre` over [first, last]:
// what a window holds for a person no camera pair places (WindowResult::monocular).
core::Tracklet3D Monocular(FrameIndex first,
                           FrameIndex last,
                           const Trajectory& centre,
                           TrackId2D track) {
  core::Tracklet3D t = MovingTracklet(first, last, centre, {track});
  REQUIRE(t.cameras == std::vector<CameraId>{0});
  return t;
}

TEST_CASE("Monocular continuation: a lost track goes on where one camera still sees the person",
          "[unit]") {
  // A person walks at 1.2 m/s; in windows 1 and 2 only camera 0 (2D track 1) sees them.
  const Trajectory walk = Straight(Vec3(0.0, 0.0, 1.0), Vec3(0.04, 0.0, 0.0));
  const Trajectory elsewhere = Straight(Vec3(0.0, 3.0, 1.0), Vec3(0.04, 0.0, 0.0));
  const std::vector<core::TrackletMember> alive = {{0, 1, 20, 49, 30}};
  REQUIRE(LinkerOptions{}.monocular_max_s == 5.0);
  {
    WindowLinker linker;
    LinkWindow(&linker, 0, {MovingTracklet(0, 29, walk, {1, 2})});
    REQUIRE(FindTrack(linker, 1)->confirmed);  // isolated: confirmed at birth
    // Its own 2D track: taken; another 2D track of the camera (nobody's): dropped, not born.
    LinkResult r = linker.Link(
        1, 20, kSpf, {}, alive, {Monocular(20, 49, walk, 1), Monocular(20, 49, elsewhere, 9)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{1, 0});
    CHECK(r.born.empty());
    CHECK(linker.tracks().size() == 1);
    CHECK(FindTrack(linker, 1)->state == TrackState::kConfirmed);
    CHECK(FindTrack(linker, 1)->last_seen_frame == 49);
    r = linker.Link(2, 40, kSpf, {}, alive, {Monocular(40, 69, walk, 1)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{1});
    // Both cameras again: linked on the overlap with the monocular tracklet.
    r = LinkWindow(&linker, 3, {MovingTracklet(60, 89, walk, {1, 5})});
    CHECK(r.track_of_tracklet[0] == 1);
    CHECK(r.link_kind[0] == LinkKind::kOverlap);
  }
  // The 2D track jumped to somebody 3 m away: not taken, the track is lost.
  {
    WindowLinker linker;
    LinkWindow(&linker, 0, {MovingTracklet(0, 29, walk, {1, 2})});
    const LinkResult r = linker.Link(1, 20, kSpf, {}, alive, {Monocular(20, 49, elsewhere, 1)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{0});
    CHECK(FindTrack(linker, 1)->state == TrackState::kLost);
  }
  // At most monocular_max_s after the last frame two cameras placed (29); 0: off.
  for (const double max_s : {1.0, 0.0}) {
    LinkerOptions o;
    o.monocular_max_s = max_s;
    WindowLinker linker(o);
    LinkWindow(&linker, 0, {MovingTracklet(0, 29, walk, {1, 2})});
    LinkResult r = linker.Link(1, 20, kSpf, {}, alive, {Monocular(20, 49, walk, 1)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{max_s > 0.0 ? 1 : 0});
    // Window 3 starts 1.03 s after frame 29.
    linker.Link(2, 40, kSpf, {}, alive, {Monocular(40, 69, walk, 1)});
    r = linker.Link(3, 60, kSpf, {}, alive, {Monocular(60, 89, walk, 1)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{0});
  }
  // A tentative track does not continue on one camera.
  {
    WindowLinker linker;
    LinkWindow(
        &linker,
        0,
        {MovingTracklet(0, 29, walk, {1, 2}),
         MovingTracklet(0, 29, Straight(Vec3(0.0, 1.0, 1.0), Vec3(0.04, 0.0, 0.0)), {3, 4})});
    REQUIRE(!FindTrack(linker, 1)->confirmed);
    const LinkResult r = linker.Link(1, 20, kSpf, {}, alive, {Monocular(20, 49, walk, 1)});
    CHECK(r.track_of_monocular == std::vector<TrackId3D>{0});
  }
  LinkerOptions bad;
  bad.monocular_max_s = -1.0;
  CHECK(!bad.Validate(nullptr));
}

TEST_CASE("Appearance: a person's fragments never seen together do not make a return ambiguous",
          "[unit]") {
  const Vec3 at(1.0, 1.0, 1.0);
  for (const bool disjoint : {true, false}) {
    core::AppearanceOptions a = AppearanceOn();
    REQUIRE(a.reid_disjoint_same_person);  // the default
    a.reid_disjoint_same_person = disjoint;
    WindowLinker linker({}, {}, a);
    // Fragment 1 (track 1) leaves every view and departs.
    LinkWindow(&linker, 0, {Looking(ConstantTracklet(0, 29, at, {1, 2}), Look(0))});
    LinkWindow(&linker, 1, {Looking(ConstantTracklet(20, 49, at, {1, 2}), Look(0))});
    linker.Link(2, 40, kSpf, {}, {});
    linker.Link(3, 60, kSpf, {}, {});
    // Fragment 2 (track 2): the person again, 30 m away 1 s later (faster than a person
    // walks: not re-identified), then gone too.
    const Vec3 far(31.0, 1.0, 1.0);
    LinkResult r =
        LinkWindow(&linker, 4, {Looking(ConstantTracklet(80, 109, far, {3, 4}), Look(0, 0.05))});
    REQUIRE(r.track_of_tracklet[0] == 2);
    LinkWindow(&linker, 5, {Looking(ConstantTracklet(100, 129, far, {3, 4}), Look(0, 0.05))});
    LinkWindow(&linker, 6, {Looking(ConstantTracklet(120, 149, far, {3, 4}), Look(0, 0.05))});
    linker.Link(7, 140, kSpf, {}, {});
    linker.Link(8, 160, kSpf, {}, {});
    REQUIRE(linker.departed().size() == 2);
    // Back after 10 s, between both places, looking more like fragment 1: both fragments
    // are within reid_margin of the look and of each other.
    r = LinkWindow(
        &linker,
        20,
        {Looking(ConstantTracklet(400, 429, Vec3(16.0, 1.0, 1.0), {7, 8}), Look(0, 0.01))});
    if (disjoint) {
      CHECK(r.link_kind[0] == LinkKind::kAppearance);
      CHECK(r.track_of_tracklet[0] == 2);  // the fragment of more windows (3 against 2)
      CHECK(linker.departed().empty());    // the other fragment is forgotten
    } else {
      CHECK(r.link_kind[0] == LinkKind::kBirth);
      CHECK(r.track_of_tracklet[0] == 3);
    }
  }
}

}  // namespace
}  // namespace mvtrack::linking
