#pragma once
/// @file
/// Cross-view association of one sliding window (paper Sec. 3.1, "Collaborative Multi-frame
/// Multi-view Association"): the Eq. 4 distance matrix of the window's 2D tracklets followed by
/// Algorithm 1 (PDNC) or one of the appendix's alternatives. Umbrella header of the module;
/// stateless functions, thread-compatible, deterministic.

#include <vector>

#include "association/clustering.h"
#include "association/options.h"
#include "association/tracklet_distance.h"
#include "core/observation.h"
#include "geometry/camera_rig.h"

namespace mvtrack::association {

/// ComputeDistanceMatrixForClustering followed by ClusterTracklets (the matrix is consumed in
/// place): the same clusters as ClusterTracklets(ComputeDistanceMatrix(...)), computed faster.
/// Every tracklet's camera must be in `rig` (checked); `options` must pass Validate() (checked).
/// Returns clusters of indices into `tracklets`: sorted lists, ordered by smallest index, every
/// tracklet in exactly one cluster (a person seen by one tracklet only is a singleton).
std::vector<std::vector<int>> AssociateTracklets(const geometry::CameraRig& rig,
                                                 const std::vector<core::Tracklet2D>& tracklets,
                                                 const AssociationOptions& options);

}  // namespace mvtrack::association
