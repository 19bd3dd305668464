#include "lcmtypes/sample_messages.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <utility>

namespace mvtrack::lcmtypes_test {
namespace {

// Seeded sample values. Every builder owns one, so samples do not depend on call order.
class Gen {
 public:
  explicit Gen(std::uint32_t seed) : rng_(seed) {}
  float Uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }
  double UniformD(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  int UniformInt(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  std::int64_t UniformInt64(std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_);
  }

 private:
  std::mt19937 rng_;
};

constexpr std::int64_t kBaseUtime = 1'700'000'000'000'000;  // 2023-11-14, µs since the epoch

std::string RealText(double value) {
  char buf[24];
  std::snprintf(buf,
                sizeof(buf),
                "0x%016llx",
                static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(value)));
  return buf;
}

std::string StringText(const std::string& value) {
  std::string out = "\"";
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte > 0x7e || c == '"' || c == '\\') {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", static_cast<unsigned>(byte));
      out += buf;
    } else {
      out += c;
    }
  }
  out += '"';
  return out;
}

// Collects one struct's fields keyed by name, so Render() emits them sorted as the format needs.
class Fields {
 public:
  explicit Fields(const std::string& prefix) : prefix_(prefix) {}

  void Int(const std::string& name, std::int64_t value) { Line(name, std::to_string(value)); }
  void Bool(const std::string& name, bool value) { Line(name, value ? "true" : "false"); }
  void Real(const std::string& name, double value) { Line(name, RealText(value)); }
  void Str(const std::string& name, const std::string& value) { Line(name, StringText(value)); }

  template <typename T>
  void IntArray(const std::string& name, const T* data, std::size_t size) {
    std::string block;
    for (std::size_t i = 0; i < size; ++i) {
      block += Path(name, i) + "=" + std::to_string(static_cast<std::int64_t>(data[i])) + "\n";
    }
    blocks_[name] = block;
  }
  template <typename T>
  void RealArray(const std::string& name, const T* data, std::size_t size) {
    std::string block;
    for (std::size_t i = 0; i < size; ++i) {
      block += Path(name, i) + "=" + RealText(static_cast<double>(data[i])) + "\n";
    }
    blocks_[name] = block;
  }
  void StrArray(const std::string& name, const std::vector<std::string>& values) {
    std::string block;
    for (std::size_t i = 0; i < values.size(); ++i) {
      block += Path(name, i) + "=" + StringText(values[i]) + "\n";
    }
    blocks_[name] = block;
  }
  template <typename Msg>
  void StructArray(const std::string& name, const std::vector<Msg>& elements) {
    std::string block;
    for (std::size_t i = 0; i < elements.size(); ++i) {
      block += Dump(elements[i], Path(name, i) + ".");
    }
    blocks_[name] = block;
  }

  std::string Render() const {
    std::string out;
    for (const auto& [name, block] : blocks_) out += block;
    return out;
  }

 private:
  std::string Path(const std::string& name, std::size_t index) const {
    return prefix_ + name + "[" + std::to_string(index) + "]";
  }
  void Line(const std::string& name, const std::string& value) {
    blocks_[name] = prefix_ + name + "=" + value + "\n";
  }

  std::string prefix_;
  std::map<std::string, std::string> blocks_;
};

template <typename Msg>
SampleEvent MakeEvent(const std::string& channel, const Msg& msg) {
  SampleEvent event;
  event.channel = channel;
  event.type_name = Msg::getTypeName();
  event.fingerprint = Msg::getHash();
  event.bytes = Encode(msg);
  event.dump = Dump(msg);
  return event;
}

}  // namespace

keypoint2d_t MakeKeypoint2d(std::uint32_t seed) {
  Gen gen(seed);
  keypoint2d_t kp;
  kp.x = gen.Uniform(0.0f, 1920.0f);
  kp.y = gen.Uniform(0.0f, 1080.0f);
  kp.confidence = gen.Uniform(0.05f, 1.0f);
  return kp;
}

detection_t MakeDetection(std::uint32_t seed, DetectionKind kind) {
  Gen gen(seed);
  detection_t det;
  const float width = gen.Uniform(40.0f, 250.0f);
  const float height = gen.Uniform(120.0f, 600.0f);
  // Boxes may stick out of the image on the left (negative x_min), as real detectors' do.
  det.x_min = gen.Uniform(-20.0f, 1920.0f - width);
  det.y_min = gen.Uniform(0.0f, 1080.0f - height);
  det.x_max = det.x_min + width;
  det.y_max = det.y_min + height;
  det.score = gen.Uniform(0.3f, 1.0f);

  int num_keypoints = 0;
  det.keypoint_layout = "";
  if (kind == DetectionKind::kPoseAndEmbedding) {
    det.keypoint_layout = "coco17";
    num_keypoints = 17;
  } else if (kind == DetectionKind::kPoseOnly) {
    det.keypoint_layout = "body25";
    num_keypoints = 25;
  }
  det.num_keypoints = static_cast<std::int16_t>(num_keypoints);
  det.keypoints.resize(static_cast<std::size_t>(num_keypoints));
  for (int j = 0; j < num_keypoints; ++j) {
    keypoint2d_t& kp = det.keypoints[static_cast<std::size_t>(j)];
    if (j % 5 == 3) {  // undetected joint: confidence 0, position 0 by convention
      kp.x = 0.0f;
      kp.y = 0.0f;
      kp.confidence = 0.0f;
    } else {
      kp.x = gen.Uniform(det.x_min, det.x_max);
      kp.y = gen.Uniform(det.y_min, det.y_max);
      kp.confidence = gen.Uniform(0.05f, 1.0f);
    }
  }

  det.embedding_model = "";
  det.num_embedding = 0;
  if (kind == DetectionKind::kPoseAndEmbedding) {
    det.embedding_model = "osnet_x0_25@1";
    det.embedding.resize(64);
    double norm2 = 0.0;
    for (float& v : det.embedding) {
      v = gen.Uniform(-1.0f, 1.0f);
      norm2 += static_cast<double>(v) * static_cast<double>(v);
    }
    const double inv_norm = 1.0 / std::sqrt(norm2);
    for (float& v : det.embedding) v = static_cast<float>(static_cast<double>(v) * inv_norm);
    det.num_embedding = static_cast<std::int16_t>(det.embedding.size());
  }
  return det;
}

camera_detections_t MakeCameraDetections(std::uint32_t seed,
                                         std::int32_t camera_id,
                                         int num_detections) {
  Gen gen(seed);
  camera_detections_t msg;
  msg.frame = 1000 + gen.UniformInt(0, 500);
  msg.utime = kBaseUtime + msg.frame * 40'000;  // 25 Hz capture
  msg.camera_id = camera_id;
  msg.image_width = 1920;
  msg.image_height = 1080;
  msg.num_detections = num_detections;
  constexpr DetectionKind kKinds[] = {
      DetectionKind::kPoseAndEmbedding, DetectionKind::kPoseOnly, DetectionKind::kBoxOnly};
  for (int i = 0; i < num_detections; ++i) {
    msg.detections.push_back(
        MakeDetection(seed * 31u + static_cast<std::uint32_t>(i), kKinds[i % 3]));
  }
  return msg;
}

joint3d_t MakeJoint3d(std::uint32_t seed, bool valid) {
  Gen gen(seed);
  joint3d_t joint;
  if (valid) {
    joint.position[0] = gen.UniformD(-5.0, 5.0);
    joint.position[1] = gen.UniformD(-5.0, 5.0);
    joint.position[2] = gen.UniformD(0.0, 1.9);
    joint.confidence = gen.Uniform(0.2f, 1.0f);
  } else {
    joint.position[0] = joint.position[1] = joint.position[2] = 0.0;
    joint.confidence = 0.0f;
  }
  joint.valid = static_cast<std::int8_t>(valid ? 1 : 0);
  return joint;
}

track3d_t MakeTrack3d(std::uint32_t seed, std::int64_t id, std::int8_t state, int num_joints) {
  Gen gen(seed);
  track3d_t track;
  track.id = id;
  track.state = state;
  track.position[0] = gen.UniformD(-5.0, 5.0);
  track.position[1] = gen.UniformD(-5.0, 5.0);
  track.position[2] = gen.UniformD(-0.05, 0.05);
  track.confidence = gen.Uniform(0.3f, 1.0f);
  track.age_frames = gen.UniformInt(1, 5000);
  track.missed_frames = state == track3d_t::STATE_LOST ? gen.UniformInt(1, 10) : 0;
  // A sorted subset of cameras {1, 2, 3, 7}.
  constexpr std::int32_t kCameras[] = {1, 2, 3, 7};
  const int mask = state == track3d_t::STATE_LOST ? 0 : gen.UniformInt(1, 15);
  for (int c = 0; c < 4; ++c) {
    if (mask & (1 << c)) track.camera_ids.push_back(kCameras[c]);
  }
  track.num_cameras = static_cast<std::int16_t>(track.camera_ids.size());
  track.num_joints = static_cast<std::int16_t>(num_joints);
  for (int j = 0; j < num_joints; ++j) {
    const bool valid = state != track3d_t::STATE_LOST && j % 6 != 5;
    track.joints.push_back(MakeJoint3d(seed * 131u + static_cast<std::uint32_t>(j), valid));
  }
  // With joints (coco17: 19 bones), the track's bone lengths; 0 = not known yet.
  if (num_joints > 0) {
    for (int b = 0; b < 19; ++b) {
      track.bone_lengths.push_back(b % 7 == 6 ? 0.0f : gen.Uniform(0.05f, 0.6f));
    }
  }
  track.num_bones = static_cast<std::int16_t>(track.bone_lengths.size());
  track.num_zones = 0;  // MakeTracks3d sets them in a stitched site's message
  return track;
}

tracks3d_t MakeTracks3d(std::uint32_t seed, int num_tracks, bool with_joints) {
  Gen gen(seed);
  tracks3d_t msg;
  msg.frame = 1000 + gen.UniformInt(0, 500);
  msg.utime = kBaseUtime + msg.frame * 40'000;
  msg.publish_utime = msg.utime + 350'000 + gen.UniformInt64(0, 99'999);
  msg.latency_us = gen.UniformInt64(1'000, 60'000);
  msg.layer = seed % 2 == 0 ? tracks3d_t::LAYER_FINAL : tracks3d_t::LAYER_PROVISIONAL;
  msg.keypoint_layout = with_joints ? "coco17" : "";
  // Every third message is a stitched site's (issue 43): its zones, and which saw each track.
  if (seed % 3 == 0) msg.zones = {"zone1", "zone2", "west_hall"};
  msg.num_zones = static_cast<std::int16_t>(msg.zones.size());
  msg.num_tracks = num_tracks;
  constexpr std::int8_t kStates[] = {
      track3d_t::STATE_CONFIRMED, track3d_t::STATE_LOST, track3d_t::STATE_TENTATIVE};
  for (int i = 0; i < num_tracks; ++i) {
    msg.tracks.push_back(MakeTrack3d(seed * 17u + static_cast<std::uint32_t>(i),
                                     /*id=*/i + 1,
                                     kStates[i % 3],
                                     with_joints ? 17 : 0));
    if (!msg.zones.empty()) {
      track3d_t& t = msg.tracks.back();
      t.zones = i % 2 == 0 ? std::vector<std::int16_t>{0, 1} : std::vector<std::int16_t>{2};
      t.num_zones = static_cast<std::int16_t>(t.zones.size());
    }
  }
  return msg;
}

camera_status_t MakeCameraStatus(std::uint32_t seed, std::int32_t camera_id) {
  Gen gen(seed);
  camera_status_t status;
  status.camera_id = camera_id;
  status.flags = camera_status_t::FLAG_LATE | camera_status_t::FLAG_DROPPING;
  status.rate_hz = gen.Uniform(20.0f, 30.0f);
  status.last_utime = kBaseUtime + gen.UniformInt64(0, 60'000'000);
  status.last_receive_utime = status.last_utime + gen.UniformInt64(5'000, 20'000);
  status.received = (std::int64_t{1} << 33) + gen.UniformInt64(0, 1'000'000);  // > 2^32
  status.late = gen.UniformInt64(0, 1000);
  status.dropped = gen.UniformInt64(0, 1000);
  status.rejected = gen.UniformInt64(0, 1000);
  status.decode_errors = gen.UniformInt64(0, 10);
  status.lost = gen.UniformInt64(0, 100);
  status.clock_offset_us = gen.UniformInt64(-300'000, 300'000);
  status.embeddings_dropped = gen.UniformInt64(0, 100);
  status.queue_capacity = 64;
  status.queue_depth = gen.UniformInt(0, 64);
  return status;
}

tracker_status_t MakeTrackerStatus(std::uint32_t seed, int num_cameras) {
  Gen gen(seed);
  tracker_status_t status;
  status.utime = kBaseUtime + gen.UniformInt64(0, 60'000'000);
  status.period_us = 1'000'000;
  status.uptime_us = gen.UniformInt64(1'000'000, 100'000'000'000);
  status.instance_id = "9f2c4e61b07ad358";
  status.start_utime = status.utime - status.uptime_us;
  status.sequence = gen.UniformInt64(0, 100'000);
  status.version = "0.1.0+g1a2b3c4";
  status.config_hash = "5f4dcc3b5aa765d61d8327deb882cf99";
  status.flags = tracker_status_t::FLAG_INPUT_LOSS | tracker_status_t::FLAG_LATENCY_HIGH;
  status.last_frame = 1000 + gen.UniformInt(0, 500);
  status.active_tracks = gen.UniformInt(0, 20);
  status.confirmed_tracks = gen.UniformInt(0, status.active_tracks);
  status.num_latency_samples = 25;
  status.latency_p50_us = gen.UniformInt64(5'000, 20'000);
  status.latency_p99_us = status.latency_p50_us + gen.UniformInt64(0, 30'000);
  status.latency_max_us = status.latency_p99_us + gen.UniformInt64(0, 30'000);
  status.windows_processed = gen.UniformInt64(0, 1'000'000);
  status.jobs_failed = gen.UniformInt64(0, 10);
  status.executor_queue_depth = gen.UniformInt(0, 8);
  status.kernel_drops = gen.UniformInt64(-1, 50);
  status.embeddings_used = gen.UniformInt64(0, 1'000'000);
  status.embeddings_dropped = gen.UniformInt64(0, 1000);
  status.tracks_revived = gen.UniformInt64(0, 50);
  status.gallery_bytes = gen.UniformInt64(0, 10'000'000);
  status.num_cameras = static_cast<std::int16_t>(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    status.cameras.push_back(MakeCameraStatus(seed * 7u + static_cast<std::uint32_t>(c), c + 1));
  }
  return status;
}

zone_status_t MakeZoneStatus(std::uint32_t seed, const std::string& name, bool stale) {
  Gen gen(seed);
  zone_status_t z;
  z.name = name;
  z.channel = "MVTRACK_TRACKS_" + name;
  z.flags = stale ? zone_status_t::FLAG_STALE : 0;
  z.frames = gen.UniformInt64(100, 100'000);
  z.late = gen.UniformInt64(0, 5);
  z.decode_errors = gen.UniformInt64(0, 3);
  z.other_layer = gen.UniformInt64(0, 3);
  z.last_utime = kBaseUtime + gen.UniformInt64(0, 60'000'000);
  z.last_receive_utime = z.last_utime + gen.UniformInt64(100'000, 900'000);
  z.latency_us = gen.UniformInt64(100'000, 900'000);
  z.tracks = gen.UniformInt(0, 50);
  z.daemon_health = stale ? zone_status_t::HEALTH_UNKNOWN : zone_status_t::HEALTH_WARNING;
  z.daemon_reasons = stale ? "" : "WARNING: camera 2 STALE";
  z.daemon_instance_id = stale ? "" : "0123456789abcdef";
  return z;
}

site_status_t MakeSiteStatus(std::uint32_t seed, int num_zones) {
  Gen gen(seed);
  site_status_t s;
  s.utime = kBaseUtime + gen.UniformInt64(0, 60'000'000);
  s.period_us = 1'000'000;
  s.uptime_us = gen.UniformInt64(1'000'000, 100'000'000'000);
  s.instance_id = "a1b2c3d4e5f60718";
  s.start_utime = s.utime - s.uptime_us;
  s.sequence = gen.UniformInt64(0, 100'000);
  s.version = "0.6.0+g1a2b3c4";
  s.flags = site_status_t::FLAG_ZONE_MISSING | site_status_t::FLAG_ZONE_DEGRADED;
  s.last_frame = 1000 + gen.UniformInt(0, 500);
  s.site_frames = s.last_frame + 1;
  s.active_tracks = gen.UniformInt(0, 200);
  s.global_ids = gen.UniformInt64(0, 100'000);
  s.splits = gen.UniformInt64(0, 100);
  s.merges = gen.UniformInt64(0, 100);
  s.num_wait_samples = 30;
  s.wait_p50_us = gen.UniformInt64(0, 5'000);
  s.wait_p99_us = s.wait_p50_us + gen.UniformInt64(0, 5'000);
  s.wait_max_us = s.wait_p99_us + gen.UniformInt64(0, 5'000);
  s.num_zones = static_cast<std::int16_t>(num_zones);
  for (int z = 0; z < num_zones; ++z) {
    s.zones.push_back(MakeZoneStatus(
        seed * 5u + static_cast<std::uint32_t>(z), "ZONE" + std::to_string(z + 1), z == 1));
  }
  return s;
}

std::string Dump(const keypoint2d_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Real("x", msg.x);
  f.Real("y", msg.y);
  f.Real("confidence", msg.confidence);
  return f.Render();
}

std::string Dump(const detection_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Real("x_min", msg.x_min);
  f.Real("y_min", msg.y_min);
  f.Real("x_max", msg.x_max);
  f.Real("y_max", msg.y_max);
  f.Real("score", msg.score);
  f.Str("keypoint_layout", msg.keypoint_layout);
  f.Int("num_keypoints", msg.num_keypoints);
  f.StructArray("keypoints", msg.keypoints);
  f.Str("embedding_model", msg.embedding_model);
  f.Int("num_embedding", msg.num_embedding);
  f.RealArray("embedding", msg.embedding.data(), msg.embedding.size());
  return f.Render();
}

std::string Dump(const camera_detections_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("utime", msg.utime);
  f.Int("frame", msg.frame);
  f.Int("camera_id", msg.camera_id);
  f.Int("image_width", msg.image_width);
  f.Int("image_height", msg.image_height);
  f.Int("num_detections", msg.num_detections);
  f.StructArray("detections", msg.detections);
  return f.Render();
}

std::string Dump(const joint3d_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.RealArray("position", msg.position, 3);
  f.Real("confidence", msg.confidence);
  f.Bool("valid", msg.valid != 0);
  return f.Render();
}

std::string Dump(const track3d_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("id", msg.id);
  f.Int("state", msg.state);
  f.RealArray("position", msg.position, 3);
  f.Real("confidence", msg.confidence);
  f.Int("age_frames", msg.age_frames);
  f.Int("missed_frames", msg.missed_frames);
  f.Int("num_cameras", msg.num_cameras);
  f.IntArray("camera_ids", msg.camera_ids.data(), msg.camera_ids.size());
  f.Int("num_joints", msg.num_joints);
  f.StructArray("joints", msg.joints);
  f.Int("num_bones", msg.num_bones);
  f.RealArray("bone_lengths", msg.bone_lengths.data(), msg.bone_lengths.size());
  f.Int("num_zones", msg.num_zones);
  f.IntArray("zones", msg.zones.data(), msg.zones.size());
  return f.Render();
}

std::string Dump(const tracks3d_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("utime", msg.utime);
  f.Int("frame", msg.frame);
  f.Int("publish_utime", msg.publish_utime);
  f.Int("latency_us", msg.latency_us);
  f.Int("layer", msg.layer);
  f.Str("keypoint_layout", msg.keypoint_layout);
  f.Int("num_zones", msg.num_zones);
  f.StrArray("zones", msg.zones);
  f.Int("num_tracks", msg.num_tracks);
  f.StructArray("tracks", msg.tracks);
  return f.Render();
}

std::string Dump(const camera_status_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("camera_id", msg.camera_id);
  f.Int("flags", msg.flags);
  f.Real("rate_hz", msg.rate_hz);
  f.Int("last_utime", msg.last_utime);
  f.Int("last_receive_utime", msg.last_receive_utime);
  f.Int("received", msg.received);
  f.Int("late", msg.late);
  f.Int("dropped", msg.dropped);
  f.Int("rejected", msg.rejected);
  f.Int("decode_errors", msg.decode_errors);
  f.Int("lost", msg.lost);
  f.Int("clock_offset_us", msg.clock_offset_us);
  f.Int("embeddings_dropped", msg.embeddings_dropped);
  f.Int("queue_depth", msg.queue_depth);
  f.Int("queue_capacity", msg.queue_capacity);
  return f.Render();
}

std::string Dump(const tracker_status_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("utime", msg.utime);
  f.Int("period_us", msg.period_us);
  f.Int("uptime_us", msg.uptime_us);
  f.Str("instance_id", msg.instance_id);
  f.Int("start_utime", msg.start_utime);
  f.Int("sequence", msg.sequence);
  f.Str("version", msg.version);
  f.Str("config_hash", msg.config_hash);
  f.Int("flags", msg.flags);
  f.Int("last_frame", msg.last_frame);
  f.Int("active_tracks", msg.active_tracks);
  f.Int("confirmed_tracks", msg.confirmed_tracks);
  f.Int("num_latency_samples", msg.num_latency_samples);
  f.Int("latency_p50_us", msg.latency_p50_us);
  f.Int("latency_p99_us", msg.latency_p99_us);
  f.Int("latency_max_us", msg.latency_max_us);
  f.Int("windows_processed", msg.windows_processed);
  f.Int("jobs_failed", msg.jobs_failed);
  f.Int("executor_queue_depth", msg.executor_queue_depth);
  f.Int("kernel_drops", msg.kernel_drops);
  f.Int("embeddings_used", msg.embeddings_used);
  f.Int("embeddings_dropped", msg.embeddings_dropped);
  f.Int("tracks_revived", msg.tracks_revived);
  f.Int("gallery_bytes", msg.gallery_bytes);
  f.Int("num_cameras", msg.num_cameras);
  f.StructArray("cameras", msg.cameras);
  return f.Render();
}

std::string Dump(const zone_status_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Str("name", msg.name);
  f.Str("channel", msg.channel);
  f.Int("flags", msg.flags);
  f.Int("frames", msg.frames);
  f.Int("late", msg.late);
  f.Int("decode_errors", msg.decode_errors);
  f.Int("other_layer", msg.other_layer);
  f.Int("last_utime", msg.last_utime);
  f.Int("last_receive_utime", msg.last_receive_utime);
  f.Int("latency_us", msg.latency_us);
  f.Int("tracks", msg.tracks);
  f.Int("daemon_health", msg.daemon_health);
  f.Str("daemon_reasons", msg.daemon_reasons);
  f.Str("daemon_instance_id", msg.daemon_instance_id);
  return f.Render();
}

std::string Dump(const site_status_t& msg, const std::string& prefix) {
  Fields f(prefix);
  f.Int("utime", msg.utime);
  f.Int("period_us", msg.period_us);
  f.Int("uptime_us", msg.uptime_us);
  f.Str("instance_id", msg.instance_id);
  f.Int("start_utime", msg.start_utime);
  f.Int("sequence", msg.sequence);
  f.Str("version", msg.version);
  f.Int("flags", msg.flags);
  f.Int("last_frame", msg.last_frame);
  f.Int("site_frames", msg.site_frames);
  f.Int("active_tracks", msg.active_tracks);
  f.Int("global_ids", msg.global_ids);
  f.Int("splits", msg.splits);
  f.Int("merges", msg.merges);
  f.Int("num_wait_samples", msg.num_wait_samples);
  f.Int("wait_p50_us", msg.wait_p50_us);
  f.Int("wait_p99_us", msg.wait_p99_us);
  f.Int("wait_max_us", msg.wait_max_us);
  f.Int("num_zones", msg.num_zones);
  f.StructArray("zones", msg.zones);
  return f.Render();
}

std::vector<SampleEvent> MakeSampleEvents() {
  std::vector<SampleEvent> events;
  // A tracker that has not published yet: no tracks, last_frame -1, all cameras silent.
  tracker_status_t fresh = MakeTrackerStatus(/*seed=*/5, /*num_cameras=*/2);
  fresh.last_frame = -1;
  fresh.active_tracks = 0;
  fresh.confirmed_tracks = 0;
  fresh.num_latency_samples = 0;
  fresh.latency_p50_us = fresh.latency_p99_us = fresh.latency_max_us = 0;
  fresh.flags = tracker_status_t::FLAG_CAMERA_MISSING;
  fresh.embeddings_used = fresh.embeddings_dropped = fresh.tracks_revived = 0;
  fresh.gallery_bytes = 0;
  for (camera_status_t& camera : fresh.cameras) {
    camera.flags = camera_status_t::FLAG_NO_DATA | camera_status_t::FLAG_STALE;
    camera.rate_hz = 0.0f;
    camera.last_utime = camera.last_receive_utime = 0;
    camera.received = camera.late = camera.dropped = camera.rejected = camera.decode_errors = 0;
    camera.lost = camera.clock_offset_us = camera.embeddings_dropped = 0;
    camera.queue_depth = 0;
  }
  events.push_back(MakeEvent("TEST_TRACKER_STATUS", fresh));

  events.push_back(MakeEvent("TEST_DETECTIONS_CAM1", MakeCameraDetections(11, 1)));
  events.push_back(MakeEvent("TEST_DETECTIONS_CAM2", MakeCameraDetections(12, 2)));
  events.push_back(MakeEvent("TEST_DETECTIONS_CAM7", MakeCameraDetections(13, 7, 5)));
  events.push_back(MakeEvent("TEST_DETECTIONS_CAM3", MakeCameraDetections(14, 3, 0)));
  events.push_back(MakeEvent("TEST_TRACKS3D", MakeTracks3d(21, 4, /*with_joints=*/true)));
  events.push_back(MakeEvent("TEST_TRACKS3D", MakeTracks3d(22, 3, /*with_joints=*/false)));
  events.push_back(MakeEvent("TEST_TRACKS3D", MakeTracks3d(23, 0, /*with_joints=*/false)));
  events.push_back(MakeEvent("TEST_TRACKER_STATUS", MakeTrackerStatus(31, 4)));
  // The nested types on their own: lcm-spy must decode them too.
  events.push_back(MakeEvent("TEST_KEYPOINT2D", MakeKeypoint2d(41)));
  events.push_back(
      MakeEvent("TEST_DETECTION", MakeDetection(42, DetectionKind::kPoseAndEmbedding)));
  events.push_back(MakeEvent("TEST_JOINT3D", MakeJoint3d(43, /*valid=*/true)));
  events.push_back(
      MakeEvent("TEST_TRACK3D", MakeTrack3d(44, 9, track3d_t::STATE_ENDED, /*num_joints=*/17)));
  events.push_back(MakeEvent("TEST_CAMERA_STATUS", MakeCameraStatus(45, 7)));
  // A site's stitcher status (issue 43), and one zone of it on its own.
  events.push_back(MakeEvent("TEST_SITE_STATUS", MakeSiteStatus(51, 3)));
  events.push_back(MakeEvent("TEST_ZONE_STATUS", MakeZoneStatus(52, "ZONE9", false)));
  return events;
}

std::string DumpEvents(const std::vector<SampleEvent>& events) {
  std::string out;
  for (std::size_t i = 0; i < events.size(); ++i) {
    out += "event " + std::to_string(i) + " channel=" + events[i].channel +
           " type=" + events[i].type_name + "\n";
    out += events[i].dump;
  }
  return out;
}

}  // namespace mvtrack::lcmtypes_test
