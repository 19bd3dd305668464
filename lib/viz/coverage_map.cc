#include "viz/coverage_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>

#include "viz/colors.h"
#include "viz/floor_view.h"

namespace mvtrack::viz {

cv::Scalar TriangulableColor(int count) {
  const double value = count <= 2 ? 0.5 : (count == 3 ? 0.68 : 0.85);
  return HsvToBgr(120.0, 0.75, value);
}

cv::Scalar CellColor(const config::CalibrationReport& report, std::size_t cell) {
  const int count = report.grid.view_count[cell];
  if (count == 0) return kUnseenColor;
  if (count == 1) return kSingleViewColor;
  if (report.grid.best_angle_deg[cell] < report.options.min_triangulation_angle_deg)
    return kWeakColor;
  return TriangulableColor(count);
}

cv::Mat RenderCoverageMap(const std::vector<geometry::CameraModel>& cameras,
                          const config::CalibrationReport& report,
                          int max_side_px,
                          const analytics::Site* site) {
  const config::CoverageGrid& grid = report.grid;
  const FloorMapping mapping = FloorMapping::Fit(grid.region, max_side_px);
  cv::Mat map(mapping.height_px, mapping.width_px, CV_8UC3, kBackground);
  for (int row = 0; row < grid.rows; ++row) {
    for (int col = 0; col < grid.cols; ++col) {
      const std::size_t cell = static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.cols) +
                               static_cast<std::size_t>(col);
      const double x0 = grid.region.x_min_m + col * grid.cell_m;
      const double y0 = grid.region.y_min_m + row * grid.cell_m;
      const cv::Point a = mapping.ToPoint(x0, y0 + grid.cell_m);
      const cv::Point b = mapping.ToPoint(x0 + grid.cell_m, y0);
      cv::rectangle(map, cv::Rect(a, b), CellColor(report, cell), cv::FILLED, cv::LINE_8);
    }
  }
  DrawFloorGrid(mapping, 1.0, &map);

  // Overlap graph.
  std::map<CameraId, Vec3> centres;
  for (const geometry::CameraModel& c : cameras) centres[c.id] = c.CenterInWorld();
  double max_area = 0.0;
  for (const config::PairCheck& p : report.pairs) max_area = std::max(max_area, p.common_area_m2);
  for (const config::PairCheck& p : report.pairs) {
    if (!(p.common_area_m2 > 0.0) || !centres.count(p.a) || !centres.count(p.b)) continue;
    const Vec3& a = centres[p.a];
    const Vec3& b = centres[p.b];
    const cv::Scalar color = p.short_baseline ? cv::Scalar(60, 60, 255) : cv::Scalar(230, 230, 230);
    const int width = 1 + static_cast<int>(std::lround(3.0 * p.common_area_m2 / max_area));
    cv::line(map,
             mapping.ToPoint(a.x(), a.y()),
             mapping.ToPoint(b.x(), b.y()),
             color,
             width,
             cv::LINE_AA);
    char text[64];
    std::snprintf(text, sizeof text, "%.0fm2 %.0fdeg", p.common_area_m2, p.median_angle_deg);
    const Vec3 mid = 0.5 * (a + b);
    cv::putText(map,
                text,
                mapping.ToPoint(mid.x(), mid.y()),
                cv::FONT_HERSHEY_SIMPLEX,
                0.4,
                color,
                1,
                cv::LINE_AA);
  }
  DrawCameras(mapping, cameras, &map, false);
  if (site != nullptr) DrawSite(mapping, *site, &map);

  // Legend.
  cv::Mat out(map.rows + kLegendBandPx, map.cols, CV_8UC3, cv::Scalar(0, 0, 0));
  map.copyTo(out(cv::Rect(0, 0, map.cols, map.rows)));
  char weak[96];
  std::snprintf(weak,
                sizeof weak,
                "2+ cameras, triangulation angle < %.0f deg",
                report.options.min_triangulation_angle_deg);
  const std::pair<cv::Scalar, std::string> entries[] = {
      {kUnseenColor, "no camera"},
      {kSingleViewColor, "1 camera (no 3D)"},
      {kWeakColor, weak},
      {TriangulableColor(3), "2+ cameras (brighter: more)"},
  };
  for (int i = 0; i < 4; ++i) {
    const int y = map.rows + 8 + i * 20;
    cv::rectangle(out, cv::Rect(8, y, 14, 14), entries[i].first, cv::FILLED);
    cv::putText(out,
                entries[i].second,
                cv::Point(28, y + 12),
                cv::FONT_HERSHEY_SIMPLEX,
                0.45,
                kTextColor,
                1,
                cv::LINE_AA);
  }
  char sampling[96];
  std::snprintf(sampling,
                sizeof sampling,
                "sampled at z = %.2f m, cell %.2f m",
                report.options.sample_height_m,
                grid.cell_m);
  const char* const notes[] = {sampling, "lines: camera pairs with common floor (red: short)"};
  for (int i = 0; i < 2; ++i) {
    cv::putText(out,
                notes[i],
                cv::Point(8, map.rows + 8 + 4 * 20 + 12 + i * 18),
                cv::FONT_HERSHEY_SIMPLEX,
                0.4,
                kTextColor,
                1,
                cv::LINE_AA);
  }
  return out;
}

}  // namespace mvtrack::viz
