#include "datasets/shelf.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "datasets/calibration_files.h"
#include "datasets/internal/common.h"
#include "datasets/internal/json_document.h"
#include "datasets/internal/skel_text.h"
#include "eval/head_rule.h"

namespace mvtrack::datasets {
namespace {

using internal::JsonValue;

constexpr FrameIndex kShelfFirstFrame = 300;  // line i of the 4D Association files = frame 300+i
constexpr int kShelfGtJoints = 15;            // gt.txt: shelf14 + pelvis
constexpr int kBody25Joints = 25;
constexpr int kSkel19Joints = 19;

// 4D Association's SKEL19 order, read off `GetSkelMapping(BODY25, SKEL19)` in src/skel.h of
// github.com/zhangyux15/4d_association (BODY25 joint b -> SKEL19 joint mapping[b]).
enum Skel19 : int {
  kMidHip = 0,
  kNeck = 1,
  kRHip = 2,
  kLHip = 3,
  kNose = 4,
  kRShoulder = 5,
  kLShoulder = 6,
  kRKnee = 7,
  kLKnee = 8,
  kREar = 9,
  kLEar = 10,
  kRElbow = 11,
  kLElbow = 12,
  kRAnkle = 13,
  kLAnkle = 14,
  kRWrist = 15,
  kLWrist = 16,
  kLBigToe = 17,
  kRBigToe = 18,
};

const std::vector<std::string>& Skel19JointNames() {
  static const std::vector<std::string> names = {"mid_hip",
                                                 "neck",
                                                 "r_hip",
                                                 "l_hip",
                                                 "nose",
                                                 "r_shoulder",
                                                 "l_shoulder",
                                                 "r_knee",
                                                 "l_knee",
                                                 "r_ear",
                                                 "l_ear",
                                                 "r_elbow",
                                                 "l_elbow",
                                                 "r_ankle",
                                                 "l_ankle",
                                                 "r_wrist",
                                                 "l_wrist",
                                                 "l_big_toe",
                                                 "r_big_toe"};
  return names;
}

std::vector<geometry::CameraModel> LoadShelfCalibration(const std::filesystem::path& file) {
  const JsonValue root = internal::LoadJsonFile(file);
  std::map<int, geometry::CameraModel> by_id;
  for (const auto& [key, value] : root.Items()) {
    int id = -1;
    try {
      std::size_t used = 0;
      id = std::stoi(key, &used);
      if (used != key.size()) id = -1;
    } catch (const std::exception&) {
      id = -1;
    }
    if (id < 0) value.Fail("camera key \"" + key + "\" is not a non-negative integer");
    const std::vector<double> k = value["K"].AsDoubles(9);
    const std::vector<double> rt = value["RT"].AsDoubles(12);
    const JsonValue size = value["imgSize"];
    const std::int64_t width = size.At(0).AsInt();
    const std::int64_t height = size.At(1).AsInt();
    if (size.Size() != 2 || width <= 0 || height <= 0 || width > 100000 || height > 100000) {
      size.Fail("expected [width, height] with positive sizes");
    }
    Mat3 rotation;
    Vec3 translation;
    for (Eigen::Index r = 0; r < 3; ++r) {
      for (Eigen::Index c = 0; c < 3; ++c) rotation(r, c) = rt[static_cast<std::size_t>(4 * r + c)];
      translation(r) = rt[static_cast<std::size_t>(4 * r + 3)];
    }
    by_id[id] = internal::MakeCamera(file.string(),
                                     "camera \"" + key + "\"",
                                     id,
                                     static_cast<int>(width),
                                     static_cast<int>(height),
                                     internal::Mat3FromRowMajor(k),
                                     rotation,
                                     translation);
  }
  if (by_id.empty()) throw DatasetError(file.string(), "no cameras");
  std::vector<geometry::CameraModel> cameras;
  cameras.reserve(by_id.size());
  for (auto& [id, camera] : by_id) cameras.push_back(std::move(camera));
  return cameras;
}

// Reads derived/persons2d_body25_cam<c>.json into [file frame][person] detections.
std::vector<std::vector<core::Detection2D>> LoadShelfPersons(const std::filesystem::path& file,
                                                             const geometry::CameraModel& camera) {
  const JsonValue root = internal::LoadJsonFile(file);
  if (root["camera"].AsInt() != camera.id) {
    root["camera"].Fail("camera " + std::to_string(root["camera"].AsInt()) +
                        " does not match the file name's camera " + std::to_string(camera.id));
  }
  const JsonValue size = root["image_size"];
  if (size.Size() != 2 || size.At(0).AsInt() != camera.width_px ||
      size.At(1).AsInt() != camera.height_px) {
    size.Fail("image size differs from the calibration's " + std::to_string(camera.width_px) + "x" +
              std::to_string(camera.height_px));
  }
  const JsonValue frames = root["frames"];
  std::vector<std::vector<core::Detection2D>> out(frames.Size());
  for (std::size_t f = 0; f < frames.Size(); ++f) {
    const JsonValue frame = frames.At(f);
    if (frame["frame_index"].AsInt() != static_cast<std::int64_t>(f)) {
      frame["frame_index"].Fail("expected frame_index " + std::to_string(f) +
                                " (frames must be consecutive from 0)");
    }
    const JsonValue persons = frame["persons"];
    for (std::size_t p = 0; p < persons.Size(); ++p) {
      const JsonValue keypoints = persons.At(p)["keypoints"];
      if (keypoints.Size() != static_cast<std::size_t>(kBody25Joints)) {
        keypoints.Fail("expected 25 BODY25 keypoints, got " + std::to_string(keypoints.Size()));
      }
      std::vector<core::Keypoint2D> kps(kBody25Joints);
      for (std::size_t j = 0; j < kps.size(); ++j) {
        const JsonValue entry = keypoints.At(j);
        const std::vector<double> v = entry.AsDoubles(3);
        if (v[2] < 0.0) entry.Fail("negative keypoint score");
        kps[j].position_px = Vec2(v[0], v[1]);
        // OpenPose peak scores can exceed 1 slightly (max 1.037 in these files); Detection2D
        // confidences are in [0, 1].
        kps[j].confidence = std::min(v[2], 1.0);
      }
      std::optional<core::Detection2D> d =
          internal::MakePoseDetection(std::move(kps), core::KeypointLayoutId::kBody25);
      if (!d.has_value()) {
        persons.At(p).Fail("a person needs at least 2 detected keypoints");
      }
      out[f].push_back(std::move(*d));
    }
  }
  return out;
}

std::vector<std::optional<Vec3>> PresentJoints(const internal::SkelTextPerson& person, int count) {
  std::vector<std::optional<Vec3>> joints(static_cast<std::size_t>(count));
  for (int j = 0; j < count; ++j) {
    if (person.rows(3, j) > 0.0) {
      joints[static_cast<std::size_t>(j)] = person.rows.block<3, 1>(0, j);
    }
  }
  return joints;
}

// 4D Association's `MappingToShelf` (evaluate_shelf/main.cpp) from SKEL19 to shelf14 (its 15th
// output joint, the pelvis, is not part of shelf14).
std::vector<std::optional<Vec3>> Skel19ToShelf14(const std::vector<std::optional<Vec3>>& s) {
  static constexpr std::array<int, 12> kLimbs = {kRAnkle,
                                                 kRKnee,
                                                 kRHip,
                                                 kLHip,
                                                 kLKnee,
                                                 kLAnkle,
                                                 kRWrist,
                                                 kRElbow,
                                                 kRShoulder,
                                                 kLShoulder,
                                                 kLElbow,
                                                 kLWrist};
  std::vector<std::optional<Vec3>> out(14);
  for (std::size_t j = 0; j < kLimbs.size(); ++j) out[j] = s[static_cast<std::size_t>(kLimbs[j])];
  const auto has = [&](std::initializer_list<int> joints) {
    for (int j : joints) {
      if (!s[static_cast<std::size_t>(j)].has_value()) return false;
    }
    return true;
  };
  const auto at = [&](int j) { return *s[static_cast<std::size_t>(j)]; };
  if (has({kLShoulder, kRShoulder, kLEar, kREar})) {
    const Vec3 shoulder_centre = 0.5 * (at(kRShoulder) + at(kLShoulder));
    const Vec3 head_centre = 0.5 * (at(kREar) + at(kLEar));
    const Vec3 head_bottom = shoulder_centre + 0.5 * (head_centre - shoulder_centre);
    out[12] = head_bottom;
    if (has({kNeck, kMidHip})) {
      out[13] = eval::FourDAssociationHeadTop(
          head_bottom, at(kNeck), at(kMidHip), at(kRShoulder), at(kLShoulder));
    }
  }
  return out;
}

std::string FormatFps(double fps) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", fps);
  return text;
}

}  // namespace

bool ShelfOptions::Validate(std::string* why) const {
  if (!(std::isfinite(fps) && fps > 0.0)) {
    if (why != nullptr) *why = "shelf options: fps must be finite and > 0";
    return false;
  }
  return true;
}

Dataset LoadShelf(const std::filesystem::path& data_root, const ShelfOptions& options) {
  const std::filesystem::path dir = data_root / "shelf";
  std::string why;
  if (!options.Validate(&why)) throw DatasetError(dir.string(), why);

  Dataset ds;
  ds.name = "shelf";
  ds.fps = options.fps;
  ds.cameras = LoadShelfCalibration(dir / "4d_association" / "calibration.json");

  const std::filesystem::path gt_file = dir / "4d_association" / "gt.txt";
  const internal::SkelTextFile gt = internal::ReadSkelText(gt_file, kShelfGtJoints);
  const std::size_t num_frames = gt.frames.size();
  std::vector<FrameIndex> frames(num_frames);
  for (std::size_t f = 0; f < num_frames; ++f) {
    frames[f] = kShelfFirstFrame + static_cast<FrameIndex>(f);
  }
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);

  for (std::size_t c = 0; c < ds.cameras.size(); ++c) {
    const std::filesystem::path file =
        dir / "derived" / ("persons2d_body25_cam" + std::to_string(ds.cameras[c].id) + ".json");
    std::vector<std::vector<core::Detection2D>> persons = LoadShelfPersons(file, ds.cameras[c]);
    if (persons.size() != num_frames) {
      throw DatasetError(
          file.string(),
          std::to_string(persons.size()) + " frames, but gt.txt has " + std::to_string(num_frames));
    }
    for (std::size_t f = 0; f < num_frames; ++f) {
      ds.source_ids[f][c].assign(persons[f].size(), kUnknownSourceId);
      ds.detections[f][c].detections = std::move(persons[f]);
    }
  }

  ds.gt_layout = core::KeypointLayoutId::kShelf14;
  ds.ground_truth.reserve(num_frames);
  for (std::size_t f = 0; f < num_frames; ++f) {
    eval::EvalFrame frame;
    frame.frame = frames[f];
    for (const internal::SkelTextPerson& person : gt.frames[f]) {
      std::vector<std::optional<Vec3>> joints = PresentJoints(person, kShelfGtJoints);
      joints.resize(14);  // drop the pelvis (the hip midpoint; derivable, not in shelf14)
      std::optional<eval::EvalObject> object =
          internal::MakeEvalObject(person.id, std::move(joints), ds.gt_layout);
      if (object.has_value()) frame.objects.push_back(std::move(*object));
    }
    ds.ground_truth.push_back(std::move(frame));
  }
  const FrameIndex last_frame = kShelfFirstFrame + static_cast<FrameIndex>(num_frames) - 1;
  ds.protocol_frames = {eval::FrameRange{kShelfFirstFrame, last_frame}};
  ds.protocol_actor_ids = {0, 1, 2};
  ds.protocol_notes =
      "Shelf (Belagiannis et al., CVPR 2014) as released by 4D Association (Zhang et al., CVPR "
      "2020). Frames 300-600: line i of the 4D Association files is Shelf frame 300+i (the "
      "standard test range; the offset is not stated by the repository). 5 cameras, 1032x776, "
      "no distortion. Detections: real OpenPose BODY25 joint candidates assembled into people "
      "with 4D Association's greedy PAF rule (shelf/derived/persons2d_body25_cam*.json); scores "
      "above 1 clamped to 1; box = keypoint bounds grown by 10% of their height on each side; "
      "score = mean keypoint score. Ground truth: gt.txt, 4 actors (ids 0-3), shelf14 (the 15th "
      "joint, pelvis, dropped); the usual PCP protocol scores ids 0, 1, 2. Frame rate not stated "
      "by the source; " +
      FormatFps(options.fps) + " fps assumed for timestamps.";
  return ds;
}

PeerOutput LoadShelfPeer4DA(const std::filesystem::path& data_root, Shelf4DARun which) {
  const std::string dir = which == Shelf4DARun::kLinux ? "4d_association_linux" : "4d_association";
  const std::filesystem::path file = data_root / "shelf" / dir / "skel.txt";
  const internal::SkelTextFile skel = internal::ReadSkelText(file, kSkel19Joints);
  PeerOutput peer;
  peer.name = dir;
  peer.native_layout = core::KeypointLayoutId::kNone;
  peer.native_joint_names = Skel19JointNames();
  std::map<std::int64_t, std::int64_t> dense_ids;
  for (std::size_t f = 0; f < skel.frames.size(); ++f) {
    eval::EvalFrame native;
    eval::EvalFrame shelf;
    native.frame = shelf.frame = kShelfFirstFrame + static_cast<FrameIndex>(f);
    for (const internal::SkelTextPerson& person : skel.frames[f]) {
      std::vector<std::optional<Vec3>> joints = PresentJoints(person, kSkel19Joints);
      const std::optional<Vec3> footprint = internal::FootprintFromHips(joints, kLHip, kRHip);
      if (!footprint.has_value()) continue;  // no joint present: 4DA's inactive skeleton
      auto [it, inserted] =
          dense_ids.emplace(person.id, static_cast<std::int64_t>(dense_ids.size()) + 1);
      if (inserted) peer.original_ids.push_back(static_cast<std::uint64_t>(person.id));
      const std::int64_t id = it->second;
      std::vector<std::optional<Vec3>> mapped = Skel19ToShelf14(joints);
      eval::EvalObject native_object;
      native_object.id = id;
      native_object.position = *footprint;
      native_object.joints = std::move(joints);
      native.objects.push_back(std::move(native_object));
      std::optional<eval::EvalObject> shelf_object =
          internal::MakeEvalObject(id, std::move(mapped), core::KeypointLayoutId::kShelf14);
      if (shelf_object.has_value()) shelf.objects.push_back(std::move(*shelf_object));
    }
    peer.native.push_back(std::move(native));
    peer.shelf14.push_back(std::move(shelf));
  }
  peer.protocol_notes =
      "4D Association's own tracking output on Shelf (" + dir +
      "/skel.txt, SKEL19, metres), "
      "frames 300-600 (line i = frame 300+i), track ids 0-4 remapped to 1-5 in order of first "
      "appearance. A joint is present when its confidence row is > 0; skeletons without any "
      "present joint are left out (and shelf14 objects without a present joint). shelf14 by 4D "
      "Association's MappingToShelf: limbs copied, "
      "head_bottom = shoulder_mid + 0.5 (ear_mid - shoulder_mid), head_top = head_bottom + "
      "0.125 m * normalize((neck - mid_hip) x (r_shoulder - l_shoulder)) + 0.145 m * z.";
  return peer;
}

std::vector<geometry::CameraModel> LoadShelfCalibrationFile(const std::filesystem::path& file) {
  return LoadShelfCalibration(file);
}

}  // namespace mvtrack::datasets
