#include "association/association.h"

#include <string>

#include "core/check.h"

namespace mvtrack::association {

std::vector<std::vector<int>> AssociateTracklets(const geometry::CameraRig& rig,
                                                 const std::vector<core::Tracklet2D>& tracklets,
                                                 const AssociationOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  return ClusterTracklets(ComputeDistanceMatrixForClustering(rig, tracklets, options), options);
}

}  // namespace mvtrack::association
