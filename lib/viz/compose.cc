#include "viz/compose.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "viz/colors.h"

namespace mvtrack::viz {
namespace {

cv::Mat ResizeTo(const cv::Mat& image, cv::Size size) {
  if (image.size() == size) return image;
  cv::Mat out;
  cv::resize(image, out, size, 0.0, 0.0, cv::INTER_AREA);
  return out;
}

int Round(double v) { return static_cast<int>(std::lround(v)); }

}  // namespace

cv::Size PanelGrid(int n) {
  if (n <= 0) return {0, 0};
  const int rows = n <= 3 ? n : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int cols = (n + rows - 1) / rows;
  return {cols, rows};
}

cv::Mat ComposeFrame(const cv::Mat& floor,
                     const std::vector<cv::Mat>& panels,
                     const ComposeOptions& options) {
  MVTRACK_CHECK(!floor.empty() && floor.type() == CV_8UC3);
  MVTRACK_CHECK(options.height_px >= 32 && options.gap_px >= 0);
  const int h = options.height_px;
  const int gap = options.gap_px;
  const cv::Mat floor_scaled = ResizeTo(
      floor, cv::Size(std::max(1, Round(floor.cols * static_cast<double>(h) / floor.rows)), h));

  int panels_width = 0;
  cv::Size grid = PanelGrid(static_cast<int>(panels.size()));
  cv::Size panel_size;
  if (!panels.empty()) {
    MVTRACK_CHECK(!panels[0].empty());
    const int ph = std::max(1, (h - (grid.height - 1) * gap) / grid.height);
    panel_size =
        cv::Size(std::max(1, Round(ph * static_cast<double>(panels[0].cols) / panels[0].rows)), ph);
    panels_width = grid.width * panel_size.width + (grid.width - 1) * gap;
  }
  const int title_h = options.title.empty() ? 0 : kTitleBandPx;
  const int width = floor_scaled.cols + (panels.empty() ? 0 : gap + panels_width);
  cv::Mat out(title_h + h, width, CV_8UC3, cv::Scalar(0, 0, 0));
  floor_scaled.copyTo(out(cv::Rect(0, title_h, floor_scaled.cols, h)));
  for (std::size_t i = 0; i < panels.size(); ++i) {
    MVTRACK_CHECK(!panels[i].empty() && panels[i].type() == CV_8UC3);
    const int col = static_cast<int>(i) % grid.width;
    const int row = static_cast<int>(i) / grid.width;
    const cv::Rect where(floor_scaled.cols + gap + col * (panel_size.width + gap),
                         title_h + row * (panel_size.height + gap),
                         panel_size.width,
                         panel_size.height);
    ResizeTo(panels[i], panel_size).copyTo(out(where));
  }
  if (title_h > 0) {
    cv::putText(out,
                options.title,
                cv::Point(8, title_h - 9),
                cv::FONT_HERSHEY_SIMPLEX,
                0.6,
                kTextColor,
                1,
                cv::LINE_AA);
  }
  return out;
}

int ContactSheetLabelBand(const ContactSheetOptions& options) {
  for (const std::string& label : options.labels) {
    if (!label.empty()) return kContactSheetLabelBandPx;
  }
  return 0;
}

cv::Rect ContactSheetTile(int index, cv::Size tile_size, const ContactSheetOptions& options) {
  const int cols = std::max(1, options.columns);
  const int col = index % cols;
  const int row = index / cols;
  const int band = ContactSheetLabelBand(options);
  return {options.gap_px + col * (tile_size.width + options.gap_px),
          options.gap_px + row * (band + tile_size.height + options.gap_px) + band,
          tile_size.width,
          tile_size.height};
}

cv::Mat MakeContactSheet(const std::vector<cv::Mat>& tiles, const ContactSheetOptions& options) {
  MVTRACK_CHECK(!tiles.empty());
  MVTRACK_CHECK(options.columns >= 1 && options.tile_width_px >= 8 && options.gap_px >= 0);
  MVTRACK_CHECK(!tiles[0].empty());
  const int n = static_cast<int>(tiles.size());
  const int cols = std::min(options.columns, n);
  const int rows = (n + cols - 1) / cols;
  const int tw = options.tile_width_px;
  const int th = std::max(1, Round(tw * static_cast<double>(tiles[0].rows) / tiles[0].cols));
  const int gap = options.gap_px;
  const int band = ContactSheetLabelBand(options);
  cv::Mat sheet(rows * (band + th) + (rows + 1) * gap,
                cols * tw + (cols + 1) * gap,
                CV_8UC3,
                cv::Scalar(0, 0, 0));
  ContactSheetOptions placement = options;
  placement.columns = cols;
  for (int i = 0; i < n; ++i) {
    const cv::Mat& tile = tiles[static_cast<std::size_t>(i)];
    MVTRACK_CHECK(!tile.empty() && tile.type() == CV_8UC3);
    const cv::Rect where = ContactSheetTile(i, cv::Size(tw, th), placement);
    ResizeTo(tile, where.size()).copyTo(sheet(where));
    if (static_cast<std::size_t>(i) < options.labels.size() &&
        !options.labels[static_cast<std::size_t>(i)].empty()) {
      cv::putText(sheet,
                  options.labels[static_cast<std::size_t>(i)],
                  where.tl() + cv::Point(6, -6),  // in the band above the tile
                  cv::FONT_HERSHEY_SIMPLEX,
                  0.5,
                  kTextColor,
                  1,
                  cv::LINE_AA);
    }
  }
  return sheet;
}

}  // namespace mvtrack::viz
