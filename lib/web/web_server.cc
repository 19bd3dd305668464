#include "web/web_server.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netdb.h>
#include <sys/socket.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <filesystem>
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

// civetweb 1.15 as Debian builds it (without REENTRANT_TIME) formats the Date header of every
// response with gmtime(), whose result is one static buffer per process: two of its threads
// answering at once race on it (ThreadSanitizer reports it, and a Date header can come out
// mixed). This definition in the program takes the C library's place for civetweb (the dynamic
// linker binds its call to the program's symbol first): the same conversion into a buffer per
// thread, which POSIX allows.
// (The buffer's TLS model is the executable's own: the library is compiled position-independent,
// whose default model would make the program need the dynamic loader's __tls_get_addr.)
extern "C" struct tm* gmtime(const time_t* t) noexcept {
  [[gnu::tls_model("initial-exec")]] thread_local struct tm result;
  return gmtime_r(t, &result);
}

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

  // Which latest event of a kind a new client gets first (kNone: not kept).
  enum class Retain { kStatus, kTracks, kCounts, kNone };

  // A new client, or nullptr when `max_clients` are connected. It first gets the latest status,
  // tracks and site counts events, so a page shows something at once.
  std::shared_ptr<Client> Connect(int max_clients) {
    std::lock_guard<std::mutex> lock(mu_);
    if (closed_ || static_cast<int>(clients_.size()) >= max_clients) return nullptr;
    auto c = std::make_shared<Client>();
    for (const auto& e : {last_status_, last_tracks_, last_counts_}) {
      if (!e) continue;
      c->queue.push_back(e);
      c->queued_bytes += e->size();
    }
    clients_.push_back(c);
    return c;
  }

  // `c` stopped reading (a write to it timed out): counted as dropped like a full queue.
  void Dropped(const std::shared_ptr<Client>& c) {
    std::lock_guard<std::mutex> lock(mu_);
    if (c->dropped) return;
    c->dropped = true;
    ++dropped_;
  }

  void Disconnect(const std::shared_ptr<Client>& c) {
    std::lock_guard<std::mutex> lock(mu_);
    clients_.erase(std::remove(clients_.begin(), clients_.end(), c), clients_.end());
  }

  void Publish(std::string event, Retain retain) {
    auto e = std::make_shared<const std::string>(std::move(event));
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (retain == Retain::kStatus) last_status_ = e;
      if (retain == Retain::kTracks) last_tracks_ = e;
      if (retain == Retain::kCounts) last_counts_ = e;
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
  std::shared_ptr<const std::string> last_counts_;
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

// HTTP server limits (issue 39, docs/DECISIONS.md "mvtrack web's HTTP server"). civetweb serves
// each connection on one of a fixed pool of threads; a request must arrive whole, headers
// included, within kRequestDeadlineMs of its first byte (a whole-request deadline, not a timeout
// between bytes that a slow sender resets byte by byte), and within kMaxRequestBytes.
constexpr int kShortRequestThreads = 64;  // threads beyond the /events clients' ones
constexpr int kRequestDeadlineMs = 2000;  // also the longest a write may block
constexpr int kMaxRequestBytes = 8192;    // request line and headers
constexpr int kListenBacklog = 1024;

// civetweb listens on numeric addresses only: "ADDR:PORT" or "[ADDR6]:PORT" for `host`, which
// may also be a name (localhost). IPv4 first. std::nullopt when the name does not resolve.
std::optional<std::string> ListeningPort(const std::string& host, int port) {
  for (const int family : {AF_INET, AF_UNSPEC}) {
    addrinfo hints{};
    hints.ai_family = family;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    addrinfo* found = nullptr;
    if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) continue;
    char text[INET6_ADDRSTRLEN] = {};
    std::string address;
    if (found->ai_family == AF_INET &&
        inet_ntop(AF_INET,
                  &reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr,
                  text,
                  sizeof(text)) != nullptr) {
      address = text;
    } else if (found->ai_family == AF_INET6 &&
               inet_ntop(AF_INET6,
                         &reinterpret_cast<const sockaddr_in6*>(found->ai_addr)->sin6_addr,
                         text,
                         sizeof(text)) != nullptr) {
      address = "[" + std::string(text) + "]";
    }
    freeaddrinfo(found);
    if (!address.empty()) return address + ":" + std::to_string(port);
  }
  return std::nullopt;
}

// The listening socket of `port` in this process, -1 if none: civetweb does not hand it out, and
// its send buffer size is what the accepted sockets inherit.
int FindListeningSocket(int port) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", error)) {
    const std::string name = entry.path().filename().string();
    int fd = -1;
    if (std::from_chars(name.data(), name.data() + name.size(), fd).ec != std::errc()) continue;
    int listening = 0;
    socklen_t length = sizeof(listening);
    if (getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &length) != 0 || listening == 0) {
      continue;
    }
    sockaddr_storage address{};
    socklen_t address_length = sizeof(address);
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&address), &address_length) != 0) continue;
    int bound = -1;
    if (address.ss_family == AF_INET) {
      bound = ntohs(reinterpret_cast<const sockaddr_in*>(&address)->sin_port);
    } else if (address.ss_family == AF_INET6) {
      bound = ntohs(reinterpret_cast<const sockaddr_in6*>(&address)->sin6_port);
    }
    if (bound == port) return fd;
  }
  return -1;
}

// A whole response with a body (or its headers only, for HEAD).
void Reply(mg_connection* conn,
           int status,
           const std::string& content_type,
           const std::string& body,
           bool head) {
  mg_response_header_start(conn, status);
  mg_response_header_add(conn, "Content-Type", content_type.c_str(), -1);
  mg_response_header_add(conn, "Content-Length", std::to_string(body.size()).c_str(), -1);
  mg_response_header_add(conn, "Cache-Control", "no-cache", -1);
  mg_response_header_send(conn);
  if (!head && !body.empty()) mg_write(conn, body.data(), body.size());
}

}  // namespace

class WebServer::Impl {
 public:
  explicit Impl(WebOptions options)
      : options_(std::move(options)),
        hub_(options_.client_queue_events, options_.client_queue_bytes),
        floor_json_(FloorJson(options_.cameras, options_.stale_after_s)),
        site_json_(SiteJson(options_.site)),
        layouts_json_(LayoutsJson()) {}

  ~Impl() { StopHttp(); }

  bool Init(std::string* why) {
    lcm_ = std::make_unique<lcm::LCM>(options_.lcm_url);
    if (!lcm_->good()) {
      *why = "cannot open LCM " + options_.lcm_url;
      return false;
    }
    if ((!options_.provisional_channel.empty() &&
         lcm_->subscribeFunction(options_.provisional_channel, &Impl::OnProvisional, this) ==
             nullptr) ||
        lcm_->subscribeFunction(options_.tracks_channel, &Impl::OnTracks, this) == nullptr ||
        lcm_->subscribeFunction(options_.status_channel, &Impl::OnStatus, this) == nullptr ||
        lcm_->subscribeFunction(options_.analytics_events_channel, &Impl::OnAnalyticsEvent, this) ==
            nullptr ||
        lcm_->subscribeFunction(options_.site_counts_channel, &Impl::OnSiteCounts, this) ==
            nullptr) {
      *why = "cannot subscribe to " + options_.tracks_channel + ", " + options_.status_channel +
             ", " + options_.analytics_events_channel + " and " + options_.site_counts_channel;
      return false;
    }
    const std::optional<std::string> listening = ListeningPort(options_.host, options_.port);
    if (!listening) {
      *why = "cannot listen on " + options_.host + ":" + std::to_string(options_.port) +
             " (not an address or a name of this host)";
      return false;
    }
    const std::string threads = std::to_string(options_.max_clients + kShortRequestThreads);
    const std::string deadline = std::to_string(kRequestDeadlineMs);
    const std::string max_request = std::to_string(kMaxRequestBytes);
    const std::string backlog = std::to_string(kListenBacklog);
    const char* config[] = {"listening_ports",
                            listening->c_str(),
                            "num_threads",
                            threads.c_str(),
                            "request_timeout_ms",
                            deadline.c_str(),
                            "max_request_size",
                            max_request.c_str(),
                            "listen_backlog",
                            backlog.c_str(),
                            "enable_keep_alive",
                            "no",
                            nullptr};
    mg_callbacks callbacks{};
    callbacks.begin_request = &Impl::OnRequest;  // every request: nothing is served from files
    mg_init_data init{};
    init.callbacks = &callbacks;
    init.user_data = this;
    init.configuration_options = config;
    char error_text[256] = {};
    unsigned error_code = 0;
    mg_error_data error{};
    error.code = &error_code;
    error.text = error_text;
    error.text_buffer_size = sizeof(error_text);
    mg_init_library(0);
    library_initialized_ = true;
    http_ = mg_start2(&init, &error);
    if (http_ == nullptr) {
      *why = "cannot listen on " + *listening + " (" +
             (error_text[0] != '\0' ? std::string(error_text) : "address in use?") + ")";
      return false;
    }
    mg_server_port ports[1] = {};
    if (mg_get_server_ports(http_, 1, ports) < 1 || ports[0].port <= 0) {
      *why = "cannot find the port listened on";
      return false;
    }
    port_ = ports[0].port;
    // A client's unread data in the kernel stays small, so a client that stops reading soon
    // blocks its writes and is disconnected (counted as dropped) instead of pinning megabytes
    // of socket buffer (Linux's accepted sockets inherit the listening socket's send buffer).
    const int listener = FindListeningSocket(port_);
    const int send_buffer = 128 * 1024;
    if (listener < 0 ||
        setsockopt(listener, SOL_SOCKET, SO_SNDBUF, &send_buffer, sizeof(send_buffer)) != 0) {
      *why = "cannot size the send buffer of port " + std::to_string(port_);
      return false;
    }
    return true;
  }

  int port() const { return port_; }

  bool Run(std::string* why) {
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
    StopHttp();
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
  // Ends the /events streams (their threads return), then stops civetweb (joins its threads).
  void StopHttp() {
    hub_.Close();
    if (http_ != nullptr) {
      mg_stop(http_);
      http_ = nullptr;
    }
    if (library_initialized_) {
      mg_exit_library();
      library_initialized_ = false;
    }
  }

  static void OnTracks(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::TracksDecodeResult d = transport::DecodeTracks(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      ++(d.ok() ? self->counters_.tracks_messages : self->counters_.decode_errors);
    }
    if (d.ok()) self->hub_.Publish(TracksEventJson(d.message), EventHub::Retain::kTracks);
  }

  // The provisional layer: passed on as it comes, not retained (the next frame replaces it).
  static void OnProvisional(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::TracksDecodeResult d = transport::DecodeTracks(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      ++(d.ok() ? self->counters_.tracks_messages : self->counters_.decode_errors);
      if (d.ok()) ++self->counters_.provisional_messages;
    }
    if (d.ok()) self->hub_.Publish(TracksEventJson(d.message), EventHub::Retain::kNone);
  }

  static void OnAnalyticsEvent(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::AnalyticsEventDecodeResult d =
        transport::DecodeAnalyticsEvent(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      if (!d.ok()) {
        ++self->counters_.decode_errors;
        return;
      }
      ++self->counters_.analytics_events;
      if (d.message.kind == analytics::Event::Kind::kExit) {
        AddDwell(&self->dwell_,
                 d.message.name,
                 static_cast<double>(d.message.utime - d.message.enter_utime) * 1e-6);
      }
    }
    self->hub_.Publish(AnalyticsEventJson(d.message), EventHub::Retain::kNone);
  }

  static void OnSiteCounts(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::SiteCountsDecodeResult d =
        transport::DecodeSiteCounts(rbuf->data, rbuf->data_size);
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      if (!d.ok()) {
        ++self->counters_.decode_errors;
        return;
      }
      ++self->counters_.site_counts_messages;
      self->counts_ = d.message;
    }
    self->hub_.Publish(SiteCountsEventJson(d.message), EventHub::Retain::kCounts);
  }

  // A tracker's status, or a site stitcher's (issue 43) on the same channel.
  static void OnStatus(const lcm::ReceiveBuffer* rbuf, const std::string&, Impl* self) {
    const transport::StatusDecodeResult d =
        transport::DecodeTrackerStatus(rbuf->data, rbuf->data_size);
    std::optional<transport::SiteStatusDecodeResult> site;
    if (d.status == transport::DecodeStatus::kBadFingerprint) {
      site = transport::DecodeSiteStatus(rbuf->data, rbuf->data_size);
    }
    service::HealthReport source;
    {
      std::lock_guard<std::mutex> lock(self->mu_);
      if (!d.ok() && !(site && site->ok())) {
        ++self->counters_.decode_errors;
        return;
      }
      ++self->counters_.status_messages;
      self->status_at_ = SteadyClock::now();
      if (d.ok()) {
        self->status_ = d.message;
        self->site_status_.reset();
        self->source_.Add(d.message, Seconds(self->status_at_));
      } else {
        self->site_status_ = site->message;
        self->status_.reset();
        self->source_.Add({site->message.instance_id, site->message.sequence},
                          Seconds(self->status_at_));
      }
      source = self->source_.Assess(Seconds(self->status_at_));
    }
    self->hub_.Publish(
        d.ok() ? StatusEventJson(d.message, source) : SiteStatusEventJson(site->message, source),
        EventHub::Retain::kStatus);
  }

  static double Seconds(SteadyClock::time_point t) {
    return std::chrono::duration<double>(t.time_since_epoch()).count();
  }

  // The latest status, its age (seconds) and what the statuses say about who sends them.
  struct Latest {
    std::optional<transport::TrackerStatus> status;  // a tracker's, or
    std::optional<transport::SiteStatus> site;       // a site stitcher's
    double age_s = 0.0;
    service::HealthReport source;
    // The status's verdict combined with what the statuses say about their senders.
    service::HealthReport Assess() const {
      return service::Combine(
          status ? service::AssessStatus(*status) : service::AssessSiteStatus(*site), source);
    }
  };
  std::optional<Latest> LatestStatus() const {
    std::lock_guard<std::mutex> lock(mu_);
    if (!status_ && !site_status_) return std::nullopt;
    const SteadyClock::time_point now = SteadyClock::now();
    return Latest{status_,
                  site_status_,
                  std::chrono::duration<double>(now - status_at_).count(),
                  source_.Assess(Seconds(now))};
  }

  // civetweb's begin_request: every request, on one of its threads. Returns the status sent.
  static int OnRequest(mg_connection* conn) {
    const mg_request_info* request = mg_get_request_info(conn);
    Impl* self = static_cast<Impl*>(request->user_data);
    const std::string method = request->request_method != nullptr ? request->request_method : "";
    const std::string path = request->local_uri != nullptr ? request->local_uri : "";
    const bool head = method == "HEAD";
    // Only GET exists: a request that announces a body is answered 413 without reading it (a
    // 200 MB POST took the process from 12 to 506 MB before, issue 39).
    if (request->content_length > 0 || mg_get_header(conn, "Transfer-Encoding") != nullptr) {
      Reply(conn, 413, "text/plain", "a request body is not accepted\n", head);
      return 413;
    }
    if (method != "GET" && !head) {
      Reply(conn, 405, "text/plain", "only GET exists\n", false);
      return 405;
    }
    return self->Serve(conn, path, head);
  }

  int Serve(mg_connection* conn, const std::string& path, bool head) {
    if (path == "/") return Ok(conn, IndexPage(), "text/html; charset=utf-8", head);
    if (path == "/floor.json") return Ok(conn, floor_json_, "application/json", head);
    if (path == "/layouts.json") return Ok(conn, layouts_json_, "application/json", head);
    if (path == "/site.json") return Ok(conn, site_json_, "application/json", head);
    if (path == "/status.json" || path == "/tracks.json") {
      const bool status = path == "/status.json";
      const std::shared_ptr<const std::string> e = hub_.last(status);
      if (!e) {
        Reply(conn,
              404,
              "text/plain",
              std::string("no ") + (status ? "status" : "tracks") + " message received yet\n",
              head);
        return 404;
      }
      return Ok(conn, *e, "application/json", head);
    }
    if (path == "/metrics") {
      const auto s = LatestStatus();
      std::string site;
      {
        std::lock_guard<std::mutex> lock(mu_);
        site = SiteMetricsText(counts_, dwell_);
      }
      return Ok(conn,
                PrometheusText(s ? s->status : std::nullopt,
                               s ? s->age_s : 0.0,
                               options_.stale_after_s,
                               Counters(),
                               s ? s->source : service::HealthReport{service::Health::kOk, {}},
                               s ? s->site : std::nullopt) +
                    site,
                "text/plain; version=0.0.4",
                head);
    }
    if (path == "/healthz") return Health(conn, head);
    if (path == "/events" && !head) return Events(conn);
    Reply(conn, 404, "text/plain", "not found: " + path + "\n", head);
    return 404;
  }

  static int Ok(mg_connection* conn, const std::string& body, const char* type, bool head) {
    Reply(conn, 200, type, body, head);
    return 200;
  }

  int Health(mg_connection* conn, bool head) {
    const auto s = LatestStatus();
    int status = 503;
    std::string text;
    if (!s) {
      text = "UNKNOWN: no status message received yet on " + options_.status_channel + " (" +
             options_.lcm_url + ")\n";
    } else if (s->age_s > options_.stale_after_s) {
      text = "UNKNOWN: the latest status is " + std::to_string(s->age_s) +
             " s old (the tracker stopped publishing)\n";
    } else {
      const service::HealthReport h = s->Assess();
      status = h.health == service::Health::kCritical ? 503 : 200;
      text = service::HealthLine(h) + "\n";
    }
    Reply(conn, status, "text/plain", text, head);
    return status;
  }

  // Server-Sent Events until the client goes, is dropped by its queue, or the server stops.
  int Events(mg_connection* conn) {
    const std::shared_ptr<EventHub::Client> client = hub_.Connect(options_.max_clients);
    if (!client) {
      Reply(conn,
            503,
            "text/plain",
            "too many /events clients (max_clients " + std::to_string(options_.max_clients) + ")\n",
            false);
      return 503;
    }
    mg_response_header_start(conn, 200);
    mg_response_header_add(conn, "Content-Type", "text/event-stream", -1);
    mg_response_header_add(conn, "Cache-Control", "no-cache", -1);
    mg_response_header_send(conn);
    // Reconnect after 1 s when the stream breaks (EventSource's retry).
    constexpr char kRetry[] = "retry: 1000\n\n";
    bool open = mg_write(conn, kRetry, sizeof(kRetry) - 1) > 0;
    while (open) {
      std::shared_ptr<const std::string> e;
      if (!hub_.Next(client, std::chrono::milliseconds(1000), &e)) break;
      const std::string chunk = e ? "data: " + *e + "\n\n" : ": keep-alive\n\n";
      const SteadyClock::time_point start = SteadyClock::now();
      open = mg_write(conn, chunk.data(), chunk.size()) == static_cast<int>(chunk.size());
      if (open && e) events_sent_.fetch_add(1);
      // A write that failed after blocking for the whole deadline: the client stopped reading
      // (its socket buffers are full), not a client that went away.
      if (!open && SteadyClock::now() - start >= std::chrono::milliseconds(kRequestDeadlineMs)) {
        hub_.Dropped(client);
      }
    }
    hub_.Disconnect(client);
    return 200;
  }

  WebOptions options_;
  EventHub hub_;
  const std::string floor_json_;
  const std::string site_json_;
  const std::string layouts_json_;
  std::unique_ptr<lcm::LCM> lcm_;
  mg_context* http_ = nullptr;
  bool library_initialized_ = false;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<std::int64_t> events_sent_{0};
  mutable std::mutex mu_;
  WebCounters counters_;
  std::optional<transport::SiteCounts> counts_;       // the latest site_counts_t
  std::map<std::string, DwellHistogram> dwell_;       // by region: the visits ended (exit events)
  std::optional<transport::TrackerStatus> status_;    // the latest status: a tracker's,
  std::optional<transport::SiteStatus> site_status_;  // or a site stitcher's
  SteadyClock::time_point status_at_;
  service::StatusSourceWatch source_{options_.stale_after_s};
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
