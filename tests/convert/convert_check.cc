// mvtrack_convert_check: verifies the output directory of `mvtrack convert` with the project's
// own readers, independently of the converter's code:
//  - detections.lcmlog: read with transport::LogReader (clean end, no skipped bytes), every event
//    decoded with transport::DecodeCameraDetections, channel as requested, event timestamp ==
//    message utime, events strictly ordered by (frame, camera id), event numbers 0, 1, 2, ...;
//    counts per camera, detections, layouts; every detection passes core::ValidateDetection;
//  - calibration.yaml: parsed with config::LoadCalibration; every event's camera is in it with
//    the same image size;
//  - ground_truth.jsonl / peer.jsonl / ground_points.jsonl: every line parsed with
//    transport::ParseTracksJsonLine, canonical (TracksJsonLine of the parsed frame reproduces
//    the line byte for byte), frames strictly increasing, each frame's utime equal to the log's.
// Expectations come from the command line; every violated one is printed and the exit status
// is 1. With --dump FILE the decoded log is written as JSON lines (one per event) for the test
// scripts to compare with the converter's input.
//
// usage: mvtrack_convert_check DIR [--cameras 0,1,2] [--frames N] [--first-frame F]
//          [--last-frame F] [--every-camera-frame] [--fps F] [--layout NAME]
//          [--channel shared|per-camera] [--detections N] [--detections-per-camera a,b,c]
//          [--gt-lines N] [--gt-layout NAME] [--peer-lines N] [--ground-points-lines N]
//          [--dump FILE]

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "config/calibration.h"
#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace {

using namespace mvtrack;  // NOLINT: a small test program

int g_failures = 0;

void Fail(const std::string& what) {
  std::cerr << "FAIL: " << what << "\n";
  ++g_failures;
}

template <typename A, typename B>
void ExpectEq(const std::string& what, const A& got, const B& want) {
  if (!(got == want)) {
    std::ostringstream os;
    os << what << ": got " << got << ", expected " << want;
    Fail(os.str());
  }
}

std::vector<std::int64_t> ParseIntList(const std::string& text) {
  std::vector<std::int64_t> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stoll(item));
  return out;
}

std::string Num(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.9g", v);
  return buffer;
}

// Reads a tracks JSONL file; checks canonical form, increasing frames and utimes.
void CheckTracksJsonl(const std::filesystem::path& file,
                      std::int64_t want_lines,
                      const std::string& want_layout,
                      const std::map<FrameIndex, Utime>& log_utimes) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    Fail(file.string() + ": missing");
    return;
  }
  std::string line;
  std::int64_t n = 0;
  std::optional<FrameIndex> previous;
  std::int64_t objects = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = file.filename().string() + ":" + std::to_string(n);
    core::KeypointLayoutId layout = core::KeypointLayoutId::kNone;
    std::string why;
    const std::optional<tracker::Frame3D> frame =
        transport::ParseTracksJsonLine(line, &layout, &why);
    if (!frame.has_value()) {
      Fail(where + ": " + why);
      continue;
    }
    const std::string layout_name =
        layout == core::KeypointLayoutId::kNone ? "none" : core::GetKeypointLayout(layout).name;
    if (!want_layout.empty()) ExpectEq(where + " layout", layout_name, want_layout);
    if (transport::TracksJsonLine(*frame, layout) != line + "\n") Fail(where + ": not canonical");
    if (previous.has_value() && frame->frame <= *previous) Fail(where + ": frame not increasing");
    previous = frame->frame;
    objects += static_cast<std::int64_t>(frame->tracks.size());
    const auto it = log_utimes.find(frame->frame);
    if (it == log_utimes.end()) {
      Fail(where + ": frame " + std::to_string(frame->frame) + " is not a frame of the log");
    } else {
      ExpectEq(where + " utime", frame->utime, it->second);
    }
  }
  ExpectEq(file.filename().string() + " lines", n, want_lines);
  std::cout << file.filename().string() << ": " << n << " lines, " << objects << " objects\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: mvtrack_convert_check DIR [options] (see the source)\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::map<std::string, std::string> opt;
  std::set<std::string> flags;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--every-camera-frame") {
      flags.insert(a.substr(2));
    } else if (a.rfind("--", 0) == 0 && i + 1 < argc) {
      opt[a.substr(2)] = argv[++i];
    } else {
      std::cerr << "bad argument " << a << "\n";
      return 2;
    }
  }
  const std::set<std::string> known = {"cameras",
                                       "frames",
                                       "first-frame",
                                       "last-frame",
                                       "fps",
                                       "layout",
                                       "channel",
                                       "detections",
                                       "detections-per-camera",
                                       "gt-lines",
                                       "gt-layout",
                                       "peer-lines",
                                       "ground-points-lines",
                                       "dump"};
  for (const auto& [k, v] : opt) {
    if (known.count(k) == 0) {
      std::cerr << "unknown option --" << k << "\n";
      return 2;
    }
  }

  // Calibration.
  std::map<CameraId, geometry::CameraModel> cameras;
  try {
    for (const geometry::CameraModel& c :
         config::LoadCalibration((dir / "calibration.yaml").string())) {
      cameras[c.id] = c;
    }
  } catch (const std::exception& e) {
    Fail(std::string("calibration: ") + e.what());
  }
  if (opt.count("cameras")) {
    std::vector<std::int64_t> want = ParseIntList(opt["cameras"]);
    std::vector<std::int64_t> got;
    for (const auto& [id, c] : cameras) got.push_back(id);
    if (got != want) Fail("calibration camera ids differ from --cameras " + opt["cameras"]);
  }

  // Log.
  std::string why;
  std::unique_ptr<transport::LogReader> reader =
      transport::LogReader::Open((dir / "detections.lcmlog").string(), &why);
  if (reader == nullptr) {
    Fail("log: " + why);
    return 1;
  }
  std::ofstream dump;
  if (opt.count("dump")) dump.open(opt["dump"], std::ios::binary);
  const std::string channel_mode = opt.count("channel") ? opt["channel"] : "shared";
  std::map<CameraId, std::int64_t> events_per_camera, detections_per_camera;
  std::map<FrameIndex, std::set<CameraId>> cameras_per_frame;
  std::map<FrameIndex, Utime> utime_of_frame;
  std::int64_t events = 0, detections = 0, rejected = 0;
  std::optional<std::pair<FrameIndex, CameraId>> previous;
  while (std::optional<transport::LogEvent> ev = reader->Next()) {
    const std::string where = "event " + std::to_string(events);
    ExpectEq(where + " event number", ev->event_number, events);
    ++events;
    const transport::DecodeResult r =
        transport::DecodeCameraDetections(ev->data.data(), ev->data.size());
    if (!r.ok()) {
      Fail(where + ": " + r.reason);
      continue;
    }
    const core::CameraFrame& cf = r.frame;
    if (channel_mode == "shared") {
      ExpectEq(where + " channel", ev->channel, std::string(transport::kDetectionsChannel));
    } else {
      ExpectEq(
          where + " channel", ev->channel, transport::DetectionsChannelForCamera(cf.camera_id));
    }
    ExpectEq(where + " timestamp == utime", ev->timestamp_us, cf.utime);
    const std::pair<FrameIndex, CameraId> key{cf.frame, cf.camera_id};
    if (previous.has_value() && !(*previous < key)) {
      Fail(where + ": (frame, camera) not strictly increasing");
    }
    previous = key;
    if (opt.count("fps")) {
      const auto want = static_cast<Utime>(
          std::llround(static_cast<double>(cf.frame) * 1e6 / std::stod(opt["fps"])));
      ExpectEq(where + " utime", cf.utime, want);
    }
    if (utime_of_frame.count(cf.frame) == 0 || cf.utime < utime_of_frame[cf.frame]) {
      utime_of_frame[cf.frame] = cf.utime;
    }
    cameras_per_frame[cf.frame].insert(cf.camera_id);
    ++events_per_camera[cf.camera_id];
    detections_per_camera[cf.camera_id] += static_cast<std::int64_t>(cf.detections.size());
    detections += static_cast<std::int64_t>(cf.detections.size());
    const auto cam = cameras.find(cf.camera_id);
    core::DetectionLimits limits;
    if (cam == cameras.end()) {
      Fail(where + ": camera " + std::to_string(cf.camera_id) + " not in the calibration");
    } else {
      ExpectEq(where + " image width", r.image_width_px, cam->second.width_px);
      ExpectEq(where + " image height", r.image_height_px, cam->second.height_px);
      limits.image_width_px = cam->second.width_px;
      limits.image_height_px = cam->second.height_px;
    }
    for (const core::Detection2D& d : cf.detections) {
      const std::string layout = d.layout == core::KeypointLayoutId::kNone
                                     ? "none"
                                     : core::GetKeypointLayout(d.layout).name;
      if (opt.count("layout")) ExpectEq(where + " layout", layout, opt["layout"]);
      core::Detection2D copy = d;
      if (core::ValidateDetection(&copy, limits).verdict == core::DetectionVerdict::kRejected)
        ++rejected;
    }
    if (dump.is_open()) {
      dump << "{\"camera\": " << cf.camera_id << ", \"frame\": " << cf.frame
           << ", \"utime\": " << cf.utime << ", \"image_size\": [" << r.image_width_px << ", "
           << r.image_height_px << "], \"channel\": \"" << ev->channel << "\", \"detections\": [";
      for (std::size_t i = 0; i < cf.detections.size(); ++i) {
        const core::Detection2D& d = cf.detections[i];
        dump << (i ? ", " : "") << "{\"box\": [" << Num(d.box.x_min) << ", " << Num(d.box.y_min)
             << ", " << Num(d.box.x_max) << ", " << Num(d.box.y_max)
             << "], \"score\": " << Num(d.score);
        if (!d.keypoints.empty()) {
          dump << ", \"layout\": \"" << core::GetKeypointLayout(d.layout).name
               << "\", \"keypoints\": [";
          for (std::size_t j = 0; j < d.keypoints.size(); ++j) {
            dump << (j ? ", " : "") << "[" << Num(d.keypoints[j].position_px.x()) << ", "
                 << Num(d.keypoints[j].position_px.y()) << ", " << Num(d.keypoints[j].confidence)
                 << "]";
          }
          dump << "]";
        }
        if (!d.embedding.empty()) {
          dump << ", \"embedding\": [";
          for (std::size_t k = 0; k < d.embedding.size(); ++k) {
            dump << (k ? ", " : "") << Num(static_cast<double>(d.embedding[k]));
          }
          dump << "]";
        }
        dump << "}";
      }
      dump << "]}\n";
    }
  }
  if (reader->end() != transport::LogEnd::kEndOfLog) {
    Fail(std::string("log ended with ") + transport::ToString(reader->end()) + ": " +
         reader->error());
  }
  ExpectEq("log skipped bytes", reader->skipped_bytes(), std::int64_t{0});
  ExpectEq("detections rejected by core::ValidateDetection", rejected, std::int64_t{0});

  const auto frames = static_cast<std::int64_t>(cameras_per_frame.size());
  if (opt.count("frames")) ExpectEq("frames", frames, std::stoll(opt["frames"]));
  if (opt.count("first-frame") && frames > 0) {
    ExpectEq("first frame", cameras_per_frame.begin()->first, std::stoll(opt["first-frame"]));
  }
  if (opt.count("last-frame") && frames > 0) {
    ExpectEq("last frame", cameras_per_frame.rbegin()->first, std::stoll(opt["last-frame"]));
  }
  if (flags.count("every-camera-frame")) {
    std::set<CameraId> all;
    for (const auto& [id, c] : cameras) all.insert(id);
    for (const auto& [frame, cams] : cameras_per_frame) {
      if (cams != all) Fail("frame " + std::to_string(frame) + " lacks a camera");
    }
    ExpectEq("events", events, frames * static_cast<std::int64_t>(all.size()));
  }
  if (opt.count("detections")) ExpectEq("detections", detections, std::stoll(opt["detections"]));
  if (opt.count("detections-per-camera")) {
    std::vector<std::int64_t> got;
    for (const auto& [id, n] : detections_per_camera) got.push_back(n);
    if (got != ParseIntList(opt["detections-per-camera"])) {
      std::string s;
      for (std::int64_t n : got) s += std::to_string(n) + ",";
      Fail("detections per camera " + s + " differ from " + opt["detections-per-camera"]);
    }
  }

  // JSONL files: present exactly when expected.
  const std::vector<std::pair<std::string, std::string>> jsonl = {
      {"ground_truth.jsonl", "gt-lines"},
      {"peer.jsonl", "peer-lines"},
      {"ground_points.jsonl", "ground-points-lines"}};
  for (const auto& [name, key] : jsonl) {
    const std::filesystem::path file = dir / name;
    if (opt.count(key)) {
      std::string layout;
      if (key == "gt-lines" && opt.count("gt-layout")) layout = opt["gt-layout"];
      if (key == "peer-lines") layout = "shelf14";
      if (key == "ground-points-lines") layout = "none";
      CheckTracksJsonl(file, std::stoll(opt[key]), layout, utime_of_frame);
    } else if (std::filesystem::exists(file)) {
      Fail(name + " exists but was not expected");
    }
  }
  if (!std::filesystem::exists(dir / "README.txt")) Fail("README.txt missing");
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().filename().string().rfind(".", 0) == 0) {
      Fail("leftover temporary file " + entry.path().string());
    }
  }

  std::cout << "detections.lcmlog: " << events << " events, " << frames << " frames, " << detections
            << " detections, " << std::filesystem::file_size(dir / "detections.lcmlog")
            << " bytes; per camera (events/detections):";
  for (const auto& [id, n] : events_per_camera) {
    std::cout << " " << id << ":" << n << "/" << detections_per_camera[id];
  }
  std::cout << "\n";
  if (g_failures > 0) {
    std::cerr << g_failures << " check(s) failed\n";
    return 1;
  }
  return 0;
}
