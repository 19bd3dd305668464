#include "tracking2d/sort_tracker.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace mvtrack::tracking2d {
namespace {

// A synthetic person walking at constant velocity in the image.
struct Walker {
  double cx0 = 0.0;  ///< centre x at frame 0
  double cy0 = 0.0;  ///< centre y at frame 0
  double vx = 0.0;   ///< px / frame
  double vy = 0.0;
  double width = 60.0;
  double height = 160.0;

  core::BoxPx BoxAt(FrameIndex frame) const {
    const double t = static_cast<double>(frame);
    const double cx = cx0 + vx * t;
    const double cy = cy0 + vy * t;
    return {cx - 0.5 * width, cy - 0.5 * height, cx + 0.5 * width, cy + 0.5 * height};
  }
};

core::BoxPx Jitter(core::BoxPx box, double sigma_px, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, sigma_px);
  box.x_min += noise(*rng);
  box.y_min += noise(*rng);
  box.x_max += noise(*rng);
  box.y_max += noise(*rng);
  return box;
}

// One frame of ground truth: boxes in a shuffled order and the person behind each box.
struct SyntheticFrame {
  std::vector<core::BoxPx> boxes;
  std::vector<int> person_of_box;
};

SyntheticFrame MakeFrame(const std::vector<Walker>& walkers,
                         const std::vector<int>& visible,
                         FrameIndex frame,
                         double sigma_px,
                         std::mt19937* rng) {
  std::vector<int> order = visible;
  std::shuffle(order.begin(), order.end(), *rng);
  SyntheticFrame out;
  for (const int p : order) {
    out.boxes.push_back(Jitter(walkers[static_cast<std::size_t>(p)].BoxAt(frame), sigma_px, rng));
    out.person_of_box.push_back(p);
  }
  return out;
}

// Output contract of SortTracker::Update: sorted by strictly increasing track id, valid
// detection indices, each detection at most once.
void CheckOutput(const std::vector<TrackedDetection>& out, std::size_t num_boxes) {
  std::set<int> seen;
  for (std::size_t k = 0; k < out.size(); ++k) {
    REQUIRE(out[k].track_id >= 1);
    if (k > 0) REQUIRE(out[k - 1].track_id < out[k].track_id);
    REQUIRE(out[k].detection_index >= 0);
    REQUIRE(static_cast<std::size_t>(out[k].detection_index) < num_boxes);
    REQUIRE(seen.insert(out[k].detection_index).second);
  }
}

// Track id of detection `index` in `out`, or 0 when it was not reported.
TrackId2D IdOf(const std::vector<TrackedDetection>& out, int index) {
  for (const TrackedDetection& td : out) {
    if (td.detection_index == index) return td.track_id;
  }
  return 0;
}

// Runs two people walking towards each other on nearly the same image row; person 1 (further
// away: smaller, slightly higher) is hidden behind person 0 for frames 29-31 around the
// crossing at frame 30. Returns, per person, the set of track ids its detections got, and
// appends every Update output to `log`.
std::vector<std::set<TrackId2D>> RunCrossing(std::uint32_t seed,
                                             std::vector<std::vector<TrackedDetection>>* log) {
  const std::vector<Walker> walkers = {
      {100.0, 300.0, 8.0, 0.0, 60.0, 160.0},
      {100.0 + 2.0 * 8.0 * 30.0, 292.0, -8.0, 0.0, 54.0, 144.0},
  };
  std::mt19937 rng(seed);
  SortTracker tracker;
  std::vector<std::set<TrackId2D>> ids(walkers.size());
  for (FrameIndex f = 0; f < 60; ++f) {
    std::vector<int> visible = {0};
    if (f < 29 || f > 31) visible.push_back(1);
    const SyntheticFrame frame = MakeFrame(walkers, visible, f, 1.0, &rng);
    const std::vector<TrackedDetection> out = tracker.Update(f, frame.boxes);
    CheckOutput(out, frame.boxes.size());
    // min_hits = 1: every detection is reported from its first frame.
    REQUIRE(out.size() == frame.boxes.size());
    for (std::size_t b = 0; b < frame.boxes.size(); ++b) {
      const TrackId2D id = IdOf(out, static_cast<int>(b));
      REQUIRE(id != 0);
      ids[static_cast<std::size_t>(frame.person_of_box[b])].insert(id);
    }
    if (log != nullptr) log->push_back(out);
  }
  return ids;
}

TEST_CASE("SortOptions validation", "[unit]") {
  std::string why;
  REQUIRE(SortOptions{}.Validate(&why));
  SortOptions o;
  o.max_age = -1;
  REQUIRE_FALSE(o.Validate(&why));
  REQUIRE(why.find("max_age") != std::string::npos);
  o = SortOptions{};
  o.min_hits = 0;
  REQUIRE_FALSE(o.Validate(&why));
  REQUIRE(why.find("min_hits") != std::string::npos);
  for (const double bad : {0.0, -0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    o = SortOptions{};
    o.iou_threshold = bad;
    REQUIRE_FALSE(o.Validate(nullptr));
  }
  o.iou_threshold = 1.0;
  REQUIRE(o.Validate(nullptr));
  for (const double bad :
       {-0.1, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    o = SortOptions{};
    o.motion_buffer = bad;
    REQUIRE_FALSE(o.Validate(&why));
    REQUIRE(why.find("motion_buffer") != std::string::npos);
  }
  for (const double bad : {0.0,
                           -1.0,
                           std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    o = SortOptions{};
    o.process_noise_scale = bad;
    REQUIRE_FALSE(o.Validate(&why));
    REQUIRE(why.find("process_noise_scale") != std::string::npos);
  }
}

// Two people walking side by side, 0.7 box heights apart, sampled at a low frame rate: each
// moves 0.5 box heights (about a box width) between frames, so consecutive boxes of one person
// barely overlap. Returns the 2D track ids each person got.
std::vector<std::set<TrackId2D>> RunSlowStream(double motion_buffer) {
  SortOptions o;
  o.max_age = 1;
  o.motion_buffer = motion_buffer;
  SortTracker tracker(o);
  const std::vector<Walker> walkers = {{100.0, 300.0, 80.0, 0.0, 60.0, 160.0},
                                       {100.0, 412.0, 80.0, 0.0, 60.0, 160.0}};
  std::vector<std::set<TrackId2D>> ids(walkers.size());
  std::mt19937 rng(7);
  for (FrameIndex f = 0; f < 12; ++f) {
    const SyntheticFrame frame = MakeFrame(walkers, {0, 1}, f, 2.0, &rng);
    for (const TrackedDetection& t : tracker.Update(f, frame.boxes)) {
      ids[static_cast<std::size_t>(
              frame.person_of_box[static_cast<std::size_t>(t.detection_index)])]
          .insert(t.track_id);
    }
  }
  return ids;
}

TEST_CASE("SORT follows people who move a box width per frame with the motion buffer", "[unit]") {
  // IoU alone: the first step (no velocity yet) leaves IoU 0.14 < 0.5, every frame starts a
  // new track until the Kalman filter could learn a velocity, which it never gets.
  const std::vector<std::set<TrackId2D>> plain = RunSlowStream(0.0);
  CHECK(plain[0].size() > 1);
  CHECK(plain[1].size() > 1);
  // Buffered by 0.8 box heights (3 m/s at 2 fps): one track each, never shared.
  const std::vector<std::set<TrackId2D>> buffered = RunSlowStream(0.8);
  REQUIRE(buffered[0].size() == 1);
  REQUIRE(buffered[1].size() == 1);
  CHECK(*buffered[0].begin() != *buffered[1].begin());
}

TEST_CASE("SORT keeps two identities through a crossing with a short occlusion", "[unit]") {
  std::vector<std::vector<TrackedDetection>> log;
  const std::vector<std::set<TrackId2D>> ids = RunCrossing(1234, &log);
  REQUIRE(ids[0].size() == 1);
  REQUIRE(ids[1].size() == 1);
  REQUIRE(*ids[0].begin() != *ids[1].begin());

  // Deterministic: the same input gives the same output.
  std::vector<std::vector<TrackedDetection>> again;
  RunCrossing(1234, &again);
  REQUIRE(again.size() == log.size());
  for (std::size_t f = 0; f < log.size(); ++f) {
    REQUIRE(again[f].size() == log[f].size());
    for (std::size_t k = 0; k < log[f].size(); ++k) {
      REQUIRE(again[f][k].track_id == log[f][k].track_id);
      REQUIRE(again[f][k].detection_index == log[f][k].detection_index);
    }
  }
}

TEST_CASE("SORT predicts the occluded person along its motion", "[unit]") {
  // Without detections the track follows the constant-velocity prediction (frames 29-31
  // above); check the snapshot of the hidden person's track directly.
  const Walker hidden{500.0, 300.0, -8.0, 0.0, 54.0, 144.0};
  SortTracker tracker;
  std::mt19937 rng(5);
  for (FrameIndex f = 0; f < 20; ++f) {
    REQUIRE(tracker.Update(f, {Jitter(hidden.BoxAt(f), 0.5, &rng)}).size() == 1);
  }
  for (FrameIndex f = 20; f < 23; ++f) {
    REQUIRE(tracker.Update(f, {}).empty());
    const std::vector<TrackSnapshot> tracks = tracker.Tracks();
    REQUIRE(tracks.size() == 1);
    REQUIRE(tracks[0].last_matched_frame == 19);
    REQUIRE(tracks[0].box.center().x() == Approx(hidden.BoxAt(f).center().x()).margin(3.0));
  }
}

TEST_CASE("SORT track dies after max_age missed frames, a returning person gets a new id",
          "[unit]") {
  // Moving at 5 px/frame with a 50 px wide box: after 6 frames a stationary guess would overlap
  // by IoU 0.25 < 0.3, so re-identification needs the multi-step prediction.
  const Walker walker{100.0, 200.0, 5.0, 0.0, 50.0, 120.0};
  SortOptions options;
  options.max_age = 5;

  for (const bool empty_frames : {true, false}) {
    for (const int absent : {5, 6}) {
      INFO("empty_frames " << empty_frames << " absent " << absent);
      SortTracker tracker(options);
      TrackId2D id = 0;
      for (FrameIndex f = 0; f < 10; ++f) {
        const auto out = tracker.Update(f, {walker.BoxAt(f)});
        REQUIRE(out.size() == 1);
        if (f == 0) id = out[0].track_id;
        REQUIRE(out[0].track_id == id);
      }
      for (FrameIndex f = 10; f < 10 + absent; ++f) {
        if (empty_frames) {
          REQUIRE(tracker.Update(f, {}).empty());
        }
        // A track survives max_age frames without a match.
        const bool alive = f - 9 <= options.max_age;
        if (empty_frames) REQUIRE(tracker.num_tracks() == (alive ? 1 : 0));
      }
      const FrameIndex back = 10 + absent;
      const auto out = tracker.Update(back, {walker.BoxAt(back)});
      REQUIRE(out.size() == 1);
      if (absent <= options.max_age) {
        REQUIRE(out[0].track_id == id);
      } else {
        REQUIRE(out[0].track_id > id);
      }
      REQUIRE(tracker.num_tracks() == 1);
    }
  }
}

TEST_CASE("SORT predicts one step per elapsed frame across frame gaps", "[unit]") {
  // 10 px/frame with a 40 px box: a 4-frame gap moves the person 40 px. Predicting a single
  // step would leave IoU 10/70 < 0.3 and start a new track.
  const Walker walker{100.0, 200.0, 10.0, 0.0, 40.0, 100.0};
  const auto run_until_9 = [&](SortTracker* tracker) {
    for (FrameIndex f = 0; f < 10; ++f) REQUIRE(tracker->Update(f, {walker.BoxAt(f)}).size() == 1);
  };
  {
    SortTracker tracker;
    run_until_9(&tracker);
    const auto out = tracker.Update(13, {walker.BoxAt(13)});
    REQUIRE(out.size() == 1);
    REQUIRE(out[0].track_id == 1);
    REQUIRE(tracker.num_tracks() == 1);
  }
  {
    // Control: the same box one frame later is too far for a one-step prediction.
    SortTracker tracker;
    run_until_9(&tracker);
    const auto out = tracker.Update(10, {walker.BoxAt(13)});
    REQUIRE(out.size() == 1);
    REQUIRE(out[0].track_id == 2);
    REQUIRE(tracker.num_tracks() == 2);
  }
  {
    // A gap longer than max_age + 1 frames: the old track is gone, the person gets a new id.
    SortTracker tracker;
    run_until_9(&tracker);
    const FrameIndex far = 9 + tracker.options().max_age + 2;
    const auto out = tracker.Update(far, {walker.BoxAt(far)});
    REQUIRE(out.size() == 1);
    REQUIRE(out[0].track_id == 2);
    REQUIRE(tracker.num_tracks() == 1);
  }
}

TEST_CASE("SORT handles empty frames", "[unit]") {
  SortTracker tracker;
  REQUIRE(tracker.Update(0, {}).empty());
  REQUIRE(tracker.num_tracks() == 0);
  const auto out = tracker.Update(1, {core::BoxPx{0, 0, 10, 20}});
  REQUIRE(out.size() == 1);
  REQUIRE(out[0].track_id == 1);
  REQUIRE(out[0].detection_index == 0);
  for (FrameIndex f = 2; f < 2 + tracker.options().max_age; ++f) {
    REQUIRE(tracker.Update(f, {}).empty());
    REQUIRE(tracker.num_tracks() == 1);
  }
  REQUIRE(tracker.Update(2 + tracker.options().max_age, {}).empty());
  REQUIRE(tracker.num_tracks() == 0);
}

TEST_CASE("SORT ignores frames that do not increase", "[unit]") {
  SortTracker tracker;
  const core::BoxPx a{0, 0, 10, 20};
  const core::BoxPx far{500, 500, 510, 520};
  REQUIRE(tracker.Update(5, {a}).size() == 1);
  REQUIRE(tracker.Update(5, {a, far}).empty());
  REQUIRE(tracker.Update(4, {far}).empty());
  REQUIRE(tracker.num_tracks() == 1);
  // Nothing was created by the rejected calls: the next new person gets id 2.
  const auto out = tracker.Update(6, {far, a});
  REQUIRE(out.size() == 2);
  REQUIRE(out[0].track_id == 1);
  REQUIRE(out[0].detection_index == 1);
  REQUIRE(out[1].track_id == 2);
  REQUIRE(out[1].detection_index == 0);
}

TEST_CASE("SORT tracks 200 people in one frame", "[unit]") {
  // A 20 x 10 grid of non-overlapping people, each drifting by (3, 2) px per frame, presented
  // in a different random order every frame.
  std::vector<Walker> walkers;
  for (int row = 0; row < 10; ++row) {
    for (int col = 0; col < 20; ++col) {
      walkers.push_back({50.0 + 50.0 * col, 60.0 + 100.0 * row, 3.0, 2.0, 30.0, 60.0});
    }
  }
  std::vector<int> everyone(walkers.size());
  std::iota(everyone.begin(), everyone.end(), 0);
  std::mt19937 rng(99);
  SortTracker tracker;
  std::map<int, TrackId2D> id_of_person;
  for (FrameIndex f = 0; f < 3; ++f) {
    const SyntheticFrame frame = MakeFrame(walkers, everyone, f, 0.5, &rng);
    const auto out = tracker.Update(f, frame.boxes);
    CheckOutput(out, frame.boxes.size());
    REQUIRE(out.size() == 200);
    for (const TrackedDetection& td : out) {
      const int person = frame.person_of_box[static_cast<std::size_t>(td.detection_index)];
      if (f == 0) {
        id_of_person[person] = td.track_id;
      } else {
        REQUIRE(id_of_person.at(person) == td.track_id);
      }
    }
  }
  REQUIRE(id_of_person.size() == 200);
  REQUIRE(tracker.num_tracks() == 200);
  // Frame 0 created ids 1..200, one per person.
  std::set<TrackId2D> ids;
  for (const auto& [person, id] : id_of_person) ids.insert(id);
  REQUIRE(ids.size() == 200);
  REQUIRE(*ids.begin() == 1);
  REQUIRE(*ids.rbegin() == 200);
}

TEST_CASE("SORT never reuses track ids", "[unit]") {
  // A resident person stays; a visitor appears for 3 frames at the same place and then stays
  // away long enough for its track to die, ten times over.
  const Walker resident{100.0, 100.0, 0.0, 0.0, 40.0, 100.0};
  const Walker visitor{400.0, 100.0, 0.0, 0.0, 40.0, 100.0};
  SortTracker tracker;
  const int cycle = 3 + tracker.options().max_age + 1;
  std::set<TrackId2D> visitor_ids;
  TrackId2D last_visitor_id = 0;
  TrackId2D resident_id = 0;
  for (FrameIndex f = 0; f < 10 * cycle; ++f) {
    const bool visiting = f % cycle < 3;
    std::vector<core::BoxPx> boxes = {resident.BoxAt(f)};
    if (visiting) boxes.push_back(visitor.BoxAt(f));
    const auto out = tracker.Update(f, boxes);
    CheckOutput(out, boxes.size());
    REQUIRE(out.size() == boxes.size());
    if (f == 0) resident_id = IdOf(out, 0);
    REQUIRE(IdOf(out, 0) == resident_id);
    if (visiting) {
      const TrackId2D id = IdOf(out, 1);
      if (f % cycle == 0) {
        REQUIRE(id > last_visitor_id);
        REQUIRE(id != resident_id);
        REQUIRE(visitor_ids.insert(id).second);
        last_visitor_id = id;
      } else {
        REQUIRE(id == last_visitor_id);
      }
    }
  }
  REQUIRE(visitor_ids.size() == 10);
}

TEST_CASE("SORT min_hits withholds tentative tracks", "[unit]") {
  // Person 0 is detected every frame except 10; person 1 only every other frame, so it never
  // has min_hits consecutive matches.
  const Walker steady{100.0, 100.0, 2.0, 0.0, 40.0, 100.0};
  const Walker flicker{400.0, 100.0, 0.0, 0.0, 40.0, 100.0};
  SortOptions options;
  options.min_hits = 3;
  SortTracker tracker(options);
  for (FrameIndex f = 0; f < 20; ++f) {
    std::vector<core::BoxPx> boxes;
    if (f != 10) boxes.push_back(steady.BoxAt(f));
    if (f % 2 == 0) boxes.push_back(flicker.BoxAt(f));
    const auto out = tracker.Update(f, boxes);
    CheckOutput(out, boxes.size());
    // The flickering person is never reported; it keeps its single tentative track.
    if (f % 2 == 0) REQUIRE(IdOf(out, static_cast<int>(boxes.size()) - 1) == 0);
    if (f == 10) {
      REQUIRE(out.empty());
    } else if (f < 2) {
      REQUIRE(out.empty());  // tentative: 1 and 2 matched frames
    } else {
      // Confirmed at its third detection and stays confirmed across the miss at frame 10.
      REQUIRE(out.size() == 1);
      REQUIRE(out[0].track_id == 1);
      REQUIRE(out[0].detection_index == 0);
    }
  }
  REQUIRE(tracker.num_tracks() == 2);
  const auto tracks = tracker.Tracks();
  REQUIRE(tracks[0].confirmed);
  REQUIRE_FALSE(tracks[1].confirmed);
}

TEST_CASE("SORT ignores unusable boxes", "[unit]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SortTracker tracker;
  const std::vector<core::BoxPx> boxes = {
      {nan, 0, 10, 10}, {0, 0, 10, 20}, {5, 5, 5, 30}, {100, 100, 90, 120}, {200, 0, 220, 40}};
  const auto out = tracker.Update(0, boxes);
  CheckOutput(out, boxes.size());
  REQUIRE(out.size() == 2);
  REQUIRE(out[0].detection_index == 1);
  REQUIRE(out[1].detection_index == 4);
  REQUIRE(tracker.num_tracks() == 2);
}

}  // namespace
}  // namespace mvtrack::tracking2d

namespace mvtrack::tracking2d {
namespace {

// Two people standing side by side swap places between two frames (boxes overlapping enough
// that IoU alone prefers the swap); their embeddings tell them apart. `noise` perturbs every
// embedding (0: identical to the person's own look).
std::vector<TrackId2D> SwapIds(bool appearance, double noise) {
  SortTracker sort;
  if (appearance) {
    SortAppearance a;
    a.weight = 0.5;
    a.gate = 0.6;
    sort.set_appearance(a);
  }
  const std::vector<float> look_a = {1.0f, 0.0f, 0.0f}, look_b = {0.0f, 1.0f, 0.0f};
  std::mt19937 rng(7);
  std::normal_distribution<float> n(0.0f, static_cast<float>(noise));
  const auto noisy = [&](const std::vector<float>& v) {
    std::vector<float> e = {v[0] + n(rng), v[1] + n(rng), v[2] + n(rng)};
    const float norm = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (float& x : e) x /= norm;
    return e;
  };
  std::vector<TrackId2D> last;
  for (FrameIndex f = 0; f < 40; ++f) {
    // Standing still for 39 frames at x = 100 (A) and x = 130 (B); at frame 39 they step
    // 18 px towards each other: each now overlaps the other's track more than its own.
    const double a_x = f < 39 ? 100.0 : 118.0, b_x = f < 39 ? 130.0 : 112.0;
    const std::vector<core::BoxPx> boxes = {{a_x, 100.0, a_x + 60.0, 260.0},
                                            {b_x, 100.0, b_x + 60.0, 260.0}};
    const std::vector<float> ea = noisy(look_a), eb = noisy(look_b);
    const std::vector<const std::vector<float>*> embeddings = {&ea, &eb};
    const std::vector<TrackedDetection> out = sort.Update(f, boxes, &embeddings);
    last.assign(2, 0);
    for (const TrackedDetection& t : out)
      last[static_cast<std::size_t>(t.detection_index)] = t.track_id;
  }
  return last;  // track id of A's and B's detection at the last frame
}

TEST_CASE("SORT with appearance keeps two people apart where IoU alone swaps them", "[unit]") {
  // Motion only: the swap (A's detection continues B's track).
  const std::vector<TrackId2D> motion = SwapIds(false, 0.0);
  CHECK(motion == std::vector<TrackId2D>{2, 1});
  // Appearance: identities kept.
  CHECK(SwapIds(true, 0.05) == std::vector<TrackId2D>{1, 2});
  // Embeddings so noisy that one person's own detections are far apart: SORT ignores them
  // and behaves as without.
  CHECK(SwapIds(true, 3.0) == motion);
  SortAppearance bad;
  bad.weight = 1.5;
  std::string why;
  CHECK_FALSE(bad.Validate(&why));
  CHECK(why.find("weight") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::tracking2d
