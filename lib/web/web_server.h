#pragma once
/// @file
/// `mvtrack web` (issue 15): a small HTTP server (civetweb) that subscribes to the daemon's
/// tracks, status and site analytics channels over LCM and serves
///   /             the live floor view (page.cc; everything it needs is in the page itself),
///   /events       Server-Sent Events: one JSON object per tracks (final and provisional layer),
///                 status, analytics event and site counts message
///                 (web_json.h; docs/FORMATS.md "Live events"),
///   /metrics      Prometheus text (metrics.h),
///   /healthz      200 when tracking (OK or WARNING, with the reasons), 503 with the reason
///                 when not (no status yet, status older than stale_after_s, CRITICAL),
///   /floor.json   the cameras and their fields of view on the floor (from the calibration),
///   /layouts.json keypoint layouts (joint names and bones) for drawing skeletons,
///   /site.json    the site's regions and lines (from --regions), drawn with their live counts,
///   /status.json, /tracks.json  the latest status and tracks event.
/// Each /events client has a queue bounded in events and bytes: a client that does not keep up is
/// disconnected and counted (clients_dropped); neither LCM nor the other clients ever wait for
/// it. At most max_clients /events clients at once (more get 503).

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "analytics/site_analytics.h"
#include "geometry/camera_model.h"
#include "web/metrics.h"

namespace mvtrack::web {

/// Options of WebServer.
struct WebOptions {
  std::string host = "127.0.0.1";  ///< address to listen on (localhost by default)
  int port = 8080;                 ///< TCP port; 0 = any free port (see WebServer::port)
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";  ///< where the daemon publishes
  std::string tracks_channel = "MVTRACK_TRACKS";
  /// The provisional layer's channel (tracks3d_t with LAYER_PROVISIONAL); "" = not subscribed.
  std::string provisional_channel = "MVTRACK_TRACKS_NOW";
  std::string status_channel = "MVTRACK_STATUS";
  std::string analytics_events_channel = "MVTRACK_ANALYTICS_EVENTS";  ///< analytics_event_t
  std::string site_counts_channel = "MVTRACK_SITE_COUNTS";            ///< site_counts_t
  std::vector<geometry::CameraModel> cameras;  ///< the floor view's cameras (may be empty)
  /// The daemon's site (its regions and lines), which the page draws with their counts; empty:
  /// the counts are still shown, without the drawing.
  analytics::Site site;
  std::size_t client_queue_events = 256;  ///< per-client queue bound, events (>= 1)
  /// Per-client queue bound, bytes of JSON (>= 1): also bounds the server's memory, as the
  /// events are shared between clients.
  std::size_t client_queue_bytes = std::size_t{32} << 20;
  int max_clients = 8;         ///< concurrent /events clients (>= 1)
  double stale_after_s = 5.0;  ///< /healthz: a status older than this is 503
};

class WebServer {
 public:
  /// Binds the port and creates the LCM subscription. nullptr and `why` on failure (port in
  /// use, bad LCM URL, invalid options).
  static std::unique_ptr<WebServer> Create(WebOptions options, std::string* why);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  /// The bound port.
  int port() const;
  /// Serves until Stop(): HTTP on its own threads, LCM on the calling thread. Returns false
  /// with `why` when LCM fails.
  bool Run(std::string* why);
  /// Thread-safe (also from a signal-handling thread): makes Run() return.
  void Stop();
  /// A snapshot of the counters.
  WebCounters Counters() const;

  class Impl;

 private:
  explicit WebServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// The page served at / (HTML with its script and style inline).
const std::string& IndexPage();

}  // namespace mvtrack::web
