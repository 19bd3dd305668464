#pragma once
/// @file
/// Reading track outputs for `mvtrack eval` and `mvtrack diff`: either an LCM log whose
/// tracks3d_t messages are on transport::kTracksChannel (what `mvtrack replay --out` and the
/// daemon write) or canonical tracks JSONL (transport::TracksJsonLine: `mvtrack replay --jsonl`
/// and the dataset converters' ground truth). The format is recognised by content: a file that
/// starts with the LCM sync word 0xEDA1DA01 is a log, anything else is read as JSONL (an empty
/// file is an empty JSONL file).
///
/// The readers are strict, because a silently skipped frame would falsify a comparison: a line
/// or message that does not parse, a damaged log (truncated, corrupt, bytes skipped between
/// events), a frame index that repeats, duplicate track ids within a frame and frames in
/// different keypoint layouts are all errors (TrackFileError naming the file, the line or event
/// and the reason). Events on other channels of a log are skipped and counted (a recorded daemon
/// log holds detections and tracks). Not thread-safe; used from the CLI's main thread.

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "tracker/types.h"

namespace mvtrack::formats {

/// A track output could not be read: what(), for example
/// "out.jsonl:12: column 40: unknown key \"poss\"" or
/// "run.lcmlog: event 7 on MVTRACK_TRACKS: truncated: ...".
class TrackFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a track output is stored.
enum class TrackFileFormat {
  kJsonl,   ///< canonical tracks JSON lines
  kLcmLog,  ///< LCM log, tracks3d_t on MVTRACK_TRACKS
};

/// "JSONL" or "LCM log".
const char* ToString(TrackFileFormat format);

/// One frame of a track output.
struct TrackFileFrame {
  /// The frame as read (tracks sorted by id; from a log, floats widened to double).
  tracker::Frame3D frame;
  /// transport::TracksJsonLine(frame, layout): the canonical text of the frame, "\n"-terminated.
  std::string canonical_line;
  /// Where the frame is in the file: the 1-based line number (JSONL) or the event number
  /// written in the log (LCM).
  std::int64_t source = 0;
};

/// A whole track output.
struct TrackFile {
  std::string path;                                  ///< as given
  TrackFileFormat format = TrackFileFormat::kJsonl;  ///< detected from the content
  /// The keypoint layout shared by every frame (kNone in box mode); nullopt without frames.
  std::optional<core::KeypointLayoutId> layout;
  /// The frames in file order (frame indices are unique, not necessarily increasing).
  std::vector<TrackFileFrame> frames;
  /// JSONL: lines that are valid but not byte-identical to their canonical form (other
  /// whitespace, key order, number spelling, "\r\n", a missing final newline).
  std::int64_t non_canonical_lines = 0;
  /// LCM log: events on channels other than MVTRACK_TRACKS, by channel.
  std::map<std::string, std::int64_t> ignored_channels;

  /// Number of distinct track ids over all frames.
  std::int64_t CountTrackIds() const;
  /// Sum over frames of the number of tracks.
  std::int64_t CountTrackFrames() const;
  /// One line for people: "<path>: LCM log, 300 frames (0-299), layout coco17, 3 track ids".
  std::string Describe() const;
};

/// Reads a track output, detecting its format from the content.
/// @throws TrackFileError when the file cannot be read or violates the strict rules above.
TrackFile ReadTrackFile(const std::string& path);

/// "coco17", "body25", ..., or "none" (core::GetKeypointLayout(layout).name, "none" for kNone).
std::string LayoutName(core::KeypointLayoutId layout);

}  // namespace mvtrack::formats
