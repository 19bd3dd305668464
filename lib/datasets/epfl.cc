#include "datasets/epfl.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>

#include "datasets/calibration_files.h"
#include "datasets/internal/common.h"

namespace mvtrack::datasets {
namespace {

constexpr int kNumCameras = 4;
constexpr int kWidthPx = 360;
constexpr int kHeightPx = 288;
constexpr double kFps = 25.0;
// A box whose bottom is at or below this row is cut by the image border (its bottom centre is
// not the feet).
constexpr double kCutBottomPx = kHeightPx - 1;
// Boxes left narrower or lower than this after clipping to the image are dropped.
constexpr double kMinBoxSidePx = 2.0;

// One annotated box of gt.txt with lost = 0.
struct GtRow {
  std::int64_t person_id = 0;
  FrameIndex frame = 0;
  core::BoxPx box;
};

std::string Num(double v, const char* format = "%.4g") {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), format, v);
  return buffer;
}

// The fields of `line` separated by blanks, tabs and (for the homography) commas.
std::vector<std::string_view> Fields(std::string_view line, bool commas) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  const auto separator = [commas](char ch) {
    return ch == ' ' || ch == '\t' || ch == '\r' || (commas && ch == ',');
  };
  while (i < line.size()) {
    while (i < line.size() && separator(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !separator(line[i])) ++i;
    if (i > begin) fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

std::optional<double> ParseDouble(std::string_view text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> ParseInt(std::string_view text) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

std::ifstream OpenText(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw DatasetError(file.string(), "not found");
  std::ifstream in(file);
  if (!in) throw DatasetError(file.string(), "cannot be opened");
  return in;
}

// gt.txt: `id xmin ymin xmax ymax frame lost occluded generated "label"`; the rows with lost = 0,
// sorted by frame, then person id.
std::vector<GtRow> LoadGtFile(const std::filesystem::path& file) {
  std::ifstream in = OpenText(file);
  std::vector<GtRow> rows;
  std::map<std::pair<FrameIndex, std::int64_t>, int> seen;  // (frame, id) -> line
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> f = Fields(line, false);
    if (f.empty()) continue;
    const auto fail = [&](const std::string& problem) {
      throw DatasetError(file.string(), "line " + std::to_string(line_number) + ": " + problem);
    };
    if (f.size() != 10) {
      fail("expected 10 fields (id xmin ymin xmax ymax frame lost occluded generated label), got " +
           std::to_string(f.size()));
    }
    const std::optional<std::int64_t> id = ParseInt(f[0]);
    const std::optional<std::int64_t> frame = ParseInt(f[5]);
    if (!id || *id < 0) fail("person id '" + std::string(f[0]) + "' is not an integer >= 0");
    if (!frame || *frame < 0) fail("frame '" + std::string(f[5]) + "' is not an integer >= 0");
    std::int64_t flags[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const std::optional<std::int64_t> flag = ParseInt(f[static_cast<std::size_t>(6 + k)]);
      if (!flag || (*flag != 0 && *flag != 1)) {
        fail("lost, occluded and generated must be 0 or 1, got '" +
             std::string(f[static_cast<std::size_t>(6 + k)]) + "'");
      }
      flags[k] = *flag;
    }
    if (!seen.emplace(std::make_pair(*frame, *id), line_number).second) {
      fail("person " + std::to_string(*id) + " appears twice in frame " + std::to_string(*frame) +
           " (also line " + std::to_string(seen.at({*frame, *id})) + ")");
    }
    if (flags[0] == 1) continue;  // lost: not visible in this camera
    double box[4];
    for (int k = 0; k < 4; ++k) {
      const std::optional<double> v = ParseDouble(f[static_cast<std::size_t>(1 + k)]);
      if (!v)
        fail("box coordinate '" + std::string(f[static_cast<std::size_t>(1 + k)]) +
             "' is not a finite number");
      box[k] = *v;
    }
    if (!(box[2] > box[0] && box[3] > box[1])) fail("box must have xmax > xmin and ymax > ymin");
    rows.push_back(GtRow{*id, *frame, core::BoxPx{box[0], box[1], box[2], box[3]}});
  }
  if (in.bad()) throw DatasetError(file.string(), "read error");
  std::sort(rows.begin(), rows.end(), [](const GtRow& a, const GtRow& b) {
    return std::tie(a.frame, a.person_id) < std::tie(b.frame, b.person_id);
  });
  return rows;
}

std::string CameraDirName(int c) { return "terrace1-c" + std::to_string(c); }

}  // namespace

Mat3 LoadFloorHomographyFile(const std::filesystem::path& file) {
  std::ifstream in = OpenText(file);
  Mat3 h = Mat3::Zero();
  int rows = 0;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> f = Fields(line, true);
    if (f.empty() || f.front().front() == '#') continue;
    const std::string where = "line " + std::to_string(line_number) + ": ";
    if (rows == 3) throw DatasetError(file.string(), where + "more than 3 rows");
    if (f.size() != 3) {
      throw DatasetError(
          file.string(),
          where + "expected a row of 3 numbers, got " + std::to_string(f.size()) + " fields");
    }
    for (int c = 0; c < 3; ++c) {
      const std::optional<double> v = ParseDouble(f[static_cast<std::size_t>(c)]);
      if (!v) {
        throw DatasetError(
            file.string(),
            where + "'" + std::string(f[static_cast<std::size_t>(c)]) + "' is not a finite number");
      }
      h(rows, c) = *v;
    }
    ++rows;
  }
  if (in.bad()) throw DatasetError(file.string(), "read error");
  if (rows != 3) {
    throw DatasetError(
        file.string(),
        "expected 3 rows of 3 numbers (a 3x3 homography), got " + std::to_string(rows) + " row(s)");
  }
  return h;
}

CorruptionOptions EpflCorruptionDefaults() { return CorruptionOptions{}; }

bool EpflOptions::Validate(std::string* why) const {
  const auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  std::string corruption_why;
  if (!corruption.Validate(&corruption_why)) return fail("epfl corruption: " + corruption_why);
  if (!std::isfinite(person_height_m) || !(person_height_m > 0.0) || person_height_m > 3.0) {
    return fail("epfl person_height_m must be in (0, 3] m, got " + Num(person_height_m));
  }
  if (floor_unit_m.has_value() && (!std::isfinite(*floor_unit_m) || !(*floor_unit_m > 0.0))) {
    return fail("epfl floor_unit_m must be finite and > 0, got " + Num(*floor_unit_m));
  }
  return true;
}

Dataset LoadEpflTerrace(const std::filesystem::path& data_root,
                        const EpflOptions& options,
                        EpflCalibration* calibration) {
  const std::filesystem::path dir = data_root / "epfl" / "terrace1";
  std::string why;
  if (!options.Validate(&why)) throw DatasetError(dir.string(), why);

  // Files.
  EpflCalibration cal;
  std::vector<std::vector<GtRow>> rows(kNumCameras);
  std::vector<std::string> homography_files;
  for (int c = 0; c < kNumCameras; ++c) {
    const std::filesystem::path cam_dir = dir / CameraDirName(c);
    homography_files.push_back((cam_dir / "Homography.txt").string());
    cal.homographies.push_back(LoadFloorHomographyFile(homography_files.back()));
    rows[static_cast<std::size_t>(c)] = LoadGtFile(cam_dir / "gt.txt");
  }

  // Cameras in floor units, the unit from the person-height prior, then the cameras in metres.
  const auto recover = [&](int c, double unit_m) {
    geometry::FloorHomographyOptions o;
    o.floor_unit_m = unit_m;
    geometry::FloorHomographyCamera r = geometry::CameraFromFloorHomography(
        cal.homographies[static_cast<std::size_t>(c)], c, kWidthPx, kHeightPx, o);
    if (!r.ok) {
      throw DatasetError(homography_files[static_cast<std::size_t>(c)],
                         "camera " + std::to_string(c) + ": " + r.reason);
    }
    return r;
  };
  std::vector<geometry::PersonBoxes> person_boxes;
  for (int c = 0; c < kNumCameras; ++c) {
    geometry::PersonBoxes p;
    p.camera = recover(c, 1.0).camera;
    for (const GtRow& row : rows[static_cast<std::size_t>(c)]) p.boxes.push_back(row.box);
    person_boxes.push_back(std::move(p));
  }
  cal.person_height =
      geometry::EstimateFloorUnitFromPersonHeight(person_boxes, options.person_height_m);
  if (options.floor_unit_m.has_value()) {
    cal.floor_unit_m = *options.floor_unit_m;
  } else {
    if (!cal.person_height.ok) {
      throw DatasetError(dir.string(),
                         "cannot estimate the floor unit: " + cal.person_height.reason);
    }
    cal.floor_unit_m = cal.person_height.unit_m;
    cal.unit_estimated = true;
  }
  Dataset ds;
  ds.name = "epfl/terrace1";
  ds.fps = kFps;
  for (int c = 0; c < kNumCameras; ++c) {
    cal.cameras.push_back(recover(c, cal.floor_unit_m));
    if (cal.cameras.back().mirrored_y != cal.cameras.front().mirrored_y) {
      throw DatasetError(homography_files[static_cast<std::size_t>(c)],
                         "camera " + std::to_string(c) + " needs the floor's y axis " +
                             (cal.cameras.back().mirrored_y ? "" : "not ") +
                             "mirrored, camera 0 the opposite: the homographies do not share "
                             "one floor frame");
    }
    ds.cameras.push_back(cal.cameras.back().camera);
  }
  cal.mirrored_y = cal.cameras.front().mirrored_y;

  // Frames: first to last with an annotated person.
  FrameIndex first = -1;
  FrameIndex last = -1;
  for (const std::vector<GtRow>& camera_rows : rows) {
    if (camera_rows.empty()) continue;
    first = first < 0 ? camera_rows.front().frame : std::min(first, camera_rows.front().frame);
    last = std::max(last, camera_rows.back().frame);
  }
  if (first < 0) throw DatasetError(dir.string(), "no annotated person (every row is lost)");
  std::vector<FrameIndex> frames;
  for (FrameIndex f = first; f <= last; ++f) frames.push_back(f);
  internal::InitDetectionGrid(frames, ds.cameras, ds.fps, &ds.detections, &ds.source_ids);

  // Detections, and the boxes of each person per frame for the ground truth.
  // by_frame[f][person] = (camera, box) of every camera that annotates it.
  std::vector<std::map<std::int64_t, std::vector<std::pair<std::size_t, core::BoxPx>>>> by_frame(
      frames.size());
  int dropped = 0;
  for (std::size_t c = 0; c < rows.size(); ++c) {
    for (const GtRow& row : rows[c]) {
      const std::size_t f = static_cast<std::size_t>(row.frame - first);
      by_frame[f][row.person_id].emplace_back(c, row.box);
      core::BoxPx b = row.box;
      b.x_min = std::clamp(b.x_min, 0.0, static_cast<double>(kWidthPx));
      b.x_max = std::clamp(b.x_max, 0.0, static_cast<double>(kWidthPx));
      b.y_min = std::clamp(b.y_min, 0.0, static_cast<double>(kHeightPx));
      b.y_max = std::clamp(b.y_max, 0.0, static_cast<double>(kHeightPx));
      if (b.width() < kMinBoxSidePx || b.height() < kMinBoxSidePx) {
        ++dropped;
        continue;
      }
      core::Detection2D d;
      d.box = b;
      d.score = 1.0;
      d.layout = core::KeypointLayoutId::kNone;
      ds.detections[f][c].detections.push_back(std::move(d));
      ds.source_ids[f][c].push_back(row.person_id);
    }
  }

  // Ground truth: the mean floor point of each person's uncut box bottoms.
  std::int64_t person_frames = 0;
  std::int64_t cut_only = 0;
  std::set<std::int64_t> people;
  // Distances of the views' floor points from their mean (persons seen by >= 2 views), m.
  std::vector<double> spread_m;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    eval::EvalFrame ef;
    ef.frame = frames[f];
    for (const auto& [person, boxes] : by_frame[f]) {
      bool any_uncut = false;
      for (const auto& [c, box] : boxes) any_uncut |= box.y_max < kCutBottomPx;
      std::vector<Vec2> points;
      for (const auto& [c, box] : boxes) {
        if (any_uncut && !(box.y_max < kCutBottomPx)) continue;
        const std::optional<Vec2> p =
            geometry::ImageToFloor(cal.homographies[c], box.bottom_center());
        if (p.has_value()) points.push_back(*p);
      }
      if (points.empty()) continue;
      if (!any_uncut) ++cut_only;
      Vec2 mean = Vec2::Zero();
      for (const Vec2& p : points) mean += p;
      mean /= static_cast<double>(points.size());
      if (points.size() >= 2) {
        for (const Vec2& p : points) spread_m.push_back(cal.floor_unit_m * (p - mean).norm());
      }
      people.insert(person);
      eval::EvalObject o;
      o.id = person;
      o.position = geometry::FloorToWorld(mean, cal.floor_unit_m, cal.mirrored_y);
      ef.objects.push_back(std::move(o));
      ++person_frames;
    }
    ds.ground_truth.push_back(std::move(ef));
  }
  ds.gt_layout = core::KeypointLayoutId::kNone;

  const CorruptionOptions corruption =
      internal::CorruptDataset(options.corruption, {{first, last}}, &ds);
  ds.protocol_frames = {eval::FrameRange{first, last}};

  // Notes.
  double spread_median_m = 0.0;
  if (!spread_m.empty()) {
    const auto middle = spread_m.begin() + static_cast<std::ptrdiff_t>(spread_m.size() / 2);
    std::nth_element(spread_m.begin(), middle, spread_m.end());
    spread_median_m = *middle;
  }
  std::string ids_text;
  if (!people.empty()) {
    ids_text =
        " (ids " + std::to_string(*people.begin()) + "-" + std::to_string(*people.rbegin()) + ")";
  }
  std::string unit_text;
  const geometry::PersonHeightEstimate& ph = cal.person_height;
  const std::string heights =
      ph.ok
          ? "the annotated boxes whose top and bottom are inside the image (" +
                std::to_string(ph.boxes_used) + " of " + std::to_string(ph.boxes_total) +
                ") imply people " + Num(ph.median_height, "%.1f") + " floor units tall (median; " +
                "p10-p90 " + Num(ph.p10_height, "%.1f") + "-" + Num(ph.p90_height, "%.1f") + ")"
          : "no person height could be measured (" + ph.reason + ")";
  if (cal.unit_estimated) {
    unit_text = "floor unit " + Num(cal.floor_unit_m, "%.5f") + " m, estimated: " + heights +
                ", taken as " + Num(options.person_height_m, "%.3g") + " m";
  } else {
    unit_text = "floor unit " + Num(cal.floor_unit_m, "%.5g") + " m as given (" + heights + ")";
  }
  std::string camera_text;
  for (const geometry::FloorHomographyCamera& c : cal.cameras) {
    camera_text += (camera_text.empty() ? "" : "; ") + std::string("c") +
                   std::to_string(c.camera.id) + " f " + Num(c.focal_px, "%.1f") + " px, hfov " +
                   Num(c.horizontal_fov_deg, "%.1f") + " deg, height " + Num(c.height_m, "%.2f") +
                   " m, orthogonality residual " + Num(c.orthogonality_residual, "%.1e") +
                   ", floor reprojection median/max " +
                   Num(c.floor_reprojection_median_px, "%.2f") + "/" +
                   Num(c.floor_reprojection_max_px, "%.2f") + " px";
  }
  ds.protocol_notes =
      "EPFL Terrace 1 (Fleuret et al., TPAMI 2008) with the per-view boxes and person ids of the "
      "UCLA multi-view annotations as released by GNN-CCA: 4 cameras c0-c3 (ids 0-3), 360x288, "
      "25 fps, frames " +
      std::to_string(first) + "-" + std::to_string(last) +
      " (the first to the last frame with an annotated person). Calibration: only an image -> "
      "floor homography per camera; each camera recovered from it assuming square pixels, zero "
      "skew, no distortion, the principal point at the image centre, the focal length from the "
      "homography's orthogonality constraints, then R, t and f refined to minimise the floor "
      "reprojection error (geometry::CameraFromFloorHomography; " +
      camera_text + "); " + unit_text + "; world = the floor frame in metres, z up" +
      (cal.mirrored_y ? ", the floor's y axis mirrored (world y = -floor y: the floor's x, y with "
                        "z up is left-handed)"
                      : "") +
      ". Detections: the annotated boxes (gt.txt rows with lost = 0), clipped to the image" +
      (dropped > 0 ? " (" + std::to_string(dropped) + " left under 2 px dropped)" : "") +
      ", box-only, score 1; " + DescribeCorruption(corruption) +
      ". Ground truth: " + std::to_string(people.size()) + " people" + ids_text + ", " +
      std::to_string(person_frames) +
      " person-frames; each person at the mean floor point of its box bottom centres mapped by "
      "the homographies of the cameras that annotate it, leaving out bottoms cut by the image "
      "border (ymax >= 287) unless all are (" +
      std::to_string(cut_only) +
      " person-frames), z = 0: an estimate, the views' points of a person lie a median " +
      Num(spread_median_m, "%.2f") +
      " m from their mean. Score tracking with `mvtrack eval --threshold 1.0` or 0.5.";
  if (calibration != nullptr) *calibration = std::move(cal);
  return ds;
}

}  // namespace mvtrack::datasets
