// Service (the daemon runtime) driven in-process: the published tracks equal tracker::Tracker's
// for 1, 2 and 8 workers; bad input is counted and reported in the status message with its
// flags; the status period and the idle flush follow the wall clock; a reload switches the
// tracker options with increasing track ids; the record log holds input and output; the LCM
// edge works over memq://.

#include "service/service.h"

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <mvtrack/tracker_status_t.hpp>
#include <string>
#include <thread>
#include <vector>

#include "analytics/site_analytics.h"
#include "config/config_test_util.h"
#include "geometry/camera_rig.h"
#include "service/daemon_config.h"
#include "service/lcm_runner.h"
#include "service/status_check.h"
#include "sim/synthetic_scene.h"
#include "tracker/tracker.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::service {
namespace {

const sim::Scene& Scene() {
  static const sim::Scene scene = [] {
    sim::SceneOptions o;
    o.seed = 11;
    o.num_cameras = 3;
    o.num_people = 3;
    o.num_frames = 90;
    o.poses = false;
    o.pixel_noise_px = 1.0;
    o.miss_rate = 0.05;
    o.false_positives_per_frame = 0.2;
    return sim::GenerateScene(o);
  }();
  return scene;
}

DaemonConfig Config(int workers) {
  DaemonConfig c;
  c.cameras = Scene().cameras;
  c.workers = workers;
  c.camera_overflow = pipeline::OverflowPolicy::kBlock;
  c.sync.idle_flush_s = 0.0;
  c.tracker.mode = tracker::InputMode::kBoxes;
  return c;
}

std::vector<std::uint8_t> Encode(const core::CameraFrame& f) {
  return transport::EncodeCameraDetections(
      f, Scene().options.image_width_px, Scene().options.image_height_px);
}

// What a Service published, collected from its hooks (thread-safe).
struct Sink {
  std::mutex mu;
  std::vector<std::string> lines;                     // on_frame, canonical JSONL
  std::vector<transport::TracksMessage> tracks;       // decoded tracks3d_t
  std::vector<transport::TracksMessage> provisional;  // decoded MVTRACK_TRACKS_NOW
  std::vector<std::string> provisional_lines;         // on_provisional, canonical JSONL
  std::vector<mvtrack::tracker_status_t> statuses;    // decoded tracker_status_t
  std::map<std::string, int> channels;
  std::map<std::string, std::vector<std::vector<std::uint8_t>>> other;  // other channels, raw
  int undecodable = 0;  // published messages that did not decode (checked on the test thread)

  ServiceHooks Hooks(const pipeline::Clock* clock) {
    ServiceHooks h;
    h.wall_clock = clock;
    h.version = "test-1";
    h.publish = [this](const std::string& channel, const std::vector<std::uint8_t>& data) {
      std::lock_guard<std::mutex> lock(mu);
      ++channels[channel];
      if (channel == "MVTRACK_TRACKS") {
        transport::TracksDecodeResult r = transport::DecodeTracks(data.data(), data.size());
        if (!r.ok()) {
          ++undecodable;
          return;
        }
        tracks.push_back(std::move(r.message));
      } else if (channel == transport::kProvisionalChannel) {
        transport::TracksDecodeResult r = transport::DecodeTracks(data.data(), data.size());
        if (!r.ok()) {
          ++undecodable;
          return;
        }
        provisional.push_back(std::move(r.message));
      } else if (channel != "MVTRACK_STATUS") {
        other[channel].push_back(data);
      } else {
        mvtrack::tracker_status_t s;
        if (s.decode(data.data(), 0, static_cast<int>(data.size())) !=
            static_cast<int>(data.size())) {
          ++undecodable;
          return;
        }
        statuses.push_back(s);
      }
    };
    h.on_frame = [this](const tracker::Frame3D& f, core::KeypointLayoutId layout) {
      std::lock_guard<std::mutex> lock(mu);
      lines.push_back(transport::TracksJsonLine(f, layout));
    };
    h.on_provisional = [this](const tracker::Frame3D& f, core::KeypointLayoutId layout) {
      std::lock_guard<std::mutex> lock(mu);
      provisional_lines.push_back(transport::TracksJsonLine(f, layout));
    };
    return h;
  }
};

// tracker::Tracker's output lines for the scene (`provisional`: its provisional layer's).
std::vector<std::string> ReferenceLines(bool provisional = false) {
  std::string why;
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kBoxes;
  auto t = tracker::Tracker::Create(
      geometry::CameraRig(Scene().cameras), options, &why, /*provisional=*/true);
  REQUIRE(t);
  std::vector<std::string> lines;
  for (const auto& cams : Scene().detections) {
    for (const core::CameraFrame& f : cams) {
      const std::vector<std::uint8_t> bytes = Encode(f);
      const transport::DecodeResult d =
          transport::DecodeCameraDetections(bytes.data(), bytes.size());
      REQUIRE(d.ok());
      for (const tracker::Frame3D& out : t->Add(d.frame).finalized) {
        lines.push_back(transport::TracksJsonLine(out, core::KeypointLayoutId::kNone));
      }
    }
  }
  for (const tracker::Frame3D& out : t->Flush()) {
    lines.push_back(transport::TracksJsonLine(out, core::KeypointLayoutId::kNone));
  }
  if (!provisional) return lines;
  lines.clear();
  for (const tracker::Frame3D& out : t->TakeProvisional()) {
    lines.push_back(transport::TracksJsonLine(out, core::KeypointLayoutId::kNone));
  }
  return lines;
}

// Feeds frames [begin, end) of the scene, camera by camera, advancing `clock` to each utime.
void Feed(Service* s, pipeline::ManualClock* clock, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    for (const core::CameraFrame& f : Scene().detections[i]) {
      clock->SetMicros(f.utime + 1000);
      const std::vector<std::uint8_t> bytes = Encode(f);
      s->OnMessage(transport::DetectionsChannelForCamera(f.camera_id), bytes.data(), bytes.size());
    }
  }
}

TEST_CASE("service publishes exactly tracker::Tracker's frames with 1, 2 and 8 workers",
          "[threads]") {
  const std::vector<std::string> reference = ReferenceLines();
  REQUIRE(reference.size() == Scene().detections.size());
  for (const int workers : {1, 2, 8}) {
    INFO("workers " << workers);
    pipeline::ManualClock clock(Scene().detections[0][0].utime);
    Sink sink;
    std::string why;
    std::unique_ptr<Service> s = Service::Create(Config(workers), sink.Hooks(&clock), &why);
    REQUIRE(s);
    Feed(s.get(), &clock, 0, Scene().detections.size());
    s->EndOfInput();
    const ServiceCounters c = s->Counters();
    s->Stop();
    CHECK(sink.undecodable == 0);
    CHECK(sink.lines == reference);
    REQUIRE(sink.tracks.size() == reference.size());
    for (std::size_t i = 0; i < sink.tracks.size(); ++i) {
      CHECK(sink.tracks[i].frame.frame == static_cast<FrameIndex>(i));
      CHECK(sink.tracks[i].latency_us >= 0);
      CHECK(sink.tracks[i].publish_utime >= Scene().detections[0][0].utime);
    }
    CHECK(c.frames_published == static_cast<std::int64_t>(reference.size()));
    // The provisional layer on its own channel, flagged, the Tracker's bit for bit.
    CHECK(sink.provisional_lines == ReferenceLines(/*provisional=*/true));
    REQUIRE(sink.provisional.size() == reference.size());
    std::size_t provisional_tracks = 0;
    for (const transport::TracksMessage& m : sink.provisional) {
      CHECK(m.layer == transport::TracksLayer::kProvisional);
      provisional_tracks += m.frame.tracks.size();
    }
    CHECK(provisional_tracks > 0);
    for (const transport::TracksMessage& m : sink.tracks) {
      CHECK(m.layer == transport::TracksLayer::kFinal);
    }
    CHECK(c.provisional_published == static_cast<std::int64_t>(reference.size()));
    CHECK(c.submitted == static_cast<std::int64_t>(3 * reference.size()));
    CHECK(c.pipeline.executor.num_workers == workers);
    CHECK(c.decode_errors == 0);
  }
}

TEST_CASE("service: output.provisional_channel \"\" computes and publishes no provisional layer",
          "[unit]") {
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  std::string why;
  DaemonConfig config = Config(1);
  config.provisional_channel.clear();
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  Feed(s.get(), &clock, 0, Scene().detections.size());
  s->EndOfInput();
  const ServiceCounters c = s->Counters();
  s->Stop();
  CHECK(c.frames_published == static_cast<std::int64_t>(Scene().detections.size()));
  CHECK(c.provisional_published == 0);
  CHECK(sink.provisional.empty());
  CHECK(sink.channels.count(transport::kProvisionalChannel) == 0);
}

TEST_CASE("service counts bad input and reports it in the status message", "[unit]") {
  pipeline::ManualClock clock(5000000);
  Sink sink;
  std::string why;
  DaemonConfig config = Config(1);
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  const std::vector<std::uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  s->OnMessage("MVTRACK_DETECTIONS_1", garbage.data(), garbage.size());
  s->OnMessage("SOMETHING_ELSE", garbage.data(), garbage.size());
  core::CameraFrame of2 = Scene().detections[0][2];
  const std::vector<std::uint8_t> wrong_channel = Encode(of2);
  s->OnMessage("MVTRACK_DETECTIONS_1", wrong_channel.data(), wrong_channel.size());
  core::CameraFrame unknown = Scene().detections[0][0];
  unknown.camera_id = 9;
  const std::vector<std::uint8_t> unknown_bytes = Encode(unknown);
  s->OnMessage("MVTRACK_DETECTIONS", unknown_bytes.data(), unknown_bytes.size());
  // Cameras 0 and 1 deliver 10 frames; camera 2 never does; one frame of camera 0 repeats.
  for (std::size_t i = 0; i < 10; ++i) {
    for (int c = 0; c < 2; ++c) {
      const std::vector<std::uint8_t> b =
          Encode(Scene().detections[i][static_cast<std::size_t>(c)]);
      s->OnMessage(transport::DetectionsChannelForCamera(c), b.data(), b.size());
    }
  }
  const std::vector<std::uint8_t> again = Encode(Scene().detections[9][0]);
  s->OnMessage("MVTRACK_DETECTIONS", again.data(), again.size());
  clock.SetMicros(7000000);  // a 2 s status period

  const ServiceCounters c = s->Counters();
  CHECK(c.messages == 25);
  CHECK(c.foreign_messages == 1);
  CHECK(c.decode_errors == 1);
  CHECK(c.channel_mismatches == 1);
  CHECK(c.sync.unknown_camera == 1);
  CHECK(c.sync_rejections.at("duplicate") == 1);

  mvtrack::tracker_status_t st;
  const std::vector<std::uint8_t> bytes = s->BuildStatus();
  REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  CHECK(st.utime == 7000000);
  CHECK(st.period_us == 2000000);
  CHECK(st.version == "test-1");
  CHECK(st.config_hash == DaemonConfigHash(config));
  REQUIRE(st.num_cameras == 3);
  CHECK(st.cameras[0].camera_id == 0);
  CHECK(st.cameras[0].received == 11);
  CHECK(st.cameras[0].rate_hz == Approx(5.5));
  REQUIRE_FALSE(Scene().detections[9][0].detections.empty());
  CHECK(st.cameras[0].rejected ==
        static_cast<std::int64_t>(Scene().detections[9][0].detections.size()) +
            c.pipeline.cameras[0].detections_rejected);
  CHECK((st.cameras[0].flags & mvtrack::camera_status_t::FLAG_REJECTING) != 0);
  CHECK(st.cameras[1].received == 10);
  CHECK(st.cameras[1].decode_errors == 2);  // garbage + a camera-2 frame on camera 1's channel
  CHECK((st.cameras[1].flags & mvtrack::camera_status_t::FLAG_DECODE_ERRORS) != 0);
  CHECK(st.cameras[2].received == 0);
  CHECK((st.cameras[2].flags & mvtrack::camera_status_t::FLAG_NO_DATA) != 0);
  CHECK((st.flags & mvtrack::tracker_status_t::FLAG_CAMERA_MISSING) != 0);
  CHECK((st.flags & mvtrack::tracker_status_t::FLAG_INPUT_LOSS) != 0);
  CHECK(st.cameras[0].queue_capacity == config.camera_queue_capacity);

  // The next period has no new errors: the per-period flags clear, the counters stay.
  clock.SetMicros(8000000);
  const std::vector<std::uint8_t> next = s->BuildStatus();
  REQUIRE(st.decode(next.data(), 0, static_cast<int>(next.size())) ==
          static_cast<int>(next.size()));
  CHECK(st.period_us == 1000000);
  CHECK(st.cameras[1].decode_errors == 2);
  CHECK((st.cameras[1].flags & mvtrack::camera_status_t::FLAG_DECODE_ERRORS) == 0);
  CHECK((st.cameras[0].flags & mvtrack::camera_status_t::FLAG_REJECTING) == 0);
  CHECK(st.cameras[0].rate_hz == 0.0f);
  s->Stop();
}

TEST_CASE("service status carries each camera's lost frames and clock offset", "[unit]") {
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  std::string why;
  std::unique_ptr<Service> s = Service::Create(Config(1), sink.Hooks(&clock), &why);
  REQUIRE(s);
  // Camera 2 never sends frames 20, 21 and 22 and its clock runs 20 ms ahead (inside the
  // tolerance: measured, not flagged); cameras 0 and 1 are clean.
  constexpr Utime kAhead = 20000;
  for (std::size_t i = 0; i < 40; ++i) {
    for (core::CameraFrame f : Scene().detections[i]) {
      if (f.camera_id == 2 && i >= 20 && i <= 22) continue;
      if (f.camera_id == 2) f.utime += kAhead;
      clock.SetMicros(f.utime + 1000);
      const std::vector<std::uint8_t> bytes = Encode(f);
      s->OnMessage(transport::DetectionsChannelForCamera(f.camera_id), bytes.data(), bytes.size());
    }
  }
  mvtrack::tracker_status_t st;
  const std::vector<std::uint8_t> bytes = s->BuildStatus();
  REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  REQUIRE(st.num_cameras == 3);
  CHECK(st.cameras[0].lost == 0);
  CHECK(st.cameras[1].lost == 0);
  CHECK(st.cameras[2].lost == 3);
  CHECK((st.cameras[0].flags & mvtrack::camera_status_t::FLAG_LOSING) == 0);
  CHECK((st.cameras[2].flags & mvtrack::camera_status_t::FLAG_LOSING) != 0);
  CHECK((st.cameras[2].flags & mvtrack::camera_status_t::FLAG_CLOCK_OFFSET) == 0);
  // Each camera is compared, as its frame arrives, with the others' newest capture times: camera
  // 2 sends last, so it meets frame i in both others; camera 0 sends first and meets frame i - 1,
  // one frame period behind (the arrival order is in the estimate, up to one period).
  const Utime period = Scene().detections[1][0].utime - Scene().detections[0][0].utime;
  CHECK(st.cameras[2].clock_offset_us == kAhead);
  CHECK(st.cameras[0].clock_offset_us == period);
  // The next period loses nothing: the flag clears, the counter stays.
  clock.SetMicros(clock.NowMicros() + 1000000);
  const std::vector<std::uint8_t> next = s->BuildStatus();
  REQUIRE(st.decode(next.data(), 0, static_cast<int>(next.size())) ==
          static_cast<int>(next.size()));
  CHECK(st.cameras[2].lost == 3);
  CHECK((st.cameras[2].flags & mvtrack::camera_status_t::FLAG_LOSING) == 0);
  s->Stop();
}

TEST_CASE("service status carries the appearance counters, per camera, across a reload", "[unit]") {
  static const sim::Scene scene = [] {
    sim::SceneOptions o = Scene().options;
    o.embedding_dim = 32;
    return sim::GenerateScene(o);
  }();
  pipeline::ManualClock clock(scene.detections[0][0].utime);
  Sink sink;
  std::string why;
  DaemonConfig config = Config(1);
  config.tracker.appearance.enabled = true;
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  // Camera 1's embeddings are unusable in frames 10-19: NaN in even frames (dropped by
  // validation), a zero vector in odd ones (dropped by the stream check).
  std::int64_t spoiled = 0;
  const auto feed = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      for (core::CameraFrame f : scene.detections[i]) {
        if (f.camera_id == 1 && i >= 10 && i < 20) {
          for (core::Detection2D& d : f.detections) {
            REQUIRE(d.embedding.size() == 32);
            std::fill(d.embedding.begin(), d.embedding.end(), i % 2 == 0 ? NAN : 0.0f);
            ++spoiled;
          }
        }
        clock.SetMicros(f.utime + 1000);
        const std::vector<std::uint8_t> bytes = Encode(f);
        s->OnMessage(
            transport::DetectionsChannelForCamera(f.camera_id), bytes.data(), bytes.size());
      }
    }
  };
  const auto status = [&] {
    mvtrack::tracker_status_t st;
    s->EndOfInput();
    const std::vector<std::uint8_t> bytes = s->BuildStatus();
    REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
            static_cast<int>(bytes.size()));
    return st;
  };
  feed(0, 45);
  REQUIRE(spoiled > 0);
  mvtrack::tracker_status_t st = status();
  REQUIRE(st.num_cameras == 3);
  CHECK(st.embeddings_dropped == spoiled);
  CHECK(st.cameras[1].embeddings_dropped == spoiled);
  CHECK(st.cameras[0].embeddings_dropped == 0);
  CHECK(st.cameras[2].embeddings_dropped == 0);
  CHECK((st.cameras[1].flags & mvtrack::camera_status_t::FLAG_BAD_EMBEDDINGS) != 0);
  CHECK((st.cameras[0].flags & mvtrack::camera_status_t::FLAG_BAD_EMBEDDINGS) == 0);
  CHECK(st.cameras[1].rejected == 0);  // the detections were kept, without their embeddings
  const std::int64_t used_before = st.embeddings_used;
  CHECK(used_before > 0);
  CHECK(st.gallery_bytes > 0);
  CHECK(st.gallery_bytes % static_cast<std::int64_t>(32 * sizeof(float)) == 0);

  // A reload starts a new pipeline; the cumulative counters continue, the flag clears.
  DaemonConfig next = config;
  next.tracker.appearance.reid_margin = 0.1;
  REQUIRE(s->Reload(next, &why));
  feed(45, 90);
  st = status();
  CHECK(st.embeddings_dropped == spoiled);
  CHECK(st.cameras[1].embeddings_dropped == spoiled);
  CHECK((st.cameras[1].flags & mvtrack::camera_status_t::FLAG_BAD_EMBEDDINGS) == 0);
  CHECK(st.embeddings_used > used_before);
  CHECK(st.gallery_bytes > 0);
  s->Stop();
}

TEST_CASE("service status: appearance off reports no embeddings and no galleries", "[unit]") {
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  std::string why;
  std::unique_ptr<Service> s = Service::Create(Config(1), sink.Hooks(&clock), &why);
  REQUIRE(s);
  Feed(s.get(), &clock, 0, 45);
  s->EndOfInput();
  mvtrack::tracker_status_t st;
  const std::vector<std::uint8_t> bytes = s->BuildStatus();
  REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  CHECK(st.embeddings_used == 0);
  CHECK(st.embeddings_dropped == 0);
  CHECK(st.tracks_revived == 0);
  CHECK(st.gallery_bytes == 0);
  s->Stop();
}

TEST_CASE("service: status period and idle flush follow the wall clock", "[unit]") {
  const Utime t0 = Scene().detections[0][0].utime;
  pipeline::ManualClock clock(t0);
  Sink sink;
  std::string why;
  DaemonConfig config = Config(1);
  config.sync.idle_flush_s = 2.0;
  config.status_period_s = 1.0;
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  clock.SetMicros(t0 + 500000);
  s->Tick();
  CHECK(sink.statuses.empty());
  clock.SetMicros(t0 + 1000000);
  s->Tick();
  CHECK(sink.statuses.size() == 1);
  // 40 frames: the first window is complete, later frames wait for theirs.
  Feed(s.get(), &clock, 0, 40);
  const std::int64_t before = s->Counters().frames_published;
  CHECK(before < 40);
  const Utime last = clock.NowMicros();
  clock.SetMicros(last + 1999999);
  s->Tick();
  CHECK(s->Counters().idle_flushes == 0);
  clock.SetMicros(last + 2000000);
  s->Tick();
  const ServiceCounters c = s->Counters();
  CHECK(c.idle_flushes == 1);
  CHECK(c.frames_published == 40);
  s->Tick();  // once per idle period
  CHECK(s->Counters().idle_flushes == 1);
  s->Stop();
  // A final status at Stop.
  CHECK(sink.channels["MVTRACK_STATUS"] >= 3);
}

TEST_CASE("service: NO_OUTPUT when cameras deliver and nothing is published for 3 s", "[unit]") {
  const Utime t0 = Scene().detections[0][0].utime;
  pipeline::ManualClock clock(t0);
  Sink sink;
  std::string why;
  DaemonConfig config = Config(1);
  config.sync.idle_flush_s = 0.0;
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  const auto flags = [&] {
    mvtrack::tracker_status_t st;
    const std::vector<std::uint8_t> bytes = s->BuildStatus();
    REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
            static_cast<int>(bytes.size()));
    return st.flags;
  };
  // 40 frames over 1.6 s: the first window is published (by the pipeline's threads), no flag.
  Feed(s.get(), &clock, 0, 40);
  // Wait until the first window's frames are all out (the count stays put for 1 s: under the
  // load of a parallel test run 200 ms were not enough, and a late publish moves the time the
  // flag is due).
  std::int64_t published = 0;
  for (int wait = 0, stable = 0; wait < 1000 && (published == 0 || stable < 20); ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const std::int64_t now_published = s->Counters().frames_published;
    stable = now_published == published ? stable + 1 : 0;
    published = now_published;
  }
  REQUIRE(published > 0);
  CHECK((flags() & mvtrack::tracker_status_t::FLAG_NO_OUTPUT) == 0);
  // Every camera keeps re-sending its frame 39 (each rejected as a duplicate): input arrives,
  // nothing more is published. Flagged once 3 s have passed since the last publish: the time
  // the last tracks message carries, which is earlier than the clock when the pipeline's
  // threads published while Feed was still moving the clock (a loaded machine).
  Utime last_publish = 0;
  {
    std::lock_guard<std::mutex> lock(sink.mu);
    REQUIRE(!sink.tracks.empty());
    last_publish = sink.tracks.back().publish_utime;
  }
  REQUIRE(last_publish <= clock.NowMicros());
  const Utime resend_from = clock.NowMicros();
  for (int k = 1; k <= 40; ++k) {
    clock.SetMicros(std::max(resend_from, last_publish + k * 100'000));
    for (const core::CameraFrame& f : Scene().detections[39]) {
      const std::vector<std::uint8_t> bytes = Encode(f);
      s->OnMessage(transport::DetectionsChannelForCamera(f.camera_id), bytes.data(), bytes.size());
    }
    const bool flagged = (flags() & mvtrack::tracker_status_t::FLAG_NO_OUTPUT) != 0;
    INFO("at " << k * 100 << " ms");
    CHECK(flagged == (k * 100'000 >= service::kNoOutputAfterUs));
  }
  // Input stops too: not NO_OUTPUT any more, the cameras' own flags tell that story: nothing
  // received for silent_after_us of wall clock is STALE even though capture time stopped with
  // them, so the health is CRITICAL (issue 39: every camera still counted as delivering).
  clock.SetMicros(clock.NowMicros() + 3'000'000);
  mvtrack::tracker_status_t st;
  const std::vector<std::uint8_t> bytes = s->BuildStatus();
  REQUIRE(st.decode(bytes.data(), 0, static_cast<int>(bytes.size())) ==
          static_cast<int>(bytes.size()));
  CHECK((st.flags & mvtrack::tracker_status_t::FLAG_NO_OUTPUT) == 0);
  CHECK((st.flags & mvtrack::tracker_status_t::FLAG_CAMERA_MISSING) != 0);
  for (const mvtrack::camera_status_t& c : st.cameras) {
    CHECK((c.flags & mvtrack::camera_status_t::FLAG_STALE) != 0);
  }
  const transport::StatusDecodeResult decoded =
      transport::DecodeTrackerStatus(bytes.data(), bytes.size());
  REQUIRE(decoded.ok());
  CHECK(service::AssessStatus(decoded.message).health == service::Health::kCritical);
  s->Stop();
}

TEST_CASE("service reload switches the tracker options, track ids keep increasing", "[unit]") {
  const Utime t0 = Scene().detections[0][0].utime;
  pipeline::ManualClock clock(t0);
  Sink sink;
  std::string why;
  std::unique_ptr<Service> s = Service::Create(Config(2), sink.Hooks(&clock), &why);
  REQUIRE(s);
  Feed(s.get(), &clock, 0, 45);

  DaemonConfig bad = Config(2);
  bad.tracker.window_step = 40;  // > window_size: invalid
  CHECK_FALSE(s->Reload(bad, &why));
  CHECK_THAT(why, Catch::Contains("window_step"));
  CHECK(s->config().tracker.window_step == 20);

  DaemonConfig next = Config(2);
  next.tracker.window_step = 10;
  next.job_queue_capacity = 3;  // restart-only
  next.log_repeat_interval_s = 1.0;
  REQUIRE(s->Reload(next, &why));
  CHECK_THAT(why, Catch::Contains("threads"));
  CHECK(s->config().tracker.window_step == 10);
  CHECK(s->config().job_queue_capacity == 64);
  CHECK(s->config_hash() != DaemonConfigHash(Config(2)));
  std::size_t published_before;
  TrackId3D max_before = 0;
  {
    std::lock_guard<std::mutex> lock(sink.mu);
    published_before = sink.tracks.size();
    CHECK(published_before == 45);  // the reload ended the stream: every frame is out
    for (const auto& m : sink.tracks) {
      for (const auto& t : m.frame.tracks) max_before = std::max(max_before, t.id);
    }
  }
  REQUIRE(max_before > 0);
  Feed(s.get(), &clock, 45, 90);
  s->EndOfInput();
  s->Stop();
  std::lock_guard<std::mutex> lock(sink.mu);
  REQUIRE(sink.tracks.size() == 90);
  bool any = false;
  for (std::size_t i = published_before; i < sink.tracks.size(); ++i) {
    for (const auto& t : sink.tracks[i].frame.tracks) {
      CHECK(t.id > max_before);
      any = true;
    }
  }
  CHECK(any);
  CHECK(s->Counters().reloads == 1);
}

TEST_CASE("service --record log holds every input and output message", "[unit]") {
  config::testing::TempDir dir;
  const std::string path = dir.File("record.lcmlog");
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  ServiceHooks hooks = sink.Hooks(&clock);
  hooks.record_path = path;
  std::string why;
  std::unique_ptr<Service> s = Service::Create(Config(1), hooks, &why);
  REQUIRE(s);
  Feed(s.get(), &clock, 0, 30);
  const std::vector<std::uint8_t> garbage = {0xde, 0xad};
  s->OnMessage("MVTRACK_DETECTIONS", garbage.data(), garbage.size());
  s->Stop();
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(path, &why);
  REQUIRE(reader);
  std::map<std::string, int> events;
  while (auto e = reader->Next()) ++events[e->channel];
  CHECK(reader->end() == transport::LogEnd::kEndOfLog);
  CHECK(events["MVTRACK_DETECTIONS_0"] == 30);
  CHECK(events["MVTRACK_DETECTIONS_1"] == 30);
  CHECK(events["MVTRACK_DETECTIONS_2"] == 30);
  CHECK(events["MVTRACK_DETECTIONS"] == 1);  // undecodable input is recorded too
  CHECK(events["MVTRACK_TRACKS"] == 30);
  CHECK(events["MVTRACK_STATUS"] == sink.channels["MVTRACK_STATUS"]);

  ServiceHooks unwritable = sink.Hooks(&clock);
  unwritable.record_path = dir.File("no/such/dir/record.lcmlog");
  CHECK_FALSE(Service::Create(Config(1), unwritable, &why));
  CHECK_THAT(why, Catch::Contains("--record"));
}

TEST_CASE("service: with a site, the analytics events of its published frames and the counts",
          "[unit]") {
  analytics::Site site;
  site.regions.push_back({"west", {{0, 0}, {3, 0}, {3, 6}, {0, 6}}});
  site.lines.push_back({"middle", {3, 0}, {3, 6}});
  site.options.hysteresis_m = 0.1;
  site.options.hold_s = 0.2;
  // The reference: the tracker's frames through the analytics directly.
  std::string why;
  tracker::TrackerOptions options;
  options.mode = tracker::InputMode::kBoxes;
  auto t = tracker::Tracker::Create(geometry::CameraRig(Scene().cameras), options, &why);
  REQUIRE(t);
  analytics::SiteAnalytics reference(site);
  std::vector<analytics::Event> expected;
  const auto analyse = [&](const tracker::Frame3D& f) {
    std::vector<analytics::TrackPosition> positions;
    for (const tracker::Track3D& track : f.tracks) {
      positions.push_back({track.id, track.position.head<2>()});
    }
    for (const analytics::Event& e :
         reference.Update(static_cast<double>(f.utime) * 1e-6, positions)) {
      expected.push_back(e);
    }
  };
  for (const auto& cams : Scene().detections) {
    for (const core::CameraFrame& f : cams) {
      const std::vector<std::uint8_t> bytes = Encode(f);
      const transport::DecodeResult d =
          transport::DecodeCameraDetections(bytes.data(), bytes.size());
      REQUIRE(d.ok());
      for (const tracker::Frame3D& out : t->Add(d.frame).finalized) analyse(out);
    }
  }
  for (const tracker::Frame3D& out : t->Flush()) analyse(out);
  REQUIRE(expected.size() >= 2);

  DaemonConfig config = Config(2);
  config.site_path = "site.yaml";  // only its being set matters here: the site is given
  config.site = site;
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  std::unique_ptr<Service> s = Service::Create(config, sink.Hooks(&clock), &why);
  REQUIRE(s);
  Feed(s.get(), &clock, 0, Scene().detections.size());
  s->EndOfInput();
  const ServiceCounters c = s->Counters();
  s->Stop();
  CHECK(sink.undecodable == 0);
  const auto& events = sink.other["MVTRACK_ANALYTICS_EVENTS"];
  REQUIRE(events.size() == expected.size());
  CHECK(c.analytics_events_published == static_cast<std::int64_t>(expected.size()));
  for (std::size_t i = 0; i < events.size(); ++i) {
    const transport::AnalyticsEventDecodeResult d =
        transport::DecodeAnalyticsEvent(events[i].data(), events[i].size());
    REQUIRE(d.ok());
    const transport::AnalyticsEventMessage want =
        transport::ToAnalyticsEventMessage(expected[i], site, d.message.publish_utime);
    CHECK(d.message.kind == want.kind);
    CHECK(d.message.name == want.name);
    CHECK(d.message.track_id == want.track_id);
    CHECK(d.message.utime == want.utime);
    CHECK(d.message.enter_utime == want.enter_utime);
    CHECK(d.message.direction == want.direction);
  }
  // Counts: after each frame with events and with the final status; the last ones are the
  // reference's.
  const auto& counts = sink.other["MVTRACK_SITE_COUNTS"];
  REQUIRE_FALSE(counts.empty());
  // One more with the final status of Stop().
  CHECK(c.site_counts_published + 1 == static_cast<std::int64_t>(counts.size()));
  const transport::SiteCountsDecodeResult last =
      transport::DecodeSiteCounts(counts.back().data(), counts.back().size());
  REQUIRE(last.ok());
  CHECK(last.message.region_names == std::vector<std::string>{"west"});
  CHECK(last.message.regions[0].entries == reference.region_counts()[0].entries);
  CHECK(last.message.regions[0].exits == reference.region_counts()[0].exits);
  CHECK(last.message.regions[0].occupancy == reference.region_counts()[0].occupancy);
  CHECK(last.message.lines[0].left_to_right == reference.line_counts()[0].left_to_right);
  CHECK(last.message.lines[0].right_to_left == reference.line_counts()[0].right_to_left);
  // Without a site nothing is published on the analytics channels.
  Sink plain;
  std::unique_ptr<Service> without = Service::Create(Config(2), plain.Hooks(&clock), &why);
  REQUIRE(without);
  Feed(without.get(), &clock, 0, 30);
  without->Stop();
  CHECK(plain.other.empty());
}

TEST_CASE("LcmRunner routes memq:// messages to the service and publishes its output", "[unit]") {
  DaemonConfig config = Config(1);
  config.input_url = "memq://";
  config.channel_mode = ChannelMode::kPerCamera;
  std::string why;
  std::unique_ptr<LcmRunner> runner = LcmRunner::Create(config, &why);
  REQUIRE(runner);
  CHECK(runner->has_output());  // "" = the input URL
  pipeline::ManualClock clock(Scene().detections[0][0].utime);
  Sink sink;
  ServiceHooks hooks = sink.Hooks(&clock);
  std::atomic<int> publish_failures{0};
  hooks.publish = [&](const std::string& channel, const std::vector<std::uint8_t>& data) {
    if (!runner->Publish(channel, data)) ++publish_failures;
  };
  std::unique_ptr<Service> s = Service::Create(config, hooks, &why);
  REQUIRE(s);
  REQUIRE(runner->Subscribe(s.get(), &why));
  for (std::size_t i = 0; i < 30; ++i) {
    for (const core::CameraFrame& f : Scene().detections[i]) {
      REQUIRE(runner->Publish(transport::DetectionsChannelForCamera(f.camera_id), Encode(f)));
    }
    // The shared channel is not subscribed in per_camera mode.
    REQUIRE(runner->Publish(transport::kDetectionsChannel, Encode(Scene().detections[i][0])));
  }
  int dispatched = 0;
  while (runner->HandleOnce(10) == HandleResult::kMessage) ++dispatched;
  CHECK(dispatched == 90);
  s->EndOfInput();
  const ServiceCounters c = s->Counters();
  CHECK(c.messages == 90);
  CHECK(c.frames_published == 30);
  s->Stop();
  CHECK(publish_failures == 0);

  DaemonConfig file_input = Config(1);
  file_input.input_url = "file:///no/such/log.lcmlog";
  CHECK_FALSE(LcmRunner::Create(file_input, &why));
  CHECK_THAT(why, Catch::Contains("cannot open the LCM input"));
}

}  // namespace
}  // namespace mvtrack::service
