#pragma once
/// @file
/// The UDP receive buffer of a udpm:// input (issue 14, "losses you can see"): LCM asks the
/// kernel for the URL's `recv_buf_size`, and the kernel silently caps it at net.core.rmem_max,
/// so a burst larger than the buffer is lost before the daemon sees it, in no counter. The
/// daemon checks at start what it will get and says what to set.

#include <optional>
#include <string>

namespace mvtrack::service {

/// What ReceiveBufferAdvice found.
struct ReceiveBufferCheck {
  bool applies = false;     ///< a udpm:// URL (other providers have no such buffer)
  bool capped = false;      ///< the kernel limit is below the requested size: warn
  std::string message;      ///< one line for the log (empty when !applies)
};

/// For `url`: its `recv_buf_size` (bytes; absent: the kernel's default, net.core.rmem_default)
/// against the kernel's net.core.rmem_max, read from `rmem_max_path` (normally
/// /proc/sys/net/core/rmem_max; unreadable: the check says so). Pure apart from that read.
ReceiveBufferCheck CheckReceiveBuffer(const std::string& url,
                                      const std::string& rmem_max_path =
                                          "/proc/sys/net/core/rmem_max");

}  // namespace mvtrack::service
