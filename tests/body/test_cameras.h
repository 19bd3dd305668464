#pragma once
// Cameras of the body tests: a ring around a person standing at the origin.

#include <cmath>

#include "core/types.h"

namespace mvtrack::body::testing {

// A camera 4 m away at `azimuth` (radians), 1.5 m high, looking at (0, 0, 1): K [R | t],
// f = 1000 px, principal point (640, 360).
inline Mat34 RingCamera(double azimuth) {
  const Vec3 c(4.0 * std::cos(azimuth), 4.0 * std::sin(azimuth), 1.5);
  const Vec3 z = (Vec3(0, 0, 1.0) - c).normalized();
  const Vec3 x = z.cross(Vec3(0, 0, 1)).normalized();
  const Vec3 y = z.cross(x);
  Mat3 r;
  r.row(0) = x.transpose();
  r.row(1) = y.transpose();
  r.row(2) = z.transpose();
  Mat3 k;
  k << 1000, 0, 640, 0, 1000, 360, 0, 0, 1;
  Mat34 rt;
  rt.leftCols<3>() = r;
  rt.col(3) = -r * c;
  return k * rt;
}

}  // namespace mvtrack::body::testing
