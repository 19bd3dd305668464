// mvtrack status: waits for one tracker_status_t and prints it for a person; exits with the
// monitoring-plugin code (0 OK, 1 WARNING, 2 CRITICAL, 3 UNKNOWN) so cron, Nagios or a systemd
// timer can use it (docs/OPERATING.md).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <string>

#include "mvtrack/cli.h"
#include "service/status_check.h"
#include "transport/codec.h"

namespace mvtrack::cli {
namespace {

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Received {
  explicit Received(double window_s) : source(window_s) {}
  // The latest status: a tracker's, or a site stitcher's (issue 43).
  std::optional<transport::TrackerStatus> status;
  std::optional<transport::SiteStatus> site;
  int count = 0;
  std::string error;  // the last decode error
  service::StatusSourceWatch source;
};

void OnStatus(const lcm::ReceiveBuffer* rbuf, const std::string&, Received* out) {
  const transport::StatusDecodeResult d =
      transport::DecodeTrackerStatus(rbuf->data, rbuf->data_size);
  if (d.ok()) {
    out->status = d.message;
    out->site.reset();
    ++out->count;
    out->source.Add(d.message, SteadySeconds());
    return;
  }
  if (d.status == transport::DecodeStatus::kBadFingerprint) {
    const transport::SiteStatusDecodeResult site =
        transport::DecodeSiteStatus(rbuf->data, rbuf->data_size);
    if (site.ok()) {
      out->site = site.message;
      out->status.reset();
      ++out->count;
      out->source.Add({site.message.instance_id, site.message.sequence}, SteadySeconds());
      return;
    }
    if (site.status != transport::DecodeStatus::kBadFingerprint) {
      out->error = site.reason;
      return;
    }
  }
  out->error = d.reason;
}

std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f s", s);
  return buf;
}

std::string Ms(std::int64_t us) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", static_cast<double>(us) / 1000.0);
  return buf;
}

std::string Join(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out.empty() ? "-" : out;
}

void Print(const transport::TrackerStatus& s, const service::HealthReport& h) {
  std::printf("mvtrack status: %s\n", service::HealthLine(h).c_str());
  std::printf("tracker %s, configuration %s, up %s, instance %s, status #%lld\n",
              s.version.c_str(),
              s.config_hash.c_str(),
              Seconds(static_cast<double>(s.uptime_us) / 1e6).c_str(),
              s.instance_id.empty() ? "-" : s.instance_id.c_str(),
              static_cast<long long>(s.sequence));
  std::printf(
      "frame %lld, %.1f frames/s, %d active tracks (%d confirmed), latency p50 %s ms, "
      "p99 %s ms, max %s ms\n",
      static_cast<long long>(s.last_frame),
      service::FramesPerSecond(s),
      s.active_tracks,
      s.confirmed_tracks,
      Ms(s.latency_p50_us).c_str(),
      Ms(s.latency_p99_us).c_str(),
      Ms(s.latency_max_us).c_str());
  std::printf("tracker flags: %s; windows %lld, failed jobs %lld, job queue %d, kernel drops %s\n",
              Join(transport::TrackerFlagNames(s.flags)).c_str(),
              static_cast<long long>(s.windows_processed),
              static_cast<long long>(s.jobs_failed),
              s.executor_queue_depth,
              s.kernel_drops < 0 ? "not measured" : std::to_string(s.kernel_drops).c_str());
  if (s.embeddings_used + s.embeddings_dropped + s.tracks_revived + s.gallery_bytes > 0) {
    std::string by_camera;
    for (const transport::CameraStatus& c : s.cameras) {
      if (c.embeddings_dropped == 0) continue;
      by_camera += (by_camera.empty() ? " (camera " : ", camera ") + std::to_string(c.camera_id) +
                   ": " + std::to_string(c.embeddings_dropped);
    }
    if (!by_camera.empty()) by_camera += ")";
    std::printf(
        "appearance: %lld embeddings used, %lld dropped as unusable%s; %lld track(s) "
        "re-identified; galleries %.1f kB\n",
        static_cast<long long>(s.embeddings_used),
        static_cast<long long>(s.embeddings_dropped),
        by_camera.c_str(),
        static_cast<long long>(s.tracks_revived),
        static_cast<double>(s.gallery_bytes) / 1000.0);
  }
  std::printf("cameras: %d of %zu delivering\n", service::CamerasDelivering(s), s.cameras.size());
  std::printf("  %6s %8s %9s %10s %9s %8s %8s %8s %9s %8s %7s  %s\n",
              "camera",
              "rate Hz",
              "last msg",
              "latency ms",
              "clock ms",
              "late",
              "dropped",
              "lost",
              "rejected",
              "decode",
              "queue",
              "flags");
  for (const transport::CameraStatus& c : s.cameras) {
    const std::string age =
        c.last_receive_utime > 0
            ? Seconds((static_cast<double>(s.utime) - static_cast<double>(c.last_receive_utime)) /
                      1e6)
            : "never";
    // Capture (camera clock) to receive (tracker clock): a transport latency when the clocks
    // agree; beyond an hour they are not comparable (a replayed recording, an unset clock).
    // (Differences in double: the fields come from the network and may be any int64.)
    const double capture_to_receive_us =
        static_cast<double>(c.last_receive_utime) - static_cast<double>(c.last_utime);
    const std::string latency = c.last_receive_utime <= 0 ? "-"
                                : std::fabs(capture_to_receive_us) > 3.6e9
                                    ? "n/a"
                                    : Ms(static_cast<std::int64_t>(capture_to_receive_us));
    std::printf("  %6d %8.1f %9s %10s %9s %8lld %8lld %8lld %9lld %8lld %3d/%-3d  %s\n",
                c.camera_id,
                static_cast<double>(c.rate_hz),
                age.c_str(),
                latency.c_str(),
                Ms(c.clock_offset_us).c_str(),
                static_cast<long long>(c.late),
                static_cast<long long>(c.dropped),
                static_cast<long long>(c.lost),
                static_cast<long long>(c.rejected),
                static_cast<long long>(c.decode_errors),
                c.queue_depth,
                c.queue_capacity,
                Join(transport::CameraFlagNames(c.flags)).c_str());
  }
}

void PrintSite(const transport::SiteStatus& s, const service::HealthReport& h) {
  std::printf("mvtrack status: %s\n", service::HealthLine(h).c_str());
  std::printf("site stitcher %s, up %s, instance %s, status #%lld\n",
              s.version.c_str(),
              Seconds(static_cast<double>(s.uptime_us) / 1e6).c_str(),
              s.instance_id.empty() ? "-" : s.instance_id.c_str(),
              static_cast<long long>(s.sequence));
  std::printf(
      "site frame %lld, %d global tracks, %lld global ids given out, joins undone %lld, ids "
      "merged %lld\n",
      static_cast<long long>(s.last_frame),
      s.active_tracks,
      static_cast<long long>(s.global_ids),
      static_cast<long long>(s.splits),
      static_cast<long long>(s.merges));
  std::printf("site flags: %s; stitching waited p50 %s ms, p99 %s ms, max %s ms (%d frames)\n",
              Join(transport::SiteFlagNames(s.flags)).c_str(),
              Ms(s.wait_p50_us).c_str(),
              Ms(s.wait_p99_us).c_str(),
              Ms(s.wait_max_us).c_str(),
              s.num_wait_samples);
  int live = 0;
  for (const transport::ZoneStatus& z : s.zones) live += (z.flags & 3) == 0 ? 1 : 0;
  std::printf("zones: %d of %zu live\n", live, s.zones.size());
  std::printf("  %-12s %-24s %8s %6s %7s %10s %9s %6s %-8s  %s\n",
              "zone",
              "channel",
              "frames",
              "late",
              "decode",
              "latency ms",
              "last msg",
              "tracks",
              "daemon",
              "flags");
  for (const transport::ZoneStatus& z : s.zones) {
    const std::string age =
        z.last_receive_utime > 0
            ? Seconds((static_cast<double>(s.utime) - static_cast<double>(z.last_receive_utime)) /
                      1e6)
            : "never";
    std::printf("  %-12s %-24s %8lld %6lld %7lld %10s %9s %6d %-8s  %s\n",
                z.name.c_str(),
                z.channel.c_str(),
                static_cast<long long>(z.frames),
                static_cast<long long>(z.late),
                static_cast<long long>(z.decode_errors),
                Ms(z.latency_us).c_str(),
                age.c_str(),
                z.tracks,
                service::ToString(static_cast<service::Health>(z.daemon_health)),
                Join(transport::ZoneFlagNames(z.flags)).c_str());
    if (!z.daemon_reasons.empty()) std::printf("    %s\n", z.daemon_reasons.c_str());
  }
}

}  // namespace

int RunStatus(int argc, char** argv) {
  Args args;
  args.Option("url", "LCM URL the daemon publishes on", "udpm://239.255.76.67:7667?ttl=0")
      .Option("channel", "status channel", "MVTRACK_STATUS")
      .Option("timeout", "seconds to wait for a status message", "5");
  if (!args.Parse(argc,
                  argv,
                  "mvtrack status [--url URL] [--timeout S] [--channel C]",
                  "Waits for one status message of the tracker daemon and prints it: health with\n"
                  "its reasons, frame rate, tracks, latency, and per camera the rate, the age of\n"
                  "its last message, its transport latency, clock offset, losses and flags in\n"
                  "words (OPERATING.md says what each flag means and what to do: installed "
                  "as\n" MVTRACK_DOC_DIR "/OPERATING.md, docs/ in the sources). It\n"
                  "listens one and a half status periods more, to see the next status: a second\n"
                  "daemon on the channel, or a status sequence going backwards (replayed or\n"
                  "forged statuses), is CRITICAL; a restart seen meanwhile is a WARNING.\n"
                  "On a site split into zones (SCALING.md) the stitcher's status comes on the\n"
                  "same channel: the site's health, and per zone whether it is live or stale,\n"
                  "its frames, latency and flags, and its zone daemon's own health.\n"
                  "Exit status (the monitoring-plugin convention): 0 OK, 1 WARNING, 2 CRITICAL,\n"
                  "3 UNKNOWN (no status within the timeout, or LCM failed).")) {
    return 0;
  }
  const double timeout_s = args.GetDouble("timeout");
  if (!(timeout_s > 0.0 && timeout_s <= 86400.0)) {
    throw UsageError("--timeout: must be in (0, 86400] seconds");
  }
  lcm::LCM lcm(args.Get("url"));
  if (!lcm.good()) {
    std::printf("mvtrack status: UNKNOWN: cannot open LCM %s\n", args.Get("url").c_str());
    return 3;
  }
  Received received(timeout_s);
  if (lcm.subscribeFunction(args.Get("channel"), &OnStatus, &received) == nullptr) {
    std::printf("mvtrack status: UNKNOWN: cannot subscribe to %s\n", args.Get("channel").c_str());
    return 3;
  }
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::microseconds(static_cast<std::int64_t>(timeout_s * 1e6));
  // Until the first status, then for one and a half of its periods more (within the timeout):
  // the statuses that follow show a second instance on the channel or a sequence going
  // backwards (service::StatusSourceWatch).
  auto until = deadline;
  bool listening_on = false;
  while (true) {
    const auto now = std::chrono::steady_clock::now();
    if ((received.status || received.site) && !listening_on) {
      listening_on = true;
      const std::int64_t period_us =
          received.status ? received.status->period_us : received.site->period_us;
      const double period_s = std::clamp(static_cast<double>(period_us) / 1e6, 0.2, 5.0);
      until = std::min(
          deadline, now + std::chrono::microseconds(static_cast<std::int64_t>(1.5e6 * period_s)));
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - now);
    if (left.count() <= 0) break;
    if (lcm.handleTimeout(static_cast<int>(std::min<std::int64_t>(left.count(), 1000))) < 0) {
      std::printf("mvtrack status: UNKNOWN: LCM receive failed on %s\n", args.Get("url").c_str());
      return 3;
    }
  }
  if (received.site) {
    const service::HealthReport h = service::Combine(service::AssessSiteStatus(*received.site),
                                                     received.source.Assess(SteadySeconds()));
    PrintSite(*received.site, h);
    return static_cast<int>(h.health);
  }
  if (!received.status) {
    std::printf("mvtrack status: UNKNOWN: no status message on %s within %s (%s)%s\n",
                args.Get("channel").c_str(),
                Seconds(timeout_s).c_str(),
                args.Get("url").c_str(),
                received.error.empty() ? "" : ("; undecodable: " + received.error).c_str());
    return 3;
  }
  const service::HealthReport h = service::Combine(service::AssessStatus(*received.status),
                                                   received.source.Assess(SteadySeconds()));
  Print(*received.status, h);
  return static_cast<int>(h.health);
}

}  // namespace mvtrack::cli
