#pragma once
/// @file
/// Camera rigs of the synthetic scene (ring around the room or ceiling grid). Stateless.

#include <vector>

#include "core/types.h"
#include "geometry/camera_model.h"
#include "sim/scene_options.h"

namespace mvtrack::sim {

/// An undistorted pinhole camera `id` at `center_in_world` whose optical axis points along
/// `forward_in_world` (need not be unit, must be non-zero), with the image x axis horizontal
/// (no roll) and the focal length fx = fy = (width/2) / tan(hfov/2), principal point at the
/// image centre. A vertical `forward_in_world` uses world +x as the image's "right".
geometry::CameraModel MakeCamera(CameraId id,
                                 int width_px,
                                 int height_px,
                                 double horizontal_fov_deg,
                                 const Vec3& center_in_world,
                                 const Vec3& forward_in_world);

/// The cameras of `options` (ids 0..num_cameras-1), laid out as options.camera_layout describes
/// (see CameraLayout). Options must be valid.
std::vector<geometry::CameraModel> MakeCameras(const SceneOptions& options);

}  // namespace mvtrack::sim
