#pragma once
/// @file
/// Prometheus text exposition (format 0.0.4) of the latest tracker_status_t and of the web
/// server's own counters, for `mvtrack web`'s /metrics (metric names in docs/OPERATING.md).

#include <cstdint>
#include <iterator>
#include <map>
#include <optional>
#include <string>

#include "service/status_check.h"
#include "transport/codec.h"

namespace mvtrack::web {

/// The web server's own counters.
struct WebCounters {
  std::int64_t tracks_messages = 0;       ///< tracks3d_t received and decoded
  std::int64_t provisional_messages = 0;  ///< of them, on the provisional channel
  std::int64_t status_messages = 0;       ///< tracker_status_t received and decoded
  std::int64_t decode_errors = 0;         ///< messages on either channel that failed to decode
  std::int64_t clients = 0;               ///< /events clients connected now
  std::int64_t clients_dropped = 0;       ///< /events clients disconnected for being too slow
  std::int64_t events_sent = 0;           ///< events written to /events clients
  std::int64_t analytics_events = 0;      ///< analytics_event_t received and decoded
  std::int64_t site_counts_messages = 0;  ///< site_counts_t received and decoded
};

/// The dwell times of one region's visits that ended (exit events) since the server started,
/// as a Prometheus histogram.
struct DwellHistogram {
  /// Upper bounds of the buckets, seconds (then +Inf).
  static constexpr double kBounds[] = {1, 5, 10, 30, 60, 300, 900, 3600};
  std::int64_t counts[std::size(kBounds)] = {};  ///< per bound: visits with dwell <= it
  std::int64_t count = 0;
  double sum_s = 0.0;
  void Add(double dwell_s);
};

/// The exposition text. Without a status (none received yet) only mvtrack_up 0 and the web
/// counters; `status_age_s` is the time since the latest status arrived. A status older than
/// `stale_after_s` (the tracker stopped publishing: /healthz's staleness rule) is not reported
/// as if it were current: mvtrack_up 0, mvtrack_health 3 (UNKNOWN), its age, and none of the
/// tracker's or the cameras' values. `source`: what the status messages say about who sends
/// them (service::StatusSourceWatch), combined into mvtrack_health. With `site` instead of
/// `status` (a site's stitcher publishes the status channel, issue 43): the site's series,
/// mvtrack_zone_* per zone (docs/OPERATING.md "Metrics").
std::string PrometheusText(const std::optional<transport::TrackerStatus>& status,
                           double status_age_s,
                           double stale_after_s,
                           const WebCounters& web,
                           const service::HealthReport& source = {service::Health::kOk, {}},
                           const std::optional<transport::SiteStatus>& site = std::nullopt);

/// Adds a visit's dwell to `name`'s histogram in `dwell`. Names come from messages (untrusted):
/// at most analytics::kMaxRegions of them are kept, a visit of another name once the map is
/// full is not counted; returns whether it was.
bool AddDwell(std::map<std::string, DwellHistogram>* dwell,
              const std::string& name,
              double dwell_s);

/// The site analytics' series (docs/OPERATING.md "Metrics"): per region of the latest counts
/// mvtrack_region_occupancy, mvtrack_region_entries_total, mvtrack_region_exits_total; per line
/// mvtrack_line_crossings_total{direction}; per region with ended visits
/// mvtrack_region_dwell_seconds (histogram). Empty without counts and dwell times.
std::string SiteMetricsText(const std::optional<transport::SiteCounts>& counts,
                            const std::map<std::string, DwellHistogram>& dwell);

}  // namespace mvtrack::web
