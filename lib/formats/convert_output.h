#pragma once
/// @file
/// The output directory of `mvtrack convert`: the detections log (one camera_detections_t
/// event per camera-frame), the canonical tracks JSONL files (ground truth, peer output,
/// WILDTRACK ground points) and the plain-text files, each written to a temporary name and
/// renamed into place when complete, so an interrupted conversion never leaves a
/// complete-looking file. Single-owner, single-threaded objects (used from the CLI's main
/// thread).

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/types.h"
#include "eval/sequence.h"
#include "tracker/types.h"

namespace mvtrack::transport {
class LogWriter;
}  // namespace mvtrack::transport

namespace mvtrack::formats {

/// File names inside the output directory.
inline constexpr char kConvertLogFile[] = "detections.lcmlog";
inline constexpr char kConvertCalibrationFile[] = "calibration.yaml";
inline constexpr char kConvertGroundTruthFile[] = "ground_truth.jsonl";
inline constexpr char kConvertPeerFile[] = "peer.jsonl";
inline constexpr char kConvertGroundPointsFile[] = "ground_points.jsonl";
inline constexpr char kConvertReadmeFile[] = "README.txt";

/// The output directory of one conversion.
class ConvertOutputDir {
 public:
  /// Prepares `dir`: creates it (with parents) when missing. An existing directory must be
  /// empty unless `overwrite`; with `overwrite`, the files of an earlier conversion (the
  /// kConvert*File names) are removed first so the directory never mixes two conversions, and
  /// other files are left alone.
  /// @throws std::runtime_error naming the directory when it cannot be created or is not
  /// empty (without `overwrite`).
  ConvertOutputDir(const std::filesystem::path& dir, bool overwrite);

  /// The directory.
  const std::filesystem::path& path() const { return dir_; }
  /// `<dir>/<name>`.
  std::filesystem::path File(const std::string& name) const { return dir_ / name; }
  /// The temporary name under which `name` is written: `<dir>/.<name>.partial`.
  std::filesystem::path TempFile(const std::string& name) const;
  /// Renames TempFile(name) to File(name).
  /// @throws std::runtime_error when the rename fails.
  void Commit(const std::string& name) const;
  /// Writes `text` to TempFile(name), then commits it.
  /// @throws std::runtime_error when writing fails.
  void WriteText(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path dir_;
};

/// How detections are put on LCM channels.
enum class ChannelMode {
  kShared,     ///< every camera on transport::kDetectionsChannel
  kPerCamera,  ///< camera c on transport::DetectionsChannelForCamera(c)
};

/// "shared" or "per-camera".
const char* ToString(ChannelMode mode);

/// Statistics of a detections log.
struct DetectionsLogStats {
  std::int64_t events = 0;                                 ///< camera-frames written
  std::int64_t frames = 0;                                 ///< distinct frame indices written
  std::int64_t detections = 0;                             ///< detections over all events
  std::int64_t bytes = 0;                                  ///< size of the log file (after Finish)
  std::optional<FrameIndex> first_frame;                   ///< smallest frame written
  std::optional<FrameIndex> last_frame;                    ///< largest frame written
  std::optional<Utime> first_utime;                        ///< smallest event timestamp
  std::optional<Utime> last_utime;                         ///< largest event timestamp
  std::map<CameraId, std::int64_t> events_per_camera;      ///< by camera id
  std::map<CameraId, std::int64_t> detections_per_camera;  ///< by camera id
  /// Detections by keypoint layout name ("none" for box-only).
  std::map<std::string, std::int64_t> detections_per_layout;
};

/// One camera-frame to write, with the image size of its camera.
struct CameraFrameToWrite {
  const core::CameraFrame* frame = nullptr;  ///< not owned
  int image_width_px = 0;                    ///< pixels; 0 = unknown
  int image_height_px = 0;                   ///< pixels; 0 = unknown
};

/// Writes the detections log, one synchronized frame at a time. Events: one
/// camera_detections_t per camera-frame (also when it has no detections), frames in increasing
/// order, within a frame cameras in increasing id order, event timestamp = the camera-frame's
/// utime. Writes to the output directory's temporary name; Finish() commits it.
class DetectionsLogSink {
 public:
  /// Opens TempFile(kConvertLogFile) of `out` (which must outlive the sink).
  /// @throws std::runtime_error when the file cannot be created.
  DetectionsLogSink(const ConvertOutputDir* out, ChannelMode mode);
  ~DetectionsLogSink();
  DetectionsLogSink(const DetectionsLogSink&) = delete;
  DetectionsLogSink& operator=(const DetectionsLogSink&) = delete;

  /// Writes the camera-frames of one frame, sorted by camera id (the vector is reordered).
  /// @throws std::runtime_error when the camera-frames are not all of one frame, the frame is
  /// not larger than the previous one, a camera repeats, an encoded message exceeds the wire
  /// format's decode limit (transport::DecodeLimits::max_message_bytes), or writing fails.
  void WriteFrame(std::vector<CameraFrameToWrite> frames);

  /// Flushes, closes and commits the log; fills stats().bytes.
  /// @throws std::runtime_error when flushing or the rename fails.
  void Finish();

  /// What has been written so far.
  const DetectionsLogStats& stats() const { return stats_; }

 private:
  const ConvertOutputDir* out_;
  ChannelMode mode_;
  std::unique_ptr<transport::LogWriter> writer_;
  DetectionsLogStats stats_;
};

/// Canonical tracks JSONL (transport::TracksJsonLine) of `sequence`: one line per frame in
/// increasing frame order, each object a track (id = the object's id, position = its
/// footprint, joints as given), utime = datasets::FrameUtime(frame, fps). Frames that appear
/// twice are an error.
/// @throws std::runtime_error when `sequence` fails eval::ValidateSequence.
std::string SequenceToTracksJsonl(const eval::EvalSequence& sequence,
                                  core::KeypointLayoutId layout,
                                  double fps,
                                  const std::string& name);

/// `args` as one shell command line (arguments with characters outside [A-Za-z0-9_./=:,@%+-]
/// single-quoted).
std::string ShellQuoteCommand(const std::vector<std::string>& args);

}  // namespace mvtrack::formats
