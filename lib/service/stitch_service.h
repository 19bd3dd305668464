#pragma once
/// @file
/// StitchService: the stitcher program (`mvtrack-stitcher`, issue 43) minus main and LCM. It
/// takes the zone daemons' tracks messages (tracks3d_t on each zone's tracks channel,
/// config::ZoneChannel), aligns them by capture time with a bounded wait for a late zone
/// (stitch::SiteAligner), joins them into global ids (stitch::Stitcher) and hands out the site
/// frames to publish, with the site's status (zones live or stale, their latency, late frames).
/// Global ids never repeat across restarts with a state directory (IdReservation).
///
/// Thread safety: single-owner, single-threaded (the program's LCM thread drives it). Never
/// throws on input: a message that does not decode, or carries another layer, is counted.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/zones.h"
#include "core/keypoint_layout.h"
#include "linking/window_linker.h"
#include "service/id_reservation.h"
#include "service/status_check.h"
#include "stitch/site_aligner.h"
#include "stitch/stitcher.h"
#include "transport/codec.h"

namespace mvtrack::service {

/// What the stitcher runs with.
struct StitchConfig {
  std::vector<config::Zone> zones;  ///< at least one
  /// The zone daemons' tracks channel before the zone suffix (each zone's is
  /// config::ZoneChannel(zone_tracks_channel, name)).
  std::string zone_tracks_channel = "MVTRACK_TRACKS";
  /// The zone daemons' status channel before the zone suffix (their tracker_status_t: the
  /// zones' own health in the site status).
  std::string zone_status_channel = "MVTRACK_STATUS";
  /// The stitcher's version (site_status_t.version).
  std::string version;
  stitch::AlignerOptions aligner;
  /// The zones' linker options (their defaults unless given).
  linking::LinkerOptions linker;
  /// Directory of the global id reservation ("" = none: ids start at 1 every run).
  std::string state_dir;
};

/// The site status as one JSON line (terminated by "\n"): {"utime", "sequence", "flags" (names),
/// "site_frames", "global_tracks", "global_ids", "wait_ms": {"p50", "p99", "max"}, "zones":
/// [{"name", "channel", "state": "live"|"stale", "flags" (names), "frames", "late",
/// "decode_errors", "latency_ms", "last_utime", "tracks", "daemon": "OK"|"WARNING"|"CRITICAL"|
/// "UNKNOWN", "daemon_reasons"}]}.
std::string SiteStatusJson(const transport::SiteStatus& status);

/// See the file comment.
class StitchService {
 public:
  /// nullptr with `why` set when the configuration is unusable (no zone, invalid aligner or
  /// linker options, a state directory that cannot be used).
  static std::unique_ptr<StitchService> Create(StitchConfig config, std::string* why);

  /// Each zone's tracks channel, parallel to the zones.
  const std::vector<std::string>& channels() const { return channels_; }
  /// Each zone daemon's status channel, parallel to the zones.
  const std::vector<std::string>& status_channels() const { return status_channels_; }
  /// Zone `zone`'s name (an index into channels()).
  const std::string& zone_name(int zone) const {
    return config_.zones.at(static_cast<std::size_t>(zone)).name;
  }
  /// Whether zone `zone` has delivered a frame yet.
  bool heard_from(int zone) const {
    return aligner_.zones().at(static_cast<std::size_t>(zone)).frames > 0;
  }
  /// Whether zone `zone` is stale at `now_us` (stitch::SiteAligner::Stale).
  bool stale(int zone, std::int64_t now_us) const { return aligner_.Stale(zone, now_us); }

  /// A message on zone `zone`'s channel (an index into channels(); checked) received at
  /// `now_us` (the program's clock, never going back).
  void OnMessage(int zone, const void* data, std::size_t size, std::int64_t now_us);

  /// A message on zone `zone`'s status channel (the zone daemon's tracker_status_t; an index
  /// into status_channels(), checked) received at `now_us`. One that does not decode is
  /// counted with the zone's decode errors.
  void OnZoneStatus(int zone, const void* data, std::size_t size, std::int64_t now_us);

  /// The site frames ready at `now_us` (with `flush`, every frame kept), stitched.
  std::vector<stitch::SiteFrame> Poll(std::int64_t now_us, bool flush = false);

  /// The layout of the zones' joints (kNone in box mode; the first message's).
  core::KeypointLayoutId layout() const { return layout_; }

  /// The site status at `now_us` (site_status_t; each call takes the next sequence number).
  /// A status period ends at each call with `end_period`: the wait figures and the per-period
  /// flags (LATE, DECODE_ERRORS) cover the time since the previous one.
  transport::SiteStatus Status(std::int64_t now_us, bool end_period = false);

  /// The stitcher's counters.
  const stitch::StitchStats& stitch_stats() const { return stitcher_.stats(); }

  /// Why the id reservation could not be extended ("" when it could; ids stay unique for this
  /// run either way).
  const std::string& id_warning() const { return id_warning_; }

 private:
  StitchService(StitchConfig config, TrackId3D first_id);

  // What the service keeps of one zone beside the aligner's counters.
  struct ZoneState {
    std::int64_t decode_errors = 0;  // on its tracks or status channel
    std::int64_t other_layer = 0;    // provisional-layer messages, ignored
    int tracks = 0;                  // in its latest frame
    std::int64_t latency_us = 0;     // of its latest frame: daemon latency + transport
    // Its daemon's latest status.
    std::int64_t status_received_us = 0;  // 0: none yet
    std::int64_t status_period_us = 0;
    HealthReport health;
    std::string instance_id;
    // The counters when the status period started (the period's LATE, DECODE_ERRORS flags).
    std::int64_t period_late = 0;
    std::int64_t period_decode_errors = 0;
  };

  void Touch(std::int64_t now_us);

  StitchConfig config_;
  std::string instance_id_;
  std::optional<std::int64_t> start_us_;
  std::int64_t period_start_us_ = 0;
  std::int64_t sequence_ = 0;
  std::int64_t last_output_us_ = 0;  // when Poll last stitched a frame (0: never)
  std::int64_t last_frame_ = -1;
  std::vector<std::string> channels_;
  std::vector<std::string> status_channels_;
  std::vector<ZoneState> zones_;  // parallel to config_.zones
  stitch::SiteAligner aligner_;
  stitch::Stitcher stitcher_;
  std::optional<IdReservation> ids_;
  core::KeypointLayoutId layout_ = core::KeypointLayoutId::kNone;
  bool layout_known_ = false;
  int global_tracks_ = 0;
  std::vector<std::int64_t> waits_;  // of the site frames since the last reset, at most 4096
  std::string id_warning_;
};

}  // namespace mvtrack::service
