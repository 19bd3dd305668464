#include "geometry/camera_rig.h"

#include <algorithm>

#include "geometry/epipolar.h"
#include "geometry/view_region.h"

namespace mvtrack::geometry {

CameraRig::CameraRig(std::vector<CameraModel> cameras, std::string* why) {
  if (cameras.empty()) {
    if (why != nullptr) *why = "the camera rig has no cameras";
    return;
  }
  std::sort(cameras.begin(), cameras.end(), [](const CameraModel& a, const CameraModel& b) {
    return a.id < b.id;
  });
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    std::string reason;
    if (!cameras[i].Validate(&reason)) {
      if (why != nullptr) *why = reason;
      return;
    }
    if (i > 0 && cameras[i].id == cameras[i - 1].id) {
      if (why != nullptr) *why = "duplicate camera id " + std::to_string(cameras[i].id);
      return;
    }
  }
  const std::size_t n = cameras.size();
  projections_.reserve(n);
  fundamentals_.resize(n * n, Mat3::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    projections_.push_back(cameras[i].ProjectionMatrix());
    index_of_[cameras[i].id] = static_cast<int>(i);
    for (std::size_t j = 0; j < n; ++j) {
      if (i != j) fundamentals_[i * n + j] = FundamentalMatrix(cameras[i], cameras[j]);
    }
  }
  cameras_ = std::move(cameras);
}

void CameraRig::ComputeSharedViews(double floor_z, double max_range_m) {
  const std::size_t n = cameras_.size();
  constexpr double kMinAreaM2 = 0.25;
  std::vector<char> shares(n * n, 0);
  for (std::size_t i = 0; i < n; ++i) shares[i * n + i] = 1;
  for (double h = -0.5; h <= 2.5 + 1e-9; h += 0.5) {
    std::vector<std::vector<HalfPlane>> views;
    views.reserve(n);
    for (const CameraModel& c : cameras_) views.push_back(ViewOnPlane(c, floor_z + h, max_range_m));
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 ci = cameras_[i].CenterInWorld();
      for (std::size_t j = i + 1; j < n; ++j) {
        if (shares[i * n + j] != 0) continue;
        // Within the range of camera i: a square of 4 x the range around it holds its view.
        if (IntersectionArea(views[i], views[j], ci.x(), ci.y(), 4.0 * max_range_m) >= kMinAreaM2) {
          shares[i * n + j] = shares[j * n + i] = 1;
        }
      }
    }
  }
  shares_view_ = std::move(shares);
}

int CameraRig::num_sharing_pairs() const {
  int pairs = 0;
  for (int i = 0; i < size(); ++i) {
    for (int j = i + 1; j < size(); ++j) pairs += SharesView(i, j) ? 1 : 0;
  }
  return pairs;
}

std::optional<int> CameraRig::IndexOf(CameraId id) const {
  auto it = index_of_.find(id);
  if (it == index_of_.end()) return std::nullopt;
  return it->second;
}

}  // namespace mvtrack::geometry
