#include "datasets/panoptic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "datasets/calibration_files.h"
#include "datasets/internal/common.h"
#include "datasets/internal/json_document.h"

namespace mvtrack::datasets {
namespace {

using internal::JsonValue;
using internal::kCmToM;

constexpr double kPanopticHdFps = 29.97;
constexpr int kPanopticJoints = 19;
constexpr int kNumHdCameras = 31;

const char* const kSequences[] = {"160906_band1", "160906_band2"};

std::string HdCameraName(int index) {
  char name[16];
  std::snprintf(name, sizeof(name), "00_%02d", index);
  return name;
}

// "00_xx" or a decimal index -> the HD index 0..30; std::nullopt when malformed.
std::optional<int> ParseHdCamera(const std::string& text) {
  std::string digits = text;
  if (text.size() == 5 && text.compare(0, 3, "00_") == 0) digits = text.substr(3);
  if (digits.empty() || digits.size() > 2 ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  const int index = std::stoi(digits);
  if (index < 0 || index >= kNumHdCameras) return std::nullopt;
  return index;
}

// body3DScene_<8 digits>.json -> the frame number.
std::optional<FrameIndex> FrameFromSkeletonFileName(const std::string& name) {
  const std::string prefix = "body3DScene_";
  const std::string suffix = ".json";
  if (name.size() != prefix.size() + 8 + suffix.size()) return std::nullopt;
  if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return std::nullopt;
  const std::string digits = name.substr(prefix.size(), 8);
  if (digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return static_cast<FrameIndex>(std::stoll(digits));
}

struct PanopticBody {
  std::int64_t id = 0;
  std::vector<std::optional<Vec3>> joints;  // our world frame, metres
};

std::vector<PanopticBody> LoadSkeletonFile(const std::filesystem::path& file,
                                           const Mat3& to_world) {
  const JsonValue root = internal::LoadJsonFile(file);
  const std::string fps_type = root["fpsType"].AsString();
  if (fps_type != "hd_29_97") {
    root["fpsType"].Fail("expected \"hd_29_97\", got \"" + fps_type + "\"");
  }
  const JsonValue bodies = root["bodies"];
  std::vector<PanopticBody> out;
  std::set<std::int64_t> ids;
  for (std::size_t b = 0; b < bodies.Size(); ++b) {
    const JsonValue body = bodies.At(b);
    PanopticBody pb;
    pb.id = body["id"].AsInt();
    if (!ids.insert(pb.id).second) body["id"].Fail("body id appears twice");
    const std::vector<double> v = body["joints19"].AsDoubles(4 * kPanopticJoints);
    pb.joints.resize(kPanopticJoints);
    for (std::size_t j = 0; j < pb.joints.size(); ++j) {
      if (v[4 * j + 3] < 0.0) continue;  // confidence < 0: invalid joint
      pb.joints[j] = kCmToM * (to_world * Vec3(v[4 * j], v[4 * j + 1], v[4 * j + 2]));
    }
    out.push_back(std::move(pb));
  }
  return out;
}

}  // namespace

Mat3 PanopticToWorldRotation() {
  Mat3 r;
  r << 1.0, 0.0, 0.0,  //
      0.0, 0.0, 1.0,   //
      0.0, -1.0, 0.0;
  return r;
}

std::vector<std::string> DefaultPanopticCameras() {
  return {"00_02", "00_06", "00_07", "00_12", "00_13", "00_28"};
}

CorruptionOptions PanopticOptions::DefaultCorruption() {
  CorruptionOptions options;
  options.pixel_noise_px = 6.0;
  return options;
}

bool PanopticOptions::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = "panoptic options: " + reason;
    return false;
  };
  if (std::find(std::begin(kSequences), std::end(kSequences), sequence) == std::end(kSequences)) {
    return fail("unknown sequence \"" + sequence + "\" (160906_band1 or 160906_band2)");
  }
  std::set<int> seen;
  for (const std::string& camera : cameras) {
    const std::optional<int> index = ParseHdCamera(camera);
    if (!index.has_value()) {
      return fail("camera \"" + camera +
                  "\" is neither an HD name 00_00..00_30 nor an index 0..30");
    }
    if (!seen.insert(*index).second) return fail("camera \"" + camera + "\" is listed twice");
  }
  return corruption.Validate(why);
}

Dataset LoadPanoptic(const std::filesystem::path& data_root, const PanopticOptions& options) {
  const std::filesystem::path dir = data_root / "panoptic" / options.sequence;
  std::string why;
  if (!options.Validate(&why)) throw DatasetError(dir.string(), why);
  const Mat3 to_world = PanopticToWorldRotation();

  Dataset ds;
  ds.name = "panoptic/" + options.sequence;
  ds.fps = kPanopticHdFps;

  // Cameras.
  const std::vector<std::string> wanted =
      options.cameras.empty() ? DefaultPanopticCameras() : options.cameras;
  ds.cameras =
      LoadPanopticCalibrationFile(dir / ("calibration_" + options.sequence + ".json"), wanted);

  // Skeleton frames, sorted by frame number.
  const std::filesystem::path skel_dir = dir / "hdPose3d_stage1_coco19";
  std::error_code ec;
  if (!std::filesystem::is_directory(skel_dir, ec)) {
    throw DatasetError(skel_dir.string(), "directory not found");
  }
  std::map<FrameIndex, std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(skel_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 5 || name.compare(name.size() - 5, 5, ".json") != 0) continue;
    const std::optional<FrameIndex> frame = FrameFromSkeletonFileName(name);
    if (!frame.has_value()) {
      throw DatasetError(entry.path().string(),
                         "unexpected file name (expected body3DScene_<8 digits>.json)");
    }
    files.emplace(*frame, entry.path());
  }
  if (files.empty()) throw DatasetError(skel_dir.string(), "no body3DScene_*.json files");
  std::vector<FrameIndex> frames;
  frames.reserve(files.size());
  for (const auto& [frame, path] : files) frames.push_back(frame);
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);

  ds.gt_layout = core::KeypointLayoutId::kPanoptic19;
  std::size_t f = 0;
  for (const auto& [frame_index, path] : files) {
    const std::vector<PanopticBody> bodies = LoadSkeletonFile(path, to_world);
    eval::EvalFrame gt;
    gt.frame = frame_index;
    for (const PanopticBody& body : bodies) {
      // Clean detections: projection with the lens distortion; invalid, behind-camera and
      // outside-image joints are not detected.
      for (std::size_t c = 0; c < ds.cameras.size(); ++c) {
        const geometry::CameraModel& camera = ds.cameras[c];
        std::vector<core::Keypoint2D> kps(kPanopticJoints);
        for (std::size_t j = 0; j < kps.size(); ++j) {
          if (!body.joints[j].has_value()) continue;
          const std::optional<Vec2> px = camera.Project(*body.joints[j]);
          if (!px.has_value() || !camera.InImage(*px)) continue;
          kps[j].position_px = *px;
          kps[j].confidence = 1.0;
        }
        std::optional<core::Detection2D> d =
            internal::MakePoseDetection(std::move(kps), core::KeypointLayoutId::kPanoptic19);
        if (!d.has_value()) continue;
        ds.detections[f][c].detections.push_back(std::move(*d));
        ds.source_ids[f][c].push_back(body.id);
      }
      std::optional<eval::EvalObject> object =
          internal::MakeEvalObject(body.id, body.joints, ds.gt_layout);
      if (object.has_value()) gt.objects.push_back(std::move(*object));
    }
    ds.ground_truth.push_back(std::move(gt));
    ++f;
  }

  // The blackout (hard level) falls inside the protocol's frames.
  const CorruptionOptions corruption =
      internal::CorruptDataset(options.corruption, {{frames.front(), frames.back()}}, &ds);

  std::string camera_list;
  for (const geometry::CameraModel& camera : ds.cameras) {
    if (!camera_list.empty()) camera_list += ", ";
    camera_list += HdCameraName(camera.id);
  }
  ds.protocol_notes =
      "CMU Panoptic (Joo et al., ICCV 2015) " + options.sequence + ", HD frames " +
      std::to_string(frames.front()) + "-" + std::to_string(frames.back()) +
      " at 29.97 fps, HD cameras " + camera_list +
      " (1920x1080, with the official 5-parameter distortion). World rotated from Panoptic's "
      "y-down axes to z up ((x, y, z) -> (x, z, -y)) and scaled cm -> m. Detections: the 3D "
      "skeletons (panoptic19, joints with confidence < 0 invalid) projected with distortion, "
      "joints outside the image or behind the camera dropped, no occlusion between people "
      "modelled, then " +
      DescribeCorruption(corruption) +
      ". Ground truth: the 3D skeletons, 3 people (ids 0-2). 20 frames: too short for "
      "meaningful MOTA/IDF1.";
  return ds;
}

std::vector<geometry::CameraModel> LoadPanopticCalibrationFile(
    const std::filesystem::path& calib_file, const std::vector<std::string>& cameras) {
  const Mat3 to_world = PanopticToWorldRotation();
  const JsonValue calib = internal::LoadJsonFile(calib_file);
  std::map<std::string, JsonValue> hd;
  const JsonValue cams = calib["cameras"];
  for (std::size_t i = 0; i < cams.Size(); ++i) {
    const JsonValue cam = cams.At(i);
    if (cam["type"].AsString() != "hd") continue;
    const std::string name = cam["name"].AsString();
    if (!hd.emplace(name, cam).second) cam["name"].Fail("HD camera " + name + " appears twice");
  }
  std::vector<std::string> wanted = cameras;
  if (wanted.empty()) {
    // Every HD camera of the file, in index order (names "00_xx" sort by index).
    for (const auto& [name, cam] : hd) {
      if (ParseHdCamera(name).has_value()) wanted.push_back(name);
    }
    if (wanted.empty()) throw DatasetError(calib_file.string(), "no HD cameras");
  }
  std::set<int> seen;
  std::vector<geometry::CameraModel> out;
  for (const std::string& entry : wanted) {
    const std::optional<int> parsed = ParseHdCamera(entry);
    if (!parsed.has_value()) {
      throw DatasetError(calib_file.string(),
                         "camera \"" + entry +
                             "\" is neither an HD name 00_00..00_30 nor an "
                             "index 0..30");
    }
    const int index = *parsed;
    if (!seen.insert(index).second) {
      throw DatasetError(calib_file.string(), "camera \"" + entry + "\" is listed twice");
    }
    const std::string name = HdCameraName(index);
    const auto it = hd.find(name);
    if (it == hd.end()) throw DatasetError(calib_file.string(), "no HD camera named " + name);
    const JsonValue& cam = it->second;
    const JsonValue resolution = cam["resolution"];
    const std::int64_t width = resolution.At(0).AsInt();
    const std::int64_t height = resolution.At(1).AsInt();
    if (resolution.Size() != 2 || width <= 0 || height <= 0 || width > 100000 || height > 100000) {
      resolution.Fail("expected [width, height] with positive sizes");
    }
    const Mat3 K = internal::Mat3FromRowMajor(cam["K"].AsMatrix(3, 3));
    const std::vector<double> dist = cam["distCoef"].AsDoubles(5);
    const Mat3 R = internal::Mat3FromRowMajor(cam["R"].AsMatrix(3, 3));
    const std::vector<double> t = cam["t"].AsMatrix(3, 1);
    geometry::Distortion distortion;
    distortion.k1 = dist[0];
    distortion.k2 = dist[1];
    distortion.p1 = dist[2];
    distortion.p2 = dist[3];
    distortion.k3 = dist[4];
    out.push_back(internal::MakeCamera(calib_file.string(),
                                       "HD camera " + name,
                                       index,
                                       static_cast<int>(width),
                                       static_cast<int>(height),
                                       K,
                                       R * to_world.transpose(),
                                       kCmToM * Vec3(t[0], t[1], t[2]),
                                       distortion));
  }
  return out;
}

}  // namespace mvtrack::datasets
