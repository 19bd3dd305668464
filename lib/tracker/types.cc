#include "tracker/types.h"

namespace mvtrack::tracker {

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
