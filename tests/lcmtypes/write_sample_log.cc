// write_sample_log: writes the sample messages (sample_messages.h) to an LCM log through LCM's
// own file:// provider in write mode, and their canonical dump (the text DecodeLog.java and
// decode_log.py must print for that log) to a text file.
//
// Usage: mvtrack_lcmtypes_write_sample_log <out.lcmlog> <out_dump.txt>
// Exit status: 0 on success, 1 on any I/O or LCM error, 2 on bad usage.

#include <cstdio>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "lcmtypes/sample_messages.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: " << argv[0] << " <out.lcmlog> <out_dump.txt>\n";
    return 2;
  }
  const std::string log_path = argv[1];
  const std::string dump_path = argv[2];
  const auto events = mvtrack::lcmtypes_test::MakeSampleEvents();

  // Remove old outputs first so a failed run cannot leave stale files that later pass the
  // decode checks.
  std::remove(log_path.c_str());
  std::remove(dump_path.c_str());
  {
    lcm::LCM lc("file://" + log_path + "?mode=w");
    if (!lc.good()) {
      std::cerr << "cannot open LCM log for writing: " << log_path << "\n";
      return 1;
    }
    for (const auto& event : events) {
      if (lc.publish(event.channel,
                     event.bytes.data(),
                     static_cast<unsigned int>(event.bytes.size())) != 0) {
        std::cerr << "publishing to " << log_path << " failed on channel " << event.channel << "\n";
        return 1;
      }
    }
  }  // ~LCM closes and flushes the log

  std::ofstream dump(dump_path, std::ios::binary | std::ios::trunc);
  dump << mvtrack::lcmtypes_test::DumpEvents(events);
  dump.close();
  if (!dump) {
    std::cerr << "cannot write " << dump_path << "\n";
    return 1;
  }
  std::cout << "wrote " << events.size() << " events to " << log_path << " and their dump to "
            << dump_path << "\n";
  return 0;
}
