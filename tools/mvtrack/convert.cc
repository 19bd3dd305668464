// mvtrack convert: turns the evaluation datasets (Shelf, Campus, CMU Panoptic, WILDTRACK, EPFL)
// and the generic JSON-lines detection format into mvtrack's inputs: a detections log that
// `mvtrack replay` tracks, the calibration, and, where the dataset has them, ground truth and a
// peer method's output as canonical tracks JSONL, plus a README.txt stating the protocol.

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "config/calibration.h"
#include "config/config_error.h"
#include "datasets/campus.h"
#include "datasets/corruption.h"
#include "datasets/dataset.h"
#include "datasets/epfl.h"
#include "datasets/panoptic.h"
#include "datasets/shelf.h"
#include "datasets/wildtrack.h"
#include "eval/sequence.h"
#include "formats/convert_output.h"
#include "formats/detection_importers.h"
#include "formats/jsonl_detections.h"
#include "formats/tracks_io.h"
#include "mvtrack/cli.h"
#include "transport/channels.h"
#include "transport/tracks_jsonl.h"

namespace mvtrack::cli {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kNumPanopticHdCameras = 31;
// Bad lines listed on stderr and in the README with --skip-bad-lines.
constexpr std::size_t kBadLinesShown = 5;

const char kConvertDescription[] =
    "Converts an evaluation dataset, or detections in the generic JSON-lines format, into\n"
    "mvtrack's inputs, written to --out DIR:\n"
    "  detections.lcmlog    one camera_detections_t event per camera and frame (also when\n"
    "                       empty), frames in increasing order, within a frame cameras in\n"
    "                       increasing id order; event timestamp = the camera-frame's utime;\n"
    "                       the same inputs always give a byte-identical log\n"
    "  calibration.yaml     the cameras (mvtrack.calibration/1)\n"
    "  ground_truth.jsonl   the ground-truth actors as tracks (canonical tracks JSONL), when\n"
    "                       the dataset has ground truth (Shelf, Campus, Panoptic,\n"
    "                       WILDTRACK, EPFL)\n"
    "  peer.jsonl           the published output of a peer method mapped to shelf14 (Shelf:\n"
    "                       4D Association, Campus: Cross-View Tracking)\n"
    "  ground_points.jsonl  WILDTRACK only: MVDeTr's merged ground points per frame\n"
    "  README.txt           what was converted, the protocol notes, the command line\n\n"
    "Exit status: 0 converted, 1 failure (missing dataset, bad input), 2 usage error.";

// The end of every format's --help.
const char kFormatTrailer[] =
    "Writes detections.lcmlog, calibration.yaml and README.txt (plus ground_truth.jsonl,\n"
    "peer.jsonl or ground_points.jsonl where the dataset has them) to --out DIR; see\n"
    "`mvtrack convert --help` for the file conventions.\n\n"
    "Exit status: 0 converted, 1 failure (missing dataset, bad input), 2 usage error.";

// ---------------------------------------------------------------------------------------------
// Options shared by the formats.

struct CommonSettings {
  std::string format;
  std::filesystem::path data_root;
  std::filesystem::path out;
  formats::ChannelMode channel = formats::ChannelMode::kShared;
  bool overwrite = false;
  bool quiet = false;
  std::string command_line;  // the command as typed, shell-quoted
};

void AddCommonOptions(Args* args, bool with_data) {
  args->Option("out",
               "output directory (created when missing; must be empty unless --overwrite) "
               "(required)");
  if (with_data) {
    args->Option("data",
                 "data root holding shelf/, campus/, panoptic/ and wildtrack/ ($MVTRACK_DATA, "
                 "else ../shared/data next to the repository)",
                 datasets::DefaultDataRoot().string());
  }
  args->Option("channel",
               "'shared': every camera on " + std::string(transport::kDetectionsChannel) +
                   "; 'per-camera': camera C on " + transport::kDetectionsChannelPrefix + "C",
               "shared")
      .Flag("overwrite", "replace the files of an earlier conversion in --out")
      .Flag("quiet", "no progress on stderr");
}

CommonSettings ParseCommon(const Args& args,
                           const std::string& format,
                           bool with_data,
                           const std::string& command_line) {
  CommonSettings c;
  c.format = format;
  if (!args.Has("out") || args.Get("out").empty()) throw UsageError("--out DIR is required");
  c.out = args.Get("out");
  if (with_data) {
    if (args.Get("data").empty()) throw UsageError("--data must not be empty");
    c.data_root = args.Get("data");
  }
  const std::string channel = args.Get("channel");
  if (channel == "shared") {
    c.channel = formats::ChannelMode::kShared;
  } else if (channel == "per-camera") {
    c.channel = formats::ChannelMode::kPerCamera;
  } else {
    throw UsageError("--channel must be 'shared' or 'per-camera', not '" + channel + "'");
  }
  c.overwrite = args.Has("overwrite");
  c.quiet = args.Has("quiet");
  c.command_line = command_line;
  return c;
}

void ShowProgress(const CommonSettings& c, const std::string& message) {
  if (!c.quiet) std::cerr << "mvtrack convert " << c.format << ": " << message << std::endl;
}

std::string FormatSeconds(double s) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.2f s", s);
  return buffer;
}

// `<root>/<folder>` when it is a directory, else an error naming the path and MVTRACK_DATA.
std::filesystem::path RequireDatasetDir(const CommonSettings& c, const std::string& folder) {
  std::filesystem::path dir = c.data_root / folder;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw std::runtime_error("dataset directory " + dir.string() + " not found (data root " +
                             c.data_root.string() +
                             "; pass --data DIR or set MVTRACK_DATA to the directory that holds "
                             "shelf/, campus/, panoptic/ and wildtrack/)");
  }
  return dir;
}

// ---------------------------------------------------------------------------------------------
// Corruption options (campus, panoptic).

void AddCorruptionOptions(Args* args, const datasets::CorruptionOptions& defaults) {
  auto num = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  const datasets::CorruptionOptions hard = datasets::HardCorruption(defaults);
  args->Option("corruption",
               "detector-error level: clean (the 2D poses unchanged), default, or hard (noise " +
                   num(hard.pixel_noise_px) + " px with Student-t tails, dropout " +
                   num(hard.joint_dropout) + ", miss rate " + num(hard.miss_rate) +
                   ", false positives " + num(hard.false_positives_per_frame) + " + " +
                   num(hard.near_false_positives_per_frame) +
                   " next to people, one camera blacked out for " + num(hard.blackout_seconds) +
                   " s in the test frames); the options below change the level's values",
               "default")
      .Flag("clean", "the same as --corruption clean")
      .Option("seed", "master seed of the corruption model", std::to_string(defaults.seed))
      .Option("noise-px", "keypoint noise: sigma in x and y, pixels", num(defaults.pixel_noise_px))
      .Option("noise-tail-dof",
              "0: Gaussian keypoint noise; N in 1-30: Student t with N degrees of freedom",
              std::to_string(defaults.noise_tail_dof))
      .Option(
          "dropout", "probability that a detected keypoint is lost", num(defaults.joint_dropout))
      .Option("miss-rate",
              "probability that a person is not detected in a view",
              num(defaults.miss_rate))
      .Option("false-positives",
              "mean ghost poses per camera and frame (Poisson)",
              num(defaults.false_positives_per_frame))
      .Option("near-false-positives",
              "mean partial ghost poses next to a real person per camera and frame (Poisson)",
              num(defaults.near_false_positives_per_frame))
      .Option("blackout-seconds",
              "one camera detects nothing for this long inside the test frames (0: never)",
              num(defaults.blackout_seconds));
}

datasets::CorruptionOptions ParseCorruption(const Args& args,
                                            const datasets::CorruptionOptions& defaults) {
  const char* const kNames[] = {"seed",
                                "noise-px",
                                "noise-tail-dof",
                                "dropout",
                                "miss-rate",
                                "false-positives",
                                "near-false-positives",
                                "blackout-seconds"};
  std::string level_name = args.Get("corruption");
  if (args.Has("clean")) {
    if (args.Has("corruption") && level_name != "clean") {
      throw UsageError("--clean contradicts --corruption " + level_name);
    }
    level_name = "clean";
  }
  const std::optional<datasets::CorruptionLevel> level =
      datasets::CorruptionLevelFromName(level_name);
  if (!level) {
    throw UsageError("--corruption must be clean, default or hard, not '" + level_name + "'");
  }
  datasets::CorruptionOptions o = datasets::CorruptionForLevel(*level, defaults);
  if (!o.enabled) {
    for (const char* name : kNames) {
      if (args.Has(name)) {
        throw UsageError(std::string("--corruption clean disables the corruption model; --") +
                         name + " cannot be combined with it");
      }
    }
    return o;
  }
  if (args.Has("seed")) {
    const std::int64_t seed = args.GetInt("seed");
    if (seed < 0) throw UsageError("--seed must be >= 0");
    o.seed = static_cast<std::uint64_t>(seed);
  }
  if (args.Has("noise-px")) o.pixel_noise_px = args.GetDouble("noise-px");
  if (args.Has("noise-tail-dof")) {
    const std::int64_t dof = args.GetInt("noise-tail-dof");
    if (dof < 0 || dof > 30) throw UsageError("--noise-tail-dof must be in 0-30");
    o.noise_tail_dof = static_cast<int>(dof);
  }
  if (args.Has("dropout")) o.joint_dropout = args.GetDouble("dropout");
  if (args.Has("miss-rate")) o.miss_rate = args.GetDouble("miss-rate");
  if (args.Has("false-positives")) o.false_positives_per_frame = args.GetDouble("false-positives");
  if (args.Has("near-false-positives")) {
    o.near_false_positives_per_frame = args.GetDouble("near-false-positives");
  }
  if (args.Has("blackout-seconds")) o.blackout_seconds = args.GetDouble("blackout-seconds");
  std::string why;
  if (!o.Validate(&why)) throw UsageError(why);
  return o;
}

// ---------------------------------------------------------------------------------------------
// Writing a loaded dataset.

struct DatasetJob {
  datasets::Dataset ds;
  std::filesystem::path source_dir;
  std::map<CameraId, std::string> camera_names;
  /// What was converted, one line each.
  std::vector<std::string> what;
  std::optional<datasets::PeerOutput> peer;
  std::optional<std::vector<datasets::WildtrackGroundFrame>> ground_points;
  double ground_cluster_radius_m = 0.0;
  /// The ground truth is floor positions without person ids (WILDTRACK): its README text and
  /// eval command differ, and `gt_area` is the annotated floor area (eval --area).
  bool gt_without_ids = false;
  std::string gt_area;
  /// Box-only ground truth with person ids (WILDTRACK's annotations): what a track of
  /// ground_truth.jsonl is, and the eval options its protocol adds (e.g. "--threshold 1.0").
  std::string gt_track_description;
  std::string eval_extra;
  /// The tracker mode and layout that match the detections.
  std::string replay_mode;
  std::string replay_layout;
  double load_seconds = 0.0;
};

std::string JoinIds(const std::vector<std::int64_t>& ids) {
  std::string s;
  for (std::int64_t id : ids) s += (s.empty() ? "" : ", ") + std::to_string(id);
  return s;
}

std::string PerCamera(const std::map<CameraId, std::int64_t>& counts) {
  std::string s;
  for (const auto& [camera, n] : counts) {
    s += (s.empty() ? "" : ", ") + std::to_string(camera) + ": " + std::to_string(n);
  }
  return s;
}

std::string LogDescription(const CommonSettings& c, const formats::DetectionsLogStats& st) {
  std::ostringstream os;
  os << "  " << formats::kConvertLogFile << " (" << st.bytes << " bytes): " << st.events
     << " events of mvtrack.camera_detections_t on "
     << (c.channel == formats::ChannelMode::kShared
             ? "the shared channel " + std::string(transport::kDetectionsChannel)
             : "the per-camera channels " + std::string(transport::kDetectionsChannelPrefix) +
                   "<camera id>")
     << ", " << st.frames << " frames";
  if (st.first_frame.has_value()) os << " (" << *st.first_frame << "-" << *st.last_frame << ")";
  os << ".\n      Events are ordered by frame, and within a frame by ascending camera id; the\n"
        "      event timestamp is the camera-frame's capture utime (the message's utime).\n"
        "      Events per camera: "
     << PerCamera(st.events_per_camera) << ".\n      Detections: " << st.detections
     << " (per camera: " << PerCamera(st.detections_per_camera) << "; by layout:";
  for (const auto& [layout, n] : st.detections_per_layout) os << " " << layout << " " << n;
  os << ").\n";
  return os.str();
}

void WriteDatasetJob(const CommonSettings& c, const DatasetJob& job) {
  const datasets::Dataset& ds = job.ds;
  const Clock::time_point start = Clock::now();
  formats::ConvertOutputDir out(c.out, c.overwrite);

  // Detections log.
  ShowProgress(c, "writing " + out.File(formats::kConvertLogFile).string());
  formats::DetectionsLogSink sink(&out, c.channel);
  for (const std::vector<core::CameraFrame>& frame : ds.detections) {
    std::vector<formats::CameraFrameToWrite> batch;
    for (std::size_t i = 0; i < frame.size(); ++i) {
      batch.push_back({&frame[i], ds.cameras[i].width_px, ds.cameras[i].height_px});
    }
    sink.WriteFrame(std::move(batch));
  }
  sink.Finish();
  const formats::DetectionsLogStats& st = sink.stats();

  // Calibration.
  config::SaveCalibration(
      out.File(formats::kConvertCalibrationFile).string(), ds.cameras, job.camera_names);

  // Ground truth, peer output, ground points.
  if (!ds.ground_truth.empty()) {
    out.WriteText(
        formats::kConvertGroundTruthFile,
        formats::SequenceToTracksJsonl(ds.ground_truth, ds.gt_layout, ds.fps, "ground truth"));
  }
  if (job.peer.has_value()) {
    out.WriteText(formats::kConvertPeerFile,
                  formats::SequenceToTracksJsonl(
                      job.peer->shelf14, core::KeypointLayoutId::kShelf14, ds.fps, job.peer->name));
  }
  std::int64_t ground_point_count = 0;
  if (job.ground_points.has_value()) {
    std::string text;
    for (const datasets::WildtrackGroundFrame& f : *job.ground_points) {
      tracker::Frame3D frame;
      frame.frame = f.frame;
      frame.utime = datasets::FrameUtime(f.frame, ds.fps);
      for (std::size_t i = 0; i < f.points.size(); ++i) {
        tracker::Track3D t;
        t.id = static_cast<TrackId3D>(i);
        t.position = f.points[i].position_m;
        frame.tracks.push_back(std::move(t));
      }
      ground_point_count += static_cast<std::int64_t>(f.points.size());
      text += transport::TracksJsonLine(frame, core::KeypointLayoutId::kNone);
    }
    out.WriteText(formats::kConvertGroundPointsFile, text);
  }

  // README.
  std::ostringstream r;
  r << "mvtrack convert " << c.format << " (mvtrack " << MVTRACK_VERSION << ")\n\n";
  r << "Command line:\n  " << c.command_line << "\n\n";
  r << "What was converted:\n";
  for (const std::string& line : job.what) r << "  " << line << "\n";
  r << "  Source directory: " << job.source_dir.string() << "\n\n";
  r << "Protocol notes (from the dataset loader):\n  " << ds.protocol_notes << "\n\n";
  r << "Frames: " << ds.detections.size() << " frames";
  if (!ds.detections.empty() && !ds.detections.front().empty()) {
    r << ", " << ds.detections.front().front().frame << "-" << ds.detections.back().front().frame;
  }
  r << ", at " << ds.fps
    << " fps.\n  Capture time: utime = round(frame * 1e6 / fps) microseconds (frame 0 at utime\n"
       "  0), the same for every camera of a frame; ground truth and peer lines carry the\n"
       "  same utime as the frame's detections.\n";
  r << "Cameras (" << ds.cameras.size() << ", id (name) image size):";
  std::vector<const geometry::CameraModel*> sorted;
  for (const geometry::CameraModel& cam : ds.cameras) sorted.push_back(&cam);
  std::sort(
      sorted.begin(), sorted.end(), [](const auto* a, const auto* b) { return a->id < b->id; });
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const geometry::CameraModel* cam = sorted[i];
    r << (i % 4 == 0 ? "\n   " : "") << " " << cam->id;
    const auto name = job.camera_names.find(cam->id);
    if (name != job.camera_names.end()) r << " (" << name->second << ")";
    r << " " << cam->width_px << "x" << cam->height_px << (i + 1 < sorted.size() ? "," : ".");
  }
  r << "\nDetections: keypoint layout " << job.replay_layout
    << (job.replay_layout == "none" ? " (box-only detections)" : "") << ".\n";
  r << "Standard protocol: scored frames " << eval::DescribeFrameRanges(ds.protocol_frames)
    << ", scored actors "
    << (ds.protocol_actor_ids.empty() ? std::string("all") : JoinIds(ds.protocol_actor_ids))
    << ".\n\n";

  r << "Files:\n" << LogDescription(c, st);
  r << "  " << formats::kConvertCalibrationFile << ": mvtrack.calibration/1 (docs/FORMATS.md), "
    << ds.cameras.size() << " cameras, cam_from_world in metres, world z up.\n";
  if (!ds.ground_truth.empty() && job.gt_without_ids) {
    std::int64_t positions = 0;
    for (const eval::EvalFrame& f : ds.ground_truth) {
      positions += static_cast<std::int64_t>(f.objects.size());
    }
    r << "  " << formats::kConvertGroundTruthFile
      << ": canonical tracks JSONL (transport::TracksJsonLine), " << ds.ground_truth.size()
      << " lines (frames " << ds.ground_truth.front().frame << "-" << ds.ground_truth.back().frame
      << "), " << positions << " annotated positions, z = 0.\n"
      << "      There are NO person ids: track ids are the index of the position within its\n"
      << "      frame. Score footprints only (mvtrack eval --points: MODA, MODP, precision,\n"
      << "      recall) inside the annotated area, --area MIN_X,MAX_X,MIN_Y,MAX_Y = " << job.gt_area
      << " (metres).\n";
  } else if (!ds.ground_truth.empty()) {
    std::map<std::int64_t, std::int64_t> frames_per_actor;
    for (const eval::EvalFrame& f : ds.ground_truth) {
      for (const eval::EvalObject& o : f.objects) ++frames_per_actor[o.id];
    }
    r << "  " << formats::kConvertGroundTruthFile
      << ": canonical tracks JSONL (transport::TracksJsonLine), " << ds.ground_truth.size()
      << " lines, one per frame (also frames without people);\n";
    if (!job.gt_track_description.empty()) {
      r << "      " << job.gt_track_description << "\n      " << frames_per_actor.size()
        << " ids; frames present per id:";
    } else {
      r << "      the ground-truth actors as tracks: id = actor id, position = footprint (hip\n"
        << "      midpoint dropped onto z = 0), joints in layout "
        << formats::LayoutName(ds.gt_layout)
        << " (metres, null = missing).\n      Actors (frames present):";
    }
    for (const auto& [id, n] : frames_per_actor) r << " " << id << " (" << n << ")";
    r << ".\n";
  }
  if (job.peer.has_value()) {
    const datasets::PeerOutput& p = *job.peer;
    r << "  " << formats::kConvertPeerFile << ": the published output of " << p.name
      << " as canonical tracks JSONL in layout shelf14, " << p.shelf14.size()
      << " lines (the frames of the file).\n"
      << "      Track ids are dense (1, 2, ... in order of first appearance); the ids in the\n"
      << "      original file:";
    for (std::size_t i = 0; i < p.original_ids.size(); ++i) {
      r << " " << (i + 1) << "=" << p.original_ids[i];
    }
    r << ".\n      Peer protocol notes: " << p.protocol_notes << "\n";
  }
  if (job.ground_points.has_value()) {
    r << "  " << formats::kConvertGroundPointsFile
      << ": MVDeTr's ground points as canonical tracks JSONL "
      << "(layout none), " << job.ground_points->size() << " lines, " << ground_point_count
      << " points.\n"
      << "      Each point is one merged person position (box bottom centres mapped to the\n"
      << "      ground by the inverse homographies of rest/metainfo.json, then merged across\n"
      << "      views within " << job.ground_cluster_radius_m
      << " m, one box per camera at most); position = the point,\n"
      << "      z = 0. Track ids are the index of the point within its frame (points sorted by\n"
      << "      x, then y): they are MEANINGLESS across frames and must not be used for identity\n"
      << "      metrics; compare footprints only.\n";
  }
  r << "  " << formats::kConvertReadmeFile << ": this file.\n\n";
  r << "Tracking it (from this directory):\n"
    << "  mvtrack replay --calibration " << formats::kConvertCalibrationFile << " --mode "
    << job.replay_mode << " --layout " << job.replay_layout << " --jsonl tracks.jsonl "
    << formats::kConvertLogFile << "\n";
  if (!ds.ground_truth.empty() && job.gt_without_ids) {
    r << "  mvtrack eval --gt " << formats::kConvertGroundTruthFile
      << " tracks.jsonl --points --area " << job.gt_area << "\n";
  } else if (!ds.ground_truth.empty()) {
    r << "  mvtrack eval --gt " << formats::kConvertGroundTruthFile << " tracks.jsonl";
    if (!ds.protocol_frames.empty()) {
      r << " --frames ";
      for (std::size_t i = 0; i < ds.protocol_frames.size(); ++i) {
        r << (i ? "," : "") << ds.protocol_frames[i].first << "-" << ds.protocol_frames[i].last;
      }
    }
    if (ds.gt_layout != core::KeypointLayoutId::kNone) r << " --distance joints";
    if (!job.eval_extra.empty()) r << " " << job.eval_extra;
    if (ds.gt_layout == core::KeypointLayoutId::kShelf14) {
      r << " --pcp";
      if (!ds.protocol_actor_ids.empty()) {
        std::string ids;
        for (std::int64_t id : ds.protocol_actor_ids)
          ids += (ids.empty() ? "" : ",") + std::to_string(id);
        r << " --actors " << ids;
      }
    }
    r << "\n";
  }
  out.WriteText(formats::kConvertReadmeFile, r.str());

  ShowProgress(c,
               "wrote " + c.out.string() + ": " + std::to_string(st.events) + " events, " +
                   std::to_string(st.detections) + " detections, " + std::to_string(st.bytes) +
                   " bytes of log (load " + FormatSeconds(job.load_seconds) + ", write " +
                   FormatSeconds(SecondsSince(start)) + ")");
}

std::map<CameraId, std::string> NamesFromPattern(const std::vector<geometry::CameraModel>& cameras,
                                                 const std::string& prefix,
                                                 int offset) {
  std::map<CameraId, std::string> names;
  for (const geometry::CameraModel& cam : cameras)
    names[cam.id] = prefix + std::to_string(cam.id + offset);
  return names;
}

// ---------------------------------------------------------------------------------------------
// The formats.

std::string FormatUsage(const std::string& format, const std::string& extra) {
  return "mvtrack convert " + format + " --out DIR " + extra +
         "[--channel shared|per-camera] [--overwrite] [--quiet]";
}

int ConvertShelf(int argc, char** argv, const std::string& command_line) {
  Args args;
  AddCommonOptions(&args, true);
  args.Option("peer",
              "the peer output written as peer.jsonl: 4d_association (its windows branch, "
              "skel.txt) or 4d_association_linux (its older linux branch run on the same "
              "detections)",
              "4d_association");
  if (!args.Parse(
          argc,
          argv,
          FormatUsage("shelf", "[--data DIR] [--peer 4d_association|4d_association_linux] "),
          "Shelf (Belagiannis et al., CVPR 2014, as released by 4D Association): the real\n"
          "OpenPose BODY25 detections of shelf/derived (5 cameras, 1032x776, frames\n"
          "300-600 = 301 frames, 25 fps assumed), the 3D ground truth of 4 actors (shelf14)\n"
          "and 4D Association's own output (skel.txt, SKEL19 mapped to shelf14) as\n"
          "peer.jsonl.\n\n" +
              std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "shelf", true, command_line);
  const std::string peer_name = args.Get("peer");
  if (peer_name != "4d_association" && peer_name != "4d_association_linux") {
    throw UsageError("--peer must be 4d_association or 4d_association_linux, not '" + peer_name +
                     "'");
  }
  DatasetJob job;
  job.source_dir = RequireDatasetDir(c, "shelf");
  ShowProgress(c, "loading Shelf from " + job.source_dir.string());
  const Clock::time_point start = Clock::now();
  job.ds = datasets::LoadShelf(c.data_root);
  job.peer = datasets::LoadShelfPeer4DA(c.data_root,
                                        peer_name == "4d_association_linux"
                                            ? datasets::Shelf4DARun::kLinux
                                            : datasets::Shelf4DARun::kWindows);
  job.load_seconds = SecondsSince(start);
  job.what = {
      "Shelf: real OpenPose BODY25 detections (shelf/derived/persons2d_body25_cam*.json, people",
      "assembled from the joint candidates with 4D Association's PAF rule), 5 cameras, layout",
      "body25, box = keypoint bounds + 10 % of their height per side, score = mean keypoint",
      "confidence; no corruption (real detector output).",
      "Ground truth: 4d_association/gt.txt (pelvis dropped -> shelf14), actors 0-3.",
      "Peer: 4D Association's " + peer_name +
          "/skel.txt (SKEL19 -> shelf14 by its own MappingToShelf)."};
  job.replay_mode = "poses";
  job.replay_layout = "body25";
  WriteDatasetJob(c, job);
  return 0;
}

int ConvertCampus(int argc, char** argv, const std::string& command_line) {
  Args args;
  AddCommonOptions(&args, true);
  const datasets::CorruptionOptions defaults;
  AddCorruptionOptions(&args, defaults);
  if (!args.Parse(argc,
                  argv,
                  FormatUsage("campus",
                              "[--data DIR] [--corruption clean|default|hard] [--seed N] "
                              "[--noise-px X] [--dropout P] [--miss-rate P] ... "),
                  "Campus (Belagiannis et al., CVPR 2014, as released by Cross-View Tracking): 3\n"
                  "cameras (360x288, 25 fps), frames 0-1999. No real detections exist: the 2D\n"
                  "ground truth (shelf14) goes through the seeded detector-error model of\n"
                  "datasets::CorruptionOptions (misses, keypoint noise, joint dropout, false\n"
                  "positives; --corruption hard: a bad day), or unchanged with --corruption\n"
                  "clean. Ground truth: the 3D\n"
                  "poses of 3 actors (shelf14); peer.jsonl: Cross-View Tracking's result_3d.json\n"
                  "(COCO-17 mapped to shelf14).\n\n" +
                      std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "campus", true, command_line);
  datasets::CampusOptions options;
  options.corruption = ParseCorruption(args, defaults);
  DatasetJob job;
  job.source_dir = RequireDatasetDir(c, "campus");
  ShowProgress(c, "loading Campus from " + job.source_dir.string());
  const Clock::time_point start = Clock::now();
  job.ds = datasets::LoadCampus(c.data_root, options);
  job.peer = datasets::LoadCampusPeerCrossView(c.data_root);
  job.load_seconds = SecondsSince(start);
  job.camera_names = NamesFromPattern(job.ds.cameras, "Camera", 0);
  job.what = {
      "Campus: the 2D ground truth (crossview_longcw/annotation_2d.json), 3 cameras, layout",
      "shelf14, box = keypoint bounds + 10 % of their height per side, score = mean keypoint",
      "confidence, then the detector-error model: " +
          datasets::DescribeCorruption(options.corruption) + ".",
      "Ground truth: annotation_3d.json (cm -> m), actors 0-2.",
      "Peer: Cross-View Tracking's result_3d.json (COCO-17 -> shelf14)."};
  job.replay_mode = "poses";
  job.replay_layout = "shelf14";
  WriteDatasetJob(c, job);
  return 0;
}

// The order --num-cameras picks from: the six default cameras, then the other HD cameras by
// name (00_00, 00_01, 00_03, ...).
std::vector<std::string> PanopticCameraOrder() {
  std::vector<std::string> order = datasets::DefaultPanopticCameras();
  for (int i = 0; i < kNumPanopticHdCameras; ++i) {
    char name[16];  // "00_" + up to 11 characters of an int: no truncation possible
    std::snprintf(name, sizeof(name), "00_%02d", i);
    if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
  }
  return order;
}

std::vector<std::string> SplitList(const std::string& text, const std::string& option) {
  std::vector<std::string> out;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(',', begin);
    const std::string item =
        text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
    if (item.empty()) throw UsageError("--" + option + ": empty entry in '" + text + "'");
    out.push_back(item);
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return out;
}

int ConvertPanoptic(int argc, char** argv, const std::string& command_line) {
  Args args;
  args.Option("sequence", "160906_band1 or 160906_band2 (required)");
  args.Option("cameras", "HD cameras, comma-separated names (00_02) or indices (2), in any order");
  std::string order_text;
  for (const std::string& name : PanopticCameraOrder())
    order_text += (order_text.empty() ? "" : ",") + name;
  args.Option("num-cameras",
              "use the first N (1-31) of the fixed order " + order_text +
                  " (the six default cameras first, then the others by name)");
  AddCommonOptions(&args, true);
  const datasets::CorruptionOptions defaults = datasets::PanopticOptions::DefaultCorruption();
  AddCorruptionOptions(&args, defaults);
  if (!args.Parse(argc,
                  argv,
                  FormatUsage("panoptic",
                              "--sequence 160906_band1|160906_band2 [--cameras A,B,...|"
                              "--num-cameras N] [--data DIR] [--corruption clean|default|hard] "
                              "[--seed N] [--noise-px X] ... "),
                  "CMU Panoptic (Joo et al., ICCV 2015), a 20-frame excerpt of 3 seated\n"
                  "musicians: the 3D skeletons (panoptic19) projected with the official lens\n"
                  "distortion into the chosen HD cameras (1920x1080, 29.97 fps; default: the six\n"
                  "cameras 00_02, 00_06, 00_07, 00_12, 00_13, 00_28), joints outside the image\n"
                  "dropped, then the seeded detector-error model (sigma scaled to the HD images:\n"
                  "6 px by default; --corruption hard: a bad day), or unchanged with --corruption\n"
                  "clean. Ground truth: the 3D skeletons.\n\n" +
                      std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "panoptic", true, command_line);
  datasets::PanopticOptions options;
  if (!args.Has("sequence"))
    throw UsageError("--sequence is required (160906_band1 or 160906_band2)");
  options.sequence = args.Get("sequence");
  if (args.Has("cameras") && args.Has("num-cameras")) {
    throw UsageError("give either --cameras or --num-cameras, not both");
  }
  if (args.Has("cameras")) {
    options.cameras = SplitList(args.Get("cameras"), "cameras");
  } else if (args.Has("num-cameras")) {
    const std::int64_t n = args.GetInt("num-cameras");
    if (n < 1 || n > kNumPanopticHdCameras) throw UsageError("--num-cameras must be in [1, 31]");
    const std::vector<std::string> order = PanopticCameraOrder();
    options.cameras.assign(order.begin(), order.begin() + n);
  }
  options.corruption = ParseCorruption(args, defaults);
  std::string why;
  if (!options.Validate(&why)) throw UsageError(why);
  DatasetJob job;
  job.source_dir = RequireDatasetDir(c, "panoptic");
  ShowProgress(c, "loading Panoptic " + options.sequence + " from " + job.source_dir.string());
  const Clock::time_point start = Clock::now();
  job.ds = datasets::LoadPanoptic(c.data_root, options);
  job.load_seconds = SecondsSince(start);
  for (const geometry::CameraModel& cam : job.ds.cameras) {
    char name[8];
    std::snprintf(name, sizeof(name), "00_%02d", cam.id);
    job.camera_names[cam.id] = name;
  }
  std::string chosen;
  for (const geometry::CameraModel& cam : job.ds.cameras) {
    chosen += (chosen.empty() ? "" : ", ") + job.camera_names[cam.id];
  }
  job.what = {
      "CMU Panoptic " + options.sequence + ": the 3D skeletons of hdPose3d_stage1_coco19",
      "projected with distortion into HD cameras " + chosen + " (camera id = HD index),",
      "layout panoptic19 (confidence 1 for projected joints inside the image), box = keypoint",
      "bounds + 10 % of their height per side, then the detector-error model: " +
          datasets::DescribeCorruption(options.corruption) + ".",
      "Ground truth: the 3D skeletons (panoptic19; joints with confidence < 0 missing)."};
  job.replay_mode = "poses";
  job.replay_layout = "panoptic19";
  WriteDatasetJob(c, job);
  return 0;
}

int ConvertWildtrack(int argc, char** argv, const std::string& command_line) {
  Args args;
  AddCommonOptions(&args, true);
  args.Option("detections",
              "'mvdetr': MVDeTr's boxes of the 40 test frames 360-399; 'annotated': the "
              "annotated per-view boxes of opentraj/ (any --frames), through --corruption",
              "mvdetr")
      .Option("frames",
              "annotated frames A-B (0-399) to convert (--detections annotated; default: the "
              "test frames 360-399)")
      .Option("gt-frames",
              "annotated frames A-B (0-399) whose ground truth goes to ground_truth.jsonl "
              "(default: the converted frames)");
  datasets::CorruptionOptions corruption_defaults = datasets::WildtrackCorruptionDefaults();
  AddCorruptionOptions(&args, corruption_defaults);
  if (!args.Parse(
          argc,
          argv,
          FormatUsage("wildtrack",
                      "[--data DIR] [--detections mvdetr|annotated] [--frames A-B] "
                      "[--gt-frames A-B] [--corruption clean|default|hard] [--seed N] "),
          "WILDTRACK (Chavdarova et al., CVPR 2018): 7 views (1920x1080) at 2 fps, box-only\n"
          "detections (layout none: track with --mode boxes).\n"
          "--detections mvdetr (default): MVDeTr's detections of the 40 test frames 360-399\n"
          "drawn as boxes into the 7 views, as they are unless --corruption names a level\n"
          "(then the detector model acts on them, e.g. --corruption default --noise-px 0\n"
          "--false-positives 0 --miss-rate 0.2 removes 20 % of the boxes).\n"
          "--detections annotated: the annotated per-view boxes of opentraj/ (the original\n"
          "annotations with person ids) of --frames, as they are (--corruption clean) or\n"
          "through the seeded detector model (default: box noise 2.1 % of the box height per\n"
          "edge, 5 % misses, 0.1 false positives per view and frame; hard: heavier).\n"
          "ground_truth.jsonl: with opentraj/ present, the annotated floor positions WITH\n"
          "person ids (score with `mvtrack eval --threshold 1.0`, the literature's 1 m radius,\n"
          "or 0.5); without it, the positions of mvdet/gt.txt without ids (score with `mvtrack\n"
          "eval --points --area -3,9,-9,27`). ground_points.jsonl (mvdetr only): MVDeTr's own\n"
          "ground points, the tracker's input as points; their ids are meaningless.\n\n" +
              std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "wildtrack", true, command_line);
  const std::string source = args.Get("detections");
  if (source != "mvdetr" && source != "annotated") {
    throw UsageError("--detections must be 'mvdetr' or 'annotated', not '" + source + "'");
  }
  const bool annotated = source == "annotated";
  const auto one_range = [&](const char* option) {
    const std::vector<eval::FrameRange> r =
        ParseFrameRanges(args.Get(option), std::string("--") + option);
    if (r.size() != 1) throw UsageError(std::string("--") + option + " takes one range A-B");
    if (r[0].first < 0 || r[0].last > 399) {
      throw UsageError(std::string("--") + option + " must lie within the annotated frames 0-399");
    }
    return r[0];
  };
  if (!annotated && args.Has("frames")) {
    throw UsageError("--frames needs --detections annotated (MVDeTr's boxes cover 360-399)");
  }
  // MVDeTr's boxes are used as they are unless a level is named: the detector model then acts
  // on them (e.g. --miss-rate 0.2 to see what missing boxes cost).
  const bool mvdetr_corrupted = !annotated && (args.Has("corruption") || args.Has("clean"));
  if (!annotated && !mvdetr_corrupted) {
    for (const char* name : {"seed",
                             "noise-px",
                             "miss-rate",
                             "false-positives",
                             "near-false-positives",
                             "blackout-seconds",
                             "dropout",
                             "noise-tail-dof"}) {
      if (args.Has(name)) {
        throw UsageError(std::string("--") + name +
                         " needs --corruption LEVEL with --detections mvdetr (its boxes are "
                         "used as they are by default)");
      }
    }
  }
  DatasetJob job;
  job.source_dir = RequireDatasetDir(c, "wildtrack");
  const bool with_ids = datasets::HasWildtrackAnnotations(c.data_root);
  if (annotated && !with_ids) {
    throw std::runtime_error("--detections annotated: " +
                             (job.source_dir / "opentraj" / "annotations_positions").string() +
                             " not found");
  }
  ShowProgress(c, "loading WILDTRACK from " + job.source_dir.string());
  const Clock::time_point start = Clock::now();
  std::string detections_line;
  if (annotated) {
    datasets::WildtrackAnnotatedOptions options;
    if (args.Has("frames")) {
      const eval::FrameRange r = one_range("frames");
      options.first = r.first;
      options.last = r.last;
    }
    options.corruption = ParseCorruption(args, corruption_defaults);
    job.ds = datasets::LoadWildtrackAnnotated(c.data_root, options);
    detections_line =
        "WILDTRACK: the annotated per-view boxes (opentraj/annotations_positions) "
        "of 7 cameras C1-C7 (ids 0-6), frames " +
        std::to_string(options.first) + "-" + std::to_string(options.last) +
        ", box-only (layout none), score 1; " + datasets::DescribeCorruption(options.corruption) +
        ".";
  } else {
    const datasets::CorruptionOptions corruption = mvdetr_corrupted
                                                       ? ParseCorruption(args, corruption_defaults)
                                                       : datasets::CorruptionOptions::Clean();
    job.ds = datasets::LoadWildtrack(c.data_root, corruption);
    detections_line =
        "WILDTRACK: MVDeTr's boxes (rest/MVDeTr_test.json) of 7 cameras C1-C7 (ids 0-6), "
        "box-only detections (layout none), score 1; " +
        datasets::DescribeCorruption(corruption) + ".";
    const datasets::WildtrackGroundOptions ground_options;
    // The ground points of the boxes the log holds (after the detector model, if any).
    job.ground_points =
        corruption.enabled
            ? datasets::WildtrackGroundPoints(c.data_root, job.ds.detections, ground_options)
            : datasets::WildtrackGroundPoints(c.data_root, ground_options);
    job.ground_cluster_radius_m = ground_options.cluster_radius_m;
  }
  const FrameIndex first = job.ds.detections.front().front().frame;
  const FrameIndex last = job.ds.detections.back().front().frame;
  eval::FrameRange gt_range{first, last};
  if (args.Has("gt-frames")) gt_range = one_range("gt-frames");
  std::string gt_line;
  if (with_ids) {
    // The annotated loader already holds the ground truth of its own frames.
    if (!annotated || args.Has("gt-frames")) {
      job.ds.ground_truth =
          datasets::WildtrackGroundTruthWithIds(c.data_root, gt_range.first, gt_range.last);
    }
    job.ds.protocol_frames = {gt_range};
    job.gt_track_description =
        "the annotated people as tracks: id = WILDTRACK's personID, position = the annotated "
        "floor position (z = 0).";
    job.eval_extra = "--threshold 1.0";
    gt_line =
        "ground_truth.jsonl: the annotated positions WITH person ids "
        "(opentraj/annotations_positions), frames " +
        std::to_string(gt_range.first) + "-" + std::to_string(gt_range.last) +
        "; score with `mvtrack eval --threshold 1.0` (1 m, the literature's radius) or 0.5.";
  } else if (datasets::HasWildtrackGroundTruth(c.data_root)) {
    job.ds.ground_truth =
        datasets::WildtrackGroundTruth(c.data_root, gt_range.first, gt_range.last);
    job.gt_without_ids = true;
    std::ostringstream area;
    area << datasets::WildtrackArea::kMinX << "," << datasets::WildtrackArea::kMaxX << ","
         << datasets::WildtrackArea::kMinY << "," << datasets::WildtrackArea::kMaxY;
    job.gt_area = area.str();
    gt_line = "ground_truth.jsonl: the positions of mvdet/gt.txt, frames " +
              std::to_string(gt_range.first) + "-" + std::to_string(gt_range.last) +
              ", no person ids (opentraj/ missing; ids = per-frame indices; use `mvtrack eval "
              "--points --area -3,9,-9,27`).";
  } else {
    job.ds.ground_truth.clear();
    gt_line = "No ground truth (opentraj/ and mvdet/gt.txt missing).";
  }
  if (job.ground_points.has_value()) gt_line += " ground_points.jsonl: MVDeTr's ground points.";
  job.load_seconds = SecondsSince(start);
  job.camera_names = NamesFromPattern(job.ds.cameras, "C", 1);
  job.what = {detections_line, gt_line};
  job.replay_mode = "boxes";
  job.replay_layout = "none";
  WriteDatasetJob(c, job);
  return 0;
}

int ConvertEpfl(int argc, char** argv, const std::string& command_line) {
  const auto num = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  Args args;
  AddCommonOptions(&args, true);
  const datasets::EpflOptions option_defaults;
  args.Option("person-height",
              "the person-height prior the floor unit is estimated from, m",
              num(option_defaults.person_height_m))
      .Option("floor-unit",
              "metres per floor unit of the homographies (default: estimated from "
              "--person-height)");
  const datasets::CorruptionOptions corruption_defaults = datasets::EpflCorruptionDefaults();
  AddCorruptionOptions(&args, corruption_defaults);
  if (!args.Parse(
          argc,
          argv,
          FormatUsage("epfl",
                      "[--data DIR] [--corruption clean|default|hard] [--seed N] "
                      "[--person-height M | --floor-unit M] "),
          "EPFL Terrace 1 (Fleuret et al., TPAMI 2008) with the UCLA per-view boxes and person\n"
          "ids (as released by GNN-CCA): 4 views (360x288) at 25 fps, 9 people, box-only\n"
          "detections (layout none: track with --mode boxes). The only calibration is one\n"
          "image -> floor homography per camera: each camera is recovered from it (square\n"
          "pixels, principal point at the image centre, focal length from the homography; see\n"
          "`mvtrack calib import homography`), and the floor unit from a person-height prior\n"
          "applied to the annotated boxes (--person-height, default 1.7 m) or --floor-unit.\n"
          "Detections: the annotated boxes as they are (--corruption clean) or through the\n"
          "seeded detector model (default: box noise 2.1 % of the box height per edge, 5 %\n"
          "misses, 0.1 false positives per view and frame; hard: heavier).\n"
          "ground_truth.jsonl: each person per frame at the mean floor point of its box bottom\n"
          "centres mapped by the homographies (score with `mvtrack eval --threshold 1.0` or\n"
          "0.5).\n\n" +
              std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "epfl", true, command_line);
  datasets::EpflOptions options;
  options.corruption = ParseCorruption(args, corruption_defaults);
  if (args.Has("person-height") && args.Has("floor-unit")) {
    throw UsageError("--floor-unit and --person-height exclude each other");
  }
  if (args.Has("person-height")) options.person_height_m = args.GetDouble("person-height");
  if (args.Has("floor-unit")) options.floor_unit_m = args.GetDouble("floor-unit");
  std::string why;
  if (!options.Validate(&why)) throw UsageError(why);
  DatasetJob job;
  job.source_dir = RequireDatasetDir(c, "epfl");
  ShowProgress(c, "loading EPFL Terrace 1 from " + job.source_dir.string());
  const Clock::time_point start = Clock::now();
  datasets::EpflCalibration calibration;
  job.ds = datasets::LoadEpflTerrace(c.data_root, options, &calibration);
  job.load_seconds = SecondsSince(start);
  std::ostringstream unit;
  unit << "floor unit " << calibration.floor_unit_m << " m ("
       << (calibration.unit_estimated
               ? "estimated: people " + num(calibration.person_height.median_height) +
                     " floor units tall, taken as " + num(options.person_height_m) + " m"
               : std::string("as given"))
       << ")" << (calibration.mirrored_y ? ", floor y mirrored" : "");
  ShowProgress(c, unit.str());
  job.camera_names = NamesFromPattern(job.ds.cameras, "c", 0);
  job.what = {
      "EPFL Terrace 1: the annotated per-view boxes (terrace1-c*/gt.txt, rows with lost = 0) of "
      "4 cameras c0-c3 (ids 0-3), box-only (layout none), score 1; " +
          datasets::DescribeCorruption(options.corruption) + ".",
      "Cameras: recovered from terrace1-c*/Homography.txt (image -> floor), " + unit.str() + ".",
      "ground_truth.jsonl: per frame, each person at the mean floor point of its box bottom "
      "centres (z = 0), ids = gt.txt's person ids; score with `mvtrack eval --threshold 1.0` "
      "or 0.5."};
  job.gt_track_description =
      "the annotated people as tracks: id = gt.txt's person id, position = the mean floor "
      "point of its box bottom centres (z = 0).";
  job.eval_extra = "--threshold 1.0";
  job.replay_mode = "boxes";
  job.replay_layout = "none";
  WriteDatasetJob(c, job);
  return 0;
}

int ConvertJsonl(int argc, char** argv, const std::string& command_line) {
  Args args;
  args.Option("detections", "the detections, JSON lines (docs/FORMATS.md) (required)")
      .Option("calibration", "the cameras, mvtrack.calibration/1 (required)")
      .Flag("skip-bad-lines",
            "skip lines that break the format (counted; the first few are printed) instead of "
            "stopping at the first");
  AddCommonOptions(&args, false);
  if (!args.Parse(argc,
                  argv,
                  FormatUsage("jsonl",
                              "--detections FILE.jsonl --calibration CAL.yaml "
                              "[--skip-bad-lines] "),
                  "The generic JSON-lines detection format (docs/FORMATS.md, \"JSON-lines\n"
                  "detections\"): one line per camera-frame,\n"
                  "  {\"camera\": 3, \"frame\": 120, \"utime\": 1700000004000000, \"image_size\": "
                  "[1920, 1080],\n"
                  "   \"detections\": [{\"box\": [x_min, y_min, x_max, y_max], \"score\": 0.93,\n"
                  "                   \"keypoints\": [[x, y, conf], ...], \"layout\": \"coco17\",\n"
                  "                   \"embedding\": [...]}]}\n"
                  "in raw (distorted) pixels, frames not decreasing. Every line becomes one event\n"
                  "(within a frame, events are sorted by camera id). The calibration is checked\n"
                  "(camera ids, image sizes) and written back in canonical form.\n\n" +
                      std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "jsonl", false, command_line);
  if (!args.Has("detections")) throw UsageError("--detections FILE.jsonl is required");
  if (!args.Has("calibration")) throw UsageError("--calibration CAL.yaml is required");
  const std::string detections_path = args.Get("detections");
  const std::string calibration_path = args.Get("calibration");

  const Clock::time_point start = Clock::now();
  const config::CalibrationDocument calibration = config::LoadCalibrationDocument(calibration_path);
  formats::JsonlReaderOptions reader_options;
  reader_options.skip_bad_lines = args.Has("skip-bad-lines");
  reader_options.max_kept_bad_lines = kBadLinesShown;
  for (const geometry::CameraModel& cam : calibration.cameras) {
    reader_options.cameras[cam.id] = formats::JsonlCameraInfo{cam.width_px, cam.height_px};
  }
  std::ifstream in(detections_path, std::ios::binary);
  if (!in) throw std::runtime_error(detections_path + ": cannot open the detections file");

  formats::ConvertOutputDir out(c.out, c.overwrite);
  ShowProgress(
      c, "reading " + detections_path + ", writing " + out.File(formats::kConvertLogFile).string());
  formats::DetectionsLogSink sink(&out, c.channel);
  formats::JsonlDetectionsReader reader(&in, detections_path, reader_options);
  std::vector<formats::JsonlCameraFrame> pending;  // the lines of the current frame
  auto flush = [&]() {
    std::vector<formats::CameraFrameToWrite> batch;
    for (const formats::JsonlCameraFrame& f : pending) {
      const formats::JsonlCameraInfo& info = reader_options.cameras.at(f.frame.camera_id);
      batch.push_back({&f.frame, info.width_px, info.height_px});
    }
    sink.WriteFrame(std::move(batch));
    pending.clear();
  };
  // Progress once a second: lines and the share of the file read.
  std::error_code size_error;
  const auto total_bytes = std::filesystem::file_size(detections_path, size_error);
  auto next_report = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (std::optional<formats::JsonlCameraFrame> f = reader.Next()) {
    if (!pending.empty() && f->frame.frame != pending.front().frame.frame) flush();
    pending.push_back(std::move(*f));
    if (std::chrono::steady_clock::now() >= next_report) {
      std::string share;
      if (!size_error && total_bytes > 0) {
        share = " (" +
                std::to_string(100 * reader.bytes_read() / static_cast<std::int64_t>(total_bytes)) +
                " %)";
      }
      ShowProgress(c, std::to_string(reader.lines_read()) + " lines read" + share);
      next_report = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    }
  }
  if (!pending.empty()) flush();
  if (sink.stats().events == 0) {
    throw std::runtime_error(detections_path + ": no valid line (" +
                             std::to_string(reader.lines_read()) + " lines read)");
  }
  sink.Finish();
  const formats::DetectionsLogStats& st = sink.stats();
  config::SaveCalibration(
      out.File(formats::kConvertCalibrationFile).string(), calibration.cameras, calibration.names);

  if (reader.bad_lines() > 0) {
    std::cerr << "mvtrack convert jsonl: skipped " << reader.bad_lines() << " bad line(s) of "
              << reader.lines_read() << "; the first:\n";
    for (const formats::JsonlBadLine& bad : reader.first_bad_lines())
      std::cerr << "  " << bad.message << "\n";
  }

  std::ostringstream r;
  r << "mvtrack convert jsonl (mvtrack " << MVTRACK_VERSION << ")\n\n";
  r << "Command line:\n  " << c.command_line << "\n\n";
  r << "What was converted:\n"
    << "  Detections: " << detections_path << " (JSON-lines detections, docs/FORMATS.md), "
    << reader.lines_read() << " lines: " << st.events << " converted, " << reader.bad_lines()
    << " bad line(s) skipped" << (reader_options.skip_bad_lines ? "" : " (--skip-bad-lines off)")
    << ".\n";
  for (const formats::JsonlBadLine& bad : reader.first_bad_lines())
    r << "    skipped: " << bad.message << "\n";
  r << "  Calibration: " << calibration_path << ", " << calibration.cameras.size()
    << " cameras, written back in canonical form.\n";
  std::vector<CameraId> silent;
  for (const geometry::CameraModel& cam : calibration.cameras) {
    if (st.events_per_camera.count(cam.id) == 0) silent.push_back(cam.id);
  }
  if (!silent.empty()) {
    std::sort(silent.begin(), silent.end());
    r << "  Calibrated cameras without any line:";
    for (CameraId id : silent) r << " " << id;
    r << ".\n";
  }
  r << "  Each line became one event; a camera-frame without a line has no event (the tracker\n"
       "  sees that camera as silent in that frame). Detections are copied as given: boxes,\n"
       "  scores, keypoints (raw pixels) and embeddings; coordinates become floats on the wire.\n"
       "  Image size of each event: the camera's calibrated size.\n\n";
  r << "Files:\n" << LogDescription(c, st);
  r << "  " << formats::kConvertCalibrationFile << ": mvtrack.calibration/1 (docs/FORMATS.md), "
    << calibration.cameras.size() << " cameras.\n";
  r << "  " << formats::kConvertReadmeFile << ": this file.\n";
  out.WriteText(formats::kConvertReadmeFile, r.str());

  ShowProgress(c,
               "wrote " + c.out.string() + ": " + std::to_string(st.events) + " events, " +
                   std::to_string(st.detections) + " detections, " + std::to_string(st.bytes) +
                   " bytes of log in " + FormatSeconds(SecondsSince(start)));
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Per-camera detection files: MOTChallenge det.txt and COCO-style keypoint JSON
// (detection_importers.h).

// What differs between the two per-camera formats.
struct PerCameraFormat {
  const char* name;               // "motchallenge" or "coco"
  const char* file_kind;          // "det.txt" or "keypoints.json"
  const char* long_name;          // for the README
  FrameIndex first_frame_number;  // frame at --start-utime: 1 (MOTChallenge) or 0 (COCO)
};

// Reads a whole file into memory.
std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the detections file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": read error");
  return text.str();
}

// `--detections ID=FILE,ID=FILE`: camera id -> path.
std::map<CameraId, std::string> ParseDetectionFiles(const std::string& text) {
  std::map<CameraId, std::string> files;
  for (const std::string& item : SplitList(text, "detections")) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) {
      throw UsageError("--detections: '" + item + "' is not CAMERA_ID=FILE");
    }
    const std::string id_text = item.substr(0, eq);
    CameraId id = 0;
    const auto [end, ec] = std::from_chars(id_text.data(), id_text.data() + id_text.size(), id);
    if (ec != std::errc() || end != id_text.data() + id_text.size() || id < 0) {
      throw UsageError("--detections: camera id '" + id_text + "' in '" + item +
                       "' is not an integer >= 0");
    }
    if (!files.emplace(id, item.substr(eq + 1)).second) {
      throw UsageError("--detections: camera " + id_text + " is given twice");
    }
  }
  return files;
}

// `--frames FIRST:LAST` (inclusive).
std::pair<FrameIndex, FrameIndex> ParseFrameRange(const std::string& text, FrameIndex min_first) {
  const std::size_t colon = text.find(':');
  auto number = [&](const std::string& t) {
    FrameIndex v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size()) {
      throw UsageError("--frames: '" + text + "' is not FIRST:LAST (two integers)");
    }
    return v;
  };
  if (colon == std::string::npos) {
    throw UsageError("--frames: '" + text + "' is not FIRST:LAST (two integers)");
  }
  const FrameIndex first = number(text.substr(0, colon));
  const FrameIndex last = number(text.substr(colon + 1));
  if (first < min_first || last < first) {
    throw UsageError("--frames: '" + text + "' needs " + std::to_string(min_first) +
                     " <= FIRST <= LAST");
  }
  return {first, last};
}

void AddPerCameraOptions(Args* args) {
  args->Option("detections", "the per-camera files: CAMERA_ID=FILE[,CAMERA_ID=FILE...] (required)")
      .Option("calibration", "the cameras, mvtrack.calibration/1 (required)")
      .Option("fps", "frame rate of the synchronized cameras, frames per second (required)")
      .Option("start-utime", "capture time of the first frame number, µs since the Unix epoch", "0")
      .Option("frames",
              "FIRST:LAST frames to write (default: the smallest to the largest frame in any "
              "file); frames without detections give empty events")
      .Flag("clamp-scores", "clamp scores and keypoint confidences outside [0, 1] into it");
}

int ConvertPerCameraFiles(
    const Args& args,
    const CommonSettings& c,
    const PerCameraFormat& format,
    const std::function<formats::ImportedDetections(const std::string&, const std::string&)>& read,
    const std::vector<std::string>& what) {
  if (!args.Has("detections")) throw UsageError("--detections CAMERA_ID=FILE,... is required");
  if (!args.Has("calibration")) throw UsageError("--calibration CAL.yaml is required");
  if (!args.Has("fps")) throw UsageError("--fps F is required");
  const double fps = args.GetDouble("fps");
  if (!(fps > 0.0 && fps <= 1000.0)) throw UsageError("--fps must be in (0, 1000]");
  const std::int64_t start_utime = args.GetInt("start-utime");
  if (start_utime < 0) throw UsageError("--start-utime must be >= 0");
  const std::map<CameraId, std::string> files = ParseDetectionFiles(args.Get("detections"));
  std::optional<std::pair<FrameIndex, FrameIndex>> range;
  if (args.Has("frames")) range = ParseFrameRange(args.Get("frames"), format.first_frame_number);

  const Clock::time_point start = Clock::now();
  const std::string calibration_path = args.Get("calibration");
  const config::CalibrationDocument calibration = config::LoadCalibrationDocument(calibration_path);
  std::map<CameraId, const geometry::CameraModel*> cameras;
  for (const geometry::CameraModel& cam : calibration.cameras) cameras[cam.id] = &cam;
  for (const auto& [id, path] : files) {
    if (cameras.count(id) == 0) {
      throw std::runtime_error("--detections: camera " + std::to_string(id) + " (" + path +
                               ") is not in the calibration " + calibration_path);
    }
  }

  // Read every file; the frame range is checked against all of them.
  std::map<CameraId, formats::ImportedDetections> per_camera;
  std::int64_t clamped = 0;
  for (const auto& [id, path] : files) {
    ShowProgress(c, "reading camera " + std::to_string(id) + ": " + path);
    per_camera[id] = read(ReadWholeFile(path), path);
    clamped += per_camera[id].clamped;
  }
  std::optional<FrameIndex> first, last;
  for (const auto& [id, imported] : per_camera) {
    if (imported.by_frame.empty()) continue;
    const FrameIndex lo = imported.by_frame.begin()->first;
    const FrameIndex hi = imported.by_frame.rbegin()->first;
    first = first.has_value() ? std::min(*first, lo) : lo;
    last = last.has_value() ? std::max(*last, hi) : hi;
    if (range.has_value() && (lo < range->first || hi > range->second)) {
      const FrameIndex bad = lo < range->first ? lo : hi;
      throw std::runtime_error(files.at(id) + ":" + std::to_string(imported.first_line.at(bad)) +
                               ": frame " + std::to_string(bad) + " is outside --frames " +
                               args.Get("frames"));
    }
  }
  if (range.has_value()) {
    first = range->first;
    last = range->second;
  }
  if (!first.has_value()) {
    throw std::runtime_error(
        "no detections in any file; give --frames FIRST:LAST to write "
        "empty frames");
  }

  formats::ConvertOutputDir out(c.out, c.overwrite);
  ShowProgress(c,
               "writing " + out.File(formats::kConvertLogFile).string() + ", frames " +
                   std::to_string(*first) + "-" + std::to_string(*last));
  formats::DetectionsLogSink sink(&out, c.channel);
  const std::vector<core::Detection2D> none;
  for (FrameIndex frame = *first; frame <= *last; ++frame) {
    const Utime utime = formats::ImportFrameUtime(
        frame, format.first_frame_number, fps, static_cast<Utime>(start_utime));
    std::vector<core::CameraFrame> frames;
    frames.reserve(per_camera.size());
    for (const auto& [id, imported] : per_camera) {
      core::CameraFrame f;
      f.utime = utime;
      f.frame = frame;
      f.camera_id = id;
      const auto it = imported.by_frame.find(frame);
      if (it != imported.by_frame.end()) f.detections = it->second;
      frames.push_back(std::move(f));
    }
    std::vector<formats::CameraFrameToWrite> batch;
    for (const core::CameraFrame& f : frames) {
      const geometry::CameraModel& cam = *cameras.at(f.camera_id);
      batch.push_back({&f, cam.width_px, cam.height_px});
    }
    sink.WriteFrame(std::move(batch));
    if ((frame - *first + 1) % 10000 == 0) {
      ShowProgress(c, std::to_string(frame - *first + 1) + " frames written");
    }
  }
  sink.Finish();
  const formats::DetectionsLogStats& st = sink.stats();
  config::SaveCalibration(
      out.File(formats::kConvertCalibrationFile).string(), calibration.cameras, calibration.names);

  std::ostringstream r;
  r << "mvtrack convert " << format.name << " (mvtrack " << MVTRACK_VERSION << ")\n\n";
  r << "Command line:\n  " << c.command_line << "\n\n";
  r << "What was converted:\n";
  for (const auto& [id, path] : files) {
    r << "  Camera " << id << ": " << path << " (" << format.long_name << "), "
      << per_camera.at(id).records << " detections.\n";
  }
  for (const std::string& line : what) r << "  " << line << "\n";
  r << "  Frames " << *first << "-" << *last << ": every listed camera has one event per frame "
    << "(empty when its file has no detection in that frame).\n"
    << "  utime = " << start_utime << " + round((frame - " << format.first_frame_number
    << ") * 1e6 / " << fps << ") µs.\n";
  if (args.Has("clamp-scores")) {
    r << "  --clamp-scores: " << clamped << " score(s) or confidence(s) clamped into [0, 1].\n";
  }
  r << "  Calibration: " << calibration_path << ", " << calibration.cameras.size()
    << " cameras, written back in canonical form.\n";
  std::vector<CameraId> silent;
  for (const geometry::CameraModel& cam : calibration.cameras) {
    if (files.count(cam.id) == 0) silent.push_back(cam.id);
  }
  if (!silent.empty()) {
    std::sort(silent.begin(), silent.end());
    r << "  Calibrated cameras without a file (no events):";
    for (CameraId id : silent) r << " " << id;
    r << ".\n";
  }
  r << "\nFiles:\n" << LogDescription(c, st);
  r << "  " << formats::kConvertCalibrationFile << ": mvtrack.calibration/1 (docs/FORMATS.md), "
    << calibration.cameras.size() << " cameras.\n";
  r << "  " << formats::kConvertReadmeFile << ": this file.\n";
  out.WriteText(formats::kConvertReadmeFile, r.str());

  ShowProgress(c,
               "wrote " + c.out.string() + ": " + std::to_string(st.events) + " events, " +
                   std::to_string(st.detections) + " detections, " + std::to_string(st.bytes) +
                   " bytes of log in " + FormatSeconds(SecondsSince(start)));
  return 0;
}

int ConvertMotChallenge(int argc, char** argv, const std::string& command_line) {
  Args args;
  AddPerCameraOptions(&args);
  args.Option(
      "pixel-origin", "coordinate of the top-left pixel in the files: 1 (MOTChallenge) or 0", "1");
  AddCommonOptions(&args, false);
  if (!args.Parse(
          argc,
          argv,
          FormatUsage("motchallenge",
                      "--detections ID=det.txt,... --calibration CAL.yaml --fps F "
                      "[--start-utime U] [--frames A:B] [--pixel-origin 1|0] [--clamp-scores] "),
          "MOTChallenge det.txt files, one per camera (docs/FORMATS.md, \"MOTChallenge\n"
          "det.txt\"): per line frame,id,left,top,width,height,conf[,x,y,z]; frames are\n"
          "1-based and equal across cameras (synchronized). Each becomes a box-only detection\n"
          "(layout none): box [left-o, top-o, left-o+width, top-o+height] with o the pixel\n"
          "origin, score conf. Frame f is captured at start-utime + round((f - 1) * 1e6 / fps)\n"
          "µs. Every camera gets an event in every frame of the range.\n\n" +
              std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "motchallenge", false, command_line);
  formats::MotChallengeOptions options;
  const std::string origin = args.Get("pixel-origin");
  if (origin != "0" && origin != "1") {
    throw UsageError("--pixel-origin must be 1 or 0, not '" + origin + "'");
  }
  options.pixel_origin = origin == "1" ? 1 : 0;
  options.clamp_scores = args.Has("clamp-scores");
  const PerCameraFormat format{"motchallenge", "det.txt", "MOTChallenge det.txt", 1};
  return ConvertPerCameraFiles(
      args,
      c,
      format,
      [&](const std::string& text, const std::string& path) {
        return formats::ReadMotChallengeDetections(text, path, options);
      },
      {"Box-only detections (layout none), box = [left, top, left + width, top + height] - " +
       origin + " (pixel origin " + origin + "), score = conf; id and x, y, z ignored."});
}

int ConvertCoco(int argc, char** argv, const std::string& command_line) {
  Args args;
  AddPerCameraOptions(&args);
  args.Option("keypoint-score",
              "third value of each keypoint: 'confidence' (in [0, 1], pose detector results) or "
              "'visibility' (COCO annotation flag 0/1/2: 0 -> 0, 1 and 2 -> 1)",
              "confidence");
  AddCommonOptions(&args, false);
  if (!args.Parse(
          argc,
          argv,
          FormatUsage("coco",
                      "--detections ID=keypoints.json,... --calibration CAL.yaml --fps F "
                      "[--start-utime U] [--frames A:B] [--keypoint-score confidence|visibility] "
                      "[--clamp-scores] "),
          "COCO-style keypoint JSON, one file per camera (docs/FORMATS.md, \"COCO-style\n"
          "keypoint JSON\"): an array of person records (COCO keypoint results as written by\n"
          "mmpose, Detectron2, OpenPifPaf, AlphaPose), or an object whose \"annotations\" is\n"
          "that array. Each record: \"image_id\" (integer, or an image file name ending in the\n"
          "frame number) or \"frame\"; \"keypoints\" (17 COCO keypoints, flat x,y,v or [x,y,v]\n"
          "triples); optional \"score\", \"bbox\"/\"box\" [x, y, w, h], \"category_id\" 1.\n"
          "Frame f "
          "is captured at start-utime + round(f * 1e6 / fps) µs. Every camera gets an event in\n"
          "every frame of the range.\n\n" +
              std::string(kFormatTrailer))) {
    return 0;
  }
  const CommonSettings c = ParseCommon(args, "coco", false, command_line);
  formats::CocoOptions options;
  const std::string score = args.Get("keypoint-score");
  if (score == "confidence") {
    options.keypoint_score = formats::CocoKeypointScore::kConfidence;
  } else if (score == "visibility") {
    options.keypoint_score = formats::CocoKeypointScore::kVisibility;
  } else {
    throw UsageError("--keypoint-score must be 'confidence' or 'visibility', not '" + score + "'");
  }
  options.clamp_scores = args.Has("clamp-scores");
  const PerCameraFormat format{"coco", "keypoints.json", "COCO-style keypoint JSON", 0};
  return ConvertPerCameraFiles(
      args,
      c,
      format,
      [&](const std::string& text, const std::string& path) {
        return formats::ReadCocoKeypoints(text, path, options);
      },
      {"COCO-17 poses (layout coco17), keypoint confidence = the keypoints' third value (" + score +
           "); box = bbox [x, y, x + w, y + h], else the keypoint",
       "bounds grown by 10 % of their height per side; score = \"score\", else the mean "
       "detected keypoint confidence."});
}

struct Format {
  const char* name;
  const char* summary;
  int (*run)(int, char**, const std::string&);
};

constexpr Format kFormats[] = {
    {"shelf", "Shelf: real OpenPose BODY25 detections, 5 cameras, frames 300-600", ConvertShelf},
    {"campus",
     "Campus: 2D ground truth through the seeded corruption model, 3 cameras",
     ConvertCampus},
    {"panoptic",
     "CMU Panoptic excerpt: 3D skeletons projected into chosen HD cameras",
     ConvertPanoptic},
    {"wildtrack",
     "WILDTRACK: MVDeTr boxes of 7 views (box mode) + MVDeTr ground points",
     ConvertWildtrack},
    {"epfl",
     "EPFL Terrace 1: annotated boxes of 4 views (box mode), cameras from homographies",
     ConvertEpfl},
    {"jsonl", "generic JSON-lines detections + a calibration (docs/FORMATS.md)", ConvertJsonl},
    {"motchallenge",
     "MOTChallenge det.txt boxes, one file per camera + a calibration",
     ConvertMotChallenge},
    {"coco",
     "COCO-style keypoint JSON (pose detector output) per camera + a calibration",
     ConvertCoco},
};

std::string ConvertHelp() {
  std::ostringstream os;
  os << "usage: mvtrack convert <format> [options] --out DIR   (mvtrack convert <format> "
        "--help)\n\n"
     << kConvertDescription << "\n\nformats:\n";
  for (const Format& f : kFormats) {
    os << "  " << f.name << std::string(14 - std::string(f.name).size(), ' ') << f.summary << "\n";
  }
  return os.str();
}

}  // namespace

int RunConvert(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << ConvertHelp();
    return 2;
  }
  const std::string format = argv[1];
  if (format == "--help" || format == "-h") {
    std::cout << ConvertHelp();
    return 0;
  }
  std::vector<std::string> words = {"mvtrack"};
  for (int i = 0; i < argc; ++i) words.emplace_back(argv[i]);
  const std::string command_line = formats::ShellQuoteCommand(words);
  for (const Format& f : kFormats) {
    if (format == f.name) return f.run(argc - 1, argv + 1, command_line);
  }
  throw UsageError("unknown format '" + format +
                   "' (shelf, campus, panoptic, wildtrack, epfl, jsonl, motchallenge, coco; "
                   "see mvtrack convert --help)");
}

}  // namespace mvtrack::cli
