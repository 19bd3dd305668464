// mvtrack-pictures: the subcommands that draw with OpenCV (bench's plot, view, calib check
// --png, analytics --plots), in their own executable so that `mvtrack` itself never loads OpenCV
// (issue 16: a replay's start-up was mostly OpenCV's libraries). `mvtrack bench|view|calib ...`
// runs this program with the same arguments; it can also be run directly.

#include <cstring>
#include <iostream>

#include "mvtrack/cli.h"

namespace {

struct Command {
  const char* name;
  int (*run)(int, char**);
};

constexpr Command kCommands[] = {
    {"bench", mvtrack::cli::RunBench},
    {"view", mvtrack::cli::RunView},
    {"calib", mvtrack::cli::RunCalib},
    {"analytics", mvtrack::cli::RunAnalyticsPictures},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2) {
    for (const Command& c : kCommands) {
      if (std::strcmp(argv[1], c.name) == 0) {
        return mvtrack::cli::RunSubcommand("mvtrack", c.name, c.run, argc - 1, argv + 1);
      }
    }
  }
  std::cerr << "usage: mvtrack-pictures bench|view|calib|analytics [options]   (run as mvtrack "
               "bench|view|calib, mvtrack analytics --plots; see mvtrack --help)\n";
  return 2;
}
