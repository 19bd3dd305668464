// Daemon configuration: the example file, strictness (unknown keys, types, ranges, combinations)
// with file/line/key in the message, camera selection, the calibration override, the canonical
// text (round trip) and the hash.

#include "service/daemon_config.h"

#include <catch2/catch.hpp>
#include <string>

#include "config/calibration.h"
#include "config/config_error.h"
#include "config/config_test_util.h"

namespace mvtrack::service {
namespace {

using config::testing::TempDir;

constexpr char kCalibration[] = "calibration.example.yaml";

std::string ExampleDir() { return std::string(MVTRACK_SOURCE_DIR) + "/docs/examples"; }

// A minimal valid document using the example calibration (cameras 0, 1, 2).
std::string Minimal(const std::string& extra = "") {
  return "format: mvtrack.daemon/1\ncameras:\n  calibration: " + std::string(kCalibration) + "\n" +
         extra;
}

DaemonConfig Parse(const std::string& text) {
  return ParseDaemonConfig(text, "test.yaml", ExampleDir());
}

// The ConfigError of parsing `text`, which must fail.
config::ConfigError ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const config::ConfigError& e) {
    return e;
  }
  FAIL("expected a ConfigError for:\n" << text);
  throw std::logic_error("unreachable");
}

TEST_CASE("daemon config: the example file is valid and documents the defaults", "[unit]") {
  const DaemonConfig c = LoadDaemonConfigFile(ExampleDir() + "/mvtrackd.yaml");
  const DaemonConfig defaults = Parse(Minimal());
  CHECK(c.cameras.size() == 3);
  CHECK(c.calibration_path == ExampleDir() + "/" + kCalibration);
  // Every value the example spells out is the default: its text equals the minimal file's,
  // apart from the source of the calibration path.
  CHECK(DaemonConfigToYaml(c) == DaemonConfigToYaml(defaults));
  CHECK(c.sync.mode == SyncMode::kFrameIndex);
  CHECK(c.camera_overflow == pipeline::OverflowPolicy::kDropOldest);
  CHECK(c.channel_mode == ChannelMode::kBoth);
  // LCM's subscription queue: 30 messages per camera unless set.
  CHECK(c.lcm_queue_capacity == 0);
  CHECK(LcmQueueCapacity(c) == static_cast<int>(30 * c.cameras.size()));
}

TEST_CASE("daemon config: values are read into every section", "[unit]") {
  const DaemonConfig c = Parse(
      Minimal("  ids: [2, 0]\n"
              "input:\n  lcm_url: \"memq://\"\n  channels: shared\n  max_detections: 50\n"
              "  lcm_queue_capacity: 77\n"
              "output:\n  lcm_url: \"file:///tmp/x.lcmlog?mode=w\"\n  tracks_channel: T\n"
              "  status_channel: S\n  status_period_s: 0.5\n  latency_limit_us: 7\n"
              "sync:\n  mode: utime\n  tolerance_us: 100\n  deadline_us: 1000\n  idle_flush_s: 0\n"
              "threads:\n  workers: 3\n  job_queue: 9\n"
              "queues:\n  camera_capacity: 2\n  camera_overflow: block\n"
              "logging:\n  level: debug\n  repeat_interval_s: 0.5\n"
              "tracker:\n  window_size: 20\n  window_step: 10\n"));
  REQUIRE(c.cameras.size() == 2);
  CHECK(c.cameras[0].id == 0);
  CHECK(c.cameras[1].id == 2);
  CHECK(c.input_url == "memq://");
  CHECK(c.channel_mode == ChannelMode::kShared);
  CHECK(c.max_detections_per_message == 50);
  CHECK(c.lcm_queue_capacity == 77);
  CHECK(LcmQueueCapacity(c) == 77);
  CHECK(c.output_url == "file:///tmp/x.lcmlog?mode=w");
  CHECK(c.tracks_channel == "T");
  CHECK(c.status_channel == "S");
  CHECK(c.status_period_s == 0.5);
  CHECK(c.latency_limit_us == 7);
  CHECK(c.sync.mode == SyncMode::kUtime);
  CHECK(c.sync.tolerance_us == 100);
  CHECK(c.sync.deadline_us == 1000);
  CHECK(c.sync.idle_flush_s == 0.0);
  CHECK(c.workers == 3);
  CHECK(c.EffectiveWorkers() == 3);
  CHECK(c.job_queue_capacity == 9);
  CHECK(c.camera_queue_capacity == 2);
  CHECK(c.camera_overflow == pipeline::OverflowPolicy::kBlock);
  CHECK(c.log_level == "debug");
  CHECK(c.log_repeat_interval_s == 0.5);
  CHECK(c.tracker.window_size == 20);
  CHECK(c.tracker.window_step == 10);
  // The canonical text reads back to the same configuration.
  const std::string text = DaemonConfigToYaml(c);
  CHECK(DaemonConfigToYaml(ParseDaemonConfig(text, "canonical.yaml", "")) == text);
}

TEST_CASE("daemon config: errors name the file, line, key and reason", "[unit]") {
  SECTION("unknown key with a suggestion") {
    const config::ConfigError e = ErrorOf(Minimal("sync:\n  deadline_usec: 5\n"));
    CHECK(e.file() == "test.yaml");
    CHECK(e.line() == 5);
    CHECK(e.key_path() == "sync.deadline_usec");
    CHECK_THAT(e.reason(), Catch::Contains("did you mean 'deadline_us'"));
  }
  SECTION("wrong type") {
    const config::ConfigError e = ErrorOf(Minimal("threads:\n  workers: four\n"));
    CHECK(e.key_path() == "threads.workers");
    CHECK(e.line() == 5);
  }
  SECTION("out of range") {
    CHECK(ErrorOf(Minimal("threads:\n  workers: 300\n")).key_path() == "threads.workers");
    CHECK(ErrorOf(Minimal("output:\n  status_period_s: 0\n")).key_path() ==
          "output.status_period_s");
    CHECK(ErrorOf(Minimal("sync:\n  deadline_us: 0\n")).key_path() == "sync.deadline_us");
  }
  SECTION("bad enum value") {
    const config::ConfigError e = ErrorOf(Minimal("queues:\n  camera_overflow: dropoldest\n"));
    CHECK_THAT(e.reason(), Catch::Contains("did you mean 'drop_oldest'"));
  }
  SECTION("inconsistent combinations") {
    CHECK_THAT(ErrorOf(Minimal("sync:\n  mode: utime\n  tolerance_us: 500\n  deadline_us: 500\n"))
                   .reason(),
               Catch::Contains("smaller than deadline_us"));
    CHECK_THAT(ErrorOf(Minimal("output:\n  tracks_channel: MVTRACK_DETECTIONS_3\n")).reason(),
               Catch::Contains("detections channel"));
    CHECK_THAT(ErrorOf(Minimal("output:\n  status_channel: MVTRACK_TRACKS\n")).reason(),
               Catch::Contains("different channels"));
    CHECK_THAT(ErrorOf(Minimal("output:\n  provisional_channel: MVTRACK_TRACKS\n")).reason(),
               Catch::Contains("the provisional layer needs its own channel"));
    CHECK_THAT(ErrorOf(Minimal("output:\n  tracks_channel: MVTRACK_TRACKS_NOW\n")).reason(),
               Catch::Contains("the provisional layer needs its own channel"));
    CHECK(Parse(Minimal()).provisional_channel == "MVTRACK_TRACKS_NOW");
    // A zone of a site (issue 43): its channels are namespaced, explicit ones kept.
    const DaemonConfig zoned = Parse("zone: east_2\n" + Minimal("output:\n  status_channel: S\n"));
    CHECK(zoned.zone == "east_2");
    CHECK(zoned.tracks_channel == "MVTRACK_TRACKS_EAST_2");
    CHECK(zoned.provisional_channel == "MVTRACK_TRACKS_NOW_EAST_2");
    CHECK(zoned.analytics_events_channel == "MVTRACK_ANALYTICS_EVENTS_EAST_2");
    CHECK(zoned.status_channel == "S");
    CHECK(ParseDaemonConfig(DaemonConfigToYaml(zoned), "again.yaml", "/").tracks_channel ==
          "MVTRACK_TRACKS_EAST_2");
    CHECK_THAT(ErrorOf("zone: East\n" + Minimal()).reason(), Catch::Contains("a zone name has"));
    CHECK(Parse(Minimal("output:\n  provisional_channel: \"\"\n")).provisional_channel.empty());
    CHECK_THAT(ErrorOf(Minimal("input:\n  lcm_url: \"http://x\"\n")).reason(),
               Catch::Contains("unsupported LCM URL"));
  }
  SECTION("cameras") {
    CHECK_THAT(ErrorOf(Minimal("  ids: [0, 7]\n")).reason(), Catch::Contains("not in"));
    CHECK_THAT(ErrorOf(Minimal("  ids: [1, 1]\n")).reason(), Catch::Contains("listed twice"));
    CHECK_THAT(ErrorOf(Minimal("  ids: [1]\n")).reason(), Catch::Contains("at least 2 cameras"));
    const config::ConfigError e =
        ErrorOf("format: mvtrack.daemon/1\ncameras:\n  calibration: missing.yaml\n");
    CHECK(e.key_path() == "cameras.calibration");
    CHECK_THAT(e.reason(), Catch::Contains("missing.yaml"));
  }
  SECTION("format") {
    CHECK(ErrorOf("cameras:\n  calibration: x\n").reason() == "missing required key 'format'");
    CHECK_THAT(ErrorOf("format: mvtrack.daemon/2\ncameras:\n  calibration: x\n").reason(),
               Catch::Contains("expected 'mvtrack.daemon/1'"));
    CHECK_THAT(ErrorOf("").reason(), Catch::Contains("empty document"));
  }
  SECTION("tracker options are checked as in a tracker options file") {
    const config::ConfigError e = ErrorOf(Minimal("tracker:\n  association:\n    lamda: 1\n"));
    CHECK(e.key_path() == "tracker.association.lamda");
  }
}

TEST_CASE("daemon config: the analytics site, its channels and its errors", "[unit]") {
  TempDir dir;
  const std::string cal_text =
      config::CalibrationToYaml(config::LoadCalibration(ExampleDir() + "/" + kCalibration));
  dir.Write(kCalibration, cal_text);
  dir.Write("site.yaml",
            "format: mvtrack.site/1\nregions:\n  - name: door\n"
            "    polygon: [[0, 0], [1, 0], [1, 1]]\n");
  const std::string path =
      dir.Write("d.yaml", Minimal("analytics:\n  site: site.yaml\n  counts_channel: COUNTS\n"));
  const DaemonConfig c = LoadDaemonConfigFile(path);
  CHECK(c.site_path == dir.File("site.yaml"));
  REQUIRE(c.site.regions.size() == 1);
  CHECK(c.site.regions[0].name == "door");
  CHECK(c.analytics_events_channel == "MVTRACK_ANALYTICS_EVENTS");
  CHECK(c.site_counts_channel == "COUNTS");
  CHECK(DaemonConfigToYaml(c).find("  site: \"" + dir.File("site.yaml") + "\"") !=
        std::string::npos);
  // The site is part of the hash.
  DaemonConfig other = c;
  other.site.regions[0].polygon[2].x() = 2.0;
  CHECK(DaemonConfigHash(c) != DaemonConfigHash(other));
  // A mistake in the site file is blamed on the site file.
  dir.Write("site.yaml", "format: mvtrack.site/1\nregion: []\n");
  try {
    LoadDaemonConfigFile(path);
    FAIL("a broken site was accepted");
  } catch (const config::ConfigError& e) {
    CHECK(e.file() == dir.File("site.yaml"));
    CHECK_THAT(e.reason(), Catch::Contains("did you mean 'regions'"));
  }
  // A channel taken twice.
  const config::ConfigError clash =
      ErrorOf(Minimal("analytics:\n  events_channel: MVTRACK_TRACKS\n"));
  CHECK(clash.key_path() == "analytics");
  CHECK_THAT(clash.reason(), Catch::Contains("must differ"));
}

TEST_CASE("daemon config: calibration override, detection and hash", "[unit]") {
  TempDir dir;
  const std::string cal_text =
      config::CalibrationToYaml(config::LoadCalibration(ExampleDir() + "/" + kCalibration));
  const std::string cal = dir.Write("other_cal.yaml", cal_text);
  const std::string path = dir.Write("d.yaml", Minimal());
  // The document's calibration does not exist next to d.yaml; the override is used instead.
  CHECK_THROWS_AS(LoadDaemonConfigFile(path), config::ConfigError);
  const DaemonConfig c = LoadDaemonConfigFile(path, cal);
  CHECK(c.calibration_path == cal);
  CHECK(c.cameras.size() == 3);
  // A broken override is blamed on its own file and line, not on d.yaml's cameras.calibration
  // line (issue 39).
  std::string broken_text = cal_text;
  const std::size_t k = broken_text.find("K: [[");
  REQUIRE(k != std::string::npos);
  broken_text.replace(k, 5, "K: [[-");
  const std::string broken = dir.Write("broken_cal.yaml", broken_text);
  try {
    LoadDaemonConfigFile(path, broken);
    FAIL("a broken calibration was accepted");
  } catch (const config::ConfigError& e) {
    const std::string what = e.what();
    CHECK(what.rfind(broken + ":", 0) == 0);
    CHECK(what.find("d.yaml") == std::string::npos);
  }

  CHECK(LooksLikeDaemonConfig(Minimal()));
  CHECK_FALSE(LooksLikeDaemonConfig("tracker:\n  window_size: 30\n"));
  CHECK_FALSE(LooksLikeDaemonConfig("format: [oops"));

  const DaemonConfig a = Parse(Minimal());
  DaemonConfig b = a;
  CHECK(DaemonConfigHash(a) == DaemonConfigHash(b));
  CHECK(DaemonConfigHash(a).size() == 16);
  b.tracker.association.lambda = 0.31;
  CHECK(DaemonConfigHash(a) != DaemonConfigHash(b));
  b = a;
  b.cameras[1].K(0, 0) += 1.0;
  CHECK(DaemonConfigHash(a) != DaemonConfigHash(b));
}

}  // namespace
}  // namespace mvtrack::service
