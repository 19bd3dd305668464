#include "viz/compose.h"

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "viz/colors.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

cv::Mat Solid(int width, int height, const cv::Scalar& color) {
  return cv::Mat(height, width, CV_8UC3, color);
}

TEST_CASE("Contact sheet: size, tile placement and order", "[unit]") {
  std::vector<cv::Mat> tiles;
  for (int i = 0; i < 7; ++i) tiles.push_back(Solid(320, 180, TrackColor(i)));
  ContactSheetOptions options;
  options.columns = 3;
  options.tile_width_px = 160;
  options.gap_px = 5;
  const cv::Mat sheet = MakeContactSheet(tiles, options);
  // 3 columns, 3 rows of 160 x 90 tiles with 5 px gaps.
  CHECK(sheet.cols == 3 * 160 + 4 * 5);
  CHECK(sheet.rows == 3 * 90 + 4 * 5);
  for (int i = 0; i < 7; ++i) {
    const cv::Rect r = ContactSheetTile(i, cv::Size(160, 90), options);
    CHECK(r.x == 5 + (i % 3) * 165);
    CHECK(r.y == 5 + (i / 3) * 95);
    INFO("tile " << i);
    CHECK(ColorDistance(PixelAt(sheet, r.tl()), TrackColor(i)) == 0.0);
    CHECK(ColorDistance(PixelAt(sheet, r.br() - cv::Point(1, 1)), TrackColor(i)) == 0.0);
    CHECK(ColorDistance(PixelAt(sheet, r.tl() - cv::Point(1, 1)), cv::Scalar(0, 0, 0)) == 0.0);
  }
  // The two unused cells of the last row stay black.
  const cv::Rect unused = ContactSheetTile(8, cv::Size(160, 90), options);
  CHECK(ColorDistance(PixelAt(sheet, unused.tl() + cv::Point(80, 45)), cv::Scalar(0, 0, 0)) == 0.0);
  // Fewer tiles than columns: one row of just those tiles.
  options.columns = 10;
  const cv::Mat row = MakeContactSheet({tiles[0], tiles[1]}, options);
  CHECK(row.cols == 2 * 160 + 3 * 5);
  CHECK(row.rows == 90 + 2 * 5);
}

TEST_CASE("Contact sheet labels sit in a band above their tile, never over it", "[unit]") {
  // Tiles whose own top rows are a bright title band (as `mvtrack view` frames have).
  std::vector<cv::Mat> tiles;
  for (int i = 0; i < 4; ++i) {
    cv::Mat t = Solid(320, 180, TrackColor(i));
    t(cv::Rect(0, 0, 320, 30)).setTo(cv::Scalar(255, 255, 255));
    tiles.push_back(t);
  }
  ContactSheetOptions options;
  options.columns = 2;
  options.tile_width_px = 160;
  options.gap_px = 5;
  options.labels = {"frame 0", "frame 10", "", "frame 30"};
  const cv::Mat sheet = MakeContactSheet(tiles, options);
  CHECK(sheet.rows == 2 * (kContactSheetLabelBandPx + 90) + 3 * 5);
  for (int i = 0; i < 4; ++i) {
    INFO("tile " << i);
    const cv::Rect r = ContactSheetTile(i, cv::Size(160, 90), options);
    CHECK(r.y == 5 + (i / 2) * (kContactSheetLabelBandPx + 95) + kContactSheetLabelBandPx);
    // The tile is copied untouched: its title band white, the rest its colour.
    const cv::Mat tile = sheet(r);
    CHECK(cv::countNonZero(tile.rowRange(0, 15).reshape(1) != 255) == 0);
    CHECK(ColorDistance(PixelAt(sheet, r.br() - cv::Point(1, 1)), TrackColor(i)) == 0.0);
    // The label is drawn in the band above (some text pixels there), none for an empty label.
    const cv::Mat band =
        sheet(cv::Rect(r.x, r.y - kContactSheetLabelBandPx, r.width, kContactSheetLabelBandPx));
    cv::Mat gray;
    cv::cvtColor(band, gray, cv::COLOR_BGR2GRAY);
    CHECK((cv::countNonZero(gray) > 0) == !options.labels[static_cast<std::size_t>(i)].empty());
  }
  // Without labels there is no band (the layout of the test above).
  options.labels.clear();
  CHECK(MakeContactSheet(tiles, options).rows == 2 * 90 + 3 * 5);
}

TEST_CASE("PanelGrid stacks up to three panels, then a near-square grid", "[unit]") {
  CHECK(PanelGrid(0) == cv::Size(0, 0));
  CHECK(PanelGrid(1) == cv::Size(1, 1));
  CHECK(PanelGrid(3) == cv::Size(1, 3));
  CHECK(PanelGrid(4) == cv::Size(2, 2));
  CHECK(PanelGrid(5) == cv::Size(2, 3));
  CHECK(PanelGrid(7) == cv::Size(3, 3));
  CHECK(PanelGrid(31) == cv::Size(6, 6));
}

TEST_CASE("ComposeFrame puts the floor left, the panels right and the title on top", "[unit]") {
  const cv::Mat floor = Solid(300, 300, cv::Scalar(10, 20, 30));
  const std::vector<cv::Mat> panels = {
      Solid(160, 90, TrackColor(1)), Solid(160, 90, TrackColor(2)), Solid(160, 90, TrackColor(3))};
  ComposeOptions options;
  options.height_px = 600;
  options.gap_px = 6;
  options.title = "t";
  const cv::Mat out = ComposeFrame(floor, panels, options);
  // Floor 600 x 600; three stacked panels (1 column) of height (600 - 2 * 6) / 3 = 196, width
  // round(196 * 16 / 9) = 348.
  CHECK(out.rows == kTitleBandPx + 600);
  CHECK(out.cols == 600 + 6 + 348);
  CHECK(ColorDistance(PixelAt(out, cv::Point(300, kTitleBandPx + 300)), cv::Scalar(10, 20, 30)) ==
        0.0);
  for (int i = 0; i < 3; ++i) {
    INFO("panel " << i);
    const cv::Point centre(606 + 174, kTitleBandPx + i * (196 + 6) + 98);
    CHECK(ColorDistance(PixelAt(out, centre), TrackColor(i + 1)) == 0.0);
  }
  const cv::Mat alone = ComposeFrame(floor, {}, ComposeOptions{});
  CHECK(alone.size() == cv::Size(720, 720));
}

}  // namespace
}  // namespace mvtrack::viz
