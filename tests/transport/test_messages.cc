#include "transport/test_messages.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

namespace mvtrack::transport::testing {
namespace {

// A double that is exactly a float: a multiple of 1/64 in [lo, hi).
double FloatExact(std::mt19937* rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return std::round(u(*rng) * 64.0) / 64.0;
}

core::Detection2D MakeDetection(std::mt19937* rng,
                                core::KeypointLayoutId layout,
                                int embedding_size) {
  core::Detection2D d;
  const double x = FloatExact(rng, 0.0, 1500.0);
  const double y = FloatExact(rng, 0.0, 800.0);
  d.box = core::BoxPx{x, y, x + FloatExact(rng, 40.0, 200.0), y + FloatExact(rng, 80.0, 400.0)};
  d.score = FloatExact(rng, 0.3, 1.0);
  d.layout = layout;
  const int n = core::GetKeypointLayout(layout).num_joints();
  for (int j = 0; j < n; ++j) {
    core::Keypoint2D kp;
    kp.position_px =
        Vec2(FloatExact(rng, d.box.x_min, d.box.x_max), FloatExact(rng, d.box.y_min, d.box.y_max));
    kp.confidence = j % 5 == 4 ? 0.0 : FloatExact(rng, 0.1, 1.0);
    d.keypoints.push_back(kp);
  }
  for (int k = 0; k < embedding_size; ++k) {
    d.embedding.push_back(static_cast<float>(FloatExact(rng, -1.0, 1.0)));
  }
  return d;
}

bool SameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

std::string BitsDiffer(const std::string& what, double a, double b) {
  return what + ": " + std::to_string(a) + " != " + std::to_string(b);
}

std::string Where(const std::string& prefix, std::size_t i) {
  return prefix + "[" + std::to_string(i) + "]";
}

}  // namespace

core::CameraFrame MakeRealisticFrame(std::uint32_t seed) {
  std::mt19937 rng(seed);
  core::CameraFrame frame;
  frame.utime = 1'700'000'000'000'000 + static_cast<Utime>(seed) * 33'333;
  frame.frame = 1000 + static_cast<FrameIndex>(seed);
  frame.camera_id = 3;
  frame.detections.push_back(MakeDetection(&rng, core::KeypointLayoutId::kNone, 0));
  frame.detections.push_back(MakeDetection(&rng, core::KeypointLayoutId::kCoco17, 0));
  frame.detections.push_back(MakeDetection(&rng, core::KeypointLayoutId::kCoco17, 16));
  frame.detections.push_back(MakeDetection(&rng, core::KeypointLayoutId::kBody25, 0));
  frame.detections.push_back(MakeDetection(&rng, core::KeypointLayoutId::kNone, 0));
  return frame;
}

tracker::Frame3D MakeTracksFrame(std::uint32_t seed, bool pose) {
  std::mt19937 rng(seed);
  tracker::Frame3D frame;
  frame.frame = 500 + static_cast<FrameIndex>(seed);
  frame.utime = 1'700'000'100'000'000 + static_cast<Utime>(seed) * 40'000;
  const TrackId3D ids[] = {7, 3, 12, 5};
  const linking::TrackState states[] = {linking::TrackState::kConfirmed,
                                        linking::TrackState::kTentative,
                                        linking::TrackState::kLost,
                                        linking::TrackState::kConfirmed};
  const std::vector<CameraId> cameras[] = {{2, 0}, {1}, {4, 1, 4}, {0, 1, 2}};
  // Odd seeds make a stitched site's frame (issue 43): its zones, and which saw each track
  // (unsorted, with a duplicate: the encoder sorts them).
  const std::vector<int> zones[] = {{1, 0}, {2}, {0, 2, 0}, {}};
  if (seed % 2 == 1) frame.zones = {"zone1", "zone2", "dock"};
  for (std::size_t i = 0; i < 4; ++i) {
    tracker::Track3D t;
    t.id = ids[i];
    t.state = states[i];
    t.position = Vec3(FloatExact(&rng, -5.0, 5.0), FloatExact(&rng, -5.0, 5.0), 0.0);
    t.confidence = FloatExact(&rng, 0.0, 1.0);
    t.cameras = cameras[i];
    t.age_frames = static_cast<std::int64_t>(i) * 17;
    if (!frame.zones.empty()) t.zones = zones[i];
    if (pose) {
      const int n = core::GetKeypointLayout(core::KeypointLayoutId::kCoco17).num_joints();
      for (int j = 0; j < n; ++j) {
        if ((j + static_cast<int>(i)) % 6 == 5) {
          t.joints.emplace_back(std::nullopt);
        } else {
          t.joints.emplace_back(Vec3(FloatExact(&rng, -5.0, 5.0),
                                     FloatExact(&rng, -5.0, 5.0),
                                     FloatExact(&rng, 0.0, 2.0)));
        }
      }
      // The track's bone lengths (coco17: 19 bones), one not known yet.
      for (int b = 0; b < 19; ++b) {
        t.bone_lengths.push_back(b == 4 ? 0.0 : FloatExact(&rng, 0.05, 0.6));
      }
    }
    frame.tracks.push_back(std::move(t));
  }
  return frame;
}

mvtrack::camera_detections_t ToLcm(const core::CameraFrame& frame, int width, int height) {
  mvtrack::camera_detections_t msg;
  msg.utime = frame.utime;
  msg.frame = frame.frame;
  msg.camera_id = frame.camera_id;
  msg.image_width = width;
  msg.image_height = height;
  msg.num_detections = static_cast<std::int32_t>(frame.detections.size());
  for (const core::Detection2D& det : frame.detections) {
    mvtrack::detection_t d;
    d.x_min = static_cast<float>(det.box.x_min);
    d.y_min = static_cast<float>(det.box.y_min);
    d.x_max = static_cast<float>(det.box.x_max);
    d.y_max = static_cast<float>(det.box.y_max);
    d.score = static_cast<float>(det.score);
    d.keypoint_layout =
        det.layout == core::KeypointLayoutId::kNone ? "" : core::GetKeypointLayout(det.layout).name;
    d.num_keypoints = static_cast<std::int16_t>(det.keypoints.size());
    for (const core::Keypoint2D& kp : det.keypoints) {
      mvtrack::keypoint2d_t k;
      k.x = static_cast<float>(kp.position_px.x());
      k.y = static_cast<float>(kp.position_px.y());
      k.confidence = static_cast<float>(kp.confidence);
      d.keypoints.push_back(k);
    }
    d.embedding_model = "";
    d.num_embedding = static_cast<std::int16_t>(det.embedding.size());
    d.embedding = det.embedding;
    msg.detections.push_back(d);
  }
  return msg;
}

CameraDetectionsOffsets OffsetsOf(const mvtrack::camera_detections_t& msg) {
  // camera_detections_t: fingerprint(8) utime(8) frame(8) camera_id(4) image_width(4)
  // image_height(4) num_detections(4) detections[]. detection_t: 5 floats, string
  // keypoint_layout (int32 length incl. NUL + bytes), int16 num_keypoints, 12 bytes per
  // keypoint, string embedding_model, int16 num_embedding, 4 bytes per value.
  CameraDetectionsOffsets out;
  out.num_detections = 8 + 8 + 8 + 4 + 4 + 4;
  std::size_t pos = out.num_detections + 4;
  for (const mvtrack::detection_t& d : msg.detections) {
    DetectionOffsets o;
    o.start = pos;
    o.keypoint_layout = pos + 5 * 4;
    o.num_keypoints = o.keypoint_layout + 4 + d.keypoint_layout.size() + 1;
    o.embedding_model = o.num_keypoints + 2 + 12 * d.keypoints.size();
    o.num_embedding = o.embedding_model + 4 + d.embedding_model.size() + 1;
    pos = o.num_embedding + 2 + 4 * d.embedding.size();
    out.detections.push_back(o);
  }
  out.total = pos;
  return out;
}

Tracks3dOffsets OffsetsOf(const mvtrack::tracks3d_t& msg) {
  // tracks3d_t: fingerprint(8) utime(8) frame(8) publish_utime(8) latency_us(8) layer(1)
  // string keypoint_layout, int16 num_zones, strings zones[], int32 num_tracks, tracks[].
  // track3d_t: id(8) state(1) position(24) confidence(4) age_frames(4) missed_frames(4) int16
  // num_cameras, 4 bytes per camera, int16 num_joints, 29 bytes per joint (3 doubles, float,
  // boolean), int16 num_bones, 4 bytes per bone length, int16 num_zones, 2 bytes per zone.
  Tracks3dOffsets out;
  out.keypoint_layout = 8 + 4 * 8 + 1;
  out.num_zones = out.keypoint_layout + 4 + msg.keypoint_layout.size() + 1;
  out.num_tracks = out.num_zones + 2;
  for (const std::string& zone : msg.zones) out.num_tracks += 4 + zone.size() + 1;
  std::size_t pos = out.num_tracks + 4;
  for (const mvtrack::track3d_t& t : msg.tracks) {
    TrackOffsets o;
    o.start = pos;
    o.state = pos + 8;
    o.num_cameras = o.state + 1 + 24 + 4 + 4 + 4;
    o.num_joints = o.num_cameras + 2 + 4 * t.camera_ids.size();
    o.num_bones = o.num_joints + 2 + 29 * t.joints.size();
    o.num_zones = o.num_bones + 2 + 4 * t.bone_lengths.size();
    pos = o.num_zones + 2 + 2 * t.zones.size();
    out.tracks.push_back(o);
  }
  out.total = pos;
  return out;
}

void PutBigEndian(std::vector<std::uint8_t>* bytes,
                  std::size_t offset,
                  std::uint64_t value,
                  std::size_t width) {
  for (std::size_t i = 0; i < width; ++i) {
    (*bytes)[offset + i] = static_cast<std::uint8_t>(value >> (8 * (width - 1 - i)));
  }
}

std::string DiffCameraFrames(const core::CameraFrame& a, const core::CameraFrame& b) {
  if (a.utime != b.utime) return "utime";
  if (a.frame != b.frame) return "frame";
  if (a.camera_id != b.camera_id) return "camera_id";
  if (a.detections.size() != b.detections.size()) return "number of detections";
  for (std::size_t i = 0; i < a.detections.size(); ++i) {
    const core::Detection2D& da = a.detections[i];
    const core::Detection2D& db = b.detections[i];
    const double box_a[] = {da.box.x_min, da.box.y_min, da.box.x_max, da.box.y_max, da.score};
    const double box_b[] = {db.box.x_min, db.box.y_min, db.box.x_max, db.box.y_max, db.score};
    for (std::size_t f = 0; f < 5; ++f) {
      if (!SameBits(box_a[f], box_b[f])) {
        return BitsDiffer(
            Where("detection", i) + " box/score field " + std::to_string(f), box_a[f], box_b[f]);
      }
    }
    if (da.layout != db.layout) return Where("detection", i) + ".layout";
    if (da.keypoints.size() != db.keypoints.size()) {
      return Where("detection", i) + " number of keypoints";
    }
    for (std::size_t k = 0; k < da.keypoints.size(); ++k) {
      const core::Keypoint2D& ka = da.keypoints[k];
      const core::Keypoint2D& kb = db.keypoints[k];
      if (!SameBits(ka.position_px.x(), kb.position_px.x()) ||
          !SameBits(ka.position_px.y(), kb.position_px.y()) ||
          !SameBits(ka.confidence, kb.confidence)) {
        return Where(Where("detection", i) + ".keypoint", k);
      }
    }
    if (da.embedding.size() != db.embedding.size()) {
      return Where("detection", i) + " embedding size";
    }
    for (std::size_t k = 0; k < da.embedding.size(); ++k) {
      if (std::bit_cast<std::uint32_t>(da.embedding[k]) !=
          std::bit_cast<std::uint32_t>(db.embedding[k])) {
        return Where(Where("detection", i) + ".embedding", k);
      }
    }
  }
  return "";
}

std::string DiffFrames3D(const tracker::Frame3D& a, const tracker::Frame3D& b) {
  if (a.frame != b.frame) return "frame";
  if (a.utime != b.utime) return "utime";
  if (a.zones != b.zones) return "zones";
  if (a.tracks.size() != b.tracks.size()) return "number of tracks";
  for (std::size_t i = 0; i < a.tracks.size(); ++i) {
    const tracker::Track3D& ta = a.tracks[i];
    const tracker::Track3D& tb = b.tracks[i];
    if (ta.id != tb.id) return Where("track", i) + ".id";
    if (ta.state != tb.state) return Where("track", i) + ".state";
    for (int c = 0; c < 3; ++c) {
      if (!SameBits(ta.position[c], tb.position[c])) {
        return BitsDiffer(Where("track", i) + ".position", ta.position[c], tb.position[c]);
      }
    }
    if (!SameBits(ta.confidence, tb.confidence)) {
      return BitsDiffer(Where("track", i) + ".confidence", ta.confidence, tb.confidence);
    }
    if (ta.cameras != tb.cameras) return Where("track", i) + ".cameras";
    if (ta.age_frames != tb.age_frames) return Where("track", i) + ".age_frames";
    if (ta.zones != tb.zones) return Where("track", i) + ".zones";
    if (ta.joints.size() != tb.joints.size()) return Where("track", i) + " number of joints";
    for (std::size_t j = 0; j < ta.joints.size(); ++j) {
      if (ta.joints[j].has_value() != tb.joints[j].has_value()) {
        return Where(Where("track", i) + ".joint", j) + " validity";
      }
      if (!ta.joints[j]) continue;
      for (int c = 0; c < 3; ++c) {
        if (!SameBits((*ta.joints[j])[c], (*tb.joints[j])[c])) {
          return Where(Where("track", i) + ".joint", j);
        }
      }
    }
  }
  return "";
}

}  // namespace mvtrack::transport::testing
