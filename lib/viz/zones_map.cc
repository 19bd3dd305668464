#include "viz/zones_map.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>

#include "viz/colors.h"
#include "viz/floor_view.h"

namespace mvtrack::viz {

cv::Scalar ZoneColor(int index, int count) {
  return HsvToBgr(360.0 * index / std::max(count, 1), 0.65, 0.8);
}

cv::Mat RenderZonesMap(const std::vector<geometry::CameraModel>& cameras,
                       const std::vector<config::Zone>& zones,
                       const config::FloorRegion& region,
                       double cell_m,
                       double sample_height_m,
                       int max_side_px) {
  const FloorMapping mapping = FloorMapping::Fit(region, max_side_px);
  cv::Mat map(mapping.height_px, mapping.width_px, CV_8UC3, kBackground);
  const int n = static_cast<int>(zones.size());
  std::map<CameraId, int> zone_of;  // a camera's own zone
  for (int z = 0; z < n; ++z) {
    for (const CameraId id : zones[static_cast<std::size_t>(z)].cameras) zone_of[id] = z;
  }
  const int cols = std::max(1, static_cast<int>(std::ceil(region.width_m() / cell_m)));
  const int rows = std::max(1, static_cast<int>(std::ceil(region.depth_m() / cell_m)));
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const double x0 = region.x_min_m + col * cell_m;
      const double y0 = region.y_min_m + row * cell_m;
      const Vec3 centre(x0 + 0.5 * cell_m, y0 + 0.5 * cell_m, sample_height_m);
      std::vector<bool> seen(static_cast<std::size_t>(n), false);
      for (const geometry::CameraModel& c : cameras) {
        const auto it = zone_of.find(c.id);
        if (it != zone_of.end() && geometry::SeesPoint(c, centre)) {
          seen[static_cast<std::size_t>(it->second)] = true;
        }
      }
      const auto count = std::count(seen.begin(), seen.end(), true);
      const cv::Scalar color =
          count == 0 ? kBackground
          : count == 1
              ? ZoneColor(
                    static_cast<int>(std::find(seen.begin(), seen.end(), true) - seen.begin()), n)
              : kBorderFloorColor;
      cv::rectangle(map,
                    cv::Rect(mapping.ToPoint(x0, y0 + cell_m), mapping.ToPoint(x0 + cell_m, y0)),
                    color,
                    cv::FILLED,
                    cv::LINE_8);
    }
  }
  // A metre grid, every 5 m on a site over 40 m.
  DrawFloorGrid(mapping, std::max(region.width_m(), region.depth_m()) > 40.0 ? 5.0 : 1.0, &map);
  // Cameras in their zone's colour; a camera that is another zone's border camera ringed.
  std::map<CameraId, bool> border;
  for (const config::Zone& z : zones) {
    for (const CameraId id : z.border) border[id] = true;
  }
  for (const geometry::CameraModel& c : cameras) {
    const auto it = zone_of.find(c.id);
    if (it == zone_of.end()) continue;
    const Vec3 p = c.CenterInWorld();
    const cv::Point at = mapping.ToPoint(p.x(), p.y());
    cv::circle(map, at, 8, border.count(c.id) ? kTextColor : kBackground, cv::FILLED, cv::LINE_AA);
    cv::circle(map, at, 6, ZoneColor(it->second, n), cv::FILLED, cv::LINE_AA);
    cv::putText(map,
                "C" + std::to_string(c.id),
                at + cv::Point(8, -6),
                cv::FONT_HERSHEY_SIMPLEX,
                0.35,
                kTextColor,
                1,
                cv::LINE_AA);
  }
  for (const config::Zone& z : zones) {
    const double cx = 0.5 * (z.bounds.x_min_m + z.bounds.x_max_m);
    const double cy = 0.5 * (z.bounds.y_min_m + z.bounds.y_max_m);
    cv::putText(map,
                z.name,
                mapping.ToPoint(cx, cy),
                cv::FONT_HERSHEY_SIMPLEX,
                0.7,
                kTextColor,
                2,
                cv::LINE_AA);
  }
  // Legend: one row per zone (its cameras), then the border floor and the ringed cameras.
  const int band = 16 + 20 * (n + 2);
  cv::Mat out(map.rows + band, map.cols, CV_8UC3, cv::Scalar(0, 0, 0));
  map.copyTo(out(cv::Rect(0, 0, map.cols, map.rows)));
  for (int i = 0; i < n + 2; ++i) {
    const int y = map.rows + 8 + i * 20;
    std::string text;
    cv::Scalar color;
    if (i < n) {
      const config::Zone& z = zones[static_cast<std::size_t>(i)];
      color = ZoneColor(i, n);
      text = z.name + ": " + std::to_string(z.cameras.size()) + " own camera(s), " +
             std::to_string(z.border.size()) + " border camera(s)";
    } else if (i == n) {
      color = kBorderFloorColor;
      text = "border: floor the own cameras of two or more zones see (tracks joined here)";
    } else {
      color = kTextColor;
      text = "white-ringed camera: also a border camera of another zone";
    }
    cv::rectangle(out, cv::Rect(8, y, 14, 14), color, cv::FILLED);
    cv::putText(out,
                text,
                cv::Point(28, y + 12),
                cv::FONT_HERSHEY_SIMPLEX,
                0.45,
                kTextColor,
                1,
                cv::LINE_AA);
  }
  return out;
}

}  // namespace mvtrack::viz
