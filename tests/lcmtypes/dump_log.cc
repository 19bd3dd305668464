// Test helper: the canonical dump (sample_messages.h) of every event of an LCM log, decoded
// with the generated C++ types, in the format DecodeLog.java prints, so a log recorded by the
// project's programs (mvtrackd --record, mvtrack replay/convert) can be decoded in Java with
// lcm-spy's class path and compared field by field.
//
//   dump_log LOG OUT_DUMP [--channels OUT_CHANNELS]
//
// Reads LOG with transport::LogReader (it must end cleanly), decodes each event by its
// fingerprint as tracks3d_t, camera_detections_t, tracker_status_t or site_status_t (anything else
// is an error), and writes the dump; with --channels, one "<channel> <type> <count>" line per
// channel (sorted). Exit status 0 on success, 1 on a bad log or message, 2 on usage errors.

#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lcmtypes/sample_messages.h"
#include "transport/log_io.h"

namespace {

using mvtrack::lcmtypes_test::SampleEvent;

// Decodes `data` as Msg into `event`; false when the bytes do not decode completely.
template <typename Msg>
bool DecodeAs(const std::vector<std::uint8_t>& data, SampleEvent* event) {
  Msg msg;
  const int size = static_cast<int>(data.size());
  int used = -1;
  try {
    used = msg.decode(data.data(), 0, size);
  } catch (const std::exception&) {
    return false;
  }
  if (used != size) return false;
  event->type_name = Msg::getTypeName();
  event->fingerprint = Msg::getHash();
  event->dump = mvtrack::lcmtypes_test::Dump(msg);
  return true;
}

std::int64_t Fingerprint(const std::vector<std::uint8_t>& data) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < 8; ++i) v = (v << 8) | data[i];
  return static_cast<std::int64_t>(v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::strcmp(argv[3], "--channels") == 0)) {
    std::cerr << "usage: dump_log LOG OUT_DUMP [--channels OUT_CHANNELS]\n";
    return 2;
  }
  std::string why;
  const std::unique_ptr<mvtrack::transport::LogReader> reader =
      mvtrack::transport::LogReader::Open(argv[1], &why);
  if (!reader) {
    std::cerr << "dump_log: " << why << "\n";
    return 1;
  }
  std::vector<SampleEvent> events;
  std::map<std::string, std::pair<std::string, int>> channels;
  while (std::optional<mvtrack::transport::LogEvent> e = reader->Next()) {
    SampleEvent event;
    event.channel = e->channel;
    const std::string where =
        std::string(argv[1]) + ": event " + std::to_string(events.size()) + " on " + e->channel;
    if (e->data.size() < 8) {
      std::cerr << "dump_log: " << where << ": shorter than a fingerprint\n";
      return 1;
    }
    const std::int64_t fp = Fingerprint(e->data);
    bool ok = false;
    if (fp == mvtrack::tracks3d_t::getHash()) {
      ok = DecodeAs<mvtrack::tracks3d_t>(e->data, &event);
    } else if (fp == mvtrack::camera_detections_t::getHash()) {
      ok = DecodeAs<mvtrack::camera_detections_t>(e->data, &event);
    } else if (fp == mvtrack::tracker_status_t::getHash()) {
      ok = DecodeAs<mvtrack::tracker_status_t>(e->data, &event);
    } else if (fp == mvtrack::site_status_t::getHash()) {
      ok = DecodeAs<mvtrack::site_status_t>(e->data, &event);
    } else {
      std::cerr << "dump_log: " << where << ": not an mvtrack top-level type\n";
      return 1;
    }
    if (!ok) {
      std::cerr << "dump_log: " << where << ": does not decode\n";
      return 1;
    }
    auto& [type, count] = channels[e->channel];
    if (!type.empty() && type != event.type_name) {
      std::cerr << "dump_log: " << where << ": channel carries both " << type << " and "
                << event.type_name << "\n";
      return 1;
    }
    type = event.type_name;
    ++count;
    events.push_back(std::move(event));
  }
  if (reader->end() != mvtrack::transport::LogEnd::kEndOfLog || reader->skipped_bytes() != 0) {
    std::cerr << "dump_log: " << argv[1] << ": " << reader->error() << " (skipped "
              << reader->skipped_bytes() << " bytes)\n";
    return 1;
  }
  std::ofstream dump(argv[2], std::ios::binary | std::ios::trunc);
  dump << mvtrack::lcmtypes_test::DumpEvents(events);
  if (!dump.flush()) {
    std::cerr << "dump_log: cannot write " << argv[2] << "\n";
    return 1;
  }
  if (argc == 5) {
    std::ofstream out(argv[4], std::ios::binary | std::ios::trunc);
    for (const auto& [channel, tc] : channels) {
      out << channel << " " << tc.first << " " << tc.second << "\n";
    }
    if (!out.flush()) {
      std::cerr << "dump_log: cannot write " << argv[4] << "\n";
      return 1;
    }
  }
  std::cout << "dump_log: " << events.size() << " events, " << channels.size() << " channels\n";
  return 0;
}
