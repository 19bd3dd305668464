#include "viz/floor_view.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/check.h"
#include "viz/colors.h"

namespace mvtrack::viz {
namespace {

// Font scale for text about 1/55 of the image's shorter side high (at least readable).
double FontScale(const cv::Mat& image) {
  return std::max(0.35, std::min(image.cols, image.rows) / 1400.0);
}

int Thickness(double px_per_m, double metres) {
  return std::max(1, static_cast<int>(std::lround(px_per_m * metres)));
}

}  // namespace

FloorMapping FloorMapping::Fit(const config::FloorRegion& region, int max_side_px) {
  MVTRACK_CHECK(max_side_px >= 16);
  MVTRACK_CHECK(region.width_m() > 0.0 && region.depth_m() > 0.0);
  FloorMapping m;
  m.region = region;
  m.px_per_m = max_side_px / std::max(region.width_m(), region.depth_m());
  m.width_px = std::max(1, static_cast<int>(std::lround(region.width_m() * m.px_per_m)));
  m.height_px = std::max(1, static_cast<int>(std::lround(region.depth_m() * m.px_per_m)));
  return m;
}

cv::Point2d FloorMapping::ToPixel(double x_m, double y_m) const {
  return {(x_m - region.x_min_m) * px_per_m, (region.y_max_m - y_m) * px_per_m};
}

cv::Point FloorMapping::ToPoint(double x_m, double y_m) const {
  const cv::Point2d p = ToPixel(x_m, y_m);
  // Clamp far-away points so the int conversion cannot overflow (OpenCV clips the drawing).
  const double limit = 1e6;
  return {static_cast<int>(std::lround(std::clamp(p.x, -limit, limit))),
          static_cast<int>(std::lround(std::clamp(p.y, -limit, limit)))};
}

config::FloorRegion ViewRegion(const std::vector<geometry::CameraModel>& cameras,
                               const std::vector<tracker::Frame3D>& frames,
                               double margin_m) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  auto add = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  };
  for (const geometry::CameraModel& c : cameras) {
    const Vec3 centre = c.CenterInWorld();
    add(centre.x(), centre.y());
  }
  for (const tracker::Frame3D& f : frames) {
    for (const tracker::Track3D& t : f.tracks) add(t.position.x(), t.position.y());
  }
  if (x0 > x1) return config::FloorRegion{-1.0, -1.0, 1.0, 1.0};
  const double cx = 0.5 * (x0 + x1);
  const double cy = 0.5 * (y0 + y1);
  const double hw = std::max(0.5 * (x1 - x0), 0.5) + margin_m;
  const double hd = std::max(0.5 * (y1 - y0), 0.5) + margin_m;
  return config::FloorRegion{cx - hw, cy - hd, cx + hw, cy + hd};
}

std::vector<Vec2> FieldOfViewOnFloor(const geometry::CameraModel& camera,
                                     double max_range_m,
                                     int samples_per_edge) {
  std::string why;
  if (!camera.Validate(&why) || samples_per_edge < 1 || !(max_range_m > 0.0)) return {};
  const Vec3 centre = camera.CenterInWorld();
  const Mat3 world_from_cam = camera.cam_from_world.rotation.transpose();
  const Mat3 k_inv = camera.K.inverse();
  const double w = camera.width_px;
  const double h = camera.height_px;
  std::vector<Vec2> border;
  const int n = samples_per_edge;
  border.reserve(4 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) border.emplace_back(w * i / n, 0.0);
  for (int i = 0; i < n; ++i) border.emplace_back(w, h * i / n);
  for (int i = 0; i < n; ++i) border.emplace_back(w - w * i / n, h);
  for (int i = 0; i < n; ++i) border.emplace_back(0.0, h - h * i / n);
  std::vector<Vec2> polygon;
  for (const Vec2& raw : border) {
    const Vec2 u = camera.UndistortPixel(raw);
    const Vec3 dir = world_from_cam * (k_inv * Vec3(u.x(), u.y(), 1.0));
    const Vec2 horizontal(dir.x(), dir.y());
    const double hnorm = horizontal.norm();
    if (!std::isfinite(hnorm)) continue;
    if (dir.z() < -1e-12) {
      const double t = -centre.z() / dir.z();
      if (t > 0.0) {
        const Vec3 p = centre + t * dir;
        const Vec2 offset(p.x() - centre.x(), p.y() - centre.y());
        if (offset.norm() <= max_range_m) {
          polygon.emplace_back(p.x(), p.y());
          continue;
        }
      }
    }
    if (hnorm < 1e-12) continue;  // straight up or down: no horizontal direction
    polygon.push_back(Vec2(centre.x(), centre.y()) + max_range_m * horizontal / hnorm);
  }
  return polygon;
}

void DrawFloorGrid(const FloorMapping& mapping, double grid_m, cv::Mat* image) {
  if (!(grid_m > 0.0)) return;
  const config::FloorRegion& r = mapping.region;
  const double step_px = grid_m * mapping.px_per_m;
  if (step_px < 4.0) return;  // too dense to be useful
  for (double x = std::ceil(r.x_min_m / grid_m) * grid_m; x <= r.x_max_m; x += grid_m) {
    const bool axis = std::abs(x) < 1e-9;
    cv::line(*image,
             mapping.ToPoint(x, r.y_min_m),
             mapping.ToPoint(x, r.y_max_m),
             axis ? Fade(kGridColor, kTextColor, 0.3) : kGridColor,
             1,
             cv::LINE_8);
  }
  for (double y = std::ceil(r.y_min_m / grid_m) * grid_m; y <= r.y_max_m; y += grid_m) {
    const bool axis = std::abs(y) < 1e-9;
    cv::line(*image,
             mapping.ToPoint(r.x_min_m, y),
             mapping.ToPoint(r.x_max_m, y),
             axis ? Fade(kGridColor, kTextColor, 0.3) : kGridColor,
             1,
             cv::LINE_8);
  }
}

void DrawCameras(const FloorMapping& mapping,
                 const std::vector<geometry::CameraModel>& cameras,
                 cv::Mat* image,
                 bool fields_of_view) {
  const config::FloorRegion& r = mapping.region;
  const double range = std::hypot(r.width_m(), r.depth_m());
  // Fields of view: translucent fill, then outline.
  cv::Mat overlay = image->clone();
  std::vector<std::vector<cv::Point>> outlines;
  for (const geometry::CameraModel& camera : cameras) {
    if (!fields_of_view) break;
    std::vector<cv::Point> poly;
    const Vec3 c = camera.CenterInWorld();
    poly.push_back(mapping.ToPoint(c.x(), c.y()));
    for (const Vec2& p : FieldOfViewOnFloor(camera, range))
      poly.push_back(mapping.ToPoint(p.x(), p.y()));
    if (poly.size() < 3) continue;
    std::vector<cv::Point> hull;
    cv::convexHull(poly, hull);
    cv::fillConvexPoly(overlay, hull, Fade(kCameraColor, kBackground, 0.55), cv::LINE_AA);
    outlines.push_back(hull);
  }
  if (!outlines.empty()) cv::addWeighted(overlay, 0.2, *image, 0.8, 0.0, *image);
  for (const auto& hull : outlines) {
    cv::polylines(*image, hull, true, Fade(kCameraColor, kBackground, 0.7), 1, cv::LINE_AA);
  }
  const double font = FontScale(*image);
  for (const geometry::CameraModel& camera : cameras) {
    const Vec3 c = camera.CenterInWorld();
    const cv::Point p = mapping.ToPoint(c.x(), c.y());
    const int s = std::max(4, static_cast<int>(std::lround(font * 12)));
    cv::rectangle(*image, p - cv::Point(s, s), p + cv::Point(s, s), kCameraColor, cv::FILLED);
    // The optical axis direction on the floor.
    const Vec3 axis = camera.cam_from_world.rotation.transpose() * Vec3(0, 0, 1);
    const Vec2 hdir(axis.x(), axis.y());
    if (hdir.norm() > 1e-6) {
      const Vec2 end = Vec2(c.x(), c.y()) + 3.0 * s / mapping.px_per_m * hdir.normalized();
      cv::line(*image, p, mapping.ToPoint(end.x(), end.y()), kCameraColor, 2, cv::LINE_AA);
    }
    cv::putText(*image,
                "C" + std::to_string(camera.id),
                p + cv::Point(s + 3, -s - 3),
                cv::FONT_HERSHEY_SIMPLEX,
                font,
                kTextColor,
                1,
                cv::LINE_AA);
  }
}

void DrawSite(const FloorMapping& mapping, const analytics::Site& site, cv::Mat* image) {
  const cv::Scalar& region_color = kRegionColor;
  const cv::Scalar& line_color = kLineColor;
  const double font = FontScale(*image);
  const int width = std::max(1, Thickness(mapping.px_per_m, 0.04));
  std::vector<std::vector<cv::Point>> polygons;
  for (const analytics::Region& r : site.regions) {
    polygons.emplace_back();
    for (const Vec2& p : r.polygon) polygons.back().push_back(mapping.ToPoint(p.x(), p.y()));
  }
  cv::Mat overlay = image->clone();
  for (const std::vector<cv::Point>& polygon : polygons) {
    // One at a time: several contours in one call would leave nested regions as holes.
    cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{polygon}, region_color, cv::LINE_AA);
  }
  cv::addWeighted(overlay, 0.15, *image, 0.85, 0.0, *image);
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    cv::polylines(*image, polygons[i], true, region_color, width, cv::LINE_AA);
    cv::putText(*image,
                site.regions[i].name,
                polygons[i][0] + cv::Point(4, -4),
                cv::FONT_HERSHEY_SIMPLEX,
                font,
                region_color,
                1,
                cv::LINE_AA);
  }
  for (const analytics::Line& l : site.lines) {
    const cv::Point a = mapping.ToPoint(l.from.x(), l.from.y());
    const cv::Point b = mapping.ToPoint(l.to.x(), l.to.y());
    cv::line(*image, a, b, line_color, 2 * width, cv::LINE_AA);
    // The left_to_right direction: the line's direction turned clockwise, in world terms.
    const Vec2 mid = 0.5 * (l.from + l.to);
    const Vec2 along = (l.to - l.from).normalized();
    const Vec2 right(along.y(), -along.x());
    const double half_m = 0.3;
    cv::arrowedLine(*image,
                    mapping.ToPoint(mid.x() - half_m * right.x(), mid.y() - half_m * right.y()),
                    mapping.ToPoint(mid.x() + half_m * right.x(), mid.y() + half_m * right.y()),
                    line_color,
                    width,
                    cv::LINE_AA,
                    0,
                    0.3);
    cv::putText(*image,
                l.name,
                b + cv::Point(4, -4),
                cv::FONT_HERSHEY_SIMPLEX,
                font,
                line_color,
                1,
                cv::LINE_AA);
  }
}

void IncludeSite(const analytics::Site& site, double margin_m, config::FloorRegion* region) {
  const auto grow = [&](const Vec2& p) {
    region->x_min_m = std::min(region->x_min_m, p.x() - margin_m);
    region->y_min_m = std::min(region->y_min_m, p.y() - margin_m);
    region->x_max_m = std::max(region->x_max_m, p.x() + margin_m);
    region->y_max_m = std::max(region->y_max_m, p.y() + margin_m);
  };
  for (const analytics::Region& r : site.regions) {
    for (const Vec2& p : r.polygon) grow(p);
  }
  for (const analytics::Line& l : site.lines) {
    grow(l.from);
    grow(l.to);
  }
}

cv::Mat RenderFloorView(const FloorMapping& mapping,
                        const std::vector<geometry::CameraModel>& cameras,
                        const std::vector<tracker::Frame3D>& frames,
                        std::size_t current,
                        const FloorViewOptions& options) {
  MVTRACK_CHECK(current < frames.size());
  cv::Mat image(mapping.height_px, mapping.width_px, CV_8UC3, kBackground);
  DrawFloorGrid(mapping, options.grid_m, &image);
  if (options.show_cameras) DrawCameras(mapping, cameras, &image);
  if (options.site != nullptr) DrawSite(mapping, *options.site, &image);

  // Trails: consecutive positions of each id, fading with age (oldest first, so newer segments
  // are drawn on top).
  const int trail = std::max(0, options.trail_frames);
  const std::size_t first =
      current >= static_cast<std::size_t>(trail) ? current - static_cast<std::size_t>(trail) : 0;
  std::map<TrackId3D, Vec3> last;
  const int trail_width = Thickness(mapping.px_per_m, 0.05);
  for (std::size_t k = first; k <= current && trail > 0; ++k) {
    const double age = static_cast<double>(current - k) / (trail + 1);
    std::map<TrackId3D, Vec3> now;
    for (const tracker::Track3D& t : frames[k].tracks) {
      now[t.id] = t.position;
      const auto it = last.find(t.id);
      if (it == last.end()) continue;
      cv::line(image,
               mapping.ToPoint(it->second.x(), it->second.y()),
               mapping.ToPoint(t.position.x(), t.position.y()),
               Fade(TrackColor(t.id), kBackground, age),
               trail_width,
               cv::LINE_AA);
    }
    last = std::move(now);
  }

  // Current positions.
  const double font = FontScale(image);
  const int radius =
      std::max(3, static_cast<int>(std::lround(options.marker_radius_m * mapping.px_per_m)));
  for (const tracker::Track3D& t : frames[current].tracks) {
    const cv::Point p = mapping.ToPoint(t.position.x(), t.position.y());
    cv::circle(image, p, radius, TrackColor(t.id), cv::FILLED, cv::LINE_AA);
    cv::circle(image, p, radius, kBackground, 1, cv::LINE_AA);
    if (options.show_ids) {
      cv::putText(image,
                  std::to_string(t.id),
                  p + cv::Point(radius + 2, radius + 2),
                  cv::FONT_HERSHEY_SIMPLEX,
                  font,
                  TrackColor(t.id),
                  1,
                  cv::LINE_AA);
    }
  }
  return image;
}

}  // namespace mvtrack::viz
