#pragma once
/// @file
/// LCM channel names of mvtrack and the per-camera detections convention. Stateless.
///
/// Detections travel either on the one shared channel kDetectionsChannel (the camera is named by
/// camera_detections_t.camera_id) or on one channel per camera, "MVTRACK_DETECTIONS_<camera_id>"
/// with the id in canonical decimal (no sign, no leading zeros). A subscriber that accepts both
/// subscribes to kDetectionsChannelRegex (LCM channel subscriptions are regular expressions,
/// implicitly anchored). On a per-camera channel the message's camera_id must equal the channel's
/// (CameraIdFromChannel); checking that is the receiver's job.

#include <optional>
#include <string>
#include <string_view>

#include "core/types.h"

namespace mvtrack::transport {

/// Shared detections channel (camera_detections_t); also the per-camera prefix without "_".
inline constexpr char kDetectionsChannel[] = "MVTRACK_DETECTIONS";
/// Prefix of the per-camera detections channels: kDetectionsChannelPrefix + "<camera_id>".
inline constexpr char kDetectionsChannelPrefix[] = "MVTRACK_DETECTIONS_";
/// LCM subscription regex matching the shared and every per-camera detections channel.
inline constexpr char kDetectionsChannelRegex[] = "MVTRACK_DETECTIONS(_[0-9]+)?";
/// Tracker output (tracks3d_t), one message per finalized frame.
inline constexpr char kTracksChannel[] = "MVTRACK_TRACKS";
/// Periodic tracker health (tracker_status_t).
inline constexpr char kStatusChannel[] = "MVTRACK_STATUS";
/// Default channel of the provisional layer (tracks3d_t with LAYER_PROVISIONAL).
inline constexpr char kProvisionalChannel[] = "MVTRACK_TRACKS_NOW";

/// "MVTRACK_DETECTIONS_<camera_id>".
/// @pre camera_id >= 0 (checked; aborts otherwise).
std::string DetectionsChannelForCamera(CameraId camera_id);

/// The camera id of a per-camera detections channel ("MVTRACK_DETECTIONS_7" -> 7). nullopt for
/// the shared channel (the id is in the message) and for anything else: other channels, an
/// empty or non-decimal suffix, a sign, leading zeros ("_07"), or an id beyond int32.
std::optional<CameraId> CameraIdFromChannel(std::string_view channel);

/// True for the shared and for every per-camera detections channel.
bool IsDetectionsChannel(std::string_view channel);

}  // namespace mvtrack::transport
