// mvtrack view: renders a track output (tracks log or canonical tracks JSONL), optionally with
// the detections log and the calibration, as pictures: a bird's-eye floor view with every track
// in its own colour and a fading trail, the cameras and their fields of view, and one panel per
// camera with the 3D tracks reprojected over the 2D detections. Output: one PNG, PNG frames, a
// contact sheet and/or an MP4 video. The drawing is lib/viz; this file reads inputs and writes
// outputs.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "config/calibration.h"
#include "config/site.h"
#include "core/detection.h"
#include "formats/tracks_io.h"
#include "mvtrack/cli.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "viz/camera_panel.h"
#include "viz/compose.h"
#include "viz/floor_view.h"
#include "viz/image_io.h"

namespace mvtrack::cli {
namespace {

constexpr int kMaxPrinted = 5;
constexpr double kDefaultFps = 25.0;

// frame -> camera -> detections.
using DetectionsByFrame = std::map<FrameIndex, std::map<CameraId, std::vector<core::Detection2D>>>;

// Reads the detections of `wanted` frames from a detections log. Undecodable messages and
// messages of cameras missing from the calibration are skipped with a warning (counted).
DetectionsByFrame ReadDetections(const std::string& path,
                                 const std::set<FrameIndex>& wanted,
                                 const std::set<CameraId>& cameras) {
  std::string why;
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(path, &why);
  if (!reader) throw std::runtime_error("--detections: " + why);
  DetectionsByFrame out;
  std::int64_t bad = 0;
  std::map<CameraId, std::int64_t> unknown_cameras;
  std::int64_t detection_events = 0;
  while (std::optional<transport::LogEvent> event = reader->Next()) {
    if (!transport::IsDetectionsChannel(event->channel)) continue;
    ++detection_events;
    transport::DecodeResult decoded =
        transport::DecodeCameraDetections(event->data.data(), event->data.size());
    if (!decoded.ok()) {
      if (bad++ < kMaxPrinted) {
        std::cerr << "view: warning: " << path << ": event " << event->event_number << " on "
                  << event->channel << ": " << transport::ToString(decoded.status) << ": "
                  << decoded.reason << " (skipped)\n";
      }
      continue;
    }
    const CameraId camera = decoded.frame.camera_id;
    if (!cameras.count(camera)) {
      ++unknown_cameras[camera];
      continue;
    }
    if (!wanted.count(decoded.frame.frame)) continue;
    std::vector<core::Detection2D>& list = out[decoded.frame.frame][camera];
    for (core::Detection2D& d : decoded.frame.detections) list.push_back(std::move(d));
  }
  if (reader->end() != transport::LogEnd::kEndOfLog) {
    std::cerr << "view: warning: " << path << ": " << transport::ToString(reader->end()) << ": "
              << reader->error() << " (the detections before it are drawn)\n";
  }
  if (bad > 0)
    std::cerr << "view: warning: " << path << ": " << bad << " undecodable message(s) skipped\n";
  for (const auto& [camera, n] : unknown_cameras) {
    std::cerr << "view: warning: " << path << ": " << n << " message(s) of camera " << camera
              << ", which is not in the calibration, skipped\n";
  }
  if (detection_events == 0) {
    std::cerr << "view: warning: " << path << ": no events on a detections channel\n";
  }
  return out;
}

// Frame rate from the frames' utimes (median over consecutive frames), else kDefaultFps.
double EstimateFps(const std::vector<tracker::Frame3D>& frames) {
  std::vector<double> rates;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double dt_us = static_cast<double>(frames[i].utime - frames[i - 1].utime);
    const double df = static_cast<double>(frames[i].frame - frames[i - 1].frame);
    if (dt_us > 0.0 && df > 0.0) rates.push_back(1e6 * df / dt_us);
  }
  if (rates.empty()) return kDefaultFps;
  std::nth_element(
      rates.begin(), rates.begin() + static_cast<std::ptrdiff_t>(rates.size() / 2), rates.end());
  const double fps = rates[rates.size() / 2];
  return fps > 0.5 && fps < 1000.0 ? fps : kDefaultFps;
}

// "A:B" (inclusive; either side may be empty).
std::pair<FrameIndex, FrameIndex> ParseRange(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) throw UsageError("--frames: '" + text + "' is not FIRST:LAST");
  auto parse = [&](const std::string& part, FrameIndex fallback) -> FrameIndex {
    if (part.empty()) return fallback;
    std::size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size()) throw UsageError("--frames: '" + text + "' is not FIRST:LAST");
    return v;
  };
  const FrameIndex a = parse(text.substr(0, colon), std::numeric_limits<FrameIndex>::min());
  const FrameIndex b = parse(text.substr(colon + 1), std::numeric_limits<FrameIndex>::max());
  if (a > b) throw UsageError("--frames: FIRST is after LAST in '" + text + "'");
  return {a, b};
}

std::string FrameFileName(FrameIndex frame) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06lld.png", static_cast<long long>(frame));
  return name;
}

void Write(const std::string& path, const cv::Mat& image) {
  std::string why;
  if (!viz::WriteImage(path, image, &why)) throw std::runtime_error(why);
}

}  // namespace

int RunView(int argc, char** argv) {
  Args args;
  args.Positional("TRACKS",
                  "track output: an LCM log with tracks3d_t on MVTRACK_TRACKS (mvtrack "
                  "replay --out, the daemon) or canonical tracks JSONL (replay --jsonl)")
      .Option("calibration",
              "camera calibration (mvtrack.calibration/1): cameras and their "
              "fields of view on the floor, and one panel per camera")
      .Option("regions",
              "a site file (mvtrack.site/1): draws its regions and lines on the floor view")
      .Option("detections",
              "detections log: the 2D detections drawn under the reprojected "
              "tracks in the camera panels (needs --calibration)")
      .Option("png", "write one picture of the frame given by --frame to this PNG file")
      .Option("png-dir",
              "write one PNG per rendered frame into this directory "
              "(frame_<frame>.png; created if missing)")
      .Option("sheet",
              "write a contact sheet (a grid of --sheet-tiles frames evenly spread over "
              "the rendered ones) to this PNG file")
      .Option("mp4",
              "write every rendered frame to this MP4 video (H.264 where the installed "
              "OpenCV/FFmpeg can encode it, else mp4v; the output line says which)")
      .Option("frame", "render only this frame index")
      .Option("frames", "render the frame indices FIRST:LAST (inclusive; a side may be empty)")
      .Option("every", "render every N-th frame of the selection", "1")
      .Option("trail", "trail length behind each track, frames", "45")
      .Option("height", "picture height without the title band, pixels", "720")
      .Option("fps", "video frame rate (default: from the tracks' timestamps, else 25)")
      .Option("sheet-tiles", "frames in the contact sheet", "12")
      .Option("sheet-columns", "contact sheet columns", "4")
      .Option("sheet-width", "contact sheet tile width, pixels", "480")
      .Option("title", "title prefix (default: the tracks file name)")
      .Flag("no-detections-panels", "floor view only, even with --calibration")
      .Flag("quiet", "no progress line on stderr");
  const std::string usage =
      "mvtrack view TRACKS [--calibration CAL.yaml [--detections DET.lcmlog]] "
      "(--png FILE --frame F | --png-dir DIR | --sheet FILE.png | --mp4 FILE.mp4) [options]";
  if (!args.Parse(argc,
                  argv,
                  usage,
                  "Renders tracks as pictures: a bird's-eye view of the floor (world x right, y\n"
                  "up, 1 m grid) with every track in its own colour (a function of its id, the\n"
                  "same in every frame and picture) and a fading trail, the cameras and their\n"
                  "fields of view on the floor; with --calibration one panel per camera with the\n"
                  "3D tracks reprojected (poses: skeletons; footprints: a standing person's box)\n"
                  "over the 2D detections of --detections (grey); with --regions the site's\n"
                  "regions and lines (an arrow marks each line's left_to_right direction).\n"
                  "Several outputs may be given.\n\n"
                  "Exit status: 0 ok, 1 error (unreadable input), 2 usage error.")) {
    return 0;
  }
  const bool any_output =
      args.Has("png") || args.Has("png-dir") || args.Has("sheet") || args.Has("mp4");
  if (!any_output)
    throw UsageError("no output: give --png, --png-dir, --sheet or --mp4 (see --help)");
  if (args.Has("png") && !args.Has("frame")) throw UsageError("--png needs --frame F (one frame)");
  if (args.Has("frame") && args.Has("frames"))
    throw UsageError("--frame and --frames exclude each other");
  if (args.Has("detections") && !args.Has("calibration")) {
    throw UsageError("--detections needs --calibration (the panels are the calibrated cameras)");
  }
  const std::int64_t every = args.GetInt("every");
  const std::int64_t trail = args.GetInt("trail");
  const std::int64_t height = args.GetInt("height");
  const std::int64_t tiles = args.GetInt("sheet-tiles");
  const std::int64_t columns = args.GetInt("sheet-columns");
  const std::int64_t tile_width = args.GetInt("sheet-width");
  if (every < 1) throw UsageError("--every must be >= 1");
  if (trail < 0 || trail > 100000) throw UsageError("--trail must be in [0, 100000]");
  if (height < 64 || height > 8192) throw UsageError("--height must be in [64, 8192]");
  if (tiles < 1 || tiles > 400) throw UsageError("--sheet-tiles must be in [1, 400]");
  if (columns < 1 || columns > 100) throw UsageError("--sheet-columns must be in [1, 100]");
  if (tile_width < 32 || tile_width > 4096) throw UsageError("--sheet-width must be in [32, 4096]");
  std::optional<double> fps_option;
  if (args.Has("fps")) {
    fps_option = args.GetDouble("fps");
    if (!(*fps_option > 0.0 && *fps_option <= 1000.0))
      throw UsageError("--fps must be in (0, 1000]");
  }
  std::pair<FrameIndex, FrameIndex> range{std::numeric_limits<FrameIndex>::min(),
                                          std::numeric_limits<FrameIndex>::max()};
  if (args.Has("frame")) range = {args.GetInt("frame"), args.GetInt("frame")};
  if (args.Has("frames")) range = ParseRange(args.Get("frames"));

  // Inputs.
  const std::string tracks_path = args.Get("TRACKS");
  formats::TrackFile tracks = formats::ReadTrackFile(tracks_path);
  if (tracks.frames.empty()) throw std::runtime_error(tracks_path + ": no frames to render");
  std::vector<tracker::Frame3D> frames;
  for (formats::TrackFileFrame& f : tracks.frames) frames.push_back(std::move(f.frame));
  std::sort(frames.begin(), frames.end(), [](const tracker::Frame3D& a, const tracker::Frame3D& b) {
    return a.frame < b.frame;
  });
  const core::KeypointLayoutId layout = tracks.layout.value_or(core::KeypointLayoutId::kNone);

  std::vector<geometry::CameraModel> cameras;
  if (args.Has("calibration")) cameras = config::LoadCalibration(args.Get("calibration"));
  std::optional<analytics::Site> site;
  if (args.Has("regions")) site = config::LoadSiteFile(args.Get("regions"));

  std::vector<std::size_t> selected;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].frame >= range.first && frames[i].frame <= range.second) selected.push_back(i);
  }
  if (selected.empty()) {
    throw std::runtime_error(
        tracks_path + ": no frame in the selected range (the file has frames " +
        std::to_string(frames.front().frame) + "-" + std::to_string(frames.back().frame) + ")");
  }
  {
    std::vector<std::size_t> thinned;
    for (std::size_t k = 0; k < selected.size(); k += static_cast<std::size_t>(every))
      thinned.push_back(selected[k]);
    selected = std::move(thinned);
  }

  DetectionsByFrame detections;
  const bool panels = !cameras.empty() && !args.Has("no-detections-panels");
  if (args.Has("detections") && panels) {
    std::set<FrameIndex> wanted;
    for (std::size_t i : selected) wanted.insert(frames[i].frame);
    std::set<CameraId> ids;
    for (const geometry::CameraModel& c : cameras) ids.insert(c.id);
    detections = ReadDetections(args.Get("detections"), wanted, ids);
  }

  // Rendering setup.
  config::FloorRegion region = viz::ViewRegion(cameras, frames, 1.0);
  if (site) viz::IncludeSite(*site, 0.5, &region);
  const viz::FloorMapping mapping = viz::FloorMapping::Fit(region, static_cast<int>(height));
  viz::FloorViewOptions floor_options;
  floor_options.trail_frames = static_cast<int>(trail);
  floor_options.site = site ? &*site : nullptr;
  const cv::Size grid = viz::PanelGrid(panels ? static_cast<int>(cameras.size()) : 0);
  const std::string title_prefix = args.Has("title")
                                       ? args.Get("title")
                                       : std::filesystem::path(tracks_path).filename().string();

  auto render = [&](std::size_t i) {
    const tracker::Frame3D& frame = frames[i];
    const cv::Mat floor = viz::RenderFloorView(mapping, cameras, frames, i, floor_options);
    std::vector<cv::Mat> panel_images;
    if (panels) {
      const auto by_camera = detections.find(frame.frame);
      for (const geometry::CameraModel& camera : cameras) {
        viz::CameraPanelOptions po;
        po.scale =
            std::clamp(static_cast<double>(height) / grid.height / camera.height_px, 0.05, 1.0);
        static const std::vector<core::Detection2D> kNone;
        const std::vector<core::Detection2D>* dets = &kNone;
        if (by_camera != detections.end()) {
          const auto it = by_camera->second.find(camera.id);
          if (it != by_camera->second.end()) dets = &it->second;
        }
        panel_images.push_back(viz::RenderCameraPanel(camera, *dets, frame, layout, po));
      }
    }
    viz::ComposeOptions co;
    co.height_px = static_cast<int>(height);
    co.title = title_prefix + "   frame " + std::to_string(frame.frame) + "   " +
               std::to_string(frame.tracks.size()) + " track(s)";
    return viz::ComposeFrame(floor, panel_images, co);
  };

  // Outputs.
  if (args.Has("png")) {
    Write(args.Get("png"), render(selected.front()));
    std::cout << "view: wrote " << args.Get("png") << "\n";
  }
  std::set<std::size_t> sheet_frames;
  if (args.Has("sheet")) {
    const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(tiles), selected.size());
    for (std::size_t k = 0; k < n; ++k) {
      sheet_frames.insert(selected[n == 1 ? 0 : k * (selected.size() - 1) / (n - 1)]);
    }
  }
  const bool every_frame = args.Has("png-dir") || args.Has("mp4");
  if (args.Has("png-dir")) {
    std::error_code ec;
    std::filesystem::create_directories(args.Get("png-dir"), ec);
    if (ec)
      throw std::runtime_error(args.Get("png-dir") + ": cannot create directory: " + ec.message());
  }
  std::unique_ptr<viz::VideoFileWriter> video;
  std::vector<cv::Mat> sheet_tiles;
  std::vector<std::string> sheet_labels;
  const bool progress = !args.Has("quiet");
  auto last_progress = std::chrono::steady_clock::now();
  std::size_t done = 0;
  for (std::size_t i : selected) {
    const bool for_sheet = sheet_frames.count(i) > 0;
    if (!every_frame && !for_sheet) continue;
    const cv::Mat image = render(i);
    if (args.Has("png-dir")) {
      Write((std::filesystem::path(args.Get("png-dir")) / FrameFileName(frames[i].frame)).string(),
            image);
    }
    if (args.Has("mp4")) {
      if (!video) {
        std::string why;
        video = viz::VideoFileWriter::Open(
            args.Get("mp4"), image.size(), fps_option.value_or(EstimateFps(frames)), &why);
        if (!video) throw std::runtime_error(why);
      }
      video->Write(image);
    }
    if (for_sheet) {
      sheet_tiles.push_back(image);
      sheet_labels.push_back("frame " + std::to_string(frames[i].frame));
    }
    ++done;
    if (progress && std::chrono::steady_clock::now() - last_progress > std::chrono::seconds(1)) {
      last_progress = std::chrono::steady_clock::now();
      std::cerr << "view: rendered " << done << " frame(s)\n";
    }
  }
  if (args.Has("png-dir")) {
    std::cout << "view: wrote " << done << " PNG frame(s) to " << args.Get("png-dir") << "\n";
  }
  if (video) {
    const int written = video->frames_written();
    video->Close();
    std::cout << "view: wrote " << written << " frame(s) to " << args.Get("mp4") << ", "
              << video->codec() << "\n";
  }
  if (args.Has("sheet")) {
    viz::ContactSheetOptions so;
    so.columns = static_cast<int>(columns);
    so.tile_width_px = static_cast<int>(tile_width);
    so.labels = sheet_labels;
    Write(args.Get("sheet"), viz::MakeContactSheet(sheet_tiles, so));
    std::cout << "view: wrote a contact sheet of " << sheet_tiles.size() << " frame(s) to "
              << args.Get("sheet") << "\n";
  }
  return 0;
}

}  // namespace mvtrack::cli
