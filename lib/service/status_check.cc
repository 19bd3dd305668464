#include "service/status_check.h"

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>

namespace mvtrack::service {

std::string RandomInstanceId() {
  std::random_device entropy;
  const std::uint64_t value = (static_cast<std::uint64_t>(entropy()) << 32) ^ entropy();
  constexpr char kHex[] = "0123456789abcdef";
  std::string id(16, '0');
  for (int i = 0; i < 16; ++i)
    id[static_cast<std::size_t>(i)] = kHex[(value >> (60 - 4 * i)) & 0xF];
  return id;
}

namespace {

constexpr std::int64_t kCameraNoData = 1, kCameraStale = 2, kCameraClockOffset = 64;
constexpr std::int64_t kTrackerBacklog = 4, kTrackerJobFailures = 16, kTrackerNoOutput = 32;

std::string Join(const std::vector<std::string>& words, const char* sep) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : sep) + w;
  return out;
}

// An instance id from the network, for a reason: at most 32 printable characters.
std::string Printable(const std::string& id) {
  if (id.empty()) return "(none)";
  std::string out = id.substr(0, 32);
  for (char& c : out) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return id.size() > out.size() ? out + "..." : out;
}

bool Delivers(const transport::CameraStatus& c) {
  return c.received > 0 && (c.flags & (kCameraNoData | kCameraStale | kCameraClockOffset)) == 0;
}

// CRITICAL with reasons `critical`, else WARNING with `warning`, else OK; reasons worst first.
HealthReport Verdict(const std::vector<std::string>& critical,
                     const std::vector<std::string>& warning) {
  HealthReport r;
  r.health = !critical.empty()  ? Health::kCritical
             : !warning.empty() ? Health::kWarning
                                : Health::kOk;
  r.reasons = critical;
  r.reasons.insert(r.reasons.end(), warning.begin(), warning.end());
  return r;
}

}  // namespace

const char* ToString(Health health) {
  switch (health) {
    case Health::kOk:
      return "OK";
    case Health::kWarning:
      return "WARNING";
    case Health::kCritical:
      return "CRITICAL";
    case Health::kUnknown:
      return "UNKNOWN";
  }
  return "UNKNOWN";
}

int CamerasDelivering(const transport::TrackerStatus& status) {
  int n = 0;
  for (const transport::CameraStatus& c : status.cameras) n += Delivers(c) ? 1 : 0;
  return n;
}

double FramesPerSecond(const transport::TrackerStatus& status) {
  if (status.period_us <= 0) return 0.0;
  return static_cast<double>(status.num_latency_samples) * 1e6 /
         static_cast<double>(status.period_us);
}

HealthReport AssessStatus(const transport::TrackerStatus& status) {
  std::vector<std::string> critical;
  std::vector<std::string> warning;
  const int delivering = CamerasDelivering(status);
  if (delivering < 2) {
    critical.push_back(std::to_string(delivering) + " of " + std::to_string(status.cameras.size()) +
                       " cameras deliver (2 are needed to triangulate)");
  }
  if ((status.flags & kTrackerBacklog) != 0) {
    critical.push_back("BACKLOG: windows are processed behind real time");
  }
  if ((status.flags & kTrackerJobFailures) != 0) {
    critical.push_back("JOB_FAILURES: " + std::to_string(status.jobs_failed) +
                       " window jobs failed since start");
  }
  if ((status.flags & kTrackerNoOutput) != 0) {
    critical.push_back("NO_OUTPUT: cameras deliver but no frame was published for " +
                       std::to_string(kNoOutputAfterUs / 1000000) + " s");
  }
  for (const std::string& f : transport::TrackerFlagNames(
           status.flags & ~(kTrackerBacklog | kTrackerJobFailures | kTrackerNoOutput))) {
    warning.push_back(f);
  }
  for (const transport::CameraStatus& c : status.cameras) {
    const std::vector<std::string> names = transport::CameraFlagNames(c.flags);
    if (!names.empty()) {
      warning.push_back("camera " + std::to_string(c.camera_id) + " " + Join(names, ","));
    }
  }
  return Verdict(critical, warning);
}

HealthReport AssessSiteStatus(const transport::SiteStatus& status) {
  constexpr std::int64_t kZoneMissing = 1 | 2;  // zone_status_t FLAG_NO_DATA | FLAG_STALE
  constexpr std::int64_t kZoneDegraded = 16;    // zone_status_t FLAG_DEGRADED
  constexpr std::int64_t kSiteNoOutput = 8;     // site_status_t FLAG_NO_OUTPUT
  std::vector<std::string> critical;
  std::vector<std::string> warning;
  int live = 0;
  for (const transport::ZoneStatus& z : status.zones) {
    if ((z.flags & kZoneMissing) == 0) ++live;
    const std::vector<std::string> names = transport::ZoneFlagNames(z.flags);
    if (names.empty()) continue;
    std::string reason = "zone " + Printable(z.name) + " " + Join(names, ",");
    if ((z.flags & kZoneDegraded) != 0 && !z.daemon_reasons.empty()) {
      reason += " (" + z.daemon_reasons + ")";
    }
    warning.push_back(std::move(reason));
  }
  if (live == 0) {
    critical.push_back("0 of " + std::to_string(status.zones.size()) + " zones live");
  }
  if ((status.flags & kSiteNoOutput) != 0) {
    critical.push_back("NO_OUTPUT: zones deliver but no site frame was published for " +
                       std::to_string(kNoOutputAfterUs / 1000000) + " s");
  }
  return Verdict(critical, warning);
}

double FrameRateMeter::Add(const transport::TrackerStatus& status) {
  if (!history_.empty() &&
      (status.utime <= history_.back().first || status.last_frame < history_.back().second)) {
    history_.clear();  // a restart, or a clock step: start over
  }
  if (status.last_frame < 0) return FramesPerSecond(status);  // no output yet
  history_.emplace_back(status.utime, status.last_frame);
  // Keep the newest sample older than the horizon as the base, drop those before it.
  std::size_t base = 0;
  while (base + 1 < history_.size() &&
         static_cast<double>(status.utime) - static_cast<double>(history_[base + 1].first) >=
             static_cast<double>(horizon_us_)) {
    ++base;
  }
  history_.erase(history_.begin(), history_.begin() + static_cast<std::ptrdiff_t>(base));
  const double dt = static_cast<double>(status.utime) - static_cast<double>(history_.front().first);
  if (dt < 1e6) return FramesPerSecond(status);
  return (static_cast<double>(status.last_frame) - static_cast<double>(history_.front().second)) *
         1e6 / dt;
}

std::string HealthLine(const HealthReport& report) {
  std::string line = ToString(report.health);
  if (!report.reasons.empty()) line += ": " + Join(report.reasons, "; ");
  return line;
}

HealthReport Combine(HealthReport a, const HealthReport& b) {
  auto rank = [](Health h) {
    switch (h) {
      case Health::kOk:
        return 0;
      case Health::kWarning:
        return 1;
      case Health::kUnknown:
        return 2;
      case Health::kCritical:
        return 3;
    }
    return 2;
  };
  if (rank(b.health) > rank(a.health)) {
    HealthReport out = b;
    out.reasons.insert(out.reasons.end(), a.reasons.begin(), a.reasons.end());
    return out;
  }
  a.reasons.insert(a.reasons.end(), b.reasons.begin(), b.reasons.end());
  return a;
}

void StatusSourceWatch::Add(const TrackerStatusSource& source, double now_s) {
  const std::string& id = source.instance_id;
  auto it = std::find_if(
      instances_.begin(), instances_.end(), [&](const Instance& i) { return i.id == id; });
  const Instance* previous = instances_.empty() ? nullptr : &instances_.back();
  if (it == instances_.end()) {
    if (previous != nullptr) {
      restart_ = {now_s,
                  "the tracker restarted: instance " + Printable(id) + " replaced " +
                      Printable(previous->id)};
    }
    if (instances_.size() >= kMaxInstances) instances_.erase(instances_.begin());
    instances_.push_back({id, source.sequence});
    return;
  }
  if (&*it != previous) {
    conflict_ = {now_s,
                 "two tracker instances publish statuses on this channel (" + Printable(id) +
                     " and " + Printable(previous->id) +
                     "): a second daemon, or forged status messages"};
  }
  if (source.sequence <= it->last_sequence) {
    backwards_ = {now_s,
                  "the status sequence of instance " + Printable(id) + " went backwards (" +
                      std::to_string(source.sequence) + " after " +
                      std::to_string(it->last_sequence) + "): replayed or forged status messages"};
  }
  it->last_sequence = std::max(it->last_sequence, source.sequence);
  std::rotate(it, it + 1, instances_.end());  // the most recently heard last
}

HealthReport StatusSourceWatch::Assess(double now_s) const {
  HealthReport r;
  r.health = Health::kOk;
  for (const Event* e : {&conflict_, &backwards_}) {
    if (now_s - e->at_s <= window_s_) {
      r.health = Health::kCritical;
      r.reasons.push_back(e->what);
    }
  }
  // A "restart" seen while two instances interleave was the second instance's start.
  if (now_s - restart_.at_s <= window_s_ && now_s - conflict_.at_s > window_s_) {
    if (r.health == Health::kOk) r.health = Health::kWarning;
    r.reasons.push_back(restart_.what);
  }
  return r;
}

std::string NotifyStatusLine(const transport::TrackerStatus& status, double frames_per_second) {
  char fps[32];
  std::snprintf(fps, sizeof(fps), "%.1f", frames_per_second);
  std::string line = "tracking: " + std::to_string(CamerasDelivering(status)) + "/" +
                     std::to_string(status.cameras.size()) + " cameras, " + fps + " fps, " +
                     std::to_string(status.active_tracks) + " tracks (" +
                     std::to_string(status.confirmed_tracks) + " confirmed), " +
                     HealthLine(AssessStatus(status));
  return line;
}

}  // namespace mvtrack::service
