// mvtrack replay: deterministic offline tracking of a recorded detections log. Reads the log
// with transport::LogReader (no LCM receive thread), decodes every detections event with the
// safe decoder, runs the threaded pipeline::Pipeline (lossless queues) in log order and writes
// every finalized frame as tracks3d_t (LCM log) and/or canonical JSONL.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "config/calibration.h"
#include "config/calibration_check.h"
#include "config/tracker_options.h"
#include "config/zones.h"
#include "core/keypoint_layout.h"
#include "formats/tracks_io.h"
#include "geometry/camera_rig.h"
#include "mvtrack/cli.h"
#include "pipeline/clock.h"
#include "pipeline/executor.h"
#include "pipeline/pipeline.h"
#include "stitch/stitcher.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::cli {
namespace {

// Diagnostics printed per kind of problem (bad messages, rejected camera-frames, image sizes);
// the rest are only counted.
constexpr std::int64_t kMaxPrintedPerKind = 5;
// Largest --threads value (ThreadPoolOptions allows [1, 256]).
constexpr std::int64_t kMaxThreads = 256;

using Clock = std::chrono::steady_clock;

// A progress line on stderr at most once per second: rewritten in place on a terminal, one
// line per update otherwise (logs, CI).
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled), tty_(isatty(STDERR_FILENO) == 1) {}

  bool Due() const {
    return enabled_ && std::chrono::duration<double>(Clock::now() - last_).count() >= 1.0;
  }
  void Print(const std::string& text) {
    last_ = Clock::now();
    std::cerr << (tty_ ? "\r" : "") << "replay: " << text << (tty_ ? "\x1b[K" : "\n") << std::flush;
    open_line_ = tty_;
  }
  // Ends a line left open on a terminal.
  void Finish() {
    if (open_line_) std::cerr << "\n";
    open_line_ = false;
  }

 private:
  bool enabled_;
  bool tty_;
  bool open_line_ = false;
  Clock::time_point last_ = Clock::now();
};

// The decoded input and what was wrong with it.
struct LoadedInput {
  std::vector<core::CameraFrame> frames;                 // camera-frames in log order
  std::vector<std::int64_t> event_times_us;              // the log timestamp of each of `frames`
  std::int64_t events = 0;                               // events read
  std::int64_t detection_events = 0;                     // events on a detections channel
  std::map<std::string, std::int64_t> foreign_channels;  // other channels: event counts
  std::map<std::string, std::int64_t> bad_messages;      // by reason kind
  std::int64_t bad_messages_total = 0;
  std::int64_t image_size_mismatches = 0;  // accepted, but the size differs from calibration
  transport::LogEnd end = transport::LogEnd::kNotEnded;
  std::string end_error;
  std::int64_t skipped_bytes = 0;
};

std::string EventWhere(const std::string& path, const transport::LogEvent& e) {
  return path + ": event " + std::to_string(e.event_number) + " on " + e.channel +
         " (t=" + std::to_string(e.timestamp_us) + " us)";
}

LoadedInput LoadDetections(const std::string& path,
                           const geometry::CameraRig& rig,
                           Progress* progress) {
  std::string why;
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(path, &why);
  if (!reader) throw std::runtime_error(why);
  LoadedInput in;
  std::int64_t printed_bad = 0;
  std::int64_t printed_size = 0;
  auto bad = [&](const std::string& kind, const std::string& message) {
    ++in.bad_messages[kind];
    ++in.bad_messages_total;
    if (printed_bad < kMaxPrintedPerKind) {
      progress->Finish();
      std::cerr << "replay: skipped: " << message << "\n";
    } else if (printed_bad == kMaxPrintedPerKind) {
      std::cerr << "replay: (further bad messages are counted, not printed)\n";
    }
    ++printed_bad;
  };
  while (std::optional<transport::LogEvent> event = reader->Next()) {
    ++in.events;
    if (progress->Due()) {
      progress->Print("reading: " + std::to_string(in.events) + " events, " +
                      std::to_string(in.frames.size()) + " camera-frames");
    }
    if (!transport::IsDetectionsChannel(event->channel)) {
      ++in.foreign_channels[event->channel];
      continue;
    }
    ++in.detection_events;
    transport::DecodeResult decoded =
        transport::DecodeCameraDetections(event->data.data(), event->data.size());
    if (!decoded.ok()) {
      bad(transport::ToString(decoded.status),
          EventWhere(path, *event) + ": " + transport::ToString(decoded.status) + ": " +
              decoded.reason);
      continue;
    }
    const std::optional<CameraId> channel_camera = transport::CameraIdFromChannel(event->channel);
    if (channel_camera && *channel_camera != decoded.frame.camera_id) {
      bad("camera id differs from channel",
          EventWhere(path, *event) + ": camera_id " + std::to_string(decoded.frame.camera_id) +
              " on the channel of camera " + std::to_string(*channel_camera));
      continue;
    }
    if (const std::optional<int> index = rig.IndexOf(decoded.frame.camera_id)) {
      const geometry::CameraModel& cam = rig.camera(*index);
      if (decoded.image_width_px != 0 && decoded.image_height_px != 0 &&
          (decoded.image_width_px != cam.width_px || decoded.image_height_px != cam.height_px)) {
        ++in.image_size_mismatches;
        if (printed_size++ < 1) {
          progress->Finish();
          std::cerr << "replay: warning: " << EventWhere(path, *event) << ": image size "
                    << decoded.image_width_px << "x" << decoded.image_height_px
                    << " differs from the calibration's " << cam.width_px << "x" << cam.height_px
                    << " (detections are validated against the calibration; further cases "
                       "are counted)\n";
        }
      }
    }
    in.frames.push_back(std::move(decoded.frame));
    in.event_times_us.push_back(event->timestamp_us);
  }
  in.end = reader->end();
  in.end_error = reader->error();
  in.skipped_bytes = reader->skipped_bytes();
  return in;
}

std::string CountsText(const std::map<std::string, std::int64_t>& counts) {
  std::string s;
  for (const auto& [name, n] : counts)
    s += (s.empty() ? "" : ", ") + name + " " + std::to_string(n);
  return s;
}

bool SamePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) {
    return std::filesystem::equivalent(a, b, ec);
  }
  return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}

// --zone-outage ZONE:FROM:TO (seconds from the log's first capture time).
struct ZoneOutage {
  std::string zone;
  Utime from_us = 0;
  Utime to_us = 0;
  bool found = false;  // the zones file has the zone
};

ZoneOutage ParseZoneOutage(const std::string& text) {
  const std::size_t a = text.find(':');
  const std::size_t b = a == std::string::npos ? a : text.find(':', a + 1);
  const auto seconds = [](const std::string& part) -> std::optional<double> {
    double v = 0.0;
    std::istringstream in(part);
    if (!(in >> v) || !in.eof() || !std::isfinite(v) || v < 0.0 || v > 1e9) return std::nullopt;
    return v;
  };
  std::optional<double> from, to;
  if (b != std::string::npos) {
    from = seconds(text.substr(a + 1, b - a - 1));
    to = seconds(text.substr(b + 1));
  }
  if (a == 0 || !from || !to || !(*from < *to)) {
    throw UsageError("--zone-outage: '" + text +
                     "' is not ZONE:FROM:TO (seconds from the log's first capture time, "
                     "0 <= FROM < TO)");
  }
  return {text.substr(0, a), std::llround(*from * 1e6), std::llround(*to * 1e6), false};
}

// What one tracking run produced.
struct TrackRun {
  std::vector<tracker::Frame3D> frames;
  std::vector<tracker::Frame3D> provisional;
  pipeline::PipelineStatus status;
};

using RejectedFn =
    std::function<void(CameraId, FrameIndex, tracker::FrameRejection, const std::string&)>;

// Tracks `frames` (log order; moved from) with `rig`. threads 0: the stages inline on this
// thread (tracker::Tracker, no thread at all); N: the threaded pipeline with lossless camera
// queues and N window-job workers. The output is identical (tools/replay_threads, service
// tests). `progress(i, frames_out)` is called before each camera-frame.
TrackRun Track(const geometry::CameraRig& rig,
               const tracker::TrackerOptions& options,
               std::int64_t threads,
               std::vector<core::CameraFrame>* frames,
               const std::vector<std::int64_t>& event_times_us,
               bool want_provisional,
               const RejectedFn& rejected,
               const std::function<void(std::size_t, std::int64_t)>& progress) {
  TrackRun run;
  std::string why;
  std::mutex frames_mu;  // the pipeline's finalizer writes run.frames and run.provisional
  std::atomic<std::int64_t> frames_out{0};
  const std::size_t n = frames->size();
  if (threads == 0) {
    std::unique_ptr<tracker::Tracker> inline_tracker =
        tracker::Tracker::Create(rig, options, &why, want_provisional);
    if (!inline_tracker) throw std::runtime_error("tracker: " + why);
    auto take = [&](std::vector<tracker::Frame3D>* finalized) {
      frames_out.fetch_add(static_cast<std::int64_t>(finalized->size()));
      for (tracker::Frame3D& f : *finalized) run.frames.push_back(std::move(f));
      for (tracker::Frame3D& f : inline_tracker->TakeProvisional()) {
        run.provisional.push_back(std::move(f));
      }
    };
    for (std::size_t i = 0; i < n; ++i) {
      progress(i, frames_out.load());
      const CameraId camera = (*frames)[i].camera_id;
      const FrameIndex frame = (*frames)[i].frame;
      tracker::AddResult r = inline_tracker->Add((*frames)[i]);
      if (r.rejection != tracker::FrameRejection::kNone) {
        rejected(camera, frame, r.rejection, r.reason);
      }
      take(&r.finalized);
    }
    std::vector<tracker::Frame3D> rest = inline_tracker->Flush();
    take(&rest);
    run.status.tracker = inline_tracker->stats();
  } else {
    pipeline::PipelineOptions pipeline_options;
    pipeline_options.camera_overflow = pipeline::OverflowPolicy::kBlock;
    pipeline::ThreadPoolOptions pool;
    pool.num_workers = static_cast<int>(threads);
    pipeline::ManualClock clock(event_times_us.empty() ? 0 : event_times_us.front());
    std::unique_ptr<pipeline::Pipeline> pipeline = pipeline::Pipeline::Create(
        rig,
        options,
        pipeline_options,
        std::make_unique<pipeline::ThreadPoolExecutor>(pool),
        clock,
        [&](tracker::Frame3D frame) {
          std::lock_guard<std::mutex> lock(frames_mu);
          run.frames.push_back(std::move(frame));
          frames_out.fetch_add(1, std::memory_order_relaxed);
        },
        &why,
        want_provisional ? pipeline::Pipeline::FrameCallback([&](tracker::Frame3D frame) {
          std::lock_guard<std::mutex> lock(frames_mu);
          run.provisional.push_back(std::move(frame));
        })
                         : pipeline::Pipeline::FrameCallback());
    if (!pipeline) throw std::runtime_error("pipeline: " + why);
    for (std::size_t i = 0; i < n; ++i) {
      progress(i, frames_out.load());
      clock.SetMicros(event_times_us[i]);
      const CameraId camera = (*frames)[i].camera_id;
      const FrameIndex frame = (*frames)[i].frame;
      const pipeline::SubmitResult r = pipeline->Submit(std::move((*frames)[i]));
      if (r.status == pipeline::SubmitStatus::kStopped) {
        throw std::runtime_error("pipeline stopped unexpectedly");
      }
      if (r.status == pipeline::SubmitStatus::kRejected) {
        rejected(camera, frame, r.rejection, r.reason);
      }
    }
    if (!pipeline->Flush()) throw std::runtime_error("pipeline stopped before the final flush");
    pipeline->Stop();
    run.status = pipeline->Status();
  }
  frames->clear();
  return run;
}

// Adds `b`'s counters to `a` (zones: a border camera's frames count in each of its zones).
void AddStats(tracker::TrackerStats* a, const tracker::TrackerStats& b) {
  a->camera_frames_accepted += b.camera_frames_accepted;
  a->camera_frames_rejected += b.camera_frames_rejected;
  for (const auto& [kind, n] : b.rejections) a->rejections[kind] += n;
  a->detections_used += b.detections_used;
  a->detections_rejected += b.detections_rejected;
  a->detections_repaired += b.detections_repaired;
  a->detections_filtered += b.detections_filtered;
  a->frames_finalized += b.frames_finalized;
  a->windows_processed += b.windows_processed;
  a->reanchors += b.reanchors;
  a->tracks_born += b.tracks_born;
  a->tracks_revived += b.tracks_revived;
  a->embeddings_used += b.embeddings_used;
  a->embeddings_dropped += b.embeddings_dropped;
  a->gallery_bytes += b.gallery_bytes;
}

std::string JoinIds(const std::vector<CameraId>& ids) {
  std::string s;
  for (const CameraId id : ids) s += (s.empty() ? "" : ",") + std::to_string(id);
  return s;
}

}  // namespace

int RunReplay(int argc, char** argv) {
  Args args;
  args.Positional("INPUT.lcmlog",
                  "detections log (camera_detections_t on MVTRACK_DETECTIONS or "
                  "MVTRACK_DETECTIONS_<camera id>)")
      .Option("calibration", "camera calibration, mvtrack.calibration/1 (required)")
      .Option("config",
              "tracker options file (a `tracker:` YAML document; default: the paper's "
              "defaults)")
      .Option("mode", "override tracker.mode: boxes or poses")
      .Option("layout", "override tracker.layout: coco17, body25, shelf14, panoptic19 or none")
      .Option("threads",
              "window-job workers: 0 = run jobs inline on the scheduler thread, N = a "
              "pool of N worker threads; the output is identical for every value",
              "0")
      .Option("out", "write the tracks as tracks3d_t on MVTRACK_TRACKS to this LCM log")
      .Option("jsonl", "write the tracks as canonical JSON lines to this file ('-': stdout)")
      .Option("zones",
              "track zone by zone and stitch: a zones file (mvtrack.zones/1, `mvtrack calib "
              "zones --out`), one tracker per zone over its own and border cameras, the zones' "
              "tracks stitched into global ids")
      .Option("zones-jsonl",
              "with --zones: also write each zone's own tracks (what its daemon publishes) as "
              "canonical JSON lines to DIR/<zone>.jsonl")
      .Option("zones-lcmlog",
              "with --zones: also write every zone's tracks on its zone channel "
              "(MVTRACK_TRACKS_<ZONE>, what its daemon publishes) into one LCM log, in capture "
              "order with the capture time as the event time (mvtrack-stitcher --input-log "
              "stitches it)")
      .Option("zone-outage",
              "with --zones: ZONE:FROM:TO, zone ZONE's tracker stops FROM seconds after the "
              "log's first capture time and a fresh one (new ids) starts at TO: a zone daemon "
              "that died and came back")
      .Option("provisional-jsonl",
              "also write the provisional layer (each frame's tracks as soon as the frame is "
              "closed, as the daemon publishes them live) as canonical JSON lines to this file")
      .Flag("quiet", "no progress line on stderr");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack replay --calibration CAL.yaml [--config OPTIONS.yaml] "
          "[--mode boxes|poses] [--layout NAME] [--threads N] [--out TRACKS.lcmlog] "
          "[--jsonl TRACKS.jsonl] [--provisional-jsonl NOW.jsonl] [--zones ZONES.yaml "
          "[--zones-jsonl DIR] [--zones-lcmlog LOG] [--zone-outage ZONE:FROM:TO]] "
          "[--quiet] "
          "INPUT.lcmlog",
          "Tracks a recorded detections log offline, deterministically: the events are read\n"
          "in log order, decoded with the safe decoder and fed to the threaded pipeline with\n"
          "lossless queues, so the output depends only on the log and the options (never on\n"
          "timing or --threads). Events on other channels are ignored and counted; messages\n"
          "that do not decode are skipped, counted, and the first few are printed. A\n"
          "truncated or damaged log is tracked up to the damage.\n\n"
          "Every finalized frame is written as tracks3d_t (event timestamp and publish_utime\n"
          "= the frame's capture utime, latency_us = 0) and/or as one canonical JSON line\n"
          "(at least one of --out and --jsonl). --provisional-jsonl writes the provisional\n"
          "layer as well: every closed frame's confirmed tracks placed from that frame's 2D\n"
          "tracks with the association of the windows linked before it (docs/DECISIONS.md\n"
          "\"The provisional layer\"), identical at any --threads.\n\n"
          "--zones runs a site split into zones in one process, deterministically: each\n"
          "zone's tracker sees its own and its border cameras' detections, and the stitcher\n"
          "(docs/DECISIONS.md \"The stitcher\") joins the zones' tracks by capture time into\n"
          "global ids; the output is the site's tracks.\n\n"
          "The decoded detections are held in memory while tracking, so the reported speed\n"
          "measures tracking only (from the first camera-frame submitted to the end of the\n"
          "final flush; reading, decoding and writing excluded).\n\n"
          "A log whose detections carry keypoints replayed in box mode, or with another\n"
          "--layout than the log's, gets a warning (both run: box mode from pose detections\n"
          "and mapping between layouts are features).\n\n"
          "Exit status: 0 done (also when messages were skipped), 1 failure (unreadable\n"
          "input, calibration or options error, output not writable, pose mode on a log\n"
          "without keypoints, or nothing to track:\n"
          "no detections message in the log, or not one camera-frame accepted, e.g. camera\n"
          "ids the calibration does not have), 2 usage error.")) {
    return 0;
  }
  const std::string input_path = args.Get("INPUT.lcmlog");
  if (!args.Has("calibration")) throw UsageError("--calibration is required");
  const std::int64_t threads = args.GetInt("threads");
  if (threads < 0 || threads > kMaxThreads) {
    throw UsageError("--threads must be in [0, " + std::to_string(kMaxThreads) + "]");
  }
  const std::string out_path = args.Get("out");
  const std::string jsonl_path = args.Get("jsonl");
  if (args.Has("out") && out_path.empty()) throw UsageError("--out needs a file name");
  if (args.Has("jsonl") && jsonl_path.empty()) throw UsageError("--jsonl needs a file name");
  const std::string provisional_path = args.Get("provisional-jsonl");
  const bool want_provisional_arg = args.Has("provisional-jsonl");
  if (args.Has("provisional-jsonl") && (provisional_path.empty() || provisional_path == "-")) {
    throw UsageError("--provisional-jsonl needs a file name");
  }
  for (const std::string* other : {&input_path, &out_path, &jsonl_path}) {
    if (!provisional_path.empty() && !other->empty() && SamePath(provisional_path, *other)) {
      throw UsageError("--provisional-jsonl names the same file as " +
                       std::string(other == &input_path ? "the input"
                                   : other == &out_path ? "--out"
                                                        : "--jsonl"));
    }
  }
  if (!out_path.empty() && SamePath(out_path, input_path)) {
    throw UsageError("--out would overwrite the input " + input_path);
  }
  if (!jsonl_path.empty() && jsonl_path != "-" && SamePath(jsonl_path, input_path)) {
    throw UsageError("--jsonl would overwrite the input " + input_path);
  }
  if (!out_path.empty() && !jsonl_path.empty() && SamePath(out_path, jsonl_path)) {
    throw UsageError("--out and --jsonl name the same file");
  }
  if (out_path.empty() && jsonl_path.empty()) {
    throw UsageError(
        "nothing would be written: give --jsonl TRACKS.jsonl ('-': stdout) and/or --out "
        "TRACKS.lcmlog");
  }
  const bool jsonl_to_stdout = jsonl_path == "-";
  std::ostream& report = jsonl_to_stdout ? std::cerr : std::cout;

  // Options: file (or defaults), then the command-line overrides.
  tracker::TrackerOptions options;
  if (args.Has("config")) options = config::LoadTrackerOptionsFile(args.Get("config"));
  if (args.Has("mode")) {
    const std::optional<tracker::InputMode> mode = config::InputModeFromName(args.Get("mode"));
    if (!mode)
      throw UsageError("--mode must be 'boxes' or 'poses', not '" + args.Get("mode") + "'");
    options.mode = *mode;
  }
  if (args.Has("layout")) {
    const std::optional<core::KeypointLayoutId> layout =
        core::KeypointLayoutFromName(args.Get("layout"));
    if (!layout) {
      throw UsageError("--layout: unknown layout '" + args.Get("layout") +
                       "' (coco17, body25, shelf14, campus14, panoptic19, none)");
    }
    options.layout = *layout;
  }
  std::string why;
  if (!options.Validate(&why)) throw UsageError("tracker options: " + why);
  const core::KeypointLayoutId output_layout =
      options.mode == tracker::InputMode::kPoses ? options.layout : core::KeypointLayoutId::kNone;

  std::vector<geometry::CameraModel> cameras = config::LoadCalibration(args.Get("calibration"));
  for (const std::string& w : config::CalibrationLoadWarnings(cameras)) {
    std::cerr << "replay: warning: " << args.Get("calibration") << ": " << w << "\n";
  }
  geometry::CameraRig rig(std::move(cameras), &why);
  if (!rig.ok()) throw std::runtime_error(args.Get("calibration") + ": " + why);
  std::vector<config::Zone> zones;
  if (args.Has("zones-jsonl") && !args.Has("zones"))
    throw UsageError("--zones-jsonl needs --zones");
  if (args.Has("zone-outage") && !args.Has("zones"))
    throw UsageError("--zone-outage needs --zones");
  if (args.Has("zones-lcmlog") && !args.Has("zones")) {
    throw UsageError("--zones-lcmlog needs --zones");
  }
  std::optional<ZoneOutage> outage;
  if (args.Has("zone-outage")) outage = ParseZoneOutage(args.Get("zone-outage"));
  if (args.Has("zones")) {
    if (want_provisional_arg) {
      throw UsageError(
          "--provisional-jsonl and --zones: the stitched site has no provisional "
          "layer yet");
    }
    zones = config::LoadZonesFile(args.Get("zones"));
    for (const config::Zone& z : zones) {
      for (const std::vector<CameraId>* list : {&z.cameras, &z.border}) {
        for (const CameraId id : *list) {
          if (!rig.IndexOf(id)) {
            throw std::runtime_error(args.Get("zones") + ": zone " + z.name + ": camera " +
                                     std::to_string(id) + " is not in " + args.Get("calibration"));
          }
        }
      }
      if (outage && outage->zone == z.name) outage->found = true;
      if (z.cameras.size() + z.border.size() < 2) {
        throw std::runtime_error(args.Get("zones") + ": zone " + z.name +
                                 " has fewer than 2 cameras (own and border): it cannot "
                                 "triangulate");
      }
    }
  }

  // Open the outputs first: an unwritable path fails before any work.
  std::unique_ptr<transport::LogWriter> lcm_out;
  if (!out_path.empty()) {
    lcm_out = transport::LogWriter::Open(out_path, &why);
    if (!lcm_out) throw std::runtime_error(why);
  }
  std::ofstream jsonl_file;
  std::ostream* jsonl = nullptr;
  if (jsonl_to_stdout) {
    jsonl = &std::cout;
  } else if (!jsonl_path.empty()) {
    jsonl_file.open(jsonl_path, std::ios::binary | std::ios::trunc);
    if (!jsonl_file) throw std::runtime_error(jsonl_path + ": cannot open for writing");
    jsonl = &jsonl_file;
  }
  std::ofstream provisional_file;
  if (!provisional_path.empty()) {
    provisional_file.open(provisional_path, std::ios::binary | std::ios::trunc);
    if (!provisional_file) {
      throw std::runtime_error(provisional_path + ": cannot open for writing");
    }
  }
  const bool want_provisional = !provisional_path.empty();

  Progress progress(!args.Has("quiet"));
  const auto read_start = Clock::now();
  LoadedInput in = LoadDetections(input_path, rig, &progress);
  const double read_seconds = SecondsSince(read_start);
  if (in.end == transport::LogEnd::kIoError) {
    progress.Finish();
    throw std::runtime_error(in.end_error);
  }
  if (outage && !outage->found) {
    throw UsageError("--zone-outage: no zone is named '" + outage->zone + "' in " +
                     args.Get("zones"));
  }
  Utime log_start = 0;  // the earliest capture time of the log (--zone-outage counts from it)
  for (std::size_t i = 0; i < in.frames.size(); ++i) {
    if (i == 0 || in.frames[i].utime < log_start) log_start = in.frames[i].utime;
  }
  // What the log says about the mode and layout it was recorded for.
  std::map<std::string, std::int64_t> log_layouts;  // keypoint layout name -> detections
  std::set<CameraId> log_cameras;
  std::int64_t log_detections = 0;
  for (const core::CameraFrame& f : in.frames) {
    log_cameras.insert(f.camera_id);
    log_detections += static_cast<std::int64_t>(f.detections.size());
    for (const core::Detection2D& d : f.detections) {
      if (d.layout != core::KeypointLayoutId::kNone) {
        ++log_layouts[core::GetKeypointLayout(d.layout).name];
      }
    }
  }
  if (log_layouts.empty() && log_detections > 0 && options.mode == tracker::InputMode::kPoses) {
    progress.Finish();
    throw std::runtime_error("the tracker runs in pose mode, but none of the log's " +
                             std::to_string(log_detections) +
                             " detections carries keypoints (a log of boxes): --mode boxes "
                             "tracks them");
  }
  if (!log_layouts.empty() && options.mode == tracker::InputMode::kBoxes) {
    progress.Finish();
    std::cerr << "replay: warning: the log's detections carry keypoints ("
              << CountsText(log_layouts) << ") but the tracker runs in box mode: --mode poses "
              << "--layout " << log_layouts.rbegin()->first << " tracks the poses\n";
  }
  if (options.mode == tracker::InputMode::kPoses && !log_layouts.empty() &&
      log_layouts.count(core::GetKeypointLayout(options.layout).name) == 0) {
    progress.Finish();
    std::cerr << "replay: warning: the log's keypoints are " << CountsText(log_layouts)
              << ", the tracker's layout is " << core::GetKeypointLayout(options.layout).name
              << ": joints are mapped by name, and joints the log's layout lacks stay empty "
              << "(--layout " << log_layouts.rbegin()->first << " tracks them as recorded)\n";
  }

  // Tracking, with the whole rig or zone by zone, then stitched. Frames are collected in memory.
  std::int64_t printed_rejections = 0;
  const RejectedFn rejected = [&](CameraId camera,
                                  FrameIndex frame,
                                  tracker::FrameRejection rejection,
                                  const std::string& reason) {
    if (printed_rejections < kMaxPrintedPerKind) {
      progress.Finish();
      std::cerr << "replay: rejected camera-frame (camera " << camera << ", frame " << frame
                << "): " << tracker::ToString(rejection) << ": " << reason << "\n";
    } else if (printed_rejections == kMaxPrintedPerKind) {
      std::cerr << "replay: (further rejected camera-frames are counted, not printed)\n";
    }
    ++printed_rejections;
  };
  const std::size_t num_camera_frames = in.frames.size();
  std::vector<tracker::Frame3D> frames;
  std::vector<tracker::Frame3D> provisional;
  pipeline::PipelineStatus status;
  std::vector<std::string> zone_lines;  // the summary's line per zone
  std::string stitch_line;
  const auto track_start = Clock::now();
  if (zones.empty()) {
    TrackRun run = Track(rig,
                         options,
                         threads,
                         &in.frames,
                         in.event_times_us,
                         want_provisional,
                         rejected,
                         [&](std::size_t i, std::int64_t out) {
                           if (progress.Due()) {
                             progress.Print("tracking: " + std::to_string(i) + "/" +
                                            std::to_string(num_camera_frames) + " camera-frames, " +
                                            std::to_string(out) + " frames out");
                           }
                         });
    frames = std::move(run.frames);
    provisional = std::move(run.provisional);
    status = std::move(run.status);
  } else {
    std::vector<std::vector<tracker::Frame3D>> zone_frames;
    for (std::size_t z = 0; z < zones.size(); ++z) {
      const config::Zone& zone = zones[z];
      std::vector<CameraId> ids = zone.cameras;
      ids.insert(ids.end(), zone.border.begin(), zone.border.end());
      std::sort(ids.begin(), ids.end());
      std::vector<geometry::CameraModel> zone_cameras;
      for (const CameraId id : ids) zone_cameras.push_back(rig.camera(*rig.IndexOf(id)));
      geometry::CameraRig zone_rig(std::move(zone_cameras), &why);
      if (!zone_rig.ok()) throw std::runtime_error("zone " + zone.name + ": " + why);
      std::vector<core::CameraFrame> zone_input;
      std::vector<std::int64_t> zone_times;
      for (std::size_t i = 0; i < in.frames.size(); ++i) {
        if (std::binary_search(ids.begin(), ids.end(), in.frames[i].camera_id)) {
          zone_input.push_back(in.frames[i]);
          zone_times.push_back(in.event_times_us[i]);
        }
      }
      const std::size_t zone_n = zone_input.size();
      auto track_zone = [&](std::vector<core::CameraFrame>* input,
                            const std::vector<std::int64_t>& times) {
        return Track(zone_rig,
                     options,
                     threads,
                     input,
                     times,
                     false,
                     rejected,
                     [&](std::size_t i, std::int64_t out) {
                       if (progress.Due()) {
                         progress.Print("tracking " + zone.name + " (" + std::to_string(z + 1) +
                                        "/" + std::to_string(zones.size()) +
                                        "): " + std::to_string(i) + "/" + std::to_string(zone_n) +
                                        " camera-frames, " + std::to_string(out) + " frames out");
                       }
                     });
      };
      TrackRun run;
      if (outage && outage->zone == zone.name) {
        // The zone's daemon stops at `from` (flushing, as on SIGTERM) and a fresh one starts at
        // `to`, its ids above the first's (as its state directory's reservation makes them).
        std::vector<core::CameraFrame> before, after;
        std::vector<std::int64_t> before_times, after_times;
        for (std::size_t i = 0; i < zone_input.size(); ++i) {
          const Utime t = zone_input[i].utime - log_start;
          if (t < outage->from_us) {
            before.push_back(std::move(zone_input[i]));
            before_times.push_back(zone_times[i]);
          } else if (t >= outage->to_us) {
            after.push_back(std::move(zone_input[i]));
            after_times.push_back(zone_times[i]);
          }
        }
        run = track_zone(&before, before_times);
        TrackRun second = track_zone(&after, after_times);
        TrackId3D offset = 0;
        for (const tracker::Frame3D& f : run.frames) {
          for (const tracker::Track3D& t : f.tracks) offset = std::max(offset, t.id);
        }
        for (tracker::Frame3D& f : second.frames) {
          for (tracker::Track3D& t : f.tracks) t.id += offset;
          run.frames.push_back(std::move(f));
        }
        AddStats(&run.status.tracker, second.status.tracker);
        run.status.windows_failed += second.status.windows_failed;
        run.status.output_callback_errors += second.status.output_callback_errors;
      } else {
        run = track_zone(&zone_input, zone_times);
      }
      std::set<TrackId3D> zone_ids;
      for (const tracker::Frame3D& f : run.frames) {
        for (const tracker::Track3D& t : f.tracks) zone_ids.insert(t.id);
      }
      zone_lines.push_back("  " + zone.name + ": cameras " + JoinIds(zone.cameras) +
                           (zone.border.empty() ? "" : " + border " + JoinIds(zone.border)) + "; " +
                           std::to_string(run.frames.size()) + " frame(s), " +
                           std::to_string(zone_ids.size()) + " track id(s), " +
                           std::to_string(run.status.tracker.windows_processed) + " window(s)");
      AddStats(&status.tracker, run.status.tracker);
      status.windows_failed += run.status.windows_failed;
      status.output_callback_errors += run.status.output_callback_errors;
      if (!run.status.last_failure.empty()) status.last_failure = run.status.last_failure;
      if (args.Has("zones-jsonl")) {
        const std::filesystem::path dir = args.Get("zones-jsonl");
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        const std::string path = (dir / (zone.name + ".jsonl")).string();
        std::ofstream file(path, std::ios::binary | std::ios::trunc);
        for (const tracker::Frame3D& f : run.frames) {
          file << transport::TracksJsonLine(f, output_layout);
        }
        file.close();
        if (!file) throw std::runtime_error(path + ": cannot write");
      }
      zone_frames.push_back(std::move(run.frames));
    }
    if (args.Has("zones-lcmlog")) {
      // Every zone's frames on its channel, by capture time (then zone), as the daemons publish.
      std::vector<std::pair<Utime, std::size_t>> order;
      std::vector<std::size_t> next(zone_frames.size(), 0);
      std::unique_ptr<transport::LogWriter> log =
          transport::LogWriter::Open(args.Get("zones-lcmlog"), &why);
      if (!log) throw std::runtime_error(why);
      while (true) {
        std::optional<std::size_t> pick;
        for (std::size_t z = 0; z < zone_frames.size(); ++z) {
          if (next[z] < zone_frames[z].size() &&
              (!pick || zone_frames[z][next[z]].utime < zone_frames[*pick][next[*pick]].utime)) {
            pick = z;
          }
        }
        if (!pick) break;
        const tracker::Frame3D& f = zone_frames[*pick][next[*pick]++];
        if (!log->Write(config::ZoneChannel(transport::kTracksChannel, zones[*pick].name),
                        f.utime,
                        transport::EncodeTracks(f, output_layout, f.utime, 0),
                        &why)) {
          throw std::runtime_error(why);
        }
      }
      if (!log->Flush(&why)) throw std::runtime_error(why);
    }
    // Stitching: the zones' frames aligned by capture time, half a frame period apart at most.
    Utime tolerance = 0;
    for (const std::vector<tracker::Frame3D>& f : zone_frames) {
      if (const std::optional<Utime> half = stitch::HalfFramePeriod(f)) {
        tolerance = tolerance == 0 ? *half : std::min(tolerance, *half);
      }
    }
    stitch::Stitcher stitcher(config::ZoneNames(zones), options.linking);
    const auto stitch_start = Clock::now();
    for (const stitch::ZoneFrames& group :
         stitch::AlignZoneFrames(zone_frames, tolerance > 0 ? tolerance : 1)) {
      frames.push_back(std::move(stitcher.Stitch(group).frame));
    }
    const double stitch_ms = SecondsSince(stitch_start) * 1000.0;
    const stitch::StitchStats& ss = stitcher.stats();
    stitch_line = "  stitched: " + std::to_string(ss.frames) + " site frame(s), " +
                  std::to_string(ss.global_ids) + " global id(s); zone tracks joined in an " +
                  "overlap " + std::to_string(ss.joined_overlap) + ", by motion " +
                  std::to_string(ss.joined_motion) + "; joins undone " + std::to_string(ss.splits) +
                  ", ids merged " + std::to_string(ss.merges) +
                  "; track-frames seen by two or more zones " +
                  std::to_string(ss.multi_zone_track_frames) + "; stitching took " +
                  std::to_string(std::llround(stitch_ms)) + " ms\n";
  }
  const double track_seconds = SecondsSince(track_start);
  in.frames.clear();
  progress.Finish();

  // Output.
  const auto write_start = Clock::now();
  std::set<TrackId3D> track_ids;
  std::int64_t track_frames = 0;
  for (const tracker::Frame3D& f : frames) {
    for (const tracker::Track3D& t : f.tracks) track_ids.insert(t.id);
    track_frames += static_cast<std::int64_t>(f.tracks.size());
    if (jsonl) *jsonl << transport::TracksJsonLine(f, output_layout);
    if (lcm_out && !lcm_out->Write(transport::kTracksChannel,
                                   f.utime,
                                   transport::EncodeTracks(f, output_layout, f.utime, 0),
                                   &why)) {
      throw std::runtime_error(why);
    }
  }
  if (lcm_out && !lcm_out->Flush(&why)) throw std::runtime_error(why);
  if (jsonl) {
    jsonl->flush();
    if (!*jsonl)
      throw std::runtime_error((jsonl_to_stdout ? "stdout" : jsonl_path) + ": write error");
  }
  if (jsonl_file.is_open()) {
    jsonl_file.close();
    if (!jsonl_file) throw std::runtime_error(jsonl_path + ": write error");
  }
  std::int64_t provisional_track_frames = 0;
  if (provisional_file.is_open()) {
    for (const tracker::Frame3D& f : provisional) {
      provisional_track_frames += static_cast<std::int64_t>(f.tracks.size());
      provisional_file << transport::TracksJsonLine(f, output_layout);
    }
    provisional_file.close();
    if (!provisional_file) throw std::runtime_error(provisional_path + ": write error");
  }
  const double write_seconds = SecondsSince(write_start);

  // Summary.
  const tracker::TrackerStats& st = status.tracker;
  report << "replay: " << input_path << ": " << in.events << " event(s), " << in.detection_events
         << " on detections channels";
  if (!in.foreign_channels.empty()) {
    std::int64_t n = 0;
    for (const auto& [channel, count] : in.foreign_channels) n += count;
    report << ", " << n << " on other channels ignored (" << CountsText(in.foreign_channels) << ")";
  }
  report << "; log " << transport::ToString(in.end);
  if (!in.end_error.empty()) report << " (" << in.end_error << ")";
  if (in.skipped_bytes > 0) report << "; " << in.skipped_bytes << " damaged byte(s) skipped";
  report << "\n";
  report << "  bad messages skipped: " << in.bad_messages_total;
  if (in.bad_messages_total > 0) report << " (" << CountsText(in.bad_messages) << ")";
  if (in.image_size_mismatches > 0) {
    report << "; image size differs from calibration: " << in.image_size_mismatches;
  }
  report << "\n";
  std::map<std::string, std::int64_t> rejections;
  for (const auto& [kind, n] : st.rejections) rejections[tracker::ToString(kind)] = n;
  report << "  camera-frames: " << st.camera_frames_accepted << " accepted, "
         << st.camera_frames_rejected << " rejected";
  if (st.camera_frames_rejected > 0) report << " (" << CountsText(rejections) << ")";
  report << "\n  detections: " << st.detections_used << " used, " << st.detections_rejected
         << " rejected, " << st.detections_repaired << " repaired, " << st.detections_filtered
         << " filtered\n";
  if (st.embeddings_used + st.embeddings_dropped > 0 || st.tracks_revived > 0) {
    report << "  appearance: " << st.embeddings_used << " embeddings used, "
           << st.embeddings_dropped << " dropped as unusable; " << st.tracks_revived
           << " track(s) re-identified after leaving; galleries " << st.gallery_bytes << " bytes\n";
  }
  report << "  output: " << frames.size() << " frame(s), " << track_ids.size() << " track id(s), "
         << track_frames << " track-frame(s), layout " << formats::LayoutName(output_layout) << "; "
         << st.windows_processed << " window(s)";
  if (status.windows_failed > 0) {
    report << ", " << status.windows_failed << " FAILED (" << status.last_failure << ")";
  }
  if (st.reanchors > 0) report << ", " << st.reanchors << " stream restart(s)";
  report << "\n";
  if (!zones.empty()) {
    report << "  zones: " << zones.size() << " (camera-frames and detections above count a "
           << "border camera in each of its zones)\n";
    for (const std::string& line : zone_lines) report << "  " << line << "\n";
    report << stitch_line;
  }
  char speed[160];
  const double fps = track_seconds > 0.0 ? static_cast<double>(frames.size()) / track_seconds : 0.0;
  std::snprintf(speed, sizeof(speed), "%.3f s = %.0f frames/s", track_seconds, fps);
  report << "  tracking: " << frames.size() << " frame(s) in " << speed << " ("
         << (threads == 0 ? std::string("inline, no threads")
                          : "pipeline, " + std::to_string(threads) + " worker thread(s)")
         << (zones.empty() ? "" : ", the zones one after the other, and stitching")
         << "; timed from the first submit to the end of the flush; reading "
         << std::llround(read_seconds * 1000.0) << " ms and writing "
         << std::llround(write_seconds * 1000.0) << " ms not included)\n";
  if (!out_path.empty())
    report << "  wrote " << out_path << " (LCM log, " << frames.size() << " event(s))\n";
  if (!jsonl_path.empty() && !jsonl_to_stdout) {
    report << "  wrote " << jsonl_path << " (JSONL, " << frames.size() << " line(s))\n";
  }
  if (!provisional_path.empty()) {
    report << "  wrote " << provisional_path << " (provisional layer, JSONL, " << provisional.size()
           << " line(s), " << provisional_track_frames << " track-frame(s))\n";
  }
  if (status.windows_failed > 0 || status.output_callback_errors > 0) return 1;
  // A run that could not do its job fails (exit 1), saying why.
  if (in.detection_events == 0) {
    std::string hint = in.events == 0 ? "the log is empty" : "no event is on a detections channel";
    if (in.foreign_channels.count(transport::kTracksChannel) > 0) {
      hint += " (it holds " + std::string(transport::kTracksChannel) +
              ": a tracks log, which `mvtrack eval`, `diff` and `view` read)";
    }
    std::cerr << "replay: error: nothing to track: " << hint << "\n";
    return 1;
  }
  if (st.camera_frames_accepted == 0) {
    std::string ids;
    for (const CameraId id : log_cameras) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    std::string calibration_ids;
    for (const geometry::CameraModel& c : rig.cameras()) {
      calibration_ids += (calibration_ids.empty() ? "" : ", ") + std::to_string(c.id);
    }
    std::cerr << "replay: error: no camera-frame was accepted"
              << (st.camera_frames_rejected > 0 ? " (" + CountsText(rejections) + ")" : "")
              << "; the log's cameras: " << (ids.empty() ? "none" : ids)
              << ", the calibration's: " << calibration_ids << "\n";
    return 1;
  }
  return 0;
}

}  // namespace mvtrack::cli
