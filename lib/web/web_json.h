#pragma once
/// @file
/// The JSON of `mvtrack web` (docs/FORMATS.md "Live events"): one object per tracks message and
/// per status message (the /events stream, for clients that do not speak LCM), and the floor
/// the page draws (cameras and their fields of view on the floor, from the calibration).
/// Written with lib/json's documents (nlohmann-json); numbers that are not finite become null.

#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "service/status_check.h"
#include "transport/codec.h"

namespace mvtrack::web {

/// {"type":"tracks", "frame", "utime", "publish_utime", "latency_us", "layout", "zones":[the
/// site's zone names; empty from one tracker], "tracks":[{"id", "state", "position":[x,y,z],
/// "confidence", "age_frames", "cameras":[...], "joints":[[x,y,z] or null, ...],
/// "bone_lengths":[metres per bone of the layout, 0 = not known yet; empty without the skeleton
/// fit], "zones":[names of the zones that saw it]}]} on one line. `state` is "tentative",
/// "confirmed", "lost" or "ended".
std::string TracksEventJson(const transport::TracksMessage& message);

/// {"type":"status", every tracker_status_t field, "flags":[names], "health", "reasons":[...],
/// "cameras_delivering", "fps", "cameras":[{every camera_status_t field, "flags":[names]}]} on
/// one line (`health` and `reasons`: service::AssessStatus combined with `source`, what the
/// status messages say about who sends them, service::StatusSourceWatch).
std::string StatusEventJson(const transport::TrackerStatus& status,
                            const service::HealthReport& source = {service::Health::kOk, {}});

/// {"type":"site_status", every site_status_t field, "flags":[names], "health", "reasons":[...],
/// "zones":[{every zone_status_t field, "flags":[names], "daemon_health": "OK"|"WARNING"|
/// "CRITICAL"|"UNKNOWN"}]} on one line: a site's stitcher status (issue 43; `health` and
/// `reasons`: service::AssessSiteStatus combined with `source`).
std::string SiteStatusEventJson(const transport::SiteStatus& status,
                                const service::HealthReport& source = {service::Health::kOk, {}});

/// {"type":"analytics", "kind":"enter"|"exit"|"crossing", "name", "track_id", "utime",
/// "enter_utime", "dwell_s" (exit; else null), "direction" (crossing: "left_to_right" or
/// "right_to_left"; else null), "track_ended", "publish_utime"} on one line.
std::string AnalyticsEventJson(const transport::AnalyticsEventMessage& event);

/// {"type":"site_counts", "utime", "publish_utime", "regions":[{"name", "occupancy", "entries",
/// "exits"}], "lines":[{"name", "left_to_right", "right_to_left"}]} on one line.
std::string SiteCountsEventJson(const transport::SiteCounts& counts);

/// {"regions":[{"name", "polygon":[[x,y], ...]}], "lines":[{"name", "from":[x,y],
/// "to":[x,y]}]}: the site the page draws (empty lists without one).
std::string SiteJson(const analytics::Site& site);

/// {"cameras":[{"id", "position":[x,y,z], "fov":[[x,y], ...]}], "bounds":[x_min, y_min, x_max,
/// y_max]}: each camera's centre and the polygon its image covers on the floor z = 0 (the rays
/// through the image border, cut at 25 m from the camera where they do not reach the floor);
/// bounds: the cameras' positions with a margin of a quarter of their spread, at least 2 m;
/// stale_after_s: the server's staleness period, which the page ages its state with.
/// Empty cameras: {"cameras":[], "bounds":null, "stale_after_s": ...}.
std::string FloorJson(const std::vector<geometry::CameraModel>& cameras,
                      double stale_after_s = 5.0);

}  // namespace mvtrack::web
