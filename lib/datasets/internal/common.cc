#include "datasets/internal/common.h"

#include <utility>

#include "datasets/dataset.h"

namespace mvtrack::datasets::internal {

geometry::CameraModel MakeCamera(const std::string& file,
                                 const std::string& what,
                                 CameraId id,
                                 int width_px,
                                 int height_px,
                                 const Mat3& K,
                                 const Mat3& cam_from_world_rotation,
                                 const Vec3& cam_from_world_translation_m,
                                 const geometry::Distortion& distortion) {
  geometry::CameraModel camera;
  camera.id = id;
  camera.width_px = width_px;
  camera.height_px = height_px;
  camera.K = K;
  camera.distortion = distortion;
  camera.cam_from_world.rotation = cam_from_world_rotation;
  camera.cam_from_world.translation = cam_from_world_translation_m;
  std::string why;
  if (!camera.Validate(&why)) throw DatasetError(file, what + ": invalid calibration: " + why);
  return camera;
}

Mat3 Mat3FromRowMajor(const std::vector<double>& v, std::size_t offset) {
  Mat3 m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      m(r, c) = v[offset + static_cast<std::size_t>(3 * r + c)];
    }
  }
  return m;
}

std::optional<Vec3> FootprintFromHips(const std::vector<std::optional<Vec3>>& joints,
                                      int l_hip,
                                      int r_hip) {
  const auto present = [&](int j) {
    return j >= 0 && static_cast<std::size_t>(j) < joints.size() &&
           joints[static_cast<std::size_t>(j)].has_value();
  };
  Vec3 point = Vec3::Zero();
  if (present(l_hip) && present(r_hip)) {
    point =
        0.5 * (*joints[static_cast<std::size_t>(l_hip)] + *joints[static_cast<std::size_t>(r_hip)]);
  } else {
    int count = 0;
    for (const auto& j : joints) {
      if (!j.has_value()) continue;
      point += *j;
      ++count;
    }
    if (count == 0) return std::nullopt;
    point /= static_cast<double>(count);
  }
  point.z() = 0.0;
  return point;
}

std::optional<eval::EvalObject> MakeEvalObject(std::int64_t id,
                                               std::vector<std::optional<Vec3>> joints,
                                               core::KeypointLayoutId layout) {
  const std::optional<Vec3> footprint = FootprintFromJoints(joints, layout);
  if (!footprint.has_value()) return std::nullopt;
  eval::EvalObject object;
  object.id = id;
  object.position = *footprint;
  object.joints = std::move(joints);
  return object;
}

std::optional<core::Detection2D> MakePoseDetection(std::vector<core::Keypoint2D> keypoints,
                                                   core::KeypointLayoutId layout) {
  const std::optional<core::BoxPx> box = BoxFromKeypoints(keypoints);
  if (!box.has_value()) return std::nullopt;
  core::Detection2D d;
  d.box = *box;
  d.score = MeanKeypointScore(keypoints);
  d.keypoints = std::move(keypoints);
  d.layout = layout;
  return d;
}

void InitDetectionGrid(const std::vector<FrameIndex>& frames,
                       const std::vector<geometry::CameraModel>& cameras,
                       double fps,
                       std::vector<std::vector<core::CameraFrame>>* detections,
                       std::vector<std::vector<std::vector<std::int64_t>>>* source_ids) {
  detections->assign(frames.size(), std::vector<core::CameraFrame>(cameras.size()));
  source_ids->assign(frames.size(), std::vector<std::vector<std::int64_t>>(cameras.size()));
  for (std::size_t f = 0; f < frames.size(); ++f) {
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      core::CameraFrame& cf = (*detections)[f][c];
      cf.frame = frames[f];
      cf.utime = FrameUtime(frames[f], fps);
      cf.camera_id = cameras[c].id;
    }
  }
}

eval::EvalSequence MapSequence(const eval::EvalSequence& sequence,
                               const core::KeypointMapping& mapping) {
  eval::EvalSequence out;
  out.reserve(sequence.size());
  std::vector<Vec3> points;
  std::vector<bool> valid;
  std::vector<Vec3> mapped_points;
  std::vector<bool> mapped_valid;
  for (const eval::EvalFrame& frame : sequence) {
    eval::EvalFrame mapped_frame;
    mapped_frame.frame = frame.frame;
    for (const eval::EvalObject& object : frame.objects) {
      points.assign(object.joints.size(), Vec3::Zero());
      valid.assign(object.joints.size(), false);
      for (std::size_t j = 0; j < object.joints.size(); ++j) {
        if (!object.joints[j].has_value()) continue;
        points[j] = *object.joints[j];
        valid[j] = true;
      }
      core::ApplyKeypointMapping(mapping, points, valid, &mapped_points, &mapped_valid);
      std::vector<std::optional<Vec3>> joints(mapped_points.size());
      for (std::size_t j = 0; j < mapped_points.size(); ++j) {
        if (mapped_valid[j]) joints[j] = mapped_points[j];
      }
      std::optional<eval::EvalObject> mapped =
          MakeEvalObject(object.id, std::move(joints), mapping.to);
      if (mapped.has_value()) mapped_frame.objects.push_back(std::move(*mapped));
    }
    out.push_back(std::move(mapped_frame));
  }
  return out;
}

void CorruptDetectionGrid(const CorruptionOptions& corruption,
                          const std::vector<geometry::CameraModel>& cameras,
                          std::vector<std::vector<core::CameraFrame>>* detections,
                          std::vector<std::vector<std::vector<std::int64_t>>>* source_ids) {
  if (!corruption.enabled) return;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    std::vector<core::Detection2D> pool;
    for (const auto& frame : *detections) {
      pool.insert(pool.end(), frame[c].detections.begin(), frame[c].detections.end());
    }
    for (std::size_t f = 0; f < detections->size(); ++f) {
      CorruptedFrame corrupted = CorruptCameraFrame((*detections)[f][c],
                                                    (*source_ids)[f][c],
                                                    pool,
                                                    cameras[c].width_px,
                                                    cameras[c].height_px,
                                                    corruption);
      (*detections)[f][c] = std::move(corrupted.frame);
      (*source_ids)[f][c] = std::move(corrupted.source_ids);
    }
  }
}

CorruptionOptions CorruptDataset(const CorruptionOptions& corruption,
                                 const std::vector<std::pair<FrameIndex, FrameIndex>>& ranges,
                                 Dataset* ds) {
  CorruptionOptions placed = corruption;
  std::vector<CameraId> camera_ids;
  camera_ids.reserve(ds->cameras.size());
  for (const geometry::CameraModel& camera : ds->cameras) camera_ids.push_back(camera.id);
  PlaceBlackout(&placed, camera_ids, ranges, ds->fps);
  CorruptDetectionGrid(placed, ds->cameras, &ds->detections, &ds->source_ids);
  return placed;
}

}  // namespace mvtrack::datasets::internal
