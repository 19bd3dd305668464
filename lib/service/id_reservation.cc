#include "service/id_reservation.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

namespace mvtrack::service {
namespace {

constexpr std::int64_t kMaxId = std::numeric_limits<std::int64_t>::max() / 2;

}  // namespace

bool IdReservation::Open(const std::filesystem::path& directory,
                         std::int64_t block,
                         std::string* why) {
  file_ = directory / "track_ids";
  block_ = block < 1 ? 1 : block;
  first_id_ = 1;
  std::error_code ec;
  if (std::filesystem::exists(file_, ec)) {
    std::ifstream in(file_, std::ios::binary);
    if (!in) {
      *why = file_.string() + ": cannot read the track id reservation";
      return false;
    }
    std::string format, line;
    std::getline(in, format);
    std::getline(in, line);
    constexpr std::string_view kKey = "reserved_end=";
    std::int64_t end = 0;
    const char* b = line.data() + kKey.size();
    const char* e = line.data() + line.size();
    if (format != kFormat || line.compare(0, kKey.size(), kKey) != 0 ||
        std::from_chars(b, e, end).ptr != e || end < 1 || end > kMaxId) {
      *why = file_.string() + ": not a " + kFormat +
             " file with reserved_end=N, 1 <= N <= " + std::to_string(kMaxId) +
             " (remove it to start ids at 1 again)";
      return false;
    }
    first_id_ = end;
  } else if (ec) {
    *why = file_.string() + ": " + ec.message();
    return false;
  }
  reserved_end_ = first_id_;
  if (first_id_ > kMaxId - block_) {
    *why = file_.string() + ": the track id space is exhausted";
    return false;
  }
  return Store(first_id_ + block_, why);
}

bool IdReservation::Extend(TrackId3D next_id, std::string* why) {
  if (next_id + block_ / 2 < reserved_end_) return true;
  if (next_id > kMaxId - block_) {
    *why = file_.string() + ": the track id space is exhausted";
    return false;
  }
  return Store(next_id + block_, why);
}

bool IdReservation::Store(TrackId3D end, std::string* why) {
  const std::filesystem::path tmp = file_.string() + ".tmp";
  const std::string text = std::string(kFormat) + "\nreserved_end=" + std::to_string(end) + "\n";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    *why = tmp.string() + ": " + std::strerror(errno);
    return false;
  }
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool synced = written && ::fsync(fd) == 0;
  const int saved_errno = errno;
  ::close(fd);
  if (!synced) {
    *why = tmp.string() + ": " + std::strerror(saved_errno);
    return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file_, ec);
  if (ec) {
    *why = file_.string() + ": " + ec.message();
    return false;
  }
  // The rename itself is durable once the directory is synced.
  const int dir = ::open(file_.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  reserved_end_ = end;
  return true;
}

}  // namespace mvtrack::service
