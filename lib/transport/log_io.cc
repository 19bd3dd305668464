#include "transport/log_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <system_error>
#include <utility>
#include <vector>

#include "core/check.h"

namespace mvtrack::transport {
namespace {

// The LCM log format (lcm/eventlog.c): per event, big-endian
//   sync word 0xEDA1DA01 (4) | event number (8) | timestamp (8) | channel length (4) |
//   data length (4) | channel bytes | data bytes.
constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::int64_t kSyncBytes = 4;
constexpr std::int64_t kHeaderBytes = kSyncBytes + 8 + 8 + 4 + 4;
// LCM's reader rejects channel lengths outside [1, 999].
constexpr std::int64_t kMaxChannelBytes = 999;

// strerror's text, thread-safely.
std::string ErrnoText(int error) {
  return std::error_code(error, std::generic_category()).message();
}

// Reads exactly `size` bytes at `offset` of `fd` (pread: no shared file offset to keep in sync).
bool ReadAt(int fd, std::int64_t offset, std::uint8_t* buffer, std::size_t size, int* error) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(
        fd, buffer + done, size - done, static_cast<off_t>(offset) + static_cast<off_t>(done));
    if (n < 0) {
      if (errno == EINTR) continue;
      *error = errno;
      return false;
    }
    if (n == 0) {
      *error = 0;  // unexpected end of file
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::uint64_t BigEndian(const std::uint8_t* bytes, std::size_t count) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < count; ++i) value = (value << 8u) | bytes[i];
  return value;
}

std::string HexBytes(const std::uint8_t* bytes, std::size_t count) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) text.push_back(' ');
    text.push_back(kDigits[bytes[i] >> 4u]);
    text.push_back(kDigits[bytes[i] & 0xFu]);
  }
  return text;
}

std::string At(std::int64_t offset) { return "byte " + std::to_string(offset); }

}  // namespace

const char* ToString(LogEnd end) {
  switch (end) {
    case LogEnd::kNotEnded:
      return "not ended";
    case LogEnd::kEndOfLog:
      return "end of log";
    case LogEnd::kTruncated:
      return "truncated";
    case LogEnd::kCorrupt:
      return "corrupt";
    case LogEnd::kIoError:
      return "I/O error";
  }
  return "unknown";
}

bool LogReaderOptions::Validate(std::string* why) const {
  if (max_event_bytes < 0 || max_event_bytes > std::int64_t{INT32_MAX} - 1) {
    if (why != nullptr) *why = "LogReaderOptions: max_event_bytes must be in [0, INT32_MAX - 1]";
    return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// LogReader

LogReader::LogReader(std::string path, int fd, LogReaderOptions options)
    : path_(std::move(path)), fd_(fd), options_(options) {}

LogReader::~LogReader() {
  if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<LogReader> LogReader::Open(const std::string& path,
                                           std::string* why,
                                           const LogReaderOptions& options) {
  std::string options_why;
  MVTRACK_CHECK_MSG(options.Validate(&options_why), options_why.c_str());
  auto fail = [&](const std::string& message) {
    if (why != nullptr) *why = message;
    return std::unique_ptr<LogReader>();
  };
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    return fail("cannot open log '" + path + "': no such file");
  }
  if (!std::filesystem::is_regular_file(status)) {
    return fail("cannot open log '" + path + "': not a regular file");
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fail("cannot open log '" + path + "': " + ErrnoText(errno));
  // Owned from here on: the reader (or this early exit) closes it.
  std::unique_ptr<LogReader> reader(new LogReader(path, fd, options));
  struct stat st {};
  if (::fstat(fd, &st) != 0) return fail("cannot stat log '" + path + "': " + ErrnoText(errno));
  const auto size = static_cast<std::int64_t>(st.st_size);
  if (size > 0) {
    std::array<std::uint8_t, kSyncBytes> head{};
    const auto n = static_cast<std::size_t>(std::min<std::int64_t>(size, kSyncBytes));
    int error = 0;
    if (!ReadAt(fd, 0, head.data(), n, &error)) {
      return fail("cannot read log '" + path +
                  "': " + (error != 0 ? ErrnoText(error) : std::string("unexpected end of file")));
    }
    if (n < static_cast<std::size_t>(kSyncBytes) ||
        static_cast<std::uint32_t>(BigEndian(head.data(), head.size())) != kSyncWord) {
      return fail("'" + path + "' is not an LCM log: it does not start with the LCM sync word " +
                  "ed a1 da 01 (its first bytes are " + HexBytes(head.data(), n) + ")");
    }
  }
  return reader;
}

std::optional<LogEvent> LogReader::Stop(LogEnd end, const std::string& error) {
  end_ = end;
  error_ = error.empty() ? std::string() : "log '" + path_ + "': " + error;
  return std::nullopt;
}

std::optional<LogEvent> LogReader::Next() {
  if (end_ != LogEnd::kNotEnded) return std::nullopt;
  struct stat st {};
  if (::fstat(fd_, &st) != 0) return Stop(LogEnd::kIoError, "fstat failed: " + ErrnoText(errno));
  const auto size = static_cast<std::int64_t>(st.st_size);
  const std::int64_t pos = position_;
  if (pos >= size) return Stop(LogEnd::kEndOfLog, "");

  // The next sync word at or after `pos` (a rolling 32-bit window, as LCM scans). Fast path: an
  // event starts right here.
  std::int64_t sync_at = -1;
  {
    std::array<std::uint8_t, kSyncBytes> head{};
    int error = 0;
    if (size - pos >= kSyncBytes && ReadAt(fd_, pos, head.data(), head.size(), &error) &&
        static_cast<std::uint32_t>(BigEndian(head.data(), head.size())) == kSyncWord) {
      sync_at = pos;
    }
  }
  if (sync_at < 0) {
    std::vector<std::uint8_t> chunk(std::size_t{1} << 16);
    std::uint32_t window = 0;
    std::int64_t offset = pos;
    while (offset < size && sync_at < 0) {
      const auto n = static_cast<std::size_t>(
          std::min<std::int64_t>(size - offset, static_cast<std::int64_t>(chunk.size())));
      int error = 0;
      if (!ReadAt(fd_, offset, chunk.data(), n, &error)) {
        return Stop(LogEnd::kIoError,
                    "read failed at " + At(offset) + ": " +
                        (error != 0 ? ErrnoText(error) : "end of file"));
      }
      for (std::size_t i = 0; i < n; ++i) {
        window = (window << 8u) | chunk[i];
        // The window holds 4 bytes read from `pos` on once offset + i - pos >= 3.
        if (window == kSyncWord && offset + static_cast<std::int64_t>(i) - pos >= kSyncBytes - 1) {
          sync_at = offset + static_cast<std::int64_t>(i) + 1 - kSyncBytes;
          break;
        }
      }
      offset += static_cast<std::int64_t>(n);
    }
  }
  if (sync_at < 0) {
    const std::int64_t tail = size - pos;
    if (tail < kSyncBytes) {
      std::array<std::uint8_t, kSyncBytes> bytes{};
      const std::array<std::uint8_t, kSyncBytes> sync = {0xED, 0xA1, 0xDA, 0x01};
      int error = 0;
      if (ReadAt(fd_, pos, bytes.data(), static_cast<std::size_t>(tail), &error) &&
          std::equal(bytes.begin(), bytes.begin() + tail, sync.begin())) {
        return Stop(LogEnd::kTruncated,
                    "the log ends inside the sync word of an event at " + At(pos));
      }
    }
    return Stop(LogEnd::kCorrupt,
                "the last " + std::to_string(tail) + " bytes (from " + At(pos) +
                    ") contain no LCM sync word");
  }
  if (sync_at + kHeaderBytes > size) {
    return Stop(LogEnd::kTruncated,
                "the event at " + At(sync_at) + " is cut off inside its header (the log ends at " +
                    At(size) + ")");
  }
  std::array<std::uint8_t, kHeaderBytes - kSyncBytes> header{};
  int error = 0;
  if (!ReadAt(fd_, sync_at + kSyncBytes, header.data(), header.size(), &error)) {
    return Stop(
        LogEnd::kIoError,
        "read failed at " + At(sync_at) + ": " + (error != 0 ? ErrnoText(error) : "end of file"));
  }
  const auto event_number = static_cast<std::int64_t>(BigEndian(header.data(), 8));
  const auto timestamp = static_cast<std::int64_t>(BigEndian(header.data() + 8, 8));
  const auto channel_length =
      static_cast<std::int32_t>(static_cast<std::uint32_t>(BigEndian(header.data() + 16, 4)));
  const auto data_length =
      static_cast<std::int32_t>(static_cast<std::uint32_t>(BigEndian(header.data() + 20, 4)));
  const std::string event = "event " + std::to_string(event_number) + " at " + At(sync_at);
  if (channel_length < 1 || channel_length > kMaxChannelBytes) {
    return Stop(LogEnd::kCorrupt,
                event + ": channel length " + std::to_string(channel_length) + " is outside [1, " +
                    std::to_string(kMaxChannelBytes) + "]");
  }
  if (data_length < 0 || data_length > options_.max_event_bytes) {
    return Stop(LogEnd::kCorrupt,
                event + ": data length " + std::to_string(data_length) + " is outside [0, " +
                    std::to_string(options_.max_event_bytes) + "]");
  }
  const std::int64_t body_at = sync_at + kHeaderBytes;
  const std::int64_t event_end = body_at + channel_length + data_length;
  if (event_end > size) {
    return Stop(LogEnd::kTruncated,
                event + " needs " + std::to_string(event_end - sync_at) +
                    " bytes but the log ends after " + std::to_string(size - sync_at));
  }
  LogEvent out;
  out.timestamp_us = timestamp;
  out.event_number = event_number;
  out.channel.resize(static_cast<std::size_t>(channel_length));
  out.data.resize(static_cast<std::size_t>(data_length));
  if (!ReadAt(fd_,
              body_at,
              reinterpret_cast<std::uint8_t*>(out.channel.data()),
              out.channel.size(),
              &error) ||
      !ReadAt(fd_, body_at + channel_length, out.data.data(), out.data.size(), &error)) {
    return Stop(LogEnd::kIoError,
                "read failed in " + event + ": " + (error != 0 ? ErrnoText(error) : "end of file"));
  }
  skipped_bytes_ += sync_at - pos;
  position_ = event_end;
  ++events_read_;
  return out;
}

// ---------------------------------------------------------------------------------------------
// LogWriter

LogWriter::LogWriter(std::string path, std::unique_ptr<lcm::LogFile> file)
    : path_(std::move(path)), file_(std::move(file)) {}

LogWriter::~LogWriter() = default;

std::unique_ptr<LogWriter> LogWriter::Open(const std::string& path, std::string* why) {
  errno = 0;
  auto file = std::make_unique<lcm::LogFile>(path, "w");
  if (!file->good()) {
    const int error = errno;
    if (why != nullptr) {
      *why = "cannot create log '" + path +
             "': " + (error != 0 ? ErrnoText(error) : std::string("lcm::LogFile failed"));
    }
    return nullptr;
  }
  return std::unique_ptr<LogWriter>(new LogWriter(path, std::move(file)));
}

bool LogWriter::Write(std::string_view channel,
                      std::int64_t timestamp_us,
                      const std::uint8_t* data,
                      std::size_t size,
                      std::string* why) {
  auto fail = [&](const std::string& message) {
    if (why != nullptr) *why = "log '" + path_ + "': " + message;
    return false;
  };
  if (failed_) return fail("an earlier write failed; the log may end in a partial event");
  if (channel.empty() || channel.size() > static_cast<std::size_t>(kMaxChannelBytes)) {
    return fail("channel name of " + std::to_string(channel.size()) +
                " bytes is outside [1, 999] (LCM log readers reject it)");
  }
  if (size > static_cast<std::size_t>(INT32_MAX) - 1) {
    return fail("event of " + std::to_string(size) + " bytes is too large for an LCM log");
  }
  std::uint8_t empty_payload = 0;
  lcm::LogEvent event;
  event.eventnum = 0;  // assigned by LCM
  event.timestamp = timestamp_us;
  event.channel.assign(channel.data(), channel.size());
  event.datalen = static_cast<std::int32_t>(size);
  // LCM only reads the payload; its C API is not const-correct.
  event.data = size > 0 ? const_cast<std::uint8_t*>(data) : &empty_payload;
  errno = 0;
  if (file_->writeEvent(&event) != 0) {
    failed_ = true;
    const int error = errno;
    return fail("write failed: " + (error != 0 ? ErrnoText(error) : std::string("unknown")));
  }
  ++events_written_;
  return true;
}

bool LogWriter::Flush(std::string* why) {
  if (std::fflush(file_->getFilePtr()) != 0) {
    const int error = errno;
    failed_ = true;
    if (why != nullptr) *why = "log '" + path_ + "': flush failed: " + ErrnoText(error);
    return false;
  }
  return true;
}

}  // namespace mvtrack::transport
