#pragma once
/// @file
/// Test-only helpers for the transport tests: realistic frames (every value exactly
/// representable as a float, so encode -> decode is lossless), reference conversions to the
/// generated LCM types written independently of lib/transport, field offsets of encoded messages
/// computed from the .lcm schemas, byte patching, and field-by-field comparisons.

#include <cstddef>
#include <cstdint>
#include <mvtrack/camera_detections_t.hpp>
#include <mvtrack/tracks3d_t.hpp>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "tracker/types.h"

namespace mvtrack::transport::testing {

/// Five detections of one camera: box only; COCO-17 pose; COCO-17 pose with a 16-d embedding;
/// BODY-25 pose; box only. Deterministic for a seed.
core::CameraFrame MakeRealisticFrame(std::uint32_t seed);

/// Four tracks with ids 7, 3, 12, 5 (not sorted), 1-3 cameras each (unsorted, one duplicate).
/// Pose mode: COCO-17 joints, some nullopt; box mode: no joints. Every value is a float.
tracker::Frame3D MakeTracksFrame(std::uint32_t seed, bool pose);

/// Reference conversion to the generated type (counts from sizes, "" for kNone).
mvtrack::camera_detections_t ToLcm(const core::CameraFrame& frame, int width, int height);

/// Encodes a generated message with its own encoder.
template <typename Msg>
std::vector<std::uint8_t> EncodeLcm(const Msg& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  const int n = msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  if (n != static_cast<int>(bytes.size())) bytes.clear();
  return bytes;
}

/// Byte offsets of the variable-length fields of one encoded detection_t.
struct DetectionOffsets {
  std::size_t start = 0;            ///< first byte (x_min)
  std::size_t keypoint_layout = 0;  ///< int32 length of keypoint_layout
  std::size_t num_keypoints = 0;    ///< int16
  std::size_t embedding_model = 0;  ///< int32 length of embedding_model
  std::size_t num_embedding = 0;    ///< int16
};

/// Offsets in an encoded camera_detections_t (fingerprint included), derived from the .lcm
/// schema; `total` is the encoded size.
struct CameraDetectionsOffsets {
  std::size_t num_detections = 0;  ///< int32
  std::vector<DetectionOffsets> detections;
  std::size_t total = 0;
};
CameraDetectionsOffsets OffsetsOf(const mvtrack::camera_detections_t& msg);

/// Byte offsets of one encoded track3d_t.
struct TrackOffsets {
  std::size_t start = 0;        ///< id
  std::size_t state = 0;        ///< int8
  std::size_t num_cameras = 0;  ///< int16
  std::size_t num_joints = 0;   ///< int16
  std::size_t num_bones = 0;    ///< int16
  std::size_t num_zones = 0;    ///< int16
};

/// Offsets in an encoded tracks3d_t.
struct Tracks3dOffsets {
  std::size_t keypoint_layout = 0;  ///< int32 length
  std::size_t num_zones = 0;        ///< int16
  std::size_t num_tracks = 0;       ///< int32
  std::vector<TrackOffsets> tracks;
  std::size_t total = 0;
};
Tracks3dOffsets OffsetsOf(const mvtrack::tracks3d_t& msg);

/// Writes `value` big-endian into `width` bytes at `offset`.
void PutBigEndian(std::vector<std::uint8_t>* bytes,
                  std::size_t offset,
                  std::uint64_t value,
                  std::size_t width);

/// "" when equal (doubles and floats compared bit for bit, so NaN == NaN), else the first
/// difference.
std::string DiffCameraFrames(const core::CameraFrame& a, const core::CameraFrame& b);
std::string DiffFrames3D(const tracker::Frame3D& a, const tracker::Frame3D& b);

}  // namespace mvtrack::transport::testing
