#include "geometry/camera_rig.h"

#include <algorithm>

#include "geometry/epipolar.h"

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

std::optional<int> CameraRig::IndexOf(CameraId id) const {
  auto it = index_of_.find(id);
  if (it == index_of_.end()) return std::nullopt;
  return it->second;
}

}  // namespace mvtrack::geometry
