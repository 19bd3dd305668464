#include "formats/tracks_io.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::formats {
namespace {

// The first 4 bytes of every LCM log event (lcm/eventlog.c), big-endian 0xEDA1DA01.
constexpr std::array<unsigned char, 4> kLcmSyncWord = {0xED, 0xA1, 0xDA, 0x01};

// Throws unless `path` names an existing regular file (ifstream opens directories too).
void CheckRegularFile(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(st)) throw TrackFileError(path + ": file does not exist");
  if (!std::filesystem::is_regular_file(st)) throw TrackFileError(path + ": not a regular file");
}

bool StartsWithLcmSyncWord(const std::string& path) {
  CheckRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TrackFileError(path + ": cannot open for reading");
  std::array<char, 4> head{};
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (in.gcount() != static_cast<std::streamsize>(head.size())) return false;
  for (std::size_t i = 0; i < head.size(); ++i) {
    if (static_cast<unsigned char>(head[i]) != kLcmSyncWord[i]) return false;
  }
  return true;
}

// Checks the per-frame invariants shared by both formats and appends the frame.
void AddFrame(tracker::Frame3D frame,
              core::KeypointLayoutId layout,
              std::int64_t source,
              const std::string& where,
              std::map<FrameIndex, std::int64_t>* seen,
              TrackFile* file) {
  if (file->layout && *file->layout != layout) {
    throw TrackFileError(where + ": layout " + LayoutName(layout) + " differs from layout " +
                         LayoutName(*file->layout) + " of the earlier frames");
  }
  const auto [it, inserted] = seen->emplace(frame.frame, source);
  if (!inserted) {
    throw TrackFileError(where + ": frame " + std::to_string(frame.frame) + " repeats (first at " +
                         (file->format == TrackFileFormat::kJsonl ? "line " : "event ") +
                         std::to_string(it->second) + ")");
  }
  if (const std::optional<TrackId3D> twice = tracker::SortTracksById(&frame)) {
    throw TrackFileError(where + ": frame " + std::to_string(frame.frame) + ": track id " +
                         std::to_string(*twice) + " appears twice");
  }
  file->layout = layout;
  TrackFileFrame f;
  f.canonical_line = transport::TracksJsonLine(frame, layout);
  f.frame = std::move(frame);
  f.source = source;
  file->frames.push_back(std::move(f));
}

void ReadJsonl(TrackFile* file) {
  std::ifstream in(file->path, std::ios::binary);
  if (!in) throw TrackFileError(file->path + ": cannot open for reading");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw TrackFileError(file->path + ": read error");
  std::map<FrameIndex, std::int64_t> seen;
  std::size_t begin = 0;
  std::int64_t line_number = 0;
  while (begin < text.size()) {
    ++line_number;
    const std::size_t newline = text.find('\n', begin);
    const bool terminated = newline != std::string::npos;
    const std::size_t end = terminated ? newline + 1 : text.size();
    const std::string_view line(text.data() + begin, end - begin);
    begin = end;
    const std::string where = file->path + ":" + std::to_string(line_number);
    core::KeypointLayoutId layout = core::KeypointLayoutId::kNone;
    std::string why;
    std::optional<tracker::Frame3D> frame = transport::ParseTracksJsonLine(line, &layout, &why);
    if (!frame) {
      std::string hint;
      if (line_number == 1) hint = " (the file is neither canonical tracks JSONL nor an LCM log)";
      throw TrackFileError(where + ": " + why + hint);
    }
    AddFrame(std::move(*frame), layout, line_number, where, &seen, file);
    if (file->frames.back().canonical_line != line) ++file->non_canonical_lines;
  }
}

void ReadLcmLog(TrackFile* file) {
  std::string why;
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(file->path, &why);
  if (!reader) throw TrackFileError(why);
  std::map<FrameIndex, std::int64_t> seen;
  while (std::optional<transport::LogEvent> event = reader->Next()) {
    if (event->channel != transport::kTracksChannel) {
      ++file->ignored_channels[event->channel];
      continue;
    }
    const std::string where = file->path + ": event " + std::to_string(event->event_number) +
                              " on " + transport::kTracksChannel;
    transport::TracksDecodeResult decoded =
        transport::DecodeTracks(event->data.data(), event->data.size());
    if (!decoded.ok()) {
      throw TrackFileError(where + ": " + transport::ToString(decoded.status) + ": " +
                           decoded.reason);
    }
    AddFrame(std::move(decoded.message.frame),
             decoded.message.layout,
             event->event_number,
             where,
             &seen,
             file);
  }
  if (reader->end() != transport::LogEnd::kEndOfLog) {
    throw TrackFileError(file->path + ": " + transport::ToString(reader->end()) + ": " +
                         reader->error());
  }
  if (reader->skipped_bytes() > 0) {
    throw TrackFileError(file->path + ": damaged: " + std::to_string(reader->skipped_bytes()) +
                         " bytes between events are not part of any event");
  }
}

}  // namespace

const char* ToString(TrackFileFormat format) {
  return format == TrackFileFormat::kJsonl ? "JSONL" : "LCM log";
}

std::string LayoutName(core::KeypointLayoutId layout) {
  return layout == core::KeypointLayoutId::kNone ? std::string("none")
                                                 : core::GetKeypointLayout(layout).name;
}

std::int64_t TrackFile::CountTrackIds() const {
  std::set<TrackId3D> ids;
  for (const TrackFileFrame& f : frames) {
    for (const tracker::Track3D& t : f.frame.tracks) ids.insert(t.id);
  }
  return static_cast<std::int64_t>(ids.size());
}

std::int64_t TrackFile::CountTrackFrames() const {
  std::int64_t n = 0;
  for (const TrackFileFrame& f : frames) n += static_cast<std::int64_t>(f.frame.tracks.size());
  return n;
}

std::string TrackFile::Describe() const {
  std::ostringstream os;
  os << path << ": " << ToString(format) << ", " << frames.size() << " frame(s)";
  if (!frames.empty()) {
    FrameIndex first = frames.front().frame.frame;
    FrameIndex last = first;
    for (const TrackFileFrame& f : frames) {
      first = std::min(first, f.frame.frame);
      last = std::max(last, f.frame.frame);
    }
    os << " (" << first << "-" << last << ")";
  }
  os << ", layout " << (layout ? LayoutName(*layout) : std::string("unknown (no frames)")) << ", "
     << CountTrackIds() << " track id(s), " << CountTrackFrames() << " track-frame(s)";
  if (non_canonical_lines > 0) os << "; " << non_canonical_lines << " line(s) not canonical";
  if (!ignored_channels.empty()) {
    std::int64_t n = 0;
    for (const auto& [channel, count] : ignored_channels) n += count;
    os << "; " << n << " event(s) on other channels ignored";
  }
  return os.str();
}

TrackFile ReadTrackFile(const std::string& path) {
  TrackFile file;
  file.path = path;
  file.format = StartsWithLcmSyncWord(path) ? TrackFileFormat::kLcmLog : TrackFileFormat::kJsonl;
  if (file.format == TrackFileFormat::kLcmLog) {
    ReadLcmLog(&file);
    // A detections log is not a track output: say so instead of scoring nothing.
    std::int64_t detections = 0;
    for (const auto& [channel, count] : file.ignored_channels) {
      if (transport::IsDetectionsChannel(channel)) detections += count;
    }
    if (file.frames.empty() && detections > 0) {
      throw TrackFileError(path + ": a detections log (" + std::to_string(detections) +
                           " camera_detections_t events, no " + transport::kTracksChannel +
                           "), not tracks: track it first (mvtrack replay --out or --jsonl)");
    }
  } else {
    ReadJsonl(&file);
  }
  return file;
}

}  // namespace mvtrack::formats
