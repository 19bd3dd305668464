// mvtrack sim: writes a deterministic simulated recording: a detections LCM log (the daemon's
// and `mvtrack replay`'s input), the calibration and the ground truth `mvtrack eval` reads.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "config/calibration.h"
#include "core/keypoint_layout.h"
#include "mvtrack/cli.h"
#include "mvtrack/sim_scene.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"
#include "tracker/types.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::cli {

int RunSim(int argc, char** argv) {
  Args args;
  args.Option("out", "output directory (created; files in it are overwritten)");
  DeclareSceneOptions(&args);
  args.Flag("per-camera-channels",
            "publish camera c on MVTRACK_DETECTIONS_<c> instead of the shared MVTRACK_DETECTIONS")
      .Flag("quiet", "no progress line");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack sim --out DIR [options]",
          "Simulates calibrated cameras watching people walk on a floor (waypoints,\n"
          "collision avoidance, optionally entering and leaving) and a detector with\n"
          "pixel noise, misses, false positives and occlusion by depth order. Writes\n"
          "  DIR/detections.lcmlog  camera_detections_t per camera-frame, in capture order\n"
          "  DIR/calibration.yaml   the cameras (mvtrack replay --calibration)\n"
          "  DIR/gt.jsonl           ground truth tracks (mvtrack eval --gt): footprints,\n"
          "                         and the 17 COCO joints in pose mode\n"
          "The same options and seed always give byte-identical files. Defaults come\n"
          "from the preset for --cameras/--people (see docs/BENCHMARKS.md); every scene\n"
          "option overrides it.")) {
    return 0;
  }
  if (!args.Has("out")) throw UsageError("--out DIR is required");
  const sim::SceneOptions so = SceneOptionsFromArgs(args);
  const std::filesystem::path out = args.Get("out");
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw std::runtime_error(out.string() + ": cannot create directory: " + ec.message());
  const bool quiet = args.Has("quiet");
  const bool per_camera = args.Has("per-camera-channels");

  const std::vector<geometry::CameraModel> cameras = sim::MakeCameras(so);
  config::SaveCalibration((out / "calibration.yaml").string(), cameras);

  std::string why;
  const std::string log_path = (out / "detections.lcmlog").string();
  std::unique_ptr<transport::LogWriter> log = transport::LogWriter::Open(log_path, &why);
  if (!log) throw std::runtime_error(why);
  const std::string gt_path = (out / "gt.jsonl").string();
  std::ofstream gt(gt_path, std::ios::binary | std::ios::trunc);
  if (!gt) throw std::runtime_error(gt_path + ": cannot open for writing");
  const core::KeypointLayoutId layout =
      so.poses ? core::KeypointLayoutId::kCoco17 : core::KeypointLayoutId::kNone;

  std::cerr << "mvtrack sim: " << DescribeScene(so) << "\n";
  sim::CrowdSimulator crowd(so);
  std::int64_t detections = 0, person_frames = 0;
  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start;
  for (int f = 0; f < so.num_frames; ++f) {
    const sim::FrameTruth truth = crowd.Next();
    const sim::RenderedFrame rendered = sim::RenderFrame(so, cameras, truth);
    for (const core::CameraFrame& cf : rendered.cameras) {
      const std::string channel = per_camera ? transport::DetectionsChannelForCamera(cf.camera_id)
                                             : std::string(transport::kDetectionsChannel);
      if (!log->Write(channel,
                      cf.utime,
                      transport::EncodeCameraDetections(cf, so.image_width_px, so.image_height_px),
                      &why)) {
        throw std::runtime_error(why);
      }
      detections += static_cast<std::int64_t>(cf.detections.size());
    }
    tracker::Frame3D g;
    g.frame = truth.frame;
    g.utime = truth.utime;
    for (const sim::PersonTruth& p : truth.people) {
      tracker::Track3D t;
      t.id = p.id;
      t.position = p.footprint_m;
      if (so.poses) {
        for (const Vec3& j : p.joints_m) t.joints.emplace_back(j);
      }
      g.tracks.push_back(std::move(t));
    }
    person_frames += static_cast<std::int64_t>(truth.people.size());
    gt << transport::TracksJsonLine(g, layout);
    const auto now = std::chrono::steady_clock::now();
    if (!quiet && now - last_progress > std::chrono::seconds(1)) {
      last_progress = now;
      std::fprintf(stderr, "\rmvtrack sim: frame %d / %d", f + 1, so.num_frames);
    }
  }
  if (!log->Flush(&why)) throw std::runtime_error(why);
  log.reset();
  gt.close();
  if (!gt) throw std::runtime_error(gt_path + ": write error");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!quiet) std::fprintf(stderr, "\r");
  std::printf(
      "mvtrack sim: wrote %s (%d camera-frames, %lld detections), calibration.yaml, "
      "gt.jsonl (%lld person-frames) in %.1f s\n",
      log_path.c_str(),
      so.num_frames * so.num_cameras,
      static_cast<long long>(detections),
      static_cast<long long>(person_frames),
      seconds);
  return 0;
}

}  // namespace mvtrack::cli
