// mvtrack check-config: validates a tracker options file (and optionally a calibration file and
// the combination of both) and prints the effective options; or validates a daemon
// configuration (format mvtrack.daemon/1, recognised by content) and prints its effective form.

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "config/calibration.h"
#include "config/config_error.h"
#include "config/site.h"
#include "config/tracker_options.h"
#include "core/keypoint_layout.h"
#include "formats/tracks_io.h"
#include "geometry/camera_rig.h"
#include "mvtrack/cli.h"
#include "service/daemon_config.h"
#include "tracker/tracker.h"

namespace mvtrack::cli {
namespace {

// The file's text, or "" when it cannot be read (the loaders then report why).
std::string ReadIfPossible(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return in ? text.str() : std::string();
}

// Validates a daemon configuration: the document, its calibration (or --calibration), and the
// tracker built from both; prints the effective configuration.
int CheckDaemonConfig(const std::string& path, const std::string& calibration_override) {
  service::DaemonConfig config;
  try {
    config = service::LoadDaemonConfigFile(path, calibration_override);
  } catch (const config::ConfigError& e) {
    std::cerr << "mvtrack check-config: invalid: " << e.what() << "\n";
    return 1;
  }
  std::string why;
  if (!tracker::Tracker::Create(geometry::CameraRig(config.cameras), config.tracker, &why)) {
    std::cerr << "mvtrack check-config: invalid: " << path << ": tracker: " << why << "\n";
    return 1;
  }
  std::string ids;
  for (const geometry::CameraModel& c : config.cameras) {
    ids += (ids.empty() ? "" : ", ") + std::to_string(c.id);
  }
  std::cout << service::DaemonConfigToYaml(config) << "# ok: " << path << ": daemon configuration, "
            << config.cameras.size() << " camera(s) (ids " << ids << ") from "
            << config.calibration_path << ", sync " << service::SyncModeName(config.sync.mode)
            << ", " << config.EffectiveWorkers() << " worker(s), hash "
            << service::DaemonConfigHash(config) << "\n";
  return 0;
}

}  // namespace

int RunCheckConfig(int argc, char** argv) {
  Args args;
  args.Positional("OPTIONS.yaml",
                  "tracker options file (a `tracker:` YAML document) or daemon "
                  "configuration (format: mvtrack.daemon/1) or site file (format: "
                  "mvtrack.site/1)")
      .Option("calibration",
              "also validate this calibration file (mvtrack.calibration/1) and "
              "that the tracker accepts the rig with these options; for a daemon "
              "configuration: use it instead of cameras.calibration");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack check-config OPTIONS.yaml [--calibration CAL.yaml]",
          "Validates a tracker options file strictly (unknown keys, wrong types and values\n"
          "out of range are errors naming the file, line and key) and prints the effective\n"
          "options, every key with its value, as a canonical `tracker:` document on stdout\n"
          "(usable as an options file), followed by a one-line summary as a YAML comment.\n"
          "With --calibration the camera file is validated too, and the tracker is built\n"
          "with both (a rig needs at least two cameras).\n\n"
          "A daemon configuration (a document with `format: mvtrack.daemon/1`, see\n"
          "docs/DAEMON.md) is validated whole, with the calibration it names (relative to\n"
          "its own directory) and the tracker built from both, and its effective\n"
          "configuration is printed (what mvtrackd logs at start), with its hash.\n\n"
          "A site file for `mvtrack analytics` (format: mvtrack.site/1, docs/FORMATS.md\n"
          "\"Site file\") is validated and printed in its canonical form.\n\n"
          "Exit status: 0 valid, 1 invalid (the error is printed on stderr), 2 usage error.")) {
    return 0;
  }
  const std::string options_path = args.Get("OPTIONS.yaml");
  if (config::LooksLikeSite(ReadIfPossible(options_path))) {
    try {
      const analytics::Site site = config::LoadSiteFile(options_path);
      std::cout << config::SiteToYaml(site) << "# ok: " << options_path << ": site, "
                << site.regions.size() << " region(s), " << site.lines.size() << " line(s)\n";
      return 0;
    } catch (const config::ConfigError& e) {
      std::cerr << "mvtrack check-config: invalid: " << e.what() << "\n";
      return 1;
    }
  }
  if (service::LooksLikeDaemonConfig(ReadIfPossible(options_path))) {
    return CheckDaemonConfig(options_path, args.Has("calibration") ? args.Get("calibration") : "");
  }
  tracker::TrackerOptions options;
  config::CalibrationDocument calibration;
  try {
    options = config::LoadTrackerOptionsFile(options_path);
    if (args.Has("calibration")) {
      calibration = config::LoadCalibrationDocument(args.Get("calibration"));
    }
  } catch (const config::ConfigError& e) {
    std::cerr << "mvtrack check-config: invalid: " << e.what() << "\n";
    return 1;
  }

  std::ostringstream summary;
  summary << "# ok: " << options_path << ": mode " << config::InputModeName(options.mode);
  if (options.mode == tracker::InputMode::kPoses) {
    summary << ", layout " << formats::LayoutName(options.layout);
  } else {
    summary << ", box point " << config::BoxPointName(options.box_point);
  }
  summary << ", window " << options.window_size << "/" << options.window_step << " frames";
  if (args.Has("calibration")) {
    std::string why;
    const std::size_t num_cameras = calibration.cameras.size();
    std::string ids;
    for (const geometry::CameraModel& c : calibration.cameras) {
      ids += (ids.empty() ? "" : ", ") + std::to_string(c.id);
    }
    geometry::CameraRig rig(std::move(calibration.cameras), &why);
    if (!rig.ok()) {
      std::cerr << "mvtrack check-config: invalid: " << args.Get("calibration") << ": " << why
                << "\n";
      return 1;
    }
    if (!tracker::Tracker::Create(rig, options, &why)) {
      std::cerr << "mvtrack check-config: invalid: " << args.Get("calibration") << " with "
                << options_path << ": " << why << "\n";
      return 1;
    }
    summary << "; " << args.Get("calibration") << ": " << num_cameras << " camera(s) (ids " << ids
            << ")";
  }
  std::cout << config::TrackerOptionsToYaml(options) << summary.str() << "\n";
  return 0;
}

}  // namespace mvtrack::cli
