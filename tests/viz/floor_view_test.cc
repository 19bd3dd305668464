#include "viz/floor_view.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "support/synthetic_cameras.h"
#include "viz/colors.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

tracker::Frame3D MakeFrame(FrameIndex frame, std::vector<std::pair<TrackId3D, Vec2>> tracks) {
  tracker::Frame3D f;
  f.frame = frame;
  for (const auto& [id, xy] : tracks) {
    tracker::Track3D t;
    t.id = id;
    t.position = Vec3(xy.x(), xy.y(), 0.0);
    f.tracks.push_back(t);
  }
  return f;
}

TEST_CASE("A site's regions and lines are drawn under the tracks, with the line's direction",
          "[unit]") {
  const FloorMapping m = FloorMapping::Fit({0.0, 0.0, 10.0, 10.0}, 500);  // 50 px per metre
  analytics::Site site;
  site.regions.push_back({"shelf", {{2, 2}, {4, 2}, {4, 4}, {2, 4}}});
  site.lines.push_back({"door", {7, 1}, {7, 9}});
  FloorViewOptions options;
  options.grid_m = 0.0;
  options.site = &site;
  const cv::Mat image = RenderFloorView(m, {}, {MakeFrame(0, {{5, Vec2(3.0, 3.0)}})}, 0, options);
  // The region's outline in its colour; inside it, the translucent fill (neither background nor
  // the full colour); the track drawn over it.
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(2.0, 3.5)), kRegionColor) < 1.0);
  const cv::Scalar fill = PixelAt(image, m.ToPoint(2.5, 3.5));
  CHECK(ColorDistance(fill, kBackground) > 5.0);
  CHECK(ColorDistance(fill, kRegionColor) > 50.0);
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(3.0, 3.0)), TrackColor(5)) == 0.0);
  // The line, and its left_to_right arrow from x < 7 to x > 7 (going north, the left is west).
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(7.0, 2.0)), kLineColor) < 1.0);
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(7.25, 5.0)), kLineColor) < 1.0);
  // Without the site: background there.
  options.site = nullptr;
  const cv::Mat plain = RenderFloorView(m, {}, {MakeFrame(0, {})}, 0, options);
  CHECK(ColorDistance(PixelAt(plain, m.ToPoint(2.0, 3.5)), kBackground) == 0.0);
  // IncludeSite grows a view to the site.
  config::FloorRegion region{5.0, 5.0, 6.0, 6.0};
  IncludeSite(site, 0.5, &region);
  CHECK(region.x_min_m == 1.5);
  CHECK(region.y_min_m == 0.5);
  CHECK(region.x_max_m == 7.5);
  CHECK(region.y_max_m == 9.5);
}

TEST_CASE("FloorMapping puts x to the right and y up at a uniform scale", "[unit]") {
  const config::FloorRegion region{-2.0, 1.0, 6.0, 5.0};  // 8 m x 4 m
  const FloorMapping m = FloorMapping::Fit(region, 800);
  CHECK(m.px_per_m == Approx(100.0));
  CHECK(m.width_px == 800);
  CHECK(m.height_px == 400);
  CHECK(m.ToPixel(-2.0, 5.0).x == Approx(0.0));
  CHECK(m.ToPixel(-2.0, 5.0).y == Approx(0.0));
  CHECK(m.ToPixel(6.0, 1.0).x == Approx(800.0));
  CHECK(m.ToPixel(6.0, 1.0).y == Approx(400.0));
  CHECK(m.ToPixel(0.0, 2.0).x == Approx(200.0));
  CHECK(m.ToPixel(0.0, 2.0).y == Approx(300.0));
}

TEST_CASE("A track is drawn at its floor position in its own colour, the same in every frame",
          "[unit]") {
  const config::FloorRegion region{0.0, 0.0, 10.0, 10.0};
  const FloorMapping m = FloorMapping::Fit(region, 500);  // 50 px per metre
  const std::vector<tracker::Frame3D> frames = {
      MakeFrame(0, {{7, Vec2(2.0, 3.0)}, {8, Vec2(7.0, 7.0)}}),
      MakeFrame(1, {{7, Vec2(5.0, 5.0)}, {8, Vec2(7.5, 2.0)}}),
  };
  FloorViewOptions options;
  options.grid_m = 0.0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat image = RenderFloorView(m, {}, frames, i, options);
    REQUIRE(image.cols == 500);
    REQUIRE(image.rows == 500);
    for (const tracker::Track3D& t : frames[i].tracks) {
      INFO("frame " << i << " track " << t.id);
      const cv::Point p = m.ToPoint(t.position.x(), t.position.y());
      CHECK(ColorDistance(PixelAt(image, p), TrackColor(t.id)) == 0.0);
      // Inside the marker radius (0.22 m = 11 px), away from its outline.
      CHECK(ColorDistance(PixelAt(image, p + cv::Point(6, 0)), TrackColor(t.id)) == 0.0);
    }
    // Far from every track: background.
    CHECK(ColorDistance(PixelAt(image, m.ToPoint(0.5, 9.5)), kBackground) == 0.0);
  }
}

TEST_CASE("The trail fades from the track colour to the background and has the set length",
          "[unit]") {
  const config::FloorRegion region{0.0, 0.0, 10.0, 10.0};
  const FloorMapping m = FloorMapping::Fit(region, 500);
  // Track 3 walks along y = 5 from x = 1 to x = 9, one metre per frame.
  std::vector<tracker::Frame3D> frames;
  for (int k = 0; k <= 8; ++k) frames.push_back(MakeFrame(k, {{3, Vec2(1.0 + k, 5.0)}}));
  FloorViewOptions options;
  options.grid_m = 0.0;
  options.show_ids = false;
  options.trail_frames = 4;
  const cv::Mat image = RenderFloorView(m, {}, frames, 8, options);
  const cv::Scalar color = TrackColor(3);
  // Segments [x, x + 1] (frames x - 1 -> x) of age 1/5, 2/5, 3/5 at their midpoints; the segment
  // between frames 3 and 4 (x = 4.5) is older than 4 frames and not drawn.
  double previous = -1.0;
  for (double x : {7.5, 6.5, 5.5}) {
    const cv::Scalar c = PixelAt(image, m.ToPoint(x, 5.0));
    const double to_track = ColorDistance(c, color);
    INFO("x = " << x);
    CHECK(ColorDistance(c, kBackground) > 0.0);
    CHECK(to_track > previous);  // older segments are further from the track colour
    previous = to_track;
  }
  CHECK(ColorDistance(PixelAt(image, m.ToPoint(4.5, 5.0)), kBackground) == 0.0);
  options.trail_frames = 0;
  const cv::Mat no_trail = RenderFloorView(m, {}, frames, 8, options);
  CHECK(ColorDistance(PixelAt(no_trail, m.ToPoint(7.5, 5.0)), kBackground) == 0.0);
}

TEST_CASE("A camera looking straight down sees a rectangle of the floor", "[unit]") {
  // 3 m above (1, 2), fx = 500 px, 1000 x 600 image: half extents 3 m * 500 / 500 = 3 m (x of
  // the image) and 3 m * 300 / 500 = 1.8 m.
  const geometry::CameraModel camera =
      mvtrack::testing::LookAtCamera(0, Vec3(1.0, 2.0, 3.0), Vec3(1.0, 2.0, 0.0), 500.0, 1000, 600);
  const std::vector<Vec2> polygon = FieldOfViewOnFloor(camera, 100.0, 8);
  REQUIRE(polygon.size() == 32);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const Vec2& p : polygon) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  // LookAtRotation takes image "up" along world +y for a vertical axis: image x is world x.
  CHECK(x1 - x0 == Approx(6.0).margin(1e-9));
  CHECK(y1 - y0 == Approx(3.6).margin(1e-9));
  CHECK(0.5 * (x0 + x1) == Approx(1.0).margin(1e-9));
  CHECK(0.5 * (y0 + y1) == Approx(2.0).margin(1e-9));
  // A shorter range cuts the rays at that horizontal distance.
  for (const Vec2& p : FieldOfViewOnFloor(camera, 1.0, 8)) {
    CHECK((p - Vec2(1.0, 2.0)).norm() <= 1.0 + 1e-9);
  }
}

TEST_CASE("ViewRegion covers cameras and tracks with the margin", "[unit]") {
  const geometry::CameraModel camera =
      mvtrack::testing::LookAtCamera(0, Vec3(-3.0, 0.0, 2.5), Vec3(0.0, 0.0, 1.0), 800.0, 640, 480);
  const std::vector<tracker::Frame3D> frames = {MakeFrame(0, {{1, Vec2(4.0, 2.0)}})};
  const config::FloorRegion r = ViewRegion({camera}, frames, 1.0);
  CHECK(r.x_min_m == Approx(-4.0));
  CHECK(r.x_max_m == Approx(5.0));
  CHECK(r.y_min_m == Approx(-1.0));
  CHECK(r.y_max_m == Approx(3.0));
  const config::FloorRegion empty = ViewRegion({}, {}, 1.0);
  CHECK(empty.width_m() == Approx(2.0));
}

}  // namespace
}  // namespace mvtrack::viz
