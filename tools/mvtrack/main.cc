// mvtrack: the command-line program. A thin dispatcher: one file per subcommand.

#include <cstring>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "core/suggest.h"
#include "mvtrack/cli.h"

namespace {

// A subcommand; run == nullptr: it lives in the mvtrack-pictures executable (it draws with
// OpenCV, which the other commands then never load).
struct Command {
  const char* name;
  const char* summary;
  int (*run)(int, char**);
};

constexpr Command kCommands[] = {
    {"demo", "simulate a small scene, track it, print tracks and accuracy", mvtrack::cli::RunDemo},
    {"replay", "track a recorded detections log (deterministic, offline)", mvtrack::cli::RunReplay},
    {"eval", "score tracks against ground truth (MOTA, IDF1, MPJPE, PCP)", mvtrack::cli::RunEval},
    {"diff", "compare two track outputs frame by frame", mvtrack::cli::RunDiff},
    {"analytics",
     "count region visits and line crossings of tracks (CSV; against ground truth)",
     mvtrack::cli::RunAnalytics},
    {"check-config",
     "validate a tracker options file (and a calibration)",
     mvtrack::cli::RunCheckConfig},
    {"convert",
     "convert a dataset or JSON-lines detections into a detections log",
     mvtrack::cli::RunConvert},
    {"sim",
     "write a simulated recording (detections log, calibration, ground truth)",
     mvtrack::cli::RunSim},
    {"bench", "measure speed, latency and memory on simulated scenes (with accuracy)", nullptr},
    {"view", "render tracks over the floor and the cameras (PNG, contact sheet, MP4)", nullptr},
    {"calib", "import a calibration from other formats; check a calibration", nullptr},
    {"web",
     "serve a live floor view, JSON events, metrics and health over HTTP",
     mvtrack::cli::RunWeb},
    {"status",
     "print the tracker's latest status; exit 0/1/2/3 (OK/WARNING/CRITICAL/UNKNOWN)",
     mvtrack::cli::RunStatus},
};

void PrintUsage(std::ostream& os) {
  os << "usage: mvtrack <command> [options]   (mvtrack <command> --help for details)\n\n"
        "Multi-view multi-person 3D tracking (Yang et al., the unified MM-tracking framework).\n\n"
        "commands:\n";
  for (const Command& c : kCommands)
    os << "  " << c.name << std::string(14 - std::strlen(c.name), ' ') << c.summary << "\n";
  os << "  version       print the version\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    PrintUsage(argc < 2 ? std::cerr : std::cout);
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "version") == 0 || std::strcmp(argv[1], "--version") == 0) {
    std::cout << "mvtrack " << MVTRACK_VERSION << "\n";
    return 0;
  }
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[1], c.name) != 0) continue;
    if (c.run != nullptr)
      return mvtrack::cli::RunSubcommand("mvtrack", c.name, c.run, argc - 1, argv + 1);
    return mvtrack::cli::ExecPictures(c.name, argc - 2, argv + 2);
  }
  std::vector<std::string> names;
  for (const Command& c : kCommands) names.emplace_back(c.name);
  const std::optional<std::string> close = mvtrack::core::SuggestClosest(argv[1], names);
  std::cerr << "mvtrack: unknown command '" << argv[1] << "'"
            << (close ? " (did you mean '" + *close + "'?)" : std::string()) << "\n\n";
  PrintUsage(std::cerr);
  return 2;
}
