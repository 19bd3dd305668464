#include "viz/colors.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;

TEST_CASE("HsvToBgr gives the primaries and grey", "[unit]") {
  CHECK(ColorDistance(HsvToBgr(0.0, 1.0, 1.0), cv::Scalar(0, 0, 255)) == 0.0);
  CHECK(ColorDistance(HsvToBgr(120.0, 1.0, 1.0), cv::Scalar(0, 255, 0)) == 0.0);
  CHECK(ColorDistance(HsvToBgr(240.0, 1.0, 1.0), cv::Scalar(255, 0, 0)) == 0.0);
  CHECK(ColorDistance(HsvToBgr(360.0 + 60.0, 1.0, 1.0), cv::Scalar(0, 255, 255)) == 0.0);
  CHECK(ColorDistance(HsvToBgr(77.0, 0.0, 0.5), cv::Scalar(128, 128, 128)) == 0.0);
}

TEST_CASE("TrackColor depends on the id only and separates consecutive ids", "[unit]") {
  for (TrackId3D id = -3; id < 40; ++id)
    CHECK(ColorDistance(TrackColor(id), TrackColor(id)) == 0.0);
  // Any 10 consecutive ids: pairwise clearly different colours (>= 20 degrees of hue at
  // saturation 0.85, value 1 moves some channel by at least 217 / 6 = 36 levels, the worst case
  // being a shift across a 60-degree sector boundary).
  for (TrackId3D start : {0, 1, 17, 1000}) {
    for (TrackId3D a = start; a < start + 10; ++a) {
      for (TrackId3D b = a + 1; b < start + 10; ++b) {
        INFO("ids " << a << " and " << b);
        CHECK(ColorDistance(TrackColor(a), TrackColor(b)) >= 36.0);
      }
    }
  }
}

TEST_CASE("Fade mixes towards the background", "[unit]") {
  const cv::Scalar c(200, 100, 0);
  const cv::Scalar bg(0, 0, 100);
  CHECK(ColorDistance(Fade(c, bg, 0.0), c) == 0.0);
  CHECK(ColorDistance(Fade(c, bg, 1.0), bg) == 0.0);
  CHECK(ColorDistance(Fade(c, bg, 0.5), cv::Scalar(100, 50, 50)) < 1e-9);
  CHECK(ColorDistance(Fade(c, bg, 7.0), bg) == 0.0);  // clamped
}

}  // namespace
}  // namespace mvtrack::viz
