// Fuzz driver of the daemon's input (issue 14): feeds a real service::Service (the daemon's
// runtime, no LCM) N seeded mutations of a clean detections log's messages and checks that it
// neither crashes nor stops tracking; run it under the asan preset (ASan + UBSan) to check
// memory and arithmetic:
//
//   mvtrack_fuzz_messages CONFIG.yaml CLEAN.lcmlog N [SEED]
//
// Each message is the next clean message (in a loop over the log) or, with probability 1/2, a
// mutation of it: random bytes flipped, a truncation, random header fields (camera id, frame,
// utime: extreme int64 values included) re-encoded, a burst of copies, or random bytes. After
// the run the service must still publish tracks for a clean replay of the log. Prints the
// counters. Exit status 0 on success, 1 on failure, 2 on usage errors.

#include <cstdint>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "service/daemon_config.h"
#include "service/service.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"

namespace {

namespace service = mvtrack::service;
namespace transport = mvtrack::transport;

struct Message {
  std::string channel;
  std::vector<std::uint8_t> data;
};

std::int64_t Extreme(std::mt19937_64& rng) {
  static const std::int64_t kValues[] = {std::numeric_limits<std::int64_t>::min(),
                                         std::numeric_limits<std::int64_t>::max(),
                                         0,
                                         -1,
                                         1,
                                         std::int64_t{1} << 62,
                                         -(std::int64_t{1} << 62)};
  return kValues[rng() % (sizeof(kValues) / sizeof(kValues[0]))];
}

int Run(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::cerr << "usage: mvtrack_fuzz_messages CONFIG.yaml CLEAN.lcmlog N [SEED]\n";
    return 2;
  }
  const std::int64_t n = std::stoll(argv[3]);
  std::mt19937_64 rng(argc == 5 ? std::stoull(argv[4]) : 1);
  service::DaemonConfig config = service::LoadDaemonConfigFile(argv[1]);
  config.camera_overflow = mvtrack::pipeline::OverflowPolicy::kBlock;
  config.sync.idle_flush_s = 0.0;
  std::string why;
  std::unique_ptr<transport::LogReader> reader = transport::LogReader::Open(argv[2], &why);
  if (!reader) throw std::runtime_error(why);
  std::vector<Message> clean;
  std::vector<transport::DecodeResult> decoded;
  while (std::optional<transport::LogEvent> e = reader->Next()) {
    if (!transport::IsDetectionsChannel(e->channel)) continue;
    decoded.push_back(transport::DecodeCameraDetections(e->data.data(), e->data.size()));
    clean.push_back({e->channel, std::move(e->data)});
  }
  if (clean.empty()) throw std::runtime_error("no detections in the log");

  std::int64_t published = 0;
  service::ServiceHooks hooks;
  hooks.publish = [&](const std::string& channel, const std::vector<std::uint8_t>&) {
    if (channel == config.tracks_channel) ++published;
  };
  std::unique_ptr<service::Service> s = service::Service::Create(config, hooks, &why);
  if (!s) throw std::runtime_error(why);
  std::int64_t mutated = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i) % clean.size();
    const Message& m = clean[k];
    if (rng() % 2 == 0) {
      s->OnMessage(m.channel, m.data.data(), m.data.size());
      continue;
    }
    ++mutated;
    std::vector<std::uint8_t> bytes = m.data;
    std::string channel = m.channel;
    switch (rng() % 6) {
      case 0:  // flipped bytes
        for (int j = 0, flips = 1 + static_cast<int>(rng() % 8); j < flips; ++j) {
          if (bytes.empty()) break;
          bytes[rng() % bytes.size()] ^= static_cast<std::uint8_t>(1 + rng() % 255);
        }
        break;
      case 1:  // truncated
        bytes.resize(rng() % (bytes.size() + 1));
        break;
      case 2:  // random header values, re-encoded
        if (decoded[k].ok()) {
          mvtrack::core::CameraFrame f = decoded[k].frame;
          const auto shift = [&](std::int64_t range) {
            return static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(2 * range)) - range;
          };
          if (rng() % 2) f.utime = rng() % 3 ? f.utime + shift(3600000000) : Extreme(rng);
          if (rng() % 2) f.frame = rng() % 3 ? f.frame + shift(1000) : Extreme(rng);
          if (rng() % 4 == 0) f.camera_id = static_cast<mvtrack::CameraId>(rng() % 10);
          bytes = transport::EncodeCameraDetections(
              f, decoded[k].image_width_px, decoded[k].image_height_px);
          channel = transport::DetectionsChannelForCamera(f.camera_id);
        }
        break;
      case 3:  // a burst of copies of an old message
        for (int j = 0; j < 1 + static_cast<int>(rng() % 100); ++j) {
          const Message& old = clean[rng() % clean.size()];
          s->OnMessage(old.channel, old.data.data(), old.data.size());
        }
        break;
      case 4:  // random bytes
        bytes.assign(rng() % 512, 0);
        for (std::uint8_t& b : bytes) b = static_cast<std::uint8_t>(rng());
        break;
      default:  // the shared channel, another camera's channel, a foreign channel
        channel = rng() % 3 == 0 ? std::string("FOREIGN") : transport::kDetectionsChannel;
        break;
    }
    s->OnMessage(channel, bytes.data(), bytes.size());
    if (i % 10000 == 0) s->Tick();
  }
  s->EndOfInput();
  const std::int64_t before = published;
  // Still tracking: a clean pass of the log (the stream may restart for it) publishes tracks.
  for (const Message& m : clean) s->OnMessage(m.channel, m.data.data(), m.data.size());
  s->EndOfInput();
  const service::ServiceCounters c = s->Counters();
  std::cout << "messages " << c.messages << " (mutated " << mutated << "), decode_errors "
            << c.decode_errors << ", published frames " << published << " (" << before
            << " during the fuzzing)\n";
  if (published <= before) {
    std::cerr << "mvtrack_fuzz_messages: no tracks published for the clean pass after fuzzing\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "mvtrack_fuzz_messages: " << e.what() << "\n";
    return 1;
  }
}
