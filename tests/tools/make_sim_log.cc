// Test helper of the mvtrack CLI tests: writes a small simulated multi-camera recording as the
// CLI consumes it.
//
//   make_sim_log OUT_DIR [--mode poses|boxes] [--frames N] [--people N] [--damaged]
//
// writes, from one seeded lib/sim scene (3 ring cameras, noisy detections with misses and false
// positives):
//   OUT_DIR/detections.lcmlog  camera_detections_t events in capture order (event timestamp =
//                              the camera-frame's utime); even cameras on the shared channel
//                              MVTRACK_DETECTIONS, odd ones on MVTRACK_DETECTIONS_<id>, so both
//                              conventions are exercised
//   OUT_DIR/calibration.yaml   the cameras (config::SaveCalibration)
//   OUT_DIR/gt.jsonl           the ground truth as canonical tracks JSONL: one line per frame,
//                              each person a track (id = person id, position = footprint,
//                              joints = the 17 COCO joints in pose mode, none in box mode)
//   OUT_DIR/reference.jsonl    what the single-threaded tracker::Tracker (default options, the
//                              mode above) outputs when fed the log's messages, decoded, in log
//                              order: the output `mvtrack replay` must reproduce byte for byte
// and with --damaged also
//   OUT_DIR/damaged.lcmlog     the same recording with injected damage: events on foreign
//                              channels, messages with a wrong fingerprint, truncated messages,
//                              a message whose camera id contradicts its channel, camera-frames
//                              of a camera missing from the calibration, and a final event cut
//                              short (the log ends inside an event)
//   OUT_DIR/damage.txt         what was injected, one "key=value" per line, for the test script
//                              to compare with what `mvtrack replay` reports.
//
// Exit status 0 on success, 1 on failure, 2 on usage errors.

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/calibration.h"
#include "core/keypoint_layout.h"
#include "geometry/camera_rig.h"
#include "sim/synthetic_scene.h"
#include "tracker/tracker.h"
#include "tracker/types.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"
#include "transport/tracks_jsonl.h"

namespace {

using mvtrack::CameraId;
namespace transport = mvtrack::transport;

// Camera-frames of the damaged log replaced or accompanied by damage, by frame index modulus.
constexpr std::int64_t kForeignEvery = 20;        // a foreign event after camera 0's message
constexpr std::int64_t kFingerprintFrame = 31;    // camera 1's message: first byte flipped
constexpr std::int64_t kTruncatedFrame = 57;      // camera 2's message: cut to half its size
constexpr std::int64_t kMismatchFrame = 83;       // camera 1's message on camera 2's channel
constexpr std::int64_t kUnknownCameraEvery = 50;  // an extra camera-frame of camera 99
constexpr CameraId kUnknownCamera = 99;

std::string Channel(CameraId camera) {
  return camera % 2 == 0 ? std::string(transport::kDetectionsChannel)
                         : transport::DetectionsChannelForCamera(camera);
}

class Writer {
 public:
  explicit Writer(const std::string& path) {
    std::string why;
    log_ = transport::LogWriter::Open(path, &why);
    if (!log_) throw std::runtime_error(why);
  }
  void Write(const std::string& channel, std::int64_t t, const std::vector<std::uint8_t>& data) {
    std::string why;
    if (!log_->Write(channel, t, data, &why)) throw std::runtime_error(why);
  }
  void Close() {
    std::string why;
    if (!log_->Flush(&why)) throw std::runtime_error(why);
    log_.reset();
  }

 private:
  std::unique_ptr<transport::LogWriter> log_;
};

int Run(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: make_sim_log OUT_DIR [--mode poses|boxes] [--frames N] [--people N] "
                 "[--damaged]\n";
    return 2;
  }
  const std::filesystem::path out = argv[1];
  bool poses = true;
  bool damaged = false;
  mvtrack::sim::SceneOptions so;
  so.seed = 7;
  so.num_cameras = 3;
  so.num_people = 3;
  so.num_frames = 240;
  so.pixel_noise_px = 1.0;
  so.miss_rate = 0.05;
  so.false_positives_per_frame = 0.2;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--damaged") {
      damaged = true;
    } else if ((arg == "--mode" || arg == "--frames" || arg == "--people") && i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--mode") {
        if (value != "poses" && value != "boxes") {
          std::cerr << "make_sim_log: --mode must be poses or boxes\n";
          return 2;
        }
        poses = value == "poses";
      } else if (arg == "--frames") {
        so.num_frames = std::atoi(value.c_str());
      } else {
        so.num_people = std::atoi(value.c_str());
      }
    } else {
      std::cerr << "make_sim_log: unknown argument '" << arg << "'\n";
      return 2;
    }
  }
  so.poses = poses;
  std::string why;
  if (!so.Validate(&why)) {
    std::cerr << "make_sim_log: " << why << "\n";
    return 2;
  }
  std::filesystem::create_directories(out);
  const mvtrack::sim::Scene scene = mvtrack::sim::GenerateScene(so);

  mvtrack::config::SaveCalibration((out / "calibration.yaml").string(), scene.cameras);

  // Ground truth.
  const mvtrack::core::KeypointLayoutId layout =
      poses ? mvtrack::core::KeypointLayoutId::kCoco17 : mvtrack::core::KeypointLayoutId::kNone;
  {
    std::ofstream gt(out / "gt.jsonl", std::ios::binary | std::ios::trunc);
    for (const mvtrack::sim::FrameTruth& t : scene.truth) {
      mvtrack::tracker::Frame3D f;
      f.frame = t.frame;
      f.utime = t.utime;
      for (const mvtrack::sim::PersonTruth& p : t.people) {
        mvtrack::tracker::Track3D track;
        track.id = p.id;
        track.position = p.footprint_m;
        if (poses) {
          for (const mvtrack::Vec3& j : p.joints_m) track.joints.emplace_back(j);
        }
        f.tracks.push_back(std::move(track));
      }
      gt << transport::TracksJsonLine(f, layout);
    }
    gt.close();
    if (!gt) throw std::runtime_error((out / "gt.jsonl").string() + ": write error");
  }

  // The clean log, and the reference output of tracker::Tracker on the decoded messages.
  {
    mvtrack::tracker::TrackerOptions to;
    to.mode = poses ? mvtrack::tracker::InputMode::kPoses : mvtrack::tracker::InputMode::kBoxes;
    std::unique_ptr<mvtrack::tracker::Tracker> tracker =
        mvtrack::tracker::Tracker::Create(mvtrack::geometry::CameraRig(scene.cameras), to, &why);
    if (!tracker) throw std::runtime_error("tracker: " + why);
    std::ofstream reference(out / "reference.jsonl", std::ios::binary | std::ios::trunc);
    auto emit = [&](const std::vector<mvtrack::tracker::Frame3D>& frames) {
      for (const mvtrack::tracker::Frame3D& f : frames) {
        reference << transport::TracksJsonLine(f, layout);
      }
    };
    Writer log((out / "detections.lcmlog").string());
    for (const auto& cams : scene.detections) {
      for (const mvtrack::core::CameraFrame& cf : cams) {
        const std::vector<std::uint8_t> bytes =
            transport::EncodeCameraDetections(cf, so.image_width_px, so.image_height_px);
        log.Write(Channel(cf.camera_id), cf.utime, bytes);
        const transport::DecodeResult decoded =
            transport::DecodeCameraDetections(bytes.data(), bytes.size());
        if (!decoded.ok())
          throw std::runtime_error("own message does not decode: " + decoded.reason);
        emit(tracker->Add(decoded.frame).finalized);
      }
    }
    emit(tracker->Flush());
    log.Close();
    reference.close();
    if (!reference) throw std::runtime_error((out / "reference.jsonl").string() + ": write error");
  }
  if (!damaged) return 0;

  // The damaged log.
  std::map<std::string, std::int64_t> injected;
  const std::string damaged_path = (out / "damaged.lcmlog").string();
  {
    Writer log(damaged_path);
    for (const auto& cams : scene.detections) {
      for (const mvtrack::core::CameraFrame& cf : cams) {
        std::vector<std::uint8_t> bytes =
            transport::EncodeCameraDetections(cf, so.image_width_px, so.image_height_px);
        std::string channel = Channel(cf.camera_id);
        if (cf.frame == kFingerprintFrame && cf.camera_id == 1) {
          bytes[0] ^= 0xFF;
          ++injected["bad_fingerprint"];
        } else if (cf.frame == kTruncatedFrame && cf.camera_id == 2) {
          bytes.resize(bytes.size() / 2);
          ++injected["truncated"];
        } else if (cf.frame == kMismatchFrame && cf.camera_id == 1) {
          channel = transport::DetectionsChannelForCamera(2);
          ++injected["channel_mismatch"];
        }
        log.Write(channel, cf.utime, bytes);
        if (cf.camera_id == 0 && cf.frame % kForeignEvery == 0) {
          const std::vector<std::uint8_t> junk = {1, 2, 3, 4, 5, 6, 7, 8, 9};
          log.Write(cf.frame % (2 * kForeignEvery) == 0 ? "OTHER_SENSOR" : "MVTRACK_STATUS",
                    cf.utime,
                    junk);
          ++injected["foreign"];
        }
        if (cf.camera_id == 0 && cf.frame % kUnknownCameraEvery == 0) {
          mvtrack::core::CameraFrame stranger = cf;
          stranger.camera_id = kUnknownCamera;
          log.Write(
              transport::kDetectionsChannel,
              cf.utime,
              transport::EncodeCameraDetections(stranger, so.image_width_px, so.image_height_px));
          ++injected["unknown_camera"];
        }
      }
    }
    // A last event that the end of the file cuts short (an interrupted recorder).
    const mvtrack::core::CameraFrame& last = scene.detections.back().front();
    log.Write(Channel(last.camera_id),
              last.utime,
              transport::EncodeCameraDetections(last, so.image_width_px, so.image_height_px));
    log.Close();
    const std::uintmax_t size = std::filesystem::file_size(damaged_path);
    std::filesystem::resize_file(damaged_path, size - 5);
  }
  std::ofstream damage(out / "damage.txt", std::ios::trunc);
  for (const auto& [key, count] : injected) damage << key << "=" << count << "\n";
  damage << "log_end=truncated\n";
  damage.close();
  if (!damage) throw std::runtime_error((out / "damage.txt").string() + ": write error");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "make_sim_log: " << e.what() << "\n";
    return 1;
  }
}
