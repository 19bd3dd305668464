#include "service/stitch_service.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>

#include "core/check.h"
#include "json/document.h"
#include "transport/codec.h"

namespace mvtrack::service {
namespace {

// Global ids reserved per write of the state directory's reservation (as the daemon's default).
constexpr std::int64_t kIdBlock = 100000;
// Site frame waits kept between status lines.
constexpr std::size_t kMaxWaits = 4096;

// zone_status_t and site_status_t flags (lcmtypes/zone_status_t.lcm, site_status_t.lcm).
constexpr std::int64_t kZoneNoData = 1;
constexpr std::int64_t kZoneStale = 2;
constexpr std::int64_t kZoneLate = 4;
constexpr std::int64_t kZoneDecodeErrors = 8;
constexpr std::int64_t kZoneDegraded = 16;
constexpr std::int64_t kSiteZoneMissing = 1;
constexpr std::int64_t kSiteInputLoss = 2;
constexpr std::int64_t kSiteZoneDegraded = 4;
constexpr std::int64_t kSiteNoOutput = 8;

// A zone daemon's status is current for three of its periods, at least kStatusFreshUs.
constexpr std::int64_t kStatusFreshUs = 3'000'000;

// At most kMaxDaemonReasons characters of `text`, "..." marking a cut.
std::string Clip(std::string text) {
  const auto limit = static_cast<std::size_t>(transport::kMaxDaemonReasons);
  if (text.size() > limit) text = text.substr(0, limit - 3) + "...";
  return text;
}

}  // namespace

std::string SiteStatusJson(const transport::SiteStatus& status) {
  json::OrderedDocument doc;
  doc["utime"] = status.utime;
  doc["sequence"] = status.sequence;
  doc["flags"] = transport::SiteFlagNames(status.flags);
  doc["site_frames"] = status.site_frames;
  doc["global_tracks"] = status.active_tracks;
  doc["global_ids"] = status.global_ids;
  const auto ms = [](std::int64_t us) {
    return std::round(static_cast<double>(us) / 100.0) / 10.0;
  };
  doc["wait_ms"] = {{"p50", ms(status.wait_p50_us)},
                    {"p99", ms(status.wait_p99_us)},
                    {"max", ms(status.wait_max_us)}};
  json::OrderedDocument zones = json::OrderedDocument::array();
  for (const transport::ZoneStatus& z : status.zones) {
    json::OrderedDocument o;
    o["name"] = z.name;
    o["channel"] = z.channel;
    o["state"] = (z.flags & (kZoneNoData | kZoneStale)) != 0 ? "stale" : "live";
    o["flags"] = transport::ZoneFlagNames(z.flags);
    o["frames"] = z.frames;
    o["late"] = z.late;
    o["decode_errors"] = z.decode_errors;
    o["latency_ms"] = ms(z.latency_us);
    o["last_utime"] = z.last_utime;
    o["tracks"] = z.tracks;
    o["daemon"] = ToString(static_cast<Health>(z.daemon_health));
    o["daemon_reasons"] = z.daemon_reasons;
    zones.push_back(std::move(o));
  }
  doc["zones"] = std::move(zones);
  return json::Dump(doc) + "\n";
}

std::unique_ptr<StitchService> StitchService::Create(StitchConfig config, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return nullptr;
  };
  if (config.zones.empty()) return fail("a site needs at least one zone");
  std::string reason;
  if (!config.aligner.Validate(&reason)) return fail("aligner: " + reason);
  if (!config.linker.Validate(&reason)) return fail("linker: " + reason);
  std::optional<IdReservation> ids;
  TrackId3D first_id = 1;
  if (!config.state_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(config.state_dir, ec);
    if (ec) return fail(config.state_dir + ": cannot create the state directory: " + ec.message());
    ids.emplace();
    if (!ids->Open(config.state_dir, kIdBlock, &reason)) return fail(reason);
    first_id = ids->first_id();
  }
  std::unique_ptr<StitchService> s(new StitchService(std::move(config), first_id));
  s->ids_ = std::move(ids);
  return s;
}

StitchService::StitchService(StitchConfig config, TrackId3D first_id)
    : config_(std::move(config)),
      zones_(config_.zones.size()),
      aligner_(static_cast<int>(config_.zones.size()), config_.aligner),
      stitcher_(config::ZoneNames(config_.zones), config_.linker, first_id) {
  instance_id_ = RandomInstanceId();
  for (const config::Zone& z : config_.zones) {
    channels_.push_back(config::ZoneChannel(config_.zone_tracks_channel, z.name));
    status_channels_.push_back(config::ZoneChannel(config_.zone_status_channel, z.name));
  }
}

void StitchService::Touch(std::int64_t now_us) {
  if (!start_us_) {
    start_us_ = now_us;
    period_start_us_ = now_us;
  }
}

void StitchService::OnZoneStatus(int zone,
                                 const void* data,
                                 std::size_t size,
                                 std::int64_t now_us) {
  MVTRACK_CHECK(zone >= 0 && zone < static_cast<int>(status_channels_.size()));
  Touch(now_us);
  ZoneState& zs = zones_[static_cast<std::size_t>(zone)];
  const transport::StatusDecodeResult decoded = transport::DecodeTrackerStatus(data, size);
  if (!decoded.ok()) {
    ++zs.decode_errors;
    return;
  }
  zs.status_received_us = now_us;
  zs.status_period_us = decoded.message.period_us;
  zs.health = AssessStatus(decoded.message);
  zs.instance_id = decoded.message.instance_id;
}

void StitchService::OnMessage(int zone, const void* data, std::size_t size, std::int64_t now_us) {
  MVTRACK_CHECK(zone >= 0 && zone < static_cast<int>(channels_.size()));
  Touch(now_us);
  ZoneState& zs = zones_[static_cast<std::size_t>(zone)];
  transport::TracksDecodeResult decoded = transport::DecodeTracks(data, size);
  if (!decoded.ok()) {
    ++zs.decode_errors;
    return;
  }
  if (decoded.message.layer != transport::TracksLayer::kFinal) {
    ++zs.other_layer;
    return;
  }
  if (!layout_known_) {
    layout_ = decoded.message.layout;
    layout_known_ = true;
  }
  zs.tracks = static_cast<int>(decoded.message.frame.tracks.size());
  zs.latency_us = decoded.message.latency_us + (now_us - decoded.message.publish_utime);
  aligner_.Push(zone, std::move(decoded.message.frame), now_us);
}

std::vector<stitch::SiteFrame> StitchService::Poll(std::int64_t now_us, bool flush) {
  Touch(now_us);
  std::vector<stitch::SiteFrame> out;
  std::vector<std::int64_t> waits;
  for (stitch::ZoneFrameGroup& group : aligner_.Pop(now_us, flush, &waits)) {
    stitch::ZoneFrames frames(group.size(), nullptr);
    for (std::size_t z = 0; z < group.size(); ++z) {
      if (group[z]) frames[z] = &*group[z];
    }
    out.push_back(stitcher_.Stitch(frames));
    global_tracks_ = static_cast<int>(out.back().frame.tracks.size());
    last_frame_ = out.back().frame.frame;
    last_output_us_ = now_us;
  }
  for (const std::int64_t w : waits) {
    if (waits_.size() < kMaxWaits) waits_.push_back(w);
  }
  if (ids_ && !out.empty()) {
    std::string why;
    id_warning_ = ids_->Extend(stitcher_.next_id(), &why) ? std::string() : why;
  }
  return out;
}

transport::SiteStatus StitchService::Status(std::int64_t now_us, bool end_period) {
  Touch(now_us);
  transport::SiteStatus s;
  s.utime = now_us;
  s.period_us = now_us - period_start_us_;
  s.uptime_us = now_us - *start_us_;
  s.instance_id = instance_id_;
  s.start_utime = *start_us_;
  s.sequence = sequence_++;
  s.version = config_.version;
  s.last_frame = last_frame_;
  s.site_frames = stitcher_.stats().frames;
  s.active_tracks = global_tracks_;
  s.global_ids = stitcher_.stats().global_ids;
  s.splits = stitcher_.stats().splits;
  s.merges = stitcher_.stats().merges;
  s.num_wait_samples = static_cast<std::int32_t>(waits_.size());
  if (!waits_.empty()) {
    std::vector<std::int64_t> w = waits_;
    std::sort(w.begin(), w.end());
    const auto at = [&](double q) {
      return w[static_cast<std::size_t>(q * static_cast<double>(w.size() - 1) + 0.5)];
    };
    s.wait_p50_us = at(0.5);
    s.wait_p99_us = at(0.99);
    s.wait_max_us = w.back();
  }
  bool some_live = false;
  for (std::size_t z = 0; z < channels_.size(); ++z) {
    const stitch::ZoneInput& in = aligner_.zones()[z];
    const ZoneState& state = zones_[z];
    transport::ZoneStatus zs;
    zs.name = config_.zones[z].name;
    zs.channel = channels_[z];
    zs.frames = in.frames;
    zs.late = in.late;
    zs.decode_errors = state.decode_errors;
    zs.other_layer = state.other_layer;
    zs.last_utime = in.last_utime;
    zs.last_receive_utime = in.last_arrival_us;
    zs.latency_us = state.latency_us;
    zs.tracks = state.tracks;
    if (in.frames == 0) zs.flags |= kZoneNoData;
    if (aligner_.Stale(static_cast<int>(z), now_us)) zs.flags |= kZoneStale;
    if (in.late > state.period_late) zs.flags |= kZoneLate;
    if (state.decode_errors > state.period_decode_errors) zs.flags |= kZoneDecodeErrors;
    const std::int64_t fresh_us = std::max(kStatusFreshUs, 3 * state.status_period_us);
    if (state.status_received_us > 0 && now_us - state.status_received_us <= fresh_us) {
      zs.daemon_health = static_cast<std::int8_t>(state.health.health);
      zs.daemon_reasons =
          Clip(state.health.reasons.empty() ? std::string() : HealthLine(state.health));
      if (state.health.health == Health::kWarning || state.health.health == Health::kCritical) {
        zs.flags |= kZoneDegraded;
      }
    } else {
      zs.daemon_health = static_cast<std::int8_t>(Health::kUnknown);
    }
    zs.daemon_instance_id = state.instance_id;
    if ((zs.flags & (kZoneNoData | kZoneStale)) != 0) {
      s.flags |= kSiteZoneMissing;
    } else {
      some_live = true;
    }
    if ((zs.flags & (kZoneLate | kZoneDecodeErrors)) != 0) s.flags |= kSiteInputLoss;
    if ((zs.flags & kZoneDegraded) != 0) s.flags |= kSiteZoneDegraded;
    s.zones.push_back(std::move(zs));
  }
  const std::int64_t output_since = last_output_us_ > 0 ? last_output_us_ : *start_us_;
  if (some_live && now_us - output_since > kNoOutputAfterUs) s.flags |= kSiteNoOutput;
  if (end_period) {
    waits_.clear();
    period_start_us_ = now_us;
    for (std::size_t z = 0; z < zones_.size(); ++z) {
      zones_[z].period_late = aligner_.zones()[z].late;
      zones_[z].period_decode_errors = zones_[z].decode_errors;
    }
  }
  return s;
}

}  // namespace mvtrack::service
