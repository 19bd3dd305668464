// mvtrack-stitcher: joins the tracks of a site's zone daemons (one mvtrackd per zone, issue 43)
// into one id space. A thin main: arguments, LCM (or a log), signals and the status line; the
// work is service::StitchService over lib/stitch. See docs/SCALING.md.

#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/config_error.h"
#include "config/zones.h"
#include "service/stitch_service.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

#ifndef MVTRACK_VERSION
#define MVTRACK_VERSION "unknown"
#endif

namespace {

using mvtrack::service::StitchService;

std::atomic<int> g_signal{0};

void OnSignal(int signal) { g_signal.store(signal); }

const char kUsage[] =
    "usage: mvtrack-stitcher --zones ZONES.yaml [--lcm-url URL] [--output-url URL]\n"
    "                        [--input-log LOG] [--channel NAME] [--zone-channel NAME]\n"
    "                        [--status-channel NAME] [--zone-status-channel NAME]\n"
    "                        [--state-dir DIR] [--wait-ms N] [--stale-ms N]\n"
    "                        [--tracks-jsonl FILE] [--status-jsonl FILE]\n"
    "       mvtrack-stitcher --version | --help\n";

const char kHelp[] =
    "\n"
    "Joins the tracks of a site's zone daemons (one mvtrackd per zone, `mvtrack calib zones`)\n"
    "into one id space: subscribes every zone's tracks channel (--zone-channel suffixed with the\n"
    "zone, e.g. MVTRACK_TRACKS_ZONE1), aligns their frames by capture time, waiting at most\n"
    "--wait-ms for a late zone and not at all for a zone silent for --stale-ms (stale), joins\n"
    "the zones' tracks in their border overlaps (docs/DECISIONS.md \"The stitcher\") and\n"
    "publishes the site's tracks (tracks3d_t, global ids, which zones see each person) on\n"
    "--channel. Every second it publishes the site's status (site_status_t: zones live or\n"
    "stale, their latency, late frames, each zone daemon's own health from its status channel)\n"
    "on --status-channel, where `mvtrack status` and `mvtrack web` read it, and writes it as a\n"
    "JSON line to --status-jsonl; at once too when a zone goes stale or comes back, which is\n"
    "also logged on stderr.\n"
    "\n"
    "  --zones FILE         the zones file (mvtrack.zones/1), required\n"
    "  --lcm-url URL        LCM to subscribe (default: LCM's default, LCM_DEFAULT_URL)\n"
    "  --output-url URL     LCM to publish on (default: --lcm-url; with --input-log: none)\n"
    "  --input-log LOG      read the zones' tracks from an LCM log instead, its event times\n"
    "                       as the clock (deterministic), then exit\n"
    "  --channel NAME       the site's tracks channel (default MVTRACK_TRACKS)\n"
    "  --zone-channel NAME  the zone daemons' tracks channel before the zone suffix\n"
    "                       (default MVTRACK_TRACKS)\n"
    "  --status-channel NAME  the site's status channel (default MVTRACK_STATUS; \"\" = none)\n"
    "  --zone-status-channel NAME  the zone daemons' status channel before the zone suffix\n"
    "                       (default MVTRACK_STATUS)\n"
    "  --state-dir DIR      keep the global id reservation here: ids never repeat across\n"
    "                       restarts\n"
    "  --wait-ms N          longest wait for a late zone, ms (default 1000)\n"
    "  --stale-ms N         a zone silent this long is stale, not waited for (default 2000)\n"
    "  --tracks-jsonl FILE  also write the site's tracks as canonical JSON lines\n"
    "  --status-jsonl FILE  write the status line every second (and at the end) here\n"
    "\n"
    "Exit status: 0 stopped by SIGINT/SIGTERM or the end of --input-log, 1 failure (zones\n"
    "file, LCM, output), 2 usage error.\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  std::string zones;
  std::string lcm_url;
  std::optional<std::string> output_url;
  std::string input_log;
  std::string channel = "MVTRACK_TRACKS";
  std::string zone_channel = "MVTRACK_TRACKS";
  std::string status_channel = "MVTRACK_STATUS";
  std::string zone_status_channel = "MVTRACK_STATUS";
  std::string state_dir;
  std::int64_t wait_ms = 1000;
  std::int64_t stale_ms = 2000;
  std::string tracks_jsonl;
  std::string status_jsonl;
};

std::int64_t Milliseconds(const std::string& flag, const std::string& text) {
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || v < 0 || v > 3'600'000) {
    throw UsageError(flag + ": '" + text + "' is not a number of milliseconds in [0, 3600000]");
  }
  return v;
}

std::optional<Options> Parse(int argc, char** argv) {
  Options o;
  const std::map<std::string, std::string*> strings = {
      {"--zones", &o.zones},
      {"--lcm-url", &o.lcm_url},
      {"--input-log", &o.input_log},
      {"--channel", &o.channel},
      {"--zone-channel", &o.zone_channel},
      {"--status-channel", &o.status_channel},
      {"--zone-status-channel", &o.zone_status_channel},
      {"--state-dir", &o.state_dir},
      {"--tracks-jsonl", &o.tracks_jsonl},
      {"--status-jsonl", &o.status_jsonl}};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage << kHelp;
      return std::nullopt;
    }
    if (arg == "--version") {
      std::cout << "mvtrack-stitcher " << MVTRACK_VERSION << "\n";
      return std::nullopt;
    }
    if (i + 1 >= argc) throw UsageError("unknown option or missing value: " + arg);
    const std::string value = argv[++i];
    if (const auto it = strings.find(arg); it != strings.end()) {
      *it->second = value;
    } else if (arg == "--output-url") {
      o.output_url = value;
    } else if (arg == "--wait-ms") {
      o.wait_ms = Milliseconds(arg, value);
    } else if (arg == "--stale-ms") {
      o.stale_ms = Milliseconds(arg, value);
      if (o.stale_ms == 0) throw UsageError("--stale-ms must be > 0");
    } else {
      throw UsageError("unknown option: " + arg);
    }
  }
  if (o.zones.empty()) throw UsageError("--zones is required");
  if (o.channel.empty() || o.zone_channel.empty() || o.zone_status_channel.empty()) {
    throw UsageError("channel names are empty");
  }
  return o;
}

std::int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Raw-bytes handler (a free function: LCM 1.3.1's member-function subscribe crashes under
// UBSan, ../shared/TOOLCHAIN.md).
struct Subscription {
  StitchService* service = nullptr;
  int zone = 0;
  bool status = false;  // the zone daemon's status channel, not its tracks
};
void OnRaw(const lcm::ReceiveBuffer* rbuf, const std::string&, Subscription* s) {
  const auto size = static_cast<std::size_t>(rbuf->data_size);
  if (s->status) {
    s->service->OnZoneStatus(s->zone, rbuf->data, size, NowUs());
  } else {
    s->service->OnMessage(s->zone, rbuf->data, size, NowUs());
  }
}

class Outputs {
 public:
  Outputs(const Options& o, lcm::LCM* lcm) : options_(o), lcm_(lcm) {
    if (!o.tracks_jsonl.empty()) {
      tracks_.open(o.tracks_jsonl, std::ios::binary | std::ios::trunc);
      if (!tracks_) throw std::runtime_error(o.tracks_jsonl + ": cannot open for writing");
    }
    if (!o.status_jsonl.empty()) {
      status_.open(o.status_jsonl, std::ios::binary | std::ios::trunc);
      if (!status_) throw std::runtime_error(o.status_jsonl + ": cannot open for writing");
    }
  }

  void Publish(const std::vector<mvtrack::stitch::SiteFrame>& frames,
               mvtrack::core::KeypointLayoutId layout,
               std::int64_t now_us) {
    for (const mvtrack::stitch::SiteFrame& f : frames) {
      ++published_;
      if (tracks_.is_open()) tracks_ << mvtrack::transport::TracksJsonLine(f.frame, layout);
      if (lcm_ != nullptr) {
        const std::vector<std::uint8_t> bytes =
            mvtrack::transport::EncodeTracks(f.frame, layout, now_us, now_us - f.frame.utime);
        if (lcm_->publish(options_.channel, bytes.data(), static_cast<unsigned>(bytes.size())) !=
            0) {
          ++publish_errors_;
        }
      }
    }
  }

  // The status line every second (and with `force`), and a log line when a zone changes state.
  void Status(StitchService& service, std::int64_t now_us, bool force) {
    const bool due = force || now_us - last_status_us_ >= 1'000'000;
    bool changed = false;
    stale_.resize(service.channels().size());
    for (std::size_t i = 0; i < stale_.size(); ++i) {
      const int z = static_cast<int>(i);
      if (!service.heard_from(z)) continue;
      const bool stale = service.stale(z, now_us);
      if (stale_[i].value_or(true) != stale) {
        std::cerr << "mvtrack-stitcher: zone " << service.zone_name(z)
                  << (stale ? " is stale: nothing on " + service.channels()[i] + " for " +
                                  std::to_string(options_.stale_ms) + " ms"
                            : " is live (" + service.channels()[i] + ")")
                  << "\n";
        changed = true;
      }
      stale_[i] = stale;
    }
    // The whole status (and its wait percentiles) only when it is written.
    const bool publish = lcm_ != nullptr && !options_.status_channel.empty();
    if ((status_.is_open() || publish) && (due || changed)) {
      const mvtrack::transport::SiteStatus s = service.Status(now_us, due);
      if (status_.is_open()) status_ << mvtrack::service::SiteStatusJson(s) << std::flush;
      if (publish) {
        const std::vector<std::uint8_t> bytes = mvtrack::transport::EncodeSiteStatus(s);
        if (lcm_->publish(
                options_.status_channel, bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
          ++publish_errors_;
        }
      }
    }
    if (due) last_status_us_ = now_us;
  }

  void Close() {
    if (tracks_.is_open()) {
      tracks_.close();
      if (!tracks_) throw std::runtime_error(options_.tracks_jsonl + ": write error");
    }
    if (status_.is_open()) {
      status_.close();
      if (!status_) throw std::runtime_error(options_.status_jsonl + ": write error");
    }
  }

  std::int64_t published() const { return published_; }
  std::int64_t publish_errors() const { return publish_errors_; }

 private:
  const Options& options_;
  lcm::LCM* lcm_;
  std::ofstream tracks_;
  std::ofstream status_;
  std::vector<std::optional<bool>> stale_;  // per zone, once heard from
  std::int64_t last_status_us_ = 0;
  std::int64_t published_ = 0;
  std::int64_t publish_errors_ = 0;
};

int Run(const Options& o) {
  mvtrack::service::StitchConfig config;
  config.zones = mvtrack::config::LoadZonesFile(o.zones);
  config.zone_tracks_channel = o.zone_channel;
  config.zone_status_channel = o.zone_status_channel;
  config.version = MVTRACK_VERSION;
  config.state_dir = o.state_dir;
  config.aligner.wait_us = o.wait_ms * 1000;
  config.aligner.stale_after_us = o.stale_ms * 1000;
  std::string why;
  std::unique_ptr<StitchService> service = StitchService::Create(config, &why);
  if (!service) throw std::runtime_error(why);

  const bool from_log = !o.input_log.empty();
  std::unique_ptr<lcm::LCM> input;
  std::unique_ptr<lcm::LCM> output;
  lcm::LCM* publish = nullptr;
  if (!from_log) {
    input = std::make_unique<lcm::LCM>(o.lcm_url);
    if (!input->good()) throw std::runtime_error("cannot open LCM '" + o.lcm_url + "'");
    publish = input.get();
  }
  if (o.output_url && (from_log || *o.output_url != o.lcm_url)) {
    output = std::make_unique<lcm::LCM>(*o.output_url);
    if (!output->good()) throw std::runtime_error("cannot open LCM '" + *o.output_url + "'");
    publish = output.get();
  }
  Outputs out(o, publish);
  std::cerr << "mvtrack-stitcher " << MVTRACK_VERSION << ": " << service->channels().size()
            << " zone(s) from " << o.zones << " -> " << o.channel << "\n";

  std::int64_t now = 0;
  if (from_log) {
    std::unique_ptr<mvtrack::transport::LogReader> reader =
        mvtrack::transport::LogReader::Open(o.input_log, &why);
    if (!reader) throw std::runtime_error(why);
    std::map<std::string, int> zone_of;         // tracks channel -> zone
    std::map<std::string, int> zone_status_of;  // status channel -> zone
    for (std::size_t z = 0; z < service->channels().size(); ++z) {
      zone_of[service->channels()[z]] = static_cast<int>(z);
      zone_status_of[service->status_channels()[z]] = static_cast<int>(z);
    }
    while (std::optional<mvtrack::transport::LogEvent> e = reader->Next()) {
      now = std::max(now, e->timestamp_us);
      if (const auto it = zone_of.find(e->channel); it != zone_of.end()) {
        service->OnMessage(it->second, e->data.data(), e->data.size(), now);
      } else if (const auto st = zone_status_of.find(e->channel); st != zone_status_of.end()) {
        service->OnZoneStatus(st->second, e->data.data(), e->data.size(), now);
      }
      out.Publish(service->Poll(now), service->layout(), now);
      out.Status(*service, now, false);
      if (g_signal.load() != 0) break;
    }
    if (reader->end() == mvtrack::transport::LogEnd::kIoError) {
      throw std::runtime_error(reader->error());
    }
  } else {
    std::vector<Subscription> subscriptions;
    subscriptions.reserve(2 * service->channels().size());
    for (std::size_t z = 0; z < service->channels().size(); ++z) {
      for (const bool status : {false, true}) {
        subscriptions.push_back({service.get(), static_cast<int>(z), status});
        const std::string& channel =
            status ? service->status_channels()[z] : service->channels()[z];
        if (input->subscribeFunction(channel, &OnRaw, &subscriptions.back()) == nullptr) {
          throw std::runtime_error("cannot subscribe to " + channel);
        }
      }
    }
    while (g_signal.load() == 0) {
      if (input->handleTimeout(20) < 0 && g_signal.load() == 0) {
        throw std::runtime_error("LCM failed while receiving");
      }
      now = NowUs();
      out.Publish(service->Poll(now), service->layout(), now);
      out.Status(*service, now, false);
    }
    now = NowUs();
  }
  out.Publish(service->Poll(now, /*flush=*/true), service->layout(), now);
  out.Status(*service, now, true);
  out.Close();
  const mvtrack::transport::SiteStatus s = service->Status(now);
  const mvtrack::stitch::StitchStats& ss = service->stitch_stats();
  std::cerr << "mvtrack-stitcher: stopped" << (g_signal.load() != 0 ? " by a signal" : "")
            << "; summary: site_frames=" << out.published() << " global_ids=" << ss.global_ids
            << " joined_overlap=" << ss.joined_overlap << " splits=" << ss.splits
            << " merges=" << ss.merges << " publish_errors=" << out.publish_errors();
  for (const mvtrack::transport::ZoneStatus& z : s.zones) {
    std::cerr << " " << z.name << ".frames=" << z.frames << " " << z.name << ".late=" << z.late
              << " " << z.name << ".decode_errors=" << z.decode_errors;
  }
  std::cerr << "\n";
  if (!service->id_warning().empty()) {
    std::cerr << "mvtrack-stitcher: warning: " << service->id_warning() << "\n";
  }
  return out.publish_errors() > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::optional<Options> options = Parse(argc, argv);
    if (!options) return 0;
    struct sigaction sa = {};
    sa.sa_handler = OnSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    return Run(*options);
  } catch (const UsageError& e) {
    std::cerr << "mvtrack-stitcher: " << e.what() << "\n" << kUsage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "mvtrack-stitcher: error: " << e.what() << "\n";
    return 1;
  }
}
