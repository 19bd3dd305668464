#pragma once
/// @file
/// Deterministic sample messages of every mvtrack LCM type, and a canonical text dump of each
/// type that DecodeLog.java and decode_log.py print too, so C++, Java and Python decoding can be
/// compared byte for byte.
///
/// Dump format, one line per primitive value: `<path>=<value>`. Fields are sorted by name (ASCII
/// order) at every nesting level; array elements appear in index order as `name[i]`, nested
/// struct fields as `name.field` / `name[i].field`. Integers print in decimal, booleans as
/// `true`/`false`, floats and doubles as `0x` + 16 hex digits of the IEEE-754 bits of the value
/// widened to double (exact, locale-free), strings as `"..."` with bytes outside printable ASCII
/// and `"`/`\` escaped as `\xHH`.

#include <cstdint>
#include <mvtrack/camera_detections_t.hpp>
#include <mvtrack/camera_status_t.hpp>
#include <mvtrack/detection_t.hpp>
#include <mvtrack/joint3d_t.hpp>
#include <mvtrack/keypoint2d_t.hpp>
#include <mvtrack/site_status_t.hpp>
#include <mvtrack/track3d_t.hpp>
#include <mvtrack/tracker_status_t.hpp>
#include <mvtrack/tracks3d_t.hpp>
#include <mvtrack/zone_status_t.hpp>
#include <string>
#include <vector>

namespace mvtrack::lcmtypes_test {

/// What a detection carries besides its box and score.
enum class DetectionKind {
  kPoseAndEmbedding,  ///< coco17 keypoints (some undetected) and a 64-d embedding
  kPoseOnly,          ///< body25 keypoints, no embedding
  kBoxOnly,           ///< neither
};

/// Sample builders: every call with the same arguments returns the same message; different
/// seeds give different values. Contents are realistic (pixels inside a 1920x1080 image,
/// metres inside a 10 m room, sorted ids) and non-trivial (negative coordinates, undetected
/// joints, 64-bit counters beyond 2^32, non-empty strings).
keypoint2d_t MakeKeypoint2d(std::uint32_t seed);
detection_t MakeDetection(std::uint32_t seed, DetectionKind kind);
/// Three detections (one of each DetectionKind) unless `num_detections` says otherwise
/// (kinds cycle in that order).
camera_detections_t MakeCameraDetections(std::uint32_t seed,
                                         std::int32_t camera_id,
                                         int num_detections = 3);
joint3d_t MakeJoint3d(std::uint32_t seed, bool valid);
/// A track with `num_joints` coco17 joints (0 = box mode), supported by 1-3 cameras.
track3d_t MakeTrack3d(std::uint32_t seed, std::int64_t id, std::int8_t state, int num_joints);
/// Tracks with ids 1..num_tracks in states CONFIRMED, LOST, TENTATIVE, ...; with `with_joints`
/// the layout is "coco17" and every track has 17 joints, otherwise box mode ("" and 0 joints).
tracks3d_t MakeTracks3d(std::uint32_t seed, int num_tracks, bool with_joints);
camera_status_t MakeCameraStatus(std::uint32_t seed, std::int32_t camera_id);
tracker_status_t MakeTrackerStatus(std::uint32_t seed, int num_cameras);
zone_status_t MakeZoneStatus(std::uint32_t seed, const std::string& name, bool stale);
site_status_t MakeSiteStatus(std::uint32_t seed, int num_zones);

/// Canonical dumps (format in the file comment); `prefix` is prepended to every path.
std::string Dump(const keypoint2d_t& msg, const std::string& prefix = "");
std::string Dump(const detection_t& msg, const std::string& prefix = "");
std::string Dump(const camera_detections_t& msg, const std::string& prefix = "");
std::string Dump(const joint3d_t& msg, const std::string& prefix = "");
std::string Dump(const track3d_t& msg, const std::string& prefix = "");
std::string Dump(const tracks3d_t& msg, const std::string& prefix = "");
std::string Dump(const camera_status_t& msg, const std::string& prefix = "");
std::string Dump(const tracker_status_t& msg, const std::string& prefix = "");
std::string Dump(const zone_status_t& msg, const std::string& prefix = "");
std::string Dump(const site_status_t& msg, const std::string& prefix = "");

/// Encodes `msg` (fingerprint included) into exactly getEncodedSize() bytes.
template <typename Msg>
std::vector<std::uint8_t> Encode(const Msg& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  const int written = msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  bytes.resize(written < 0 ? 0 : static_cast<std::size_t>(written));
  return bytes;
}

/// One message of the sample log.
struct SampleEvent {
  std::string channel;
  std::string type_name;            ///< getTypeName(), e.g. "camera_detections_t"
  std::int64_t fingerprint = 0;     ///< getHash()
  std::vector<std::uint8_t> bytes;  ///< the encoded message
  std::string dump;                 ///< Dump() of the message
};

/// The sample log's messages, in publish order: every type at least once, top-level types with
/// several variants (three cameras with poses, a camera frame with no detections, pose-mode,
/// box-mode and empty track frames, tracker status before and after the first output).
std::vector<SampleEvent> MakeSampleEvents();

/// The text DecodeLog.java and decode_log.py print for a log holding `events`: for each event
/// `event <index> channel=<channel> type=<type_name>` followed by its dump.
std::string DumpEvents(const std::vector<SampleEvent>& events);

}  // namespace mvtrack::lcmtypes_test
