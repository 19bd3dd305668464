#include "datasets/campus.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "datasets/calibration_files.h"
#include "datasets/internal/common.h"
#include "datasets/internal/json_document.h"

namespace mvtrack::datasets {
namespace {

using internal::JsonValue;
using internal::kCmToM;

constexpr double kCampusFps = 25.0;
constexpr double kFramePeriodS = 1.0 / kCampusFps;  // 0.04 s
constexpr int kCampusJoints = 14;
constexpr int kCoco17Joints = 17;

// frame = round(timestamp / 0.04), which must be (nearly) an integer: the timestamps are
// written with 2-3 decimals.
FrameIndex FrameFromTimestamp(const JsonValue& value) {
  const double t = value.AsDouble();
  const double x = t / kFramePeriodS;
  const double rounded = std::round(x);
  if (!(rounded >= 0.0 && rounded < 1e9) || std::abs(x - rounded) > 0.01) {
    value.Fail("timestamp " + std::to_string(t) + " s is not on the 25 fps grid");
  }
  return static_cast<FrameIndex>(rounded);
}

// "CameraN" -> N.
CameraId CameraIdFromName(const JsonValue& where, const std::string& name) {
  const std::string prefix = "Camera";
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.size() > prefix.size() + 4 ||
      name.find_first_not_of("0123456789", prefix.size()) != std::string::npos) {
    where.Fail("camera name \"" + name + "\" is not of the form CameraN");
  }
  return static_cast<CameraId>(std::stoi(name.substr(prefix.size())));
}

// Per-joint scores of one pose: 0 = missing, must be in [0, 1].
std::vector<double> ReadScores(const JsonValue& value, int joints) {
  std::vector<double> scores = value.AsDoubles(joints);
  for (double s : scores) {
    if (s < 0.0 || s > 1.0) value.Fail("score outside [0, 1]");
  }
  return scores;
}

std::vector<std::optional<Vec3>> ReadJoints3d(const JsonValue& pose, int joints) {
  const std::vector<double> xyz = pose["points_3d"].AsMatrix(joints, 3);
  const std::vector<double> scores = ReadScores(pose["scores"], joints);
  std::vector<std::optional<Vec3>> out(static_cast<std::size_t>(joints));
  for (std::size_t j = 0; j < out.size(); ++j) {
    if (!(scores[j] > 0.0)) continue;
    out[j] = kCmToM * Vec3(xyz[3 * j], xyz[3 * j + 1], xyz[3 * j + 2]);
  }
  return out;
}

std::vector<geometry::CameraModel> LoadCampusCalibration(const std::filesystem::path& file,
                                                         int width,
                                                         int height) {
  const JsonValue root = internal::LoadJsonFile(file);
  std::map<CameraId, geometry::CameraModel> by_id;
  for (const auto& [name, value] : root["cameras"].Items()) {
    const CameraId id = CameraIdFromName(value, name);
    const std::vector<double> k = value["K"].AsMatrix(3, 3);
    const std::vector<double> tw = value["Tw"].AsMatrix(4, 4);
    if (tw[12] != 0.0 || tw[13] != 0.0 || tw[14] != 0.0 || tw[15] != 1.0) {
      value["Tw"].Fail("last row must be [0, 0, 0, 1]");
    }
    // K is normalised by the image size: row 0 by the width, row 1 by the height.
    Mat3 K = internal::Mat3FromRowMajor(k);
    K.row(0) *= static_cast<double>(width);
    K.row(1) *= static_cast<double>(height);
    // Tw = world_from_camera with the camera centre in cm.
    Mat3 world_from_cam;
    Vec3 centre_m;
    for (Eigen::Index r = 0; r < 3; ++r) {
      for (Eigen::Index c = 0; c < 3; ++c) {
        world_from_cam(r, c) = tw[static_cast<std::size_t>(4 * r + c)];
      }
      centre_m(r) = kCmToM * tw[static_cast<std::size_t>(4 * r + 3)];
    }
    const Mat3 rotation = world_from_cam.transpose();
    if (!by_id
             .emplace(id,
                      internal::MakeCamera(file.string(),
                                           "camera \"" + name + "\"",
                                           id,
                                           width,
                                           height,
                                           K,
                                           rotation,
                                           -(rotation * centre_m)))
             .second) {
      value.Fail("camera " + std::to_string(id) + " appears twice");
    }
  }
  std::vector<geometry::CameraModel> cameras;
  cameras.reserve(by_id.size());
  for (auto& [id, camera] : by_id) cameras.push_back(std::move(camera));
  if (cameras.empty()) throw DatasetError(file.string(), "no cameras");
  return cameras;
}

}  // namespace

bool CampusOptions::Validate(std::string* why) const { return corruption.Validate(why); }

Dataset LoadCampus(const std::filesystem::path& data_root, const CampusOptions& options) {
  const std::filesystem::path dir = data_root / "campus" / "crossview_longcw";
  std::string why;
  if (!options.Validate(&why)) throw DatasetError(dir.string(), why);

  Dataset ds;
  ds.name = "campus";
  ds.fps = kCampusFps;

  const std::filesystem::path file_2d = dir / "annotation_2d.json";
  const JsonValue ann_2d = internal::LoadJsonFile(file_2d);
  const JsonValue image_wh = ann_2d["image_wh"];
  const std::int64_t width = image_wh.At(0).AsInt();
  const std::int64_t height = image_wh.At(1).AsInt();
  if (image_wh.Size() != 2 || width <= 0 || height <= 0 || width > 100000 || height > 100000) {
    image_wh.Fail("expected [width, height] with positive sizes");
  }
  ds.cameras = LoadCampusCalibration(
      dir / "calibration.json", static_cast<int>(width), static_cast<int>(height));
  std::map<CameraId, std::size_t> camera_index;
  for (std::size_t c = 0; c < ds.cameras.size(); ++c) camera_index[ds.cameras[c].id] = c;

  // 3D ground truth: defines the frames of the sequence.
  const std::filesystem::path file_3d = dir / "annotation_3d.json";
  const JsonValue ann_3d = internal::LoadJsonFile(file_3d);
  std::map<FrameIndex, eval::EvalFrame> gt_frames;
  ds.gt_layout = core::KeypointLayoutId::kShelf14;
  for (std::size_t i = 0; i < ann_3d.Size(); ++i) {
    const JsonValue entry = ann_3d.At(i);
    eval::EvalFrame frame;
    frame.frame = FrameFromTimestamp(entry["timestamp"]);
    const JsonValue poses = entry["poses"];
    std::set<std::int64_t> ids;
    for (std::size_t p = 0; p < poses.Size(); ++p) {
      const JsonValue pose = poses.At(p);
      const std::int64_t id = pose["id"].AsInt();
      if (!ids.insert(id).second) pose["id"].Fail("id appears twice in one frame");
      std::optional<eval::EvalObject> object =
          internal::MakeEvalObject(id, ReadJoints3d(pose, kCampusJoints), ds.gt_layout);
      if (object.has_value()) frame.objects.push_back(std::move(*object));
    }
    const FrameIndex index = frame.frame;
    if (!gt_frames.emplace(index, std::move(frame)).second) {
      entry["timestamp"].Fail("a second entry for frame " + std::to_string(index));
    }
  }
  if (gt_frames.empty()) throw DatasetError(file_3d.string(), "no frames");
  std::vector<FrameIndex> frames;
  for (auto& [index, frame] : gt_frames) {
    frames.push_back(index);
    ds.ground_truth.push_back(std::move(frame));
  }
  for (std::size_t f = 0; f < frames.size(); ++f) {
    if (frames[f] != frames.front() + static_cast<FrameIndex>(f)) {
      throw DatasetError(file_3d.string(),
                         "frames are not consecutive (frame " + std::to_string(frames[f]) +
                             " follows " + std::to_string(frames[f - 1]) + ")");
    }
  }
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);

  // 2D ground truth -> clean detections.
  std::vector<std::vector<bool>> seen(frames.size(), std::vector<bool>(ds.cameras.size(), false));
  for (const auto& [key, value] : ann_2d["frames"].Items()) {
    const std::string camera_name = value["camera"].AsString();
    const CameraId camera_id = CameraIdFromName(value["camera"], camera_name);
    const auto cam_it = camera_index.find(camera_id);
    if (cam_it == camera_index.end()) {
      value["camera"].Fail("camera " + camera_name + " is not in the calibration");
    }
    const FrameIndex frame = FrameFromTimestamp(value["timestamp"]);
    if (frame < frames.front() || frame > frames.back()) {
      value["timestamp"].Fail("frame " + std::to_string(frame) +
                              " is outside the frames of annotation_3d.json");
    }
    const std::size_t f = static_cast<std::size_t>(frame - frames.front());
    const std::size_t c = cam_it->second;
    if (seen[f][c]) {
      value.Fail("a second entry for " + camera_name + " at frame " + std::to_string(frame));
    }
    seen[f][c] = true;
    const JsonValue poses = value["poses"];
    for (std::size_t p = 0; p < poses.Size(); ++p) {
      const JsonValue pose = poses.At(p);
      const std::int64_t id = pose["id"].AsInt();
      const std::vector<double> xy = pose["points_2d"].AsMatrix(kCampusJoints, 2);
      const std::vector<double> scores = ReadScores(pose["scores"], kCampusJoints);
      std::vector<core::Keypoint2D> kps(kCampusJoints);
      for (std::size_t j = 0; j < kps.size(); ++j) {
        kps[j].position_px = Vec2(xy[2 * j], xy[2 * j + 1]);
        kps[j].confidence = scores[j];
      }
      std::optional<core::Detection2D> d =
          internal::MakePoseDetection(std::move(kps), core::KeypointLayoutId::kShelf14);
      if (!d.has_value()) continue;  // fewer than 2 annotated joints: not a usable detection
      ds.detections[f][c].detections.push_back(std::move(*d));
      ds.source_ids[f][c].push_back(id);
    }
  }

  // The detector model; the false-positive pool of a camera is all its clean poses.
  // The blackout (hard level) falls inside the protocol's frames.
  const CorruptionOptions corruption =
      internal::CorruptDataset(options.corruption, {{350, 470}, {650, 750}}, &ds);

  ds.protocol_frames = {eval::FrameRange{350, 470}, eval::FrameRange{650, 750}};
  ds.protocol_actor_ids = {0, 1, 2};
  ds.protocol_notes =
      "Campus (Belagiannis et al., CVPR 2014, CampusSeq1) as released by Cross-View Tracking "
      "(Chen et al., CVPR 2020): frames " +
      std::to_string(frames.front()) + "-" + std::to_string(frames.back()) +
      " at 25 fps (frame = round(timestamp / 0.04)), 3 cameras 360x288, calibration.json without "
      "its dist_coeffs (the 2D ground truth is the undistorted projection). No real detections "
      "exist: the 2D ground truth (shelf14) is the input, " +
      DescribeCorruption(corruption) +
      ". Ground truth: annotation_3d.json (cm -> m), 3 actors (ids 0-2); standard protocol "
      "frames 350-470 and 650-750 (VoxelPose).";
  return ds;
}

PeerOutput LoadCampusPeerCrossView(const std::filesystem::path& data_root) {
  const std::filesystem::path file = data_root / "campus" / "crossview_longcw" / "result_3d.json";
  const JsonValue root = internal::LoadJsonFile(file);
  PeerOutput peer;
  peer.name = "crossview_tracking";
  peer.native_layout = core::KeypointLayoutId::kCoco17;
  peer.native_joint_names = core::GetKeypointLayout(peer.native_layout).joints;
  std::map<std::uint64_t, std::int64_t> dense_ids;
  std::map<FrameIndex, eval::EvalFrame> frames;
  for (std::size_t i = 0; i < root.Size(); ++i) {
    const JsonValue entry = root.At(i);
    eval::EvalFrame frame;
    frame.frame = FrameFromTimestamp(entry["timestamp"]);
    const JsonValue poses = entry["poses"];
    std::set<std::int64_t> ids;
    for (std::size_t p = 0; p < poses.Size(); ++p) {
      const JsonValue pose = poses.At(p);
      const std::uint64_t original = pose["id"].AsUint64();
      auto [it, inserted] =
          dense_ids.emplace(original, static_cast<std::int64_t>(dense_ids.size()) + 1);
      if (inserted) peer.original_ids.push_back(original);
      if (!ids.insert(it->second).second) pose["id"].Fail("id appears twice in one frame");
      std::optional<eval::EvalObject> object = internal::MakeEvalObject(
          it->second, ReadJoints3d(pose, kCoco17Joints), peer.native_layout);
      if (object.has_value()) frame.objects.push_back(std::move(*object));
    }
    const FrameIndex index = frame.frame;
    if (!frames.emplace(index, std::move(frame)).second) {
      entry["timestamp"].Fail("a second entry for frame " + std::to_string(index));
    }
  }
  for (auto& [index, frame] : frames) peer.native.push_back(std::move(frame));
  peer.shelf14 = internal::MapSequence(
      peer.native,
      core::MakeKeypointMapping(core::KeypointLayoutId::kCoco17, core::KeypointLayoutId::kShelf14));
  peer.protocol_notes =
      "Cross-View Tracking's own output on Campus (crossview_longcw/result_3d.json, COCO-17, "
      "cm -> m, frame = round(timestamp / 0.04), joints with score 0 missing, 64-bit track ids "
      "remapped to 1, 2, ... in order of first appearance). shelf14 by "
      "core::MakeKeypointMapping(coco17, shelf14): limbs copied, head_bottom = 0.25 (l_shoulder "
      "+ r_shoulder + l_ear + r_ear), head_top = 0.75 (l_ear + r_ear) - 0.25 (l_shoulder + "
      "r_shoulder) (VoxelPose's coco2campus).";
  return peer;
}

std::vector<geometry::CameraModel> LoadCampusCalibrationFile(const std::filesystem::path& file,
                                                             int width_px,
                                                             int height_px) {
  return LoadCampusCalibration(file, width_px, height_px);
}

}  // namespace mvtrack::datasets
