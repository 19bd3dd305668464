#include "datasets/wildtrack.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/check.h"
#include "datasets/calibration_files.h"
#include "datasets/internal/common.h"
#include "datasets/internal/json_document.h"

namespace mvtrack::datasets {
namespace {

using internal::JsonValue;
using internal::kCmToM;

constexpr double kWildtrackFps = 2.0;  // annotated frames: every 5th image of a 10 fps video
// gt.txt: annotated frame k is image frame 5 k; the grid is 480 x 1440 cells of 2.5 cm.
constexpr std::int64_t kImageFramesPerAnnotatedFrame = 5;
constexpr std::int64_t kGridWidth = 480;
constexpr std::int64_t kGridHeight = 1440;
constexpr double kGridCellM = 0.025;
// Largest allowed difference between the file's R and Rodrigues(rvec).
constexpr double kRotationTolerance = 1e-6;

// One MVDeTr box: [left, top, width, height, -1, cam].
struct MvdetrBox {
  core::BoxPx box;
  std::size_t camera = 0;  // index into the camera list
};

// frame -> boxes in file order.
std::map<FrameIndex, std::vector<MvdetrBox>> LoadMvdetrBoxes(const std::filesystem::path& file,
                                                             std::size_t num_cameras) {
  const JsonValue root = internal::LoadJsonFile(file);
  std::map<FrameIndex, std::vector<MvdetrBox>> out;
  for (const auto& [key, value] : root.Items()) {
    if (key.empty() || key.size() > 9 || key.find_first_not_of("0123456789") != std::string::npos) {
      value.Fail("frame key \"" + key + "\" is not a non-negative integer");
    }
    const FrameIndex frame = static_cast<FrameIndex>(std::stoll(key));
    std::vector<MvdetrBox> boxes;
    for (std::size_t i = 0; i < value.Size(); ++i) {
      const JsonValue entry = value.At(i);
      const std::vector<double> v = entry.AsDoubles(6);
      if (!(v[2] > 0.0 && v[3] > 0.0)) entry.Fail("box width and height must be positive");
      const double cam = v[5];
      if (cam != std::floor(cam) || cam < 0.0 || cam >= static_cast<double>(num_cameras)) {
        entry.Fail("camera index " + std::to_string(cam) + " is not one of the " +
                   std::to_string(num_cameras) + " cameras");
      }
      MvdetrBox b;
      b.box = core::BoxPx{v[0], v[1], v[0] + v[2], v[1] + v[3]};
      b.camera = static_cast<std::size_t>(cam);
      boxes.push_back(b);
    }
    if (!out.emplace(frame, std::move(boxes)).second) value.Fail("frame " + key + " appears twice");
  }
  if (out.empty()) throw DatasetError(file.string(), "no frames");
  return out;
}

std::vector<geometry::CameraModel> LoadWildtrackCalibration(const std::filesystem::path& file) {
  const JsonValue root = internal::LoadJsonFile(file);
  const std::string units = root["world_units"].AsString();
  if (units != "cm") root["world_units"].Fail("expected \"cm\", got \"" + units + "\"");
  const JsonValue size = root["image_size"];
  const std::int64_t width = size.At(0).AsInt();
  const std::int64_t height = size.At(1).AsInt();
  if (size.Size() != 2 || width <= 0 || height <= 0 || width > 100000 || height > 100000) {
    size.Fail("expected [width, height] with positive sizes");
  }
  const JsonValue cams = root["cameras"];
  std::vector<geometry::CameraModel> cameras;
  for (std::size_t i = 0; i < cams.Size(); ++i) {
    const JsonValue cam = cams.At(i);
    if (cam["index"].AsInt() != static_cast<std::int64_t>(i)) {
      cam["index"].Fail("cameras must be listed in index order 0, 1, ...");
    }
    const Mat3 K = internal::Mat3FromRowMajor(cam["K"].AsMatrix(3, 3));
    const std::vector<double> dist = cam["dist"].AsDoubles(5);
    const std::vector<double> rvec = cam["rvec"].AsDoubles(3);
    const std::vector<double> tvec = cam["tvec_cm"].AsDoubles(3);
    const Mat3 file_rotation = internal::Mat3FromRowMajor(cam["R"].AsMatrix(3, 3));
    const Mat3 rotation = geometry::RotationFromRodrigues(Vec3(rvec[0], rvec[1], rvec[2]));
    if ((rotation - file_rotation).cwiseAbs().maxCoeff() > kRotationTolerance) {
      cam["R"].Fail("R differs from Rodrigues(rvec) by more than 1e-6");
    }
    geometry::Distortion distortion;
    distortion.k1 = dist[0];
    distortion.k2 = dist[1];
    distortion.p1 = dist[2];
    distortion.p2 = dist[3];
    distortion.k3 = dist[4];
    cameras.push_back(internal::MakeCamera(file.string(),
                                           "camera " + std::to_string(i),
                                           static_cast<CameraId>(i),
                                           static_cast<int>(width),
                                           static_cast<int>(height),
                                           K,
                                           rotation,
                                           kCmToM * Vec3(tvec[0], tvec[1], tvec[2]),
                                           distortion));
  }
  if (cameras.empty()) throw DatasetError(file.string(), "no cameras");
  return cameras;
}

constexpr FrameIndex kLastAnnotatedFrame = 399;

// One frame of WildtrackGroundPoints: the bottom centres of (camera index, box) mapped to the
// ground and merged across views.
WildtrackGroundFrame GroundFrame(FrameIndex frame,
                                 const std::vector<std::pair<std::size_t, core::BoxPx>>& boxes,
                                 const std::vector<Mat3>& ground_from_image,
                                 double cluster_radius_m,
                                 const std::filesystem::path& source) {
  std::vector<Vec2> points;
  std::vector<int> cameras;
  for (const auto& [camera, box] : boxes) {
    const Vec2 foot = box.bottom_center();
    const Vec3 g = ground_from_image[camera] * Vec3(foot.x(), foot.y(), 1.0);
    if (!(std::abs(g.z()) > 0.0)) {
      throw DatasetError(
          source.string(),
          "frame " + std::to_string(frame) + ": a box's bottom centre maps to infinity");
    }
    points.push_back(kCmToM * g.head<2>() / g.z());
    cameras.push_back(static_cast<int>(camera));
  }
  WildtrackGroundFrame gf;
  gf.frame = frame;
  gf.points = MergeGroundPoints(points, cameras, cluster_radius_m);
  return gf;
}

std::filesystem::path AnnotationsDir(const std::filesystem::path& data_root) {
  return data_root / "wildtrack" / "opentraj" / "annotations_positions";
}

// One person of one annotated frame: id, floor position, box per view (views where it is
// annotated only).
struct AnnotatedPerson {
  std::int64_t person_id = 0;
  Vec3 position_m = Vec3::Zero();
  std::vector<std::pair<std::size_t, core::BoxPx>> boxes;
};

// The people of annotated frame `frame` (file 5 * frame, 8 digits), in file order.
std::vector<AnnotatedPerson> LoadAnnotatedFrame(const std::filesystem::path& data_root,
                                                FrameIndex frame) {
  char name[32];
  std::snprintf(name,
                sizeof(name),
                "%08lld.json",
                static_cast<long long>(frame * kImageFramesPerAnnotatedFrame));
  const std::filesystem::path file = AnnotationsDir(data_root) / name;
  const JsonValue root = internal::LoadJsonFile(file);
  std::vector<AnnotatedPerson> people;
  for (std::size_t i = 0; i < root.Size(); ++i) {
    const JsonValue person = root.At(i);
    AnnotatedPerson p;
    p.person_id = person["personID"].AsInt();
    if (p.person_id < 0) person["personID"].Fail("must be >= 0");
    for (const AnnotatedPerson& other : people) {
      if (other.person_id == p.person_id) {
        person["personID"].Fail("person " + std::to_string(p.person_id) + " appears twice");
      }
    }
    const std::int64_t position = person["positionID"].AsInt();
    if (position < 0 || position >= kGridWidth * kGridHeight) {
      person["positionID"].Fail("outside the 480 x 1440 grid");
    }
    p.position_m =
        Vec3(WildtrackArea::kMinX + kGridCellM * static_cast<double>(position % kGridWidth),
             WildtrackArea::kMinY + kGridCellM * static_cast<double>(position / kGridWidth),
             0.0);
    const JsonValue views = person["views"];
    for (std::size_t v = 0; v < views.Size(); ++v) {
      const JsonValue view = views.At(v);
      const std::int64_t num = view["viewNum"].AsInt();
      if (num < 0 || num > 63) view["viewNum"].Fail("must be in 0..63");
      const double x_min = view["xmin"].AsDouble();
      const double y_min = view["ymin"].AsDouble();
      const double x_max = view["xmax"].AsDouble();
      const double y_max = view["ymax"].AsDouble();
      if (x_min < 0.0 && x_max < 0.0 && y_min < 0.0 && y_max < 0.0) continue;  // not visible
      if (!(std::isfinite(x_min) && std::isfinite(y_min) && std::isfinite(x_max) &&
            std::isfinite(y_max)) ||
          !(x_max > x_min && y_max > y_min)) {
        view.Fail("box must have xmax > xmin and ymax > ymin");
      }
      p.boxes.emplace_back(static_cast<std::size_t>(num), core::BoxPx{x_min, y_min, x_max, y_max});
    }
    people.push_back(std::move(p));
  }
  return people;
}

// The ground truth of one annotated frame: its people as objects (id = personID).
eval::EvalFrame GroundTruthFrame(FrameIndex frame, const std::vector<AnnotatedPerson>& people) {
  eval::EvalFrame ef;
  ef.frame = frame;
  for (const AnnotatedPerson& p : people) {
    eval::EvalObject o;
    o.id = p.person_id;
    o.position = p.position_m;
    ef.objects.push_back(std::move(o));
  }
  return ef;
}

}  // namespace

Dataset LoadWildtrack(const std::filesystem::path& data_root, const CorruptionOptions& corruption) {
  const std::filesystem::path dir = data_root / "wildtrack";
  Dataset ds;
  ds.name = "wildtrack";
  ds.fps = kWildtrackFps;
  ds.cameras = LoadWildtrackCalibration(dir / "derived" / "calibration_wildtrack.json");
  const std::map<FrameIndex, std::vector<MvdetrBox>> boxes =
      LoadMvdetrBoxes(dir / "rest" / "MVDeTr_test.json", ds.cameras.size());
  std::vector<FrameIndex> frames;
  frames.reserve(boxes.size());
  for (const auto& [frame, list] : boxes) frames.push_back(frame);
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);
  std::size_t f = 0;
  for (const auto& [frame, list] : boxes) {
    for (const MvdetrBox& b : list) {
      core::Detection2D d;
      d.box = b.box;
      d.score = 1.0;
      d.layout = core::KeypointLayoutId::kNone;
      ds.detections[f][b.camera].detections.push_back(d);
      ds.source_ids[f][b.camera].push_back(kUnknownSourceId);
    }
    ++f;
  }
  std::string why;
  if (!corruption.Validate(&why)) throw std::invalid_argument("wildtrack corruption: " + why);
  const CorruptionOptions placed =
      internal::CorruptDataset(corruption, {{frames.front(), frames.back()}}, &ds);
  ds.gt_layout = core::KeypointLayoutId::kNone;
  const bool has_gt = HasWildtrackGroundTruth(data_root);
  if (has_gt) ds.ground_truth = WildtrackGroundTruth(data_root, frames.front(), frames.back());
  ds.protocol_notes =
      "WILDTRACK (Chavdarova et al., CVPR 2018): 7 cameras (C1-C7 = ids 0-6), 1920x1080, "
      "official calibration (intrinsic_zero, undistorted images; cm -> m; ground z = 0). "
      "Detections: MVDeTr's boxes for the test frames " +
      std::to_string(frames.front()) + "-" + std::to_string(frames.back()) +
      " (annotated-frame indices, image file = 5 x index, 2 fps) from ReST's "
      "MVDeTr_test.json, box-only, score 1; " +
      DescribeCorruption(placed) +
      ". They are ground-plane detections drawn into every view, not independent per-view "
      "detections. " +
      (has_gt ? std::string("Ground truth: the floor positions of mvdet/gt.txt (MVDet), no "
                            "person ids: detection metrics (MODA, MODP, precision, recall) "
                            "only, with `mvtrack eval --points`; ids in ground_truth.jsonl are "
                            "per-frame indices. Annotated area x in [-3, 9) m, y in [-9, 27) m.")
              : std::string("No ground truth (mvdet/gt.txt missing)."));
  return ds;
}

bool WildtrackAnnotatedOptions::Validate(std::string* why) const {
  const auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (first < 0 || last > kLastAnnotatedFrame || first > last) {
    return fail("wildtrack frames must satisfy 0 <= first <= last <= 399");
  }
  std::string corruption_why;
  if (!corruption.Validate(&corruption_why)) return fail("wildtrack corruption: " + corruption_why);
  return true;
}

CorruptionOptions WildtrackCorruptionDefaults() { return CorruptionOptions{}; }

bool HasWildtrackAnnotations(const std::filesystem::path& data_root) {
  std::error_code ec;
  return std::filesystem::is_directory(AnnotationsDir(data_root), ec);
}

eval::EvalSequence WildtrackGroundTruthWithIds(const std::filesystem::path& data_root,
                                               FrameIndex first,
                                               FrameIndex last) {
  if (first < 0 || last > kLastAnnotatedFrame || first > last) {
    throw DatasetError(AnnotationsDir(data_root).string(),
                       "frames " + std::to_string(first) + "-" + std::to_string(last) +
                           " are not within the annotated frames 0-399");
  }
  eval::EvalSequence out;
  for (FrameIndex f = first; f <= last; ++f) {
    out.push_back(GroundTruthFrame(f, LoadAnnotatedFrame(data_root, f)));
  }
  return out;
}

Dataset LoadWildtrackAnnotated(const std::filesystem::path& data_root,
                               const WildtrackAnnotatedOptions& options) {
  std::string why;
  if (!options.Validate(&why)) throw std::invalid_argument(why);
  const std::filesystem::path dir = data_root / "wildtrack";
  Dataset ds;
  ds.name = "wildtrack";
  ds.fps = kWildtrackFps;
  ds.cameras = LoadWildtrackCalibration(dir / "derived" / "calibration_wildtrack.json");
  std::vector<FrameIndex> frames;
  for (FrameIndex f = options.first; f <= options.last; ++f) frames.push_back(f);
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::vector<AnnotatedPerson> people = LoadAnnotatedFrame(data_root, frames[i]);
    for (const AnnotatedPerson& p : people) {
      for (const auto& [view, box] : p.boxes) {
        if (view >= ds.cameras.size()) continue;
        const geometry::CameraModel& cam = ds.cameras[view];
        core::BoxPx b = box;
        b.x_min = std::clamp(b.x_min, 0.0, static_cast<double>(cam.width_px));
        b.x_max = std::clamp(b.x_max, 0.0, static_cast<double>(cam.width_px));
        b.y_min = std::clamp(b.y_min, 0.0, static_cast<double>(cam.height_px));
        b.y_max = std::clamp(b.y_max, 0.0, static_cast<double>(cam.height_px));
        if (b.width() < 2.0 || b.height() < 2.0) continue;
        core::Detection2D d;
        d.box = b;
        d.score = 1.0;
        d.layout = core::KeypointLayoutId::kNone;
        ds.detections[i][view].detections.push_back(d);
        ds.source_ids[i][view].push_back(p.person_id);
      }
    }
    ds.ground_truth.push_back(GroundTruthFrame(frames[i], people));
  }
  const CorruptionOptions corruption =
      internal::CorruptDataset(options.corruption, {{frames.front(), frames.back()}}, &ds);
  ds.gt_layout = core::KeypointLayoutId::kNone;
  ds.protocol_frames = {{frames.front(), frames.back()}};
  ds.protocol_notes =
      "WILDTRACK (Chavdarova et al., CVPR 2018): 7 cameras (C1-C7 = ids 0-6), 1920x1080, "
      "official calibration (intrinsic_zero, undistorted images; cm -> m; ground z = 0). "
      "Detections: the annotated per-view boxes of opentraj/annotations_positions (the "
      "original annotations, with person ids) for the annotated frames " +
      std::to_string(frames.front()) + "-" + std::to_string(frames.back()) +
      " (image file = 5 x index, 2 fps), clipped to the image, box-only, score 1; " +
      DescribeCorruption(corruption) +
      ". Ground truth: the annotated floor positions with person ids (positionID on the 480 x "
      "1440 grid of 2.5 cm cells from (-3, -9) m). Score tracking with `mvtrack eval "
      "--threshold 1.0` (the literature's 1 m radius) or 0.5 m.";
  return ds;
}

bool HasWildtrackGroundTruth(const std::filesystem::path& data_root) {
  std::error_code ec;
  return std::filesystem::is_regular_file(data_root / "wildtrack" / "mvdet" / "gt.txt", ec);
}

eval::EvalSequence WildtrackGroundTruth(const std::filesystem::path& data_root,
                                        FrameIndex first,
                                        FrameIndex last) {
  const std::filesystem::path file = data_root / "wildtrack" / "mvdet" / "gt.txt";
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw DatasetError(name, "file not found or not readable");
  std::map<FrameIndex, std::vector<eval::EvalObject>> by_frame;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string at = "line " + std::to_string(line_number);
    std::istringstream fields(line);
    std::int64_t image_frame = 0, gx = 0, gy = 0;
    std::string rest;
    if (!(fields >> image_frame >> gx >> gy) || (fields >> rest)) {
      throw DatasetError(name, at + ": expected three integers 'frame grid_x grid_y'");
    }
    if (image_frame < 0 || image_frame % kImageFramesPerAnnotatedFrame != 0 ||
        image_frame > 1'000'000'000) {
      throw DatasetError(name,
                         at + ": image frame " + std::to_string(image_frame) +
                             " is not a non-negative multiple of 5");
    }
    if (gx < 0 || gx >= kGridWidth || gy < 0 || gy >= kGridHeight) {
      throw DatasetError(name,
                         at + ": grid cell (" + std::to_string(gx) + ", " + std::to_string(gy) +
                             ") outside the 480 x 1440 grid");
    }
    const FrameIndex frame = image_frame / kImageFramesPerAnnotatedFrame;
    std::vector<eval::EvalObject>& objects = by_frame[frame];
    eval::EvalObject o;
    o.id = static_cast<std::int64_t>(objects.size());
    o.position = Vec3(WildtrackArea::kMinX + kGridCellM * static_cast<double>(gx),
                      WildtrackArea::kMinY + kGridCellM * static_cast<double>(gy),
                      0.0);
    objects.push_back(o);
  }
  if (by_frame.empty()) throw DatasetError(name, "no positions");
  if (first > last || first < by_frame.begin()->first || last > by_frame.rbegin()->first) {
    throw DatasetError(name,
                       "frames " + std::to_string(first) + "-" + std::to_string(last) +
                           " are not within the file's annotated frames " +
                           std::to_string(by_frame.begin()->first) + "-" +
                           std::to_string(by_frame.rbegin()->first));
  }
  eval::EvalSequence out;
  for (FrameIndex f = first; f <= last; ++f) {
    eval::EvalFrame ef;
    ef.frame = f;
    if (const auto it = by_frame.find(f); it != by_frame.end()) ef.objects = it->second;
    out.push_back(std::move(ef));
  }
  return out;
}

bool WildtrackGroundOptions::Validate(std::string* why) const {
  if (!(std::isfinite(cluster_radius_m) && cluster_radius_m >= 0.0)) {
    if (why != nullptr) *why = "wildtrack ground options: cluster_radius_m must be finite and >= 0";
    return false;
  }
  return true;
}

std::vector<Mat3> WildtrackHomographies(const std::filesystem::path& data_root) {
  const std::filesystem::path file = data_root / "wildtrack" / "rest" / "metainfo.json";
  const JsonValue root = internal::LoadJsonFile(file);
  const JsonValue seq = root["sequence1"];
  const JsonValue list = seq["homography"];
  const std::int64_t cam_nbr = seq["cam_nbr"].AsInt();
  if (static_cast<std::int64_t>(list.Size()) != cam_nbr) {
    list.Fail(std::to_string(list.Size()) + " homographies for cam_nbr " + std::to_string(cam_nbr));
  }
  std::vector<Mat3> out;
  for (std::size_t i = 0; i < list.Size(); ++i) {
    const Mat3 h = internal::Mat3FromRowMajor(list.At(i).AsMatrix(3, 3));
    if (!(std::abs(h.determinant()) > 0.0)) list.At(i).Fail("singular homography");
    out.push_back(h);
  }
  return out;
}

std::vector<WildtrackGroundPoint> MergeGroundPoints(const std::vector<Vec2>& points_m,
                                                    const std::vector<int>& cameras,
                                                    double radius_m) {
  MVTRACK_CHECK(points_m.size() == cameras.size());
  const std::vector<Vec2>& points = points_m;
  struct Cluster {
    Vec2 sum = Vec2::Zero();
    int count = 0;
    std::uint64_t camera_mask = 0;
    Vec2 mean() const { return sum / static_cast<double>(count); }
  };
  std::vector<Cluster> clusters(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    clusters[i].sum = points[i];
    clusters[i].count = 1;
    MVTRACK_CHECK(cameras[i] >= 0 && cameras[i] < 64);
    clusters[i].camera_mask = std::uint64_t{1} << static_cast<unsigned>(cameras[i]);
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto distance = [&](std::size_t a, std::size_t b) {
    if ((clusters[a].camera_mask & clusters[b].camera_mask) != 0) return kInf;
    return (clusters[a].mean() - clusters[b].mean()).norm();
  };
  // Clusters stay in the order of their first point, so "lowest indices" is well defined.
  // d[a * n + b] (a < b) holds the current distance; row_best[a] caches the minimum of row a
  // over living b > a (the first such b on ties), so each merge costs O(n) plus the rows whose
  // cached minimum pointed at one of the two merged clusters.
  const std::size_t n = clusters.size();
  std::vector<double> d(n * n, kInf);
  std::vector<bool> alive(n, true);
  std::vector<double> row_best(n, kInf);
  std::vector<std::size_t> row_arg(n, n);
  const auto recompute_row = [&](std::size_t a) {
    row_best[a] = kInf;
    row_arg[a] = n;
    for (std::size_t b = a + 1; b < n; ++b) {
      if (alive[b] && d[a * n + b] < row_best[a]) {
        row_best[a] = d[a * n + b];
        row_arg[a] = b;
      }
    }
  };
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) d[a * n + b] = distance(a, b);
  }
  for (std::size_t a = 0; a < n; ++a) recompute_row(a);
  while (true) {
    // The smallest distance; ties go to the lowest row, then (row_arg) the lowest column.
    double best = kInf;
    std::size_t best_a = n;
    for (std::size_t a = 0; a < n; ++a) {
      if (alive[a] && row_best[a] < best) {
        best = row_best[a];
        best_a = a;
      }
    }
    if (best_a == n || !(best <= radius_m)) break;
    const std::size_t best_b = row_arg[best_a];
    clusters[best_a].sum += clusters[best_b].sum;
    clusters[best_a].count += clusters[best_b].count;
    clusters[best_a].camera_mask |= clusters[best_b].camera_mask;
    alive[best_b] = false;
    for (std::size_t o = 0; o < n; ++o) {
      if (!alive[o] || o == best_a) continue;
      const std::size_t lo = std::min(o, best_a);
      const std::size_t hi = std::max(o, best_a);
      d[lo * n + hi] = distance(lo, hi);
    }
    for (std::size_t o = 0; o < n; ++o) {
      if (!alive[o]) continue;
      if (o == best_a || row_arg[o] == best_a || row_arg[o] == best_b) {
        recompute_row(o);
      } else if (o < best_a) {
        const double v = d[o * n + best_a];
        if (v < row_best[o] || (v == row_best[o] && best_a < row_arg[o])) {
          row_best[o] = v;
          row_arg[o] = best_a;
        }
      }
    }
  }
  std::vector<WildtrackGroundPoint> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (!alive[i]) continue;
    WildtrackGroundPoint p;
    const Vec2 m = clusters[i].mean();
    p.position_m = Vec3(m.x(), m.y(), 0.0);
    p.num_views = clusters[i].count;
    out.push_back(p);
  }
  std::sort(
      out.begin(), out.end(), [](const WildtrackGroundPoint& a, const WildtrackGroundPoint& b) {
        if (a.position_m.x() != b.position_m.x()) return a.position_m.x() < b.position_m.x();
        return a.position_m.y() < b.position_m.y();
      });
  return out;
}

std::vector<WildtrackGroundFrame> WildtrackGroundPoints(const std::filesystem::path& data_root,
                                                        const WildtrackGroundOptions& options) {
  std::string why;
  if (!options.Validate(&why)) throw DatasetError((data_root / "wildtrack").string(), why);
  const std::vector<Mat3> homographies = WildtrackHomographies(data_root);
  if (homographies.size() > 64) {
    throw DatasetError((data_root / "wildtrack" / "rest" / "metainfo.json").string(),
                       "more than 64 cameras");
  }
  std::vector<Mat3> ground_from_image;
  ground_from_image.reserve(homographies.size());
  for (const Mat3& h : homographies) ground_from_image.push_back(h.inverse());
  const std::filesystem::path box_file = data_root / "wildtrack" / "rest" / "MVDeTr_test.json";
  const std::map<FrameIndex, std::vector<MvdetrBox>> boxes =
      LoadMvdetrBoxes(box_file, homographies.size());
  std::vector<WildtrackGroundFrame> out;
  for (const auto& [frame, list] : boxes) {
    std::vector<std::pair<std::size_t, core::BoxPx>> frame_boxes;
    for (const MvdetrBox& b : list) frame_boxes.emplace_back(b.camera, b.box);
    out.push_back(
        GroundFrame(frame, frame_boxes, ground_from_image, options.cluster_radius_m, box_file));
  }
  return out;
}

std::vector<WildtrackGroundFrame> WildtrackGroundPoints(
    const std::filesystem::path& data_root,
    const std::vector<std::vector<core::CameraFrame>>& detections,
    const WildtrackGroundOptions& options) {
  std::string why;
  if (!options.Validate(&why)) throw DatasetError((data_root / "wildtrack").string(), why);
  const std::vector<Mat3> homographies = WildtrackHomographies(data_root);
  std::vector<Mat3> ground_from_image;
  for (const Mat3& h : homographies) ground_from_image.push_back(h.inverse());
  std::vector<WildtrackGroundFrame> out;
  for (const std::vector<core::CameraFrame>& frame : detections) {
    if (frame.empty()) continue;
    std::vector<std::pair<std::size_t, core::BoxPx>> frame_boxes;
    for (std::size_t c = 0; c < frame.size() && c < ground_from_image.size() && c < 64; ++c) {
      for (const core::Detection2D& d : frame[c].detections) frame_boxes.emplace_back(c, d.box);
    }
    out.push_back(GroundFrame(frame.front().frame,
                              frame_boxes,
                              ground_from_image,
                              options.cluster_radius_m,
                              data_root / "wildtrack"));
  }
  return out;
}

std::vector<geometry::CameraModel> LoadWildtrackCalibrationFile(const std::filesystem::path& file) {
  return LoadWildtrackCalibration(file);
}

}  // namespace mvtrack::datasets
