#include "config/calibration_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/check.h"

namespace mvtrack::config {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// Optical axes meeting the sample plane within this distance (or the spread of the camera
// centres, if larger) enlarge the default region.
constexpr double kMinAxisRangeM = 10.0;
// Camera centres closer than this are reported as duplicates, metres.
constexpr double kDuplicateCenterM = 0.01;
// Centre spreads beyond this suggest millimetres or centimetres, metres.
constexpr double kImplausibleSpreadM = 1000.0;
// Distortion round-trip error reported as a problem, pixels.
constexpr double kMaxRoundtripPx = 0.5;

std::string Format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

std::string CameraName(CameraId id) { return "camera " + std::to_string(id); }

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const double upper = *mid;
  const double lower = *std::max_element(v.begin(), mid);
  return 0.5 * (lower + upper);
}

// The angle between the lines along `a` and `b`, in [0, 90] degrees: rays meeting at 170° are
// as badly conditioned as rays meeting at 10° (the point's position along them is as unsure).
double LineAngleDeg(const Vec3& a, const Vec3& b) {
  const double c = std::abs(a.dot(b)) / (a.norm() * b.norm());
  return std::acos(std::clamp(c, 0.0, 1.0)) * kRadToDeg;
}

// Optical axis (unit) in the world.
Vec3 AxisInWorld(const geometry::CameraModel& camera) {
  return camera.cam_from_world.rotation.transpose() * Vec3(0.0, 0.0, 1.0);
}

double RoundtripError(const geometry::CameraModel& camera) {
  if (camera.distortion.IsZero()) return 0.0;
  const double w = camera.width_px;
  const double h = camera.height_px;
  const Vec2 probes[] = {
      {0, 0}, {w, 0}, {0, h}, {w, h}, {w / 2, 0}, {w / 2, h}, {0, h / 2}, {w, h / 2}};
  double worst = 0.0;
  for (const Vec2& p : probes) {
    const Vec2 back = camera.DistortPixel(camera.UndistortPixel(p));
    const double e = (back - p).norm();
    worst = std::max(worst, std::isfinite(e) ? e : 1e9);
  }
  return worst;
}

}  // namespace

bool CalibrationCheckOptions::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (region) {
    const FloorRegion& r = *region;
    if (!std::isfinite(r.x_min_m) || !std::isfinite(r.x_max_m) || !std::isfinite(r.y_min_m) ||
        !std::isfinite(r.y_max_m) || !(r.x_max_m > r.x_min_m) || !(r.y_max_m > r.y_min_m)) {
      return fail("region must be finite with x_max > x_min and y_max > y_min");
    }
  }
  if (!(margin_m >= 0.0) || !std::isfinite(margin_m)) return fail("margin_m must be >= 0");
  if (!(cell_m > 0.0) || !std::isfinite(cell_m)) return fail("cell_m must be > 0");
  if (!std::isfinite(sample_height_m)) return fail("sample_height_m must be finite");
  if (!(min_triangulation_angle_deg > 0.0 && min_triangulation_angle_deg < 90.0)) {
    return fail("min_triangulation_angle_deg must be in (0, 90)");
  }
  return true;
}

Vec3 CoverageGrid::CellCenter(int col, int row, double sample_height_m) const {
  return Vec3(region.x_min_m + (col + 0.5) * cell_m,
              region.y_min_m + (row + 0.5) * cell_m,
              sample_height_m);
}

std::size_t CalibrationReport::WarningCount() const {
  std::size_t n = warnings.size();
  for (const CameraCheck& c : cameras) n += c.warnings.size();
  return n;
}

FloorRegion DefaultFloorRegion(const std::vector<geometry::CameraModel>& cameras,
                               double sample_height_m,
                               double margin_m) {
  MVTRACK_CHECK(!cameras.empty());
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  auto add = [&](const Vec3& p) {
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  };
  for (const geometry::CameraModel& c : cameras) add(c.CenterInWorld());
  // Axis hits count up to max(kMinAxisRangeM, the spread of the centres) from the camera, so a
  // camera looking almost horizontally does not stretch the region far beyond the rig.
  const double range = std::max(kMinAxisRangeM, std::hypot(x1 - x0, y1 - y0));
  for (const geometry::CameraModel& c : cameras) {
    const Vec3 centre = c.CenterInWorld();
    const Vec3 axis = AxisInWorld(c);
    if (std::abs(axis.z()) > 1e-9) {
      const double s = (sample_height_m - centre.z()) / axis.z();
      if (s > 0.0 && s * axis.norm() <= range) add(centre + s * axis);
    }
  }
  // A single camera looking horizontally gives a degenerate box: keep at least 1 m.
  const double cx = 0.5 * (x0 + x1);
  const double cy = 0.5 * (y0 + y1);
  const double hw = std::max(0.5 * (x1 - x0), 0.5) + margin_m;
  const double hd = std::max(0.5 * (y1 - y0), 0.5) + margin_m;
  return FloorRegion{cx - hw, cy - hd, cx + hw, cy + hd};
}

CalibrationReport CheckCalibration(const std::vector<geometry::CameraModel>& cameras,
                                   const CalibrationCheckOptions& options) {
  MVTRACK_CHECK(!cameras.empty());
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  for (const geometry::CameraModel& c : cameras) MVTRACK_CHECK_MSG(c.Validate(&why), why.c_str());

  CalibrationReport report;
  report.options = options;
  const FloorRegion region = options.region.value_or(
      DefaultFloorRegion(cameras, options.sample_height_m, options.margin_m));
  report.options.region = region;

  // Grid.
  CoverageGrid& grid = report.grid;
  grid.region = region;
  grid.cell_m = options.cell_m;
  const double area = region.width_m() * region.depth_m();
  const double max_cells = static_cast<double>(CalibrationCheckOptions::kMaxCells);
  if (area / (grid.cell_m * grid.cell_m) > max_cells) grid.cell_m = std::sqrt(area / max_cells);
  grid.cols = std::max(1, static_cast<int>(std::ceil(region.width_m() / grid.cell_m)));
  grid.rows = std::max(1, static_cast<int>(std::ceil(region.depth_m() / grid.cell_m)));
  const std::size_t num_cells =
      static_cast<std::size_t>(grid.cols) * static_cast<std::size_t>(grid.rows);
  grid.view_count.assign(num_cells, 0);
  grid.best_angle_deg.assign(num_cells, 0.0);
  const double cell_area = grid.cell_m * grid.cell_m;

  const std::size_t n = cameras.size();
  std::vector<Vec3> centres;
  centres.reserve(n);
  for (const geometry::CameraModel& c : cameras) centres.push_back(c.CenterInWorld());

  // Visibility per camera and cell.
  std::vector<std::vector<char>> sees(n, std::vector<char>(num_cells, 0));
  for (int row = 0; row < grid.rows; ++row) {
    for (int col = 0; col < grid.cols; ++col) {
      const std::size_t cell = static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.cols) +
                               static_cast<std::size_t>(col);
      const Vec3 p = grid.CellCenter(col, row, options.sample_height_m);
      for (std::size_t i = 0; i < n; ++i) {
        if (geometry::SeesPoint(cameras[i], p)) {
          sees[i][cell] = 1;
          ++grid.view_count[cell];
        }
      }
    }
  }

  // Cameras.
  for (std::size_t i = 0; i < n; ++i) {
    const geometry::CameraModel& c = cameras[i];
    CameraCheck cc;
    cc.id = c.id;
    cc.center_m = centres[i];
    cc.horizontal_fov_deg = 2.0 * std::atan(0.5 * c.width_px / c.K(0, 0)) * kRadToDeg;
    cc.vertical_fov_deg = 2.0 * std::atan(0.5 * c.height_px / c.K(1, 1)) * kRadToDeg;
    const Vec3 axis = AxisInWorld(c);
    cc.pitch_down_deg = std::asin(std::clamp(-axis.z(), -1.0, 1.0)) * kRadToDeg;
    std::size_t seen = 0;
    for (char s : sees[i]) seen += s != 0 ? 1 : 0;
    cc.seen_area_m2 = static_cast<double>(seen) * cell_area;
    cc.distortion_roundtrip_px = RoundtripError(c);

    const double cx = c.K(0, 2);
    const double cy = c.K(1, 2);
    if (cx < 0.0 || cx > c.width_px || cy < 0.0 || cy > c.height_px) {
      cc.warnings.push_back(Format("principal point (%.1f, %.1f) lies outside the image", cx, cy) +
                            " " + std::to_string(c.width_px) + "x" + std::to_string(c.height_px) +
                            " (wrong image size, or K for another resolution?)");
    }
    const double aspect = c.K(0, 0) / c.K(1, 1);
    if (aspect < 0.5 || aspect > 2.0) {
      cc.warnings.push_back(
          Format("fx / fy = %.3f is implausible (swapped or wrong intrinsics?)", aspect));
    }
    if (cc.horizontal_fov_deg > 170.0 || cc.horizontal_fov_deg < 3.0) {
      cc.warnings.push_back(
          Format("horizontal field of view %.1f deg is implausible for a "
                 "pinhole camera (K normalised, or for another resolution?)",
                 cc.horizontal_fov_deg));
    }
    if (cc.distortion_roundtrip_px > kMaxRoundtripPx) {
      cc.warnings.push_back(
          Format("the distortion model does not invert at the image border "
                 "(round trip error %.2f px): coefficients for another "
                 "resolution or model?",
                 cc.distortion_roundtrip_px));
    }
    if (cc.center_m.z() < 0.0) {
      cc.warnings.push_back(
          Format("camera centre at z = %.2f m is below the floor (z = 0): is "
                 "the world z axis up and the floor at z = 0?",
                 cc.center_m.z()));
    }
    if (seen == 0) {
      cc.warnings.push_back(
          Format("sees none of the floor region at z = %.2f m (region, units "
                 "or axes wrong?)",
                 options.sample_height_m));
    }
    report.cameras.push_back(std::move(cc));
  }

  // Pairs.
  const double min_angle = options.min_triangulation_angle_deg;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      PairCheck pc;
      pc.a = cameras[i].id;
      pc.b = cameras[j].id;
      pc.baseline_m = (centres[i] - centres[j]).norm();
      std::vector<double> angles;
      std::vector<double> distances;
      for (int row = 0; row < grid.rows; ++row) {
        for (int col = 0; col < grid.cols; ++col) {
          const std::size_t cell =
              static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.cols) +
              static_cast<std::size_t>(col);
          if (!sees[i][cell] || !sees[j][cell]) continue;
          const Vec3 p = grid.CellCenter(col, row, options.sample_height_m);
          const double angle = LineAngleDeg(p - centres[i], p - centres[j]);
          angles.push_back(angle);
          distances.push_back(0.5 * ((p - centres[i]).norm() + (p - centres[j]).norm()));
          grid.best_angle_deg[cell] = std::max(grid.best_angle_deg[cell], angle);
        }
      }
      pc.common_area_m2 = static_cast<double>(angles.size()) * cell_area;
      pc.median_angle_deg = Median(angles);
      pc.median_distance_m = Median(distances);
      pc.short_baseline = !angles.empty() && pc.median_angle_deg < min_angle;
      if (pc.short_baseline) {
        report.warnings.push_back(
            CameraName(pc.a) + " and " + CameraName(pc.b) +
            Format(": short baseline: %.2f m at a median distance of %.2f m gives a median "
                   "triangulation angle of %.1f deg",
                   pc.baseline_m,
                   pc.median_distance_m,
                   pc.median_angle_deg) +
            Format(" (< %.1f deg) over their %.1f m2 of common floor; 3D positions there are "
                   "poorly constrained (move one camera to widen the baseline)",
                   min_angle,
                   pc.common_area_m2));
      }
      if (pc.baseline_m < kDuplicateCenterM) {
        report.warnings.push_back(CameraName(pc.a) + " and " + CameraName(pc.b) +
                                  " have the same centre (duplicated camera?)");
        report.load_warnings.push_back(report.warnings.back());
      }
      report.pairs.push_back(pc);
    }
  }

  // Areas.
  for (std::size_t cell = 0; cell < num_cells; ++cell) {
    const int count = grid.view_count[cell];
    if (count == 0) {
      report.area_unseen_m2 += cell_area;
    } else if (count == 1) {
      report.area_single_view_m2 += cell_area;
    } else if (grid.best_angle_deg[cell] < min_angle) {
      report.area_weak_m2 += cell_area;
    } else {
      report.area_triangulable_m2 += cell_area;
    }
  }
  if (report.area_single_view_m2 > 0.0) {
    report.warnings.push_back(
        Format("%.1f m2 of the region is seen by one camera only: no 3D "
               "position can be triangulated there",
               report.area_single_view_m2));
  }
  // A camera that shares no floor with any other camera cannot triangulate anything it sees.
  if (n >= 2) {
    for (const CameraCheck& cc : report.cameras) {
      double shared = 0.0;
      for (const PairCheck& pc : report.pairs) {
        if (pc.a == cc.id || pc.b == cc.id) shared += pc.common_area_m2;
      }
      if (shared <= 0.0 && cc.seen_area_m2 > 0.0) {
        report.warnings.push_back(CameraName(cc.id) +
                                  " shares no floor with any other camera: nothing it sees can "
                                  "be triangulated (wrong pose, or the wrong camera's file?)");
        report.load_warnings.push_back(report.warnings.back());
      }
    }
  }
  // Low cameras may look up at people (Panoptic's dome); most cameras looking up suggests a
  // world whose z axis points down.
  std::size_t looking_up = 0;
  for (const CameraCheck& cc : report.cameras) looking_up += cc.pitch_down_deg < 0.0 ? 1 : 0;
  if (2 * looking_up > n) {
    report.warnings.push_back(std::to_string(looking_up) + " of " + std::to_string(n) +
                              " cameras look upwards: does the world z axis point down?");
    report.load_warnings.push_back(report.warnings.back());
  }
  double spread = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j)
      spread = std::max(spread, (centres[i] - centres[j]).norm());
  }
  if (spread > kImplausibleSpreadM) {
    report.warnings.push_back(
        Format("camera centres are up to %.0f m apart: are the extrinsics "
               "in millimetres or centimetres instead of metres?",
               spread));
    report.load_warnings.push_back(report.warnings.back());
  }
  return report;
}

std::vector<std::string> CalibrationLoadWarnings(
    const std::vector<geometry::CameraModel>& cameras) {
  CalibrationCheckOptions options;
  options.cell_m = 0.5;
  const CalibrationReport report = CheckCalibration(cameras, options);
  std::vector<std::string> warnings = report.load_warnings;
  for (const CameraCheck& c : report.cameras) {
    for (const std::string& w : c.warnings) {
      warnings.push_back("camera " + std::to_string(c.id) + ": " + w);
    }
  }
  return warnings;
}

}  // namespace mvtrack::config
