// CheckReceiveBuffer: the udpm:// receive buffer against the kernel's net.core.rmem_max;
// ProcessUdpDrops: the kernel's receive drops of this process's UDP sockets.

#include "service/receive_buffer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "config/config_test_util.h"

namespace mvtrack::service {
namespace {

TEST_CASE("receive buffer: the kernel's cap is found and named with what to set", "[unit]") {
  config::testing::TempDir dir;
  const std::string rmem = dir.Write("rmem_max", "212992\n");
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";

  CHECK_FALSE(CheckReceiveBuffer("memq://", rmem).applies);
  CHECK_FALSE(CheckReceiveBuffer("file:///tmp/x.lcmlog?speed=0", rmem).applies);

  const ReceiveBufferCheck none = CheckReceiveBuffer(url, rmem);
  CHECK(none.applies);
  CHECK_FALSE(none.capped);
  CHECK_THAT(none.message, Catch::Contains("no recv_buf_size"));

  const ReceiveBufferCheck capped = CheckReceiveBuffer(url + "&recv_buf_size=8388608", rmem);
  CHECK(capped.capped);
  CHECK_THAT(capped.message, Catch::Contains("net.core.rmem_max = 212992"));
  CHECK_THAT(capped.message, Catch::Contains("sysctl -w net.core.rmem_max=8388608"));

  const ReceiveBufferCheck fine =
      CheckReceiveBuffer("udpm://239.255.76.67:7667?recv_buf_size=100000&ttl=0", rmem);
  CHECK_FALSE(fine.capped);
  CHECK_THAT(fine.message, Catch::Contains("100000 bytes"));

  CHECK(CheckReceiveBuffer(url + "&recv_buf_size=lots", rmem).capped);
  const ReceiveBufferCheck unknown = CheckReceiveBuffer(url, dir.File("missing"));
  CHECK_FALSE(unknown.capped);
  CHECK_THAT(unknown.message, Catch::Contains("cannot read"));
}

TEST_CASE("udp drops: the drops column is summed over the given inodes only", "[unit]") {
  const std::string table =
      "   sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  "
      "timeout inode ref pointer drops            \n"
      "  231: 00000000:1DF3 00000000:0000 07 00000000:00000000 00:00000000 00000000  1000        "
      "0 51123 2 0000000000000000 17         \n"
      "  232: 0100007F:0035 00000000:0000 07 00000000:00000000 00:00000000 00000000     0        "
      "0 777 2 0000000000000000 5\n"
      "  233: truncated row\n"
      "  234: 00000000:1DF3 00000000:0000 07 00000000:00000000 00:00000000 00000000  1000        "
      "0 90001 2 0000000000000000 -3\n";
  CHECK(SumUdpDrops(table, {51123}) == 17);
  CHECK(SumUdpDrops(table, {777, 51123}) == 22);
  CHECK(SumUdpDrops(table, {90001}) == 0);  // a negative count is malformed
  CHECK(SumUdpDrops(table, {}) == 0);
  CHECK(SumUdpDrops("", {1}) == 0);
  CHECK(SumUdpDrops("header only", {1}) == 0);
}

TEST_CASE("udp drops: a full receive buffer of a real socket is counted", "[unit]") {
  config::testing::TempDir dir;
  CHECK_FALSE(ProcessUdpDrops(dir.File("proc")).has_value());  // no /proc there
  const std::optional<std::int64_t> before = ProcessUdpDrops();
  if (!before) {
    WARN("no /proc/self/net/udp here: nothing to measure");
    return;
  }
  // A loopback socket with the smallest buffer, sent to and never read: the kernel drops.
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  REQUIRE(fd >= 0);
  const int small = 1;
  REQUIRE(::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof(small)) == 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) == 0);
  socklen_t len = sizeof(addr);
  REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0);
  const std::vector<char> payload(1000, 'x');
  for (int i = 0; i < 200; ++i) {
    ::sendto(fd,
             payload.data(),
             payload.size(),
             0,
             reinterpret_cast<const sockaddr*>(&addr),
             sizeof(addr));
  }
  const std::optional<std::int64_t> after = ProcessUdpDrops();
  ::close(fd);
  REQUIRE(after.has_value());
  CHECK(*after - *before >= 100);
}

}  // namespace
}  // namespace mvtrack::service
