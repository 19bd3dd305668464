#include "web/web_json.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "json/document.h"

namespace mvtrack::web {
namespace {

using Json = mvtrack::json::Document;

Json Number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json Point(const Vec3& p) { return Json::array({Number(p.x()), Number(p.y()), Number(p.z())}); }

const char* StateName(transport::WireTrackState s) {
  switch (s) {
    case transport::WireTrackState::kTentative:
      return "tentative";
    case transport::WireTrackState::kConfirmed:
      return "confirmed";
    case transport::WireTrackState::kLost:
      return "lost";
    case transport::WireTrackState::kEnded:
      return "ended";
  }
  return "lost";
}

Json Names(const std::vector<std::string>& names) {
  Json a = Json::array();
  for (const std::string& n : names) a.push_back(n);
  return a;
}

}  // namespace

std::string TracksEventJson(const transport::TracksMessage& message) {
  Json tracks = Json::array();
  for (std::size_t i = 0; i < message.frame.tracks.size(); ++i) {
    const tracker::Track3D& t = message.frame.tracks[i];
    Json joints = Json::array();
    for (const std::optional<Vec3>& j : t.joints) joints.push_back(j ? Point(*j) : Json(nullptr));
    Json bones = Json::array();
    for (const double b : t.bone_lengths) bones.push_back(Number(b));
    Json zones = Json::array();  // by name (the decoder checked the indices)
    for (const int z : t.zones)
      zones.push_back(message.frame.zones.at(static_cast<std::size_t>(z)));
    tracks.push_back(
        {{"id", t.id},
         {"state", i < message.info.size() ? StateName(message.info[i].state) : "confirmed"},
         {"position", Point(t.position)},
         {"confidence", Number(t.confidence)},
         {"age_frames", t.age_frames},
         {"cameras", t.cameras},
         {"joints", std::move(joints)},
         {"bone_lengths", std::move(bones)},
         {"zones", std::move(zones)}});
  }
  const Json o = {{"type", "tracks"},
                  {"layer", transport::ToString(message.layer)},
                  {"frame", message.frame.frame},
                  {"utime", message.frame.utime},
                  {"publish_utime", message.publish_utime},
                  {"latency_us", message.latency_us},
                  {"layout",
                   message.layout == core::KeypointLayoutId::kNone
                       ? std::string()
                       : core::GetKeypointLayout(message.layout).name},
                  {"zones", message.frame.zones},
                  {"tracks", std::move(tracks)}};
  return mvtrack::json::Dump(o, -1, mvtrack::json::Ascii::kEscape);
}

std::string SiteStatusEventJson(const transport::SiteStatus& s,
                                const service::HealthReport& source) {
  const service::HealthReport health = service::Combine(service::AssessSiteStatus(s), source);
  Json zones = Json::array();
  for (const transport::ZoneStatus& z : s.zones) {
    zones.push_back(
        {{"name", z.name},
         {"channel", z.channel},
         {"flags", Names(transport::ZoneFlagNames(z.flags))},
         {"frames", z.frames},
         {"late", z.late},
         {"decode_errors", z.decode_errors},
         {"other_layer", z.other_layer},
         {"last_utime", z.last_utime},
         {"last_receive_utime", z.last_receive_utime},
         {"latency_us", z.latency_us},
         {"tracks", z.tracks},
         {"daemon_health", service::ToString(static_cast<service::Health>(z.daemon_health))},
         {"daemon_reasons", z.daemon_reasons},
         {"daemon_instance_id", z.daemon_instance_id}});
  }
  const Json o = {{"type", "site_status"},
                  {"utime", s.utime},
                  {"period_us", s.period_us},
                  {"uptime_us", s.uptime_us},
                  {"instance_id", s.instance_id},
                  {"start_utime", s.start_utime},
                  {"sequence", s.sequence},
                  {"version", s.version},
                  {"flags", Names(transport::SiteFlagNames(s.flags))},
                  {"health", service::ToString(health.health)},
                  {"reasons", health.reasons},
                  {"last_frame", s.last_frame},
                  {"site_frames", s.site_frames},
                  {"active_tracks", s.active_tracks},
                  {"global_ids", s.global_ids},
                  {"splits", s.splits},
                  {"merges", s.merges},
                  {"num_wait_samples", s.num_wait_samples},
                  {"wait_p50_us", s.wait_p50_us},
                  {"wait_p99_us", s.wait_p99_us},
                  {"wait_max_us", s.wait_max_us},
                  {"zones", std::move(zones)}};
  return mvtrack::json::Dump(o, -1, mvtrack::json::Ascii::kEscape);
}

std::string StatusEventJson(const transport::TrackerStatus& s,
                            const service::HealthReport& source) {
  const service::HealthReport health = service::Combine(service::AssessStatus(s), source);
  Json cameras = Json::array();
  for (const transport::CameraStatus& c : s.cameras) {
    cameras.push_back({{"camera_id", c.camera_id},
                       {"flags", Names(transport::CameraFlagNames(c.flags))},
                       {"rate_hz", Number(c.rate_hz)},
                       {"last_utime", c.last_utime},
                       {"last_receive_utime", c.last_receive_utime},
                       {"received", c.received},
                       {"late", c.late},
                       {"dropped", c.dropped},
                       {"rejected", c.rejected},
                       {"decode_errors", c.decode_errors},
                       {"lost", c.lost},
                       {"clock_offset_us", c.clock_offset_us},
                       {"embeddings_dropped", c.embeddings_dropped},
                       {"queue_depth", c.queue_depth},
                       {"queue_capacity", c.queue_capacity}});
  }
  const Json o = {{"type", "status"},
                  {"utime", s.utime},
                  {"period_us", s.period_us},
                  {"uptime_us", s.uptime_us},
                  {"instance_id", s.instance_id},
                  {"start_utime", s.start_utime},
                  {"sequence", s.sequence},
                  {"version", s.version},
                  {"config_hash", s.config_hash},
                  {"flags", Names(transport::TrackerFlagNames(s.flags))},
                  {"health", service::ToString(health.health)},
                  {"reasons", health.reasons},
                  {"cameras_delivering", service::CamerasDelivering(s)},
                  {"fps", Number(service::FramesPerSecond(s))},
                  {"last_frame", s.last_frame},
                  {"active_tracks", s.active_tracks},
                  {"confirmed_tracks", s.confirmed_tracks},
                  {"num_latency_samples", s.num_latency_samples},
                  {"latency_p50_us", s.latency_p50_us},
                  {"latency_p99_us", s.latency_p99_us},
                  {"latency_max_us", s.latency_max_us},
                  {"windows_processed", s.windows_processed},
                  {"jobs_failed", s.jobs_failed},
                  {"executor_queue_depth", s.executor_queue_depth},
                  {"kernel_drops", s.kernel_drops},
                  {"embeddings_used", s.embeddings_used},
                  {"embeddings_dropped", s.embeddings_dropped},
                  {"tracks_revived", s.tracks_revived},
                  {"gallery_bytes", s.gallery_bytes},
                  {"cameras", std::move(cameras)}};
  return mvtrack::json::Dump(o, -1, mvtrack::json::Ascii::kEscape);
}

std::string FloorJson(const std::vector<geometry::CameraModel>& cameras, double stale_after_s) {
  constexpr double kMaxRange = 25.0;
  constexpr int kPerEdge = 8;
  Json out_cameras = Json::array();
  double bx0 = INFINITY, by0 = INFINITY, bx1 = -INFINITY, by1 = -INFINITY;
  auto grow = [&](double x, double y) {
    bx0 = std::min(bx0, x);
    by0 = std::min(by0, y);
    bx1 = std::max(bx1, x);
    by1 = std::max(by1, y);
  };
  for (const geometry::CameraModel& cam : cameras) {
    const Vec3 c = cam.CenterInWorld();
    const Mat3 k_inv = cam.K.inverse();
    const Mat3 world_from_cam = cam.cam_from_world.rotation.transpose();
    Json fov = Json::array();
    const double w = cam.width_px, h = cam.height_px;
    // The image border, clockwise from the top-left corner.
    const double corners[5][2] = {{0, 0}, {w, 0}, {w, h}, {0, h}, {0, 0}};
    for (int e = 0; e < 4; ++e) {
      for (int s = 0; s < kPerEdge; ++s) {
        const double a = static_cast<double>(s) / kPerEdge;
        const double u = corners[e][0] + a * (corners[e + 1][0] - corners[e][0]);
        const double v = corners[e][1] + a * (corners[e + 1][1] - corners[e][1]);
        const Vec3 d = world_from_cam * (k_inv * Vec3(u, v, 1.0));
        Vec3 p;
        const double horizontal = std::hypot(d.x(), d.y());
        if (d.z() < -1e-9 && -c.z() / d.z() * horizontal <= kMaxRange) {
          p = c + d * (-c.z() / d.z());
        } else if (horizontal > 1e-9) {
          p = c + Vec3(d.x(), d.y(), 0.0) * (kMaxRange / horizontal);
        } else {
          continue;
        }
        fov.push_back(Json::array({Number(p.x()), Number(p.y())}));
      }
    }
    if (std::isfinite(c.x()) && std::isfinite(c.y())) grow(c.x(), c.y());
    out_cameras.push_back({{"id", cam.id}, {"position", Point(c)}, {"fov", std::move(fov)}});
  }
  // The cameras' positions with a margin of a quarter of their spread (at least 2 m): where the
  // people are; the fields of view reach far beyond and are clipped by the view.
  Json bounds = nullptr;
  if (bx0 <= bx1) {
    const double m = std::max(2.0, 0.25 * std::max(bx1 - bx0, by1 - by0));
    bounds = Json::array({bx0 - m, by0 - m, bx1 + m, by1 + m});
  }
  const Json o = {{"cameras", std::move(out_cameras)},
                  {"bounds", std::move(bounds)},
                  {"stale_after_s", stale_after_s}};
  return mvtrack::json::Dump(o, -1, mvtrack::json::Ascii::kEscape);
}

}  // namespace mvtrack::web

namespace mvtrack::web {

std::string AnalyticsEventJson(const transport::AnalyticsEventMessage& e) {
  const bool exit = e.kind == analytics::Event::Kind::kExit;
  const bool crossing = e.kind == analytics::Event::Kind::kCrossing;
  const Json o = {
      {"type", "analytics"},
      {"kind", analytics::ToString(e.kind)},
      {"name", e.name},
      {"track_id", e.track_id},
      {"utime", e.utime},
      {"enter_utime", e.enter_utime},
      {"dwell_s", exit ? Json(static_cast<double>(e.utime - e.enter_utime) * 1e-6) : Json(nullptr)},
      {"direction", crossing ? Json(analytics::ToString(e.direction)) : Json(nullptr)},
      {"track_ended", e.track_ended},
      {"publish_utime", e.publish_utime}};
  return json::Dump(o, -1, json::Ascii::kEscape);
}

std::string SiteCountsEventJson(const transport::SiteCounts& c) {
  Json regions = Json::array();
  for (std::size_t i = 0; i < c.regions.size() && i < c.region_names.size(); ++i) {
    regions.push_back({{"name", c.region_names[i]},
                       {"occupancy", c.regions[i].occupancy},
                       {"entries", c.regions[i].entries},
                       {"exits", c.regions[i].exits}});
  }
  Json lines = Json::array();
  for (std::size_t i = 0; i < c.lines.size() && i < c.line_names.size(); ++i) {
    lines.push_back({{"name", c.line_names[i]},
                     {"left_to_right", c.lines[i].left_to_right},
                     {"right_to_left", c.lines[i].right_to_left}});
  }
  const Json o = {{"type", "site_counts"},
                  {"utime", c.utime},
                  {"publish_utime", c.publish_utime},
                  {"regions", std::move(regions)},
                  {"lines", std::move(lines)}};
  return json::Dump(o, -1, json::Ascii::kEscape);
}

std::string SiteJson(const analytics::Site& site) {
  const auto xy = [](const Vec2& p) { return Json::array({p.x(), p.y()}); };
  Json regions = Json::array();
  for (const analytics::Region& r : site.regions) {
    Json polygon = Json::array();
    for (const Vec2& p : r.polygon) polygon.push_back(xy(p));
    regions.push_back({{"name", r.name}, {"polygon", std::move(polygon)}});
  }
  Json lines = Json::array();
  for (const analytics::Line& l : site.lines) {
    lines.push_back({{"name", l.name}, {"from", xy(l.from)}, {"to", xy(l.to)}});
  }
  const Json o = {{"regions", std::move(regions)}, {"lines", std::move(lines)}};
  return json::Dump(o, -1, json::Ascii::kEscape);
}

}  // namespace mvtrack::web
