#include "datasets/dataset.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string_view>
#include <utility>

#include "datasets/internal/common.h"

#ifndef MVTRACK_DEFAULT_DATA_ROOT
#error "MVTRACK_DEFAULT_DATA_ROOT must be defined by lib/datasets/CMakeLists.txt"
#endif

namespace mvtrack::datasets {
namespace {

int FindJoint(const core::KeypointLayout& layout, std::string_view name) {
  for (std::size_t i = 0; i < layout.joints.size(); ++i) {
    if (layout.joints[i] == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

DatasetError::DatasetError(std::string file, std::string problem)
    : std::runtime_error(file + ": " + problem),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

std::filesystem::path DefaultDataRoot() {
  const char* env = std::getenv("MVTRACK_DATA");
  if (env != nullptr && env[0] != '\0') return std::filesystem::path(env);
  return std::filesystem::path(MVTRACK_DEFAULT_DATA_ROOT).lexically_normal();
}

Utime FrameUtime(FrameIndex frame, double fps) {
  return static_cast<Utime>(std::llround(static_cast<double>(frame) * 1e6 / fps));
}

std::optional<core::BoxPx> BoxFromKeypoints(const std::vector<core::Keypoint2D>& keypoints) {
  int count = 0;
  double x_min = 0.0, y_min = 0.0, x_max = 0.0, y_max = 0.0;
  for (const core::Keypoint2D& kp : keypoints) {
    if (!(kp.confidence > 0.0)) continue;
    const double x = kp.position_px.x();
    const double y = kp.position_px.y();
    if (count == 0) {
      x_min = x_max = x;
      y_min = y_max = y;
    } else {
      x_min = std::min(x_min, x);
      x_max = std::max(x_max, x);
      y_min = std::min(y_min, y);
      y_max = std::max(y_max, y);
    }
    ++count;
  }
  if (count < 2) return std::nullopt;
  const double pad = std::max(kBoxPaddingFraction * (y_max - y_min), 1.0);
  return core::BoxPx{x_min - pad, y_min - pad, x_max + pad, y_max + pad};
}

double MeanKeypointScore(const std::vector<core::Keypoint2D>& keypoints) {
  double sum = 0.0;
  int count = 0;
  for (const core::Keypoint2D& kp : keypoints) {
    if (!(kp.confidence > 0.0)) continue;
    sum += kp.confidence;
    ++count;
  }
  return count == 0 ? 0.0 : sum / static_cast<double>(count);
}

std::optional<Vec3> FootprintFromJoints(const std::vector<std::optional<Vec3>>& joints,
                                        core::KeypointLayoutId layout) {
  const core::KeypointLayout& l = core::GetKeypointLayout(layout);
  return internal::FootprintFromHips(joints, FindJoint(l, "l_hip"), FindJoint(l, "r_hip"));
}

}  // namespace mvtrack::datasets
