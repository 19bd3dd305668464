#pragma once
/// @file
/// The bird's-eye view of the floor: world x to the right, world y up, uniform scale, floor
/// grid every metre, cameras with their floor field of view, every track in its own colour
/// (viz::TrackColor) with a fading trail. Stateless drawing functions; thread-compatible.

#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

#include "analytics/site_analytics.h"
#include "config/calibration_check.h"
#include "core/types.h"
#include "geometry/camera_model.h"
#include "tracker/types.h"

namespace mvtrack::viz {

/// World (x, y) in metres <-> pixels of a floor image covering `region`.
struct FloorMapping {
  config::FloorRegion region;  ///< the world area shown
  double px_per_m = 1.0;       ///< scale, pixels per metre
  int width_px = 1;            ///< image width
  int height_px = 1;           ///< image height

  /// The mapping of `region` into an image whose longer side is `max_side_px` (>= 16).
  static FloorMapping Fit(const config::FloorRegion& region, int max_side_px);
  /// Pixel of world (x, y): column (x - x_min) * scale, row (y_max - y) * scale.
  cv::Point2d ToPixel(double x_m, double y_m) const;
  /// ToPixel rounded to the pixel grid (for drawing).
  cv::Point ToPoint(double x_m, double y_m) const;
};

/// The region a view shows: the bounding box of the camera centres and of the positions of
/// every track of `frames`, grown by `margin_m` (at least 1 m x 1 m before the margin). Without
/// cameras and tracks: [-1, 1] x [-1, 1].
config::FloorRegion ViewRegion(const std::vector<geometry::CameraModel>& cameras,
                               const std::vector<tracker::Frame3D>& frames,
                               double margin_m);

/// The floor area a camera sees, as a polygon (world x, y): rays through `samples_per_edge`
/// points of each image edge (undistorted), cut at the floor z = 0 or, for rays that do not
/// meet it within `max_range_m`, at that horizontal distance. Empty for an invalid camera.
std::vector<Vec2> FieldOfViewOnFloor(const geometry::CameraModel& camera,
                                     double max_range_m,
                                     int samples_per_edge = 16);

/// Options of RenderFloorView.
struct FloorViewOptions {
  /// Frames of trail behind each track (0: no trail). The trail fades linearly to the
  /// background over this many frames.
  int trail_frames = 45;
  /// Radius of the marker of a track's current position, metres.
  double marker_radius_m = 0.22;
  /// Draw each track's id next to its marker.
  bool show_ids = true;
  /// Draw the cameras' fields of view (translucent) and centres.
  bool show_cameras = true;
  /// Spacing of the floor grid, metres (0: no grid).
  double grid_m = 1.0;
  /// The site's regions and lines to draw under the tracks (DrawSite); null: none.
  const analytics::Site* site = nullptr;
};

/// Draws cameras (centre marker with the optical axis direction, label "C<id>", and when
/// `fields_of_view` the translucent field of view on the floor) onto `image`.
void DrawCameras(const FloorMapping& mapping,
                 const std::vector<geometry::CameraModel>& cameras,
                 cv::Mat* image,
                 bool fields_of_view = true);

/// Colour of the regions (BGR: yellow, visible on the floor view and on the coverage map).
inline const cv::Scalar kRegionColor{40, 200, 240};
/// Colour of the lines (purple).
inline const cv::Scalar kLineColor{190, 50, 170};

/// Draws a site's regions (translucent, outlined, named at their first vertex) and lines (named
/// at their `to` end, with a small arrow across the middle pointing from the line's left to its
/// right: the left_to_right direction of docs/FORMATS.md "Site file") onto `image`.
void DrawSite(const FloorMapping& mapping, const analytics::Site& site, cv::Mat* image);

/// Grows `region` to hold every vertex of `site` with `margin_m` around it.
void IncludeSite(const analytics::Site& site, double margin_m, config::FloorRegion* region);

/// Draws the floor grid (lines every `grid_m` metres, x = 0 and y = 0 brighter) onto `image`.
void DrawFloorGrid(const FloorMapping& mapping, double grid_m, cv::Mat* image);

/// The floor view of frame `frames[current]`: grid, cameras, the trails of every track over the
/// frames [current - trail_frames, current) (by position in `frames`, which must be in time
/// order), and a filled disc with the id at each current track position. A CV_8UC3 image of
/// mapping.width_px x mapping.height_px. `current` must be < frames.size() (checked).
cv::Mat RenderFloorView(const FloorMapping& mapping,
                        const std::vector<geometry::CameraModel>& cameras,
                        const std::vector<tracker::Frame3D>& frames,
                        std::size_t current,
                        const FloorViewOptions& options = {});

}  // namespace mvtrack::viz
