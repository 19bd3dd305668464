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
#include "stitch/site_aligner.h"
#include "stitch/stitcher.h"

namespace mvtrack::service {

/// What the stitcher runs with.
struct StitchConfig {
  std::vector<config::Zone> zones;  ///< at least one
  /// The zone daemons' tracks channel before the zone suffix (each zone's is
  /// config::ZoneChannel(zone_tracks_channel, name)).
  std::string zone_tracks_channel = "MVTRACK_TRACKS";
  stitch::AlignerOptions aligner;
  /// The zones' linker options (their defaults unless given).
  linking::LinkerOptions linker;
  /// Directory of the global id reservation ("" = none: ids start at 1 every run).
  std::string state_dir;
};

/// One zone's state in the site status.
struct ZoneStatus {
  std::string name;
  std::string channel;
  stitch::ZoneInput input;
  std::int64_t decode_errors = 0;  ///< messages that did not decode
  std::int64_t other_layer = 0;    ///< provisional-layer messages (ignored)
  int tracks = 0;                  ///< tracks in its latest frame
  /// Capture to arrival at the stitcher of its latest frame, µs: the zone daemon's own
  /// receive-to-publish latency (tracks3d_t.latency_us) plus publish to arrival (host clocks).
  std::int64_t latency_us = 0;
};

/// The site status.
struct SiteStatus {
  std::int64_t now_us = 0;
  std::vector<ZoneStatus> zones;
  std::int64_t site_frames = 0;  ///< site frames stitched
  int global_tracks = 0;         ///< tracks in the latest site frame
  stitch::StitchStats stitch;
  /// How long the site frames of the last status period (at most the last 4096) waited from
  /// their first zone frame's arrival to being stitched, µs: the latency the stitcher adds to
  /// the earliest zone's output (p50, p99, max; 0 without frames).
  std::int64_t wait_p50_us = 0;
  std::int64_t wait_p99_us = 0;
  std::int64_t wait_max_us = 0;
};

/// The site status as one JSON line (terminated by "\n"): {"utime", "site_frames",
/// "global_tracks", "global_ids", "zones": [{"name", "state": "live"|"stale", "frames", "late",
/// "decode_errors", "latency_ms", "last_utime", "tracks"}]}.
std::string SiteStatusJson(const SiteStatus& status);

/// See the file comment.
class StitchService {
 public:
  /// nullptr with `why` set when the configuration is unusable (no zone, invalid aligner or
  /// linker options, a state directory that cannot be used).
  static std::unique_ptr<StitchService> Create(StitchConfig config, std::string* why);

  /// Each zone's tracks channel, parallel to the zones.
  const std::vector<std::string>& channels() const { return channels_; }
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

  /// The site frames ready at `now_us` (with `flush`, every frame kept), stitched.
  std::vector<stitch::SiteFrame> Poll(std::int64_t now_us, bool flush = false);

  /// The layout of the zones' joints (kNone in box mode; the first message's).
  core::KeypointLayoutId layout() const { return layout_; }

  /// The status now; the wait figures cover the site frames since the previous call with
  /// `reset_waits`.
  SiteStatus Status(std::int64_t now_us, bool reset_waits = false);

  /// Why the id reservation could not be extended ("" when it could; ids stay unique for this
  /// run either way).
  const std::string& id_warning() const { return id_warning_; }

 private:
  StitchService(StitchConfig config, TrackId3D first_id);

  StitchConfig config_;
  std::vector<std::string> channels_;
  stitch::SiteAligner aligner_;
  stitch::Stitcher stitcher_;
  std::optional<IdReservation> ids_;
  std::vector<std::int64_t> decode_errors_;
  std::vector<std::int64_t> other_layer_;
  std::vector<int> zone_tracks_;
  std::vector<std::int64_t> zone_latency_;
  core::KeypointLayoutId layout_ = core::KeypointLayoutId::kNone;
  bool layout_known_ = false;
  int global_tracks_ = 0;
  std::vector<std::int64_t> waits_;  // of the site frames since the last reset, at most 4096
  std::string id_warning_;
};

}  // namespace mvtrack::service
