#include "tracker/types.h"

#include <algorithm>

namespace mvtrack::tracker {

std::optional<TrackId3D> SortTracksById(Frame3D* frame) {
  std::stable_sort(frame->tracks.begin(),
                   frame->tracks.end(),
                   [](const Track3D& a, const Track3D& b) { return a.id < b.id; });
  for (std::size_t i = 1; i < frame->tracks.size(); ++i) {
    if (frame->tracks[i].id == frame->tracks[i - 1].id) return frame->tracks[i].id;
  }
  return std::nullopt;
}

const char* ToString(FrameRejection rejection) {
  switch (rejection) {
    case FrameRejection::kNone:
      return "none";
    case FrameRejection::kUnknownCamera:
      return "unknown_camera";
    case FrameRejection::kStaleFrame:
      return "stale_frame";
    case FrameRejection::kDuplicateCamera:
      return "duplicate_camera";
    case FrameRejection::kTooManyDetections:
      return "too_many_detections";
    case FrameRejection::kBadFrameIndex:
      return "bad_frame_index";
  }
  return "?";
}

}  // namespace mvtrack::tracker
