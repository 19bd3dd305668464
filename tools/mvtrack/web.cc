// mvtrack web: the live floor view, /events, /metrics and /healthz over the daemon's LCM output
// (lib/web; docs/OPERATING.md). This file only parses arguments and handles signals.

#include <signal.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <string>
#include <thread>

#include "config/calibration.h"
#include "config/config_error.h"
#include "config/site.h"
#include "mvtrack/cli.h"
#include "web/web_server.h"

namespace mvtrack::cli {
namespace {

std::atomic<bool> g_stop_requested{false};  // set by the SIGINT/SIGTERM handler

}  // namespace

int RunWeb(int argc, char** argv) {
  Args args;
  args.Option("listen",
              "ADDR:PORT to serve on (localhost by default; PORT 0 = any free port)",
              "127.0.0.1:8080")
      .Option("url", "LCM URL the daemon publishes on", "udpm://239.255.76.67:7667?ttl=0")
      .Option("calibration",
              "the daemon's calibration (mvtrack.calibration/1): draws the cameras "
              "and their fields of view on the floor")
      .Option("regions",
              "the daemon's site file (mvtrack.site/1, its analytics.site): draws the regions "
              "and lines with their live counts")
      .Option("tracks-channel", "channel of the tracks3d_t messages", "MVTRACK_TRACKS")
      .Option("provisional-channel",
              "channel of the provisional layer (tracks3d_t, LAYER_PROVISIONAL); the page shows "
              "it while it arrives, else the final tracks; '' = not subscribed",
              "MVTRACK_TRACKS_NOW")
      .Option("status-channel",
              "channel of the tracker_status_t (or a site stitcher's site_status_t) messages",
              "MVTRACK_STATUS")
      .Option(
          "events-channel", "channel of the analytics_event_t messages", "MVTRACK_ANALYTICS_EVENTS")
      .Option("counts-channel", "channel of the site_counts_t messages", "MVTRACK_SITE_COUNTS")
      .Option("max-clients", "concurrent /events clients (browsers, scripts)", "8")
      .Option("client-queue", "events a client may fall behind before it is disconnected", "256")
      .Option("stale-after", "seconds without a status after which /healthz says 503", "5");
  if (!args.Parse(argc,
                  argv,
                  "mvtrack web [--listen ADDR:PORT] [--url LCM_URL] [--calibration FILE] "
                  "[--regions SITE.yaml]",
                  "Serves a live view of the tracker (OPERATING.md: installed as\n" MVTRACK_DOC_DIR
                  "/OPERATING.md, docs/ in the sources): subscribes to the\n"
                  "daemon's tracks, status and site analytics channels and serves, over HTTP,\n"
                  "  /          a floor view in the browser: tracks with ids and fading trails,\n"
                  "             skeletons from above in pose mode, camera health in words, the\n"
                  "             regions and lines (--regions) with their live counts;\n"
                  "  /events    the same data as Server-Sent Events, one JSON object per tracks,\n"
                  "             status, analytics event and site counts message\n"
                  "             (docs/FORMATS.md \"Live events\");\n"
                  "  /metrics   Prometheus text of the status counters, per camera and totals,\n"
                  "             and of the site's counts (occupancy, entries, exits, crossings,\n"
                  "             dwell);\n"
                  "  /healthz   200 when tracking (OK or WARNING), 503 with the reason when not.\n"
                  "On a site split into zones (SCALING.md) it serves the stitcher's output the\n"
                  "same way: the site's tracks with the zones that see each person, and the\n"
                  "site's status with a row per zone instead of the cameras.\n"
                  "Runs until SIGINT or SIGTERM. The page needs nothing from the internet.")) {
    return 0;
  }
  web::WebOptions o;
  const std::string listen = args.Get("listen");
  const std::size_t colon = listen.rfind(':');
  const std::optional<std::int64_t> port =
      colon == std::string::npos ? std::nullopt : ParseNonNegative(listen.substr(colon + 1));
  if (colon == 0 || !port || *port > 65535) {
    throw UsageError("--listen: expected ADDR:PORT (e.g. 127.0.0.1:8080), got '" + listen + "'");
  }
  o.host = listen.substr(0, colon);
  o.port = static_cast<int>(*port);
  o.lcm_url = args.Get("url");
  o.tracks_channel = args.Get("tracks-channel");
  o.provisional_channel = args.Get("provisional-channel");
  if (!o.provisional_channel.empty() && (o.provisional_channel == o.tracks_channel ||
                                         o.provisional_channel == args.Get("status-channel"))) {
    throw UsageError("--provisional-channel must differ from the tracks and status channels");
  }
  o.status_channel = args.Get("status-channel");
  o.analytics_events_channel = args.Get("events-channel");
  o.site_counts_channel = args.Get("counts-channel");
  const std::int64_t max_clients = args.GetInt("max-clients");
  const std::int64_t queue = args.GetInt("client-queue");
  if (max_clients < 1 || max_clients > 1000)
    throw UsageError("--max-clients: must be in [1, 1000]");
  if (queue < 1 || queue > 1000000) throw UsageError("--client-queue: must be in [1, 1000000]");
  o.max_clients = static_cast<int>(max_clients);
  o.client_queue_events = static_cast<std::size_t>(queue);
  o.stale_after_s = args.GetDouble("stale-after");
  if (!(o.stale_after_s > 0.0)) throw UsageError("--stale-after: must be > 0 seconds");
  if (args.Has("calibration") || args.Has("regions")) {
    try {
      if (args.Has("calibration")) o.cameras = config::LoadCalibration(args.Get("calibration"));
      if (args.Has("regions")) o.site = config::LoadSiteFile(args.Get("regions"));
    } catch (const config::ConfigError& e) {
      std::cerr << "mvtrack web: " << e.what() << "\n";
      return 1;
    }
  }
  // SIGINT/SIGTERM end the server: the handler only sets a flag (libraries may have started
  // threads before this point, so blocking the signals here would not cover them).
  struct sigaction action {};
  action.sa_handler = [](int) { g_stop_requested.store(true); };
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::string why;
  std::unique_ptr<web::WebServer> server = web::WebServer::Create(o, &why);
  if (!server) {
    std::cerr << "mvtrack web: " << why << "\n";
    return 1;
  }
  std::cerr << "mvtrack web: serving http://" << o.host << ":" << server->port() << "/ (tracks "
            << o.tracks_channel << ", status " << o.status_channel << " on " << o.lcm_url << ")"
            << std::endl;
  std::atomic<bool> done{false};
  std::thread waiter([&] {
    while (!done.load() && !g_stop_requested.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    server->Stop();
  });
  const bool ok = server->Run(&why);
  done.store(true);
  waiter.join();
  if (!ok) std::cerr << "mvtrack web: " << why << "\n";
  const web::WebCounters c = server->Counters();
  std::cerr << "mvtrack web: stopped; " << c.tracks_messages << " tracks and " << c.status_messages
            << " status messages received, " << c.decode_errors << " undecodable, " << c.events_sent
            << " events sent, " << c.clients_dropped << " slow clients disconnected" << std::endl;
  return ok ? 0 : 1;
}

}  // namespace mvtrack::cli
