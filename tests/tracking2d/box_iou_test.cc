#include "tracking2d/box_iou.h"

#include <catch2/catch.hpp>
#include <limits>
#include <random>

namespace mvtrack::tracking2d {
namespace {

core::BoxPx Box(double x_min, double y_min, double x_max, double y_max) {
  return {x_min, y_min, x_max, y_max};
}

TEST_CASE("BoxIou matches hand-computed overlaps", "[unit]") {
  const core::BoxPx a = Box(0, 0, 10, 10);
  REQUIRE(BoxIou(a, a) == Approx(1.0));
  // Shifted by half a width: intersection 5x10 = 50, union 100 + 100 - 50 = 150.
  REQUIRE(BoxIou(a, Box(5, 0, 15, 10)) == Approx(50.0 / 150.0));
  // Corner overlap 5x5 = 25 of union 175.
  REQUIRE(BoxIou(a, Box(5, 5, 15, 15)) == Approx(25.0 / 175.0));
  // Containment: 4x4 inside 10x10.
  REQUIRE(BoxIou(a, Box(2, 2, 6, 6)) == Approx(16.0 / 100.0));
  // Symmetric.
  REQUIRE(BoxIou(Box(5, 5, 15, 15), a) == Approx(BoxIou(a, Box(5, 5, 15, 15))));
}

TEST_CASE("BoxIou is zero for disjoint, touching and degenerate boxes", "[unit]") {
  const core::BoxPx a = Box(0, 0, 10, 10);
  REQUIRE(BoxIou(a, Box(20, 0, 30, 10)) == 0.0);
  REQUIRE(BoxIou(a, Box(10, 0, 20, 10)) == 0.0);  // shares an edge only
  REQUIRE(BoxIou(a, Box(5, 5, 5, 8)) == 0.0);     // zero width
  REQUIRE(BoxIou(a, Box(8, 8, 2, 2)) == 0.0);     // inverted
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE(BoxIou(a, Box(nan, 0, 10, 10)) == 0.0);
  REQUIRE_FALSE(IsUsableBox(Box(nan, 0, 10, 10)));
  REQUIRE_FALSE(IsUsableBox(Box(0, 0, std::numeric_limits<double>::infinity(), 10)));
  REQUIRE(IsUsableBox(a));
}

TEST_CASE("BoxIouOfUsable equals BoxIou on usable boxes", "[unit]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0.0, 200.0);
  std::uniform_real_distribution<double> size(0.5, 80.0);
  for (int k = 0; k < 5000; ++k) {
    const double ax = pos(rng), ay = pos(rng), bx = pos(rng), by = pos(rng);
    const core::BoxPx a{ax, ay, ax + size(rng), ay + size(rng)};
    const core::BoxPx b{bx, by, bx + size(rng), by + size(rng)};
    REQUIRE(IsUsableBox(a));
    REQUIRE(IsUsableBox(b));
    REQUIRE(BoxIouOfUsable(a, b) == BoxIou(a, b));
  }
}

}  // namespace
}  // namespace mvtrack::tracking2d
