#pragma once
/// @file
/// The `mvtrack` command-line program: a thin dispatcher over one file per subcommand (as
/// colmap's exe/). Each subcommand is `int Run<Name>(int argc, char** argv)` with argv[0] being
/// the subcommand name; it prints its own --help and returns a process exit code.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "analytics/recording.h"
#include "eval/sequence.h"

namespace mvtrack::formats {
struct TrackFile;
}  // namespace mvtrack::formats

namespace mvtrack::cli {

/// Seconds of the steady clock since `start` (progress lines and timings).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Bad command-line usage: printed with the subcommand's usage line, exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A small strict argument parser: `--name value`, `--name=value`, `--flag`, positionals.
/// Unknown options are errors. Not thread-safe (used from main only).
class Args {
 public:
  /// Declares an option taking a value, or a boolean flag.
  Args& Option(const std::string& name,
               const std::string& help,
               const std::string& default_value = "");
  Args& Flag(const std::string& name, const std::string& help);
  Args& Positional(const std::string& name, const std::string& help, bool required = true);
  /// Declares that any number of positionals may follow the declared ones (GetRest).
  Args& Rest(const std::string& name, const std::string& help);

  /// Parses argv[1..argc); returns false if --help was given (help already printed).
  /// @throws UsageError on unknown options, missing values or missing positionals.
  bool Parse(int argc, char** argv, const std::string& usage_line, const std::string& description);

  std::string Get(const std::string& name) const;
  bool Has(const std::string& name) const;  ///< flag given, or option given explicitly
  double GetDouble(const std::string& name) const;
  std::int64_t GetInt(const std::string& name) const;
  /// The positionals after the declared ones (only with Rest), in order.
  const std::vector<std::string>& GetRest() const { return rest_; }
  std::string Help(const std::string& usage_line, const std::string& description) const;

 private:
  struct Spec {
    std::string help;
    std::string default_value;
    bool is_flag = false;
  };
  std::map<std::string, Spec> options_;
  std::vector<std::string> option_order_;
  std::vector<std::pair<std::string, std::string>> positional_specs_;
  std::vector<bool> positional_required_;
  std::optional<std::pair<std::string, std::string>> rest_spec_;
  std::vector<std::string> rest_;
  std::map<std::string, std::string> values_;
  std::map<std::string, bool> given_;
};

/// A non-negative decimal integer, the whole of `text`; nullopt otherwise.
std::optional<std::int64_t> ParseNonNegative(std::string_view text);

/// A finite decimal number (std::strtod's syntax), the whole of `text`; nullopt otherwise.
std::optional<double> ParseFinite(std::string_view text);

/// `text` split at every comma (empty parts kept).
std::vector<std::string_view> SplitCommas(std::string_view text);

/// Frame ranges "A-B[,C-D...]" (inclusive, a single frame "A" meaning A-A).
/// @throws UsageError naming `option` on a malformed or reversed range.
std::vector<eval::FrameRange> ParseFrameRanges(const std::string& text, const std::string& option);

/// Runs one subcommand: `run(argc, argv)` with the exit codes of every subcommand (a
/// UsageError prints "<program> <name>: <message>" and gives 2, another exception "... error:"
/// and 1) (args.cc; shared by `mvtrack` and `mvtrack-pictures`).
int RunSubcommand(
    const char* program, const char* name, int (*run)(int, char**), int argc, char** argv);

/// `mvtrack demo`: simulate a scene, track it, print tracks and accuracy (demo.cc).
int RunDemo(int argc, char** argv);
/// `mvtrack replay`: track a recorded detections log deterministically (replay.cc).
int RunReplay(int argc, char** argv);
/// `mvtrack eval`: score a track output against ground truth (eval.cc).
int RunEval(int argc, char** argv);
/// `mvtrack diff`: compare two track outputs frame by frame (diff.cc).
int RunDiff(int argc, char** argv);
/// `mvtrack analytics`: region visits and line crossings of tracks, as CSV and against ground
/// truth (analytics.cc). With --plots, mvtrack runs it in the helper mvtrack-pictures (OpenCV),
/// which gives it `plots` (analytics_plots.cc); `plots` null: --plots execs the helper.
int RunAnalytics(int argc, char** argv);
/// What draws the analytics pictures into a directory (called after the CSVs are written;
/// throws std::runtime_error when a picture cannot be written).
using AnalyticsPlots = void (*)(const std::string& dir,
                                const analytics::Site& site,
                                const std::vector<analytics::TimedPositions>& messages,
                                const analytics::RecordingAnalytics& result);
int RunAnalyticsWith(int argc, char** argv, AnalyticsPlots plots);
/// `mvtrack analytics` in mvtrack-pictures: with the pictures (analytics_plots.cc).
int RunAnalyticsPictures(int argc, char** argv);

/// `value` with `decimals` digits after the point ("%.*f"); "" when it is not finite (a figure
/// that does not exist, e.g. the median of no visits).
std::string Fixed(double value, int decimals);

/// The frames of `file` as an evaluation sequence of ids and footprints, joints dropped (eval.cc;
/// `mvtrack eval --points` and `mvtrack diff --layers`).
eval::EvalSequence FootprintSequence(const formats::TrackFile& file);

/// The helper mvtrack-pictures next to the running executable (build tree and install alike),
/// or "" when it is not there.
std::string PicturesHelper();
/// Replaces this process by `mvtrack-pictures COMMAND ARGS...` (`args` without the command);
/// returns 1 with a message on stderr when that is not possible.
int ExecPictures(const char* command, int argc, char** args);
/// `mvtrack check-config`: validate an options file (and a calibration) (check_config.cc).
int RunCheckConfig(int argc, char** argv);
/// `mvtrack convert`: datasets and JSON-lines detections -> detections log, calibration,
/// ground truth (convert.cc).
int RunConvert(int argc, char** argv);
/// `mvtrack sim`: write a simulated recording (detections log, calibration, ground truth)
/// (sim.cc).
int RunSim(int argc, char** argv);
/// `mvtrack bench`: throughput, latency and memory on simulated scenes, with accuracy
/// (bench.cc).
int RunBench(int argc, char** argv);
/// `mvtrack view`: render tracks (and detections, cameras) as PNG, contact sheet or MP4
/// (view.cc).
int RunView(int argc, char** argv);
/// `mvtrack calib`: import calibrations from other formats, check a calibration (calib.cc).
int RunCalib(int argc, char** argv);
/// `mvtrack web`: live floor view, /events, /metrics, /healthz over HTTP (web.cc, lib/web).
int RunWeb(int argc, char** argv);
/// `mvtrack status`: one status message for a person, monitoring-plugin exit code (status.cc).
int RunStatus(int argc, char** argv);

}  // namespace mvtrack::cli
