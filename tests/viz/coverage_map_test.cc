#include "viz/coverage_map.h"

#include <catch2/catch.hpp>

#include "viz/floor_view.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

TEST_CASE("The coverage map colours each cell by its view count and triangulation angle",
          "[unit]") {
  config::CalibrationReport report;
  report.options.min_triangulation_angle_deg = 10.0;
  report.options.sample_height_m = 1.0;
  config::CoverageGrid& g = report.grid;
  g.region = config::FloorRegion{0.0, 0.0, 4.0, 2.0};
  g.cell_m = 1.0;
  g.cols = 4;
  g.rows = 2;
  // Row 0 (y in [0, 1]): 0, 1, 2 weak, 2 good; row 1: 3, 4, 5, 2 weak.
  g.view_count = {0, 1, 2, 2, 3, 4, 5, 2};
  g.best_angle_deg = {0, 0, 5, 30, 40, 40, 40, 9.9};
  report.options.region = g.region;
  const cv::Mat image = RenderCoverageMap({}, report, 400);
  REQUIRE(image.cols == 400);
  REQUIRE(image.rows == 200 + kLegendBandPx);
  const FloorMapping m = FloorMapping::Fit(g.region, 400);
  const cv::Scalar expected[] = {kUnseenColor,
                                 kSingleViewColor,
                                 kWeakColor,
                                 TriangulableColor(2),
                                 TriangulableColor(3),
                                 TriangulableColor(4),
                                 TriangulableColor(5),
                                 kWeakColor};
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 4; ++col) {
      const std::size_t cell = static_cast<std::size_t>(row * 4 + col);
      INFO("cell " << col << ", " << row);
      CHECK(ColorDistance(CellColor(report, cell), expected[cell]) == 0.0);
      // A point inside the cell away from the 1 m grid lines.
      const cv::Point p = m.ToPoint(col + 0.3, row + 0.3);
      CHECK(ColorDistance(PixelAt(image, p), expected[cell]) == 0.0);
    }
  }
  CHECK(ColorDistance(TriangulableColor(4), TriangulableColor(9)) == 0.0);
  CHECK(ColorDistance(TriangulableColor(2), TriangulableColor(3)) > 0.0);
}

}  // namespace
}  // namespace mvtrack::viz
