#pragma once
/// @file
/// Readers of the per-camera detection files that `mvtrack convert motchallenge` and
/// `mvtrack convert coco` turn into a detections log (docs/FORMATS.md, "MOTChallenge det.txt"
/// and "COCO-style keypoint JSON"), and the frame/utime rule both share.
///
///  - MOTChallenge det.txt: one detection per line, `frame,id,left,top,width,height,conf` plus
///    optionally `,x,y,z` (7 or 10 comma-separated numbers); box-only detections.
///  - COCO keypoint results: a JSON array of person records (or an object whose "annotations"
///    holds that array), each with "image_id" or "frame", 17 COCO keypoints, an optional score
///    and an optional box; COCO-17 pose detections.
///
/// Every reader checks its whole input and throws ImportError naming the file, the line (and
/// column for JSON) and the reason on the first violation. Free functions, stateless.

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/detection.h"
#include "core/types.h"

namespace mvtrack::formats {

/// Bad input in a detection file. what() is "FILE:LINE: reason" or "FILE:LINE:COLUMN: PATH:
/// reason".
class ImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The detections of one camera's file, grouped by frame.
struct ImportedDetections {
  /// Detections by frame index, each frame's in file order.
  std::map<FrameIndex, std::vector<core::Detection2D>> by_frame;
  /// Line (1-based) of the first record of each frame in `by_frame`, for error messages.
  std::map<FrameIndex, std::int64_t> first_line;
  /// Detections read.
  std::int64_t records = 0;
  /// Scores or keypoint confidences that were outside [0, 1] and clamped (clamp_scores).
  std::int64_t clamped = 0;
};

/// Options of ReadMotChallengeDetections().
struct MotChallengeOptions {
  /// Pixel coordinate of the top-left pixel in the file: 1 (the MOTChallenge convention,
  /// subtracted so boxes use mvtrack's origin at the top-left pixel's corner) or 0 (kept).
  int pixel_origin = 1;
  /// false: a conf outside [0, 1] is an error. true: it is clamped to [0, 1] and counted.
  bool clamp_scores = false;
};

/// Reads a MOTChallenge det.txt: per non-empty line `frame,id,left,top,width,height,conf` or
/// `frame,id,left,top,width,height,conf,x,y,z` (spaces around values allowed, a trailing "\r"
/// accepted). frame: integer >= 1; id: integer (ignored, detections carry no identity); left,
/// top: finite; width, height: finite and > 0; conf: in [0, 1] (see clamp_scores); x, y, z:
/// numbers (ignored). Box = [left - o, top - o, left - o + width, top - o + height] with o the
/// pixel origin; score = conf; layout none. `source` names the input in errors.
/// @throws ImportError on the first bad line ("FILE:LINE: column N (name): reason").
ImportedDetections ReadMotChallengeDetections(std::string_view text,
                                              const std::string& source,
                                              const MotChallengeOptions& options);

/// How the third value of each COCO keypoint triple is read.
enum class CocoKeypointScore {
  kConfidence,  ///< a detector confidence in [0, 1] (keypoint results of pose detectors)
  kVisibility,  ///< the COCO annotation flag v in {0, 1, 2}: 0 -> confidence 0, 1 or 2 -> 1
};

/// Options of ReadCocoKeypoints().
struct CocoOptions {
  /// Meaning of the keypoints' third values.
  CocoKeypointScore keypoint_score = CocoKeypointScore::kConfidence;
  /// false: a score or keypoint confidence outside [0, 1] is an error. true: clamped, counted.
  bool clamp_scores = false;
};

/// Keypoints per record: the COCO-17 layout.
inline constexpr int kCocoNumKeypoints = 17;

/// Reads COCO-style keypoint JSON (the whole file in `text`). Accepted: a JSON array of
/// records, or an object with an "annotations" array of records (its other keys ignored).
/// A record is an object with
///   "image_id": integer >= 0, or a string (an image file name) whose base name without
///               extension ends in decimal digits ("000123.jpg" -> 123), or "frame": integer
///               >= 0 (exactly one of the two): the frame index;
///   "keypoints": 51 numbers [x1, y1, v1, ..., x17, y17, v17] or 17 arrays [x, y, v], raw
///               pixels, COCO-17 joint order; v per keypoint_score;
///   "score":    optional, in [0, 1]; default: mean confidence of the keypoints with
///               confidence > 0;
///   "bbox" or "box": optional [x, y, width, height], width and height > 0; default: the
///               keypoint bounds grown by 10 % of their height on each side (at least 1 px;
///               datasets::BoxFromKeypoints), which needs 2 keypoints with confidence > 0;
///   "category_id": optional, must be 1 (person).
/// Other keys (id, area, iscrowd, num_keypoints, idx, track_id, ...) are ignored.
/// @throws ImportError on the first violation ("FILE:LINE:COLUMN: PATH: reason").
ImportedDetections ReadCocoKeypoints(std::string_view text,
                                     const std::string& source,
                                     const CocoOptions& options);

/// Capture time of `frame`: start_utime + round((frame - first_frame_number) * 1e6 / fps) µs.
/// @pre fps > 0 and frame >= first_frame_number (checked by the caller).
Utime ImportFrameUtime(FrameIndex frame,
                       FrameIndex first_frame_number,
                       double fps,
                       Utime start_utime);

}  // namespace mvtrack::formats
