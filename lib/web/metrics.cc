#include "web/metrics.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "service/status_check.h"

namespace mvtrack::web {
namespace {

// Appends one metric family: HELP and TYPE, then the samples added by `samples`.
class Exposition {
 public:
  void Family(const char* name, const char* type, const char* help) {
    name_ = name;
    text_ += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  }
  void Sample(double value, const std::string& labels = "") {
    char buf[64];
    if (std::isnan(value)) {
      std::snprintf(buf, sizeof(buf), "NaN");
    } else if (std::isinf(value)) {
      std::snprintf(buf, sizeof(buf), value > 0 ? "+Inf" : "-Inf");
    } else if (value == std::floor(value) && std::fabs(value) < 1e15) {
      std::snprintf(buf, sizeof(buf), "%.0f", value);
    } else {
      std::snprintf(buf, sizeof(buf), "%.9g", value);
    }
    text_ += name_ + (labels.empty() ? "" : "{" + labels + "}") + " " + buf + "\n";
  }
  const std::string& text() const { return text_; }

 private:
  std::string name_;
  std::string text_;
};

// A Prometheus label value: backslash, double quote and line feed escaped (names are printable
// ASCII, ValidateName, but a hostile message may still carry quotes).
std::string LabelValue(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '\\' || c == '"') out += '\\';
    out += c == '\n' ? std::string("\\n") : std::string(1, c);
  }
  return out;
}

std::string CameraLabel(const transport::CameraStatus& c) {
  return "camera=\"" + std::to_string(c.camera_id) + "\"";
}

double D(std::int64_t v) { return static_cast<double>(v); }

// One 0/1 sample per documented flag bit, named as transport names it (`names` of a single bit;
// the first undocumented bit is named "BIT<n>" and ends the list), labelled `labels` + flag.
void FlagSamples(Exposition* e,
                 std::int64_t flags,
                 std::vector<std::string> (*names)(std::int64_t),
                 const std::string& labels) {
  for (int bit = 0; bit < 63; ++bit) {
    const std::string name = names(std::int64_t{1} << bit).front();
    if (name.rfind("BIT", 0) == 0) break;
    e->Sample((flags >> bit & 1) != 0 ? 1.0 : 0.0, labels + "flag=\"" + name + "\"");
  }
}

}  // namespace

namespace {

// The site stitcher's series (issue 43): per zone its state, counters, latency and its daemon's
// health; the site's tracks, ids and how long site frames waited.
void SiteStatusSamples(Exposition& e, const transport::SiteStatus& s) {
  const auto zone = [](const transport::ZoneStatus& z) {
    return "zone=\"" + LabelValue(z.name) + "\"";
  };
  e.Family("mvtrack_uptime_seconds", "gauge", "stitcher uptime");
  e.Sample(D(s.uptime_us) / 1e6);
  e.Family("mvtrack_start_time_seconds",
           "gauge",
           "when the stitcher instance started, seconds since the Unix epoch (changes on restart)");
  e.Sample(D(s.start_utime) / 1e6);
  e.Family("mvtrack_last_frame", "gauge", "frame index of the latest published site frame");
  e.Sample(D(s.last_frame));
  e.Family("mvtrack_active_tracks", "gauge", "global tracks in the latest site frame");
  e.Sample(s.active_tracks);
  e.Family("mvtrack_site_frames_total", "counter", "site frames published");
  e.Sample(D(s.site_frames));
  e.Family("mvtrack_site_global_ids_total", "counter", "global ids given out");
  e.Sample(D(s.global_ids));
  e.Family("mvtrack_site_wait_seconds",
           "gauge",
           "how long the period's site frames waited for the zones");
  e.Sample(D(s.wait_p50_us) / 1e6, "quantile=\"0.5\"");
  e.Sample(D(s.wait_p99_us) / 1e6, "quantile=\"0.99\"");
  e.Sample(D(s.wait_max_us) / 1e6, "quantile=\"1\"");
  e.Family("mvtrack_site_flag", "gauge", "1 when the site flag is set this period");
  FlagSamples(&e, s.flags, transport::SiteFlagNames, "");
  e.Family("mvtrack_zones", "gauge", "zones of the site");
  e.Sample(D(static_cast<std::int64_t>(s.zones.size())));
  e.Family("mvtrack_zone_live", "gauge", "1 while the zone delivers (not NO_DATA or STALE)");
  for (const transport::ZoneStatus& z : s.zones) e.Sample((z.flags & 3) == 0 ? 1.0 : 0.0, zone(z));
  e.Family("mvtrack_zone_frames_total", "counter", "tracks frames received from the zone");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(D(z.frames), zone(z));
  e.Family("mvtrack_zone_late_total", "counter", "zone frames that came after their site frame");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(D(z.late), zone(z));
  e.Family("mvtrack_zone_decode_errors_total", "counter", "zone messages that failed to decode");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(D(z.decode_errors), zone(z));
  e.Family("mvtrack_zone_latency_seconds",
           "gauge",
           "the zone's latest frame: its daemon's latency plus the transport to the stitcher");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(D(z.latency_us) / 1e6, zone(z));
  e.Family("mvtrack_zone_tracks", "gauge", "tracks in the zone's latest frame");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(z.tracks, zone(z));
  e.Family("mvtrack_zone_daemon_health",
           "gauge",
           "the zone daemon's own health: 0 OK, 1 WARNING, 2 CRITICAL, 3 UNKNOWN");
  for (const transport::ZoneStatus& z : s.zones) e.Sample(z.daemon_health, zone(z));
  e.Family("mvtrack_zone_flag", "gauge", "1 when the zone flag is set this period");
  for (const transport::ZoneStatus& z : s.zones) {
    FlagSamples(&e, z.flags, transport::ZoneFlagNames, zone(z) + ",");
  }
}

}  // namespace

std::string PrometheusText(const std::optional<transport::TrackerStatus>& status,
                           double status_age_s,
                           double stale_after_s,
                           const WebCounters& web,
                           const service::HealthReport& source,
                           const std::optional<transport::SiteStatus>& site) {
  Exposition e;
  const bool fresh = (status || site) && !(status_age_s > stale_after_s);
  e.Family("mvtrack_up",
           "gauge",
           "1 while tracker status messages arrive (the latest within the staleness period)");
  e.Sample(fresh ? 1.0 : 0.0);
  e.Family("mvtrack_web_tracks_messages_total", "counter", "tracks messages received");
  e.Sample(D(web.tracks_messages));
  e.Family("mvtrack_web_provisional_messages_total",
           "counter",
           "tracks messages received on the provisional channel (included in tracks messages)");
  e.Sample(D(web.provisional_messages));
  e.Family("mvtrack_web_status_messages_total", "counter", "status messages received");
  e.Sample(D(web.status_messages));
  e.Family("mvtrack_web_decode_errors_total", "counter", "messages that failed to decode");
  e.Sample(D(web.decode_errors));
  e.Family("mvtrack_web_clients", "gauge", "/events clients connected");
  e.Sample(D(web.clients));
  e.Family("mvtrack_web_clients_dropped_total",
           "counter",
           "/events clients disconnected because they did not keep up");
  e.Sample(D(web.clients_dropped));
  e.Family("mvtrack_web_events_sent_total", "counter", "events written to /events clients");
  e.Sample(D(web.events_sent));
  if (!status && !site) return e.text();
  e.Family("mvtrack_status_age_seconds", "gauge", "time since the latest status message");
  e.Sample(status_age_s);
  e.Family("mvtrack_health",
           "gauge",
           "0 OK, 1 WARNING, 2 CRITICAL, 3 UNKNOWN: the latest status is stale "
           "(monitoring-plugin levels; mvtrack status)");
  if (!fresh) {
    e.Sample(static_cast<double>(static_cast<int>(service::Health::kUnknown)));
    return e.text();
  }
  if (site) {
    e.Sample(static_cast<double>(
        static_cast<int>(service::Combine(service::AssessSiteStatus(*site), source).health)));
    SiteStatusSamples(e, *site);
    return e.text();
  }
  const transport::TrackerStatus& s = *status;
  e.Sample(static_cast<double>(
      static_cast<int>(service::Combine(service::AssessStatus(s), source).health)));
  e.Family("mvtrack_uptime_seconds", "gauge", "tracker uptime");
  e.Sample(D(s.uptime_us) / 1e6);
  e.Family("mvtrack_start_time_seconds",
           "gauge",
           "when the tracker instance started, seconds since the Unix epoch (changes on restart)");
  e.Sample(D(s.start_utime) / 1e6);
  e.Family("mvtrack_last_frame", "gauge", "frame index of the latest published tracks");
  e.Sample(D(s.last_frame));
  e.Family("mvtrack_frames_per_second", "gauge", "tracks messages per second in the period");
  e.Sample(service::FramesPerSecond(s));
  e.Family("mvtrack_active_tracks", "gauge", "tracks in the latest output, not ended");
  e.Sample(s.active_tracks);
  e.Family("mvtrack_confirmed_tracks", "gauge", "confirmed or lost tracks in the latest output");
  e.Sample(s.confirmed_tracks);
  e.Family("mvtrack_latency_seconds", "gauge", "processing latency of the period's outputs");
  e.Sample(D(s.latency_p50_us) / 1e6, "quantile=\"0.5\"");
  e.Sample(D(s.latency_p99_us) / 1e6, "quantile=\"0.99\"");
  e.Sample(D(s.latency_max_us) / 1e6, "quantile=\"1\"");
  e.Family("mvtrack_windows_processed_total", "counter", "sliding windows processed");
  e.Sample(D(s.windows_processed));
  e.Family("mvtrack_jobs_failed_total", "counter", "window jobs that failed");
  e.Sample(D(s.jobs_failed));
  e.Family("mvtrack_executor_queue_depth", "gauge", "window jobs waiting");
  e.Sample(s.executor_queue_depth);
  e.Family("mvtrack_kernel_drops_total",
           "counter",
           "input datagrams the kernel dropped (receive buffer full); -1 not measured");
  e.Sample(D(s.kernel_drops));
  e.Family("mvtrack_embeddings_used_total", "counter", "embeddings used for appearance");
  e.Sample(D(s.embeddings_used));
  e.Family("mvtrack_embeddings_dropped_total", "counter", "embeddings dropped as unusable");
  e.Sample(D(s.embeddings_dropped));
  e.Family("mvtrack_tracks_revived_total",
           "counter",
           "ended tracks that came back with their old id by appearance");
  e.Sample(D(s.tracks_revived));
  e.Family("mvtrack_gallery_bytes", "gauge", "memory of the appearance galleries");
  e.Sample(D(s.gallery_bytes));
  e.Family("mvtrack_tracker_flag", "gauge", "1 when the tracker flag is set this period");
  FlagSamples(&e, s.flags, transport::TrackerFlagNames, "");
  e.Family("mvtrack_cameras", "gauge", "configured cameras");
  e.Sample(D(static_cast<std::int64_t>(s.cameras.size())));
  e.Family("mvtrack_cameras_delivering", "gauge", "cameras whose input is used for tracking");
  e.Sample(service::CamerasDelivering(s));
  struct Counter {
    const char* name;
    const char* help;
    std::int64_t transport::CameraStatus::*field;
  };
  const std::vector<Counter> counters = {
      {"mvtrack_camera_received_total",
       "messages received and decoded",
       &transport::CameraStatus::received},
      {"mvtrack_camera_late_total",
       "camera-frames discarded as late",
       &transport::CameraStatus::late},
      {"mvtrack_camera_dropped_total",
       "camera-frames dropped (queue overflow, flooding)",
       &transport::CameraStatus::dropped},
      {"mvtrack_camera_rejected_total",
       "detections rejected by validation",
       &transport::CameraStatus::rejected},
      {"mvtrack_camera_decode_errors_total",
       "messages on the camera's channel that failed",
       &transport::CameraStatus::decode_errors},
      {"mvtrack_camera_lost_total",
       "frames the camera never delivered",
       &transport::CameraStatus::lost},
      {"mvtrack_camera_embeddings_dropped_total",
       "embeddings dropped as unusable",
       &transport::CameraStatus::embeddings_dropped},
  };
  for (const Counter& c : counters) {
    e.Family(c.name, "counter", c.help);
    for (const transport::CameraStatus& cam : s.cameras)
      e.Sample(D(cam.*c.field), CameraLabel(cam));
  }
  e.Family("mvtrack_camera_rate_hz", "gauge", "messages per second in the period");
  for (const transport::CameraStatus& cam : s.cameras) e.Sample(cam.rate_hz, CameraLabel(cam));
  e.Family("mvtrack_camera_clock_offset_seconds",
           "gauge",
           "the clock model's offset of the camera to the others");
  for (const transport::CameraStatus& cam : s.cameras) {
    e.Sample(D(cam.clock_offset_us) / 1e6, CameraLabel(cam));
  }
  e.Family("mvtrack_camera_queue_depth", "gauge", "camera-frames waiting for the camera thread");
  for (const transport::CameraStatus& cam : s.cameras) e.Sample(cam.queue_depth, CameraLabel(cam));
  e.Family("mvtrack_camera_last_receive_age_seconds",
           "gauge",
           "time from the camera's latest message to the status");
  for (const transport::CameraStatus& cam : s.cameras) {
    e.Sample(cam.last_receive_utime > 0 ? (D(s.utime) - D(cam.last_receive_utime)) / 1e6 : NAN,
             CameraLabel(cam));
  }
  e.Family("mvtrack_camera_flag", "gauge", "1 when the camera flag is set this period");
  for (const transport::CameraStatus& cam : s.cameras) {
    FlagSamples(&e, cam.flags, transport::CameraFlagNames, CameraLabel(cam) + ",");
  }
  return e.text();
}

void DwellHistogram::Add(double dwell_s) {
  if (!std::isfinite(dwell_s) || dwell_s < 0.0) return;
  for (std::size_t i = 0; i < std::size(kBounds); ++i) counts[i] += dwell_s <= kBounds[i] ? 1 : 0;
  ++count;
  sum_s += dwell_s;
}

bool AddDwell(std::map<std::string, DwellHistogram>* dwell,
              const std::string& name,
              double dwell_s) {
  auto it = dwell->find(name);
  if (it == dwell->end()) {
    if (dwell->size() >= static_cast<std::size_t>(analytics::kMaxRegions)) return false;
    it = dwell->emplace(name, DwellHistogram{}).first;
  }
  it->second.Add(dwell_s);
  return true;
}

std::string SiteMetricsText(const std::optional<transport::SiteCounts>& counts,
                            const std::map<std::string, DwellHistogram>& dwell) {
  Exposition e;
  if (counts) {
    const auto region = [](const std::string& name) {
      return "region=\"" + LabelValue(name) + "\"";
    };
    e.Family("mvtrack_region_occupancy", "gauge", "people inside the region now (confirmed)");
    for (std::size_t i = 0; i < counts->regions.size(); ++i) {
      e.Sample(counts->regions[i].occupancy, region(counts->region_names[i]));
    }
    e.Family("mvtrack_region_entries_total", "counter", "visits of the region begun");
    for (std::size_t i = 0; i < counts->regions.size(); ++i) {
      e.Sample(D(counts->regions[i].entries), region(counts->region_names[i]));
    }
    e.Family("mvtrack_region_exits_total", "counter", "visits of the region ended");
    for (std::size_t i = 0; i < counts->regions.size(); ++i) {
      e.Sample(D(counts->regions[i].exits), region(counts->region_names[i]));
    }
    if (!counts->lines.empty()) {
      e.Family("mvtrack_line_crossings_total", "counter", "crossings of the line, by direction");
      for (std::size_t i = 0; i < counts->lines.size(); ++i) {
        const std::string line = "line=\"" + LabelValue(counts->line_names[i]) + "\"";
        e.Sample(D(counts->lines[i].left_to_right), line + ",direction=\"left_to_right\"");
        e.Sample(D(counts->lines[i].right_to_left), line + ",direction=\"right_to_left\"");
      }
    }
  }
  if (!dwell.empty()) {
    e.Family("mvtrack_region_dwell_seconds",
             "histogram",
             "dwell of the visits that ended since the web server started, seconds");
    std::string text = e.text();
    for (const auto& [name, h] : dwell) {
      const std::string region = "region=\"" + LabelValue(name) + "\"";
      char buf[64];
      for (std::size_t i = 0; i < std::size(DwellHistogram::kBounds); ++i) {
        std::snprintf(buf, sizeof(buf), "%g", DwellHistogram::kBounds[i]);
        text += "mvtrack_region_dwell_seconds_bucket{" + region + ",le=\"" + buf + "\"} " +
                std::to_string(h.counts[i]) + "\n";
      }
      text += "mvtrack_region_dwell_seconds_bucket{" + region + ",le=\"+Inf\"} " +
              std::to_string(h.count) + "\n";
      std::snprintf(buf, sizeof(buf), "%.9g", h.sum_s);
      text += "mvtrack_region_dwell_seconds_sum{" + region + "} " + buf + "\n";
      text +=
          "mvtrack_region_dwell_seconds_count{" + region + "} " + std::to_string(h.count) + "\n";
    }
    return text;
  }
  return e.text();
}

}  // namespace mvtrack::web
