#include "viz/camera_panel.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "core/check.h"
#include "viz/colors.h"

namespace mvtrack::viz {
namespace {

// Pixel (raw image pixels) -> panel point; nullopt when not finite or absurdly far outside.
std::optional<cv::Point> ToPanel(const Vec2& px, double scale) {
  const double x = px.x() * scale;
  const double y = px.y() * scale;
  const double limit = 1e6;
  if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > limit || std::abs(y) > limit) {
    return std::nullopt;
  }
  return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
}

std::optional<cv::Point> Project(const geometry::CameraModel& camera, const Vec3& p, double scale) {
  const std::optional<Vec2> px = camera.Project(p);
  if (!px) return std::nullopt;
  return ToPanel(*px, scale);
}

void DrawDetection(const core::Detection2D& d, double scale, cv::Mat* image) {
  const std::optional<cv::Point> a = ToPanel(Vec2(d.box.x_min, d.box.y_min), scale);
  const std::optional<cv::Point> b = ToPanel(Vec2(d.box.x_max, d.box.y_max), scale);
  if (a && b) cv::rectangle(*image, *a, *b, kDetectionColor, 1, cv::LINE_8);
  const core::KeypointLayout& layout = core::GetKeypointLayout(d.layout);
  if (d.keypoints.size() != static_cast<std::size_t>(layout.num_joints())) return;
  auto point = [&](int j) -> std::optional<cv::Point> {
    const core::Keypoint2D& k = d.keypoints[static_cast<std::size_t>(j)];
    if (!(k.confidence > 0.0)) return std::nullopt;
    return ToPanel(k.position_px, scale);
  };
  for (const auto& [i, j] : layout.bones) {
    const auto p = point(i);
    const auto q = point(j);
    if (p && q) cv::line(*image, *p, *q, kDetectionColor, 1, cv::LINE_AA);
  }
  for (int j = 0; j < layout.num_joints(); ++j) {
    if (const auto p = point(j)) cv::circle(*image, *p, 2, kDetectionColor, cv::FILLED, cv::LINE_8);
  }
}

}  // namespace

cv::Size PanelSize(const geometry::CameraModel& camera, double scale) {
  return {std::max(1, static_cast<int>(std::lround(camera.width_px * scale))),
          std::max(1, static_cast<int>(std::lround(camera.height_px * scale)))};
}

cv::Mat RenderCameraPanel(const geometry::CameraModel& camera,
                          const std::vector<core::Detection2D>& detections,
                          const tracker::Frame3D& frame,
                          core::KeypointLayoutId layout,
                          const CameraPanelOptions& options) {
  MVTRACK_CHECK(options.scale > 0.0 && std::isfinite(options.scale));
  const double s = options.scale;
  cv::Mat image(PanelSize(camera, s), CV_8UC3, kBackground);
  for (const core::Detection2D& d : detections) DrawDetection(d, s, &image);

  const core::KeypointLayout& bones = core::GetKeypointLayout(layout);
  const int line = std::max(1, static_cast<int>(std::lround(3.0 * s)));
  const double font = std::max(0.35, 0.9 * s);
  for (const tracker::Track3D& t : frame.tracks) {
    const cv::Scalar color = TrackColor(t.id);
    std::optional<cv::Point> label;
    bool drew_joints = false;
    if (!t.joints.empty()) {
      std::vector<std::optional<cv::Point>> pts;
      for (const std::optional<Vec3>& j : t.joints)
        pts.push_back(j ? Project(camera, *j, s) : std::nullopt);
      for (const auto& [i, j] : bones.bones) {
        const auto a = static_cast<std::size_t>(i);
        const auto b = static_cast<std::size_t>(j);
        if (a < pts.size() && b < pts.size() && pts[a] && pts[b]) {
          cv::line(image, *pts[a], *pts[b], color, line, cv::LINE_AA);
          drew_joints = true;
        }
      }
      for (const auto& p : pts) {
        if (!p) continue;
        cv::circle(image, *p, line + 1, color, cv::FILLED, cv::LINE_AA);
        drew_joints = true;
        if (!label || p->y < label->y) label = *p;
      }
    }
    if (!drew_joints) {
      // Footprint: the outline of a standing person's box, and a vertical centre line.
      const double hw = 0.5 * options.person_width_m;
      const double h = options.person_height_m;
      std::vector<cv::Point> corners;
      bool all = true;
      for (double dx : {-hw, hw}) {
        for (double dy : {-hw, hw}) {
          for (double z : {0.0, h}) {
            const auto p = Project(camera, t.position + Vec3(dx, dy, z), s);
            if (!p) {
              all = false;
              continue;
            }
            corners.push_back(*p);
          }
        }
      }
      if (all && corners.size() == 8) {
        const cv::Rect box = cv::boundingRect(corners);
        cv::rectangle(image, box, color, line, cv::LINE_AA);
        label = box.tl();
      }
      const auto foot = Project(camera, t.position, s);
      const auto head = Project(camera, t.position + Vec3(0, 0, h), s);
      if (foot && head) {
        cv::line(image, *foot, *head, color, std::max(1, line - 1), cv::LINE_AA);
        cv::circle(image, *foot, line + 2, color, cv::FILLED, cv::LINE_AA);
        if (!label) label = *head;
      }
    }
    if (label) {
      cv::putText(image,
                  std::to_string(t.id),
                  *label + cv::Point(4, -6),
                  cv::FONT_HERSHEY_SIMPLEX,
                  font,
                  color,
                  std::max(1, line - 1),
                  cv::LINE_AA);
    }
  }
  const std::string title = options.title.empty() ? "C" + std::to_string(camera.id) : options.title;
  cv::putText(image,
              title,
              cv::Point(8, static_cast<int>(std::lround(22 * std::max(0.6, s * 1.5)))),
              cv::FONT_HERSHEY_SIMPLEX,
              std::max(0.45, 1.2 * s),
              kTextColor,
              1,
              cv::LINE_AA);
  return image;
}

}  // namespace mvtrack::viz
