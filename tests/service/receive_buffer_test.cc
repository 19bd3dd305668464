// CheckReceiveBuffer: the udpm:// receive buffer against the kernel's net.core.rmem_max.

#include "service/receive_buffer.h"

#include <catch2/catch.hpp>
#include <string>

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

}  // namespace
}  // namespace mvtrack::service
