// The analytics pictures (issue 41): the occupancy line at its level, the dwell bars in their
// bins, the heat map hottest where the tracks stayed longest.

#include "viz/analytics_plots.h"

#include <catch2/catch.hpp>
#include <vector>

#include "viz/colors.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

// Pixels of `image` within `area` that have `color`.
int CountColor(const cv::Mat& image, const cv::Rect& area, const cv::Scalar& color) {
  int n = 0;
  for (int y = area.y; y < area.y + area.height; ++y) {
    for (int x = area.x; x < area.x + area.width; ++x) {
      n += ColorDistance(PixelAt(image, {x, y}), color) < 1.0;
    }
  }
  return n;
}

}  // namespace

TEST_CASE("analytics plots: occupancy steps, dwell bars, heat where people stayed", "[unit]") {
  // One region: 0 people for 10 s, then 2 for 10 s (plot area x 60..730, y 30..375; peak 2).
  std::vector<double> times;
  std::vector<int> occupancy;
  for (int i = 0; i <= 200; ++i) {
    times.push_back(0.1 * i);
    occupancy.push_back(i < 100 ? 0 : 2);
  }
  const cv::Mat plot = RenderOccupancyPlot({"shelf"}, times, {occupancy}, 900, 420);
  REQUIRE(plot.cols == 900);
  REQUIRE(plot.rows == 420);
  const cv::Scalar color = TrackColor(1);
  // The level 2 (the top of the plot area) over the second half, not the first.
  CHECK(CountColor(plot, cv::Rect(420, 26, 300, 8), color) > 100);
  CHECK(CountColor(plot, cv::Rect(70, 26, 300, 8), color) == 0);

  // Dwell: 10 visits of 1 s and 5 of 9 s, 20 bins of 0.5 s over 0..10 s.
  std::vector<double> dwell(10, 1.0);
  dwell.insert(dwell.end(), 5, 9.0);
  dwell.push_back(10.0);
  const cv::Mat bars = RenderDwellHistogram({"shelf"}, {dwell}, 20, 900, 140);
  // Bars of bin [1, 1.5) and [9, 9.5) (x = 60 + 840 * t / 10), none at 5 s.
  const auto column = [&](double t) {
    return cv::Rect(60 + static_cast<int>(84 * t) + 10, 50, 10, 70);
  };
  CHECK(CountColor(bars, column(1.0), color) > 100);
  CHECK(CountColor(bars, column(9.0), color) > 0);
  CHECK(CountColor(bars, column(5.0), color) == 0);
  // The taller bar is the more frequent dwell.
  CHECK(CountColor(bars, column(1.0), color) > CountColor(bars, column(9.0), color));

  // Heat map: one track standing at (1, 1) for 10 s, another passing (3, 3) once.
  const FloorMapping mapping = FloorMapping::Fit({0.0, 0.0, 4.0, 4.0}, 400);
  std::vector<analytics::TimedPositions> messages;
  for (int i = 0; i < 100; ++i) {
    analytics::TimedPositions m;
    m.time_s = 0.1 * i;
    m.tracks.push_back({1, {1.1, 1.1}});
    if (i == 50) m.tracks.push_back({2, {3.1, 3.1}});
    messages.push_back(m);
  }
  const cv::Mat heat = RenderHeatMap(mapping, messages, analytics::Site{}, 0.25, 1.0);
  REQUIRE(heat.cols == 400);
  const cv::Scalar stay = PixelAt(heat, mapping.ToPoint(1.1, 1.1));
  const cv::Scalar pass = PixelAt(heat, mapping.ToPoint(3.1, 3.1));
  const cv::Scalar empty = PixelAt(heat, mapping.ToPoint(2.1, 3.6));
  const auto brightness = [](const cv::Scalar& c) { return c[0] + c[1] + c[2]; };
  CHECK(brightness(stay) > brightness(pass));
  CHECK(brightness(pass) > brightness(empty));
}

}  // namespace mvtrack::viz
