#pragma once
/// @file
/// Putting pictures together: one output frame (floor view + camera panels + title) and contact
/// sheets (a grid of frames). Stateless; thread-compatible.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace mvtrack::viz {

/// Options of ComposeFrame.
struct ComposeOptions {
  /// Height of the picture without the title band, pixels (>= 32).
  int height_px = 720;
  /// Text of the title band at the top (no band when empty).
  std::string title;
  /// Space between the parts, pixels.
  int gap_px = 4;
};

/// Height of the title band ComposeFrame adds for a non-empty title, pixels.
inline constexpr int kTitleBandPx = 30;

/// The grid ComposeFrame uses for `n` panels: rows = n for n <= 3, else ceil(sqrt(n)); columns =
/// ceil(n / rows). {0, 0} for n = 0.
cv::Size PanelGrid(int n);

/// The floor view scaled to height_px on the left, the panels (all scaled to the first panel's
/// aspect ratio, in PanelGrid rows filling height_px) on the right, separated by gap_px, and the
/// title band above. `floor` must be a non-empty CV_8UC3 image; panels CV_8UC3.
cv::Mat ComposeFrame(const cv::Mat& floor,
                     const std::vector<cv::Mat>& panels,
                     const ComposeOptions& options = {});

/// Options of MakeContactSheet.
struct ContactSheetOptions {
  /// Tiles per row (>= 1); fewer when there are fewer tiles.
  int columns = 4;
  /// Width of every tile, pixels (>= 8); the height keeps the first tile's aspect ratio.
  int tile_width_px = 480;
  /// Space around and between tiles, pixels (>= 0).
  int gap_px = 4;
  /// Optional label of tile i, drawn in a band of kContactSheetLabelBandPx above it (never over
  /// the tile's own title); fewer labels than tiles is fine, no label at all: no band.
  std::vector<std::string> labels;
};

/// Height of the label band above every tile when any label is given, pixels.
inline constexpr int kContactSheetLabelBandPx = 22;

/// kContactSheetLabelBandPx when `options` has a non-empty label, else 0.
int ContactSheetLabelBand(const ContactSheetOptions& options);

/// Where tile `index` is placed by MakeContactSheet for `tile_size` tiles.
cv::Rect ContactSheetTile(int index, cv::Size tile_size, const ContactSheetOptions& options);

/// A grid of `tiles` (non-empty, all CV_8UC3, each resized to the tile size) in row-major order:
/// columns c = min(columns, n), rows r = ceil(n / c), size (c * tw + (c + 1) gap) x
/// (r * (band + th) + (r + 1) gap) with band = ContactSheetLabelBand(options), tile i at
/// ContactSheetTile(i, ...) with its label in the band above it; the background is black.
cv::Mat MakeContactSheet(const std::vector<cv::Mat>& tiles,
                         const ContactSheetOptions& options = {});

}  // namespace mvtrack::viz
