#pragma once
/// @file
/// The canonical JSON-lines form of the tracker's output: the regression format written by
/// `mvtrack replay --jsonl` and compared by `mvtrack diff` / `mvtrack eval`. One line per
/// finalized frame:
///
///   {"frame": F, "layout": "<name>", "tracks": [T, ...], "utime": U[, "zones": [N, ...]]}
///   T = {["bone_lengths": [L, ...], ]"id": I, "joints": [J, ...], "position": [x, y, z]
///        [, "zones": [Z, ...]]}
///   J = [x, y, z] or null
///   L = a bone length of the layout's bone in order, metres (0: not known yet); only with the
///       skeleton fit (tracker::Track3D::bone_lengths non-empty)
///   N = a zone name of a site's stitched output (tracker::Frame3D::zones); only there
///   Z = the zones that saw the track, ascending indices into the line's "zones" (issue 43)
///
/// Canonical means byte-for-byte reproducible: keys sorted alphabetically at every level,
/// tracks sorted by id, ", " and ": " as separators, integers in plain decimal, coordinates in
/// metres with exactly kTracksJsonDecimals digits after the point (std::to_chars: no locale),
/// "-0.0000" written as "0.0000", the line ends with a single "\n". The layout is the layout's
/// name ("coco17", ...) or "none" in box mode, where every track has "joints": [].
///
/// JSON has no NaN or infinity: a joint with a non-finite coordinate is written as null (not
/// triangulated) and a non-finite footprint as "position": null.
///
/// Stateless functions.

#include <optional>
#include <string>
#include <string_view>

#include "core/keypoint_layout.h"
#include "tracker/types.h"

namespace mvtrack::transport {

/// Digits after the decimal point of every coordinate (0.1 mm).
inline constexpr int kTracksJsonDecimals = 4;

/// The canonical line of `frame` (terminated by "\n"). Writes id, footprint, joints and bone
/// lengths and zones (when it has them) of each track, and the frame's zones (when it has
/// them); confidence, cameras, age and state are not part of the
/// format. Tracks with equal ids keep their order. The joints are written as given (the tracker's
/// invariant: none in box mode, one per joint of `layout` in pose mode).
std::string TracksJsonLine(const tracker::Frame3D& frame, core::KeypointLayoutId layout);

/// Parses one line of the format above (whitespace between tokens is free, a trailing "\n" or
/// "\r\n" is allowed, keys may come in any order). Returns the frame with tracks sorted by id
/// (id, position, joints, bone lengths and zones set; the other Track3D fields keep their defaults;
/// "position": null gives NaN coordinates) and sets `layout` (when not null). Returns nullopt with
/// `why` set (when not null; column numbers are 1-based bytes) when the line is not exactly this
/// schema: syntax errors, a missing, duplicate or unknown key, a value of the wrong type, an
/// integer beyond int64, a number beyond double, an unknown layout name, duplicate track ids, a
/// track whose joint count is neither 0 nor the layout's (always 0 for "none"), an empty zone
/// name, or track zones that are not ascending indices of the line's zones.
std::optional<tracker::Frame3D> ParseTracksJsonLine(std::string_view line,
                                                    core::KeypointLayoutId* layout,
                                                    std::string* why);

}  // namespace mvtrack::transport
