#include "mvtrack/sim_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/scene_presets.h"

namespace mvtrack::cli {
namespace {

// "WxH" -> (W, H); UsageError naming `option` otherwise.
std::pair<double, double> ParsePair(const std::string& text, const std::string& option) {
  const std::size_t x = text.find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument(text);
    std::size_t used_a = 0, used_b = 0;
    const double a = std::stod(text.substr(0, x), &used_a);
    const double b = std::stod(text.substr(x + 1), &used_b);
    if (used_a != x || used_b != text.size() - x - 1) throw std::invalid_argument(text);
    return {a, b};
  } catch (const std::exception&) {
    throw UsageError("--" + option + ": expected WIDTHxHEIGHT (e.g. 20x15), got '" + text + "'");
  }
}

// "X,Y;X,Y" -> points; UsageError otherwise.
std::vector<Vec2> ParsePoints(const std::string& text, const std::string& option) {
  std::vector<Vec2> points;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(';', start), text.size());
    const std::vector<std::string_view> xy =
        SplitCommas(std::string_view(text).substr(start, end - start));
    const std::optional<double> x = xy.size() == 2 ? ParseFinite(xy[0]) : std::nullopt;
    const std::optional<double> y = xy.size() == 2 ? ParseFinite(xy[1]) : std::nullopt;
    if (!x || !y) {
      throw UsageError("--" + option +
                       ": expected X,Y[;X,Y...] in metres (e.g. 2.5,3.5;4.5,3), got '" + text +
                       "'");
    }
    points.emplace_back(*x, *y);
    start = end + 1;
  }
  return points;
}

}  // namespace

void DeclareSceneOptions(Args* args) {
  args->Option("cameras", "number of cameras", "4")
      .Option("people", "number of people (maximum present at once with --enter-leave)", "8")
      .Option("frames", "frames to simulate", "300")
      .Option("mode", "'poses' (boxes + COCO-17 keypoints) or 'boxes'", "poses")
      .Option("seed", "simulation seed (everything random derives from it)", "1")
      .Option("layout",
              "camera mounting: 'auto' (ring up to 8 cameras on a floor side <= 10 m, else "
              "ceiling grid), 'ring', 'grid', or 'corridor' (along the two long walls of a "
              "floor WIDTH long, alternating, each looking across and along; e.g. --room 96x6)",
              "auto")
      .Option("room", "floor size WIDTHxDEPTH in metres (default: 4 m^2 per person, >= 6x6)")
      .Option("camera-height", "camera height in metres (default: 3 ring and corridor, 4 grid)")
      .Option(
          "image",
          "image size WIDTHxHEIGHT in pixels (default: 1280x720 ring and corridor, 1920x1080 grid)")
      .Option("fov", "horizontal field of view in degrees (default: 80 ring and corridor, 90 grid)")
      .Option("grid-pitch",
              "ceiling grid and corridor: camera pitch below the horizontal, degrees (default 50 "
              "grid, 35 corridor)")
      .Option("fps", "frame rate", "30")
      .Option("noise-px", "pixel noise (Gaussian sigma) on box edges and keypoints", "1.5")
      .Option("miss-rate", "probability that a visible person is not detected in a view", "0.05")
      .Option("false-positives", "mean false-positive detections per camera-frame", "0.2")
      .Option("keypoint-dropout", "probability that a visible keypoint is reported missing", "0.02")
      .Option("occlusion-threshold",
              "a person covered to this fraction by nearer people is not detected",
              "0.7")
      .Flag("no-occlusion", "no occlusion by depth order (everyone in view is a candidate)")
      .Flag("enter-leave", "people enter and leave through the walls (new ids on re-entry)")
      .Option("mean-stay", "--enter-leave: mean stay in the room, seconds", "8")
      .Option("embedding-dim",
              "length of a re-identification embedding on every detection (0 = none)",
              "0")
      .Option("embedding-noise",
              "embedding noise (expected norm of the Gaussian added to the unit prototype; "
              "0.5: same person at a cosine distance of about 0.2)",
              "0.5")
      .Option("embedding-view-drift",
              "how far the back view's prototype is from the front's (0 = one look)",
              "0.5")
      .Option("look-alikes",
              "probability that an odd-id person is a look-alike of the one with the id below",
              "0")
      .Option("reentry",
              "--enter-leave: probability that an entering person is someone who left 10-60 s "
              "before (same id and appearance)",
              "0")
      .Option("reentry-absence",
              "--reentry: MIN-MAX seconds away before a return (e.g. 10-60)",
              "10-60")
      .Option("linger-at",
              "floor points X,Y[;X,Y...] (metres) where people stop and stand for minutes, "
              "shifting within 0.2 m (a free one is taken whenever someone picks where to go)")
      .Option("linger-s", "--linger-at: mean standing time, seconds (uniform 0.5-1.5 x)", "120");
}

sim::SceneOptions SceneOptionsFromArgs(const Args& args) {
  const std::string mode = args.Get("mode");
  if (mode != "poses" && mode != "boxes") throw UsageError("--mode must be 'poses' or 'boxes'");
  const std::int64_t cameras = args.GetInt("cameras");
  const std::int64_t people = args.GetInt("people");
  if (cameras < 1 || cameras > 4096) throw UsageError("--cameras must be in [1, 4096]");
  if (people < 0 || people > 100000) throw UsageError("--people must be in [0, 100000]");
  const std::int64_t seed = args.GetInt("seed");
  if (seed < 0) throw UsageError("--seed must be >= 0");
  sim::SceneOptions o = sim::SizedScene(static_cast<int>(cameras),
                                        static_cast<int>(people),
                                        mode == "poses",
                                        static_cast<std::uint64_t>(seed));
  const std::int64_t frames = args.GetInt("frames");
  if (frames < 0 || frames > 100000000) throw UsageError("--frames must be in [0, 1e8]");
  o.num_frames = static_cast<int>(frames);
  if (args.Has("room")) {
    const auto [w, d] = ParsePair(args.Get("room"), "room");
    o.room_width_m = w;
    o.room_depth_m = d;
  }
  const std::string layout = args.Get("layout");
  if (layout == "ring" || layout == "grid") {
    // Switching layout: take that layout's defaults from a preset that chose it.
    const sim::SceneOptions ref =
        layout == "ring" ? sim::SizedScene(2, 2, true, 1) : sim::SizedScene(32, 100, true, 1);
    o.camera_layout = ref.camera_layout;
    o.camera_height_m = ref.camera_height_m;
    o.image_width_px = ref.image_width_px;
    o.image_height_px = ref.image_height_px;
    o.horizontal_fov_deg = ref.horizontal_fov_deg;
  } else if (layout == "corridor") {
    // Wall cameras as in the ring (3 m, 1280x720, 80 deg), pitched 35 deg down: each sees
    // local floor (from 1.7 m off its wall; chest height within 15 m along the corridor), every
    // point but the far corners seen by two or more (tests/sim/cameras_test.cc).
    const sim::SceneOptions ref = sim::SizedScene(2, 2, true, 1);
    o.camera_layout = sim::CameraLayout::kCorridor;
    o.camera_height_m = ref.camera_height_m;
    o.image_width_px = ref.image_width_px;
    o.image_height_px = ref.image_height_px;
    o.horizontal_fov_deg = ref.horizontal_fov_deg;
    o.grid_pitch_deg = 35.0;
  } else if (layout != "auto") {
    throw UsageError("--layout must be 'auto', 'ring', 'grid' or 'corridor'");
  }
  if (args.Has("camera-height")) o.camera_height_m = args.GetDouble("camera-height");
  if (args.Has("image")) {
    const auto [w, h] = ParsePair(args.Get("image"), "image");
    if (w != static_cast<double>(static_cast<int>(w)) ||
        h != static_cast<double>(static_cast<int>(h))) {
      throw UsageError("--image: width and height must be whole pixels");
    }
    o.image_width_px = static_cast<int>(w);
    o.image_height_px = static_cast<int>(h);
  }
  if (args.Has("fov")) o.horizontal_fov_deg = args.GetDouble("fov");
  if (args.Has("grid-pitch")) o.grid_pitch_deg = args.GetDouble("grid-pitch");
  o.fps = args.GetDouble("fps");
  o.pixel_noise_px = args.GetDouble("noise-px");
  o.miss_rate = args.GetDouble("miss-rate");
  o.false_positives_per_frame = args.GetDouble("false-positives");
  o.keypoint_dropout = args.GetDouble("keypoint-dropout");
  o.occlusion_threshold = args.GetDouble("occlusion-threshold");
  o.occlusion = !args.Has("no-occlusion");
  o.enter_and_leave = args.Has("enter-leave");
  o.mean_stay_s = args.GetDouble("mean-stay");
  const std::int64_t dim = args.GetInt("embedding-dim");
  if (dim < 0 || dim > 4096) throw UsageError("--embedding-dim must be in [0, 4096]");
  o.embedding_dim = static_cast<int>(dim);
  o.embedding_noise = args.GetDouble("embedding-noise");
  o.embedding_view_drift = args.GetDouble("embedding-view-drift");
  o.look_alike_fraction = args.GetDouble("look-alikes");
  o.reentry_probability = args.GetDouble("reentry");
  {
    const std::string text = args.Get("reentry-absence");
    const std::size_t dash = text.find('-');
    char* end = nullptr;
    const double lo = dash == std::string::npos ? -1.0 : std::strtod(text.c_str(), &end);
    const bool lo_ok = dash != std::string::npos && end == text.c_str() + dash;
    const double hi = lo_ok ? std::strtod(text.c_str() + dash + 1, &end) : -1.0;
    if (!lo_ok || end != text.c_str() + text.size() || dash + 1 == text.size()) {
      throw UsageError("--reentry-absence: expected MIN-MAX seconds (e.g. 10-60), got '" + text +
                       "'");
    }
    o.min_reentry_absence_s = lo;
    o.max_reentry_absence_s = hi;
  }
  if (args.Has("linger-at")) o.linger_spots = ParsePoints(args.Get("linger-at"), "linger-at");
  o.mean_linger_s = args.GetDouble("linger-s");
  if (o.reentry_probability > 0.0 && !o.enter_and_leave) {
    throw UsageError("--reentry needs --enter-leave");
  }
  std::string why;
  if (!o.Validate(&why)) throw UsageError("scene: " + why);
  return o;
}

namespace {

std::string EmbeddingText(const sim::SceneOptions& o) {
  std::string text;
  char part[160];
  if (o.embedding_dim > 0) {
    std::snprintf(part,
                  sizeof(part),
                  "; %d-d embeddings (noise %.2f, view drift %.2f, look-alikes %.2f)",
                  o.embedding_dim,
                  o.embedding_noise,
                  o.embedding_view_drift,
                  o.look_alike_fraction);
    text += part;
  }
  if (o.reentry_probability > 0.0) {
    std::snprintf(part,
                  sizeof(part),
                  "; re-entry %.2f after %.0f-%.0f s",
                  o.reentry_probability,
                  o.min_reentry_absence_s,
                  o.max_reentry_absence_s);
    text += part;
  }
  if (!o.linger_spots.empty()) {
    std::snprintf(part,
                  sizeof(part),
                  "; %zu linger spots, %.0f s mean",
                  o.linger_spots.size(),
                  o.mean_linger_s);
    text += part;
  }
  return text;
}

}  // namespace

std::string DescribeScene(const sim::SceneOptions& o) {
  char line[512];
  std::snprintf(line,
                sizeof(line),
                "%d cameras (%s, %dx%d px, %.0f deg, %.1f m high), %d people%s on %.0f x %.0f m, "
                "%d frames at %.0f fps, %s; noise %.1f px, miss %.2f, false positives %.2f/frame, "
                "occlusion %s%s, seed %llu",
                o.num_cameras,
                o.camera_layout == sim::CameraLayout::kRing          ? "ring"
                : o.camera_layout == sim::CameraLayout::kCeilingGrid ? "ceiling grid"
                                                                     : "corridor walls",
                o.image_width_px,
                o.image_height_px,
                o.horizontal_fov_deg,
                o.camera_height_m,
                o.num_people,
                o.enter_and_leave ? " (entering and leaving)" : "",
                o.room_width_m,
                o.room_depth_m,
                o.num_frames,
                o.fps,
                o.poses ? "poses" : "boxes",
                o.pixel_noise_px,
                o.miss_rate,
                o.false_positives_per_frame,
                o.occlusion ? "on" : "off",
                EmbeddingText(o).c_str(),
                static_cast<unsigned long long>(o.seed));
  return line;
}

eval::EvalFrame TruthEvalFrame(const sim::FrameTruth& truth, bool with_joints) {
  eval::EvalFrame f;
  f.frame = truth.frame;
  for (const sim::PersonTruth& p : truth.people) {
    eval::EvalObject o;
    o.id = p.id;
    o.position = p.footprint_m;
    if (with_joints) {
      for (const Vec3& j : p.joints_m) o.joints.emplace_back(j);
    }
    f.objects.push_back(std::move(o));
  }
  return f;
}

eval::EvalFrame TrackEvalFrame(const tracker::Frame3D& frame) {
  eval::EvalFrame f;
  f.frame = frame.frame;
  for (const tracker::Track3D& t : frame.tracks) f.objects.push_back({t.id, t.position, t.joints});
  return f;
}

}  // namespace mvtrack::cli
