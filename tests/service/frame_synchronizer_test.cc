// FrameSynchronizer: grouping by frame index and by utime, the late-camera deadline, silent
// cameras, the time-order rejections, flooding, stream restarts and the pending bound.

#include "service/frame_synchronizer.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::service {
namespace {

constexpr std::int64_t kPeriod = 40000;  // 25 Hz

core::CameraFrame Frame(CameraId camera, FrameIndex frame, Utime utime, int detections = 0) {
  core::CameraFrame f;
  f.camera_id = camera;
  f.frame = frame;
  f.utime = utime;
  f.detections.resize(static_cast<std::size_t>(detections));
  return f;
}

core::CameraFrame At(CameraId camera, FrameIndex frame) {
  return Frame(camera, frame, 1000000 + frame * kPeriod + camera * 100);
}

// (frame, camera) of every submit, kEndStream as (-1, -1).
std::vector<std::pair<FrameIndex, CameraId>> Released(const std::vector<SyncAction>& actions) {
  std::vector<std::pair<FrameIndex, CameraId>> out;
  for (const SyncAction& a : actions) {
    if (a.kind == SyncAction::Kind::kEndStream) {
      out.emplace_back(-1, -1);
    } else {
      out.emplace_back(a.frame.frame, a.frame.camera_id);
    }
  }
  return out;
}

using Pairs = std::vector<std::pair<FrameIndex, CameraId>>;

SyncOptions Options() {
  SyncOptions o;
  o.deadline_us = 3 * kPeriod;
  o.silent_after_us = 10 * kPeriod;
  o.max_future_us = 100 * kPeriod;
  o.max_frame_ahead = 100;
  o.resync_after_rejections = 3;
  o.min_frame_interval_us = 0;  // the flooding test sets its own
  return o;
}

TEST_CASE("synchronizer releases a frame once every camera delivered, cameras sorted", "[unit]") {
  FrameSynchronizer sync({2, 0, 1}, Options());
  CHECK(sync.Add(At(1, 0)).actions.empty());
  CHECK(sync.Add(At(2, 0)).actions.empty());
  const SyncResult r = sync.Add(At(0, 0));
  CHECK(r.rejection == SyncRejection::kNone);
  CHECK(Released(r.actions) == Pairs{{0, 0}, {0, 1}, {0, 2}});
  CHECK(sync.Status().released_complete == 1);
  CHECK(sync.Status().pending_frames == 0);
}

TEST_CASE("synchronizer: a late camera is waited for until the deadline, then counted late",
          "[unit]") {
  FrameSynchronizer sync({0, 1}, Options());
  sync.Add(At(0, 0));
  // Camera 1 misses frame 0; frames 1 and 2 of camera 0 do not reach the deadline yet.
  CHECK(sync.Add(At(0, 1)).actions.empty());
  CHECK(sync.Add(At(0, 2)).actions.empty());
  // Frame 3 of camera 0 is 3 periods after frame 0: frame 0 is released without camera 1.
  const SyncResult r = sync.Add(At(0, 3));
  CHECK(Released(r.actions) == Pairs{{0, 0}});
  CHECK(sync.Status().released_by_deadline == 1);
  CHECK(sync.Status().cameras[1].missed == 1);
  // Its frame 0 arriving now is late; its frames 1-3 complete the pending frames.
  const SyncResult late = sync.Add(At(1, 0));
  CHECK(late.rejection == SyncRejection::kLate);
  CHECK(sync.Status().cameras[1].late == 1);
  CHECK(Released(sync.Add(At(1, 1)).actions) == Pairs{{1, 0}, {1, 1}});
}

TEST_CASE("synchronizer excludes a silent camera and re-includes it when it returns", "[unit]") {
  SyncOptions o = Options();
  FrameSynchronizer sync({0, 1}, o);
  for (FrameIndex f = 0; f < 3; ++f) {
    sync.Add(At(0, f));
    sync.Add(At(1, f));
  }
  // Camera 1 goes silent: frames wait for it only until it counts as silent.
  bool excluded = false;
  FrameIndex f = 3;
  for (; f < 30 && !excluded; ++f) {
    const SyncResult r = sync.Add(At(0, f));
    for (const CameraTransition& t : r.transitions) {
      CHECK(t.camera_id == 1);
      excluded = excluded || t.excluded;
    }
  }
  REQUIRE(excluded);
  CHECK(sync.Status().cameras[1].excluded);
  // Now a frame of camera 0 alone is released at once.
  const SyncResult alone = sync.Add(At(0, f));
  CHECK(Released(alone.actions).back() == std::make_pair(f, CameraId{0}));
  CHECK(sync.Status().pending_frames == 0);
  // Camera 1 returns with the next frame: re-included, and waited for again.
  const SyncResult back = sync.Add(At(1, f + 1));
  REQUIRE(back.transitions.size() == 1);
  CHECK_FALSE(back.transitions[0].excluded);
  CHECK(back.actions.empty());
  CHECK(Released(sync.Add(At(0, f + 1)).actions) == Pairs{{f + 1, 0}, {f + 1, 1}});
}

TEST_CASE("synchronizer rejects time going backwards, duplicates and far-future frames", "[unit]") {
  FrameSynchronizer sync({0, 1}, Options());
  sync.Add(At(0, 5));
  sync.Add(At(1, 5));
  sync.Add(At(0, 6));
  SECTION("backwards in utime and in frame index") {
    CHECK(sync.Add(Frame(0, 7, 1000000 + 4 * kPeriod, 3)).rejection == SyncRejection::kBackwards);
    CHECK(sync.Add(At(0, 4)).rejection == SyncRejection::kBackwards);
    CHECK(sync.Status().cameras[0].backwards == 2);
    CHECK(sync.Status().cameras[0].detections_rejected == 3);
  }
  SECTION("duplicates: same utime, or same frame index") {
    CHECK(sync.Add(At(0, 6)).rejection == SyncRejection::kDuplicate);
    CHECK(sync.Add(Frame(0, 6, 1000000 + 6 * kPeriod + 999)).rejection ==
          SyncRejection::kDuplicate);
    CHECK(sync.Status().cameras[0].duplicates == 2);
  }
  SECTION("far future in utime and in frame index") {
    CHECK(sync.Add(Frame(1, 7, 1000000 + 200 * kPeriod)).rejection == SyncRejection::kFarFuture);
    CHECK(sync.Add(Frame(1, 6 + 101, 1000000 + 7 * kPeriod)).rejection ==
          SyncRejection::kFarFuture);
    CHECK(sync.Status().cameras[1].far_future == 2);
  }
  SECTION("unknown cameras") {
    CHECK(sync.Add(At(9, 6)).rejection == SyncRejection::kUnknownCamera);
    CHECK(sync.Status().unknown_camera == 1);
  }
  // A rejection changes nothing: frame 6 still completes with camera 1.
  CHECK(Released(sync.Add(At(1, 6)).actions) == Pairs{{6, 0}, {6, 1}});
}

TEST_CASE("synchronizer drops frames closer than min_frame_interval_us (flooding)", "[unit]") {
  SyncOptions o = Options();
  o.mode = SyncMode::kUtime;
  o.tolerance_us = 1000;
  o.min_frame_interval_us = kPeriod / 2;
  FrameSynchronizer sync({0, 1}, o);
  int flooded = 0;
  for (FrameIndex f = 0; f < 10; ++f) {
    const Utime t = 1000000 + f * kPeriod;
    sync.Add(Frame(0, 0, t));
    sync.Add(Frame(1, 0, t + 200));
    // Camera 1 floods at 10x its rate.
    for (int i = 1; i < 10 && f < 9; ++i) {
      if (i * kPeriod / 10 >= kPeriod / 2) continue;  // these would be beyond the interval
      flooded +=
          sync.Add(Frame(1, 0, t + 200 + i * kPeriod / 10)).rejection == SyncRejection::kFlood;
    }
  }
  CHECK(flooded == 9 * 4);
  CHECK(sync.Status().cameras[1].flood == 9 * 4);
  CHECK(sync.Status().frames_released == 10);
}

TEST_CASE("synchronizer by utime groups within the tolerance and numbers the frames", "[unit]") {
  SyncOptions o = Options();
  o.mode = SyncMode::kUtime;
  o.tolerance_us = 2000;
  FrameSynchronizer sync({0, 1, 2}, o);
  // Free-running cameras: their own frame counters disagree; utimes within 1.5 ms.
  CHECK(sync.Add(Frame(0, 500, 1000000)).actions.empty());
  CHECK(sync.Add(Frame(2, 7, 1001500)).actions.empty());
  CHECK(sync.Add(Frame(2, 8, 1000900)).rejection == SyncRejection::kBackwards);
  const SyncResult r = sync.Add(Frame(1, 90, 999000));
  CHECK(Released(r.actions) == Pairs{{0, 0}, {0, 1}, {0, 2}});
  // Next frame: numbered 1 whatever the cameras' counters say.
  sync.Add(Frame(1, 91, 1040000));
  sync.Add(Frame(0, 501, 1039000));
  const SyncResult second = sync.Add(Frame(2, 9, 1041000));
  CHECK(Released(second.actions) == Pairs{{1, 0}, {1, 1}, {1, 2}});
  // Camera-frames for the released frame's time are late.
  CHECK(sync.Add(Frame(0, 502, 1040500)).rejection == SyncRejection::kLate);
  CHECK(sync.Add(Frame(1, 92, 1041500)).rejection == SyncRejection::kLate);
}

TEST_CASE("synchronizer output does not depend on the camera order within a frame", "[unit]") {
  const std::vector<std::vector<CameraId>> orders = {{0, 1, 2}, {2, 1, 0}, {1, 2, 0}};
  std::vector<Pairs> outputs;
  for (const auto& order : orders) {
    FrameSynchronizer sync({0, 1, 2}, Options());
    Pairs out;
    for (FrameIndex f = 0; f < 6; ++f) {
      for (const CameraId c : order) {
        for (const auto& p : Released(sync.Add(At(c, f)).actions)) out.push_back(p);
      }
    }
    for (const auto& p : Released(sync.Flush())) out.push_back(p);
    outputs.push_back(out);
  }
  CHECK(outputs[0] == outputs[1]);
  CHECK(outputs[0] == outputs[2]);
  CHECK(outputs[0].size() == 18);
}

TEST_CASE("synchronizer detects a stream restart when more than half of the cameras restart",
          "[unit]") {
  FrameSynchronizer sync({0, 1}, Options());  // resync_after_rejections = 3
  for (FrameIndex f = 100; f < 103; ++f) {
    sync.Add(At(0, f));
    sync.Add(At(1, f));
  }
  sync.Add(At(0, 103));  // pending: frame 103 waits for camera 1
  // The cameras restart at frame 0 with an earlier clock. Camera 0's third out-of-order frame
  // marks it restarted: one of two cameras is not more than half, so it starts over alone (its
  // frame 2 is then late: frame 102 was released).
  CHECK(sync.Add(At(0, 0)).rejection == SyncRejection::kBackwards);
  CHECK(sync.Add(At(0, 1)).rejection == SyncRejection::kBackwards);
  const SyncResult alone = sync.Add(At(0, 2));
  CHECK_FALSE(alone.resynced);
  CHECK(alone.rejection == SyncRejection::kLate);
  REQUIRE(alone.transitions.size() == 1);
  CHECK(alone.transitions[0].kind == CameraTransition::Kind::kRestart);
  CHECK(sync.Status().cameras[0].restarts == 1);
  // Camera 1 restarts too: two of two, the stream restarts.
  CHECK(sync.Add(At(1, 0)).rejection == SyncRejection::kBackwards);
  CHECK(sync.Add(At(1, 1)).rejection == SyncRejection::kBackwards);
  const SyncResult r = sync.Add(At(1, 2));
  CHECK(r.resynced);
  CHECK(r.rejection == SyncRejection::kNone);
  CHECK(Released(r.actions) == Pairs{{103, 0}, {-1, -1}});
  CHECK(sync.Status().resyncs == 1);
  CHECK(Released(sync.Add(At(0, 2)).actions) == Pairs{{2, 0}, {2, 1}});
}

// Four cameras at 25 Hz by frame index; camera 0's clock is `skew_us` off from frame `from` on.
// Returns, per released frame, the cameras it holds.
std::vector<std::vector<CameraId>> RunSkewed(FrameSynchronizer* sync,
                                             std::int64_t skew_us,
                                             FrameIndex from,
                                             FrameIndex frames,
                                             std::vector<CameraTransition>* transitions) {
  std::vector<std::vector<CameraId>> out;
  std::map<FrameIndex, std::vector<CameraId>> by_frame;
  for (FrameIndex f = 0; f < frames; ++f) {
    for (CameraId c = 0; c < 4; ++c) {
      core::CameraFrame cf = At(c, f);
      if (c == 0 && f >= from) cf.utime += skew_us;
      const SyncResult r = sync->Add(cf);
      for (const SyncAction& a : r.actions) {
        if (a.kind == SyncAction::Kind::kSubmit) {
          by_frame[a.frame.frame].push_back(a.frame.camera_id);
        }
      }
      transitions->insert(transitions->end(), r.transitions.begin(), r.transitions.end());
    }
  }
  for (auto& [f, cams] : by_frame) out.push_back(cams);
  return out;
}

TEST_CASE("clock model: one camera's skewed clock is flagged alone, the others keep tracking",
          "[unit]") {
  for (const std::int64_t skew : {std::int64_t{250000},
                                  std::int64_t{-250000},
                                  std::int64_t{2000000},
                                  std::int64_t{3600000000}}) {
    INFO("skew " << skew);
    FrameSynchronizer sync({0, 1, 2, 3}, Options());
    std::vector<CameraTransition> transitions;
    const auto released = RunSkewed(&sync, skew, 10, 100, &transitions);
    // Every frame is released with the three healthy cameras (the last one or two may still
    // pend); camera 0 is flagged within 10 of its frames and then rejected as clock offset.
    CHECK(released.size() >= 98);
    for (const auto& cams : released) {
      CHECK(std::count(cams.begin(), cams.end(), 1) == 1);
      CHECK(std::count(cams.begin(), cams.end(), 2) == 1);
      CHECK(std::count(cams.begin(), cams.end(), 3) == 1);
    }
    const SyncStatus st = sync.Status();
    CHECK(st.cameras[0].clock_flagged);
    CHECK(st.cameras[0].clock_offset >= 80);  // flagged within 10 of its 90 skewed frames
    CHECK(std::abs(st.cameras[0].offset_us - skew) < 2 * kPeriod);
    for (int c = 1; c < 4; ++c) {
      CHECK_FALSE(st.cameras[static_cast<std::size_t>(c)].clock_flagged);
      CHECK_FALSE(st.cameras[static_cast<std::size_t>(c)].excluded);
      CHECK(st.cameras[static_cast<std::size_t>(c)].late == 0);
    }
    CHECK(st.resyncs == 0);
    // The first clock transition flags camera 0 (it may also restart alone first: a clock that
    // jumps is out of order for a while).
    const auto clock = std::find_if(transitions.begin(), transitions.end(), [](const auto& t) {
      return t.kind == CameraTransition::Kind::kClock;
    });
    REQUIRE(clock != transitions.end());
    CHECK(clock->camera_id == 0);
    CHECK(clock->excluded);
    for (const CameraTransition& t : transitions) CHECK(t.camera_id == 0);
  }
}

TEST_CASE("clock model: a clock that comes back is included again, one message cannot move time",
          "[unit]") {
  FrameSynchronizer sync({0, 1, 2, 3}, Options());
  std::vector<CameraTransition> transitions;
  // Frames 0..39 with camera 0 two seconds ahead, then its clock is fixed (RunSkewed skews from
  // frame 10 on; run 40 frames skewed, then 40 frames clean by a second call on later frames).
  for (FrameIndex f = 0; f < 80; ++f) {
    for (CameraId c = 0; c < 4; ++c) {
      core::CameraFrame cf = At(c, f);
      if (c == 0 && f < 40) cf.utime += 2000000;
      const SyncResult r = sync.Add(cf);
      transitions.insert(transitions.end(), r.transitions.begin(), r.transitions.end());
    }
  }
  // Flagged, then cleared once the median of its offsets is back.
  REQUIRE(transitions.size() >= 2);
  CHECK(transitions[0].excluded);
  CHECK_FALSE(transitions.back().excluded);
  CHECK_FALSE(sync.Status().cameras[0].clock_flagged);
  // One far-future message from a healthy camera id is rejected and does not move the time.
  const SyncResult far = sync.Add(Frame(1, 80, At(1, 80).utime + 3600000000LL));
  CHECK(far.rejection == SyncRejection::kFarFuture);
  for (CameraId c = 0; c < 4; ++c) {
    const SyncResult r = sync.Add(At(c, 81));
    CHECK(r.rejection == SyncRejection::kNone);
  }
}

TEST_CASE("clock model: a step of the whole rig's time restarts the stream within 8 frames",
          "[unit]") {
  // Four cameras at 25 Hz; from frame 50 on every camera's clock steps by `step_us`, or every
  // frame counter starts again at 0. Before issue 39 the cameras flagged each other's clocks
  // against the old time and no frame was released again.
  struct Case {
    const char* name;
    std::int64_t step_us;
    bool reset_counters;
  };
  for (const Case& c : {Case{"-2 s", -2000000, false},
                        Case{"-1 h", -3600000000LL, false},
                        Case{"+1 h", 3600000000LL, false},
                        Case{"counters reset", 0, true}}) {
    for (const SyncMode mode : {SyncMode::kFrameIndex, SyncMode::kUtime}) {
      if (c.reset_counters && mode == SyncMode::kUtime) continue;  // utimes go on: no step
      INFO(c.name << (mode == SyncMode::kUtime ? " utime" : " frame_index"));
      SyncOptions o = Options();
      o.mode = mode;
      o.resync_after_rejections = 30;  // the default: a camera restarts alone after 30
      FrameSynchronizer sync({0, 1, 2, 3}, o);
      int released_after = 0;
      int resync_frame = -1;
      for (FrameIndex f = 0; f < 120; ++f) {
        for (CameraId cam = 0; cam < 4; ++cam) {
          core::CameraFrame cf = At(cam, f);
          if (f >= 50) {
            cf.utime += c.step_us;
            if (c.reset_counters) cf.frame = f - 50;
          }
          const SyncResult r = sync.Add(cf);
          if (r.resynced && resync_frame < 0) resync_frame = static_cast<int>(f);
          for (const SyncAction& a : r.actions) {
            if (a.kind == SyncAction::Kind::kSubmit && resync_frame >= 0) ++released_after;
          }
        }
      }
      const SyncStatus st = sync.Status();
      CHECK(st.resyncs == 1);
      CHECK(resync_frame >= 50);
      CHECK(resync_frame <= 50 + FrameSynchronizer::kStreamVoteRejections);
      // Every camera-frame from the restart on is released (the last frames may still pend).
      CHECK(released_after >= 4 * (120 - resync_frame - 2));
      for (const SyncCameraStatus& cs : st.cameras) {
        CHECK_FALSE(cs.clock_flagged);
        CHECK_FALSE(cs.excluded);
      }
    }
  }
}

TEST_CASE("clock model: a slow rig's time step restarts the stream within 1.5 s", "[unit]") {
  // Four cameras at 2 fps (WILDTRACK's rate): 8 frames would be 4 s; 3 frames spanning 1 s of
  // the cameras' own capture time are enough (FrameSynchronizer::kStreamVoteSpanUs).
  constexpr std::int64_t kSlow = 500000;
  SyncOptions o = Options();
  o.resync_after_rejections = 30;
  o.deadline_us = 3 * kSlow;
  o.silent_after_us = 10 * kSlow;
  o.max_future_us = 100 * kSlow;
  o.min_frame_interval_us = 0;
  FrameSynchronizer sync({0, 1, 2, 3}, o);
  int resync_frame = -1;
  for (FrameIndex f = 0; f < 40; ++f) {
    for (CameraId cam = 0; cam < 4; ++cam) {
      Utime utime = 1000000 + f * kSlow + cam * 100;
      if (f >= 20) utime -= 2000000;  // every clock steps back 2 s
      if (sync.Add(Frame(cam, f, utime)).resynced && resync_frame < 0) {
        resync_frame = static_cast<int>(f);
      }
    }
  }
  CHECK(sync.Status().resyncs == 1);
  CHECK(resync_frame >= 20);
  CHECK((resync_frame - 20) * kSlow <= 1500000);
}

TEST_CASE("clock model: one camera stuck on a bogus time does not get the others flagged",
          "[unit]") {
  // Camera 0's first message is an hour ahead; its real frames are then backwards until it
  // restarts alone (resync_after_rejections, 30). Its stale frame must not be the quorum the
  // other cameras are judged by: by frame index they would soon look 10 frames off.
  SyncOptions o = Options();
  o.resync_after_rejections = 30;
  FrameSynchronizer sync({0, 1, 2}, o);
  core::CameraFrame ahead = At(0, 0);
  ahead.utime += 3600000000LL;
  sync.Add(ahead);
  for (FrameIndex f = 0; f < 60; ++f) {
    for (CameraId cam = 0; cam < 3; ++cam) sync.Add(At(cam, f));
  }
  const SyncStatus st = sync.Status();
  CHECK(st.resyncs == 0);
  CHECK(st.cameras[0].restarts == 1);
  CHECK(st.cameras[1].clock_offset == 0);
  CHECK(st.cameras[2].clock_offset == 0);
  CHECK_FALSE(st.cameras[1].clock_flagged);
  CHECK_FALSE(st.cameras[2].clock_flagged);
}

TEST_CASE("synchronizer: every camera-frame is submitted or in exactly one rejection counter",
          "[unit]") {
  // Issue 39: after a camera restarted alone, a few accepted camera-frames appeared in no
  // counter. Random time faults (restarts, jumps, repeats, stale bursts) in both modes.
  for (const SyncMode mode : {SyncMode::kFrameIndex, SyncMode::kUtime}) {
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
      INFO((mode == SyncMode::kUtime ? "utime" : "frame_index") << " seed " << seed);
      SyncOptions o = Options();
      o.mode = mode;
      FrameSynchronizer sync({0, 1, 2}, o);
      std::mt19937 rng(seed);
      std::uniform_int_distribution<int> pick(0, 99);
      std::map<CameraId, std::int64_t> added, submitted;
      std::map<CameraId, FrameIndex> frame{{0, 0}, {1, 0}, {2, 0}};
      const auto count = [&](const std::vector<SyncAction>& actions) {
        for (const SyncAction& a : actions) {
          if (a.kind == SyncAction::Kind::kSubmit) ++submitted[a.frame.camera_id];
        }
      };
      for (int step = 0; step < 600; ++step) {
        const CameraId cam = static_cast<CameraId>(pick(rng) % 3);
        const int fault = pick(rng);
        FrameIndex& f = frame[cam];
        if (fault < 3) {
          f = std::max<FrameIndex>(0, f - 20);  // a restart: the counter and clock go back
        } else if (fault < 5) {
          f += 50;  // a jump ahead
        } else if (fault < 10) {
          // a repeat of its previous frame (no advance)
        } else {
          ++f;
        }
        ++added[cam];
        count(sync.Add(At(cam, f)).actions);
      }
      count(sync.Flush());
      const SyncStatus st = sync.Status();
      for (const SyncCameraStatus& c : st.cameras) {
        INFO("camera " << c.camera_id);
        CHECK(c.accepted == submitted[c.camera_id]);
        CHECK(added[c.camera_id] == c.accepted + c.backwards + c.duplicates + c.far_future +
                                        c.late + c.flood + c.clock_offset);
      }
    }
  }
}

TEST_CASE("clock model: a frame counter running fast is caught", "[unit]") {
  FrameSynchronizer sync({0, 1, 2, 3}, Options());
  std::size_t released_healthy = 0;
  for (FrameIndex f = 0; f < 100; ++f) {
    for (CameraId c = 0; c < 4; ++c) {
      core::CameraFrame cf = At(c, f);
      if (c == 0 && f >= 10) cf.frame = 10 + (f - 10) * 10;  // ten times fast
      for (const SyncAction& a : sync.Add(cf).actions) {
        if (a.kind == SyncAction::Kind::kSubmit && a.frame.camera_id != 0) ++released_healthy;
      }
    }
  }
  const SyncStatus st = sync.Status();
  CHECK(st.cameras[0].clock_flagged);
  CHECK(st.resyncs == 0);
  for (int c = 1; c < 4; ++c) CHECK(st.cameras[static_cast<std::size_t>(c)].late == 0);
  CHECK(released_healthy >= 3 * 98);
}

TEST_CASE("synchronizer counts the frames a camera never sent as lost", "[unit]") {
  // Frame index: camera 1 skips frames 5, 6 and 7.
  FrameSynchronizer by_frame({0, 1, 2}, Options());
  for (FrameIndex f = 0; f < 12; ++f) {
    for (CameraId c = 0; c < 3; ++c) {
      if (c == 1 && f >= 5 && f <= 7) continue;
      by_frame.Add(At(c, f));
    }
  }
  CHECK(by_frame.Status().cameras[1].lost == 3);
  CHECK(by_frame.Status().cameras[0].lost == 0);
  // By utime: camera 2 misses two frames after its period is known (8 steps).
  SyncOptions o = Options();
  o.mode = SyncMode::kUtime;
  FrameSynchronizer by_utime({0, 1, 2}, o);
  for (FrameIndex f = 0; f < 20; ++f) {
    for (CameraId c = 0; c < 3; ++c) {
      if (c == 2 && (f == 12 || f == 13)) continue;
      by_utime.Add(At(c, f));
    }
  }
  CHECK(by_utime.Status().cameras[2].lost == 2);
  CHECK(by_utime.Status().cameras[1].lost == 0);
}

TEST_CASE("synchronizer arithmetic saturates on extreme times and frames", "[unit]") {
  for (const SyncMode mode : {SyncMode::kFrameIndex, SyncMode::kUtime}) {
    SyncOptions o = Options();
    o.mode = mode;
    FrameSynchronizer sync({0, 1, 2}, o);
    const std::int64_t big = std::numeric_limits<std::int64_t>::max();
    const std::int64_t small = std::numeric_limits<std::int64_t>::min();
    for (FrameIndex f = 0; f < 20; ++f) {
      for (CameraId c = 0; c < 3; ++c) sync.Add(At(c, f));
    }
    for (const auto& [frame, utime] : std::vector<std::pair<std::int64_t, std::int64_t>>{
             {big, big}, {small, small}, {big, small}, {small, big}, {0, big}, {big, 0}}) {
      sync.Add(Frame(1, frame, utime));
      sync.Add(Frame(2, frame, utime));
    }
    // The healthy stream goes on.
    std::size_t released = 0;
    for (FrameIndex f = 20; f < 40; ++f) {
      for (CameraId c = 0; c < 3; ++c) released += sync.Add(At(c, f)).actions.size();
    }
    CHECK(released > 0);
    sync.Flush();
  }
}

TEST_CASE("synchronizer bounds the pending frames", "[unit]") {
  SyncOptions o = Options();
  o.max_pending_frames = 4;
  o.deadline_us = 1000 * kPeriod;
  o.silent_after_us = 1000 * kPeriod;
  FrameSynchronizer sync({0, 1}, o);
  std::size_t released = 0;
  for (FrameIndex f = 0; f < 50; ++f) {
    released += sync.Add(At(0, f)).actions.size();
    CHECK(sync.Status().pending_frames <= 4);
  }
  CHECK(released == 46);
  CHECK(sync.Status().released_by_bound == 46);
  CHECK(Released(sync.Flush()).size() == 4);
  CHECK(sync.Status().pending_frames == 0);
}

}  // namespace
}  // namespace mvtrack::service
