// tracks3d_t <-> tracker::Frame3D.

#include <algorithm>
#include <climits>
#include <cstdint>
#include <exception>
#include <mvtrack/joint3d_t.hpp>
#include <mvtrack/track3d_t.hpp>
#include <mvtrack/tracks3d_t.hpp>
#include <numeric>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "core/keypoint_layout.h"
#include "transport/codec.h"
#include "transport/internal/wire_walker.h"

namespace mvtrack::transport {
namespace {

using internal::kDoubleBytes;
using internal::kFloatBytes;
using internal::kInt16Bytes;
using internal::kInt32Bytes;
using internal::kInt64Bytes;
using internal::kInt8Bytes;
using internal::WireWalker;

// Encoded sizes (lcmtypes/README.md): joint3d_t = 3 doubles, a float and a boolean; the
// smallest track3d_t has no cameras and no joints.
constexpr std::size_t kJointBytes = 3 * kDoubleBytes + kFloatBytes + kInt8Bytes;
constexpr std::size_t kMinTrackBytes =
    kInt64Bytes + kInt8Bytes + 3 * kDoubleBytes + kFloatBytes + 2 * kInt32Bytes + 4 * kInt16Bytes;
using internal::kMinStringBytes;

using internal::LayoutOfName;

bool IsWireState(std::int8_t state) {
  return state >= mvtrack::track3d_t::STATE_TENTATIVE && state <= mvtrack::track3d_t::STATE_ENDED;
}

// Walks one track3d_t; `layout_joints` and `layout_bones` are the joint and bone counts of the
// message's layout (0 in box mode), `site_zones` the message's num_zones.
bool WalkTrack(WireWalker* w,
               const DecodeLimits& limits,
               int layout_joints,
               int layout_bones,
               std::int32_t site_zones,
               std::int32_t index) {
  std::int64_t id = 0;
  if (!w->ReadInt64("id", &id)) return false;
  w->set_context("track " + std::to_string(index) + " (id " + std::to_string(id) + ")");
  const std::size_t state_at = w->position();
  std::int8_t state = 0;
  if (!w->ReadInt8("state", &state)) return false;
  if (!IsWireState(state)) {
    return w->Fail(DecodeStatus::kMalformed,
                   "state " + std::to_string(static_cast<int>(state)) +
                       " is not one of track3d_t::STATE_* (0..3)",
                   state_at);
  }
  w->Skip("position", 3 * kDoubleBytes);
  w->Skip("confidence", kFloatBytes);
  w->Skip("age_frames", kInt32Bytes);
  w->Skip("missed_frames", kInt32Bytes);
  std::int32_t num_cameras = 0;
  if (!w->ReadCount16("num_cameras", limits.max_cameras, kInt32Bytes, &num_cameras)) {
    return false;
  }
  w->Skip("camera_ids", static_cast<std::size_t>(num_cameras) * kInt32Bytes);
  const std::size_t joints_at = w->position();
  std::int32_t num_joints = 0;
  if (!w->ReadCount16("num_joints", limits.max_joints, kJointBytes, &num_joints)) return false;
  if (num_joints != 0 && num_joints != layout_joints) {
    return w->Fail(DecodeStatus::kMalformed,
                   "num_joints " + std::to_string(num_joints) + " is neither 0 nor the " +
                       std::to_string(layout_joints) + " joints of the message's layout",
                   joints_at);
  }
  if (!w->Skip("joints", static_cast<std::size_t>(num_joints) * kJointBytes)) return false;
  const std::size_t bones_at = w->position();
  std::int32_t num_bones = 0;
  if (!w->ReadCount16("num_bones", limits.max_joints, kFloatBytes, &num_bones)) return false;
  if (num_bones != 0 && num_bones != layout_bones) {
    return w->Fail(DecodeStatus::kMalformed,
                   "num_bones " + std::to_string(num_bones) + " is neither 0 nor the " +
                       std::to_string(layout_bones) + " bones of the message's layout",
                   bones_at);
  }
  if (!w->Skip("bone_lengths", static_cast<std::size_t>(num_bones) * kFloatBytes)) return false;
  std::int32_t num_zones = 0;
  if (!w->ReadCount16("num_zones", limits.max_zones, kInt16Bytes, &num_zones)) return false;
  std::int32_t previous = -1;
  for (std::int32_t i = 0; i < num_zones; ++i) {
    const std::size_t zone_at = w->position();
    std::int16_t zone = 0;
    if (!w->ReadInt16("zones", &zone)) return false;
    if (zone <= previous || zone >= site_zones) {
      return w->Fail(DecodeStatus::kMalformed,
                     "zones[" + std::to_string(i) + "] = " + std::to_string(zone) +
                         (zone >= site_zones ? " is not an index of the message's " +
                                                   std::to_string(site_zones) + " zones"
                                             : " is not ascending without duplicates"),
                     zone_at);
    }
    previous = zone;
  }
  return true;
}

bool WalkTracks(WireWalker* w, const DecodeLimits& limits) {
  if (!internal::WalkFingerprint(
          w, mvtrack::tracks3d_t::getHash(), mvtrack::tracks3d_t::getTypeName())) {
    return false;
  }
  w->Skip("utime", kInt64Bytes);
  w->Skip("frame", kInt64Bytes);
  w->Skip("publish_utime", kInt64Bytes);
  w->Skip("latency_us", kInt64Bytes);
  const std::size_t layer_at = w->position();
  std::int8_t layer = 0;
  if (!w->ReadInt8("layer", &layer)) return false;
  if (layer != mvtrack::tracks3d_t::LAYER_FINAL &&
      layer != mvtrack::tracks3d_t::LAYER_PROVISIONAL) {
    return w->Fail(DecodeStatus::kMalformed,
                   "layer " + std::to_string(static_cast<int>(layer)) +
                       " is not LAYER_FINAL (0) or LAYER_PROVISIONAL (1)",
                   layer_at);
  }
  const std::size_t layout_at = w->position();
  std::string_view layout_name;
  if (!w->ReadString("keypoint_layout", limits.max_string, &layout_name)) return false;
  const std::optional<core::KeypointLayoutId> layout = LayoutOfName(layout_name);
  if (!layout) {
    return w->Fail(DecodeStatus::kMalformed,
                   "unknown keypoint_layout \"" + std::string(layout_name) + "\"",
                   layout_at);
  }
  const int layout_joints = core::GetKeypointLayout(*layout).num_joints();
  const auto layout_bones = static_cast<int>(core::GetKeypointLayout(*layout).bones.size());
  std::int32_t num_zones = 0;
  if (!w->ReadCount16("num_zones", limits.max_zones, kMinStringBytes, &num_zones)) return false;
  for (std::int32_t i = 0; i < num_zones; ++i) {
    const std::size_t zone_at = w->position();
    std::string_view zone;
    if (!w->ReadString("zones", limits.max_string, &zone)) return false;
    if (zone.empty()) {
      return w->Fail(DecodeStatus::kMalformed,
                     "zones[" + std::to_string(i) + "] is an empty zone name",
                     zone_at);
    }
  }
  std::int32_t num_tracks = 0;
  if (!w->ReadCount32("num_tracks", limits.max_tracks, kMinTrackBytes, &num_tracks)) {
    return false;
  }
  for (std::int32_t i = 0; i < num_tracks; ++i) {
    w->set_context("track " + std::to_string(i));
    if (!WalkTrack(w, limits, layout_joints, layout_bones, num_zones, i)) return false;
  }
  w->set_context("");
  if (w->remaining() > 0) {
    return w->Fail(DecodeStatus::kMalformed,
                   std::to_string(w->remaining()) + " trailing bytes after the message",
                   w->position());
  }
  return true;
}

linking::TrackState ToTrackState(WireTrackState state) {
  switch (state) {
    case WireTrackState::kTentative:
      return linking::TrackState::kTentative;
    case WireTrackState::kConfirmed:
      return linking::TrackState::kConfirmed;
    case WireTrackState::kLost:
    case WireTrackState::kEnded:
      return linking::TrackState::kLost;
  }
  return linking::TrackState::kLost;
}

std::int8_t ToWireState(linking::TrackState state) {
  switch (state) {
    case linking::TrackState::kTentative:
      return mvtrack::track3d_t::STATE_TENTATIVE;
    case linking::TrackState::kConfirmed:
      return mvtrack::track3d_t::STATE_CONFIRMED;
    case linking::TrackState::kLost:
      return mvtrack::track3d_t::STATE_LOST;
  }
  return mvtrack::track3d_t::STATE_LOST;
}

std::int32_t SaturateToInt32(std::int64_t value) {
  return static_cast<std::int32_t>(
      std::clamp<std::int64_t>(value, std::int64_t{INT32_MIN}, std::int64_t{INT32_MAX}));
}

}  // namespace

TracksDecodeResult DecodeTracks(const void* data, std::size_t size, const DecodeLimits& limits) {
  TracksDecodeResult result;
  const auto convert = [&](const mvtrack::tracks3d_t& msg) {
    TracksMessage& out = result.message;
    out.frame.frame = msg.frame;
    out.frame.utime = msg.utime;
    out.publish_utime = msg.publish_utime;
    out.latency_us = msg.latency_us;
    out.layer = msg.layer == mvtrack::tracks3d_t::LAYER_PROVISIONAL ? TracksLayer::kProvisional
                                                                    : TracksLayer::kFinal;
    out.layout = LayoutOfName(msg.keypoint_layout).value_or(core::KeypointLayoutId::kNone);
    out.frame.zones = msg.zones;
    out.frame.tracks.reserve(msg.tracks.size());
    out.info.reserve(msg.tracks.size());
    for (const mvtrack::track3d_t& t : msg.tracks) {
      WireTrackInfo info;
      info.state = static_cast<WireTrackState>(t.state);  // the walk checked the range
      info.missed_frames = t.missed_frames;
      tracker::Track3D track;
      track.id = t.id;
      track.state = ToTrackState(info.state);
      track.position = Vec3(t.position[0], t.position[1], t.position[2]);
      track.confidence = static_cast<double>(t.confidence);
      track.age_frames = t.age_frames;
      track.cameras.assign(t.camera_ids.begin(), t.camera_ids.end());
      track.joints.reserve(t.joints.size());
      for (const mvtrack::joint3d_t& j : t.joints) {
        if (j.valid != 0) {
          track.joints.emplace_back(Vec3(j.position[0], j.position[1], j.position[2]));
        } else {
          track.joints.emplace_back(std::nullopt);
        }
      }
      track.bone_lengths.assign(t.bone_lengths.begin(), t.bone_lengths.end());
      track.zones.assign(t.zones.begin(), t.zones.end());
      out.frame.tracks.push_back(std::move(track));
      out.info.push_back(info);
    }
  };
  if (!internal::CheckedDecode<mvtrack::tracks3d_t>(
          data, size, limits, WalkTracks, convert, &result.status, &result.reason)) {
    TracksDecodeResult failed;  // nothing partially converted leaks out
    failed.status = result.status;
    failed.reason = std::move(result.reason);
    return failed;
  }
  return result;
}

std::vector<std::uint8_t> EncodeTracks(const tracker::Frame3D& frame,
                                       core::KeypointLayoutId layout,
                                       Utime publish_utime,
                                       std::int64_t latency_us,
                                       TracksLayer layer) {
  using internal::NarrowToFloat;
  MVTRACK_CHECK_MSG(frame.tracks.size() <= static_cast<std::size_t>(INT32_MAX),
                    "too many tracks for tracks3d_t");
  mvtrack::tracks3d_t msg;
  msg.utime = frame.utime;
  msg.frame = frame.frame;
  msg.publish_utime = publish_utime;
  msg.latency_us = latency_us;
  msg.layer = layer == TracksLayer::kProvisional ? mvtrack::tracks3d_t::LAYER_PROVISIONAL
                                                 : mvtrack::tracks3d_t::LAYER_FINAL;
  msg.keypoint_layout = layout == core::KeypointLayoutId::kNone
                            ? std::string()
                            : core::GetKeypointLayout(layout).name;
  MVTRACK_CHECK_MSG(frame.zones.size() <= static_cast<std::size_t>(INT16_MAX),
                    "too many zones for tracks3d_t");
  msg.num_zones = static_cast<std::int16_t>(frame.zones.size());
  msg.zones = frame.zones;
  msg.num_tracks = static_cast<std::int32_t>(frame.tracks.size());

  std::vector<std::size_t> order(frame.tracks.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&frame](std::size_t a, std::size_t b) {
    return frame.tracks[a].id < frame.tracks[b].id;
  });
  msg.tracks.reserve(frame.tracks.size());
  for (std::size_t index : order) {
    const tracker::Track3D& track = frame.tracks[index];
    std::vector<CameraId> cameras = track.cameras;
    std::sort(cameras.begin(), cameras.end());
    cameras.erase(std::unique(cameras.begin(), cameras.end()), cameras.end());
    MVTRACK_CHECK_MSG(cameras.size() <= static_cast<std::size_t>(INT16_MAX),
                      "too many cameras for track3d_t");
    MVTRACK_CHECK_MSG(track.joints.size() <= static_cast<std::size_t>(INT16_MAX) &&
                          track.bone_lengths.size() <= static_cast<std::size_t>(INT16_MAX),
                      "too many joints or bones for track3d_t");
    mvtrack::track3d_t t;
    t.id = track.id;
    t.state = ToWireState(track.state);
    t.position[0] = track.position.x();
    t.position[1] = track.position.y();
    t.position[2] = track.position.z();
    t.confidence = NarrowToFloat(track.confidence);
    t.age_frames = SaturateToInt32(track.age_frames);
    t.missed_frames = 0;
    t.num_cameras = static_cast<std::int16_t>(cameras.size());
    t.camera_ids = std::move(cameras);
    t.num_joints = static_cast<std::int16_t>(track.joints.size());
    t.joints.reserve(track.joints.size());
    for (const std::optional<Vec3>& joint : track.joints) {
      mvtrack::joint3d_t j;
      j.position[0] = joint ? joint->x() : 0.0;
      j.position[1] = joint ? joint->y() : 0.0;
      j.position[2] = joint ? joint->z() : 0.0;
      j.confidence = joint ? 1.0f : 0.0f;
      j.valid = joint ? 1 : 0;
      t.joints.push_back(j);
    }
    t.num_bones = static_cast<std::int16_t>(track.bone_lengths.size());
    t.bone_lengths.reserve(track.bone_lengths.size());
    for (const double length : track.bone_lengths) t.bone_lengths.push_back(NarrowToFloat(length));
    std::vector<int> zones = track.zones;
    std::sort(zones.begin(), zones.end());
    zones.erase(std::unique(zones.begin(), zones.end()), zones.end());
    for (const int zone : zones) {
      MVTRACK_CHECK_MSG(zone >= 0 && static_cast<std::size_t>(zone) < frame.zones.size(),
                        "a track's zone is not one of the frame's zones");
      t.zones.push_back(static_cast<std::int16_t>(zone));
    }
    t.num_zones = static_cast<std::int16_t>(t.zones.size());
    msg.tracks.push_back(std::move(t));
  }
  return internal::EncodeMessage(msg);
}

}  // namespace mvtrack::transport
