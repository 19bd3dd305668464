#include "service/receive_buffer.h"

#include <charconv>
#include <cstdint>
#include <fstream>

namespace mvtrack::service {
namespace {

// The value of `key`=... in the URL's query, if present.
std::optional<std::string> QueryValue(const std::string& url, const std::string& key) {
  const std::size_t q = url.find('?');
  if (q == std::string::npos) return std::nullopt;
  std::size_t pos = q + 1;
  while (pos <= url.size()) {
    const std::size_t amp = url.find('&', pos);
    const std::string item =
        url.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
    if (item.compare(0, key.size() + 1, key + "=") == 0) return item.substr(key.size() + 1);
    if (amp == std::string::npos) break;
    pos = amp + 1;
  }
  return std::nullopt;
}

std::optional<std::int64_t> ParseBytes(const std::string& text) {
  std::int64_t v = 0;
  const char* end = text.data() + text.size();
  if (text.empty() || std::from_chars(text.data(), end, v).ptr != end || v < 0) {
    return std::nullopt;
  }
  return v;
}

}  // namespace

ReceiveBufferCheck CheckReceiveBuffer(const std::string& url, const std::string& rmem_max_path) {
  ReceiveBufferCheck c;
  if (url.rfind("udpm://", 0) != 0) return c;
  c.applies = true;
  std::optional<std::int64_t> rmem_max;
  {
    std::ifstream in(rmem_max_path);
    std::string line;
    if (in && std::getline(in, line)) rmem_max = ParseBytes(line);
  }
  const std::optional<std::string> requested_text = QueryValue(url, "recv_buf_size");
  const std::optional<std::int64_t> requested =
      requested_text ? ParseBytes(*requested_text) : std::nullopt;
  if (requested_text && !requested) {
    c.capped = true;
    c.message = "input: recv_buf_size=" + *requested_text + " is not a byte count";
    return c;
  }
  if (!rmem_max) {
    c.message = "input: cannot read " + rmem_max_path +
                ": the UDP receive buffer the kernel grants is unknown";
    return c;
  }
  if (!requested) {
    c.message = "input: no recv_buf_size in the URL: the kernel's default UDP receive buffer "
                "applies (a burst larger than it is lost unseen; e.g. ?recv_buf_size=8388608 with "
                "net.core.rmem_max >= 8388608, docs/DAEMON.md)";
    return c;
  }
  if (*requested > *rmem_max) {
    c.capped = true;
    c.message = "input: recv_buf_size " + std::to_string(*requested) +
                " bytes, but the kernel caps it at net.core.rmem_max = " +
                std::to_string(*rmem_max) + ": set `sysctl -w net.core.rmem_max=" +
                std::to_string(*requested) + "` (and in /etc/sysctl.d/) or lower recv_buf_size";
    return c;
  }
  c.message = "input: UDP receive buffer " + std::to_string(*requested) +
              " bytes (net.core.rmem_max " + std::to_string(*rmem_max) + ")";
  return c;
}

}  // namespace mvtrack::service
