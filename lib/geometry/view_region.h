#pragma once
/// @file
/// Where a camera can see a horizontal plane, and whether two cameras can see one place
/// (issue 43: on a site with many cameras most pairs never see the same person, and an
/// epipolar-consistent pair of tracklets of two such cameras is a coincidence). Pure geometry.

#include <vector>

#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::geometry {

/// A half-plane of the plane z = const: a x + b y + c >= 0.
struct HalfPlane {
  double a = 0.0, b = 0.0, c = 0.0;
};

/// The part of the plane z = `plane_z` that `camera` sees within `max_range_m` along its optical
/// axis, as half-planes: the four sides of its image (widened by `margin` of the image size on
/// each side, for lens distortion the pinhole frustum ignores), in front of the camera, and
/// the far limit. Their intersection is convex (possibly empty).
std::vector<HalfPlane> ViewOnPlane(const CameraModel& camera,
                                   double plane_z,
                                   double max_range_m,
                                   double margin = 0.05);

/// The area of the intersection of the half-planes `a` and `b` (m² when x, y are metres), within
/// a square of half-size `extent` around (cx, cy).
double IntersectionArea(const std::vector<HalfPlane>& a,
                        const std::vector<HalfPlane>& b,
                        double cx,
                        double cy,
                        double extent);

}  // namespace mvtrack::geometry
