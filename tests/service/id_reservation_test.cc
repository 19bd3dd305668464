// IdReservation: track ids continue above every earlier run's, across restarts and crashes.

#include "service/id_reservation.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "config/config_test_util.h"

namespace mvtrack::service {
namespace {

using config::testing::TempDir;

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_CASE("IdReservation: ids start at 1, continue at the reservation's end after a restart",
          "[unit]") {
  TempDir dir;
  std::string why;
  IdReservation a;
  REQUIRE(a.Open(dir.File(""), 100, &why));
  CHECK(a.first_id() == 1);
  CHECK(a.reserved_end() == 101);
  CHECK(Read(dir.File("track_ids")) == "mvtrack.track_ids/1\nreserved_end=101\n");
  // Within the first half of the block nothing is written; from its middle on the end moves.
  REQUIRE(a.Extend(50, &why));
  CHECK(a.reserved_end() == 101);
  REQUIRE(a.Extend(51, &why));
  CHECK(a.reserved_end() == 151);
  // A restart (or a kill -9 at any point) continues at the stored end: never below an id the
  // first run could have given out (< 151).
  IdReservation b;
  REQUIRE(b.Open(dir.File(""), 100, &why));
  CHECK(b.first_id() == 151);
  CHECK(b.reserved_end() == 251);
}

TEST_CASE("IdReservation: a malformed or unwritable state is refused with a reason", "[unit]") {
  TempDir dir;
  std::string why;
  for (const char* bad : {"",
                          "mvtrack.track_ids/1\n",
                          "other/1\nreserved_end=5\n",
                          "mvtrack.track_ids/1\nreserved_end=x\n",
                          "mvtrack.track_ids/1\nreserved_end=0\n",
                          "mvtrack.track_ids/1\nreserved_end=99999999999999999999\n"}) {
    INFO(bad);
    dir.Write("track_ids", bad);
    IdReservation r;
    CHECK_FALSE(r.Open(dir.File(""), 10, &why));
    CHECK(why.find("track_ids") != std::string::npos);
  }
  IdReservation missing;
  CHECK_FALSE(missing.Open(dir.File("no/such/dir"), 10, &why));
  CHECK_FALSE(why.empty());
}

}  // namespace
}  // namespace mvtrack::service
