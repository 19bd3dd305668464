// mvtrack demo: simulate a small scene (cameras, walking people, noisy detections), track it
// with the full method, print the tracks and score them against the simulation's ground truth.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include "eval/report.h"
#include "eval/tracking_metrics.h"
#include "mvtrack/cli.h"
#include "sim/synthetic_scene.h"
#include "tracker/tracker.h"

namespace mvtrack::cli {
namespace {

eval::EvalSequence TruthSequence(const sim::Scene& scene, bool with_joints) {
  eval::EvalSequence seq;
  for (const sim::FrameTruth& t : scene.truth) {
    eval::EvalFrame f;
    f.frame = t.frame;
    for (const sim::PersonTruth& p : t.people) {
      eval::EvalObject o;
      o.id = p.id;
      o.position = p.footprint_m;
      if (with_joints) {
        for (const Vec3& j : p.joints_m) o.joints.emplace_back(j);
      }
      f.objects.push_back(std::move(o));
    }
    seq.push_back(std::move(f));
  }
  return seq;
}

eval::EvalSequence TrackSequence(const std::vector<tracker::Frame3D>& frames) {
  eval::EvalSequence seq;
  for (const tracker::Frame3D& fr : frames) {
    eval::EvalFrame f;
    f.frame = fr.frame;
    for (const tracker::Track3D& t : fr.tracks) f.objects.push_back({t.id, t.position, t.joints});
    seq.push_back(std::move(f));
  }
  return seq;
}

void PrintFrame(const tracker::Frame3D& f, const sim::Scene& scene) {
  std::printf(
      "frame %4lld  utime %lld  %zu track(s), %zu person(s) in the room\n",
      static_cast<long long>(f.frame),
      static_cast<long long>(f.utime),
      f.tracks.size(),
      scene.truth[static_cast<std::size_t>(f.frame - scene.truth.front().frame)].people.size());
  for (const tracker::Track3D& t : f.tracks) {
    std::string cams;
    for (CameraId c : t.cameras) cams += (cams.empty() ? "" : ",") + std::to_string(c);
    std::printf("    id %3lld  footprint (%6.2f, %6.2f) m  conf %.2f  age %4lld  cameras {%s}\n",
                static_cast<long long>(t.id),
                t.position.x(),
                t.position.y(),
                t.confidence,
                static_cast<long long>(t.age_frames),
                cams.c_str());
  }
}

}  // namespace

int RunDemo(int argc, char** argv) {
  Args args;
  args.Option("mode",
              "what to track: 'poses' (2D poses -> 3D poses) or 'boxes' (boxes -> footprints)",
              "poses")
      .Option("cameras", "number of cameras on a ring around the room", "3")
      .Option("people", "number of people walking in the room", "3")
      .Option("frames", "frames to simulate (30 fps)", "300")
      .Option("seed", "simulation seed", "1")
      .Option("noise-px", "pixel noise (Gaussian sigma) on boxes and keypoints", "1.5")
      .Option("miss-rate", "probability that a visible person is not detected in a view", "0.05")
      .Option("false-positives", "mean false-positive detections per camera-frame", "0.2")
      .Option("print-every", "print the tracks of every N-th frame (0: none)", "30")
      .Flag("json", "print the accuracy report as JSON instead of a table");
  if (!args.Parse(argc,
                  argv,
                  "mvtrack demo [options]",
                  "Simulates a room with calibrated cameras and walking people, feeds the noisy\n"
                  "detections to the tracker exactly as a live system would (camera-frame by\n"
                  "camera-frame), prints the tracks, and scores them against the simulation's\n"
                  "ground truth (CLEAR MOT, identity F1, MPJPE).")) {
    return 0;
  }
  const std::string mode = args.Get("mode");
  if (mode != "poses" && mode != "boxes") throw UsageError("--mode must be 'poses' or 'boxes'");
  const bool poses = mode == "poses";

  sim::SceneOptions so;
  so.seed = static_cast<std::uint64_t>(args.GetInt("seed"));
  so.num_cameras = static_cast<int>(args.GetInt("cameras"));
  so.num_people = static_cast<int>(args.GetInt("people"));
  so.num_frames = static_cast<int>(args.GetInt("frames"));
  so.pixel_noise_px = args.GetDouble("noise-px");
  so.miss_rate = args.GetDouble("miss-rate");
  so.false_positives_per_frame = args.GetDouble("false-positives");
  so.poses = poses;
  std::string why;
  if (!so.Validate(&why)) throw UsageError("simulation: " + why);
  const std::int64_t print_every = args.GetInt("print-every");

  const sim::Scene scene = sim::GenerateScene(so);
  tracker::TrackerOptions to;
  to.mode = poses ? tracker::InputMode::kPoses : tracker::InputMode::kBoxes;
  to.layout = core::KeypointLayoutId::kCoco17;
  auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), to, &why);
  if (!t) throw std::runtime_error("tracker: " + why);

  std::printf("mvtrack demo: %d cameras, %d people, %d frames at %.0f fps, %s mode (seed %llu)\n",
              so.num_cameras,
              so.num_people,
              so.num_frames,
              so.fps,
              mode.c_str(),
              static_cast<unsigned long long>(so.seed));
  std::vector<tracker::Frame3D> frames;
  const auto start = std::chrono::steady_clock::now();
  auto take = [&](std::vector<tracker::Frame3D>&& out) {
    for (tracker::Frame3D& f : out) {
      if (print_every > 0 && f.frame % print_every == 0) PrintFrame(f, scene);
      frames.push_back(std::move(f));
    }
  };
  for (const auto& cams : scene.detections) {
    for (const core::CameraFrame& cf : cams) take(std::move(t->Add(cf).finalized));
  }
  take(t->Flush());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  eval::TrackingOptions eo;
  eo.distance = eval::DistanceKind::kFootprint;
  eval::EvaluationReport report;
  report.tracking = eval::EvaluateTracking(TruthSequence(scene, poses), TrackSequence(frames), eo);
  if (!report.tracking->valid) throw std::runtime_error("evaluation: " + report.tracking->error);
  const tracker::TrackerStats& st = t->stats();
  std::printf(
      "\ntracked %lld frames in %.3f s (%.0f frames/s, single thread); %lld windows, "
      "%lld tracks born; %lld detections used, %lld rejected, %lld filtered\n\n",
      static_cast<long long>(frames.size()),
      seconds,
      static_cast<double>(frames.size()) / seconds,
      static_cast<long long>(st.windows_processed),
      static_cast<long long>(st.tracks_born),
      static_cast<long long>(st.detections_used),
      static_cast<long long>(st.detections_rejected),
      static_cast<long long>(st.detections_filtered));
  if (args.Has("json")) {
    std::cout << eval::ReportToJson(report, 4);
  } else {
    std::cout << "accuracy against the simulation's ground truth:\n"
              << eval::FormatReportTable(report);
  }
  return 0;
}

}  // namespace mvtrack::cli
