#include "web/web_server.h"

// cpp-httplib (header-only, compiled in this translation unit only) listens with a backlog of 5
// by default: a burst of connections beyond the pool was refused by the kernel (issue 39).
#define CPPHTTPLIB_LISTEN_BACKLOG 128
#include <httplib.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "core/keypoint_layout.h"
#include "json/document.h"
#include "service/status_check.h"
#include "transport/codec.h"
#include "web/web_json.h"

namespace mvtrack::web {
namespace {

using SteadyClock = std::chrono::steady_clock;

// The /events fan-out: one bounded queue per client; Publish never blocks.
class EventHub {
 public:
  struct Client {
    std::deque<std::shared_ptr<const std::string>> queue;
    std::size_t queued_bytes = 0;
    bool dropped = false;
  };

  // At most `capacity` events and `max_bytes` of them per client (events are shared between
  // clients, so this also bounds the hub's memory: a hostile 4 MiB tracks message makes a
  // large event).
  EventHub(std::size_t capacity, std::size_t max_bytes)
      : capacity_(capacity), max_bytes_(max_bytes) {}

  // A new client, or nullptr when `max_clients` are connected. It first gets the latest status
  // and tracks events, so a page shows something at once.
  std::shared_ptr<Client> Connect(int max_clients) {
    std::lock_guard<std::mutex> lock(mu_);
    if (closed_ || static_cast<int>(clients_.size()) >= max_clients) return nullptr;
    auto c = std::make_shared<Client>();
    for (const auto& e : {last_status_, last_tracks_}) {
      if (!e) continue;
      c->queue.push_back(e);
      c->queued_bytes += e->size();
    }
    clients_.push_back(c);
    return c;
  }

  void Disconnect(const std::shared_ptr<Client>& c) {
    std::lock_guard<std::mutex> lock(mu_);
    clients_.erase(std::remove(clients_.begin(), clients_.end(), c), clients_.end());
  }

  void Publish(std::string event, bool is_status) {
    auto e = std::make_shared<const std::string>(std::move(event));
    {
      std::lock_guard<std::mutex> lock(mu_);
      (is_status ? last_status_ : last_tracks_) = e;
      for (const std::shared_ptr<Client>& c : clients_) {
        if (c->dropped) continue;
        if (c->queue.size() >= capacity_ || c->queued_bytes + e->size() > max_bytes_) {
          c->dropped = true;  // it does not keep up: disconnect it, never wait for it
          c->queue.clear();
          c->queued_bytes = 0;
          ++dropped_;
          continue;
        }
        c->queue.push_back(e);
        c->queued_bytes += e->size();
      }
    }
    cv_.notify_all();
  }

  // The next event for `c`: the event, nullptr after `timeout` without one (send a keep-alive),
  // or false when the client must be disconnected (dropped, or the hub closed).
  bool Next(const std::shared_ptr<Client>& c,
            std::chrono::milliseconds timeout,
            std::shared_ptr<const std::string>* event) {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait_for(lock, timeout, [&] { return closed_ || c->dropped || !c->queue.empty(); });
    if (closed_ || c->dropped) return false;
    *event = nullptr;
    if (!c->queue.empty()) {
      *event = c->queue.front();
      c->queue.pop_front();
      c->queued_bytes -= (*event)->size();
    }
    return true;
  }

  void Close() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      closed_ = true;
    }
    cv_.notify_all();
  }

  std::int64_t clients() const {
    std::lock_guard<std::mutex> lock(mu_);
    return static_cast<std::int64_t>(clients_.size());
  }
  std::int64_t dropped() const {
    std::lock_guard<std::mutex> lock(mu_);
    return dropped_;
  }
  std::shared_ptr<const std::string> last(bool status) const {
    std::lock_guard<std::mutex> lock(mu_);
    return status ? last_status_ : last_tracks_;
  }

 private:
  const std::size_t capacity_;
  const std::size_t max_bytes_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::vector<std::shared_ptr<Client>> clients_;
  std::shared_ptr<const std::string> last_status_;
  std::shared_ptr<const std::string> last_tracks_;
  std::int64_t dropped_ = 0;
  bool closed_ = false;
};

std::string LayoutsJson() {
  json::Document o = json::Document::object();
  for (const core::KeypointLayoutId id : core::AllKeypointLayouts()) {
    const core::KeypointLayout& l = core::GetKeypointLayout(id);
    json::Document bones = json::Document::array();
    for (const auto& [a, b] : l.bones) bones.push_back({a, b});
    o[l.name] = {{"joints", l.joints}, {"bones", std::move(bones)}};
  }
  return json::Dump(o);
}

}  // namespace

class WebServer::Impl {
 public:
  explicit Impl(WebOptions options)
      : options_(std::move(options)),
        hub_(options_.client_queue_events, options_.client_queue_bytes),
        floor_json_(FloorJson(options_.cameras, options_.stale_after_s)),
        layouts_json_(LayoutsJson()) {}

  bool Init(std::string* why) {
    lcm_ = std::make_unique<lcm::LCM>(options_.lcm_url);
    if (!lcm_->good()) {
      *why = "cannot open LCM " + options_.lcm_url;
      return false;
    }
    if (lcm_->subscribeFunction(options_.tracks_channel, &Impl::OnTracks, this) == nullptr ||
        lcm_->subscribeFunction(options_.status_channel, &Impl::OnStatus, this) == nullptr) {
      *why = "cannot subscribe to " + options_.tracks_channel + " and " + options_.status_channel;
      return false;
    }
    Routes();
    const int threads = options_.max_clients + 4;  // /events clients plus the short requests
    server_.new_task_queue = [threads] {
      return new httplib::ThreadPool(static_cast<size_t>(threads));
    };
    server_.set_write_timeout(10, 0);  // a stuck client is dropped by its queue first
    // Only GET exists: a request that announces a body is answered 413 without reading it (a
    // 200 MB POST took the process from 12 to 506 MB before, issue 39).
    server_.set_payload_max_length(0);
    // A client's unread data in the kernel stays small (accepted sockets inherit the listening
    // socket's send buffer), so a client that stops reading soon fills its own queue and is
    // disconnected instead of pinning megabytes of socket buffer.
    server_.set_socket_options([](socket_t sock) {
      int yes = 1;
      setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
      int send_buffer = 128 * 1024;
      setsockopt(sock, SOL_SOCKET, SO_SNDBUF, &send_buffer, sizeof(send_buffer));
    });
    if (options_.port == 0) {
      port_ = server_.bind_to_any_port(options_.host);
      if (port_ < 0) port_ = 0;
    } else if (server_.bind_to_port(options_.host, options_.port)) {
      port_ = options_.port;
    }
    if (port_ <= 0) {
      *why = "cannot listen on " + options_.host + ":" + std::to_string(options_.port) +
             " (address in use, or not an address of this host)";
      return false;
    }
    return true;
  }

  int port() const { return port_; }

  bool Run(std::string* why) {
    std::thread http([this] { server_.listen_after_bind(); });
    bool ok = true;
    while (!stop_.load()) {
      errno = 0;
      const int r = lcm_->handleTimeout(100);
      if (r < 0 && errno == EINTR) continue;  // a signal (e.g. the SIGTERM that stops us)
      if (r < 0) {
        *why = "LCM receive failed on " + options_.lcm_url;
        ok = false;
        break;
      }
    }
    hub_.Close();
    server_.stop();
    http.join();
    return ok;
  }

  void Stop() { stop_.store(true); }

  WebCounters Counters() const {
    WebCounters c;
    {
      std::lock_guard<std::mutex> lock(mu_);
      c = counters_;
    }
    c.clients = hub_.clients();
    c.clients_dropped = hub_.dropped();
    c.events_sent = events_sent_.load();
    return c;
  }

 private:
  static void OnTracks(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::TracksDecodeResult d = transport::DecodeTracks(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      ++(d.ok() ? self->counters_.tracks_messages : self->counters_.decode_errors);
    }
    if (d.ok()) self->hub_.Publish(TracksEventJson(d.message), false);
  }

  static void OnStatus(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::StatusDecodeResult d =
        transport::DecodeTrackerStatus(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      if (!d.ok()) {
        ++self->counters_.decode_errors;
        return;
      }
      ++self->counters_.status_messages;
      self->status_ = d.message;
      self->status_at_ = SteadyClock::now();
    }
    self->hub_.Publish(StatusEventJson(d.message), true);
  }

  // The latest status and its age, seconds.
  std::optional<std::pair<transport::TrackerStatus, double>> LatestStatus() const {
    std::lock_guard<std::mutex> lock(mu_);
    if (!status_) return std::nullopt;
    const double age = std::chrono::duration<double>(SteadyClock::now() - status_at_).count();
    return std::make_pair(*status_, age);
  }

  void Routes() {
    server_.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(IndexPage(), "text/html; charset=utf-8");
    });
    server_.Get("/floor.json", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(floor_json_, "application/json");
    });
    server_.Get("/layouts.json", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(layouts_json_, "application/json");
    });
    auto latest = [this](bool status) {
      return [this, status](const httplib::Request&, httplib::Response& res) {
        const std::shared_ptr<const std::string> e = hub_.last(status);
        if (!e) {
          res.status = 404;
          res.set_content(
              std::string("no ") + (status ? "status" : "tracks") + " message received yet\n",
              "text/plain");
          return;
        }
        res.set_content(*e, "application/json");
      };
    };
    server_.Get("/status.json", latest(true));
    server_.Get("/tracks.json", latest(false));
    server_.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
      const auto s = LatestStatus();
      res.set_content(PrometheusText(s ? std::optional(s->first) : std::nullopt,
                                     s ? s->second : 0.0,
                                     options_.stale_after_s,
                                     Counters()),
                      "text/plain; version=0.0.4");
    });
    server_.Get("/healthz", [this](const httplib::Request&, httplib::Response& res) {
      const auto s = LatestStatus();
      if (!s) {
        res.status = 503;
        res.set_content("UNKNOWN: no status message received yet on " + options_.status_channel +
                            " (" + options_.lcm_url + ")\n",
                        "text/plain");
        return;
      }
      if (s->second > options_.stale_after_s) {
        res.status = 503;
        res.set_content("UNKNOWN: the latest status is " + std::to_string(s->second) +
                            " s old (the tracker stopped publishing)\n",
                        "text/plain");
        return;
      }
      const service::HealthReport h = service::AssessStatus(s->first);
      res.status = h.health == service::Health::kCritical ? 503 : 200;
      res.set_content(service::HealthLine(h) + "\n", "text/plain");
    });
    server_.Get("/events", [this](const httplib::Request&, httplib::Response& res) {
      std::shared_ptr<EventHub::Client> client = hub_.Connect(options_.max_clients);
      if (!client) {
        res.status = 503;
        res.set_content(
            "too many /events clients (max_clients " + std::to_string(options_.max_clients) + ")\n",
            "text/plain");
        return;
      }
      res.set_header("Cache-Control", "no-cache");
      res.set_chunked_content_provider(
          "text/event-stream",
          [this, client, first = true](std::size_t, httplib::DataSink& sink) mutable {
            if (first) {  // reconnect after 1 s when the stream breaks (EventSource's retry)
              first = false;
              constexpr char kRetry[] = "retry: 1000\n\n";
              return sink.write(kRetry, sizeof(kRetry) - 1);
            }
            std::shared_ptr<const std::string> e;
            if (!hub_.Next(client, std::chrono::milliseconds(1000), &e)) return false;
            const std::string chunk = e ? "data: " + *e + "\n\n" : ": keep-alive\n\n";
            if (!sink.write(chunk.data(), chunk.size())) return false;
            if (e) events_sent_.fetch_add(1);
            return true;
          },
          [this, client](bool) { hub_.Disconnect(client); });
    });
  }

  WebOptions options_;
  EventHub hub_;
  const std::string floor_json_;
  const std::string layouts_json_;
  std::unique_ptr<lcm::LCM> lcm_;
  httplib::Server server_;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> events_sent_{0};
  mutable std::mutex mu_;
  WebCounters counters_;
  std::optional<transport::TrackerStatus> status_;
  SteadyClock::time_point status_at_;
};

WebServer::WebServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
WebServer::~WebServer() = default;

std::unique_ptr<WebServer> WebServer::Create(WebOptions options, std::string* why) {
  std::string reason;
  if (options.client_queue_events < 1 || options.client_queue_bytes < 1 ||
      options.max_clients < 1 || options.port < 0 || options.port > 65535 ||
      !(options.stale_after_s > 0.0)) {
    if (why != nullptr) *why = "invalid web options";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>(std::move(options));
  if (!impl->Init(&reason)) {
    if (why != nullptr) *why = reason;
    return nullptr;
  }
  return std::unique_ptr<WebServer>(new WebServer(std::move(impl)));
}

int WebServer::port() const { return impl_->port(); }
bool WebServer::Run(std::string* why) {
  std::string reason;
  const bool ok = impl_->Run(&reason);
  if (!ok && why != nullptr) *why = reason;
  return ok;
}
void WebServer::Stop() { impl_->Stop(); }
WebCounters WebServer::Counters() const { return impl_->Counters(); }

}  // namespace mvtrack::web
