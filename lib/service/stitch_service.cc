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

}  // namespace

std::string SiteStatusJson(const SiteStatus& status) {
  json::OrderedDocument doc;
  doc["utime"] = status.now_us;
  doc["site_frames"] = status.site_frames;
  doc["global_tracks"] = status.global_tracks;
  doc["global_ids"] = status.stitch.global_ids;
  const auto ms = [](std::int64_t us) {
    return std::round(static_cast<double>(us) / 100.0) / 10.0;
  };
  doc["wait_ms"] = {{"p50", ms(status.wait_p50_us)},
                    {"p99", ms(status.wait_p99_us)},
                    {"max", ms(status.wait_max_us)}};
  json::OrderedDocument zones = json::OrderedDocument::array();
  for (const ZoneStatus& z : status.zones) {
    json::OrderedDocument o;
    o["name"] = z.name;
    o["channel"] = z.channel;
    o["state"] = z.input.stale ? "stale" : "live";
    o["frames"] = z.input.frames;
    o["late"] = z.input.late;
    o["decode_errors"] = z.decode_errors;
    o["latency_ms"] = ms(z.latency_us);
    o["last_utime"] = z.input.last_utime;
    o["tracks"] = z.tracks;
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
      aligner_(static_cast<int>(config_.zones.size()), config_.aligner),
      stitcher_(static_cast<int>(config_.zones.size()), config_.linker, first_id),
      decode_errors_(config_.zones.size(), 0),
      other_layer_(config_.zones.size(), 0),
      zone_tracks_(config_.zones.size(), 0),
      zone_latency_(config_.zones.size(), 0) {
  for (const config::Zone& z : config_.zones) {
    channels_.push_back(config::ZoneChannel(config_.zone_tracks_channel, z.name));
  }
}

void StitchService::OnMessage(int zone, const void* data, std::size_t size, std::int64_t now_us) {
  MVTRACK_CHECK(zone >= 0 && zone < static_cast<int>(channels_.size()));
  const auto z = static_cast<std::size_t>(zone);
  transport::TracksDecodeResult decoded = transport::DecodeTracks(data, size);
  if (!decoded.ok()) {
    ++decode_errors_[z];
    return;
  }
  if (decoded.message.layer != transport::TracksLayer::kFinal) {
    ++other_layer_[z];
    return;
  }
  if (!layout_known_) {
    layout_ = decoded.message.layout;
    layout_known_ = true;
  }
  zone_tracks_[z] = static_cast<int>(decoded.message.frame.tracks.size());
  zone_latency_[z] = decoded.message.latency_us + (now_us - decoded.message.publish_utime);
  aligner_.Push(zone, std::move(decoded.message.frame), now_us);
}

std::vector<stitch::SiteFrame> StitchService::Poll(std::int64_t now_us, bool flush) {
  std::vector<stitch::SiteFrame> out;
  std::vector<std::int64_t> waits;
  for (stitch::ZoneFrameGroup& group : aligner_.Pop(now_us, flush, &waits)) {
    stitch::ZoneFrames frames(group.size(), nullptr);
    for (std::size_t z = 0; z < group.size(); ++z) {
      if (group[z]) frames[z] = &*group[z];
    }
    out.push_back(stitcher_.Stitch(frames));
    global_tracks_ = static_cast<int>(out.back().frame.tracks.size());
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

SiteStatus StitchService::Status(std::int64_t now_us, bool reset_waits) {
  SiteStatus s;
  s.now_us = now_us;
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
  if (reset_waits) waits_.clear();
  for (std::size_t z = 0; z < channels_.size(); ++z) {
    ZoneStatus zs;
    zs.name = config_.zones[z].name;
    zs.channel = channels_[z];
    zs.input = aligner_.zones()[z];
    zs.input.stale = aligner_.Stale(static_cast<int>(z), now_us);
    zs.decode_errors = decode_errors_[z];
    zs.other_layer = other_layer_[z];
    zs.tracks = zone_tracks_[z];
    zs.latency_us = zone_latency_[z];
    s.zones.push_back(std::move(zs));
  }
  s.site_frames = stitcher_.stats().frames;
  s.global_tracks = global_tracks_;
  s.stitch = stitcher_.stats();
  return s;
}

}  // namespace mvtrack::service
