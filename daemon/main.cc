// mvtrackd: the real-time multi-view tracking daemon. A thin main: arguments, logging, the
// configuration, signals and systemd notification; the runtime is lib/service (Service,
// LcmRunner, FrameSynchronizer) on top of lib/pipeline. See docs/DAEMON.md.

#include <signal.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <systemd/sd-daemon.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "config/calibration_check.h"
#include "config/config_error.h"
#include "service/daemon_config.h"
#include "service/lcm_runner.h"
#include "service/rate_limiter.h"
#include "service/receive_buffer.h"
#include "service/service.h"
#include "service/status_check.h"
#include "transport/codec.h"
#include "transport/tracks_jsonl.h"

#ifndef MVTRACK_VERSION
#define MVTRACK_VERSION "unknown"
#endif

namespace {

// Set once the daemon drains: the final status no longer replaces systemd's STATUS=draining.
std::atomic<bool> g_stopping{false};
// A signal taken by a thread that does not block it (see Run); 0 = none.
std::atomic<int> g_caught_signal{0};

using mvtrack::service::DaemonConfig;

constexpr int kPollMs = 50;

const char kUsage[] =
    "usage: mvtrackd --config FILE [--calibration FILE] [--input-log LOG [--input-speed X]]\n"
    "                [--output-url URL]\n"
    "                [--record LOG] [--tracks-jsonl FILE] [--provisional-jsonl FILE]\n"
    "                [--workers N] [--log-level LEVEL]\n"
    "       mvtrackd --version | --help\n";

const char kHelp[] =
    "\n"
    "Tracks people in 3D from the 2D detections that calibrated cameras publish over LCM\n"
    "(camera_detections_t), and publishes one tracks3d_t per finalized frame and a\n"
    "tracker_status_t every status period. See docs/DAEMON.md.\n"
    "\n"
    "  --config FILE       daemon configuration (format mvtrack.daemon/1); required\n"
    "  --calibration FILE  override cameras.calibration (relative to the working directory)\n"
    "  --input-log LOG     read detections from this LCM log through LCM's file:// provider as\n"
    "                      fast as the tracker consumes them (input.lcm_url = file://LOG?speed=0,\n"
    "                      queues.camera_overflow = block, sync.idle_flush_s = 0), exit at the\n"
    "                      end of the log after a summary\n"
    "  --input-speed X     with --input-log: play the log at X times its recorded pace (1 = as\n"
    "                      recorded, live-like: LCM's ?speed=X; queues and idle flush stay as\n"
    "                      configured); 0 (default) = as fast as the tracker consumes\n"
    "  --output-url URL    override output.lcm_url\n"
    "  --record LOG        write every received and published message to this LCM log\n"
    "                      (replayable with `mvtrack replay`)\n"
    "  --tracks-jsonl FILE also write every published frame as canonical tracks JSONL\n"
    "  --provisional-jsonl FILE\n"
    "                      also write every published provisional frame (the layer on\n"
    "                      output.provisional_channel) as canonical tracks JSONL\n"
    "  --workers N         override threads.workers (0 = one per core)\n"
    "  --log-level LEVEL   override logging.level (trace, debug, info, warn, error, critical, "
    "off)\n"
    "  --version           print the version and exit\n"
    "\n"
    "Signals: SIGINT/SIGTERM stop the input, finish the open windows, publish every remaining\n"
    "frame and exit 0; SIGHUP reloads the configuration file (logging, status period and the\n"
    "tracker options; other changes need a restart). Under systemd (Type=notify) it reports\n"
    "READY=1, STOPPING=1 and feeds the watchdog.\n"
    "\n"
    "Exit status: 0 stopped cleanly (signal or end of log), 1 failure (configuration, LCM,\n"
    "output), 2 usage error.\n";

struct Options {
  std::string config_path;
  std::string calibration;
  std::optional<std::string> input_log;
  double input_speed = 0.0;
  std::optional<std::string> output_url;
  std::string record_path;
  std::string tracks_jsonl;
  std::string provisional_jsonl;
  std::optional<int> workers;
  std::optional<std::string> log_level;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// --tracks-jsonl / --provisional-jsonl: canonical tracks JSON lines, written from the pipeline's
// finalizer thread. Flushed per frame: a reader tailing the file sees each frame when it is
// published, and a kill -9 loses no line that was published over LCM.
class JsonlWriter {
 public:
  // Opens `path` (nothing when empty); throws when it cannot be written.
  explicit JsonlWriter(std::string path) : path_(std::move(path)) {
    if (path_.empty()) return;
    file_.open(path_, std::ios::binary | std::ios::trunc);
    if (!file_) throw std::runtime_error(path_ + ": cannot open for writing");
  }
  bool enabled() const { return !path_.empty(); }
  void Write(const mvtrack::tracker::Frame3D& frame, mvtrack::core::KeypointLayoutId layout) {
    std::lock_guard<std::mutex> lock(mu_);
    file_ << mvtrack::transport::TracksJsonLine(frame, layout) << std::flush;
    if (!file_ && !failed_) {
      failed_ = true;
      spdlog::error("{}: write error", path_);
    }
  }
  // Closes the file; false (logged) when a write failed.
  bool Close() {
    if (!file_.is_open()) return true;
    file_.close();
    if (!file_ || failed_) {
      spdlog::error("{}: write error", path_);
      return false;
    }
    return true;
  }

 private:
  std::string path_;
  std::ofstream file_;
  std::mutex mu_;
  bool failed_ = false;
};

// Parses argv; returns nullopt after printing --help or --version.
// `text` as a number of type T in [lo, hi], the whole of it; otherwise a UsageError naming
// `flag` and the range.
template <typename T>
T NumberIn(const std::string& flag, const std::string& text, T lo, T hi) {
  std::size_t used = 0;
  T x = lo;
  bool ok = false;
  try {
    if constexpr (std::is_integral_v<T>) {
      x = static_cast<T>(std::stoi(text, &used));
    } else {
      x = static_cast<T>(std::stod(text, &used));
    }
    ok = used == text.size() && x >= lo && x <= hi;
  } catch (const std::exception&) {
    ok = false;
  }
  if (!ok) {
    std::ostringstream msg;
    msg << flag << " must be " << (std::is_integral_v<T> ? "an integer" : "a number") << " in ["
        << lo << ", " << hi << "], not '" << text << "'";
    throw UsageError(msg.str());
  }
  return x;
}

std::optional<Options> ParseArgs(int argc, char** argv) {
  Options o;
  std::map<std::string, std::string*> values = {{"--config", &o.config_path},
                                                {"--calibration", &o.calibration},
                                                {"--record", &o.record_path},
                                                {"--tracks-jsonl", &o.tracks_jsonl},
                                                {"--provisional-jsonl", &o.provisional_jsonl}};
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::string value;
    bool has_value = false;
    if (const auto eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      has_value = true;
    }
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage << kHelp;
      return std::nullopt;
    }
    if (arg == "--version") {
      std::cout << "mvtrackd " << MVTRACK_VERSION << "\n";
      return std::nullopt;
    }
    auto next = [&]() -> std::string {
      if (has_value) return value;
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (const auto it = values.find(arg); it != values.end()) {
      *it->second = next();
      if (it->second->empty()) throw UsageError(arg + " needs a non-empty value");
    } else if (arg == "--input-log") {
      o.input_log = next();
    } else if (arg == "--input-speed") {
      o.input_speed = NumberIn<double>(arg, next(), 0.0, 1000.0);
    } else if (arg == "--output-url") {
      o.output_url = next();
    } else if (arg == "--log-level") {
      o.log_level = next();
    } else if (arg == "--workers") {
      o.workers = NumberIn<int>(arg, next(), 0, 256);
    } else {
      throw UsageError("unknown argument '" + arg + "'");
    }
  }
  if (o.config_path.empty()) throw UsageError("--config is required");
  if (o.input_log && o.input_log->empty()) throw UsageError("--input-log needs a file name");
  if (o.input_speed > 0.0 && !o.input_log) throw UsageError("--input-speed needs --input-log");
  if (o.log_level && spdlog::level::from_str(*o.log_level) == spdlog::level::off &&
      *o.log_level != "off") {
    throw UsageError("--log-level: unknown level '" + *o.log_level + "'");
  }
  return o;
}

// Loads the configuration file and applies the command-line overrides.
DaemonConfig LoadConfig(const Options& o) {
  DaemonConfig c = mvtrack::service::LoadDaemonConfigFile(o.config_path, o.calibration);
  if (o.input_log) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(*o.input_log, ec)) {
      throw std::runtime_error("--input-log " + *o.input_log + ": not a readable log file");
    }
    if (std::filesystem::file_size(*o.input_log, ec) == 0) {
      throw std::runtime_error("--input-log " + *o.input_log + ": the log is empty");
    }
    const std::string abs = std::filesystem::absolute(*o.input_log, ec).lexically_normal().string();
    if (o.input_speed > 0.0) {
      std::ostringstream url;
      url << "file://" << abs << "?speed=" << o.input_speed;
      c.input_url = url.str();
    } else {
      c.input_url = "file://" + abs + "?speed=0";
      c.camera_overflow = mvtrack::pipeline::OverflowPolicy::kBlock;
      c.sync.idle_flush_s = 0.0;
    }
  }
  if (o.output_url) c.output_url = *o.output_url;
  if (o.workers) c.workers = *o.workers;
  // systemd's StateDirectory= (the unit's /var/lib/mvtrackd) when the file names none.
  const char* env = std::getenv("STATE_DIRECTORY");
  if (c.state_directory.empty() && env != nullptr && *env != '\0') {
    const std::string dirs = env;
    c.state_directory = dirs.substr(0, dirs.find(':'));
  }
  if (o.log_level) c.log_level = *o.log_level;
  return c;
}

void SetupLogging() {
  auto logger = spdlog::stdout_logger_mt("mvtrackd");
  // journald adds its own timestamps; elsewhere print ours.
  if (std::getenv("JOURNAL_STREAM") != nullptr) {
    logger->set_pattern("[%l] %v");
  } else {
    logger->set_pattern("[%Y-%m-%dT%H:%M:%S.%e] [%l] %v");
  }
  logger->flush_on(spdlog::level::info);
  spdlog::set_default_logger(logger);
}

std::string Counts(const std::map<std::string, std::int64_t>& counts) {
  std::string s;
  for (const auto& [k, v] : counts) s += (s.empty() ? "" : ", ") + k + " " + std::to_string(v);
  return s.empty() ? "none" : s;
}

// Peak resident memory of this process so far, kB.
long MaxRssKb() {
  rusage usage{};
  return getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_maxrss : -1;
}

void LogSummary(const mvtrack::service::ServiceCounters& c, double seconds) {
  const auto& st = c.pipeline.tracker;
  std::int64_t late = 0, flood = 0, backwards = 0, duplicates = 0, far_future = 0, missed = 0;
  std::int64_t clock_offset = 0, camera_restarts = 0, lost = 0;
  for (const auto& cam : c.sync.cameras) {
    lost += cam.lost;
    clock_offset += cam.clock_offset;
    camera_restarts += cam.restarts;
    late += cam.late;
    flood += cam.flood;
    backwards += cam.backwards;
    duplicates += cam.duplicates;
    far_future += cam.far_future;
    missed += cam.missed;
  }
  spdlog::info(
      "summary: messages={} foreign={} decode_errors={} ({}) channel_mismatches={} "
      "image_size_mismatches={}",
      c.messages,
      c.foreign_messages,
      c.decode_errors,
      Counts(c.decode_errors_by_kind),
      c.channel_mismatches,
      c.image_size_mismatches);
  spdlog::info(
      "summary: camera_frames={} unknown_camera={} backwards={} duplicates={} "
      "far_future={} late={} flood={} clock_offset={} camera_restarts={} lost={} "
      "resyncs={} submitted={} gate_rejected={}",
      c.camera_frames_decoded,
      c.sync.unknown_camera,
      backwards,
      duplicates,
      far_future,
      late,
      flood,
      clock_offset,
      camera_restarts,
      lost,
      c.stream_restarts,
      c.submitted,
      c.gate_rejected);
  spdlog::info(
      "summary: frames_released={} complete={} by_deadline={} by_bound={} missed={} "
      "queue_dropped={} kernel_drops={}",
      c.sync.frames_released,
      c.sync.released_complete,
      c.sync.released_by_deadline,
      c.sync.released_by_bound,
      missed,
      c.pipeline.camera_frames_dropped,
      c.kernel_drops);
  spdlog::info("summary: detections used={} rejected={} repaired={} filtered={}",
               st.detections_used,
               st.detections_rejected,
               st.detections_repaired,
               st.detections_filtered);
  spdlog::info(
      "summary: appearance embeddings used={} dropped={} tracks_revived={} gallery_bytes={}",
      st.embeddings_used,
      st.embeddings_dropped,
      st.tracks_revived,
      st.gallery_bytes);
  std::vector<std::int64_t> e2e = c.receive_to_publish_us;
  const std::size_t samples = e2e.size();
  const std::int64_t e2e_max = e2e.empty() ? 0 : *std::max_element(e2e.begin(), e2e.end());
  spdlog::info(
      "summary: receive_to_publish_us p50={} p99={} max={} samples={} "
      "(frames published by a flush, not sampled: {})",
      mvtrack::service::NearestRankPercentile(&e2e, 0.5),
      mvtrack::service::NearestRankPercentile(&e2e, 0.99),
      e2e_max,
      samples,
      c.frames_published_by_flush);
  std::vector<std::int64_t> now_e2e = c.provisional_receive_to_publish_us;
  const std::int64_t now_max =
      now_e2e.empty() ? 0 : *std::max_element(now_e2e.begin(), now_e2e.end());
  spdlog::info("summary: provisional published={} receive_to_publish_us p50={} p99={} max={}",
               c.provisional_published,
               mvtrack::service::NearestRankPercentile(&now_e2e, 0.5),
               mvtrack::service::NearestRankPercentile(&now_e2e, 0.99),
               now_max);
  spdlog::info(
      "summary: published_frames={} status_messages={} windows={} windows_failed={} "
      "tracks_born={} max_latency_us={} reloads={} idle_flushes={} suppressed_warnings={} "
      "seconds={:.3f} max_rss_kb={}",
      c.frames_published,
      c.status_published,
      st.windows_processed,
      c.pipeline.windows_failed,
      st.tracks_born,
      c.max_latency_us,
      c.reloads,
      c.idle_flushes,
      c.log_suppressed,
      seconds,
      MaxRssKb());
}

int Run(const Options& options) {
  DaemonConfig config = LoadConfig(options);
  spdlog::set_level(spdlog::level::from_str(config.log_level));
  spdlog::info("mvtrackd {} starting: {} camera(s), {} worker(s)",
               MVTRACK_VERSION,
               config.cameras.size(),
               config.EffectiveWorkers());
  spdlog::info("effective configuration (hash {}):\n{}",
               mvtrack::service::DaemonConfigHash(config),
               mvtrack::service::DaemonConfigToYaml(config));
  for (const std::string& w : mvtrack::config::CalibrationLoadWarnings(config.cameras)) {
    spdlog::warn("{}: {}", config.calibration_path, w);
  }

  // Signals are taken synchronously by the control loop (sigtimedwait): block them before any
  // thread starts so every thread inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A thread started before this point (a sanitizer's runtime has one) still takes these
  // signals: a handler records them for the control loop instead of the default action
  // (terminating the process), so a SIGHUP can never kill the daemon.
  struct sigaction record {};
  record.sa_handler = [](int sig) { g_caught_signal.store(sig); };
  sigemptyset(&record.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &record, nullptr);
  signal(SIGPIPE, SIG_IGN);

  std::string why;
  std::unique_ptr<mvtrack::service::LcmRunner> runner =
      mvtrack::service::LcmRunner::Create(config, &why);
  if (!runner) throw std::runtime_error(why);

  JsonlWriter jsonl(options.tracks_jsonl);
  JsonlWriter provisional_jsonl(options.provisional_jsonl);
  mvtrack::service::ServiceHooks hooks;
  hooks.version = MVTRACK_VERSION;
  hooks.record_path = options.record_path;
  mvtrack::service::LcmRunner* runner_ptr = runner.get();
  const std::string status_channel = config.status_channel;
  const bool notify = std::getenv("NOTIFY_SOCKET") != nullptr;
  auto frame_rate = std::make_shared<mvtrack::service::FrameRateMeter>();
  hooks.publish = [runner_ptr, status_channel, notify, frame_rate](
                      const std::string& channel, const std::vector<std::uint8_t>& data) {
    if (!runner_ptr->Publish(channel, data)) spdlog::error("LCM publish on {} failed", channel);
    // `systemctl status` shows the latest status in words (cameras, rate, tracks, worst flag).
    if (notify && channel == status_channel && !g_stopping.load()) {
      const mvtrack::transport::StatusDecodeResult st =
          mvtrack::transport::DecodeTrackerStatus(data.data(), data.size());
      if (st.ok()) {
        const std::string line =
            "STATUS=" + mvtrack::service::NotifyStatusLine(st.message, frame_rate->Add(st.message));
        sd_notify(0, line.c_str());
      }
    }
  };
  if (jsonl.enabled()) {
    hooks.on_frame = [&jsonl](const mvtrack::tracker::Frame3D& frame,
                              mvtrack::core::KeypointLayoutId layout) {
      jsonl.Write(frame, layout);
    };
  }
  if (provisional_jsonl.enabled()) {
    hooks.on_provisional = [&provisional_jsonl](const mvtrack::tracker::Frame3D& frame,
                                                mvtrack::core::KeypointLayoutId layout) {
      provisional_jsonl.Write(frame, layout);
    };
  }
  if (config.input_url.rfind("udpm://", 0) == 0) {
    hooks.kernel_drops = [] { return mvtrack::service::ProcessUdpDrops(); };
  }
  std::unique_ptr<mvtrack::service::Service> service =
      mvtrack::service::Service::Create(config, hooks, &why);
  if (!service) throw std::runtime_error(why);
  if (!runner->Subscribe(service.get(), &why)) throw std::runtime_error(why);
  if (const mvtrack::service::ReceiveBufferCheck rb =
          mvtrack::service::CheckReceiveBuffer(config.input_url);
      rb.applies) {
    if (rb.capped) {
      spdlog::warn("{}", rb.message);
    } else {
      spdlog::info("{}", rb.message);
    }
  }
  spdlog::info(
      "input: LCM holds up to {} message(s) per subscription while the tracker is busy "
      "(input.lcm_queue_capacity)",
      mvtrack::service::LcmQueueCapacity(config));
  spdlog::info("input {}, output {}{}",
               config.input_url,
               runner->has_output() ? runner->output_url() : std::string("none (no LCM output)"),
               options.record_path.empty() ? "" : ", recording to " + options.record_path);

  std::uint64_t watchdog_usec = 0;
  const bool watchdog = sd_watchdog_enabled(0, &watchdog_usec) > 0 && watchdog_usec > 0;
  using SteadyClock = std::chrono::steady_clock;
  const auto watchdog_period = std::chrono::microseconds(watchdog_usec / 2);
  auto next_watchdog = SteadyClock::now();
  sd_notify(0, "READY=1\nSTATUS=tracking");
  const auto start = SteadyClock::now();

  int exit_code = 0;
  bool stop = false;
  while (!stop) {
    const mvtrack::service::HandleResult r = runner->HandleOnce(kPollMs);
    if (r == mvtrack::service::HandleResult::kEndOfInput) {
      spdlog::info("end of the input log");
      break;
    }
    if (r == mvtrack::service::HandleResult::kError) {
      spdlog::error("LCM input failed; stopping");
      exit_code = 1;
      break;
    }
    service->Tick();
    const timespec zero{0, 0};
    int sig = 0;
    while ((sig = sigtimedwait(&signals, nullptr, &zero)) > 0 ||
           (sig = g_caught_signal.exchange(0)) > 0) {
      if (sig == SIGHUP) {
        sd_notify(0, "RELOADING=1");
        try {
          const DaemonConfig next = LoadConfig(options);
          std::string notes;
          if (service->Reload(next, &notes)) {
            spdlog::set_level(spdlog::level::from_str(next.log_level));
            spdlog::info("configuration reloaded from {} (hash {}){}",
                         options.config_path,
                         service->config_hash(),
                         notes.empty() ? "" : "; " + notes);
          } else {
            spdlog::error("reload refused, keeping the running configuration: {}", notes);
          }
        } catch (const std::exception& e) {
          spdlog::error("reload failed, keeping the running configuration: {}", e.what());
        }
        sd_notify(0, "READY=1");
      } else {
        spdlog::info("{} received: draining", sig == SIGINT ? "SIGINT" : "SIGTERM");
        stop = true;
      }
    }
    if (watchdog && SteadyClock::now() >= next_watchdog) {
      sd_notify(0, "WATCHDOG=1");
      next_watchdog = SteadyClock::now() + watchdog_period;
    }
  }
  g_stopping.store(true);
  sd_notify(0, "STOPPING=1\nSTATUS=draining");
  service->Stop();
  const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();
  LogSummary(service->Counters(), seconds);
  const mvtrack::service::ServiceCounters counters = service->Counters();
  service.reset();
  runner.reset();
  if (!jsonl.Close() || !provisional_jsonl.Close()) exit_code = 1;
  if (counters.record_errors > 0) exit_code = 1;
  // A log that gave the tracker nothing: the run could not do its job (a live daemon waits).
  if (options.input_log && counters.submitted == 0) {
    std::string ids;
    for (const auto& cam : config.cameras)
      ids += (ids.empty() ? "" : ", ") + std::to_string(cam.id);
    spdlog::error(
        "{}: no camera-frame was tracked ({} message(s), {} of unknown cameras, {} "
        "undecodable; the calibration's cameras: {})",
        *options.input_log,
        counters.messages,
        counters.sync.unknown_camera,
        counters.decode_errors,
        ids);
    exit_code = 1;
  }
  spdlog::info("mvtrackd stopped (exit {})", exit_code);
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<Options> options;
  try {
    options = ParseArgs(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "mvtrackd: " << e.what() << "\n" << kUsage;
    return 2;
  }
  if (!options) return 0;
  SetupLogging();
  try {
    return Run(*options);
  } catch (const mvtrack::config::ConfigError& e) {
    spdlog::critical("configuration error: {}", e.what());
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
  }
  return 1;
}
