#pragma once
/// @file
/// The UDP receive buffer of a udpm:// input (issue 14, "losses you can see"): LCM asks the
/// kernel for the URL's `recv_buf_size`, and the kernel silently caps it at net.core.rmem_max,
/// so a burst larger than the buffer is lost before the daemon sees it, in no counter. The
/// daemon checks at start what it will get and says what to set, and counts what the kernel
/// still drops (ProcessUdpDrops) in the status message and the summary.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mvtrack::service {

/// What ReceiveBufferAdvice found.
struct ReceiveBufferCheck {
  bool applies = false;  ///< a udpm:// URL (other providers have no such buffer)
  bool capped = false;   ///< the kernel limit is below the requested size: warn
  std::string message;   ///< one line for the log (empty when !applies)
};

/// For `url`: its `recv_buf_size` (bytes; absent: the kernel's default, net.core.rmem_default)
/// against the kernel's net.core.rmem_max, read from `rmem_max_path` (normally
/// /proc/sys/net/core/rmem_max; unreadable: the check says so). Pure apart from that read.
ReceiveBufferCheck CheckReceiveBuffer(
    const std::string& url, const std::string& rmem_max_path = "/proc/sys/net/core/rmem_max");

/// The datagrams the kernel dropped because a receive buffer was full, summed over the UDP
/// sockets this process holds: the `drops` column of `proc_root`/self/net/udp and udp6 for the
/// socket inodes among `proc_root`/self/fd. Cumulative over each socket's life; nullopt when
/// those files cannot be read (not Linux, no /proc). Reads a few small files: call it at the
/// status period, not per message.
std::optional<std::int64_t> ProcessUdpDrops(const std::string& proc_root = "/proc");

/// The pure part of ProcessUdpDrops: the sum of the `drops` column over the rows of `table`
/// (the text of /proc/net/udp or udp6, header line first) whose inode is in `sorted_inodes`.
/// Malformed rows are skipped.
std::int64_t SumUdpDrops(std::string_view table, const std::vector<std::uint64_t>& sorted_inodes);

}  // namespace mvtrack::service
