// LogWriter / LogReader against real LCM log files, including hostile and damaged ones.

#include "transport/log_io.h"

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/test_messages.h"

namespace mvtrack::transport {
namespace {

namespace fs = std::filesystem;
using testing::PutBigEndian;

// A scratch directory unique to this process and test case, removed on destruction.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("mvtrack_transport_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

struct Sample {
  std::string channel;
  std::int64_t timestamp_us;
  std::vector<std::uint8_t> data;
};

// Detections of three cameras and a tracks message, as a recording would hold them.
std::vector<Sample> MakeSamples() {
  std::vector<Sample> samples;
  for (int i = 0; i < 3; ++i) {
    core::CameraFrame frame = testing::MakeRealisticFrame(static_cast<std::uint32_t>(i));
    frame.camera_id = i;
    samples.push_back({DetectionsChannelForCamera(i),
                       frame.utime + i,
                       EncodeCameraDetections(frame, 1920, 1080)});
  }
  samples.push_back(
      {kTracksChannel,
       1'700'000'100'000'000,
       EncodeTracks(testing::MakeTracksFrame(1, true), core::KeypointLayoutId::kCoco17, 1, 2)});
  samples.push_back({kStatusChannel, 5, {}});  // an empty payload is a valid event
  return samples;
}

std::string WriteSampleLog(const ScratchDir& dir, const std::string& name) {
  const std::string path = dir.File(name);
  std::string why;
  std::unique_ptr<LogWriter> writer = LogWriter::Open(path, &why);
  REQUIRE(writer != nullptr);
  for (const Sample& s : MakeSamples()) {
    REQUIRE(writer->Write(s.channel, s.timestamp_us, s.data, &why));
  }
  REQUIRE(writer->Flush(&why));
  return path;
}

// Byte offsets at which each event of a log starts (sync word), plus the file size.
std::vector<std::size_t> EventStarts(const std::vector<Sample>& samples) {
  std::vector<std::size_t> starts;
  std::size_t pos = 0;
  for (const Sample& s : samples) {
    starts.push_back(pos);
    pos += 28 + s.channel.size() + s.data.size();
  }
  starts.push_back(pos);
  return starts;
}

TEST_CASE("LogWriter -> LogReader round trips channels, timestamps, payloads", "[unit]") {
  ScratchDir dir("roundtrip");
  const std::string path = WriteSampleLog(dir, "a.lcmlog");
  const std::vector<Sample> samples = MakeSamples();
  CHECK(fs::file_size(path) == EventStarts(samples).back());

  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
  REQUIRE(reader != nullptr);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::optional<LogEvent> event = reader->Next();
    REQUIRE(event.has_value());
    CHECK(event->channel == samples[i].channel);
    CHECK(event->timestamp_us == samples[i].timestamp_us);
    CHECK(event->data == samples[i].data);
    CHECK(event->event_number == static_cast<std::int64_t>(i));
  }
  CHECK_FALSE(reader->Next().has_value());
  CHECK(reader->end() == LogEnd::kEndOfLog);
  CHECK(reader->error().empty());
  CHECK(reader->skipped_bytes() == 0);
  CHECK(reader->events_read() == static_cast<std::int64_t>(samples.size()));
  CHECK_FALSE(reader->Next().has_value());  // stays ended

  // The payloads decode to what was encoded.
  reader = LogReader::Open(path, &why);
  const std::optional<LogEvent> first = reader->Next();
  REQUIRE(first.has_value());
  const DecodeResult decoded = DecodeCameraDetections(first->data.data(), first->data.size());
  REQUIRE(decoded.ok());
  CHECK(CameraIdFromChannel(first->channel) == decoded.frame.camera_id);
}

TEST_CASE("logs interoperate with LCM's own writer and reader", "[unit]") {
  ScratchDir dir("interop");
  const std::vector<Sample> samples = MakeSamples();
  // LCM's file:// provider in write mode (what a live daemon's recorder would produce).
  const std::string lcm_written = dir.File("lcm.lcmlog");
  {
    lcm::LCM lc("file://" + lcm_written + "?mode=w");
    REQUIRE(lc.good());
    for (const Sample& s : samples) {
      REQUIRE(lc.publish(s.channel, s.data.data(), static_cast<unsigned int>(s.data.size())) == 0);
    }
  }
  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(lcm_written, &why);
  REQUIRE(reader != nullptr);
  for (const Sample& s : samples) {
    const std::optional<LogEvent> event = reader->Next();
    REQUIRE(event.has_value());
    CHECK(event->channel == s.channel);
    CHECK(event->data == s.data);
  }
  CHECK_FALSE(reader->Next().has_value());
  CHECK(reader->end() == LogEnd::kEndOfLog);

  // Our writer's log, read by lcm::LogFile directly.
  const std::string ours = WriteSampleLog(dir, "ours.lcmlog");
  lcm::LogFile file(ours, "r");
  REQUIRE(file.good());
  for (const Sample& s : samples) {
    const lcm::LogEvent* event = file.readNextEvent();
    REQUIRE(event != nullptr);
    CHECK(event->channel == s.channel);
    CHECK(event->timestamp == s.timestamp_us);
    const auto* data = static_cast<const std::uint8_t*>(event->data);
    CHECK(std::vector<std::uint8_t>(data, data + event->datalen) == s.data);
  }
  CHECK(file.readNextEvent() == nullptr);
}

TEST_CASE("LogReader::Open explains missing, non-regular and non-LCM files", "[unit]") {
  ScratchDir dir("open_errors");
  std::string why;
  CHECK(LogReader::Open(dir.File("missing.lcmlog"), &why) == nullptr);
  CHECK_THAT(why, Catch::Matchers::Contains("missing.lcmlog': no such file"));

  CHECK(LogReader::Open(dir.File(""), &why) == nullptr);
  CHECK_THAT(why, Catch::Matchers::Contains("not a regular file"));

  const std::string json = dir.File("frames.jsonl");
  WriteBytes(json, {'{', '"', 'f', 'r', 'a', 'm', 'e', '"', ':', ' ', '1', '}', '\n'});
  CHECK(LogReader::Open(json, &why) == nullptr);
  CHECK_THAT(why, Catch::Matchers::Contains("is not an LCM log"));
  CHECK_THAT(why, Catch::Matchers::Contains("its first bytes are 7b 22 66 72"));
  // What LCM itself does with that file: no error, just no events (why Open checks).
  lcm::LogFile file(json, "r");
  CHECK(file.good());
  CHECK(file.readNextEvent() == nullptr);

  const std::string tiny = dir.File("tiny.lcmlog");
  WriteBytes(tiny, {0xED, 0xA1});
  CHECK(LogReader::Open(tiny, &why) == nullptr);
  CHECK_THAT(why, Catch::Matchers::Contains("its first bytes are ed a1"));

  // Unreadable: only meaningful when not running as root (root reads mode-000 files).
  if (::geteuid() != 0) {
    const std::string locked = WriteSampleLog(dir, "locked.lcmlog");
    fs::permissions(locked, fs::perms::none);
    CHECK(LogReader::Open(locked, &why) == nullptr);
    CHECK_THAT(why, Catch::Matchers::Contains("Permission denied"));
  } else {
    WARN("running as root: the unreadable-file case is not exercised");
  }
}

TEST_CASE("an empty file is an empty log", "[unit]") {
  ScratchDir dir("empty");
  const std::string path = dir.File("empty.lcmlog");
  WriteBytes(path, {});
  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
  REQUIRE(reader != nullptr);
  CHECK_FALSE(reader->Next().has_value());
  CHECK(reader->end() == LogEnd::kEndOfLog);
  CHECK(reader->error().empty());
}

TEST_CASE("a log cut at any byte ends cleanly with the complete events", "[unit]") {
  ScratchDir dir("truncated");
  // Small events (every cut is a separate file to read): payloads of 0, 5 and 60 bytes and a
  // real tracks message, channel names of different lengths.
  const std::vector<Sample> samples = {
      {kStatusChannel, 1, {}},
      {"A", 2, {1, 2, 3, 4, 5}},
      {DetectionsChannelForCamera(12), 3, std::vector<std::uint8_t>(60, 0xED)},
      {kTracksChannel,
       4,
       EncodeTracks(testing::MakeTracksFrame(2, false), core::KeypointLayoutId::kNone, 0, 0)}};
  const std::string full_path = dir.File("full.lcmlog");
  {
    std::string why;
    std::unique_ptr<LogWriter> writer = LogWriter::Open(full_path, &why);
    REQUIRE(writer != nullptr);
    for (const Sample& s : samples) REQUIRE(writer->Write(s.channel, s.timestamp_us, s.data, &why));
  }
  const std::vector<std::uint8_t> full = ReadBytes(full_path);
  const std::vector<std::size_t> starts = EventStarts(samples);
  REQUIRE(full.size() == starts.back());
  const std::string path = dir.File("cut.lcmlog");
  WriteBytes(path, full);
  // Shrink one file step by step (cheaper than writing a file per cut).
  for (std::size_t cut = full.size() + 1; cut-- > 0;) {
    fs::resize_file(path, cut);
    std::string why;
    std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
    INFO("cut at " << cut << ": " << why);
    if (cut > 0 && cut < 4) {  // not even a whole sync word: not recognisable as a log
      CHECK(reader == nullptr);
      continue;
    }
    REQUIRE(reader != nullptr);
    std::size_t events = 0;
    while (reader->Next()) ++events;
    const std::size_t complete = static_cast<std::size_t>(
        std::upper_bound(starts.begin() + 1, starts.end(), cut) - (starts.begin() + 1));
    const bool on_boundary = std::find(starts.begin(), starts.end(), cut) != starts.end();
    INFO("end: " << ToString(reader->end()) << " " << reader->error());
    REQUIRE(events == complete);
    if (on_boundary) {
      REQUIRE(reader->end() == LogEnd::kEndOfLog);
      REQUIRE(reader->error().empty());
    } else {
      REQUIRE(reader->end() == LogEnd::kTruncated);
      REQUIRE_THAT(reader->error(), Catch::Matchers::Contains("cut.lcmlog"));
    }
  }
}

// A log of one event whose header is patched at `offset` (relative to the event start).
std::vector<std::uint8_t> PatchedSingleEvent(std::size_t offset,
                                             std::uint64_t value,
                                             std::size_t width,
                                             std::size_t extra_bytes) {
  std::vector<std::uint8_t> log = {0xED, 0xA1, 0xDA, 0x01};
  log.resize(28, 0);
  PutBigEndian(&log, 12, 1000, 8);  // timestamp
  PutBigEndian(&log, 20, 3, 4);     // channel length
  PutBigEndian(&log, 24, 4, 4);     // data length
  log.insert(log.end(), {'A', 'B', 'C', 1, 2, 3, 4});
  PutBigEndian(&log, offset, value, width);
  log.insert(log.end(), extra_bytes, 7);
  return log;
}

TEST_CASE("hostile event headers are reported as corrupt, never allocated or crashed on",
          "[unit]") {
  ScratchDir dir("hostile");
  const std::string path = dir.File("hostile.lcmlog");
  struct Case {
    std::size_t offset;
    std::uint64_t value;
    std::string needle;
  };
  const Case cases[] = {
      // data length INT32_MAX with bytes after it: segfaults lcm::LogFile 1.3.1.
      {24, 0x7FFFFFFF, "data length 2147483647 is outside [0, 67108864]"},
      {24, 0xFFFFFFFF, "data length -1 is outside"},
      {20, 0, "channel length 0 is outside [1, 999]"},
      {20, 1000, "channel length 1000 is outside [1, 999]"},
      {20, 0x80000000, "channel length -2147483648 is outside"},
  };
  for (const Case& c : cases) {
    WriteBytes(path, PatchedSingleEvent(c.offset, c.value, 4, 200));
    std::string why;
    std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
    REQUIRE(reader != nullptr);
    CHECK_FALSE(reader->Next().has_value());
    CHECK(reader->end() == LogEnd::kCorrupt);
    CHECK_THAT(reader->error(), Catch::Matchers::Contains("event 0 at byte 0: " + c.needle));
  }
  // A data length within the limit but beyond the file is a truncation.
  WriteBytes(path, PatchedSingleEvent(24, 1000, 4, 0));
  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
  REQUIRE(reader != nullptr);
  CHECK_FALSE(reader->Next().has_value());
  CHECK(reader->end() == LogEnd::kTruncated);
  CHECK_THAT(reader->error(),
             Catch::Matchers::Contains("needs 1031 bytes but the log ends after 35"));
  // A lower max_event_bytes turns big events into corruption.
  LogReaderOptions options;
  options.max_event_bytes = 3;
  WriteBytes(path, PatchedSingleEvent(0, 0xEDA1DA01, 4, 0));
  reader = LogReader::Open(path, &why, options);
  REQUIRE(reader != nullptr);
  CHECK_FALSE(reader->Next().has_value());
  CHECK_THAT(reader->error(), Catch::Matchers::Contains("data length 4 is outside [0, 3]"));
}

TEST_CASE("garbage between events is skipped and counted, trailing garbage is corrupt", "[unit]") {
  ScratchDir dir("garbage");
  const std::vector<Sample> samples = MakeSamples();
  const std::vector<std::size_t> starts = EventStarts(samples);
  std::vector<std::uint8_t> log = ReadBytes(WriteSampleLog(dir, "clean.lcmlog"));
  // 13 junk bytes between events 1 and 2 and 9 after the last one.
  log.insert(log.begin() + static_cast<std::ptrdiff_t>(starts[2]), 13, 0x55);
  log.insert(log.end(), 9, 0x66);
  const std::string path = dir.File("junk.lcmlog");
  WriteBytes(path, log);
  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(path, &why);
  REQUIRE(reader != nullptr);
  std::vector<std::string> channels;
  while (std::optional<LogEvent> event = reader->Next()) channels.push_back(event->channel);
  REQUIRE(channels.size() == samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) CHECK(channels[i] == samples[i].channel);
  CHECK(reader->skipped_bytes() == 13);
  CHECK(reader->end() == LogEnd::kCorrupt);
  CHECK_THAT(reader->error(), Catch::Matchers::Contains("the last 9 bytes"));
  CHECK_THAT(reader->error(), Catch::Matchers::Contains("contain no LCM sync word"));
}

// Counts the events lcm::LogFile returns before its first NULL.
std::size_t LcmReadableEvents(const std::string& path) {
  lcm::LogFile file(path, "r");
  std::size_t n = 0;
  while (file.good() && file.readNextEvent() != nullptr) ++n;
  return n;
}

TEST_CASE("lcm::LogFile 1.3.1 loses events LogReader keeps (why LogReader frames itself)",
          "[unit]") {
  ScratchDir dir("lcm_behaviour");
  const std::vector<Sample> samples = MakeSamples();
  const std::vector<std::size_t> starts = EventStarts(samples);
  const std::vector<std::uint8_t> clean = ReadBytes(WriteSampleLog(dir, "clean.lcmlog"));
  CHECK(LcmReadableEvents(dir.File("clean.lcmlog")) == samples.size());

  // 4 junk bytes after event 1: LCM drops event 1 itself ("Invalid header after log data") and
  // reports it like the end of the log; LogReader returns events 0..4 and counts the junk.
  std::vector<std::uint8_t> junk = clean;
  junk.insert(junk.begin() + static_cast<std::ptrdiff_t>(starts[2]), 4, 0x55);
  const std::string junk_path = dir.File("junk.lcmlog");
  WriteBytes(junk_path, junk);
  CHECK(LcmReadableEvents(junk_path) == 1);
  std::string why;
  std::unique_ptr<LogReader> reader = LogReader::Open(junk_path, &why);
  REQUIRE(reader != nullptr);
  std::size_t n = 0;
  while (reader->Next()) ++n;
  CHECK(n == samples.size());
  CHECK(reader->skipped_bytes() == 4);
  CHECK(reader->end() == LogEnd::kEndOfLog);

  // A cut inside the last event: LCM's NULL looks like a clean end; LogReader says truncated.
  const std::string cut_path = dir.File("cut.lcmlog");
  WriteBytes(cut_path, std::vector<std::uint8_t>(clean.begin(), clean.end() - 2));
  CHECK(LcmReadableEvents(cut_path) == samples.size() - 1);
  reader = LogReader::Open(cut_path, &why);
  REQUIRE(reader != nullptr);
  n = 0;
  while (reader->Next()) ++n;
  CHECK(n == samples.size() - 1);
  CHECK(reader->end() == LogEnd::kTruncated);
}

TEST_CASE("LogWriter rejects events LCM readers cannot read and reports I/O errors", "[unit]") {
  ScratchDir dir("writer_errors");
  std::string why;
  CHECK(LogWriter::Open(dir.File("no/such/dir/x.lcmlog"), &why) == nullptr);
  CHECK_THAT(why, Catch::Matchers::Contains("No such file or directory"));

  std::unique_ptr<LogWriter> writer = LogWriter::Open(dir.File("w.lcmlog"), &why);
  REQUIRE(writer != nullptr);
  const std::vector<std::uint8_t> payload = {1, 2, 3};
  CHECK_FALSE(writer->Write("", 0, payload, &why));
  CHECK_THAT(why, Catch::Matchers::Contains("channel name of 0 bytes is outside [1, 999]"));
  CHECK_FALSE(writer->Write(std::string(1000, 'C'), 0, payload, &why));
  CHECK_THAT(why, Catch::Matchers::Contains("channel name of 1000 bytes"));
  CHECK(writer->Write(std::string(999, 'C'), 0, payload, &why));
  CHECK(writer->events_written() == 1);
  writer.reset();
  std::unique_ptr<LogReader> reader = LogReader::Open(dir.File("w.lcmlog"), &why);
  REQUIRE(reader != nullptr);
  const std::optional<LogEvent> event = reader->Next();
  REQUIRE(event.has_value());
  CHECK(event->channel.size() == 999);

  // A full device: the buffered write succeeds, the flush fails, the writer then refuses.
  if (fs::exists("/dev/full")) {
    writer = LogWriter::Open("/dev/full", &why);
    REQUIRE(writer != nullptr);
    CHECK(writer->Write("X", 0, payload, &why));
    CHECK_FALSE(writer->Flush(&why));
    CHECK_THAT(why, Catch::Matchers::Contains("No space left on device"));
    CHECK_FALSE(writer->Write("X", 0, payload, &why));
    CHECK_THAT(why, Catch::Matchers::Contains("an earlier write failed"));
  }
}

}  // namespace
}  // namespace mvtrack::transport
