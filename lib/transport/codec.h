#pragma once
/// @file
/// Conversion between the LCM wire types of package `mvtrack` (lcmtypes/*.lcm) and the
/// tracker's own types, with safe decoding of untrusted bytes.
///
/// Why not the generated `decode()` alone: the C++ code that lcm-gen 1.3.1 emits sizes vectors
/// from the message's counts before it checks the buffer length, so a negative count or a
/// string length of 0 throws std::length_error and a huge count allocates that many elements
/// before failing (memory exhaustion on hostile input). The Decode* functions below therefore
/// first walk the encoded structure themselves (fingerprint, fixed fields, every count and
/// string length checked against the remaining bytes and the DecodeLimits), so no allocation is
/// ever driven by an unchecked count, and only then call the generated decoder, inside
/// try/catch. They never throw and never allocate more than a small multiple of the message
/// size.
///
/// Receiving from LCM: subscribe with the raw-bytes overload
/// `lcm::LCM::subscribeFunction(channel, &Handler, context)` whose handler has the signature
/// `void(const lcm::ReceiveBuffer*, const std::string&, Context)` and pass `rbuf->data` /
/// `rbuf->data_size` to DecodeCameraDetections(). Do not use the typed overloads: they call the
/// generated decode() on untrusted bytes, and an exception would unwind through LCM's C code.
/// Do not use LCM 1.3.1's member-function `subscribe()` overloads either: under GCC 12
/// `-fsanitize=undefined` their callbacks crash (vptr check); a free or static function with
/// subscribeFunction() or the C API `lcm_subscribe` works.
///
/// Encoding: the generated encoder trusts the `num_*` fields; the Encode* functions set every
/// count from the container sizes.
///
/// All functions are stateless and thread-compatible (no shared state).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "analytics/site_analytics.h"
#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/types.h"
#include "tracker/types.h"

namespace mvtrack::transport {

/// Bounds applied while decoding untrusted bytes. Counts are checked before anything is
/// allocated; a count above its limit gives DecodeStatus::kLimitExceeded.
struct DecodeLimits {
  /// Messages larger than this are rejected unread (kTooLarge), bytes. At most INT32_MAX (the
  /// generated decoder indexes with int).
  std::size_t max_message_bytes = std::size_t{4} << 20;
  /// camera_detections_t.num_detections.
  int max_detections = 1000;
  /// detection_t.num_keypoints.
  int max_keypoints = 64;
  /// detection_t.num_embedding (floats).
  int max_embedding = 4096;
  /// Any string (keypoint_layout, embedding_model), bytes without the NUL terminator.
  int max_string = 64;
  /// tracks3d_t.num_tracks.
  int max_tracks = 1000;
  /// track3d_t.num_cameras.
  int max_cameras = 256;
  /// track3d_t.num_joints.
  int max_joints = 64;
  /// site_counts_t.num_regions and num_lines.
  int max_site_items = analytics::kMaxRegions;
  /// tracks3d_t.num_zones (a site's zones, config::kMaxZones) and track3d_t.num_zones.
  int max_zones = 256;

  /// True when usable: 8 <= max_message_bytes <= INT32_MAX and every count limit >= 0.
  /// Otherwise false, with the first violated condition in `why` (when not null).
  bool Validate(std::string* why) const;
};

/// Outcome of decoding one message.
enum class DecodeStatus {
  kOk,              ///< decoded; the payload fields are valid
  kTooLarge,        ///< more bytes than DecodeLimits::max_message_bytes; not read
  kBadFingerprint,  ///< the first 8 bytes are not this type's fingerprint (other type/version)
  kTruncated,       ///< the bytes end before the structure does
  kMalformed,       ///< structurally invalid: negative count, bad string, unknown layout name,
                    ///< unknown enum value, trailing bytes
  kLimitExceeded,   ///< a count or string length exceeds its DecodeLimits bound
};

/// "ok", "too large", "bad fingerprint", "truncated", "malformed", "limit exceeded".
const char* ToString(DecodeStatus status);

/// Result of DecodeCameraDetections().
struct DecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  /// Empty when kOk; otherwise what failed, where and why, e.g.
  /// "detection 3: num_keypoints -5 is negative (byte 123)".
  std::string reason;
  /// The detections (valid only when kOk). Only the structure is checked: the geometry is
  /// validated by the tracker (core::ValidateDetection). Each detection's layout comes from
  /// its keypoint_layout ("" -> kNone). detection_t.embedding_model has no place in
  /// core::Detection2D and is dropped.
  core::CameraFrame frame;
  /// camera_detections_t.image_width / image_height, pixels; 0 = unknown. Passed through
  /// unchecked (negative values are the consumer's to reject).
  int image_width_px = 0;
  int image_height_px = 0;

  /// status == kOk.
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes a camera_detections_t from untrusted bytes `data[0, size)` (the whole LCM payload;
/// trailing bytes are kMalformed). Never throws; `data` may be null when `size` is 0.
/// @pre limits.Validate() (checked; aborts otherwise: a programmer error).
DecodeResult DecodeCameraDetections(const void* data,
                                    std::size_t size,
                                    const DecodeLimits& limits = {});

/// Encodes `frame` as a camera_detections_t (all num_* set from the container sizes; doubles
/// become floats, values beyond the float range become +-infinity; keypoint_layout is the
/// layout's name, "" for kNone; embedding_model is "" as Detection2D does not carry one).
/// @pre at most INT32_MAX detections, INT16_MAX keypoints and INT16_MAX embedding values per
///      detection (checked; aborts otherwise).
std::vector<std::uint8_t> EncodeCameraDetections(const core::CameraFrame& frame,
                                                 int image_width_px,
                                                 int image_height_px);

/// track3d_t::STATE_* as an enum (the wire has one state more than linking::TrackState).
enum class WireTrackState : std::int8_t {
  kTentative = 0,  ///< STATE_TENTATIVE
  kConfirmed = 1,  ///< STATE_CONFIRMED
  kLost = 2,       ///< STATE_LOST
  kEnded = 3,      ///< STATE_ENDED (last message for this id)
};

/// Wire fields of one track that tracker::Track3D has no place for.
struct WireTrackInfo {
  WireTrackState state = WireTrackState::kConfirmed;
  /// track3d_t.missed_frames, frames.
  std::int32_t missed_frames = 0;
};

/// A decoded tracks3d_t.
/// tracks3d_t.layer: the final (windowed) output or the provisional ("now") layer.
enum class TracksLayer {
  kFinal,        ///< LAYER_FINAL
  kProvisional,  ///< LAYER_PROVISIONAL (tracker::ProvisionalEstimator)
};

/// "final" or "provisional".
const char* ToString(TracksLayer layer);

struct TracksMessage {
  /// frame, utime and the tracks, in message order (producers sort by ascending id). Per track:
  /// id, position, confidence, cameras (camera_ids), age_frames, state (STATE_ENDED maps to
  /// linking::TrackState::kLost; the exact state is in `info`) and joints (valid joints as
  /// positions, invalid ones as nullopt; per-joint confidences are dropped).
  tracker::Frame3D frame;
  /// Layout of every track's joints; kNone in box mode.
  core::KeypointLayoutId layout = core::KeypointLayoutId::kNone;
  /// tracks3d_t.publish_utime, µs, tracker host clock.
  Utime publish_utime = 0;
  /// tracks3d_t.latency_us, µs.
  std::int64_t latency_us = 0;
  /// tracks3d_t.layer.
  TracksLayer layer = TracksLayer::kFinal;
  /// info[i] describes frame.tracks[i].
  std::vector<WireTrackInfo> info;
};

/// Result of DecodeTracks().
struct TracksDecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  std::string reason;     ///< empty when kOk; otherwise what, where, why
  TracksMessage message;  ///< valid only when kOk

  /// status == kOk.
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes a tracks3d_t from untrusted bytes (same guarantees as DecodeCameraDetections()).
/// Beyond the structure it checks what the message's own contract makes checkable without
/// geometry: a layer that is one of LAYER_*, a known keypoint_layout name ("" = box mode), a
/// state that is one of STATE_*, non-empty zone names, track zones that are ascending indices
/// of the message's zones, and
/// num_joints equal to 0 or to the layout's joint count and num_bones to 0 or its bone count
/// (always 0 in box mode).
TracksDecodeResult DecodeTracks(const void* data,
                                std::size_t size,
                                const DecodeLimits& limits = {});

/// Encodes one output frame as a tracks3d_t. Tracks are written sorted by ascending id (stable
/// for equal ids), camera ids ascending without duplicates, all num_* from sizes. State maps
/// kTentative/kConfirmed/kLost to STATE_TENTATIVE/CONFIRMED/LOST. missed_frames is written as
/// 0: Track3D carries no missed-frame count (the tracker only emits tracks supported in their
/// window). Joints: a valid joint has confidence 1 (the tracker estimates no per-joint
/// confidence), an invalid one is (0, 0, 0) with confidence 0 and valid = false. age_frames
/// saturates to the int32 range; doubles beyond the float range become +-infinity. `layer`:
/// tracks3d_t.layer. frame.zones become tracks3d_t.zones, each track's zones its zones
/// (ascending, no duplicates).
/// @pre every track has at most INT16_MAX cameras and joints, and its zones index frame.zones
/// (checked; aborts otherwise).
std::vector<std::uint8_t> EncodeTracks(const tracker::Frame3D& frame,
                                       core::KeypointLayoutId layout,
                                       Utime publish_utime,
                                       std::int64_t latency_us,
                                       TracksLayer layer = TracksLayer::kFinal);

/// One camera of a decoded tracker_status_t (the fields of camera_status_t,
/// lcmtypes/camera_status_t.lcm, with the same units and meaning).
struct CameraStatus {
  CameraId camera_id = 0;
  std::int64_t flags = 0;  ///< camera_status_t::FLAG_* bits (CameraFlagNames spells them)
  float rate_hz = 0.0f;
  std::int64_t last_utime = 0;
  std::int64_t last_receive_utime = 0;
  std::int64_t received = 0;
  std::int64_t late = 0;
  std::int64_t dropped = 0;
  std::int64_t rejected = 0;
  std::int64_t decode_errors = 0;
  std::int64_t lost = 0;
  std::int64_t clock_offset_us = 0;
  std::int64_t embeddings_dropped = 0;
  std::int32_t queue_depth = 0;
  std::int32_t queue_capacity = 0;
};

/// A decoded tracker_status_t (lcmtypes/tracker_status_t.lcm; same fields, units, meaning).
struct TrackerStatus {
  std::int64_t utime = 0;
  std::int64_t period_us = 0;
  std::int64_t uptime_us = 0;
  std::string instance_id;  ///< the sending daemon's random id (status_check.h StatusSourceWatch)
  std::int64_t start_utime = 0;
  std::int64_t sequence = 0;  ///< of this status within its instance, from 0
  std::string version;
  std::string config_hash;
  std::int64_t flags = 0;  ///< tracker_status_t::FLAG_* bits (TrackerFlagNames spells them)
  std::int64_t last_frame = -1;
  std::int32_t active_tracks = 0;
  std::int32_t confirmed_tracks = 0;
  std::int32_t num_latency_samples = 0;
  std::int64_t latency_p50_us = 0;
  std::int64_t latency_p99_us = 0;
  std::int64_t latency_max_us = 0;
  std::int64_t windows_processed = 0;
  std::int64_t jobs_failed = 0;
  std::int32_t executor_queue_depth = 0;
  std::int64_t kernel_drops = -1;
  std::int64_t embeddings_used = 0;
  std::int64_t embeddings_dropped = 0;
  std::int64_t tracks_revived = 0;
  std::int64_t gallery_bytes = 0;
  std::vector<CameraStatus> cameras;  ///< as in the message (the daemon sorts by camera id)
};

/// Result of DecodeTrackerStatus().
struct StatusDecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  std::string reason;     ///< empty when kOk; otherwise what, where, why
  TrackerStatus message;  ///< valid only when kOk

  /// status == kOk.
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes a tracker_status_t from untrusted bytes (same guarantees as
/// DecodeCameraDetections(); num_cameras is bounded by limits.max_cameras, the strings by
/// limits.max_string).
StatusDecodeResult DecodeTrackerStatus(const void* data,
                                       std::size_t size,
                                       const DecodeLimits& limits = {});

/// Encodes `status` as a tracker_status_t (num_cameras from the vector's size).
/// @pre at most INT16_MAX cameras (checked; aborts otherwise).
std::vector<std::uint8_t> EncodeTrackerStatus(const TrackerStatus& status);

/// The names of the camera_status_t::FLAG_* bits set in `flags` ("NO_DATA", "STALE", "LATE",
/// "DROPPING", "REJECTING", "DECODE_ERRORS", "CLOCK_OFFSET", "LOSING", "BAD_EMBEDDINGS"), in bit
/// order; an unknown bit n is named "BIT<n>".
std::vector<std::string> CameraFlagNames(std::int64_t flags);

/// The names of the tracker_status_t::FLAG_* bits set in `flags` ("CAMERA_MISSING",
/// "INPUT_LOSS", "BACKLOG", "LATENCY_HIGH", "JOB_FAILURES", "NO_OUTPUT"), in bit order; unknown
/// bits as
/// CameraFlagNames does.
std::vector<std::string> TrackerFlagNames(std::int64_t flags);

/// One zone of a decoded site_status_t (the fields of zone_status_t,
/// lcmtypes/zone_status_t.lcm, with the same units and meaning).
struct ZoneStatus {
  std::string name;
  std::string channel;
  std::int64_t flags = 0;  ///< zone_status_t::FLAG_* bits (ZoneFlagNames spells them)
  std::int64_t frames = 0;
  std::int64_t late = 0;
  std::int64_t decode_errors = 0;
  std::int64_t other_layer = 0;
  Utime last_utime = 0;
  Utime last_receive_utime = 0;
  std::int64_t latency_us = 0;
  std::int32_t tracks = 0;
  std::int8_t daemon_health = 3;  ///< zone_status_t::HEALTH_* (3: unknown)
  std::string daemon_reasons;     ///< at most kMaxDaemonReasons characters
  std::string daemon_instance_id;
};

/// Longest zone_status_t.daemon_reasons.
inline constexpr int kMaxDaemonReasons = 255;

/// A decoded site_status_t (lcmtypes/site_status_t.lcm; same fields, units, meaning).
struct SiteStatus {
  Utime utime = 0;
  std::int64_t period_us = 0;
  std::int64_t uptime_us = 0;
  std::string instance_id;
  Utime start_utime = 0;
  std::int64_t sequence = 0;
  std::string version;
  std::int64_t flags = 0;  ///< site_status_t::FLAG_* bits (SiteFlagNames spells them)
  std::int64_t last_frame = -1;
  std::int64_t site_frames = 0;
  std::int32_t active_tracks = 0;
  std::int64_t global_ids = 0;
  std::int64_t splits = 0;
  std::int64_t merges = 0;
  std::int32_t num_wait_samples = 0;
  std::int64_t wait_p50_us = 0;
  std::int64_t wait_p99_us = 0;
  std::int64_t wait_max_us = 0;
  std::vector<ZoneStatus> zones;
};

/// Result of DecodeSiteStatus().
struct SiteStatusDecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  std::string reason;  ///< empty when kOk; otherwise what, where, why
  SiteStatus message;  ///< valid only when kOk
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes a site_status_t from untrusted bytes (same guarantees as DecodeCameraDetections();
/// num_zones bounded by limits.max_zones, strings by limits.max_string, daemon_reasons by
/// kMaxDaemonReasons; daemon_health one of HEALTH_*).
SiteStatusDecodeResult DecodeSiteStatus(const void* data,
                                        std::size_t size,
                                        const DecodeLimits& limits = {});

/// Encodes `status` as a site_status_t.
/// @pre at most INT16_MAX zones, daemon_health one of HEALTH_* (checked; aborts otherwise).
std::vector<std::uint8_t> EncodeSiteStatus(const SiteStatus& status);

/// The names of the site_status_t::FLAG_* bits set in `flags` ("ZONE_MISSING", "INPUT_LOSS",
/// "ZONE_DEGRADED", "NO_OUTPUT"), in bit order; unknown bits as CameraFlagNames does.
std::vector<std::string> SiteFlagNames(std::int64_t flags);

/// The names of the zone_status_t::FLAG_* bits set in `flags` ("NO_DATA", "STALE", "LATE",
/// "DECODE_ERRORS", "DEGRADED"), in bit order; unknown bits as CameraFlagNames does.
std::vector<std::string> ZoneFlagNames(std::int64_t flags);

/// A decoded analytics_event_t (lcmtypes/analytics_event_t.lcm; same fields and units).
struct AnalyticsEventMessage {
  Utime utime = 0;
  Utime publish_utime = 0;
  analytics::Event::Kind kind = analytics::Event::Kind::kEnter;
  std::string name;
  TrackId3D track_id = 0;
  Utime enter_utime = 0;
  analytics::Event::Direction direction = analytics::Event::Direction::kLeftToRight;
  bool track_ended = false;
};

/// Result of DecodeAnalyticsEvent().
struct AnalyticsEventDecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  std::string reason;             ///< empty when kOk; otherwise what, where, why
  AnalyticsEventMessage message;  ///< valid only when kOk
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes an analytics_event_t from untrusted bytes (same guarantees as
/// DecodeCameraDetections(); the name bounded by limits.max_string, kind and direction one of
/// their constants).
AnalyticsEventDecodeResult DecodeAnalyticsEvent(const void* data,
                                                std::size_t size,
                                                const DecodeLimits& limits = {});

/// Encodes one event as an analytics_event_t.
std::vector<std::uint8_t> EncodeAnalyticsEvent(const AnalyticsEventMessage& event);

/// The analytics_event_t of `event` (times in seconds of capture time, as lib/analytics keeps
/// them, rounded to µs) for a site whose regions and lines are `site`'s.
AnalyticsEventMessage ToAnalyticsEventMessage(const analytics::Event& event,
                                              const analytics::Site& site,
                                              Utime publish_utime);

/// A decoded site_counts_t (lcmtypes/site_counts_t.lcm).
struct SiteCounts {
  Utime utime = 0;
  Utime publish_utime = 0;
  std::vector<std::string> region_names;
  std::vector<analytics::RegionCounts> regions;  ///< by region, as region_names
  std::vector<std::string> line_names;
  std::vector<analytics::LineCounts> lines;  ///< by line, as line_names
};

/// Result of DecodeSiteCounts().
struct SiteCountsDecodeResult {
  DecodeStatus status = DecodeStatus::kMalformed;
  std::string reason;  ///< empty when kOk; otherwise what, where, why
  SiteCounts message;  ///< valid only when kOk
  bool ok() const { return status == DecodeStatus::kOk; }
};

/// Decodes a site_counts_t from untrusted bytes (same guarantees as DecodeCameraDetections();
/// num_regions and num_lines bounded by limits.max_site_items, names by limits.max_string).
SiteCountsDecodeResult DecodeSiteCounts(const void* data,
                                        std::size_t size,
                                        const DecodeLimits& limits = {});

/// Encodes `counts` as a site_counts_t.
/// @pre names and counts of equal sizes, at most INT16_MAX each (checked; aborts otherwise).
std::vector<std::uint8_t> EncodeSiteCounts(const SiteCounts& counts);

}  // namespace mvtrack::transport
