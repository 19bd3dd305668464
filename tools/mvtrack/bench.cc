// mvtrack bench: throughput, latency and memory of the tracker on simulated scenes (lib/sim),
// with the accuracy (MOTA, IDF1, MPJPE) of every measured run next to its speed. Writes
// results.json, results.md (the tables of docs/BENCHMARKS.md) and fps.png (the plot).
//
// What "FPS" counts: multi-view frames (time steps: one camera-frame from every camera) per
// second of tracking time, from the first camera-frame's detections in to the last frame's
// tracks out (Tracker::Add ... Tracker::Flush, or Pipeline::Submit ... Pipeline::Flush),
// excluding detection (the detections come precomputed from the simulator, as the paper's speed
// study excludes its detector) and excluding the simulation itself.

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "config/tracker_options.h"
#include "eval/layer_agreement.h"
#include "eval/tracking_metrics.h"
#include "json/document.h"
#include "mvtrack/cli.h"
#include "mvtrack/sim_scene.h"
#include "pipeline/clock.h"
#include "pipeline/executor.h"
#include "pipeline/pipeline.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"
#include "sim/scene_presets.h"
#include "tracker/tracker.h"

#ifndef MVTRACK_BUILD_TYPE
#define MVTRACK_BUILD_TYPE "unknown"
#endif

namespace mvtrack::cli {
namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process (all threads), seconds.
double ProcessCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// --- machine and process ------------------------------------------------------------------

std::string ReadFirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown";
}

// A "VmRSS"/"VmHWM" field of /proc/self/status in MiB (0 when unavailable).
double ProcStatusMiB(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream fields(line.substr(key.size() + 1));
      double kib = 0.0;
      fields >> kib;
      return kib / 1024.0;
    }
  }
  return 0.0;
}
double RssMiB() { return ProcStatusMiB("VmRSS"); }
double PeakRssMiB() { return ProcStatusMiB("VmHWM"); }
// Resets the peak RSS (VmHWM) to the current RSS (Linux >= 4.0; ignored elsewhere).
void ResetPeakRss() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
}

std::string UtcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// --- scenes ---------------------------------------------------------------------------------

// A simulated scene held in memory: its camera-frames in capture order and its ground truth.
struct PreparedScene {
  sim::SceneOptions options;
  std::vector<geometry::CameraModel> cameras;
  std::vector<core::CameraFrame> camera_frames;  // frame-major, cameras in rig order
  eval::EvalSequence truth;
  double coverage = 0.0;  // person-frames detected in >= 2 cameras / person-frames
  double generate_s = 0.0;
};

PreparedScene Prepare(const sim::SceneOptions& options) {
  const auto start = Clock::now();
  PreparedScene s;
  s.options = options;
  s.cameras = sim::MakeCameras(options);
  sim::CrowdSimulator crowd(options);
  std::int64_t person_frames = 0, covered = 0;
  for (int f = 0; f < options.num_frames; ++f) {
    const sim::FrameTruth truth = crowd.Next();
    sim::RenderedFrame rendered = sim::RenderFrame(options, s.cameras, truth);
    std::map<int, int> views;
    for (const auto& ids : rendered.person_ids) {
      for (const int id : ids) {
        if (id >= 0) ++views[id];
      }
    }
    person_frames += static_cast<std::int64_t>(truth.people.size());
    for (const auto& [id, n] : views) covered += n >= 2 ? 1 : 0;
    for (core::CameraFrame& cf : rendered.cameras) s.camera_frames.push_back(std::move(cf));
    s.truth.push_back(TruthEvalFrame(truth, options.poses));
  }
  s.coverage =
      person_frames > 0 ? static_cast<double>(covered) / static_cast<double>(person_frames) : 0.0;
  s.generate_s = SecondsSince(start);
  return s;
}

// The tracker options every run starts from (--config; default: the paper's defaults).
tracker::TrackerOptions& BaseTrackerOptions() {
  static tracker::TrackerOptions options;
  return options;
}

tracker::TrackerOptions TrackerOptionsFor(const sim::SceneOptions& so) {
  tracker::TrackerOptions to = BaseTrackerOptions();
  to.mode = so.poses ? tracker::InputMode::kPoses : tracker::InputMode::kBoxes;
  to.layout = core::KeypointLayoutId::kCoco17;
  return to;
}

// Accuracy of one run against the scene's truth.
struct Accuracy {
  double mota = std::nan("");
  double idf1 = std::nan("");
  double hota = std::nan("");
  double mpjpe_m = std::nan("");
  std::int64_t switches = 0;
  std::int64_t id_transfers = 0;       // IDTR: predicted ids covering >= 2 GT persons
  std::int64_t id_fragmentations = 0;  // IDFRAG: GT persons covered by >= 2 predicted ids
  std::int64_t gt_ids = 0;
  std::int64_t predicted_ids = 0;
};

// The accuracy of `frames` against `truth` over `ranges` (empty: every frame).
Accuracy Score(const eval::EvalSequence& truth,
               const std::vector<tracker::Frame3D>& frames,
               const std::vector<eval::FrameRange>& ranges = {}) {
  eval::EvalSequence pred;
  pred.reserve(frames.size());
  for (const tracker::Frame3D& f : frames) pred.push_back(TrackEvalFrame(f));
  eval::TrackingOptions eo;
  eo.distance = eval::DistanceKind::kFootprint;
  eo.frame_ranges = ranges;
  const eval::TrackingEvaluation e = eval::EvaluateTracking(truth, pred, eo);
  if (!e.valid) throw std::runtime_error("evaluation: " + e.error);
  Accuracy a;
  a.mota = e.clear.mota;
  a.idf1 = e.identity.idf1;
  a.hota = e.hota.mean_hota;
  a.mpjpe_m = e.pose.mpjpe_m;
  a.switches = e.clear.num_switches;
  a.id_transfers = static_cast<std::int64_t>(e.coverage.transfers.size());
  a.id_fragmentations = static_cast<std::int64_t>(e.coverage.fragmentations.size());
  a.gt_ids = e.clear.num_unique_objects;
  a.predicted_ids = e.clear.num_unique_predictions;
  return a;
}

// --- runs -----------------------------------------------------------------------------------

// One timed run: the tracker's output and the seconds from first input to last output.
struct TimedRun {
  std::vector<tracker::Frame3D> frames;
  double seconds = 0.0;
  double cpu_seconds = 0.0;  // process CPU time over the same span (all threads)
};

// threads == 0: tracker::Tracker inline (one thread). threads >= 1: pipeline::Pipeline with a
// ThreadPoolExecutor of that many workers, lossless (kBlock).
TimedRun RunOnce(const PreparedScene& scene, int threads) {
  std::string why;
  TimedRun run;
  run.frames.reserve(static_cast<std::size_t>(scene.options.num_frames));
  const tracker::TrackerOptions to = TrackerOptionsFor(scene.options);
  if (threads == 0) {
    auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), to, &why);
    if (!t) throw std::runtime_error("tracker: " + why);
    const double cpu_start = ProcessCpuSeconds();
    const auto start = Clock::now();
    for (const core::CameraFrame& cf : scene.camera_frames) {
      tracker::AddResult r = t->Add(cf);
      for (tracker::Frame3D& f : r.finalized) run.frames.push_back(std::move(f));
    }
    for (tracker::Frame3D& f : t->Flush()) run.frames.push_back(std::move(f));
    run.seconds = SecondsSince(start);
    run.cpu_seconds = ProcessCpuSeconds() - cpu_start;
    return run;
  }
  pipeline::PipelineOptions po;
  po.camera_overflow = pipeline::OverflowPolicy::kBlock;
  pipeline::ThreadPoolOptions tpo;
  tpo.num_workers = threads;
  pipeline::SteadyClock clock;
  std::vector<tracker::Frame3D>* out = &run.frames;
  auto p = pipeline::Pipeline::Create(
      geometry::CameraRig(scene.cameras),
      to,
      po,
      std::make_unique<pipeline::ThreadPoolExecutor>(tpo),
      clock,
      [out](tracker::Frame3D f) { out->push_back(std::move(f)); },
      &why);
  if (!p) throw std::runtime_error("pipeline: " + why);
  const double cpu_start = ProcessCpuSeconds();
  const auto start = Clock::now();
  for (const core::CameraFrame& cf : scene.camera_frames) p->Submit(cf);
  p->Flush();
  run.seconds = SecondsSince(start);
  run.cpu_seconds = ProcessCpuSeconds() - cpu_start;
  p->Stop();
  return run;
}

// One measured configuration.
struct PointResult {
  std::string suite;
  int cameras = 0;
  int people = 0;
  bool poses = false;
  int threads = 0;  // 0 = inline Tracker
  int frames = 0;
  int repeats = 0;
  double median_s = 0.0;
  double min_s = 0.0;
  double fps = 0.0;              // frames / median_s
  double cpu_fps = 0.0;          // frames / median CPU seconds (all threads)
  double camera_fps = 0.0;       // fps * cameras
  double realtime_factor = 0.0;  // fps / scene fps
  double peak_rss_mib = 0.0;
  double coverage = 0.0;
  double detections_per_frame = 0.0;
  double generate_s = 0.0;
  Accuracy accuracy;
  double paper_fps = 0.0;  // 0 when the paper has no figure for this point
};

double PaperFps(int cameras, int people, bool poses) {
  (void)poses;  // the paper's speed figure does not say which mode; both are compared
  if (cameras == 2 && people == 2) return 1643.0;
  if (cameras == 6 && people == 2) return 186.0;
  if (cameras == 2 && people == 8) return 1286.0;
  return 0.0;
}

PointResult MeasurePoint(const std::string& suite,
                         int cameras,
                         int people,
                         bool poses,
                         const std::vector<int>& thread_counts,
                         int frames,
                         int min_repeats,
                         double min_total_s,
                         std::uint64_t seed,
                         std::vector<PointResult>* all) {
  ResetPeakRss();
  sim::SceneOptions so = sim::SizedScene(cameras, people, poses, seed);
  so.num_frames = frames;
  const PreparedScene scene = Prepare(so);
  std::int64_t detections = 0;
  for (const core::CameraFrame& cf : scene.camera_frames) {
    detections += static_cast<std::int64_t>(cf.detections.size());
  }
  PointResult last;
  for (const int threads : thread_counts) {
    PointResult r;
    r.suite = suite;
    r.cameras = cameras;
    r.people = people;
    r.poses = poses;
    r.threads = threads;
    r.frames = frames;
    r.coverage = scene.coverage;
    r.generate_s = scene.generate_s;
    r.detections_per_frame = static_cast<double>(detections) / std::max(1, frames);
    std::vector<double> seconds, cpu_seconds;
    double total = 0.0;
    while (static_cast<int>(seconds.size()) < min_repeats ||
           (total < min_total_s && seconds.size() < 50)) {
      TimedRun run = RunOnce(scene, threads);
      if (seconds.empty()) r.accuracy = Score(scene.truth, run.frames);
      seconds.push_back(run.seconds);
      cpu_seconds.push_back(run.cpu_seconds);
      total += run.seconds;
    }
    std::vector<double> sorted = seconds;
    std::sort(sorted.begin(), sorted.end());
    r.repeats = static_cast<int>(sorted.size());
    r.median_s = sorted[sorted.size() / 2];
    r.min_s = sorted.front();
    r.fps = frames / r.median_s;
    std::sort(cpu_seconds.begin(), cpu_seconds.end());
    r.cpu_fps = frames / cpu_seconds[cpu_seconds.size() / 2];
    r.camera_fps = r.fps * cameras;
    r.realtime_factor = r.fps / so.fps;
    r.peak_rss_mib = PeakRssMiB();
    r.paper_fps = suite == "paper" ? PaperFps(cameras, people, poses) : 0.0;
    std::fprintf(
        stderr,
        "  %-6s %2d cams %3d people %-5s %s: %9.0f FPS (median of %d; %.0f per CPU "
        "second), MOTA %.3f IDF1 %.3f%s, peak RSS %.0f MiB\n",
        suite.c_str(),
        cameras,
        people,
        poses ? "poses" : "boxes",
        threads == 0 ? "1 thread (inline)  "
                     : (std::to_string(threads) + " worker(s) pipeline").c_str(),
        r.fps,
        r.repeats,
        r.cpu_fps,
        r.accuracy.mota,
        r.accuracy.idf1,
        poses ? (", MPJPE " + std::to_string(r.accuracy.mpjpe_m * 1000.0).substr(0, 5) + " mm")
                    .c_str()
              : "",
        r.peak_rss_mib);
    all->push_back(r);
    last = r;
  }
  return last;
}

json::OrderedDocument PointJson(const PointResult& r) {
  json::OrderedDocument o = {{"suite", r.suite},
                             {"cameras", r.cameras},
                             {"people", r.people},
                             {"mode", r.poses ? "poses" : "boxes"},
                             {"runner", r.threads == 0 ? "tracker_inline" : "pipeline"},
                             {"worker_threads", r.threads == 0 ? 1 : r.threads},
                             {"frames", r.frames},
                             {"repeats", r.repeats},
                             {"median_s", r.median_s},
                             {"min_s", r.min_s},
                             {"fps", r.fps},
                             {"fps_per_cpu_second", r.cpu_fps},
                             {"camera_frames_per_s", r.camera_fps},
                             {"realtime_factor_at_30fps", r.realtime_factor},
                             {"mota", r.accuracy.mota},
                             {"idf1", r.accuracy.idf1},
                             {"hota", r.accuracy.hota},
                             {"mpjpe_m", r.accuracy.mpjpe_m},
                             {"id_switches", r.accuracy.switches},
                             {"id_transfers", r.accuracy.id_transfers},
                             {"coverage_two_views", r.coverage},
                             {"detections_per_frame", r.detections_per_frame},
                             {"peak_rss_mib", r.peak_rss_mib},
                             {"scene_generation_s", r.generate_s}};
  if (r.paper_fps > 0.0) {
    o["paper_fps"] = r.paper_fps;
    o["ratio_to_paper"] = r.fps / r.paper_fps;
  }
  return o;
}

// --- identity over long runs -------------------------------------------------------------------

// One long scene: who is who over minutes, with people coming and going (docs/BENCHMARKS.md
// "Identity over long runs").
struct IdentityResult {
  int cameras = 0;
  int people = 0;
  bool poses = false;
  bool enter_leave = false;
  int frames = 0;
  std::uint64_t seed = 0;
  double fps = 0.0;
  Accuracy whole;
  Accuracy head;  // the first 10 % of the frames
};

IdentityResult MeasureIdentity(
    int cameras, int people, bool poses, bool enter_leave, int frames, std::uint64_t seed) {
  sim::SceneOptions so = sim::SizedScene(cameras, people, poses, seed);
  so.num_frames = frames;
  so.enter_and_leave = enter_leave;
  const PreparedScene scene = Prepare(so);
  const TimedRun run = RunOnce(scene, 0);
  IdentityResult r;
  r.cameras = cameras;
  r.people = people;
  r.poses = poses;
  r.enter_leave = enter_leave;
  r.frames = frames;
  r.seed = seed;
  r.fps = frames / run.seconds;
  r.whole = Score(scene.truth, run.frames);
  r.head = Score(scene.truth, run.frames, {{0, frames / 10 - 1}});
  std::fprintf(stderr,
               "  identity %2d cams %3d people %-5s %s %d frames seed %llu: IDF1 %.3f (first 10 %% "
               "%.3f), HOTA %.3f, MOTA %.3f, ids %lld / %lld GT, IDTR %lld, IDFRAG %lld\n",
               cameras,
               people,
               poses ? "poses" : "boxes",
               enter_leave ? "enter/leave" : "closed",
               frames,
               static_cast<unsigned long long>(seed),
               r.whole.idf1,
               r.head.idf1,
               r.whole.hota,
               r.whole.mota,
               static_cast<long long>(r.whole.predicted_ids),
               static_cast<long long>(r.whole.gt_ids),
               static_cast<long long>(r.whole.id_transfers),
               static_cast<long long>(r.whole.id_fragmentations));
  return r;
}

json::OrderedDocument AccuracyJson(const Accuracy& a) {
  return {{"mota", a.mota},
          {"idf1", a.idf1},
          {"hota", a.hota},
          {"id_switches", a.switches},
          {"id_transfers", a.id_transfers},
          {"id_fragmentations", a.id_fragmentations},
          {"gt_ids", a.gt_ids},
          {"predicted_ids", a.predicted_ids}};
}

// --- latency --------------------------------------------------------------------------------

struct LatencyResult {
  int cameras = 0, people = 0;
  bool poses = false;
  int threads = 0;
  int frames = 0;
  std::int64_t windows = 0;
  double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;  // window close -> final publish
  double pipeline_mean_ms = 0.0, pipeline_max_ms = 0.0;
  // Per frame, capture (its camera-frames submitted) -> publish of the final and of the
  // provisional frame.
  double final_p50_ms = 0.0, final_p99_ms = 0.0, final_max_ms = 0.0;
  double now_p50_ms = 0.0, now_p99_ms = 0.0, now_max_ms = 0.0;
  std::int64_t late_frames = 0;  // frames submitted later than their schedule by > 1 period
  Accuracy accuracy;
  Accuracy now_accuracy;     // the provisional layer against the truth
  eval::LayerAgreement now;  // the provisional layer against the final output
};

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double rank = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (v[hi] - v[lo]) * (rank - static_cast<double>(lo));
}

// Feeds the scene to a Pipeline in real time (all cameras of frame f at start + f / fps) and
// measures, per window, the time from its closing camera-frame (the last camera-frame of the
// window's last frame: a frame closes when every camera delivered it) being submitted to the last
// frame it finalizes being handed to the output callback; and per frame, capture (its first
// camera-frame submitted) -> publish of its final and provisional frames.
LatencyResult MeasureLatency(
    int cameras, int people, bool poses, int threads, int frames, std::uint64_t seed) {
  sim::SceneOptions so = sim::SizedScene(cameras, people, poses, seed);
  so.num_frames = frames;
  const PreparedScene scene = Prepare(so);
  const tracker::TrackerOptions to = TrackerOptionsFor(so);
  pipeline::PipelineOptions po;
  po.camera_overflow = pipeline::OverflowPolicy::kBlock;
  pipeline::ThreadPoolOptions tpo;
  tpo.num_workers = threads;
  pipeline::SteadyClock clock;
  std::mutex mu;
  std::vector<tracker::Frame3D> out;
  std::vector<tracker::Frame3D> now_out;
  std::map<FrameIndex, std::int64_t> published_us;
  std::map<FrameIndex, std::int64_t> now_published_us;
  std::string why;
  auto p = pipeline::Pipeline::Create(
      geometry::CameraRig(scene.cameras),
      to,
      po,
      std::make_unique<pipeline::ThreadPoolExecutor>(tpo),
      clock,
      [&](tracker::Frame3D f) {
        const std::int64_t now = clock.NowMicros();
        std::lock_guard<std::mutex> lock(mu);
        published_us[f.frame] = now;
        out.push_back(std::move(f));
      },
      &why,
      [&](tracker::Frame3D f) {
        const std::int64_t now = clock.NowMicros();
        std::lock_guard<std::mutex> lock(mu);
        now_published_us[f.frame] = now;
        now_out.push_back(std::move(f));
      });
  if (!p) throw std::runtime_error("pipeline: " + why);
  std::map<FrameIndex, std::int64_t> first_submit_us;
  std::map<FrameIndex, std::int64_t> last_submit_us;
  LatencyResult r;
  const auto period = std::chrono::duration<double>(1.0 / so.fps);
  const auto start = Clock::now();
  std::size_t i = 0;
  for (int f = 0; f < frames; ++f) {
    const auto due = start + std::chrono::duration_cast<Clock::duration>(period * f);
    if (Clock::now() > due + std::chrono::duration_cast<Clock::duration>(period)) ++r.late_frames;
    std::this_thread::sleep_until(due);
    for (int c = 0; c < cameras && i < scene.camera_frames.size(); ++c, ++i) {
      const core::CameraFrame& cf = scene.camera_frames[i];
      if (c == 0) first_submit_us[cf.frame] = clock.NowMicros();
      if (c == cameras - 1) last_submit_us[cf.frame] = clock.NowMicros();
      p->Submit(cf);
    }
  }
  p->Flush();
  const pipeline::PipelineStatus status = p->Status();
  p->Stop();
  // Window k covers [F0 + k step, F0 + k step + size) and finalizes (k >= 1) the frames
  // [F0 + k step + (size - step) / 2, + step) (docs/ARCHITECTURE.md, "Time and windows").
  const FrameIndex f0 = scene.camera_frames.front().frame;
  const int size = to.window_size, step = to.window_step;
  std::vector<double> latencies_ms;
  for (std::int64_t k = 0;; ++k) {
    const FrameIndex last = f0 + k * step + size - 1;  // its last camera closes window k
    if (last >= f0 + frames - 1) break;                // later windows end with the flush
    const FrameIndex last_finalized = f0 + k * step + (size - step) / 2 + step - 1;
    const auto s = last_submit_us.find(last);
    const auto q = published_us.find(last_finalized);
    if (s == last_submit_us.end() || q == published_us.end()) continue;
    latencies_ms.push_back(static_cast<double>(q->second - s->second) / 1000.0);
  }
  r.cameras = cameras;
  r.people = people;
  r.poses = poses;
  r.threads = threads;
  r.frames = frames;
  r.windows = static_cast<std::int64_t>(latencies_ms.size());
  r.p50_ms = Percentile(latencies_ms, 0.50);
  r.p99_ms = Percentile(latencies_ms, 0.99);
  r.max_ms = latencies_ms.empty() ? std::nan("")
                                  : *std::max_element(latencies_ms.begin(), latencies_ms.end());
  r.pipeline_mean_ms = status.window_latency.mean_us() / 1000.0;
  r.pipeline_max_ms = static_cast<double>(status.window_latency.max_us) / 1000.0;
  // Capture -> publish per frame (the frames the flush output excluded: their wait is the end
  // of the input).
  std::vector<double> final_ms, now_ms;
  for (const auto& [frame, submitted] : first_submit_us) {
    if (const auto q = published_us.find(frame);
        q != published_us.end() && frame < f0 + frames - size) {
      final_ms.push_back(static_cast<double>(q->second - submitted) / 1000.0);
    }
    if (const auto q = now_published_us.find(frame); q != now_published_us.end()) {
      now_ms.push_back(static_cast<double>(q->second - submitted) / 1000.0);
    }
  }
  const auto max_of = [](const std::vector<double>& v) {
    return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end());
  };
  r.final_p50_ms = Percentile(final_ms, 0.50);
  r.final_p99_ms = Percentile(final_ms, 0.99);
  r.final_max_ms = max_of(final_ms);
  r.now_p50_ms = Percentile(now_ms, 0.50);
  r.now_p99_ms = Percentile(now_ms, 0.99);
  r.now_max_ms = max_of(now_ms);
  r.accuracy = Score(scene.truth, out);
  r.now_accuracy = Score(scene.truth, now_out);
  {
    eval::EvalSequence final_seq, now_seq;
    for (const tracker::Frame3D& f : out) final_seq.push_back(TrackEvalFrame(f));
    for (const tracker::Frame3D& f : now_out) now_seq.push_back(TrackEvalFrame(f));
    r.now = eval::CompareLayers(final_seq, now_seq);
  }
  std::fprintf(stderr,
               "  latency %d cams %d people %s, %d worker(s): window close -> publish p50 %.2f "
               "ms, p99 %.2f ms, max %.2f ms over %lld windows; MOTA %.3f IDF1 %.3f\n"
               "    capture -> publish: provisional p50 %.1f p99 %.1f max %.1f ms, final p50 %.1f "
               "p99 %.1f max %.1f ms; provisional ids the final's %.2f %%, median %.3f m, MOTA "
               "%.3f\n",
               cameras,
               people,
               poses ? "poses" : "boxes",
               threads,
               r.p50_ms,
               r.p99_ms,
               r.max_ms,
               static_cast<long long>(r.windows),
               r.accuracy.mota,
               r.accuracy.idf1,
               r.now_p50_ms,
               r.now_p99_ms,
               r.now_max_ms,
               r.final_p50_ms,
               r.final_p99_ms,
               r.final_max_ms,
               100.0 * r.now.same_id_fraction(),
               r.now.median_distance_m,
               r.now_accuracy.mota);
  return r;
}

// --- soak -----------------------------------------------------------------------------------

struct SoakResult {
  int cameras = 0, people = 0;
  bool poses = false;
  int threads = 0;
  std::int64_t frames = 0;
  double wall_s = 0.0;
  double simulate_s = 0.0;  // main-thread time spent simulating (overlaps the pipeline)
  std::vector<std::pair<std::int64_t, double>> rss_mib;  // (frames submitted, RSS)
  double peak_rss_mib = 0.0;
  double rss_growth_after_warmup_mib = 0.0;
  std::vector<Accuracy> chunks;
  std::int64_t chunk_frames = 0;
  std::int64_t tracks_born = 0;
};

// Streams a long enter-and-leave scene through a Pipeline as fast as possible (simulated on
// the fly, so memory does not hold the scene), sampling the RSS, and scores it in chunks.
SoakResult MeasureSoak(int cameras,
                       int people,
                       bool poses,
                       int threads,
                       std::int64_t frames,
                       std::int64_t sample_every,
                       std::int64_t chunk_frames,
                       std::uint64_t seed) {
  sim::SceneOptions so = sim::SizedScene(cameras, people, poses, seed);
  so.enter_and_leave = true;
  so.num_frames = static_cast<int>(std::min<std::int64_t>(frames, 1 << 30));
  const std::vector<geometry::CameraModel> rig_cameras = sim::MakeCameras(so);
  const tracker::TrackerOptions to = TrackerOptionsFor(so);
  pipeline::PipelineOptions po;
  po.camera_overflow = pipeline::OverflowPolicy::kBlock;
  pipeline::ThreadPoolOptions tpo;
  tpo.num_workers = threads;
  pipeline::SteadyClock clock;
  std::mutex mu;
  std::deque<tracker::Frame3D> out;
  std::string why;
  auto p = pipeline::Pipeline::Create(
      geometry::CameraRig(rig_cameras),
      to,
      po,
      std::make_unique<pipeline::ThreadPoolExecutor>(tpo),
      clock,
      [&](tracker::Frame3D f) {
        std::lock_guard<std::mutex> lock(mu);
        out.push_back(std::move(f));
      },
      &why);
  if (!p) throw std::runtime_error("pipeline: " + why);
  SoakResult r;
  r.cameras = cameras;
  r.people = people;
  r.poses = poses;
  r.threads = threads;
  r.frames = frames;
  r.chunk_frames = chunk_frames;
  sim::CrowdSimulator crowd(so);
  std::deque<eval::EvalFrame> truth_chunk;
  std::int64_t chunk_begin = 0;
  // Scores frames [chunk_begin, end) once the pipeline has output all of them.
  auto score_chunk = [&](std::int64_t end) {
    std::vector<tracker::Frame3D> pred;
    {
      std::lock_guard<std::mutex> lock(mu);
      while (!out.empty() && out.front().frame < end) {
        pred.push_back(std::move(out.front()));
        out.pop_front();
      }
    }
    eval::EvalSequence truth;
    while (!truth_chunk.empty() && truth_chunk.front().frame < end) {
      truth.push_back(std::move(truth_chunk.front()));
      truth_chunk.pop_front();
    }
    r.chunks.push_back(Score(truth, pred));
    chunk_begin = end;
  };
  ResetPeakRss();
  const auto start = Clock::now();
  auto last_progress = start;
  const std::int64_t lag = to.window_size + to.window_step;  // output lags input by < this
  for (std::int64_t f = 0; f < frames; ++f) {
    const auto sim_start = Clock::now();
    const sim::FrameTruth truth = crowd.Next();
    sim::RenderedFrame rendered = sim::RenderFrame(so, rig_cameras, truth);
    truth_chunk.push_back(TruthEvalFrame(truth, poses));
    r.simulate_s += SecondsSince(sim_start);
    for (core::CameraFrame& cf : rendered.cameras) p->Submit(std::move(cf));
    if (f % sample_every == 0) r.rss_mib.emplace_back(f, RssMiB());
    if (f + 1 - chunk_begin >= chunk_frames + lag) {
      // Wait until the chunk's frames are out (they are, unless the pipeline lags behind).
      for (;;) {
        {
          std::lock_guard<std::mutex> lock(mu);
          if (!out.empty() && out.back().frame >= chunk_begin + chunk_frames - 1) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      score_chunk(chunk_begin + chunk_frames);
    }
    if (Clock::now() - last_progress > std::chrono::seconds(5)) {
      last_progress = Clock::now();
      std::fprintf(stderr,
                   "\r  soak: frame %lld / %lld, RSS %.1f MiB",
                   static_cast<long long>(f),
                   static_cast<long long>(frames),
                   RssMiB());
    }
  }
  p->Flush();
  r.wall_s = SecondsSince(start);
  r.rss_mib.emplace_back(frames, RssMiB());
  r.tracks_born = p->Status().tracker.tracks_born;
  p->Stop();
  score_chunk(frames);
  r.peak_rss_mib = PeakRssMiB();
  // Growth after warm-up: last sample minus the first sample at or after the first chunk.
  double warm = r.rss_mib.front().second;
  for (const auto& [f, mib] : r.rss_mib) {
    if (f >= chunk_frames) {
      warm = mib;
      break;
    }
  }
  r.rss_growth_after_warmup_mib = r.rss_mib.back().second - warm;
  std::fprintf(stderr,
               "\r  soak: %lld frames (%d cams, %d people entering and leaving, %s, %d workers) "
               "in %.0f s; RSS %.1f -> %.1f MiB (peak %.1f), growth after warm-up %.2f MiB\n",
               static_cast<long long>(frames),
               cameras,
               people,
               poses ? "poses" : "boxes",
               threads,
               r.wall_s,
               r.rss_mib.front().second,
               r.rss_mib.back().second,
               r.peak_rss_mib,
               r.rss_growth_after_warmup_mib);
  return r;
}

// --- the plot -------------------------------------------------------------------------------

// A log-scale panel of FPS against cameras, one line per people count.
void DrawPanel(
    cv::Mat* img,
    const cv::Rect& area,
    const std::string& title,
    const std::string& x_label,
    const std::vector<int>& xs,
    const std::vector<std::pair<std::string, std::vector<std::pair<int, double>>>>& lines,
    const std::vector<std::tuple<int, double, std::string>>& markers,
    double realtime_line) {
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  const int left = area.x + 70, right = area.x + area.width - 20;
  const int top = area.y + 40, bottom = area.y + area.height - 50;
  double lo = 1e300, hi = 0.0;
  for (const auto& [name, pts] : lines) {
    for (const auto& [x, y] : pts) {
      if (y > 0.0) lo = std::min(lo, y), hi = std::max(hi, y);
    }
  }
  for (const auto& [x, y, label] : markers) lo = std::min(lo, y), hi = std::max(hi, y);
  if (realtime_line > 0.0) lo = std::min(lo, realtime_line), hi = std::max(hi, realtime_line);
  if (hi <= 0.0) return;
  const double ylo = std::pow(10.0, std::floor(std::log10(lo)));
  const double yhi = std::pow(10.0, std::ceil(std::log10(hi)));
  const int xmin = xs.front(), xmax = xs.back();
  auto px = [&](double x) {
    return left +
           static_cast<int>(std::lround((x - xmin) / std::max(1, xmax - xmin) * (right - left)));
  };
  auto py = [&](double y) {
    return bottom -
           static_cast<int>(std::lround((std::log10(y) - std::log10(ylo)) /
                                        (std::log10(yhi) - std::log10(ylo)) * (bottom - top)));
  };
  cv::putText(*img,
              title,
              {area.x + 70, area.y + 25},
              cv::FONT_HERSHEY_SIMPLEX,
              0.6,
              black,
              1,
              cv::LINE_AA);
  for (double d = ylo; d <= yhi * 1.0001; d *= 10.0) {
    cv::line(*img, {left, py(d)}, {right, py(d)}, grey, 1);
    char buf[32];
    std::snprintf(buf, sizeof(buf), d >= 1e3 ? "%.0e" : "%.0f", d);
    cv::putText(
        *img, buf, {area.x + 8, py(d) + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1, cv::LINE_AA);
  }
  for (const int x : xs) {
    cv::line(*img, {px(x), bottom}, {px(x), bottom + 5}, black, 1);
    cv::putText(*img,
                std::to_string(x),
                {px(x) - 6, bottom + 20},
                cv::FONT_HERSHEY_SIMPLEX,
                0.45,
                black,
                1,
                cv::LINE_AA);
  }
  cv::rectangle(*img, {left, top}, {right, bottom}, black, 1);
  cv::putText(*img,
              x_label,
              {(left + right) / 2 - 30, bottom + 42},
              cv::FONT_HERSHEY_SIMPLEX,
              0.5,
              black,
              1,
              cv::LINE_AA);
  cv::putText(
      *img, "FPS", {area.x + 8, top - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  if (realtime_line > 0.0) {
    cv::line(*img, {left, py(realtime_line)}, {right, py(realtime_line)}, cv::Scalar(0, 0, 220), 1);
    cv::putText(*img,
                "real time (30 FPS)",
                {right - 150, py(realtime_line) - 6},
                cv::FONT_HERSHEY_SIMPLEX,
                0.4,
                cv::Scalar(0, 0, 220),
                1,
                cv::LINE_AA);
  }
  static const std::array<cv::Scalar, 6> kColors = {cv::Scalar(180, 119, 31),
                                                    cv::Scalar(14, 127, 255),
                                                    cv::Scalar(44, 160, 44),
                                                    cv::Scalar(40, 39, 214),
                                                    cv::Scalar(189, 103, 148),
                                                    cv::Scalar(75, 86, 140)};
  int legend_y = top + 18;
  for (std::size_t li = 0; li < lines.size(); ++li) {
    const cv::Scalar& color = kColors[li % kColors.size()];
    const auto& pts = lines[li].second;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const cv::Point p(px(pts[k].first), py(pts[k].second));
      cv::circle(*img, p, 4, color, cv::FILLED, cv::LINE_AA);
      if (k > 0) {
        cv::line(*img, {px(pts[k - 1].first), py(pts[k - 1].second)}, p, color, 2, cv::LINE_AA);
      }
    }
    cv::line(*img, {right - 150, legend_y - 4}, {right - 125, legend_y - 4}, color, 2);
    cv::putText(*img,
                lines[li].first,
                {right - 120, legend_y},
                cv::FONT_HERSHEY_SIMPLEX,
                0.45,
                black,
                1,
                cv::LINE_AA);
    legend_y += 18;
  }
  for (const auto& [x, y, label] : markers) {
    const cv::Point p(px(x), py(y));
    cv::drawMarker(*img, p, black, cv::MARKER_TILTED_CROSS, 12, 2, cv::LINE_AA);
    cv::putText(
        *img, label, {p.x + 8, p.y + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  }
}

void WritePlot(const std::string& path, const std::vector<PointResult>& points) {
  std::vector<const PointResult*> paper, scale;
  for (const PointResult& r : points) {
    if (r.suite == "paper" || r.suite == "smoke") paper.push_back(&r);
    if (r.suite == "scale" || r.suite == "smoke_scale") scale.push_back(&r);
  }
  const int panels = (paper.empty() ? 0 : 2) + (scale.empty() ? 0 : 1);
  if (panels == 0) return;
  const int w = 520, h = 440;
  cv::Mat img(h, w * panels, CV_8UC3, cv::Scalar(255, 255, 255));
  int panel = 0;
  for (const bool poses : {false, true}) {
    if (paper.empty()) break;
    std::map<int, std::vector<std::pair<int, double>>> by_people;
    std::vector<int> xs;
    for (const PointResult* r : paper) {
      if (r->poses != poses) continue;
      by_people[r->people].emplace_back(r->cameras, r->fps);
      xs.push_back(r->cameras);
    }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    if (xs.empty()) continue;
    std::vector<std::pair<std::string, std::vector<std::pair<int, double>>>> lines;
    for (auto& [people, pts] : by_people) {
      std::sort(pts.begin(), pts.end());
      lines.emplace_back(std::to_string(people) + " people", pts);
    }
    std::vector<std::tuple<int, double, std::string>> markers;
    if (xs.back() >= 6) {
      markers = {{2, 1643.0, "paper 2p"}, {6, 186.0, "paper 2p"}, {2, 1286.0, "paper 8p"}};
    }
    DrawPanel(&img,
              cv::Rect(panel * w, 0, w, h),
              std::string("mvtrack, ") + (poses ? "poses" : "boxes") + ", 1 thread (x = paper)",
              "cameras",
              xs,
              lines,
              markers,
              30.0);
    ++panel;
  }
  if (!scale.empty()) {
    std::map<std::string, std::vector<std::pair<int, double>>> by_config;
    std::vector<int> xs;
    for (const PointResult* r : scale) {
      by_config[std::to_string(r->cameras) + " cams, " +
                (r->threads == 0 ? std::string("1 thr") : std::to_string(r->threads) + " wkr")]
          .emplace_back(r->people, r->fps);
      xs.push_back(r->people);
    }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::vector<std::pair<std::string, std::vector<std::pair<int, double>>>> lines;
    for (auto& [name, pts] : by_config) {
      std::sort(pts.begin(), pts.end());
      lines.emplace_back(name, pts);
    }
    DrawPanel(
        &img, cv::Rect(panel * w, 0, w, h), "store floor, boxes", "people", xs, lines, {}, 30.0);
  }
  if (!cv::imwrite(path, img)) throw std::runtime_error(path + ": cannot write the PNG");
}

// --- tables ---------------------------------------------------------------------------------

std::string Fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string PointsTable(const std::vector<PointResult>& points, const std::string& suite) {
  std::string t =
      "| cameras | people | mode | threads | FPS | FPS per CPU-s | camera-frames/s | paper FPS | "
      "ratio | MOTA | IDF1 | HOTA | IDTR | MPJPE mm | 2-view coverage | peak RSS MiB |\n"
      "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const PointResult& r : points) {
    if (r.suite != suite) continue;
    t += "| " + std::to_string(r.cameras) + " | " + std::to_string(r.people) + " | " +
         (r.poses ? "poses" : "boxes") + " | " +
         (r.threads == 0 ? std::string("1 (inline)") : std::to_string(r.threads) + " workers") +
         " | " + Fmt("%.0f", r.fps) + " | " + Fmt("%.0f", r.cpu_fps) + " | " +
         Fmt("%.0f", r.camera_fps) + " | " + (r.paper_fps > 0 ? Fmt("%.0f", r.paper_fps) : "") +
         " | " + (r.paper_fps > 0 ? Fmt("%.1f×", r.fps / r.paper_fps) : "") + " | " +
         Fmt("%.3f", r.accuracy.mota) + " | " + Fmt("%.3f", r.accuracy.idf1) + " | " +
         Fmt("%.3f", r.accuracy.hota) + " | " + std::to_string(r.accuracy.id_transfers) + " | " +
         Fmt("%.1f", r.accuracy.mpjpe_m * 1000.0) + " | " + Fmt("%.2f", r.coverage) + " | " +
         Fmt("%.0f", r.peak_rss_mib) + " |\n";
  }
  return t;
}

// Fits log(seconds per frame) = a + b log(cameras) + c log(people) over the paper grid of one
// mode (least squares); returns (b, c), the measured growth exponents.
std::pair<double, double> GrowthExponents(const std::vector<PointResult>& points, bool poses) {
  Eigen::MatrixXd a(0, 3);
  Eigen::VectorXd y(0);
  for (const PointResult& r : points) {
    if (r.suite != "paper" || r.poses != poses || r.threads != 0) continue;
    a.conservativeResize(a.rows() + 1, 3);
    y.conservativeResize(y.rows() + 1);
    a.row(a.rows() - 1) << 1.0, std::log(r.cameras), std::log(r.people);
    y(y.rows() - 1) = -std::log(r.fps);
  }
  if (a.rows() < 3) return {std::nan(""), std::nan("")};
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(y);
  return {x(1), x(2)};
}

// "2,4,8" -> {2, 4, 8}, each in [lo, hi]; UsageError naming --`option` otherwise.
std::vector<int> IntList(const std::string& text, const std::string& option, int lo, int hi) {
  std::vector<int> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    long v = 0;
    try {
      v = std::stol(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || v < lo || v > hi) {
      throw UsageError("--" + option + ": '" + item + "' is not an integer in [" +
                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    values.push_back(static_cast<int>(v));
  }
  if (values.empty()) throw UsageError("--" + option + ": empty list");
  return values;
}

}  // namespace

int RunBench(int argc, char** argv) {
  Args args;
  args.Option("suite",
              "comma-separated suites: smoke, paper, scale, latency, soak, identity, custom, or "
              "full (= paper, scale, latency, soak, identity)",
              "smoke")
      .Option("out", "directory for results.json, results.md and fps.png", "bench/results")
      .Option("frames", "frames per scene of the paper and scale grids", "900")
      .Option("repeats", "timed runs per point at least (the median is reported)", "3")
      .Option("min-seconds", "repeat a point until its runs took at least this long", "1.0")
      .Option("latency-seconds", "length of the real-time paced latency run", "60")
      .Option("soak-frames", "frames of the soak run (108000 = one hour at 30 fps)", "108000")
      .Option("seed", "simulation seed", "1")
      .Option("cameras", "suite custom: comma-separated camera counts", "8")
      .Option("people", "suite custom: comma-separated people counts", "16")
      .Option("mode", "suite custom: boxes, poses or both", "boxes")
      .Option("threads",
              "suite custom: comma-separated runners, 0 = tracker inline (one thread), "
              "N = pipeline with N workers",
              "0")
      .Option("config",
              "tracker options file (a `tracker:` YAML document) every run starts from; the "
              "mode comes from the suite",
              "");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack bench [options]",
          "Measures the tracker on simulated scenes (mvtrack sim's presets) and scores\n"
          "every run against the simulation's ground truth. FPS = multi-view frames (one\n"
          "camera-frame of every camera) per second of tracking, detections in to tracks\n"
          "out, detection and simulation excluded. Suites:\n"
          "  paper    the paper's speed study: cameras {2,3,4,5,6,8} x people {2,4,8,16},\n"
          "           boxes and poses, one thread (tracker::Tracker inline)\n"
          "  scale    store floor: cameras {16,32} x people {32,64,100}, boxes, inline\n"
          "           and the threaded pipeline with 1 and 2 workers\n"
          "  latency  8 x 16 (boxes, poses) and 32 x 100 (boxes) fed in real time to the\n"
          "           pipeline (2 workers): window close -> publish, and per frame capture ->\n"
          "           publish of the provisional and the final layer, p50/p99/max\n"
          "  soak     --soak-frames of 8 cameras x 16 people entering and leaving, as fast\n"
          "           as possible, RSS sampled (memory must stay flat)\n"
          "  smoke    a tiny version of all of them (seconds; what CI runs)\n"
          "  identity long runs with people coming and going (4 x 12 enter/leave, 9000\n"
          "           frames, boxes and poses; 2 x 8, 6000 frames; 32 x 100): MOTA,\n"
          "           IDF1 (whole run and first 10 %), HOTA, id transfers/fragmentations\n"
          "  custom   --cameras x --people x --mode x --threads, for sizing a deployment\n"
          "Writes OUT/results.json, OUT/results.md and OUT/fps.png; progress on stderr.")) {
    return 0;
  }
  std::vector<std::string> suites;
  {
    std::stringstream ss(args.Get("suite"));
    std::string s;
    while (std::getline(ss, s, ',')) {
      if (s == "full") {
        for (const char* x : {"paper", "scale", "latency", "soak", "identity"}) {
          suites.emplace_back(x);
        }
      } else if (s == "smoke" || s == "paper" || s == "scale" || s == "latency" || s == "soak" ||
                 s == "custom" || s == "identity") {
        suites.push_back(s);
      } else {
        throw UsageError("--suite: unknown suite '" + s +
                         "' (smoke, paper, scale, latency, soak, identity, full, custom)");
      }
    }
  }
  if (!args.Get("config").empty()) {
    BaseTrackerOptions() = config::LoadTrackerOptionsFile(args.Get("config"));
  }
  const auto frames = static_cast<int>(args.GetInt("frames"));
  const auto repeats = static_cast<int>(args.GetInt("repeats"));
  const double min_seconds = args.GetDouble("min-seconds");
  const double latency_seconds = args.GetDouble("latency-seconds");
  const std::int64_t soak_frames = args.GetInt("soak-frames");
  const std::int64_t seed_arg = args.GetInt("seed");
  if (frames < 60 || frames > 1000000) throw UsageError("--frames must be in [60, 1000000]");
  if (repeats < 1 || repeats > 100) throw UsageError("--repeats must be in [1, 100]");
  if (!(min_seconds >= 0.0)) throw UsageError("--min-seconds must be >= 0");
  if (!(latency_seconds >= 3.0)) throw UsageError("--latency-seconds must be >= 3");
  if (soak_frames < 300) throw UsageError("--soak-frames must be >= 300");
  if (seed_arg < 0) throw UsageError("--seed must be >= 0");
  const auto seed = static_cast<std::uint64_t>(seed_arg);
  const std::filesystem::path out = args.Get("out");
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw std::runtime_error(out.string() + ": cannot create directory: " + ec.message());

  const std::string build_type = MVTRACK_BUILD_TYPE;
  if (build_type != "Release" && build_type != "RelWithDebInfo") {
    std::fprintf(stderr,
                 "mvtrack bench: warning: this is a '%s' build; measure with Release or "
                 "RelWithDebInfo\n",
                 build_type.c_str());
  }
  const std::string load_before = ReadFirstLine("/proc/loadavg");
  const std::string started = UtcNow();
  const auto bench_start = Clock::now();
  std::fprintf(stderr,
               "mvtrack bench: %s, %u hardware threads, load %s\n",
               CpuModel().c_str(),
               std::thread::hardware_concurrency(),
               load_before.c_str());

  std::vector<PointResult> points;
  std::vector<IdentityResult> identities;
  std::vector<LatencyResult> latencies;
  std::vector<SoakResult> soaks;
  for (const std::string& suite : suites) {
    std::fprintf(stderr, "suite %s\n", suite.c_str());
    if (suite == "smoke") {
      for (const bool poses : {false, true}) {
        for (const int c : {2, 3}) {
          for (const int p : {2, 4}) {
            MeasurePoint("smoke", c, p, poses, {0}, 120, 1, 0.0, seed, &points);
          }
        }
      }
      MeasurePoint("smoke_scale", 16, 32, false, {0, 2}, 90, 1, 0.0, seed, &points);
      latencies.push_back(MeasureLatency(4, 4, false, 2, 90, seed));
      soaks.push_back(MeasureSoak(3, 4, false, 2, 900, 100, 300, seed));
    } else if (suite == "paper") {
      for (const bool poses : {false, true}) {
        for (const int c : {2, 3, 4, 5, 6, 8}) {
          for (const int p : {2, 4, 8, 16}) {
            MeasurePoint("paper", c, p, poses, {0}, frames, repeats, min_seconds, seed, &points);
          }
        }
      }
    } else if (suite == "scale") {
      for (const int c : {16, 32}) {
        for (const int p : {32, 64, 100}) {
          MeasurePoint("scale", c, p, false, {0, 1, 2}, frames, 1, 0.0, seed, &points);
        }
      }
    } else if (suite == "latency") {
      const int n = static_cast<int>(std::lround(latency_seconds * 30.0));
      for (const bool poses : {false, true})
        latencies.push_back(MeasureLatency(8, 16, poses, 2, n, seed));
      latencies.push_back(MeasureLatency(32, 100, false, 2, n, seed));
    } else if (suite == "custom") {
      const std::string mode = args.Get("mode");
      if (mode != "boxes" && mode != "poses" && mode != "both") {
        throw UsageError("--mode must be boxes, poses or both");
      }
      const std::vector<int> threads = IntList(args.Get("threads"), "threads", 0, 64);
      for (const int c : IntList(args.Get("cameras"), "cameras", 2, 4096)) {
        for (const int p : IntList(args.Get("people"), "people", 0, 100000)) {
          for (const bool poses : {false, true}) {
            if ((poses && mode == "boxes") || (!poses && mode == "poses")) continue;
            MeasurePoint(
                "custom", c, p, poses, threads, frames, repeats, min_seconds, seed, &points);
          }
        }
      }
    } else if (suite == "soak") {
      soaks.push_back(MeasureSoak(8, 16, false, 2, soak_frames, 1000, 9000, seed));
    } else if (suite == "identity") {
      // The scenes (seeds 11 and 5), then a second seed of each, 32 x 100 last.
      for (const std::uint64_t s : {std::uint64_t{11}, std::uint64_t{21}}) {
        identities.push_back(MeasureIdentity(4, 12, false, true, 9000, s));
        identities.push_back(MeasureIdentity(4, 12, true, true, 9000, s));
      }
      for (const std::uint64_t s : {std::uint64_t{5}, std::uint64_t{15}}) {
        identities.push_back(MeasureIdentity(2, 8, false, false, 6000, s));
      }
      identities.push_back(MeasureIdentity(32, 100, false, false, 900, 1));
    }
  }
  const double total_s = SecondsSince(bench_start);
  const std::string load_after = ReadFirstLine("/proc/loadavg");

  // results.json
  std::vector<json::OrderedDocument> point_json, latency_json, soak_json;
  for (const PointResult& r : points) point_json.push_back(PointJson(r));
  for (const LatencyResult& l : latencies) {
    latency_json.push_back(
        json::OrderedDocument{{"cameras", l.cameras},
                              {"people", l.people},
                              {"mode", l.poses ? "poses" : "boxes"},
                              {"worker_threads", l.threads},
                              {"frames", l.frames},
                              {"windows", l.windows},
                              {"p50_ms", l.p50_ms},
                              {"p99_ms", l.p99_ms},
                              {"max_ms", l.max_ms},
                              {"pipeline_job_to_link_mean_ms", l.pipeline_mean_ms},
                              {"pipeline_job_to_link_max_ms", l.pipeline_max_ms},
                              {"capture_to_final_p50_ms", l.final_p50_ms},
                              {"capture_to_final_p99_ms", l.final_p99_ms},
                              {"capture_to_final_max_ms", l.final_max_ms},
                              {"capture_to_provisional_p50_ms", l.now_p50_ms},
                              {"capture_to_provisional_p99_ms", l.now_p99_ms},
                              {"capture_to_provisional_max_ms", l.now_max_ms},
                              {"provisional_same_id", l.now.same_id_fraction()},
                              {"provisional_coverage", l.now.coverage()},
                              {"provisional_median_distance_m", l.now.median_distance_m},
                              {"provisional_mota", l.now_accuracy.mota},
                              {"provisional_idf1", l.now_accuracy.idf1},
                              {"late_frames", l.late_frames},
                              {"mota", l.accuracy.mota},
                              {"idf1", l.accuracy.idf1},
                              {"hota", l.accuracy.hota},
                              {"id_transfers", l.accuracy.id_transfers},
                              {"mpjpe_m", l.accuracy.mpjpe_m}});
  }
  std::vector<json::OrderedDocument> identity_json;
  identity_json.reserve(identities.size());
  for (const IdentityResult& r : identities) {
    identity_json.push_back(json::OrderedDocument{{"cameras", r.cameras},
                                                  {"people", r.people},
                                                  {"mode", r.poses ? "poses" : "boxes"},
                                                  {"enter_and_leave", r.enter_leave},
                                                  {"frames", r.frames},
                                                  {"seed", static_cast<std::int64_t>(r.seed)},
                                                  {"fps", r.fps},
                                                  {"whole_run", AccuracyJson(r.whole)},
                                                  {"first_10_percent", AccuracyJson(r.head)}});
  }
  for (const SoakResult& s : soaks) {
    std::vector<json::OrderedDocument> samples, chunks;
    for (const auto& [f, mib] : s.rss_mib) {
      samples.push_back(json::OrderedDocument::array({f, mib}));
    }
    for (const Accuracy& a : s.chunks) {
      chunks.push_back(AccuracyJson(a));
    }
    soak_json.push_back(json::OrderedDocument{
        {"cameras", s.cameras},
        {"people", s.people},
        {"mode", s.poses ? "poses" : "boxes"},
        {"enter_and_leave", true},
        {"worker_threads", s.threads},
        {"frames", s.frames},
        {"wall_s", s.wall_s},
        {"simulate_s", s.simulate_s},
        {"fps_including_simulation", static_cast<double>(s.frames) / s.wall_s},
        {"peak_rss_mib", s.peak_rss_mib},
        {"rss_growth_after_warmup_mib", s.rss_growth_after_warmup_mib},
        {"tracks_born", s.tracks_born},
        {"chunk_frames", s.chunk_frames},
        {"rss_samples_frame_mib", samples},
        {"chunk_accuracy", chunks}});
  }
  json::OrderedDocument growth = json::OrderedDocument::object();
  for (const bool poses : {false, true}) {
    const auto [b, c] = GrowthExponents(points, poses);
    growth[poses ? "poses" : "boxes"] = {{"cameras_exponent", b}, {"people_exponent", c}};
  }
  const json::OrderedDocument results = {
      {"schema", "mvtrack.bench/1"},
      {"version", MVTRACK_VERSION},
      {"build_type", build_type},
      {"started_utc", started},
      {"cpu", CpuModel()},
      {"hardware_threads", std::thread::hardware_concurrency()},
      {"loadavg_before", load_before},
      {"loadavg_after", load_after},
      {"total_s", total_s},
      {"fps_definition",
       "multi-view frames (one camera-frame from every camera) per second of tracking "
       "time, detections in to tracks out; detection and simulation excluded"},
      {"growth_exponents", growth},
      {"points", point_json},
      {"identity", identity_json},
      {"latency", latency_json},
      {"soak", soak_json}};
  const std::string results_text = json::Dump(results, 2) + "\n";
  {
    std::ofstream f(out / "results.json", std::ios::trunc);
    f << results_text;
    if (!f) throw std::runtime_error((out / "results.json").string() + ": write error");
  }

  // results.md
  std::string md = "Measured " + started + " with `mvtrack bench --suite " + args.Get("suite") +
                   "` (" + build_type + " build, mvtrack " + MVTRACK_VERSION + ") on " +
                   CpuModel() + ", " + std::to_string(std::thread::hardware_concurrency()) +
                   " hardware threads; load average before: " + load_before +
                   ", after: " + load_after + "; total " + Fmt("%.0f", total_s) + " s.\n\n";
  for (const char* suite : {"smoke", "smoke_scale", "paper", "scale", "custom"}) {
    bool any = false;
    for (const PointResult& r : points) any = any || r.suite == suite;
    if (!any) continue;
    md += std::string("### ") + suite + "\n\n" + PointsTable(points, suite) + "\n";
  }
  for (const bool poses : {false, true}) {
    const auto [b, c] = GrowthExponents(points, poses);
    if (std::isfinite(b)) {
      md += std::string("Growth (") + (poses ? "poses" : "boxes") +
            ", least-squares fit of time per frame over the paper grid): ∝ cameras^" +
            Fmt("%.2f", b) + " × people^" + Fmt("%.2f", c) + "\n\n";
    }
  }
  if (!identities.empty()) {
    md +=
        "### identity over long runs\n\n| cameras × people | mode | people | frames | seed | "
        "MOTA | IDF1 | IDF1 first 10 % | HOTA | GT ids | predicted ids | IDTR | IDFRAG | FPS "
        "|\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const IdentityResult& r : identities) {
      md += "| " + std::to_string(r.cameras) + " × " + std::to_string(r.people) + " | " +
            (r.poses ? "poses" : "boxes") + " | " + (r.enter_leave ? "enter/leave" : "stay") +
            " | " + std::to_string(r.frames) + " | " + std::to_string(r.seed) + " | " +
            Fmt("%.1f", 100.0 * r.whole.mota) + " | " + Fmt("%.1f", 100.0 * r.whole.idf1) + " | " +
            Fmt("%.1f", 100.0 * r.head.idf1) + " | " + Fmt("%.1f", 100.0 * r.whole.hota) + " | " +
            std::to_string(r.whole.gt_ids) + " | " + std::to_string(r.whole.predicted_ids) + " | " +
            std::to_string(r.whole.id_transfers) + " | " +
            std::to_string(r.whole.id_fragmentations) + " | " + Fmt("%.0f", r.fps) + " |\n";
    }
    md += "\n";
  }
  if (!latencies.empty()) {
    md +=
        "### latency (window close → publish)\n\n| cameras | people | mode | workers | windows "
        "| p50 ms | p99 ms | max ms | MOTA | IDF1 | HOTA | IDTR "
        "|\n|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const LatencyResult& l : latencies) {
      md += "| " + std::to_string(l.cameras) + " | " + std::to_string(l.people) + " | " +
            (l.poses ? "poses" : "boxes") + " | " + std::to_string(l.threads) + " | " +
            std::to_string(l.windows) + " | " + Fmt("%.2f", l.p50_ms) + " | " +
            Fmt("%.2f", l.p99_ms) + " | " + Fmt("%.2f", l.max_ms) + " | " +
            Fmt("%.3f", l.accuracy.mota) + " | " + Fmt("%.3f", l.accuracy.idf1) + " | " +
            Fmt("%.3f", l.accuracy.hota) + " | " + std::to_string(l.accuracy.id_transfers) + " |\n";
    }
    md +=
        "\n### latency (capture → publish, per frame), provisional and final\n\n| cameras | people "
        "| mode | workers | late frames | provisional p50 / p99 / max ms | final p50 / p99 / max "
        "ms "
        "| provisional ids = final's | median to final m | provisional MOTA / IDF1 | final MOTA / "
        "IDF1 |\n|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const LatencyResult& l : latencies) {
      md += "| " + std::to_string(l.cameras) + " | " + std::to_string(l.people) + " | " +
            (l.poses ? "poses" : "boxes") + " | " + std::to_string(l.threads) + " | " +
            std::to_string(l.late_frames) + " | " + Fmt("%.1f", l.now_p50_ms) + " / " +
            Fmt("%.1f", l.now_p99_ms) + " / " + Fmt("%.1f", l.now_max_ms) + " | " +
            Fmt("%.1f", l.final_p50_ms) + " / " + Fmt("%.1f", l.final_p99_ms) + " / " +
            Fmt("%.1f", l.final_max_ms) + " | " + Fmt("%.2f %%", 100.0 * l.now.same_id_fraction()) +
            " | " + Fmt("%.3f", l.now.median_distance_m) + " | " +
            Fmt("%.3f", l.now_accuracy.mota) + " / " + Fmt("%.3f", l.now_accuracy.idf1) + " | " +
            Fmt("%.3f", l.accuracy.mota) + " / " + Fmt("%.3f", l.accuracy.idf1) + " |\n";
    }
    md += "\n";
  }
  for (const SoakResult& s : soaks) {
    double mota = 0.0, idf1 = 0.0, hota = 0.0;
    std::int64_t transfers = 0;
    for (const Accuracy& a : s.chunks) {
      mota += a.mota;
      idf1 += a.idf1;
      hota += a.hota;
      transfers += a.id_transfers;
    }
    const double n = static_cast<double>(std::max<std::size_t>(1, s.chunks.size()));
    md += "### soak\n\n" + std::to_string(s.frames) + " frames, " + std::to_string(s.cameras) +
          " cameras, " + std::to_string(s.people) + " people entering and leaving (" +
          std::to_string(s.tracks_born) + " tracks born), boxes, pipeline with " +
          std::to_string(s.threads) + " workers, as fast as possible: " + Fmt("%.0f", s.wall_s) +
          " s wall (" + Fmt("%.0f", static_cast<double>(s.frames) / s.wall_s) +
          " FPS including the simulation, of which " + Fmt("%.0f", s.simulate_s) +
          " s simulating on the feeding thread). RSS " + Fmt("%.1f", s.rss_mib.front().second) +
          " MiB at the start, " + Fmt("%.1f", s.rss_mib.back().second) + " MiB at the end, peak " +
          Fmt("%.1f", s.peak_rss_mib) + " MiB; growth after the first " +
          std::to_string(s.chunk_frames) +
          " frames: " + Fmt("%.2f", s.rss_growth_after_warmup_mib) + " MiB. Accuracy, mean over " +
          std::to_string(s.chunks.size()) + " chunks of " + std::to_string(s.chunk_frames) +
          " frames: MOTA " + Fmt("%.3f", mota / n) + ", IDF1 " + Fmt("%.3f", idf1 / n) + ", HOTA " +
          Fmt("%.3f", hota / n) + ", id transfers " + std::to_string(transfers) +
          " in all.\n\nRSS samples (frame: MiB): ";
    for (std::size_t i = 0; i < s.rss_mib.size();
         i += std::max<std::size_t>(1, s.rss_mib.size() / 12)) {
      md += std::to_string(s.rss_mib[i].first) + ": " + Fmt("%.1f", s.rss_mib[i].second) + ", ";
    }
    md += std::to_string(s.rss_mib.back().first) + ": " + Fmt("%.1f", s.rss_mib.back().second) +
          "\n\n";
  }
  {
    std::ofstream f(out / "results.md", std::ios::trunc);
    f << md;
    if (!f) throw std::runtime_error((out / "results.md").string() + ": write error");
  }
  WritePlot((out / "fps.png").string(), points);
  std::cout << md;
  std::fprintf(stderr,
               "mvtrack bench: wrote %s/results.json, results.md, fps.png in %.0f s\n",
               out.string().c_str(),
               total_s);
  return 0;
}

}  // namespace mvtrack::cli
