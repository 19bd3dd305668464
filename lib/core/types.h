#pragma once
/// @file
/// Basic identifiers and geometric aliases shared by every module. Eigen only.

#include <Eigen/Core>
#include <cstdint>
#include <numbers>

namespace mvtrack {

/// Radians per degree.
inline constexpr double kDeg = std::numbers::pi / 180.0;

/// Capture time in microseconds since the Unix epoch (the `utime` of every LCM message).
using Utime = std::int64_t;
/// Frame index of a synchronized multi-camera capture (monotonic, may have gaps).
using FrameIndex = std::int64_t;
/// Camera identifier as configured (any non-negative int; not necessarily dense).
using CameraId = std::int32_t;
/// Identifier of a 2D track inside one camera's SortTracker.
using TrackId2D = std::int64_t;
/// Identifier of a long-term 3D track (unique per Tracker instance, starts at 1).
using TrackId3D = std::int64_t;

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat34 = Eigen::Matrix<double, 3, 4>;

}  // namespace mvtrack
