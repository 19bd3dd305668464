#include "tracker/camera_stage.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <utility>

#include "core/check.h"

namespace mvtrack::tracker {
namespace {

// A box edge at `edge_px` touches the image border at `border_px` (0 for the top and left
// edges, the image size for the bottom and right ones) when it lies within kClipMarginPx of it:
// detectors clip boxes there (at 0 / size - 1 or at 0 / size, by convention). An edge beyond
// the border is an extrapolated (amodal) box and is kept.
// Box ends are used while the person's vertical axis leans at most this much in the image
// (|dx / dy|, tan 30 deg): further out, an axis-aligned box says little about where the axis
// meets its edges.
constexpr double kMaxEndsTilt = 0.577;

// CameraStage::CompleteCutBox: a track's whole size is used this many frames after its last
// uncut box (about 2 s at 30 fps; the size changes as the person walks).
constexpr FrameIndex kMaxWholeSizeAgeFrames = 60;

bool TouchesBorder(double edge_px, int border_px) {
  constexpr double kClipMarginPx = 1.5;
  const double b = static_cast<double>(border_px);
  return border_px == 0 ? edge_px <= kClipMarginPx && edge_px >= -kClipMarginPx
                        : edge_px >= b - 1.0 - kClipMarginPx && edge_px <= b + kClipMarginPx;
}

// A camera's SORT: `options.sort`, and appearance when it is on.
tracking2d::SortTracker MakeSort(const TrackerOptions& options) {
  tracking2d::SortTracker sort(options.sort);
  if (options.appearance.enabled) {
    tracking2d::SortAppearance s;
    s.weight = options.appearance.sort_weight;
    s.gate = options.appearance.sort_gate;
    s.gallery_size = options.appearance.sort_gallery_size;
    sort.set_appearance(s);
  }
  return sort;
}

}  // namespace

CameraStage::CameraStage(geometry::CameraModel camera,
                         int camera_index,
                         const TrackerOptions& options)
    : camera_(std::move(camera)),
      camera_index_(camera_index),
      options_(options),
      num_points_(NumPoints(options)),
      sort_(MakeSort(options)),
      k_inverse_(camera_.K.inverse()),
      world_from_cam_(camera_.cam_from_world.rotation.transpose()),
      up_vanishing_(camera_.K * camera_.cam_from_world.rotation.col(2)),
      sin_ends_limit_(std::sin(options.box_ends_max_elevation_deg * std::numbers::pi / 180.0)) {
  if (options_.mode == InputMode::kPoses) {
    for (core::KeypointLayoutId from : core::AllKeypointLayouts()) {
      mappings_[from] = core::MakeKeypointMapping(from, options_.layout);
    }
  }
}

Vec2 CameraStage::VerticalDirectionAt(const Vec2& undistorted_px) const {
  // Vanishing point of the world's z axis: K R e_z (homogeneous). Image direction from the
  // pixel towards it, pointing down the image (the feet are below the head).
  const Vec3& v = up_vanishing_;
  Vec2 d;
  if (std::abs(v.z()) < 1e-12) {
    d = Vec2(v.x(), v.y());  // verticals are parallel in the image
  } else {
    d = Vec2(v.x() / v.z(), v.y() / v.z()) - undistorted_px;
    if (v.z() > 0.0) d = -d;  // the up vanishing point lies in front: down is away from it
  }
  if (d.y() < 0.0) d = -d;
  return d;
}

bool CameraStage::SteeperThanEndsLimit(const Vec2& undistorted_px) const {
  // The ray through the pixel in the world frame (z up) is steeper than the limit when the
  // sine of its angle below the horizontal, -z / |ray|, exceeds the limit's sine.
  const Vec3 in_camera = k_inverse_ * Vec3(undistorted_px.x(), undistorted_px.y(), 1.0);
  const Vec3 in_world = world_from_cam_ * in_camera;
  return -in_world.z() > sin_ends_limit_ * in_world.norm();
}

std::optional<core::Observation2D> CameraStage::MakeObservation(const core::Detection2D& detection,
                                                                core::BoxPx* sort_box) const {
  if (detection.score < options_.min_detection_score) return std::nullopt;
  core::Observation2D obs;
  if (options_.mode == InputMode::kBoxes) {
    const core::BoxPx& box = detection.box;
    obs.cut_edges = static_cast<std::uint8_t>(
        (TouchesBorder(box.x_min, 0) ? core::kCutLeft : 0) |
        (TouchesBorder(box.x_max, camera_.width_px) ? core::kCutRight : 0) |
        (TouchesBorder(box.y_min, 0) ? core::kCutTop : 0) |
        (TouchesBorder(box.y_max, camera_.height_px) ? core::kCutBottom : 0));
    if (options_.box_point == BoxPoint::kCenterEnds) {
      // Centre, bottom (feet), top (head); an edge that touches the image border cuts the
      // person off, so that end is unknown.
      const core::BoxPx& b = detection.box;
      const Vec2 center = camera_.UndistortPixel(b.center());
      const double bottom_y = camera_.UndistortPixel(b.bottom_center()).y();
      const double top_y = camera_.UndistortPixel(b.top_center()).y();
      // The person's vertical axis through the box centre, in the image: towards the vanishing
      // point of the world's vertical. Where it crosses the box's bottom and top edges are the
      // feet and the head (the bottom and top centres only for an upright image of the person).
      const Vec2 axis = VerticalDirectionAt(center);
      const bool usable = std::abs(axis.y()) > 1e-9 &&
                          std::abs(axis.x() / axis.y()) <= kMaxEndsTilt &&
                          !SteeperThanEndsLimit(center);
      const auto on_axis = [&](double y) {
        return Vec2(center.x() + (y - center.y()) * axis.x() / axis.y(), y);
      };
      const bool bottom_cut = !usable || (obs.cut_edges & core::kCutBottom) != 0;
      const bool top_cut = !usable || (obs.cut_edges & core::kCutTop) != 0;
      obs.points_px.reserve(3);
      obs.confidence.reserve(3);
      obs.points_px.push_back(center);
      obs.confidence.push_back(1.0);
      obs.points_px.push_back(usable ? on_axis(bottom_y) : Vec2(center.x(), bottom_y));
      obs.confidence.push_back(bottom_cut ? 0.0 : 1.0);
      obs.points_px.push_back(usable ? on_axis(top_y) : Vec2(center.x(), top_y));
      obs.confidence.push_back(top_cut ? 0.0 : 1.0);
    } else {
      const Vec2 raw = options_.box_point == BoxPoint::kCenter ? detection.box.center()
                                                               : detection.box.bottom_center();
      obs.points_px.push_back(camera_.UndistortPixel(raw));
      obs.confidence.push_back(1.0);
    }
    obs.scale_px = detection.box.width() + detection.box.height();
    *sort_box = detection.box;
    return obs;
  }
  // Pose mode: map the detector's layout to ours, undistorting each source keypoint first.
  auto it = mappings_.find(detection.layout);
  if (it == mappings_.end() || detection.keypoints.empty()) return std::nullopt;
  const core::KeypointMapping& mapping = it->second;
  const double min_conf = options_.min_keypoint_confidence;
  obs.points_px.assign(static_cast<std::size_t>(num_points_), Vec2::Zero());
  obs.confidence.assign(static_cast<std::size_t>(num_points_), 0.0);
  int usable = 0;
  for (std::size_t j = 0; j < mapping.targets.size(); ++j) {
    const auto& sources = mapping.targets[j];
    if (sources.empty()) continue;
    Vec2 sum = Vec2::Zero();
    double conf = 1.0;
    for (const core::JointSource& s : sources) {
      const core::Keypoint2D& kp = detection.keypoints[static_cast<std::size_t>(s.source_joint)];
      conf = std::min(conf, kp.confidence);
      if (conf < min_conf) break;
      sum += s.weight * camera_.UndistortPixel(kp.position_px);
    }
    if (conf < min_conf) continue;
    obs.points_px[j] = sum;
    obs.confidence[j] = conf;
    ++usable;
  }
  if (usable < options_.min_pose_keypoints) return std::nullopt;
  // The pose's box encloses its usable (raw) keypoints.
  core::BoxPx box{std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  for (const core::Keypoint2D& kp : detection.keypoints) {
    if (kp.confidence < min_conf) continue;
    box.x_min = std::min(box.x_min, kp.position_px.x());
    box.y_min = std::min(box.y_min, kp.position_px.y());
    box.x_max = std::max(box.x_max, kp.position_px.x());
    box.y_max = std::max(box.y_max, kp.position_px.y());
  }
  if (!(box.width() + box.height() > 1.0)) return std::nullopt;
  obs.scale_px = box.width() + box.height();
  *sort_box = box;
  return obs;
}

void CameraStage::CompleteCutBox(TrackId2D track,
                                 FrameIndex frame,
                                 const core::BoxPx& box,
                                 core::Observation2D* obs) {
  const std::uint8_t cut = obs->cut_edges;
  if (cut == 0) {
    whole_size_[track] = WholeSize{box.width(), box.height(), frame};
    return;
  }
  const auto it = whole_size_.find(track);
  if (it == whole_size_.end() || frame - it->second.frame > kMaxWholeSizeAgeFrames) return;
  core::BoxPx whole = box;
  const double w = std::max(it->second.width, box.width());
  const double h = std::max(it->second.height, box.height());
  const bool left = (cut & core::kCutLeft) != 0;
  const bool right = (cut & core::kCutRight) != 0;
  const bool top = (cut & core::kCutTop) != 0;
  const bool bottom = (cut & core::kCutBottom) != 0;
  if (left && !right) whole.x_min = box.x_max - w;
  if (right && !left) whole.x_max = box.x_min + w;
  if (top && !bottom) whole.y_min = box.y_max - h;
  if (bottom && !top) whole.y_max = box.y_min + h;
  obs->points_px[0] = camera_.UndistortPixel(whole.center());
  obs->scale_px = whole.width() + whole.height();
}

TrackedCameraFrame CameraStage::Process(const core::CameraFrame& frame,
                                        std::int64_t stream_epoch,
                                        CameraStageCounters* counters) {
  MVTRACK_CHECK(counters != nullptr);
  MVTRACK_CHECK_MSG(stream_epoch >= stream_epoch_, "stream epochs must not decrease");
  *counters = CameraStageCounters{};
  if (stream_epoch != stream_epoch_) {
    // The stream ended (re-anchor or flush) since this camera's last frame: SORT restarts.
    sort_ = MakeSort(options_);
    whole_size_.clear();  // the new SORT's track ids start again
    stream_epoch_ = stream_epoch;
    period_.Clear();
    sort_seconds_per_frame_ = 0.0;
    frames_since_period_ = FramePeriod::kFrames - 1;
  }
  core::DetectionLimits limits;
  limits.image_width_px = camera_.width_px;
  limits.image_height_px = camera_.height_px;
  limits.box_margin_fraction = options_.box_margin_fraction;
  std::vector<core::BoxPx>& boxes = boxes_;
  std::vector<core::Observation2D>& observations = observations_;
  boxes.clear();
  observations.clear();
  boxes.reserve(frame.detections.size());
  observations.reserve(frame.detections.size());
  for (const core::Detection2D& original : frame.detections) {
    core::Detection2D detection = original;
    const core::DetectionCheck check = core::ValidateDetection(&detection, limits);
    if (check.verdict == core::DetectionVerdict::kRejected) {
      ++counters->detections_rejected;
      if (counters->first_rejection_reason.empty()) counters->first_rejection_reason = check.reason;
      continue;
    }
    if (check.verdict == core::DetectionVerdict::kAcceptedRepaired) ++counters->detections_repaired;
    core::BoxPx sort_box;
    std::optional<core::Observation2D> obs = MakeObservation(detection, &sort_box);
    if (!obs) {
      ++counters->detections_filtered;
      continue;
    }
    if (options_.appearance.enabled && check.embedding_dropped) {
      ++counters->embeddings_dropped;
      if (counters->first_embedding_reason.empty()) counters->first_embedding_reason = check.reason;
    } else if (options_.appearance.enabled && !detection.embedding.empty()) {
      std::string why =
          core::CheckEmbedding(detection.embedding_model, &detection.embedding, &embedding_stream_);
      if (why.empty()) {
        obs->embedding = std::make_shared<const std::vector<float>>(std::move(detection.embedding));
        ++counters->embeddings_used;
      } else {
        ++counters->embeddings_dropped;
        if (counters->first_embedding_reason.empty()) {
          counters->first_embedding_reason = std::move(why);
        }
      }
    }
    boxes.push_back(sort_box);
    observations.push_back(std::move(*obs));
  }
  counters->detections_used = static_cast<int>(observations.size());

  TrackedCameraFrame out;
  out.camera_index = camera_index_;
  out.frame = frame.frame;
  out.utime = frame.utime;
  // SORT's options follow the estimate at 2, 4, 8, 16 and 32 frames of the stream, then every
  // kFrames frames (a median over kFrames frames moves slowly; it runs per camera-frame).
  period_.Add(frame.frame, frame.utime);
  const std::size_t n = period_.size();
  const bool due = n < FramePeriod::kFrames ? (n & (n - 1)) == 0
                                            : ++frames_since_period_ >= FramePeriod::kFrames;
  if (due) {
    frames_since_period_ = 0;
    if (const double s = period_.Seconds(); s != sort_seconds_per_frame_) {
      sort_.set_options(SortOptionsAtFrameRate(options_, s));
      sort_seconds_per_frame_ = s;
    }
  }
  std::vector<const std::vector<float>*>* embeddings = nullptr;
  if (options_.appearance.enabled) {
    embeddings_.clear();
    for (const core::Observation2D& obs : observations) {
      embeddings_.push_back(obs.embedding.get());
    }
    embeddings = &embeddings_;
  }
  const std::vector<tracking2d::TrackedDetection> tracked =
      sort_.Update(frame.frame, boxes, embeddings);
  out.observations.reserve(tracked.size());
  // Each detection belongs to at most one track, so its observation can be moved out.
  for (const tracking2d::TrackedDetection& td : tracked) {
    const auto i = static_cast<std::size_t>(td.detection_index);
    if (options_.mode == InputMode::kBoxes && options_.box_complete_cut &&
        options_.box_point != BoxPoint::kBottomCenter) {
      CompleteCutBox(td.track_id, frame.frame, boxes[i], &observations[i]);
    }
    out.observations.emplace_back(td.track_id, std::move(observations[i]));
  }
  // Bounded: sizes of tracks without a whole box for kMaxWholeSizeAgeFrames are forgotten.
  if (whole_size_.size() > 2 * tracked.size() + 64) {
    std::erase_if(whole_size_, [&](const auto& e) {
      return frame.frame - e.second.frame > kMaxWholeSizeAgeFrames;
    });
  }
  if (options_.appearance.enabled) {
    counters->sort_gallery_bytes = static_cast<std::int64_t>(sort_.gallery_bytes());
  }
  return out;
}

}  // namespace mvtrack::tracker
