#pragma once
/// @file
/// Reading and writing LCM log files (the lcm-logger format) without LCM's receive thread, for
/// deterministic replay and for the log tools.
///
/// Format (lcm/eventlog.c), per event, big-endian: sync word 0xEDA1DA01, event number (int64),
/// timestamp (int64, µs), channel length (int32), data length (int32), channel, data.
///
/// LogWriter writes through lcm::LogFile, so its logs are LCM's own. LogReader frames the events
/// itself (pread on the file) instead of calling lcm::LogFile::readNextEvent(), because LCM
/// 1.3.1's reader is unfit for damaged or hostile logs (measured; log_io_test.cc pins the
/// non-crashing cases):
///  - it opens any readable file, and a file that is not a log yields no event: indistinguishable
///    from an empty log;
///  - it returns NULL for a truncated last event and for an invalid header, the same NULL as at
///    the end of the log, and prints to stderr;
///  - it drops a complete event when the 4 bytes after it are not a sync word
///    ("Invalid header after log data"): damage after event k loses event k too;
///  - a header whose data length is INT32_MAX makes it segfault when bytes follow (`datalen + 1`
///    overflows, calloc fails, fread writes through NULL).
/// LogReader tells those cases apart (end(), error()), returns every complete event before the
/// damage, and never allocates more than the file holds or max_event_bytes allows. Like LCM's
/// reader it resynchronises on the next sync word when bytes between events are not one; the
/// skipped bytes are counted (skipped_bytes()) so tools can refuse such logs.
///
/// Both classes are single-owner, single-threaded objects; the file is closed by the destructor.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lcm {
class LogFile;
}  // namespace lcm

namespace mvtrack::transport {

/// One event of an LCM log.
struct LogEvent {
  /// The event's timestamp, µs (lcm-logger writes the receive time on the logging host; our
  /// LogWriter writes whatever the caller passes, by convention the message's utime).
  std::int64_t timestamp_us = 0;
  std::string channel;
  /// The LCM payload (fingerprint + encoded message).
  std::vector<std::uint8_t> data;
  /// The event number written in the log (0, 1, 2, ... from the writer).
  std::int64_t event_number = 0;
};

/// Why LogReader::Next() stopped returning events.
enum class LogEnd {
  kNotEnded,   ///< more events may follow
  kEndOfLog,   ///< the log ended cleanly after a complete event (or was empty)
  kTruncated,  ///< the log ends inside an event (an interrupted writer); error() says where
  kCorrupt,    ///< an event header is invalid, or trailing bytes hold no event; error() says why
  kIoError,    ///< reading failed; error() says why
};

/// "not ended", "end of log", "truncated", "corrupt", "I/O error".
const char* ToString(LogEnd end);

/// Options of LogReader.
struct LogReaderOptions {
  /// Events whose data length exceeds this are corrupt (kCorrupt), bytes; at most
  /// INT32_MAX - 1 (LCM's reader allocates data length + 1 as an int).
  std::int64_t max_event_bytes = std::int64_t{64} << 20;

  /// True when 0 <= max_event_bytes <= INT32_MAX - 1; otherwise false with `why` set.
  bool Validate(std::string* why) const;
};

/// Sequential reader of an LCM log file.
class LogReader {
 public:
  /// Opens `path` for reading. Returns nullptr and sets `why` (when not null) when the file does
  /// not exist, is not a regular file, cannot be read, or does not start with the LCM sync word
  /// (not an LCM log). An empty file is an empty log. Invalid options abort (programmer error).
  static std::unique_ptr<LogReader> Open(const std::string& path,
                                         std::string* why,
                                         const LogReaderOptions& options = {});

  ~LogReader();
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;

  /// The next event, or nullopt once the log has ended (then end() says how; nullopt again on
  /// every later call).
  std::optional<LogEvent> Next();

  /// kNotEnded until Next() returned nullopt.
  LogEnd end() const { return end_; }
  /// Empty unless end() is kTruncated, kCorrupt or kIoError; then what, where and why.
  const std::string& error() const { return error_; }
  /// Bytes skipped between events while looking for the next sync word (0 for a clean log).
  std::int64_t skipped_bytes() const { return skipped_bytes_; }
  /// Events returned so far.
  std::int64_t events_read() const { return events_read_; }
  const std::string& path() const { return path_; }

 private:
  LogReader(std::string path, int fd, LogReaderOptions options);
  std::optional<LogEvent> Stop(LogEnd end, const std::string& error);

  std::string path_;
  int fd_ = -1;                ///< owned; closed by the destructor
  std::int64_t position_ = 0;  ///< byte offset of the next unread byte
  LogReaderOptions options_;
  LogEnd end_ = LogEnd::kNotEnded;
  std::string error_;
  std::int64_t skipped_bytes_ = 0;
  std::int64_t events_read_ = 0;
};

/// Writer of an LCM log file (lcm::LogFile in write mode; readable by lcm-logplayer, lcm-spy,
/// Python's lcm.EventLog and LogReader).
class LogWriter {
 public:
  /// Creates (or truncates) `path`. Returns nullptr and sets `why` (when not null) on failure.
  static std::unique_ptr<LogWriter> Open(const std::string& path, std::string* why);

  /// Flushes and closes the file (errors at this point are not reported: call Flush() first).
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  /// Appends one event; event numbers count from 0. Returns false with `why` set (when not null)
  /// when the channel is empty or 1000+ bytes long (LCM's readers reject such events), the data
  /// is longer than INT32_MAX - 1 bytes, the write fails, or an earlier write failed (a failed
  /// write may leave a partial event, so the writer refuses to continue).
  bool Write(std::string_view channel,
             std::int64_t timestamp_us,
             const std::uint8_t* data,
             std::size_t size,
             std::string* why);
  /// Same, for a byte vector.
  bool Write(std::string_view channel,
             std::int64_t timestamp_us,
             const std::vector<std::uint8_t>& data,
             std::string* why) {
    return Write(channel, timestamp_us, data.data(), data.size(), why);
  }

  /// Pushes buffered events to the operating system. Returns false with `why` set on failure.
  bool Flush(std::string* why);

  /// Events written so far.
  std::int64_t events_written() const { return events_written_; }
  const std::string& path() const { return path_; }

 private:
  LogWriter(std::string path, std::unique_ptr<lcm::LogFile> file);

  std::string path_;
  std::unique_ptr<lcm::LogFile> file_;
  std::int64_t events_written_ = 0;
  bool failed_ = false;
};

}  // namespace mvtrack::transport
