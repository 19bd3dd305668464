#pragma once
/// @file
/// Reader of the generic JSON-lines detection format that `mvtrack convert jsonl` turns into a
/// detections log. The format is specified in docs/FORMATS.md ("JSON-lines detections"); in
/// short, one line per camera-frame:
///
///   {"camera": 3, "frame": 120, "utime": 1700000004000000, "image_size": [1920, 1080],
///    "detections": [{"box": [x_min, y_min, x_max, y_max], "score": 0.93,
///                    "keypoints": [[x, y, conf], ...], "layout": "coco17",
///                    "embedding": [...], "embedding_model": "osnet_x0_25"}]}
///
/// in raw (distorted) image pixels. `image_size`, `keypoints` (with `layout`), `embedding` and
/// `embedding_model` are optional. Every line is a strict RFC 8259 JSON object checked against this
/// schema (unknown, missing and duplicate keys, wrong types, out-of-range values are errors), and
/// the lines together must satisfy the cross-line rules: frames never decrease, a camera appears at
/// most once per frame, a camera's utime increases strictly from frame to frame, and (when the
/// calibration is known) the camera exists and the image size matches.
///
/// JSON is read by lib/json (nlohmann-json's parser with byte positions); not yaml-cpp, which is
/// lenient where this format must be strict (single quotes, unquoted words, comments, `.inf`,
/// duplicate keys) and was measured 25 times slower (docs/DECISIONS.md "JSON").
///
/// Free functions are stateless; JsonlDetectionsReader is a single-owner, single-threaded
/// object.

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/detection.h"
#include "core/types.h"

namespace mvtrack::formats {

/// Most detections one line may hold (the decode limit of the detections wire format, so
/// every accepted line can be replayed).
inline constexpr int kJsonlMaxDetections = 1000;
/// Most values one embedding may hold (the wire format's decode limit).
inline constexpr int kJsonlMaxEmbedding = 4096;
/// Longest embedding_model name (the wire format's string decode limit).
inline constexpr int kJsonlMaxModelName = 64;
/// Deepest nesting of arrays and objects the parser accepts (the schema needs 5:
/// line, detections, detection, keypoints, keypoint).
inline constexpr int kJsonlMaxDepth = 16;
/// Largest image width or height, pixels (as in the calibration format).
inline constexpr int kJsonlMaxImageSize = 1048576;

/// One valid line: a camera-frame and the image size it declares.
struct JsonlCameraFrame {
  /// camera_id, frame, utime and the detections in line order.
  core::CameraFrame frame;
  /// The line's "image_size", pixels; 0 when the line has none.
  int image_width_px = 0;
  int image_height_px = 0;
};

/// Parses one line of the format (without the "\n"; one trailing "\r" is accepted, so CRLF
/// files work). Returns std::nullopt on any error and writes "column C: PATH: REASON" to `why`
/// (when not null): C is the 1-based byte column, PATH the key path of the offending value
/// ("detections[2].keypoints[5][2]", "" for the line itself) and REASON what is wrong. Checks
/// only the line itself, not the cross-line rules.
std::optional<JsonlCameraFrame> ParseJsonlDetectionsLine(std::string_view line, std::string* why);

/// A bad line of the input, with the full error message.
struct JsonlBadLine {
  std::int64_t line = 0;  ///< 1-based line number
  std::string message;    ///< "SOURCE:LINE:COLUMN: PATH: REASON" (":COLUMN" when known)
};

/// The first bad line when bad lines are not skipped. what() is the JsonlBadLine message.
class JsonlError : public std::runtime_error {
 public:
  /// `bad`: the offending line.
  explicit JsonlError(JsonlBadLine bad);
  /// 1-based line number of the offending line.
  std::int64_t line() const { return bad_.line; }

 private:
  JsonlBadLine bad_;
};

/// What the reader knows about one camera of the calibration.
struct JsonlCameraInfo {
  int width_px = 0;   ///< image width, pixels
  int height_px = 0;  ///< image height, pixels
};

/// Options of JsonlDetectionsReader.
struct JsonlReaderOptions {
  /// false: the first bad line throws JsonlError. true: bad lines are skipped and counted.
  bool skip_bad_lines = false;
  /// The calibrated cameras by id. When not empty, a line for another camera is bad, and a
  /// line's image_size must equal its camera's. Empty: neither is checked.
  std::map<CameraId, JsonlCameraInfo> cameras;
  /// How many bad lines are kept in first_bad_lines().
  std::size_t max_kept_bad_lines = 5;
};

/// Reads the lines of one input stream in order and applies the line and cross-line rules.
/// A skipped bad line does not change the cross-line state (the next line is checked against
/// the last good one).
class JsonlDetectionsReader {
 public:
  /// Reads from `in` (not owned; must outlive the reader). `source_name` (usually the path)
  /// starts every error message.
  JsonlDetectionsReader(std::istream* in, std::string source_name, JsonlReaderOptions options);

  /// The next good line, or std::nullopt at the end of the input.
  /// @throws JsonlError on a bad line unless skip_bad_lines; std::runtime_error when the
  /// stream fails for another reason than its end.
  std::optional<JsonlCameraFrame> Next();

  /// Lines read so far (good and bad).
  std::int64_t lines_read() const { return lines_read_; }
  /// Bytes of input consumed so far (lines and their newlines).
  std::int64_t bytes_read() const { return bytes_read_; }
  /// Bad lines skipped so far.
  std::int64_t bad_lines() const { return bad_lines_; }
  /// The first max_kept_bad_lines bad lines, in input order.
  const std::vector<JsonlBadLine>& first_bad_lines() const { return first_bad_lines_; }

 private:
  std::istream* in_;
  std::string source_name_;
  JsonlReaderOptions options_;
  std::int64_t lines_read_ = 0;
  std::int64_t bytes_read_ = 0;
  std::int64_t bad_lines_ = 0;
  std::vector<JsonlBadLine> first_bad_lines_;
  // Cross-line state of the good lines so far.
  std::optional<FrameIndex> current_frame_;
  std::int64_t current_frame_line_ = 0;                // line that opened current_frame_
  std::map<CameraId, std::int64_t> cameras_in_frame_;  // camera -> line, at current_frame_
  std::map<CameraId, std::pair<Utime, std::int64_t>> last_utime_;  // camera -> (utime, line)
};

}  // namespace mvtrack::formats
