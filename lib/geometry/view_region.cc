#include "geometry/view_region.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace mvtrack::geometry {
namespace {

// Clips a convex polygon by a half-plane (Sutherland-Hodgman, one edge).
std::vector<Vec2> Clip(const std::vector<Vec2>& polygon, const HalfPlane& h) {
  std::vector<Vec2> out;
  const auto value = [&h](const Vec2& p) { return h.a * p.x() + h.b * p.y() + h.c; };
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % polygon.size()];
    const double vp = value(p), vq = value(q);
    if (vp >= 0.0) out.push_back(p);
    if ((vp >= 0.0) != (vq >= 0.0)) out.push_back(p + (q - p) * (vp / (vp - vq)));
  }
  return out;
}

}  // namespace

std::vector<HalfPlane> ViewOnPlane(const CameraModel& camera,
                                   double plane_z,
                                   double max_range_m,
                                   double margin) {
  const Mat3& r = camera.cam_from_world.rotation;
  const Vec3& t = camera.cam_from_world.translation;
  // A point (x, y, plane_z) in camera coordinates: P = r.col(0) x + r.col(1) y + offset.
  const Vec3 offset = r.col(2) * plane_z + t;
  const auto half_plane = [&](const Vec3& n, double shift) {
    return HalfPlane{n.dot(r.col(0)), n.dot(r.col(1)), n.dot(offset) + shift};
  };
  const double w = camera.width_px, h = camera.height_px;
  const double mx = margin * w, my = margin * h;
  const Mat3 k_inv = camera.K.inverse();
  const Vec3 corners[4] = {k_inv * Vec3(-mx, -my, 1.0),
                           k_inv * Vec3(w + mx, -my, 1.0),
                           k_inv * Vec3(w + mx, h + my, 1.0),
                           k_inv * Vec3(-mx, h + my, 1.0)};
  std::vector<HalfPlane> planes;
  for (int i = 0; i < 4; ++i) {
    Vec3 n = corners[i].cross(corners[(i + 1) % 4]);
    if (n.z() < 0.0) n = -n;  // the optical axis (0, 0, 1) is inside
    planes.push_back(half_plane(n, 0.0));
  }
  planes.push_back(half_plane(Vec3(0.0, 0.0, 1.0), -0.05));         // in front
  planes.push_back(half_plane(Vec3(0.0, 0.0, -1.0), max_range_m));  // not beyond the range
  return planes;
}

double IntersectionArea(const std::vector<HalfPlane>& a,
                        const std::vector<HalfPlane>& b,
                        double cx,
                        double cy,
                        double extent) {
  std::vector<Vec2> polygon = {Vec2(cx - extent, cy - extent),
                               Vec2(cx + extent, cy - extent),
                               Vec2(cx + extent, cy + extent),
                               Vec2(cx - extent, cy + extent)};
  for (const std::vector<HalfPlane>* set : {&a, &b}) {
    for (const HalfPlane& h : *set) {
      polygon = Clip(polygon, h);
      if (polygon.size() < 3) return 0.0;
    }
  }
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % polygon.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(0.5 * twice);
}

}  // namespace mvtrack::geometry
