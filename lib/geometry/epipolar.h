#pragma once
/// @file
/// Epipolar geometry and the paper's normalized epipolar distance (Eq. 1-2). Stateless.

#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::geometry {

/// Fundamental matrix F with x_to^T F x_from = 0 for undistorted pixels: F * x_from is the
/// epipolar line of x_from in camera `to` (F_{c_from, c_to} in the paper's notation).
/// Normalised to unit Frobenius norm. Cameras with (numerically) coincident centres have no
/// epipolar geometry: the zero matrix is returned, and every distance computed with it is +inf.
Mat3 FundamentalMatrix(const CameraModel& from, const CameraModel& to);

/// Euclidean distance in pixels from point `x` to the line (a, b, c): a x + b y + c = 0.
double PointLineDistance(const Vec2& x, const Vec3& line);

/// Symmetric epipolar distance of Eq. 1 (pixels): d(x_i, F_ji x_j) + d(x_j, F_ij x_i),
/// where `f_i_to_j` maps points of camera i to lines in camera j (F_ji = f_i_to_j^T).
double SymmetricEpipolarDistance(const Vec2& x_i, const Vec2& x_j, const Mat3& f_i_to_j);

/// Normalized epipolar distance of Eq. 2: each one-sided distance divided by the person's
/// scale |w + h| in that view, which makes it independent of the person-to-camera distance.
double NormalizedEpipolarDistance(
    const Vec2& x_i, double scale_i_px, const Vec2& x_j, double scale_j_px, const Mat3& f_i_to_j);

}  // namespace mvtrack::geometry
