#include "service/daemon_config.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>
#include <thread>
#include <utility>

#include "config/calibration.h"
#include "config/internal/tracker_options_node.h"
#include "config/internal/yaml_node.h"
#include "config/site.h"
#include "config/zones.h"
#include "geometry/camera_rig.h"
#include "transport/channels.h"

namespace mvtrack::service {
namespace {

using config::ConfigError;
using config::internal::DoubleRange;
using config::internal::FormatDouble;
using config::internal::GetDouble;
using config::internal::GetEnum;
using config::internal::GetInt;
using config::internal::GetInt64;
using config::internal::GetSequence;
using config::internal::GetString;
using config::internal::MapRef;
using config::internal::NodeRef;
using config::internal::QuoteString;

constexpr std::array<std::pair<SyncMode, std::string_view>, 2> kSyncModeNames = {{
    {SyncMode::kFrameIndex, "frame_index"},
    {SyncMode::kUtime, "utime"},
}};
constexpr std::array<std::pair<ChannelMode, std::string_view>, 3> kChannelModeNames = {{
    {ChannelMode::kPerCamera, "per_camera"},
    {ChannelMode::kShared, "shared"},
    {ChannelMode::kBoth, "both"},
}};
const std::vector<std::string> kLogLevels = {
    "trace", "debug", "info", "warn", "error", "critical", "off"};

std::optional<pipeline::OverflowPolicy> OverflowFromName(std::string_view name) {
  if (name == "drop_oldest") return pipeline::OverflowPolicy::kDropOldest;
  if (name == "block") return pipeline::OverflowPolicy::kBlock;
  return std::nullopt;
}

std::optional<std::string> LogLevelFromName(std::string_view name) {
  for (const std::string& level : kLogLevels) {
    if (level == name) return level;
  }
  return std::nullopt;
}

// A channel name LCM accepts and that a log can hold: 1..255 printable ASCII, no spaces.
void CheckChannelName(const NodeRef& node, const std::string& channel) {
  if (channel.empty() || channel.size() > 255) node.Fail("channel names have 1 to 255 characters");
  for (const char c : channel) {
    if (c <= ' ' || c > '~') node.Fail("channel names are printable ASCII without spaces");
  }
  if (transport::IsDetectionsChannel(channel)) {
    node.Fail("'" + channel + "' is a detections channel; outputs need their own channel");
  }
}

void CheckUrl(const NodeRef& node, const std::string& url) {
  static const std::array<std::string_view, 4> kSchemes = {
      "udpm://", "file://", "memq://", "tcpq://"};
  for (std::string_view scheme : kSchemes) {
    if (url.rfind(scheme, 0) == 0) return;
  }
  node.Fail("unsupported LCM URL '" + url + "' (expected udpm://, file://, memq:// or tcpq://)");
}

std::string ResolvePath(const std::string& base_dir, const std::string& path) {
  std::filesystem::path p(path);
  if (p.is_absolute() || base_dir.empty()) return p.lexically_normal().string();
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

void ParseCameras(const MapRef& root,
                  const std::string& base_dir,
                  const std::string& override_path,
                  DaemonConfig* c) {
  const MapRef cams(root.Get("cameras"), {"calibration", "ids"});
  const NodeRef cal_node = cams.Get("calibration");
  c->calibration_path = override_path.empty() ? ResolvePath(base_dir, GetString(cal_node))
                                              : ResolvePath("", override_path);
  std::vector<geometry::CameraModel> all;
  try {
    all = config::LoadCalibration(c->calibration_path);
  } catch (const ConfigError& e) {
    // A calibration given instead of the file's (--calibration) is not this file's fault: its
    // error names the calibration's own file, line and key alone.
    if (!override_path.empty()) throw;
    cal_node.Fail(std::string("calibration: ") + e.what());
  }
  if (const std::optional<NodeRef> ids_node = cams.Find("ids")) {
    std::set<CameraId> ids;
    for (const NodeRef& id_node : GetSequence(*ids_node)) {
      const CameraId id = GetInt(id_node, 0, std::numeric_limits<CameraId>::max());
      if (!ids.insert(id).second) id_node.Fail("camera id " + std::to_string(id) + " listed twice");
      const auto it = std::find_if(
          all.begin(), all.end(), [&](const geometry::CameraModel& m) { return m.id == id; });
      if (it == all.end()) {
        id_node.Fail("camera id " + std::to_string(id) + " is not in " + c->calibration_path);
      }
      c->cameras.push_back(*it);
    }
  } else {
    c->cameras = std::move(all);
  }
  std::sort(
      c->cameras.begin(),
      c->cameras.end(),
      [](const geometry::CameraModel& a, const geometry::CameraModel& b) { return a.id < b.id; });
  if (c->cameras.size() < 2) {
    cams.ref().Fail("at least 2 cameras are needed to triangulate (have " +
                    std::to_string(c->cameras.size()) + ")");
  }
  std::string why;
  geometry::CameraRig rig(c->cameras, &why);
  if (!rig.ok()) cams.ref().Fail(why);
}

void ParseInput(const MapRef& root, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("input");
  if (!node) return;
  const MapRef m(
      *node,
      {"lcm_url", "channels", "max_message_bytes", "max_detections", "lcm_queue_capacity"},
      true);
  if (auto v = m.Find("lcm_url")) {
    c->input_url = GetString(*v);
    CheckUrl(*v, c->input_url);
  }
  if (auto v = m.Find("channels")) {
    c->channel_mode =
        GetEnum<ChannelMode>(*v, ChannelModeFromName, {"per_camera", "shared", "both"});
  }
  if (auto v = m.Find("max_message_bytes")) c->max_message_bytes = GetInt64(*v, 64, INT32_MAX);
  if (auto v = m.Find("max_detections")) c->max_detections_per_message = GetInt(*v, 1, 1000000);
  if (auto v = m.Find("lcm_queue_capacity")) c->lcm_queue_capacity = GetInt(*v, 0, 1000000);
}

void ParseOutput(const MapRef& root, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("output");
  if (!node) return;
  const MapRef m(*node,
                 {"lcm_url",
                  "tracks_channel",
                  "status_channel",
                  "provisional_channel",
                  "status_period_s",
                  "latency_limit_us"},
                 true);
  if (auto v = m.Find("lcm_url")) {
    c->output_url = GetString(*v, /*allow_empty=*/true);
    if (!c->output_url.empty()) CheckUrl(*v, c->output_url);
  }
  if (auto v = m.Find("tracks_channel")) {
    c->tracks_channel = GetString(*v);
    CheckChannelName(*v, c->tracks_channel);
  }
  if (auto v = m.Find("status_channel")) {
    c->status_channel = GetString(*v);
    CheckChannelName(*v, c->status_channel);
    if (c->status_channel == c->tracks_channel)
      v->Fail("status and tracks need different channels");
  }
  if (auto v = m.Find("provisional_channel")) {
    c->provisional_channel = GetString(*v, /*allow_empty=*/true);
    if (!c->provisional_channel.empty()) CheckChannelName(*v, c->provisional_channel);
  }
  if (!c->provisional_channel.empty() && (c->provisional_channel == c->tracks_channel ||
                                          c->provisional_channel == c->status_channel)) {
    const std::optional<NodeRef> at = m.Find("provisional_channel");
    (at ? *at : *node)
        .Fail(
            "the provisional layer needs its own channel, not the tracks or status "
            "channel (\"" +
            c->provisional_channel + "\")");
  }
  if (auto v = m.Find("status_period_s")) {
    c->status_period_s = GetDouble(*v, DoubleRange::Closed(0.05, 3600.0));
  }
  if (auto v = m.Find("latency_limit_us")) c->latency_limit_us = GetInt64(*v, 1);
}

void ParseAnalytics(const MapRef& root, const std::string& base_dir, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("analytics");
  if (!node) return;
  const MapRef m(*node, {"site", "events_channel", "counts_channel"}, true);
  if (auto v = m.Find("site")) {
    const std::string path = GetString(*v, /*allow_empty=*/true);
    if (!path.empty()) {
      c->site_path = ResolvePath(base_dir, path);
      c->site = config::LoadSiteFile(c->site_path);
    }
  }
  const std::vector<std::string> taken = {
      c->tracks_channel, c->status_channel, c->provisional_channel};
  if (auto v = m.Find("events_channel")) {
    c->analytics_events_channel = GetString(*v);
    CheckChannelName(*v, c->analytics_events_channel);
  }
  if (auto v = m.Find("counts_channel")) {
    c->site_counts_channel = GetString(*v);
    CheckChannelName(*v, c->site_counts_channel);
  }
  for (const std::string& channel : {c->analytics_events_channel, c->site_counts_channel}) {
    if (std::count(taken.begin(), taken.end(), channel) > 0 ||
        c->analytics_events_channel == c->site_counts_channel) {
      node->Fail(
          "the analytics channels must differ from each other and from the tracks and "
          "status channels ('" +
          channel + "')");
    }
  }
}

void ParseSync(const MapRef& root, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("sync");
  if (!node) return;
  const MapRef m(*node,
                 {"mode",
                  "tolerance_us",
                  "deadline_us",
                  "silent_after_us",
                  "max_future_us",
                  "max_frame_ahead",
                  "clock_tolerance_us",
                  "max_frame_offset",
                  "min_frame_interval_us",
                  "resync_after_rejections",
                  "max_pending_frames",
                  "idle_flush_s"},
                 true);
  SyncOptions& s = c->sync;
  constexpr std::int64_t kHour = std::int64_t{3600} * 1000000;
  if (auto v = m.Find("mode"))
    s.mode = GetEnum<SyncMode>(*v, SyncModeFromName, {"frame_index", "utime"});
  if (auto v = m.Find("tolerance_us")) s.tolerance_us = GetInt64(*v, 0, kHour);
  if (auto v = m.Find("deadline_us")) s.deadline_us = GetInt64(*v, 1, kHour);
  if (auto v = m.Find("silent_after_us")) s.silent_after_us = GetInt64(*v, 1, kHour);
  if (auto v = m.Find("max_future_us")) s.max_future_us = GetInt64(*v, 1, 24 * kHour);
  if (auto v = m.Find("max_frame_ahead")) s.max_frame_ahead = GetInt64(*v, 1, INT32_MAX);
  if (auto v = m.Find("clock_tolerance_us")) s.clock_tolerance_us = GetInt64(*v, 1, 24 * kHour);
  if (auto v = m.Find("max_frame_offset")) s.max_frame_offset = GetInt64(*v, 1, INT32_MAX);
  if (auto v = m.Find("min_frame_interval_us")) s.min_frame_interval_us = GetInt64(*v, 0, kHour);
  if (auto v = m.Find("resync_after_rejections")) {
    s.resync_after_rejections = GetInt(*v, 1, 1000000);
  }
  if (auto v = m.Find("max_pending_frames")) s.max_pending_frames = GetInt(*v, 1, 100000);
  if (auto v = m.Find("idle_flush_s"))
    s.idle_flush_s = GetDouble(*v, DoubleRange::Closed(0.0, 86400.0));
  if (s.mode == SyncMode::kUtime && s.tolerance_us >= s.deadline_us) {
    m.KeyRef("tolerance_us")
        .Fail("tolerance_us must be smaller than deadline_us (" + std::to_string(s.deadline_us) +
              ")");
  }
}

void ParseThreadsAndQueues(const MapRef& root, DaemonConfig* c) {
  if (const std::optional<NodeRef> node = root.Find("threads")) {
    const MapRef m(*node, {"workers", "job_queue"}, true);
    if (auto v = m.Find("workers")) c->workers = GetInt(*v, 0, 256);
    if (auto v = m.Find("job_queue")) c->job_queue_capacity = GetInt(*v, 1, 1 << 20);
  }
  if (const std::optional<NodeRef> node = root.Find("queues")) {
    const MapRef m(*node,
                   {"camera_capacity", "camera_overflow", "reorder_capacity", "finalizer_capacity"},
                   true);
    if (auto v = m.Find("camera_capacity")) c->camera_queue_capacity = GetInt(*v, 1, 100000);
    if (auto v = m.Find("camera_overflow")) {
      c->camera_overflow =
          GetEnum<pipeline::OverflowPolicy>(*v, OverflowFromName, {"drop_oldest", "block"});
    }
    if (auto v = m.Find("reorder_capacity")) c->reorder_capacity = GetInt(*v, 1, 1000000);
    if (auto v = m.Find("finalizer_capacity")) c->finalizer_queue_capacity = GetInt(*v, 1, 1000000);
  }
}

void ParseState(const MapRef& root, const std::string& base_dir, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("state");
  if (!node) return;
  const MapRef m(*node, {"directory", "id_block"}, true);
  if (auto v = m.Find("directory")) {
    const std::string dir = GetString(*v, /*allow_empty=*/true);
    c->state_directory = dir.empty() ? "" : ResolvePath(base_dir, dir);
  }
  if (auto v = m.Find("id_block")) c->id_block = GetInt64(*v, 1, std::int64_t{1} << 40);
}

void ParseLogging(const MapRef& root, DaemonConfig* c) {
  const std::optional<NodeRef> node = root.Find("logging");
  if (!node) return;
  const MapRef m(*node, {"level", "repeat_interval_s"}, true);
  if (auto v = m.Find("level"))
    c->log_level = GetEnum<std::string>(*v, LogLevelFromName, kLogLevels);
  if (auto v = m.Find("repeat_interval_s")) {
    c->log_repeat_interval_s = GetDouble(*v, DoubleRange::LeftOpen(0.0, 86400.0));
  }
}

std::string Fnv1a64Hex(std::string_view text) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const char ch : text) {
    h ^= static_cast<std::uint8_t>(ch);
    h *= 1099511628211ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::string_view SyncModeName(SyncMode mode) {
  for (const auto& [m, name] : kSyncModeNames) {
    if (m == mode) return name;
  }
  return "?";
}

std::optional<SyncMode> SyncModeFromName(std::string_view name) {
  for (const auto& [m, n] : kSyncModeNames) {
    if (n == name) return m;
  }
  return std::nullopt;
}

std::string_view ChannelModeName(ChannelMode mode) {
  for (const auto& [m, name] : kChannelModeNames) {
    if (m == mode) return name;
  }
  return "?";
}

std::optional<ChannelMode> ChannelModeFromName(std::string_view name) {
  for (const auto& [m, n] : kChannelModeNames) {
    if (n == name) return m;
  }
  return std::nullopt;
}

int DaemonConfig::EffectiveWorkers() const {
  if (workers > 0) return workers;
  const unsigned cores = std::thread::hardware_concurrency();
  return cores == 0 ? 1 : static_cast<int>(std::min(cores, 256U));
}

DaemonConfig ParseDaemonConfig(std::string_view text,
                               const std::string& source_name,
                               const std::string& base_dir,
                               const std::string& calibration_override) {
  const NodeRef root_node = config::internal::ParseDocument(text, source_name);
  if (root_node.IsNull()) {
    root_node.Fail("empty document (expected a map with 'format: mvtrack.daemon/1')");
  }
  DaemonConfig c;
  c.source = source_name;
  try {
    const MapRef root(root_node,
                      {"format",
                       "zone",
                       "cameras",
                       "input",
                       "output",
                       "sync",
                       "threads",
                       "queues",
                       "state",
                       "logging",
                       "analytics",
                       "tracker"});
    const NodeRef format = root.Get("format");
    if (GetString(format) != kDaemonConfigFormat) {
      format.Fail("expected '" + std::string(kDaemonConfigFormat) + "', not '" + GetString(format) +
                  "'");
    }
    if (const std::optional<NodeRef> zone = root.Find("zone");
        zone && !GetString(*zone, true).empty()) {
      c.zone = GetString(*zone);
      if (const std::optional<std::string> why = config::ValidateZoneName(c.zone)) {
        zone->Fail(*why);
      }
      for (std::string* channel : {&c.tracks_channel,
                                   &c.status_channel,
                                   &c.provisional_channel,
                                   &c.analytics_events_channel,
                                   &c.site_counts_channel}) {
        *channel = config::ZoneChannel(*channel, c.zone);
      }
    }
    ParseCameras(root, base_dir, calibration_override, &c);
    ParseInput(root, &c);
    ParseOutput(root, &c);
    ParseAnalytics(root, base_dir, &c);
    ParseSync(root, &c);
    ParseThreadsAndQueues(root, &c);
    ParseState(root, base_dir, &c);
    ParseLogging(root, &c);
    if (const std::optional<NodeRef> tracker = root.Find("tracker")) {
      c.tracker = config::internal::ParseTrackerOptionsNode(*tracker);
    }
  } catch (const YAML::Exception& e) {
    throw ConfigError(source_name,
                      e.mark.is_null() ? 0 : e.mark.line + 1,
                      e.mark.is_null() ? 0 : e.mark.column + 1,
                      "",
                      e.msg);
  }
  return c;
}

DaemonConfig LoadDaemonConfigFile(const std::string& path,
                                  const std::string& calibration_override) {
  const std::string text = config::internal::ReadTextFile(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return ParseDaemonConfig(text, path, dir, calibration_override);
}

bool LooksLikeDaemonConfig(std::string_view text) {
  try {
    const YAML::Node root = YAML::Load(std::string(text));
    if (!root.IsMap()) return false;
    if (root["cameras"]) return true;
    const YAML::Node format = root["format"];
    return format.IsScalar() && format.Scalar().rfind("mvtrack.daemon/", 0) == 0;
  } catch (...) {
    return false;
  }
}

std::string DaemonConfigToYaml(const DaemonConfig& c) {
  std::string out;
  auto line = [&](const std::string& s) { out += s + "\n"; };
  line("format: " + std::string(kDaemonConfigFormat));
  line("zone: " + QuoteString(c.zone));
  line("cameras:");
  line("  calibration: " + QuoteString(c.calibration_path));
  std::string ids;
  for (const geometry::CameraModel& m : c.cameras)
    ids += (ids.empty() ? "" : ", ") + std::to_string(m.id);
  line("  ids: [" + ids + "]");
  line("input:");
  line("  lcm_url: " + QuoteString(c.input_url));
  line("  channels: " + std::string(ChannelModeName(c.channel_mode)));
  line("  max_message_bytes: " + std::to_string(c.max_message_bytes));
  line("  max_detections: " + std::to_string(c.max_detections_per_message));
  line("  lcm_queue_capacity: " + std::to_string(c.lcm_queue_capacity));
  line("output:");
  line("  lcm_url: " + QuoteString(c.output_url));
  line("  tracks_channel: " + QuoteString(c.tracks_channel));
  line("  status_channel: " + QuoteString(c.status_channel));
  line("  provisional_channel: " + QuoteString(c.provisional_channel));
  line("  status_period_s: " + FormatDouble(c.status_period_s));
  line("  latency_limit_us: " + std::to_string(c.latency_limit_us));
  line("analytics:");
  line("  site: " + QuoteString(c.site_path));
  line("  events_channel: " + QuoteString(c.analytics_events_channel));
  line("  counts_channel: " + QuoteString(c.site_counts_channel));
  line("sync:");
  line("  mode: " + std::string(SyncModeName(c.sync.mode)));
  line("  tolerance_us: " + std::to_string(c.sync.tolerance_us));
  line("  deadline_us: " + std::to_string(c.sync.deadline_us));
  line("  silent_after_us: " + std::to_string(c.sync.silent_after_us));
  line("  max_future_us: " + std::to_string(c.sync.max_future_us));
  line("  max_frame_ahead: " + std::to_string(c.sync.max_frame_ahead));
  line("  clock_tolerance_us: " + std::to_string(c.sync.clock_tolerance_us));
  line("  max_frame_offset: " + std::to_string(c.sync.max_frame_offset));
  line("  min_frame_interval_us: " + std::to_string(c.sync.min_frame_interval_us));
  line("  resync_after_rejections: " + std::to_string(c.sync.resync_after_rejections));
  line("  max_pending_frames: " + std::to_string(c.sync.max_pending_frames));
  line("  idle_flush_s: " + FormatDouble(c.sync.idle_flush_s));
  line("threads:");
  line("  workers: " + std::to_string(c.workers));
  line("  job_queue: " + std::to_string(c.job_queue_capacity));
  line("queues:");
  line("  camera_capacity: " + std::to_string(c.camera_queue_capacity));
  line("  camera_overflow: " + std::string(pipeline::ToString(c.camera_overflow)));
  line("  reorder_capacity: " + std::to_string(c.reorder_capacity));
  line("  finalizer_capacity: " + std::to_string(c.finalizer_queue_capacity));
  line("state:");
  line("  directory: " + QuoteString(c.state_directory));
  line("  id_block: " + std::to_string(c.id_block));
  line("logging:");
  line("  level: " + c.log_level);
  line("  repeat_interval_s: " + FormatDouble(c.log_repeat_interval_s));
  line("tracker:");
  config::internal::AppendTrackerOptionsYaml(c.tracker, 2, &out);
  return out;
}

int LcmQueueCapacity(const DaemonConfig& config) {
  if (config.lcm_queue_capacity > 0) return config.lcm_queue_capacity;
  const std::size_t per_camera = 30 * std::max<std::size_t>(1, config.cameras.size());
  return static_cast<int>(std::min<std::size_t>(per_camera, 1000000));
}

std::string DaemonConfigHash(const DaemonConfig& c) {
  return Fnv1a64Hex(DaemonConfigToYaml(c) + "\n---\n" + config::CalibrationToYaml(c.cameras) +
                    (c.site_path.empty() ? "" : "\n---\n" + config::SiteToYaml(c.site)));
}

}  // namespace mvtrack::service
