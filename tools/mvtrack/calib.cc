// mvtrack calib: calibration tools.
//   mvtrack calib import FORMAT INPUT [INPUT2 ...] --out CAL.yaml   other formats -> ours
//   mvtrack calib check CAL.yaml [--png FILE]                      sanity, overlap, baselines
// The importers and the checks are lib/config (calibration_import.h, calibration_check.h), the
// picture lib/viz (coverage_map.h); this file parses arguments and prints.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "config/calibration.h"
#include "config/calibration_check.h"
#include "config/calibration_import.h"
#include "config/site.h"
#include "config/tracker_options.h"
#include "config/zones.h"
#include "mvtrack/cli.h"
#include "viz/coverage_map.h"
#include "viz/image_io.h"
#include "viz/zones_map.h"

namespace mvtrack::cli {
namespace {

const char kFormats[] =
    "formats:\n"
    "  easymocap INTRI.yml EXTRI.yml   OpenCV FileStorage pair (K_<c>, dist_<c>, Rot_<c>/R_<c>,\n"
    "                                  T_<c> in m; W_<c>/H_<c> or --image-size)\n"
    "  4da FILE.json                   4D Association calibration.json (K, RT, imgSize)\n"
    "  voxelpose FILE.json             VoxelPose calibration_<dataset>.json (T = centre in mm;\n"
    "                                  --image-size required)\n"
    "  panoptic FILE.json              CMU Panoptic calibration_<seq>.json (HD cameras;\n"
    "                                  --cameras to choose)\n"
    "  wildtrack DIR|FILE.json         WILDTRACK calibrations/ (intrinsic_zero/, extrinsic/ XML)\n"
    "                                  or the derived JSON; image size 1920x1080 unless given\n"
    "  campus FILE.json                Cross-View Tracking Campus calibration.json (360x288\n"
    "                                  unless given)\n"
    "  homography H0.txt [H1.txt ...]  image -> floor homographies, one 3x3 text file per camera\n"
    "                                  (EPFL's Homography.txt), ids 0..n-1 in argument order;\n"
    "                                  --image-size required, --floor-unit M (default 1 m),\n"
    "                                  --focal PX (default: from each homography)\n";

// One of the homography options, finite (and > 0 when `positive`).
double FiniteOption(const Args& args, const std::string& name, bool positive) {
  const double v = args.GetDouble(name);
  if (positive && !(v > 0.0)) throw UsageError("--" + name + " must be > 0");
  return v;
}

// The per-camera checks of `calib import homography`, a table on stdout.
void PrintHomographyChecks(const std::vector<std::string>& paths,
                           const config::ImportedHomographies& imported,
                           const config::HomographyImportOptions& options) {
  std::ostream& os = std::cout;
  os << "calib import homography: " << paths.size() << " camera(s), image "
     << options.image_size.width_px << "x" << options.image_size.height_px << ", floor unit "
     << (options.floor_unit_m ? Fixed(*options.floor_unit_m, 6) + " m"
                              : std::string("1 m (assumed)"))
     << ", floor y " << (imported.checks.front().mirrored_y ? "mirrored" : "kept") << "\n\n";
  os << "camera  focal px        height m  hfov deg  vfov deg  orthogonality  floor reprojection "
        "px       file\n"
        "                                                      residual       median / max "
        "(points)\n";
  for (std::size_t i = 0; i < imported.checks.size(); ++i) {
    const geometry::FloorHomographyCamera& c = imported.checks[i];
    char line[512];
    std::snprintf(line,
                  sizeof line,
                  "%6d  %8.1f %-6s  %8.3f  %8.1f  %8.1f  %13.1e  %6.2f / %-6.2f (%3d)   %s\n",
                  c.camera.id,
                  c.focal_px,
                  c.focal_estimated ? "(est.)" : "(given)",
                  c.height_m,
                  c.horizontal_fov_deg,
                  c.vertical_fov_deg,
                  c.orthogonality_residual,
                  c.floor_reprojection_median_px,
                  c.floor_reprojection_max_px,
                  c.floor_check_points,
                  paths[i].c_str());
    os << line;
  }
  os << "\n";
}

std::vector<std::string> SplitComma(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

int RunImport(int argc, char** argv) {
  Args args;
  args.Positional("FORMAT", "easymocap, 4da, voxelpose, panoptic, wildtrack, campus or homography")
      .Positional("INPUT", "the file (or WILDTRACK directory) to import")
      .Positional("INPUT2", "easymocap: extri.yml; homography: the second camera's file", false)
      .Rest("INPUT3...", "homography: the further cameras' files")
      .Option("out", "write the calibration (mvtrack.calibration/1) here (required)")
      .Option("image-size", "WIDTHxHEIGHT for formats without image sizes")
      .Option("cameras", "panoptic: comma-separated HD cameras (00_xx or 0..30; default: all)")
      .Option("floor-unit",
              "homography: metres per floor unit of the homographies (default: 1, the floor "
              "unit taken as the metre)")
      .Option("focal",
              "homography: the focal length of every camera, pixels (default: from "
              "each homography)")
      .Option("principal-point",
              "homography: CX,CY in pixels for every camera (default: the image centre)");
  const std::string usage =
      "mvtrack calib import FORMAT INPUT [INPUT2 ...] --out CAL.yaml [options]";
  if (!args.Parse(argc,
                  argv,
                  usage,
                  std::string("Converts a calibration into mvtrack.calibration/1 (metres, z up "
                              "where the source\nsays so, cam_from_world, OpenCV distortion); "
                              "every camera is validated.\nNotes on the conventions applied "
                              "go to stderr. docs/FORMATS.md, \"Calibration\nimporters\", "
                              "specifies each format.\n\n") +
                      kFormats + "\nExit status: 0 ok, 1 invalid input, 2 usage error.")) {
    return 0;
  }
  if (!args.Has("out")) throw UsageError("--out CAL.yaml is required");
  const std::string format = args.Get("FORMAT");
  const std::string input = args.Get("INPUT");
  const bool two_inputs = format == "easymocap";
  const bool homography = format == "homography";
  if (two_inputs && !args.Has("INPUT2")) {
    throw UsageError("easymocap needs two files: INTRI.yml EXTRI.yml");
  }
  if (!homography && !args.GetRest().empty()) {
    throw UsageError(format + " takes at most " + (two_inputs ? "two inputs" : "one input") +
                     ", got also '" + args.GetRest().front() + "'");
  }
  if (!two_inputs && !homography && args.Has("INPUT2")) {
    throw UsageError(format + " takes one input, got also '" + args.Get("INPUT2") + "'");
  }
  for (const char* name : {"floor-unit", "focal", "principal-point"}) {
    if (args.Has(name) && !homography) {
      throw UsageError(std::string("--") + name + " is for homography only");
    }
  }
  if (args.Has("cameras") && format != "panoptic")
    throw UsageError("--cameras is for panoptic only");
  config::ImageSize size;
  if (args.Has("image-size")) {
    try {
      size = config::ParseImageSize(args.Get("image-size"), "--image-size");
    } catch (const config::ConfigError& e) {
      throw UsageError(e.reason());
    }
    if (format == "4da" || format == "panoptic") {
      throw UsageError("--image-size: " + format + " files carry their image sizes");
    }
  }
  config::ImportedCalibration imported;
  if (homography) {
    if (!size.given()) {
      throw UsageError("homography needs --image-size WxH (the files have none; EPFL 360x288)");
    }
    std::vector<std::string> paths = {input};
    if (args.Has("INPUT2")) paths.push_back(args.Get("INPUT2"));
    for (const std::string& path : args.GetRest()) paths.push_back(path);
    config::HomographyImportOptions options;
    options.image_size = size;
    if (args.Has("floor-unit")) options.floor_unit_m = FiniteOption(args, "floor-unit", true);
    if (args.Has("focal")) options.focal_px = FiniteOption(args, "focal", true);
    if (args.Has("principal-point")) {
      const std::vector<std::string> parts = SplitComma(args.Get("principal-point"));
      if (parts.size() != 2) throw UsageError("--principal-point: expected CX,CY");
      Vec2 pp;
      for (int i = 0; i < 2; ++i) {
        char* end = nullptr;
        const std::string& part = parts[static_cast<std::size_t>(i)];
        pp(i) = std::strtod(part.c_str(), &end);
        if (end == nullptr || *end != '\0' || !std::isfinite(pp(i))) {
          throw UsageError("--principal-point: '" + part + "' is not a number");
        }
      }
      options.principal_point_px = pp;
    }
    const config::ImportedHomographies result = config::ImportFloorHomographies(paths, options);
    PrintHomographyChecks(paths, result, options);
    imported = result.calibration;
  } else if (format == "easymocap") {
    imported = config::ImportEasyMocap(input, args.Get("INPUT2"), size);
  } else if (format == "4da") {
    imported = config::ImportFourDAssociation(input);
  } else if (format == "voxelpose") {
    if (!size.given()) {
      throw UsageError(
          "voxelpose needs --image-size WxH (the files have none; Shelf 1032x776, "
          "Campus 360x288)");
    }
    imported = config::ImportVoxelPose(input, size);
  } else if (format == "panoptic") {
    imported = config::ImportPanoptic(input, SplitComma(args.Get("cameras")));
  } else if (format == "wildtrack") {
    imported = config::ImportWildtrack(input, size);
  } else if (format == "campus") {
    imported = config::ImportCampus(input, size);
  } else {
    throw UsageError("unknown format '" + format + "'\n" + kFormats);
  }
  config::SaveCalibration(args.Get("out"), imported.document.cameras, imported.document.names);
  for (const std::string& note : imported.notes)
    std::cerr << "calib import: note: " << note << "\n";
  std::cout << "calib import: wrote " << imported.document.cameras.size() << " camera(s) to "
            << args.Get("out") << "\n";
  return 0;
}

void PrintReport(const std::string& path,
                 const std::vector<geometry::CameraModel>& cameras,
                 const config::CalibrationReport& r) {
  std::ostream& os = std::cout;
  os << "calibration: " << path << ", " << cameras.size() << " camera(s)\n\n";
  os << "camera  image        fx       fy       cx      cy     hfov   centre x, y, z (m)      "
        "pitch  floor seen\n";
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const geometry::CameraModel& c = cameras[i];
    const config::CameraCheck& cc = r.cameras[i];
    char line[256];
    std::snprintf(line,
                  sizeof line,
                  "%6d  %-11s %8.1f %8.1f %7.1f %7.1f %6.1f  %7.2f %7.2f %6.2f  %5.1f  %7.1f m2\n",
                  c.id,
                  (std::to_string(c.width_px) + "x" + std::to_string(c.height_px)).c_str(),
                  c.K(0, 0),
                  c.K(1, 1),
                  c.K(0, 2),
                  c.K(1, 2),
                  cc.horizontal_fov_deg,
                  cc.center_m.x(),
                  cc.center_m.y(),
                  cc.center_m.z(),
                  cc.pitch_down_deg,
                  cc.seen_area_m2);
    os << line;
  }
  const config::FloorRegion& g = r.grid.region;
  os << "\nfloor region x [" << Fixed(g.x_min_m, 2) << ", " << Fixed(g.x_max_m, 2) << "] y ["
     << Fixed(g.y_min_m, 2) << ", " << Fixed(g.y_max_m, 2)
     << "] m, sampled at z = " << Fixed(r.options.sample_height_m, 2) << " m every "
     << Fixed(r.grid.cell_m, 3) << " m\n";
  os << "area: triangulable " << Fixed(r.area_triangulable_m2, 1) << " m2, weak (angle < "
     << Fixed(r.options.min_triangulation_angle_deg, 1) << " deg) " << Fixed(r.area_weak_m2, 1)
     << " m2, one camera only " << Fixed(r.area_single_view_m2, 1) << " m2, unseen "
     << Fixed(r.area_unseen_m2, 1) << " m2\n\n";
  os << "camera pairs with common floor (overlap graph):\n"
        "  pair      common     baseline  median dist  median angle\n";
  int shown = 0;
  for (const config::PairCheck& p : r.pairs) {
    if (!(p.common_area_m2 > 0.0)) continue;
    char line[200];
    std::snprintf(line,
                  sizeof line,
                  "  %3d-%-3d %8.1f m2 %8.2f m %9.2f m %10.1f deg%s\n",
                  p.a,
                  p.b,
                  p.common_area_m2,
                  p.baseline_m,
                  p.median_distance_m,
                  p.median_angle_deg,
                  p.short_baseline ? "  SHORT BASELINE" : "");
    os << line;
    ++shown;
  }
  if (shown == 0) os << "  (none: no two cameras see a common floor point)\n";
  os << "\n";
  for (const std::string& w : r.warnings) os << "warning: " << w << "\n";
  for (const config::CameraCheck& cc : r.cameras) {
    for (const std::string& w : cc.warnings) os << "warning: camera " << cc.id << ": " << w << "\n";
  }
  os << r.WarningCount() << " warning(s)\n";
}

int RunCheck(int argc, char** argv) {
  Args args;
  args.Positional("CAL.yaml", "calibration file (mvtrack.calibration/1)")
      .Option("png", "write the coverage picture (cameras per floor cell, overlap graph) here")
      .Option("regions",
              "with --png: also draw this site file's regions and lines (mvtrack.site/1)")
      .Option("region",
              "floor region to sample, X0,Y0,X1,Y1 in metres (default: the camera "
              "centres and where their optical axes meet the sample plane, + --margin)")
      .Option("margin", "margin around the default region, m", "1")
      .Option("cell", "grid cell size, m", "0.1")
      .Option("height", "height of the sampled points above the floor, m", "1")
      .Option("min-angle",
              "pairs with a smaller median triangulation angle are short-baseline, "
              "degrees",
              "10")
      .Flag("strict", "exit with status 3 when there are warnings");
  if (!args.Parse(argc,
                  argv,
                  "mvtrack calib check CAL.yaml [--png FILE] [options]",
                  "Checks a calibration: per camera the image size, intrinsics, field of view,\n"
                  "centre and pitch, principal point inside the image, distortion invertible\n"
                  "over the image, looking at the floor; the overlap graph: the floor region is\n"
                  "sampled on a grid at --height and every cell counts the cameras that see it\n"
                  "(in front, inside the image); each camera pair reports its common floor area\n"
                  "and median triangulation angle (the angle between the two viewing rays).\n"
                  "Warnings: areas only one camera sees (no 3D position possible), and short\n"
                  "baselines: a pair whose median triangulation angle is below --min-angle\n"
                  "(about baseline / distance < 0.17 rad at 10 deg; the depth error grows like\n"
                  "1 / angle), the failure case the paper names for cameras close together.\n\n"
                  "Exit status: 0 ok (warnings allowed), 1 invalid calibration, 2 usage error,\n"
                  "3 warnings with --strict.")) {
    return 0;
  }
  if (args.Has("regions") && !args.Has("png")) {
    throw UsageError("--regions draws on the coverage picture: give --png too");
  }
  config::CalibrationCheckOptions options;
  options.margin_m = args.GetDouble("margin");
  options.cell_m = args.GetDouble("cell");
  options.sample_height_m = args.GetDouble("height");
  options.min_triangulation_angle_deg = args.GetDouble("min-angle");
  if (args.Has("region")) {
    const std::vector<std::string> parts = SplitComma(args.Get("region"));
    if (parts.size() != 4) throw UsageError("--region: expected X0,Y0,X1,Y1");
    double v[4];
    for (int i = 0; i < 4; ++i) {
      char* end = nullptr;
      v[i] = std::strtod(parts[static_cast<std::size_t>(i)].c_str(), &end);
      if (end == nullptr || *end != '\0' || !std::isfinite(v[i])) {
        throw UsageError("--region: '" + parts[static_cast<std::size_t>(i)] + "' is not a number");
      }
    }
    options.region = config::FloorRegion{v[0], v[1], v[2], v[3]};
  }
  std::string why;
  if (!options.Validate(&why)) throw UsageError(why);
  if (options.region) {
    const double cells =
        options.region->width_m() * options.region->depth_m() / (options.cell_m * options.cell_m);
    if (cells > static_cast<double>(config::CalibrationCheckOptions::kMaxCells)) {
      std::cerr << "calib check: note: the region has more than "
                << config::CalibrationCheckOptions::kMaxCells
                << " cells of --cell; the cell size is enlarged\n";
    }
  }
  const std::string path = args.Get("CAL.yaml");
  const std::vector<geometry::CameraModel> cameras = config::LoadCalibration(path);
  const config::CalibrationReport report = config::CheckCalibration(cameras, options);
  PrintReport(path, cameras, report);
  if (args.Has("png")) {
    std::optional<analytics::Site> site;
    if (args.Has("regions")) site = config::LoadSiteFile(args.Get("regions"));
    if (!viz::WriteImage(args.Get("png"),
                         viz::RenderCoverageMap(cameras, report, 900, site ? &*site : nullptr),
                         &why)) {
      throw std::runtime_error(why);
    }
    std::cout << "wrote " << args.Get("png") << "\n";
  }
  return args.Has("strict") && report.WarningCount() > 0 ? 3 : 0;
}

std::string IdList(const std::vector<CameraId>& ids) {
  std::string s;
  for (const CameraId id : ids) s += (s.empty() ? "" : ", ") + std::to_string(id);
  return s;
}

int RunZones(int argc, char** argv) {
  Args args;
  args.Positional("CAL.yaml", "site calibration file (mvtrack.calibration/1)")
      .Option("max-cameras", "largest number of a zone's own cameras", "16")
      .Option("cell", "floor grid cell size, m", "0.5")
      .Option("height", "height of the sampled points above the floor, m", "1")
      .Option("min-shared",
              "floor area another zone's camera must see of a zone to be its border camera, m^2",
              "2")
      .Option("out", "write one daemon configuration per zone (ZONE.yaml) and zones.yaml here")
      .Option("png",
              "draw the zones here: the floor in each zone's colour, the border floor two zones "
              "share in grey, the cameras in their zone's colour")
      .Option("mode", "--out: the zone daemons' tracker.mode, boxes or poses (default: theirs)")
      .Option("lcm-url", "--out: the zone daemons' input.lcm_url (default: LCM's default)");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack calib zones CAL.yaml [--max-cameras N] [--out DIR] [--png FILE] [options]",
          "Splits a site's cameras into zones for one mvtrackd per zone (issue 43): zones\n"
          "of at most --max-cameras cameras covering compact floor areas, each tracking\n"
          "with its own cameras plus the border cameras (other zones' cameras that see its\n"
          "floor), so the floor along a border is triangulated by both zones. Coverage is\n"
          "sampled on a --cell grid at --height as in `mvtrack calib check`. Prints the\n"
          "zones; with --out writes DIR/<zone>.yaml, a daemon configuration per zone (its\n"
          "cameras and border cameras, per-camera detection channels, the tracks, status and\n"
          "provisional channels namespaced by the zone, e.g. MVTRACK_TRACKS_ZONE1), and\n"
          "DIR/zones.yaml, the zones with their cameras, borders and neighbours.\n\n"
          "Exit status: 0 ok, 1 invalid calibration or unwritable output, 2 usage error.")) {
    return 0;
  }
  config::ZoneOptions options;
  const std::int64_t max_cameras = args.GetInt("max-cameras");
  if (max_cameras < 2 || max_cameras > 100000)
    throw UsageError("--max-cameras must be in [2, 100000]");
  options.max_cameras = static_cast<int>(max_cameras);
  options.cell_m = args.GetDouble("cell");
  options.sample_height_m = args.GetDouble("height");
  options.min_shared_area_m2 = args.GetDouble("min-shared");
  std::string daemon_extra;  // lines the zone daemons' configurations get
  if (args.Has("mode")) {
    if (!config::InputModeFromName(args.Get("mode"))) {
      throw UsageError("--mode must be 'boxes' or 'poses', not '" + args.Get("mode") + "'");
    }
    daemon_extra += "tracker:\n  mode: " + args.Get("mode") + "\n";
  }
  std::string input_url;
  if (args.Has("lcm-url")) {
    const std::string url = args.Get("lcm-url");
    if (url.empty() || url.find_first_of("\"\\\n") != std::string::npos) {
      throw UsageError("--lcm-url needs a URL (without quotes or backslashes)");
    }
    input_url = "  lcm_url: \"" + url + "\"\n";
  }
  std::string why;
  if (!options.Validate(&why)) throw UsageError(why);
  const std::string path = args.Get("CAL.yaml");
  const std::vector<geometry::CameraModel> cameras = config::LoadCalibration(path);
  if (cameras.size() < 2) throw std::runtime_error(path + ": a site needs at least 2 cameras");
  const std::vector<config::Zone> zones = config::PartitionZones(cameras, options);
  std::cout << "zones of " << path << ": " << cameras.size() << " camera(s), " << zones.size()
            << " zone(s) of at most " << options.max_cameras << " own camera(s)\n";
  for (const config::Zone& z : zones) {
    char area[160];
    std::snprintf(area,
                  sizeof(area),
                  "floor %.1f m^2 (x %.1f..%.1f, y %.1f..%.1f), shared with neighbours %.1f m^2",
                  z.area_m2,
                  z.bounds.x_min_m,
                  z.bounds.x_max_m,
                  z.bounds.y_min_m,
                  z.bounds.y_max_m,
                  z.border_area_m2);
    std::cout << "  " << z.name << ": cameras " << IdList(z.cameras) << "; border cameras "
              << (z.border.empty() ? std::string("none") : IdList(z.border)) << "; neighbours "
              << (z.neighbours.empty() ? std::string("none") : [&] {
                   std::string n;
                   for (const std::string& x : z.neighbours) n += (n.empty() ? "" : ", ") + x;
                   return n;
                 }())
              << "\n    " << area << "\n";
    if (z.cameras.size() + z.border.size() < 2) {
      std::cout << "    warning: " << z.name
                << " tracks with one camera: it cannot triangulate (give it more cameras, "
                   "or a larger --max-cameras)\n";
    }
  }
  if (args.Has("png")) {
    // The floor the split sampled (PartitionZones' region, 1 m around what the cameras see),
    // with 1 m more for the cameras' labels.
    const config::FloorRegion region =
        config::DefaultFloorRegion(cameras, options.sample_height_m, 2.0);
    if (!viz::WriteImage(
            args.Get("png"),
            viz::RenderZonesMap(cameras, zones, region, options.cell_m, options.sample_height_m),
            &why)) {
      throw std::runtime_error(why);
    }
    std::cout << "wrote " << args.Get("png") << "\n";
  }
  if (!args.Has("out")) return 0;
  namespace fs = std::filesystem;
  const fs::path dir = args.Get("out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create: " + ec.message());
  const std::string calibration =
      fs::relative(fs::absolute(path), fs::absolute(dir), ec).generic_string();
  const auto write = [&](const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(file.string() + ": cannot write");
    std::cout << "wrote " << file.string() << "\n";
  };
  std::vector<config::Zone> written = zones;
  for (config::Zone& z : written) {
    z.daemon = z.name + ".yaml";
    std::vector<CameraId> ids = z.cameras;
    ids.insert(ids.end(), z.border.begin(), z.border.end());
    std::sort(ids.begin(), ids.end());
    write(dir / z.daemon,
          "# Zone " + z.name + " of " + path + " (mvtrack calib zones): its own cameras " +
              IdList(z.cameras) + "; border cameras " +
              (z.border.empty() ? std::string("none") : IdList(z.border)) +
              ".\n# Its output channels are the site's suffixed with the zone (" +
              config::ZoneChannel("MVTRACK_TRACKS", z.name) +
              ", ...).\nformat: mvtrack.daemon/1\nzone: " + z.name + "\ncameras:\n  calibration: " +
              (ec ? fs::absolute(path).generic_string() : calibration) + "\n  ids: [" +
              IdList(ids) + "]\ninput:\n" + input_url + "  channels: per_camera\n" + daemon_extra);
  }
  write(dir / "zones.yaml",
        config::ZonesToYaml(written,
                            "Zones of " + path + " (mvtrack calib zones --max-cameras " +
                                std::to_string(options.max_cameras) + ")"));
  return 0;
}

}  // namespace

int RunCalib(int argc, char** argv) {
  const char* usage =
      "usage: mvtrack calib <import|check|zones> ... (mvtrack calib <command> --help for "
      "details)\n\n"
      "  import   convert a calibration (EasyMocap, 4D Association, VoxelPose, Panoptic,\n"
      "           WILDTRACK, Campus, floor homographies) into mvtrack.calibration/1\n"
      "  check    sanity checks, camera overlap graph and short-baseline warnings\n"
      "  zones    split a site's cameras into zones, one mvtrackd each (issue 43)\n";
  if (argc < 2) {
    std::cerr << usage;
    return 2;
  }
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << usage;
    return 0;
  }
  if (command == "import") return RunImport(argc - 1, argv + 1);
  if (command == "check") return RunCheck(argc - 1, argv + 1);
  if (command == "zones") return RunZones(argc - 1, argv + 1);
  throw UsageError("unknown calib command '" + command + "' (import, check or zones)");
}

}  // namespace mvtrack::cli
