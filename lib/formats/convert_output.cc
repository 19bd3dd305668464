#include "formats/convert_output.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "datasets/dataset.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::formats {
namespace {

const char* const kAllOutputFiles[] = {kConvertLogFile,
                                       kConvertCalibrationFile,
                                       kConvertGroundTruthFile,
                                       kConvertPeerFile,
                                       kConvertGroundPointsFile,
                                       kConvertReadmeFile};

}  // namespace

ConvertOutputDir::ConvertOutputDir(const std::filesystem::path& dir, bool overwrite) : dir_(dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir_, ec)) {
    if (!std::filesystem::is_directory(dir_, ec)) {
      throw std::runtime_error("--out " + dir_.string() + " exists and is not a directory");
    }
    if (!overwrite && !std::filesystem::is_empty(dir_, ec)) {
      throw std::runtime_error("output directory " + dir_.string() +
                               " is not empty (pass --overwrite to replace the files of an "
                               "earlier conversion)");
    }
    if (overwrite) {
      for (const char* name : kAllOutputFiles) {
        for (const std::filesystem::path& p : {File(name), TempFile(name)}) {
          std::filesystem::remove(p, ec);
          if (ec) throw std::runtime_error("cannot remove " + p.string() + ": " + ec.message());
        }
      }
    }
    return;
  }
  std::filesystem::create_directories(dir_, ec);
  if (ec)
    throw std::runtime_error("cannot create output directory " + dir_.string() + ": " +
                             ec.message());
}

std::filesystem::path ConvertOutputDir::TempFile(const std::string& name) const {
  return dir_ / ("." + name + ".partial");
}

void ConvertOutputDir::Commit(const std::string& name) const {
  std::error_code ec;
  std::filesystem::rename(TempFile(name), File(name), ec);
  if (ec) {
    throw std::runtime_error("cannot rename " + TempFile(name).string() + " to " +
                             File(name).string() + ": " + ec.message());
  }
}

void ConvertOutputDir::WriteText(const std::string& name, const std::string& text) const {
  const std::filesystem::path tmp = TempFile(name);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  Commit(name);
}

const char* ToString(ChannelMode mode) {
  return mode == ChannelMode::kShared ? "shared" : "per-camera";
}

DetectionsLogSink::DetectionsLogSink(const ConvertOutputDir* out, ChannelMode mode)
    : out_(out), mode_(mode) {
  std::string why;
  writer_ = transport::LogWriter::Open(out_->TempFile(kConvertLogFile).string(), &why);
  if (writer_ == nullptr) throw std::runtime_error(why);
}

DetectionsLogSink::~DetectionsLogSink() {
  if (writer_ == nullptr) return;  // finished (committed) or never opened
  // Not finished: an error interrupted the conversion; leave no partial log behind.
  writer_.reset();
  std::error_code ec;
  std::filesystem::remove(out_->TempFile(kConvertLogFile), ec);
}

void DetectionsLogSink::WriteFrame(std::vector<CameraFrameToWrite> frames) {
  if (writer_ == nullptr) throw std::runtime_error("detections log already finished");
  if (frames.empty()) return;
  std::stable_sort(
      frames.begin(), frames.end(), [](const CameraFrameToWrite& a, const CameraFrameToWrite& b) {
        return a.frame->camera_id < b.frame->camera_id;
      });
  const FrameIndex frame = frames.front().frame->frame;
  if (stats_.last_frame.has_value() && frame <= *stats_.last_frame) {
    throw std::runtime_error("frame " + std::to_string(frame) + " written after frame " +
                             std::to_string(*stats_.last_frame));
  }
  const transport::DecodeLimits limits;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const core::CameraFrame& cf = *frames[i].frame;
    if (cf.frame != frame) {
      throw std::runtime_error("camera-frames of frames " + std::to_string(frame) + " and " +
                               std::to_string(cf.frame) + " written as one frame");
    }
    if (i > 0 && frames[i - 1].frame->camera_id == cf.camera_id) {
      throw std::runtime_error("camera " + std::to_string(cf.camera_id) +
                               " appears twice in frame " + std::to_string(frame));
    }
    const std::vector<std::uint8_t> bytes =
        transport::EncodeCameraDetections(cf, frames[i].image_width_px, frames[i].image_height_px);
    if (bytes.size() > limits.max_message_bytes) {
      throw std::runtime_error("camera " + std::to_string(cf.camera_id) + ", frame " +
                               std::to_string(frame) + ": the encoded message has " +
                               std::to_string(bytes.size()) + " bytes, more than the " +
                               std::to_string(limits.max_message_bytes) + " a replay accepts");
    }
    const std::string channel = mode_ == ChannelMode::kShared
                                    ? std::string(transport::kDetectionsChannel)
                                    : transport::DetectionsChannelForCamera(cf.camera_id);
    std::string why;
    if (!writer_->Write(channel, cf.utime, bytes, &why)) throw std::runtime_error(why);
    ++stats_.events;
    ++stats_.events_per_camera[cf.camera_id];
    const auto n = static_cast<std::int64_t>(cf.detections.size());
    stats_.detections += n;
    stats_.detections_per_camera[cf.camera_id] += n;
    for (const core::Detection2D& d : cf.detections) {
      const std::string layout = d.layout == core::KeypointLayoutId::kNone
                                     ? std::string("none")
                                     : core::GetKeypointLayout(d.layout).name;
      ++stats_.detections_per_layout[layout];
    }
    if (!stats_.first_utime.has_value() || cf.utime < *stats_.first_utime)
      stats_.first_utime = cf.utime;
    if (!stats_.last_utime.has_value() || cf.utime > *stats_.last_utime)
      stats_.last_utime = cf.utime;
  }
  ++stats_.frames;
  if (!stats_.first_frame.has_value()) stats_.first_frame = frame;
  stats_.last_frame = frame;
}

void DetectionsLogSink::Finish() {
  if (writer_ == nullptr) throw std::runtime_error("detections log already finished");
  std::string why;
  if (!writer_->Flush(&why)) throw std::runtime_error(why);
  writer_.reset();
  out_->Commit(kConvertLogFile);
  std::error_code ec;
  const auto size = std::filesystem::file_size(out_->File(kConvertLogFile), ec);
  if (ec) throw std::runtime_error("cannot stat " + out_->File(kConvertLogFile).string());
  stats_.bytes = static_cast<std::int64_t>(size);
}

std::string SequenceToTracksJsonl(const eval::EvalSequence& sequence,
                                  core::KeypointLayoutId layout,
                                  double fps,
                                  const std::string& name) {
  std::string why;
  if (!eval::ValidateSequence(sequence, name, &why)) throw std::runtime_error(why);
  std::vector<const eval::EvalFrame*> frames;
  frames.reserve(sequence.size());
  for (const eval::EvalFrame& f : sequence) frames.push_back(&f);
  std::sort(frames.begin(), frames.end(), [](const eval::EvalFrame* a, const eval::EvalFrame* b) {
    return a->frame < b->frame;
  });
  std::string text;
  for (const eval::EvalFrame* f : frames) {
    tracker::Frame3D out;
    out.frame = f->frame;
    out.utime = datasets::FrameUtime(f->frame, fps);
    for (const eval::EvalObject& o : f->objects) {
      tracker::Track3D t;
      t.id = o.id;
      t.position = o.position;
      t.joints = o.joints;
      out.tracks.push_back(std::move(t));
    }
    std::sort(out.tracks.begin(),
              out.tracks.end(),
              [](const tracker::Track3D& a, const tracker::Track3D& b) { return a.id < b.id; });
    text += transport::TracksJsonLine(out, layout);
  }
  return text;
}

std::string ShellQuoteCommand(const std::vector<std::string>& args) {
  std::string out;
  for (const std::string& a : args) {
    if (!out.empty()) out.push_back(' ');
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                         "0123456789_./=:,@%+-") == std::string::npos;
    if (plain) {
      out += a;
      continue;
    }
    out.push_back('\'');
    for (char c : a) {
      if (c == '\'') {
        out += "'\\''";
      } else {
        out.push_back(c);
      }
    }
    out.push_back('\'');
  }
  return out;
}

}  // namespace mvtrack::formats
