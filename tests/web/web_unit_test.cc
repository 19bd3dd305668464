// lib/web and service::AssessStatus without a network: the events' JSON (parsed back with
// nlohmann-json), the floor, the Prometheus text, the health verdicts and the systemd line.

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "service/status_check.h"
#include "web/metrics.h"
#include "web/web_json.h"

namespace mvtrack::web {
namespace {

using nlohmann::json;

transport::TrackerStatus Healthy() {
  transport::TrackerStatus s;
  s.utime = 2'000'000;
  s.period_us = 1'000'000;
  s.version = "0.3.0";
  s.num_latency_samples = 30;
  s.active_tracks = 5;
  s.confirmed_tracks = 4;
  for (int i = 0; i < 3; ++i) {
    transport::CameraStatus c;
    c.camera_id = i;
    c.received = 100;
    c.rate_hz = 30.0f;
    c.last_receive_utime = 1'900'000;
    s.cameras.push_back(c);
  }
  return s;
}

TEST_CASE("health: OK, WARNING with the flags named, CRITICAL below two cameras", "[unit]") {
  transport::TrackerStatus s = Healthy();
  service::HealthReport h = service::AssessStatus(s);
  CHECK(h.health == service::Health::kOk);
  CHECK(h.reasons.empty());
  CHECK(service::NotifyStatusLine(s, 30.0) ==
        "tracking: 3/3 cameras, 30.0 fps, 5 tracks (4 confirmed), OK");

  s.cameras[1].flags = 64;  // CLOCK_OFFSET: excluded, still two deliver
  s.flags = 8;              // LATENCY_HIGH
  h = service::AssessStatus(s);
  CHECK(h.health == service::Health::kWarning);
  CHECK(h.reasons == std::vector<std::string>{"LATENCY_HIGH", "camera 1 CLOCK_OFFSET"});
  CHECK(service::CamerasDelivering(s) == 2);
  CHECK(service::NotifyStatusLine(s, 29.96) ==
        "tracking: 2/3 cameras, 30.0 fps, 5 tracks (4 confirmed), WARNING: LATENCY_HIGH; "
        "camera 1 CLOCK_OFFSET");

  s.cameras[2].flags = 2;  // STALE
  h = service::AssessStatus(s);
  CHECK(h.health == service::Health::kCritical);
  CHECK(h.reasons.front() == "1 of 3 cameras deliver (2 are needed to triangulate)");

  transport::TrackerStatus backlog = Healthy();
  backlog.flags = 4;
  CHECK(service::AssessStatus(backlog).health == service::Health::kCritical);
  transport::TrackerStatus never = Healthy();
  for (auto& c : never.cameras) c.received = 0;
  CHECK(service::AssessStatus(never).health == service::Health::kCritical);

  // Cameras deliver, nothing is published (issue 39: this was WARNING at best).
  transport::TrackerStatus no_output = Healthy();
  no_output.flags = 32;  // NO_OUTPUT
  h = service::AssessStatus(no_output);
  CHECK(h.health == service::Health::kCritical);
  CHECK(h.reasons ==
        std::vector<std::string>{"NO_OUTPUT: cameras deliver but no frame was published for 3 s"});
  CHECK(transport::TrackerFlagNames(32 | 8) ==
        std::vector<std::string>{"LATENCY_HIGH", "NO_OUTPUT"});
}

TEST_CASE("status source: a restart, two instances at once, a sequence going backwards", "[unit]") {
  using service::Health;
  service::StatusSourceWatch w(5.0);
  auto add = [&](const char* id, std::int64_t seq, double t) { w.Add({id, seq}, t); };
  // One daemon, statuses once a second: nothing to say.
  for (int i = 0; i < 5; ++i) add("aaaa", i, i);
  CHECK(w.Assess(4.0).health == Health::kOk);
  CHECK(w.Assess(4.0).reasons.empty());
  // It restarts: a new instance, the old one is not heard again. WARNING for the window.
  add("bbbb", 0, 5.0);
  add("bbbb", 1, 6.0);
  service::HealthReport h = w.Assess(6.0);
  CHECK(h.health == Health::kWarning);
  CHECK(h.reasons ==
        std::vector<std::string>{"the tracker restarted: instance bbbb replaced aaaa"});
  CHECK(w.Assess(10.1).health == Health::kOk);  // the window passed
  // A second daemon on the channel (or forged statuses): the instances interleave.
  add("cccc", 0, 11.0);  // first heard: looks like a restart
  CHECK(w.Assess(11.0).health == Health::kWarning);
  add("bbbb", 7, 11.5);  // the "replaced" one is heard again: two at once
  h = w.Assess(11.5);
  CHECK(h.health == Health::kCritical);
  CHECK(h.reasons ==
        std::vector<std::string>{"two tracker instances publish statuses on this channel (bbbb and "
                                 "cccc): a second daemon, or forged status messages"});
  CHECK(w.Assess(16.4).health == Health::kCritical);
  // A replayed status of the live instance: its sequence goes backwards (or repeats).
  service::StatusSourceWatch r(5.0);
  r.Add({"dddd", 10}, 0.0);
  r.Add({"dddd", 11}, 1.0);
  CHECK(r.Assess(1.0).health == Health::kOk);
  r.Add({"dddd", 11}, 1.5);
  h = r.Assess(1.5);
  CHECK(h.health == Health::kCritical);
  CHECK(h.reasons == std::vector<std::string>{"the status sequence of instance dddd went "
                                              "backwards (11 after 11): replayed or forged "
                                              "status messages"});
  r.Add({"dddd", 12}, 2.0);  // the real one goes on: still CRITICAL for the window
  CHECK(r.Assess(6.4).health == Health::kCritical);
  CHECK(r.Assess(6.6).health == Health::kOk);
  // Hostile ids: bounded memory, printable and short in the reasons.
  service::StatusSourceWatch f(5.0);
  for (int i = 0; i < 1000; ++i) f.Add({std::string(100, 'x') + std::to_string(i), 0}, 0.0);
  f.Add({std::string("\x01\n") + std::string(40, 'y'), 0}, 0.1);
  h = f.Assess(0.1);
  REQUIRE(h.reasons.size() == 1);
  CHECK(h.reasons[0].find('\n') == std::string::npos);
  CHECK(h.reasons[0].size() < 120);

  // Combined with the status's own verdict: the worse first.
  transport::TrackerStatus s = Healthy();
  s.flags = 8;  // LATENCY_HIGH: WARNING
  h = service::Combine(service::AssessStatus(s), r.Assess(1.5));
  CHECK(h.health == Health::kCritical);
  CHECK(h.reasons.size() == 2);
  CHECK(h.reasons.back() == "LATENCY_HIGH");
  h = service::Combine(service::AssessStatus(s), {Health::kOk, {}});
  CHECK(h.health == Health::kWarning);
  CHECK(h.reasons == std::vector<std::string>{"LATENCY_HIGH"});
  // ... in the status event and the metrics.
  const json e = json::parse(StatusEventJson(s, r.Assess(1.5)));
  CHECK(e["health"] == "CRITICAL");
  CHECK(e["reasons"].size() == 2);
  CHECK_THAT(PrometheusText(s, 0.5, 5.0, WebCounters{}, r.Assess(1.5)),
             Catch::Contains("mvtrack_health 2\n"));
}

TEST_CASE("frame rate over a horizon, not one bursty status period", "[unit]") {
  service::FrameRateMeter meter(5'000'000);
  transport::TrackerStatus s = Healthy();
  // The output advances 20 frames every 0.667 s (a window step at 30 fps), statuses every 0.2 s.
  double rate = 0.0;
  for (int i = 0; i < 60; ++i) {
    s.utime = 1'000'000 + i * 200'000;
    s.last_frame = (i * 200'000 / 666'667) * 20;
    rate = meter.Add(s);
  }
  CHECK(rate == Approx(30.0).margin(4.0));
  s.utime += 200'000;
  s.last_frame = 3;  // a new daemon: starts over
  s.num_latency_samples = 4;
  CHECK(meter.Add(s) == Approx(service::FramesPerSecond(s)));
}

TEST_CASE("tracks event: the documented fields, states, joints as null or [x,y,z]", "[unit]") {
  transport::TracksMessage m;
  m.frame.frame = 42;
  m.frame.utime = 1000;
  m.publish_utime = 2000;
  m.latency_us = 7;
  m.layout = core::KeypointLayoutId::kCoco17;
  tracker::Track3D t;
  t.id = 9;
  t.position = Vec3(1.5, -2.25, 0.0);
  t.confidence = 0.5;
  t.age_frames = 3;
  t.cameras = {0, 2};
  t.joints.assign(17, std::nullopt);
  t.joints[0] = Vec3(1.0, 2.0, 1.7);
  t.bone_lengths.assign(19, 0.0);  // with the skeleton fit: coco17's 19 bones
  t.bone_lengths[3] = 0.25;
  m.frame.tracks.push_back(t);
  t.id = 10;
  t.bone_lengths.clear();
  t.position = Vec3(std::nan(""), 0.0, 0.0);
  m.frame.tracks.push_back(t);
  m.info.resize(2);
  m.info[1].state = transport::WireTrackState::kLost;
  const json e = json::parse(TracksEventJson(m));
  CHECK(e["type"] == "tracks");
  CHECK(e["frame"] == 42);
  CHECK(e["publish_utime"] == 2000);
  CHECK(e["layout"] == "coco17");
  CHECK(e["layer"] == "final");
  m.layer = transport::TracksLayer::kProvisional;
  CHECK(json::parse(TracksEventJson(m))["layer"] == "provisional");
  REQUIRE(e["tracks"].size() == 2);
  const json& a = e["tracks"][0];
  CHECK(a["id"] == 9);
  CHECK(a["state"] == "confirmed");
  CHECK(a["position"][1] == -2.25);
  CHECK(a["cameras"] == json::array({0, 2}));
  CHECK(a["joints"].size() == 17);
  CHECK(a["joints"][0][2] == 1.7);
  CHECK(a["joints"][1].is_null());
  CHECK(a["bone_lengths"].size() == 19);
  CHECK(a["bone_lengths"][3] == 0.25);
  CHECK(e["tracks"][1]["bone_lengths"] == json::array());
  CHECK(e["tracks"][1]["state"] == "lost");
  CHECK(e["tracks"][1]["position"][0].is_null());  // not finite -> null, still valid JSON
  CHECK(e["zones"] == json::array());
  CHECK(a["zones"] == json::array());
  // A site's stitched output: the site's zones, and per track the zones that saw it, by name.
  m.frame.zones = {"east", "west"};
  m.frame.tracks[0].zones = {0, 1};
  m.frame.tracks[1].zones = {1};
  const json site = json::parse(TracksEventJson(m));
  CHECK(site["zones"] == json::array({"east", "west"}));
  CHECK(site["tracks"][0]["zones"] == json::array({"east", "west"}));
  CHECK(site["tracks"][1]["zones"] == json::array({"west"}));
}

TEST_CASE("status event: health, flag names and every camera field", "[unit]") {
  transport::TrackerStatus s = Healthy();
  s.cameras[0].flags = 128;
  s.cameras[0].lost = 4;
  s.kernel_drops = 12;
  s.embeddings_used = 500;
  s.embeddings_dropped = 7;
  s.tracks_revived = 2;
  s.gallery_bytes = 65'536;
  s.cameras[2].embeddings_dropped = 7;
  s.cameras[2].flags = 256;
  s.instance_id = "0123456789abcdef";
  s.start_utime = 1'000'000;
  s.sequence = 17;
  const json e = json::parse(StatusEventJson(s));
  CHECK(e["type"] == "status");
  CHECK(e["instance_id"] == "0123456789abcdef");
  CHECK(e["start_utime"] == 1'000'000);
  CHECK(e["sequence"] == 17);
  CHECK(e["health"] == "WARNING");
  CHECK(e["reasons"] == json::array({"camera 0 LOSING", "camera 2 BAD_EMBEDDINGS"}));
  CHECK(e["fps"] == 30.0);
  CHECK(e["kernel_drops"] == 12);
  CHECK(e["embeddings_used"] == 500);
  CHECK(e["embeddings_dropped"] == 7);
  CHECK(e["tracks_revived"] == 2);
  CHECK(e["gallery_bytes"] == 65'536);
  CHECK(e["cameras_delivering"] == 3);
  REQUIRE(e["cameras"].size() == 3);
  CHECK(e["cameras"][0]["flags"] == json::array({"LOSING"}));
  CHECK(e["cameras"][0]["lost"] == 4);
  CHECK(e["cameras"][2]["flags"] == json::array({"BAD_EMBEDDINGS"}));
  CHECK(e["cameras"][2]["embeddings_dropped"] == 7);
  for (const char* key : {"camera_id",
                          "rate_hz",
                          "last_utime",
                          "last_receive_utime",
                          "received",
                          "late",
                          "dropped",
                          "rejected",
                          "decode_errors",
                          "clock_offset_us",
                          "embeddings_dropped",
                          "queue_depth",
                          "queue_capacity"}) {
    CHECK(e["cameras"][1].contains(key));
  }
}

TEST_CASE("floor: a camera looking down covers the floor around it", "[unit]") {
  geometry::CameraModel cam;
  cam.id = 4;
  cam.width_px = 640;
  cam.height_px = 480;
  cam.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  // Camera at (1, 2, 3) looking straight down: camera z = world -z, camera x = world x.
  cam.cam_from_world.rotation << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  cam.cam_from_world.translation = -(cam.cam_from_world.rotation * Vec3(1, 2, 3));
  const json f = json::parse(FloorJson({cam}));
  REQUIRE(f["cameras"].size() == 1);
  CHECK(f["cameras"][0]["id"] == 4);
  CHECK(f["cameras"][0]["position"][2].get<double>() == Approx(3.0));
  const json& fov = f["cameras"][0]["fov"];
  REQUIRE(fov.size() == 32);
  // The top-left image corner (u, v) = (0, 0) hits the floor at x = 1 - 320/500 * 3.
  CHECK(fov[0][0].get<double>() == Approx(1.0 - 0.64 * 3.0));
  CHECK(fov[0][1].get<double>() == Approx(2.0 + 0.48 * 3.0));
  CHECK(f["bounds"][0].get<double>() == Approx(-1.0));  // the centre with the 2 m margin
  CHECK(json::parse(FloorJson({}))["bounds"].is_null());
}

TEST_CASE("metrics: Prometheus text of the status, per camera, and the web counters", "[unit]") {
  WebCounters w;
  w.tracks_messages = 7;
  w.provisional_messages = 4;
  w.clients_dropped = 1;
  const std::string none = PrometheusText(std::nullopt, 0.0, 5.0, w);
  CHECK_THAT(none, Catch::Contains("mvtrack_web_provisional_messages_total 4\n"));
  CHECK_THAT(none, Catch::Contains("\nmvtrack_up 0\n") || Catch::StartsWith("# HELP mvtrack_up"));
  CHECK_THAT(none, Catch::Contains("mvtrack_web_tracks_messages_total 7\n"));
  CHECK_THAT(none, !Catch::Contains("mvtrack_camera_"));
  transport::TrackerStatus s = Healthy();
  s.cameras[2].flags = 64;
  s.cameras[2].clock_offset_us = 250000;
  s.latency_p99_us = 25000;
  s.gallery_bytes = 2048;
  s.cameras[1].embeddings_dropped = 3;
  const std::string text = PrometheusText(s, 0.5, 5.0, w);
  CHECK_THAT(text, Catch::Contains("mvtrack_up 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_status_age_seconds 0.5\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_health 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_latency_seconds{quantile=\"0.99\"} 0.025\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_camera_received_total{camera=\"1\"} 100\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_camera_clock_offset_seconds{camera=\"2\"} 0.25\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_camera_flag{camera=\"2\",flag=\"CLOCK_OFFSET\"} 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_camera_flag{camera=\"0\",flag=\"CLOCK_OFFSET\"} 0\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_web_clients_dropped_total 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_gallery_bytes 2048\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_camera_embeddings_dropped_total{camera=\"1\"} 3\n"));
  // A status older than the staleness period (the daemon died): down, UNKNOWN, no stale values
  // (issue 39: mvtrack_up stayed 1 and mvtrack_health kept its last value forever).
  const std::string stale = PrometheusText(s, 5.5, 5.0, w);
  CHECK_THAT(stale, Catch::Contains("mvtrack_up 0\n"));
  CHECK_THAT(stale, Catch::Contains("mvtrack_status_age_seconds 5.5\n"));
  CHECK_THAT(stale, Catch::Contains("mvtrack_health 3\n"));
  CHECK_THAT(stale, !Catch::Contains("mvtrack_active_tracks"));
  CHECK_THAT(stale, !Catch::Contains("mvtrack_camera_"));
  CHECK_THAT(stale, Catch::Contains("mvtrack_web_tracks_messages_total 7\n"));
  CHECK_THAT(PrometheusText(s, 5.0, 5.0, w), Catch::Contains("mvtrack_up 1\n"));
  // Every sample line belongs to a family declared with HELP and TYPE before it.
  std::string family;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    if (line.rfind("# TYPE ", 0) == 0) {
      family = line.substr(7, line.find(' ', 7) - 7);
    } else if (line.rfind("#", 0) != 0) {
      INFO(line);
      CHECK(line.rfind(family, 0) == 0);
    }
  }
}

TEST_CASE("a site's stitcher status: event, verdict and metrics per zone", "[unit]") {
  transport::SiteStatus s;
  s.utime = 1'700'000'010'000'000;
  s.instance_id = "00aa11bb22cc33dd";
  s.last_frame = 300;
  s.active_tracks = 9;
  s.wait_p99_us = 2'500;
  transport::ZoneStatus a, b;
  a.name = "zone1";
  a.frames = 300;
  a.latency_us = 170'000;
  a.daemon_health = 0;
  b = a;
  b.name = "zo\"ne2";  // a hostile name is escaped in labels and JSON
  b.flags = 16;        // DEGRADED
  b.daemon_health = 1;
  b.daemon_reasons = "WARNING: camera 4 STALE";
  s.zones = {a, b};
  s.flags = 4;  // ZONE_DEGRADED
  const service::HealthReport h = service::AssessSiteStatus(s);
  CHECK(h.health == service::Health::kWarning);
  CHECK(h.reasons == std::vector<std::string>{"zone zo\"ne2 DEGRADED (WARNING: camera 4 STALE)"});
  const json e = json::parse(SiteStatusEventJson(s));
  CHECK(e["type"] == "site_status");
  CHECK(e["health"] == "WARNING");
  CHECK(e["flags"] == json::array({"ZONE_DEGRADED"}));
  CHECK(e["last_frame"] == 300);
  CHECK(e["zones"][1]["name"] == "zo\"ne2");
  CHECK(e["zones"][1]["daemon_health"] == "WARNING");
  CHECK(e["zones"][1]["daemon_reasons"] == "WARNING: camera 4 STALE");
  CHECK(e["zones"][1]["flags"] == json::array({"DEGRADED"}));
  CHECK(e["zones"][0]["latency_us"] == 170'000);

  const std::string text =
      PrometheusText(std::nullopt, 0.4, 5.0, WebCounters{}, {service::Health::kOk, {}}, s);
  CHECK_THAT(text, Catch::Contains("mvtrack_up 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_health 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_active_tracks 9\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_site_wait_seconds{quantile=\"0.99\"} 0.0025\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_zone_live{zone=\"zone1\"} 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_zone_daemon_health{zone=\"zo\\\"ne2\"} 1\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_zone_flag{zone=\"zo\\\"ne2\",flag=\"DEGRADED\"} 1\n"));
  CHECK_THAT(text, !Catch::Contains("mvtrack_camera_"));
  // Every zone missing: CRITICAL.
  s.zones[0].flags = 2;
  s.zones[1].flags = 1;
  CHECK(service::AssessSiteStatus(s).health == service::Health::kCritical);
  CHECK(service::AssessSiteStatus(s).reasons.at(0) == "0 of 2 zones live");
  // Stale like a tracker's: down, UNKNOWN, no zone values.
  const std::string stale =
      PrometheusText(std::nullopt, 6.0, 5.0, WebCounters{}, {service::Health::kOk, {}}, s);
  CHECK_THAT(stale, Catch::Contains("mvtrack_health 3\n"));
  CHECK_THAT(stale, !Catch::Contains("mvtrack_zone_"));
}

}  // namespace
TEST_CASE("site metrics: counts per region and line, dwell histogram, bounded names", "[unit]") {
  CHECK(SiteMetricsText(std::nullopt, {}).empty());
  transport::SiteCounts counts;
  counts.region_names = {"door \"A\""};
  counts.regions = {{2, 10, 8}};
  counts.line_names = {"gate"};
  counts.lines = {{4, 5}};
  std::map<std::string, DwellHistogram> dwell;
  CHECK(AddDwell(&dwell, "door \"A\"", 0.5));
  CHECK(AddDwell(&dwell, "door \"A\"", 42.0));
  CHECK(AddDwell(&dwell, "x", -1.0));
  CHECK(dwell.at("x").count == 0);  // a negative dwell is not counted
  dwell.erase("x");
  const std::string text = SiteMetricsText(counts, dwell);
  CHECK_THAT(text, Catch::Contains("mvtrack_region_occupancy{region=\"door \\\"A\\\"\"} 2\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_region_entries_total{region=\"door \\\"A\\\"\"} 10\n"));
  CHECK_THAT(text, Catch::Contains("mvtrack_region_exits_total{region=\"door \\\"A\\\"\"} 8\n"));
  CHECK_THAT(text,
             Catch::Contains(
                 "mvtrack_line_crossings_total{line=\"gate\",direction=\"right_to_left\"} 5\n"));
  CHECK_THAT(text,
             Catch::Contains(
                 "mvtrack_region_dwell_seconds_bucket{region=\"door \\\"A\\\"\",le=\"1\"} 1\n"));
  CHECK_THAT(text,
             Catch::Contains(
                 "mvtrack_region_dwell_seconds_bucket{region=\"door \\\"A\\\"\",le=\"60\"} 2\n"));
  CHECK_THAT(text,
             Catch::Contains("mvtrack_region_dwell_seconds_count{region=\"door \\\"A\\\"\"} 2\n"));
  // Hostile names: at most kMaxRegions histograms.
  for (int i = 0; i < analytics::kMaxRegions + 50; ++i)
    AddDwell(&dwell, "r" + std::to_string(i), 1.0);
  CHECK(dwell.size() == static_cast<std::size_t>(analytics::kMaxRegions));
  CHECK_FALSE(AddDwell(&dwell, "one more", 1.0));
}

}  // namespace mvtrack::web
