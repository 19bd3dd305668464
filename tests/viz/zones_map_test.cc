#include "viz/zones_map.h"

#include <catch2/catch.hpp>

#include "viz/colors.h"
#include "viz/floor_view.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

// A camera `id` 5 m above (x, 2) looking straight down, 90 degrees both ways: at 1 m height it
// sees x - 4 .. x + 4, y -2 .. 6.
geometry::CameraModel Down(CameraId id, double x) {
  geometry::CameraModel c;
  c.id = id;
  c.width_px = 1000;
  c.height_px = 1000;
  c.K << 500.0, 0.0, 500.0, 0.0, 500.0, 500.0, 0.0, 0.0, 1.0;
  // Camera x = world x, camera y = world -y, camera z (forward) = world -z.
  c.cam_from_world.rotation << 1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0;
  c.cam_from_world.translation = -(c.cam_from_world.rotation * Vec3(x, 2.0, 5.0));
  return c;
}

TEST_CASE("The zones map colours the floor by zone, the shared floor grey", "[unit]") {
  const std::vector<geometry::CameraModel> cameras = {Down(0, 2.0), Down(1, 7.0)};
  config::Zone a, b;
  a.name = "zone1";
  a.cameras = {0};
  a.border = {1};
  a.bounds = config::FloorRegion{-2.0, -2.0, 6.0, 6.0};
  b.name = "zone2";
  b.cameras = {1};
  b.bounds = config::FloorRegion{3.0, -2.0, 11.0, 6.0};
  const config::FloorRegion region{-4.0, -4.0, 14.0, 8.0};
  const cv::Mat image = RenderZonesMap(cameras, {a, b}, region, 0.25, 1.0, 900);
  const FloorMapping m = FloorMapping::Fit(region, 900);
  REQUIRE(image.cols == m.width_px);
  REQUIRE(image.rows > m.height_px);  // the legend below
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(0.3, 4.3)), ZoneColor(0, 2)) == 0.0);
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(9.3, 4.3)), ZoneColor(1, 2)) == 0.0);
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(4.6, 4.3)), kBorderFloorColor) == 0.0);
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(13.3, 7.3)), kBackground) == 0.0);
  CHECK(ColorDistance(ZoneColor(0, 2), ZoneColor(1, 2)) > 50.0);
}

}  // namespace
}  // namespace mvtrack::viz
