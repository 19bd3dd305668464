#include "service/receive_buffer.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

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
    c.message =
        "input: no recv_buf_size in the URL: the kernel's default UDP receive buffer "
        "applies (a burst larger than it is lost, counted as kernel_drops; e.g. "
        "?recv_buf_size=8388608 with net.core.rmem_max >= 8388608, docs/DAEMON.md)";
    return c;
  }
  if (*requested > *rmem_max) {
    c.capped = true;
    c.message =
        "input: recv_buf_size " + std::to_string(*requested) +
        " bytes, but the kernel caps it at net.core.rmem_max = " + std::to_string(*rmem_max) +
        ": set `sysctl -w net.core.rmem_max=" + std::to_string(*requested) +
        "` (and in /etc/sysctl.d/) or lower recv_buf_size";
    return c;
  }
  c.message = "input: UDP receive buffer " + std::to_string(*requested) +
              " bytes (net.core.rmem_max " + std::to_string(*rmem_max) + ")";
  return c;
}

std::int64_t SumUdpDrops(std::string_view table, const std::vector<std::uint64_t>& sorted_inodes) {
  // Columns: sl local_address rem_address st tx_queue:rx_queue tr:tm->when retrnsmt uid timeout
  // inode ref pointer drops (Linux since 2.6.27).
  constexpr std::size_t kInode = 9, kDrops = 12;
  std::int64_t sum = 0;
  std::size_t begin = table.find('\n');  // the header line
  while (begin != std::string_view::npos && begin < table.size()) {
    const std::size_t end = table.find('\n', begin + 1);
    std::istringstream row(std::string(table.substr(
        begin + 1, end == std::string_view::npos ? std::string_view::npos : end - begin - 1)));
    begin = end;
    std::vector<std::string> cols;
    for (std::string col; row >> col && cols.size() <= kDrops;) cols.push_back(col);
    if (cols.size() <= kDrops) continue;
    std::uint64_t inode = 0;
    std::int64_t drops = 0;
    const std::string& ci = cols[kInode];
    const std::string& cd = cols[kDrops];
    if (std::from_chars(ci.data(), ci.data() + ci.size(), inode).ptr != ci.data() + ci.size() ||
        std::from_chars(cd.data(), cd.data() + cd.size(), drops).ptr != cd.data() + cd.size() ||
        drops < 0) {
      continue;
    }
    if (std::binary_search(sorted_inodes.begin(), sorted_inodes.end(), inode)) {
      sum = drops > INT64_MAX - sum ? INT64_MAX : sum + drops;
    }
  }
  return sum;
}

std::optional<std::int64_t> ProcessUdpDrops(const std::string& proc_root) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::uint64_t> inodes;
  fs::directory_iterator it(fs::path(proc_root) / "self" / "fd", ec);
  if (ec) return std::nullopt;
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) return std::nullopt;
    std::error_code link_ec;
    const std::string target = fs::read_symlink(it->path(), link_ec).string();
    constexpr std::string_view kPrefix = "socket:[";
    if (link_ec || target.size() < kPrefix.size() + 2 || target.rfind(kPrefix, 0) != 0 ||
        target.back() != ']') {
      continue;
    }
    std::uint64_t inode = 0;
    const char* first = target.data() + kPrefix.size();
    const char* last = target.data() + target.size() - 1;
    if (std::from_chars(first, last, inode).ptr == last) inodes.push_back(inode);
  }
  std::sort(inodes.begin(), inodes.end());
  std::int64_t sum = 0;
  bool any = false;
  for (const char* name : {"udp", "udp6"}) {
    std::ifstream in(fs::path(proc_root) / "self" / "net" / name, std::ios::binary);
    if (!in) continue;
    std::ostringstream text;
    text << in.rdbuf();
    any = true;
    const std::int64_t d = SumUdpDrops(text.str(), inodes);
    sum = d > INT64_MAX - sum ? INT64_MAX : sum + d;
  }
  if (!any) return std::nullopt;
  return sum;
}

}  // namespace mvtrack::service
