// The pure stages the Tracker is composed of (FrameGate, CameraStage, WindowBuilder,
// ProcessWindowJob, WindowFinalizer), tested on their own and recomposed by hand.

#include <algorithm>
#include <catch2/catch.hpp>
#include <variant>

#include "tracker/frame3d_equal.h"
#include "tracker/scene_eval.h"

namespace mvtrack {
namespace {

sim::Scene SmallScene(int frames, bool poses, int people = 2) {
  sim::SceneOptions o;
  o.seed = 5;
  o.num_cameras = 3;
  o.num_people = people;
  o.num_frames = frames;
  o.poses = poses;
  o.occlusion = false;
  o.miss_rate = 0.05;
  o.false_positives_per_frame = 0.2;
  return sim::GenerateScene(o);
}

core::CameraFrame Header(CameraId camera, FrameIndex frame, std::size_t detections = 0) {
  core::CameraFrame cf;
  cf.camera_id = camera;
  cf.frame = frame;
  cf.utime = 1000 * frame + camera;
  cf.detections.resize(detections);
  return cf;
}

// The tracker's stages by hand up to the window builder: every admitted camera-frame through
// FrameGate, its CameraStage and the WindowBuilder, then both flushed; the builder's whole
// output sequence (closed frames and window jobs, in order).
std::vector<tracker::BuilderOutput> RunStagesToWindows(const sim::Scene& scene,
                                                       const geometry::CameraRig& rig,
                                                       const tracker::TrackerOptions& options) {
  tracker::FrameGate gate(rig, options);
  std::vector<tracker::CameraStage> stages;
  for (int c = 0; c < rig.size(); ++c) stages.emplace_back(rig.camera(c), c, options);
  tracker::WindowBuilder builder(rig, options);
  std::vector<tracker::BuilderOutput> outputs;
  for (const auto& cams : scene.detections) {
    for (const core::CameraFrame& cf : cams) {
      const tracker::FrameAdmission a = gate.Admit(cf);
      REQUIRE(a.rejection == tracker::FrameRejection::kNone);
      tracker::CameraStageCounters counters;
      builder.Add(
          a.events,
          stages[static_cast<std::size_t>(a.camera_index)].Process(cf, a.stream_epoch, &counters),
          &outputs);
    }
  }
  gate.Flush();
  builder.Flush(&outputs);
  return outputs;
}

TEST_CASE("FrameGate decides admission and frame sequencing from headers", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(10, false);
  const geometry::CameraRig rig(scene.cameras);
  tracker::TrackerOptions options;
  options.max_frame_jump = 1000;
  options.max_detections_per_frame = 5;
  tracker::FrameGate gate(rig, options);

  tracker::FrameAdmission a = gate.Admit(Header(0, 10));
  CHECK(a.rejection == tracker::FrameRejection::kNone);
  CHECK(a.camera_index == 0);
  CHECK((!a.events.close_open_frame && !a.events.reanchor && a.events.open_frame));
  CHECK(a.stream_epoch == 0);

  a = gate.Admit(Header(2, 10));
  CHECK(a.camera_index == 2);
  CHECK((!a.events.close_open_frame && !a.events.reanchor && !a.events.open_frame));

  CHECK(gate.Admit(Header(2, 10)).rejection == tracker::FrameRejection::kDuplicateCamera);
  CHECK(gate.Admit(Header(1, 9)).rejection == tracker::FrameRejection::kStaleFrame);
  a = gate.Admit(Header(99, 10));
  CHECK(a.rejection == tracker::FrameRejection::kUnknownCamera);
  CHECK(a.camera_index == -1);
  CHECK(gate.Admit(Header(1, 10, 6)).rejection == tracker::FrameRejection::kTooManyDetections);
  CHECK(gate.open_frame() == 10);  // rejections changed nothing

  a = gate.Admit(Header(1, 12));
  CHECK((a.events.close_open_frame && !a.events.reanchor && a.events.open_frame));
  CHECK(gate.last_closed_frame() == 10);
  CHECK(gate.Admit(Header(0, 11)).rejection == tracker::FrameRejection::kStaleFrame);

  // More than max_frame_jump past the last closed frame (12): the stream restarts.
  a = gate.Admit(Header(0, 12 + 1001));
  CHECK((a.events.close_open_frame && a.events.reanchor && a.events.open_frame));
  CHECK(a.stream_epoch == 1);
  a = gate.Admit(Header(1, 1013 + 1000));  // exactly max_frame_jump past 1013: no restart
  CHECK((a.events.close_open_frame && !a.events.reanchor && a.events.open_frame));
  CHECK(a.stream_epoch == 1);

  CHECK(gate.Flush());
  CHECK(gate.stream_epoch() == 2);
  CHECK_FALSE(gate.Flush());  // nothing left to end
  CHECK(gate.stream_epoch() == 2);
  a = gate.Admit(Header(0, 5));  // after a flush any frame starts a new stream
  CHECK(a.rejection == tracker::FrameRejection::kNone);
  CHECK((!a.events.close_open_frame && !a.events.reanchor && a.events.open_frame));
  CHECK(a.stream_epoch == 2);
}

// Issue 44: a frame every camera delivered is closed by its last camera (close_after), not a
// frame period later by the next frame's first camera; the builder emits it then.
TEST_CASE("FrameGate closes a frame once every camera delivered it", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(10, false);  // 3 cameras
  const geometry::CameraRig rig(scene.cameras);
  tracker::TrackerOptions options;
  tracker::FrameGate gate(rig, options);
  tracker::WindowBuilder builder(rig, options);
  std::vector<tracker::BuilderOutput> out;
  const auto add = [&](CameraId camera, FrameIndex frame) {
    const tracker::FrameAdmission a = gate.Admit(Header(camera, frame));
    REQUIRE(a.rejection == tracker::FrameRejection::kNone);
    tracker::TrackedCameraFrame tracked;
    tracked.camera_index = a.camera_index;
    tracked.frame = frame;
    out.clear();
    builder.Add(a.events, tracked, &out);
    return a.events;
  };
  CHECK_FALSE(add(2, 7).close_after);
  CHECK_FALSE(add(0, 7).close_after);
  CHECK(out.empty());
  tracker::FrameEvents e = add(1, 7);
  CHECK(e.close_after);
  CHECK_FALSE(e.close_open_frame);
  REQUIRE(out.size() == 1);
  CHECK(std::get<tracker::ClosedFrame>(out[0]).frame == 7);
  CHECK(gate.last_closed_frame() == 7);
  CHECK_FALSE(gate.open_frame().has_value());
  // The same frame again: a duplicate; an older one: stale.
  const tracker::FrameAdmission dup = gate.Admit(Header(1, 7));
  CHECK(dup.rejection == tracker::FrameRejection::kDuplicateCamera);
  CHECK_THAT(dup.reason, Catch::Contains("already delivered frame 7"));
  CHECK(gate.Admit(Header(0, 6)).rejection == tracker::FrameRejection::kStaleFrame);
  // The next frame opens without closing anything; a frame left incomplete is closed by the
  // next one as before.
  e = add(0, 8);
  CHECK((e.open_frame && !e.close_open_frame && !e.close_after));
  e = add(1, 9);
  CHECK((e.open_frame && e.close_open_frame && !e.close_after));
  CHECK(gate.last_closed_frame() == 8);
}

TEST_CASE("FrameGate never looks at detection contents", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(40, true);
  const geometry::CameraRig rig(scene.cameras);
  tracker::FrameGate with(rig, {});
  tracker::FrameGate without(rig, {});
  for (const auto& cams : scene.detections) {
    for (const core::CameraFrame& cf : cams) {
      const tracker::FrameAdmission a = with.Admit(cf);
      const tracker::FrameAdmission b =
          without.Admit(Header(cf.camera_id, cf.frame, cf.detections.size()));
      CHECK(a.rejection == b.rejection);
      CHECK(a.events.close_open_frame == b.events.close_open_frame);
      CHECK(a.events.open_frame == b.events.open_frame);
      CHECK(a.events.reanchor == b.events.reanchor);
      CHECK(a.events.close_after == b.events.close_after);
    }
  }
}

// Runs gate + builder over headers only (no detections) and returns the builder's outputs.
std::vector<tracker::BuilderOutput> BuildHeadersOnly(const geometry::CameraRig& rig,
                                                     const tracker::TrackerOptions& options,
                                                     const std::vector<FrameIndex>& frames,
                                                     bool flush) {
  tracker::FrameGate gate(rig, options);
  tracker::WindowBuilder builder(rig, options);
  std::vector<tracker::BuilderOutput> out;
  for (FrameIndex f : frames) {
    for (int c = rig.size() - 1; c >= 0; --c) {
      const core::CameraFrame cf = Header(rig.camera(c).id, f);
      const tracker::FrameAdmission a = gate.Admit(cf);
      REQUIRE(a.rejection == tracker::FrameRejection::kNone);
      tracker::TrackedCameraFrame t;
      t.camera_index = a.camera_index;
      t.frame = cf.frame;
      t.utime = cf.utime;
      builder.Add(a.events, std::move(t), &out);
    }
  }
  if (flush) {
    gate.Flush();
    builder.Flush(&out);
  }
  return out;
}

TEST_CASE("WindowBuilder: window grid, finalize ranges partition the closed frames",
          "[unit][tracker]") {
  const sim::Scene scene = SmallScene(10, false);
  const geometry::CameraRig rig(scene.cameras);
  tracker::TrackerOptions options;  // ν = 30, δ = 20
  const std::int64_t nu = options.window_size;
  const std::int64_t delta = options.window_step;
  const std::int64_t half = (nu - delta) / 2;
  const FrameIndex first = 7;
  const FrameIndex last = 106;  // 100 frames
  std::vector<FrameIndex> frames;
  for (FrameIndex f = first; f <= last; ++f) frames.push_back(f);
  const std::vector<tracker::BuilderOutput> out = BuildHeadersOnly(rig, options, frames, true);

  std::vector<tracker::WindowJob> jobs;
  std::map<FrameIndex, std::size_t> closed_at;  // frame -> position in the output
  std::size_t stream_ends = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (const auto* c = std::get_if<tracker::ClosedFrame>(&out[i])) {
      CHECK(closed_at.emplace(c->frame, i).second);
      CHECK(c->utime == 1000 * c->frame);  // the smallest utime of the frame (camera 0)
    } else if (const auto* j = std::get_if<tracker::WindowJob>(&out[i])) {
      jobs.push_back(*j);
      // A complete window is emitted after its last frame closed.
      if (j->end == j->begin + nu) CHECK(closed_at.count(j->end - 1) == 1);
    } else {
      ++stream_ends;
      CHECK(i + 1 == out.size());
    }
  }
  CHECK(stream_ends == 1);
  CHECK(closed_at.size() == frames.size());
  // Window k covers [F0 + kδ, F0 + kδ + ν) (cut at the last frame), F0 the multiple of δ at or
  // before the first frame, and finalizes its middle δ (window 0 from F0).
  const FrameIndex origin = 0;  // 7 - 7 % 20
  REQUIRE(jobs.size() == 6);    // begins 0, 20, 40, 60, 80, 100 (<= 106)
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    const auto ki = static_cast<std::int64_t>(k);
    INFO("window " << k);
    CHECK(jobs[k].window_id == ki);
    CHECK(jobs[k].begin == origin + ki * delta);
    CHECK(jobs[k].end == std::min(origin + ki * delta + nu, last + 1));
    CHECK(jobs[k].finalize_from == (k == 0 ? origin : origin + ki * delta + half));
    CHECK(jobs[k].finalize_to ==
          (k + 1 == jobs.size() ? last + 1 : origin + ki * delta + half + delta));
  }
  // A tracker of the same stream that started later (a site's other zone, a restarted daemon;
  // frames 33 and 41) has the same windows over the frames both saw.
  for (const FrameIndex later : {FrameIndex{33}, FrameIndex{41}}) {
    INFO("stream from frame " << later);
    std::vector<FrameIndex> tail;
    for (FrameIndex f = later; f <= last; ++f) tail.push_back(f);
    std::vector<tracker::WindowJob> again;
    for (const tracker::BuilderOutput& o : BuildHeadersOnly(rig, options, tail, true)) {
      if (const auto* j = std::get_if<tracker::WindowJob>(&o)) again.push_back(*j);
    }
    REQUIRE(!again.empty());
    CHECK(again.front().begin == (later == 33 ? 20 : 40));
    for (const tracker::WindowJob& j : again) {
      CHECK((j.begin - origin) % delta == 0);
      for (const tracker::WindowJob& k : jobs) {
        if (k.begin == j.begin && j.begin > later) {
          CHECK(k.end == j.end);
          CHECK(k.finalize_to == j.finalize_to);
        }
      }
    }
  }
  // Every closed frame is finalized by exactly one window.
  for (FrameIndex f : frames) {
    int n = 0;
    for (const auto& j : jobs) n += (f >= j.finalize_from && f < j.finalize_to) ? 1 : 0;
    CHECK(n == 1);
  }
}

TEST_CASE("WindowBuilder: skipped frames and a new stream after a flush", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(10, false);
  const geometry::CameraRig rig(scene.cameras);
  tracker::TrackerOptions options;
  // Frames 0..25, then 60: opening 60 completes every window ending at or before 59.
  std::vector<FrameIndex> frames;
  for (FrameIndex f = 0; f <= 25; ++f) frames.push_back(f);
  frames.push_back(60);
  std::vector<tracker::BuilderOutput> out = BuildHeadersOnly(rig, options, frames, false);
  std::vector<std::int64_t> begins;
  for (const auto& o : out) {
    if (const auto* j = std::get_if<tracker::WindowJob>(&o)) begins.push_back(j->begin);
  }
  CHECK(begins == std::vector<std::int64_t>{0, 20});  // [0,30) and [20,50); [40,70) is open

  // After a flush, window ids continue.
  tracker::FrameGate gate(rig, options);
  tracker::WindowBuilder builder(rig, options);
  out.clear();
  std::int64_t windows_first_stream = 0;
  for (FrameIndex f : {0, 1, 2, 3}) {
    const tracker::FrameAdmission a = gate.Admit(Header(0, f));
    builder.Add(a.events, tracker::TrackedCameraFrame{0, f, 0, {}}, &out);
  }
  gate.Flush();
  builder.Flush(&out);
  for (const auto& o : out) windows_first_stream += std::holds_alternative<tracker::WindowJob>(o);
  CHECK(windows_first_stream == 1);
  out.clear();
  for (FrameIndex f = 0; f < 40; ++f) {
    const tracker::FrameAdmission a = gate.Admit(Header(1, f));
    builder.Add(a.events, tracker::TrackedCameraFrame{1, f, 0, {}}, &out);
  }
  const auto* j = std::get_if<tracker::WindowJob>(&out[30]);  // 30 closed frames, then window
  REQUIRE(j != nullptr);
  CHECK(j->window_id == 1);
}

TEST_CASE("CameraStage: a newer stream epoch restarts SORT", "[unit][tracker]") {
  const sim::Scene scene = SmallScene(12, false);
  const geometry::CameraRig rig(scene.cameras);
  const tracker::TrackerOptions options;
  tracker::CameraStage stage(rig.camera(1), 1, options);
  tracker::CameraStageCounters counters;
  for (int f = 0; f < 10; ++f) {
    stage.Process(scene.detections[static_cast<std::size_t>(f)][1], 0, &counters);
  }
  REQUIRE(stage.sort().num_tracks() > 0);
  tracker::CameraStage fresh(rig.camera(1), 1, options);
  const core::CameraFrame& next = scene.detections[10][1];
  const tracker::TrackedCameraFrame a = stage.Process(next, 1, &counters);
  const tracker::TrackedCameraFrame b = fresh.Process(next, 0, &counters);
  REQUIRE(a.observations.size() == b.observations.size());
  REQUIRE(!a.observations.empty());
  for (std::size_t i = 0; i < a.observations.size(); ++i) {
    CHECK(a.observations[i].first == b.observations[i].first);  // ids restart at 1
    CHECK(a.observations[i].second.points_px == b.observations[i].second.points_px);
  }
  CHECK(a.observations.front().first == 1);
  CHECK(a.camera_index == 1);
  CHECK(a.frame == next.frame);
  CHECK(a.utime == next.utime);

  // Invalid detections are counted with the first reason.
  core::CameraFrame bad = scene.detections[11][1];
  core::Detection2D nan_box;
  nan_box.box = {std::numeric_limits<double>::quiet_NaN(), 0, 10, 10};
  bad.detections.push_back(nan_box);
  bad.detections.push_back(nan_box);
  stage.Process(bad, 1, &counters);
  CHECK(counters.detections_rejected == 2);
  CHECK(!counters.first_rejection_reason.empty());
  CHECK(counters.detections_used ==
        static_cast<int>(scene.detections[11][1].detections.size()) - counters.detections_filtered);
}

TEST_CASE("windows processed out of order on one reused workspace give the Tracker's output",
          "[unit][tracker]") {
  const sim::Scene scene = SmallScene(90, true, 3);
  const geometry::CameraRig rig(scene.cameras);
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kPoses;
  options.window_size = 20;  // 8 windows over 90 frames
  options.window_step = 10;

  std::string why;
  auto reference = tracker::Tracker::Create(rig, options, &why);
  REQUIRE(reference);
  const std::vector<tracker::Frame3D> expected = testing::RunScene(reference.get(), scene);

  // The stages by hand: collect the whole output sequence first.
  std::vector<tracker::BuilderOutput> outputs = RunStagesToWindows(scene, rig, options);

  // Process every window in reverse order on one workspace, then finalize in order.
  std::map<std::size_t, tracker::WindowResult> results;
  tracker::WindowWorkspace workspace(options.triangulation);
  for (std::size_t i = outputs.size(); i-- > 0;) {
    if (const auto* job = std::get_if<tracker::WindowJob>(&outputs[i])) {
      results.emplace(i, tracker::ProcessWindowJob(rig, options, *job, &workspace));
    }
  }
  REQUIRE(results.size() >= 7);
  tracker::WindowFinalizer finalizer(rig, options);
  std::vector<tracker::Frame3D> frames;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (const auto* closed = std::get_if<tracker::ClosedFrame>(&outputs[i])) {
      finalizer.AddClosedFrame(*closed);
    } else if (std::holds_alternative<tracker::WindowJob>(outputs[i])) {
      finalizer.Finalize(results.at(i), &frames);
    } else {
      finalizer.EndStream(&frames);
    }
  }
  INFO(testing::FirstDifference(expected, frames));
  CHECK(testing::FirstDifference(expected, frames).empty());
  CHECK(finalizer.counters().frames_finalized == static_cast<std::int64_t>(expected.size()));
  CHECK(finalizer.counters().windows_processed == reference->stats().windows_processed);
  std::size_t tracks = 0;
  for (const auto& f : frames) tracks += f.tracks.size();
  CHECK(tracks > 0);
}

TEST_CASE("a PersonLoop spreading persons over workspaces gives the same window results",
          "[unit][tracker]") {
  for (const bool poses : {false, true}) {
    INFO((poses ? "poses" : "boxes"));
    const sim::Scene scene = SmallScene(90, poses, 5);
    const geometry::CameraRig rig(scene.cameras);
    tracker::TrackerOptions options;
    options.mode = poses ? tracker::InputMode::kPoses : tracker::InputMode::kBoxes;
    std::vector<tracker::BuilderOutput> outputs = RunStagesToWindows(scene, rig, options);

    tracker::WindowWorkspace sequential(options.triangulation);
    std::vector<tracker::WindowWorkspace> pool;
    for (int w = 0; w < 3; ++w) pool.emplace_back(options.triangulation);
    // Persons in reverse order, round-robin over three workspaces.
    int calls = 0;
    const tracker::PersonLoop reversed = [&](int n, const tracker::PersonTask& task) {
      for (int i = n - 1; i >= 0; --i) {
        task(i, &pool[static_cast<std::size_t>(calls++ % 3)]);
      }
    };
    int windows = 0;
    std::size_t persons = 0;
    for (const tracker::BuilderOutput& output : outputs) {
      const auto* job = std::get_if<tracker::WindowJob>(&output);
      if (job == nullptr) continue;
      const tracker::WindowResult a = tracker::ProcessWindowJob(rig, options, *job, &sequential);
      const tracker::WindowResult b =
          tracker::ProcessWindowJob(rig, options, *job, &sequential, reversed);
      REQUIRE(a.clusters == b.clusters);
      REQUIRE(a.persons.size() == b.persons.size());
      for (std::size_t i = 0; i < a.persons.size(); ++i) {
        REQUIRE(a.persons[i].frames == b.persons[i].frames);
        REQUIRE(a.persons[i].points == b.persons[i].points);
        REQUIRE(a.persons[i].cameras == b.persons[i].cameras);
        REQUIRE(a.persons[i].source_tracklets == b.persons[i].source_tracklets);
      }
      persons += a.persons.size();
      ++windows;
    }
    CHECK(windows >= 3);
    CHECK(persons > 0);
    CHECK(calls > 0);
  }
}

// A box-mode person of one window, at `x` (metres) in the frames given, supported by the 2D
// tracks `tracks` (one per camera, cameras 0, 1, ...).
core::Tracklet3D PersonAt(double x,
                          const std::vector<FrameIndex>& frames,
                          const std::vector<TrackId2D>& tracks) {
  core::Tracklet3D p;
  for (const FrameIndex f : frames) {
    p.frames.push_back(f);
    p.points.push_back({Vec3(x, 0.0, 1.0)});
  }
  for (std::size_t c = 0; c < tracks.size(); ++c) {
    const auto camera = static_cast<CameraId>(c);
    p.cameras.push_back(camera);
    p.source_tracklets.push_back(static_cast<int>(c));
    p.members.push_back(core::TrackletMember{
        camera, tracks[c], frames.front(), frames.back(), static_cast<int>(frames.size())});
  }
  return p;
}

// A window result with its window [begin, begin + 30) and finalized frames [from, to).
tracker::WindowResult WindowOf(std::int64_t id, FrameIndex begin, FrameIndex from, FrameIndex to) {
  tracker::WindowResult w;
  w.window_id = id;
  w.begin = begin;
  w.end = begin + 30;
  w.finalize_from = from;
  w.finalize_to = to;
  return w;
}

std::vector<FrameIndex> FrameRange(FrameIndex first, FrameIndex last) {
  std::vector<FrameIndex> f;
  for (FrameIndex t = first; t <= last; ++t) f.push_back(t);
  return f;
}

// The case of Campus hard seed 4 (docs/ACCURACY.md "Bridging short gaps"): in a window, the
// person's linked tracklet has only a few frames (one in the finalized range, far after the
// previous window's last output), and a duplicate tracklet of the same person carries the
// rest. The gap between the previous window and the duplicate's first frame is bridged: the
// track's frames of the window, from both, are one sequence.
TEST_CASE("WindowFinalizer bridges a gap that the person's duplicate tracklet ends",
          "[unit][tracker]") {
  tracker::TrackerOptions options;  // box mode, bridge_max_gap_s 0.6 (18 frames at 30 fps)
  tracker::WindowFinalizer finalizer(geometry::CameraRig(), options);
  for (FrameIndex f = 0; f < 50; ++f) finalizer.AddClosedFrame({f, 1000 * f, {}});
  std::vector<tracker::Frame3D> frames;
  tracker::WindowResult w0 = WindowOf(0, 0, 0, 25);
  w0.persons = {PersonAt(0.0, FrameRange(0, 29), {1, 2})};
  finalizer.Finalize(w0, &frames);
  REQUIRE(frames.size() == 25);
  REQUIRE(frames.back().tracks.size() == 1);
  const TrackId3D id = frames.back().tracks.front().id;
  tracker::WindowResult w1 = WindowOf(1, 20, 25, 45);
  std::vector<FrameIndex> sparse = FrameRange(20, 24);
  for (FrameIndex f = 44; f < 50; ++f) sparse.push_back(f);
  w1.persons = {PersonAt(0.0, sparse, {1, 2}), PersonAt(0.1, FrameRange(30, 49), {5, 6})};
  const linking::LinkResult link = finalizer.Finalize(w1, &frames);
  REQUIRE(link.link_kind[1] == linking::LinkKind::kDuplicate);
  finalizer.EndStream(&frames);
  for (const tracker::Frame3D& f : frames) {
    if (f.frame < 25 || f.frame >= 45) continue;
    INFO("frame " << f.frame);
    REQUIRE(f.tracks.size() == 1);
    CHECK(f.tracks.front().id == id);
    // 25-29 bridged between frame 24 (x = 0) and the duplicate's frame 30 (x = 0.1), with no
    // cameras; 30-43 the duplicate; 44 the person's own tracklet.
    const double x = f.tracks.front().position.x();
    if (f.frame < 30) {
      CHECK(x == Approx(0.1 * static_cast<double>(f.frame - 24) / 6.0));
      CHECK(f.tracks.front().cameras.empty());
    } else {
      CHECK(x == Approx(f.frame < 44 ? 0.1 : 0.0));
      CHECK(f.tracks.front().cameras.size() == 2);
    }
  }
}

}  // namespace
}  // namespace mvtrack
