#include "sim/body.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mvtrack::sim {
namespace {

// COCO-17 indices.
enum Joint : int {
  kNose = 0,
  kLEye,
  kREye,
  kLEar,
  kREar,
  kLShoulder,
  kRShoulder,
  kLElbow,
  kRElbow,
  kLWrist,
  kRWrist,
  kLHip,
  kRHip,
  kLKnee,
  kRKnee,
  kLAnkle,
  kRAnkle,
};

// Plain 3-vector for the per-joint arithmetic: this code runs for every person every frame, and
// Eigen's expression templates are very slow in unoptimised (debug) builds.
struct P3 {
  double x, y, z;
};
P3 operator+(const P3& a, const P3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator*(double s, const P3& a) { return {s * a.x, s * a.y, s * a.z}; }
Vec3 ToVec3(const P3& a) { return Vec3(a.x, a.y, a.z); }

// Body axes in the world: forward, left, up.
struct Axes {
  P3 forward;
  P3 left;
  P3 up;
};

Axes AxesOf(double heading_rad) {
  const double c = std::cos(heading_rad), s = std::sin(heading_rad);
  return {{c, s, 0.0}, {-s, c, 0.0}, {0.0, 0.0, 1.0}};
}

// Unit direction of a limb hanging down, abducted by `abduction` towards `side` (+left / -left)
// and flexed forward by `flexion` in the (down, forward) plane. The two components are
// orthogonal unit vectors, so the result is a unit vector.
P3 LimbDirection(const Axes& a, double flexion, double abduction, double side) {
  const P3 hang = (-std::cos(abduction)) * a.up + (side * std::sin(abduction)) * a.left;
  return std::cos(flexion) * hang + std::sin(flexion) * a.forward;
}

}  // namespace

std::array<Vec3, kNumCocoJoints> Coco17Joints(const BodyState& body) {
  MVTRACK_DCHECK(body.height_m > 0.0);
  const double h = body.height_m;
  const double s = h / 1.75;  // head offsets are given for a 1.75 m person
  const Axes a = AxesOf(body.heading_rad);
  const P3 p{body.footprint_m.x(), body.footprint_m.y(), body.footprint_m.z()};
  const double amp = std::clamp(body.gait_amplitude, 0.0, 1.0);
  std::array<Vec3, kNumCocoJoints> j;

  // Legs: side +1 = left, -1 = right; the right leg is half a stride out of phase.
  const double thigh = 0.24 * h, shank = 0.24 * h;
  for (int side_index = 0; side_index < 2; ++side_index) {
    const bool left = side_index == 0;
    const double side = left ? 1.0 : -1.0;
    const double leg_phase = body.walk_phase_rad + (left ? 0.0 : std::numbers::pi);
    const double hip_flexion = 22.0 * kDeg * amp * std::sin(leg_phase);
    // The knee bends most while the thigh swings forward (d/dphase sin > 0).
    const double knee_flexion = (5.0 + 40.0 * std::max(0.0, std::cos(leg_phase))) * kDeg * amp;
    const P3 hip = p + (0.52 * h) * a.up + (side * 0.06 * h) * a.left;
    const P3 knee = hip + thigh * LimbDirection(a, hip_flexion, 0.0, side);
    const P3 ankle = knee + shank * LimbDirection(a, hip_flexion - knee_flexion, 0.0, side);
    j[left ? kLHip : kRHip] = ToVec3(hip);
    j[left ? kLKnee : kRKnee] = ToVec3(knee);
    j[left ? kLAnkle : kRAnkle] = ToVec3(ankle);

    // The arm swings opposite to the leg of the same side.
    const double arm_flexion = -18.0 * kDeg * amp * std::sin(leg_phase);
    const double elbow_flexion = (12.0 + 8.0 * amp) * kDeg;
    const double abduction = 6.0 * kDeg;
    const P3 shoulder = p + (0.82 * h) * a.up + (side * 0.11 * h) * a.left;
    const P3 elbow = shoulder + (0.18 * h) * LimbDirection(a, arm_flexion, abduction, side);
    const P3 wrist =
        elbow + (0.15 * h) * LimbDirection(a, arm_flexion + elbow_flexion, abduction, side);
    j[left ? kLShoulder : kRShoulder] = ToVec3(shoulder);
    j[left ? kLElbow : kRElbow] = ToVec3(elbow);
    j[left ? kLWrist : kRWrist] = ToVec3(wrist);
  }

  // Head: ears around the head centre, eyes and nose in front of it.
  const P3 head = p + (0.925 * h) * a.up + (-0.01 * s) * a.forward;
  j[kLEar] = ToVec3(head + (0.075 * s) * a.left);
  j[kREar] = ToVec3(head + (-0.075 * s) * a.left);
  const P3 eyes = head + (0.085 * s) * a.forward + (0.012 * s) * a.up;
  j[kLEye] = ToVec3(eyes + (0.032 * s) * a.left);
  j[kREye] = ToVec3(eyes + (-0.032 * s) * a.left);
  j[kNose] = ToVec3(head + (0.105 * s) * a.forward + (-0.02 * s) * a.up);
  return j;
}

Vec3 HeadTop(const BodyState& body) {
  const double s = body.height_m / 1.75;
  const double c = std::cos(body.heading_rad), sn = std::sin(body.heading_rad);
  return Vec3(body.footprint_m.x() - 0.01 * s * c,
              body.footprint_m.y() - 0.01 * s * sn,
              body.footprint_m.z() + body.height_m);
}

std::vector<Vec3> BoxPoints(std::span<const Vec3> joints,
                            const Vec3& head_top,
                            double heading_rad,
                            double height_m) {
  MVTRACK_CHECK(joints.size() == static_cast<std::size_t>(kNumCocoJoints));
  const double s = height_m / 1.75;
  const double c = std::cos(heading_rad), sn = std::sin(heading_rad);
  std::vector<Vec3> points;
  points.reserve(joints.size() + 5);
  points.insert(points.end(), joints.begin(), joints.end());
  points.push_back(head_top);
  for (const int ankle_index : {static_cast<int>(kLAnkle), static_cast<int>(kRAnkle)}) {
    const Vec3& ankle = joints[static_cast<std::size_t>(ankle_index)];
    const double ax = ankle.x(), ay = ankle.y();
    const double sole_z = std::max(0.0, ankle.z() - 0.04 * height_m);
    points.emplace_back(ax - 0.04 * s * c, ay - 0.04 * s * sn, sole_z);  // heel
    points.emplace_back(ax + 0.14 * s * c, ay + 0.14 * s * sn, sole_z);  // toe
  }
  return points;
}

}  // namespace mvtrack::sim
