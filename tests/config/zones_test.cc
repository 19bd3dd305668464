// Zones of a site (issue 43): a corridor of cameras splits into compact zones along its length,
// with border cameras only near the border.

#include "config/zones.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <map>

#include "config_test_util.h"
#include "sim/cameras.h"

namespace mvtrack::config {
namespace {

using testing::CheckLocated;
using testing::LineOf;
using testing::RequireConfigError;

// A 48 m corridor: 16 cameras 3 m apart along x at 3 m height, alternately on the two walls
// (y = 0 and y = 6), each looking down 45 degrees across the corridor and along +x.
std::vector<geometry::CameraModel> Corridor() {
  std::vector<geometry::CameraModel> cameras;
  for (int i = 0; i < 16; ++i) {
    const double y = i % 2 == 0 ? 0.0 : 6.0;
    const Vec3 center(1.5 + 3.0 * i, y, 3.0);
    const Vec3 forward(0.5, i % 2 == 0 ? 1.0 : -1.0, -1.2);
    cameras.push_back(sim::MakeCamera(i, 640, 480, 70.0, center, forward));
  }
  return cameras;
}

double CameraX(CameraId id) { return 1.5 + 3.0 * static_cast<double>(id); }

TEST_CASE("PartitionZones splits a corridor along its length, borders near the border",
          "[unit][config]") {
  const std::vector<geometry::CameraModel> cameras = Corridor();
  ZoneOptions options;
  options.max_cameras = 8;
  const std::vector<Zone> zones = PartitionZones(cameras, options);
  REQUIRE(zones.size() == 2);
  CHECK(zones[0].name == "zone1");
  CHECK(zones[1].name == "zone2");
  // The first half of the corridor and the second, each camera in one zone.
  CHECK(zones[0].cameras == std::vector<CameraId>{0, 1, 2, 3, 4, 5, 6, 7});
  CHECK(zones[1].cameras == std::vector<CameraId>{8, 9, 10, 11, 12, 13, 14, 15});
  CHECK(zones[0].neighbours == std::vector<std::string>{"zone2"});
  CHECK(zones[1].neighbours == std::vector<std::string>{"zone1"});
  // Border cameras: the other zone's cameras that see this zone's floor, all near the border
  // (x = 24 m), none from the far end.
  for (const Zone& z : zones) {
    INFO(z.name);
    REQUIRE(!z.border.empty());
    for (const CameraId id : z.border) {
      CHECK(std::find(z.cameras.begin(), z.cameras.end(), id) == z.cameras.end());
      CHECK(std::abs(CameraX(id) - 24.0) < 12.0);
    }
    CHECK(z.area_m2 > 50.0);
    CHECK(z.border_area_m2 > 0.0);
    CHECK(z.border_area_m2 < z.area_m2);
  }
  CHECK(zones[0].bounds.x_max_m < zones[1].bounds.x_max_m);
  // Deterministic, and one zone when it fits.
  const std::vector<Zone> again = PartitionZones(cameras, options);
  REQUIRE(again.size() == zones.size());
  for (std::size_t z = 0; z < zones.size(); ++z) {
    CHECK(again[z].cameras == zones[z].cameras);
    CHECK(again[z].border == zones[z].border);
  }
  options.max_cameras = 16;
  const std::vector<Zone> one = PartitionZones(cameras, options);
  REQUIRE(one.size() == 1);
  CHECK(one[0].cameras.size() == 16);
  CHECK(one[0].border.empty());
  CHECK(one[0].neighbours.empty());
  // Uneven: 16 cameras in zones of at most 6 are 3 zones of 5-6.
  options.max_cameras = 6;
  const std::vector<Zone> three = PartitionZones(cameras, options);
  REQUIRE(three.size() == 3);
  for (const Zone& z : three) CHECK((z.cameras.size() == 5 || z.cameras.size() == 6));
  CHECK(three[1].neighbours == std::vector<std::string>{"zone1", "zone3"});
}

TEST_CASE("ZoneOptions are checked, zone channels are namespaced", "[unit][config]") {
  std::string why;
  ZoneOptions o;
  CHECK(o.Validate(&why));
  o.max_cameras = 1;
  CHECK_FALSE(o.Validate(&why));
  CHECK_THAT(why, Catch::Contains("max_cameras"));
  o = ZoneOptions();
  o.cell_m = 0.0;
  CHECK_FALSE(o.Validate(&why));
  o = ZoneOptions();
  o.min_shared_area_m2 = -1.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(ZoneChannel("MVTRACK_TRACKS", "zone2") == "MVTRACK_TRACKS_ZONE2");
}

TEST_CASE("zones file: written zones read back", "[unit][config]") {
  const std::vector<Zone> zones = PartitionZones(Corridor(), ZoneOptions{8, 0.5, 1.0, 2.0});
  std::vector<Zone> named = zones;
  named[0].daemon = "zone1.yaml";
  const std::string text = ZonesToYaml(named, "the corridor");
  const std::vector<Zone> again = ParseZones(text, "z.yaml");
  REQUIRE(again.size() == zones.size());
  for (std::size_t i = 0; i < zones.size(); ++i) {
    CHECK(again[i].name == zones[i].name);
    CHECK(again[i].cameras == zones[i].cameras);
    CHECK(again[i].border == zones[i].border);
    CHECK(again[i].neighbours == zones[i].neighbours);
  }
  CHECK(again[0].daemon == "zone1.yaml");
  CHECK(again[1].daemon.empty());
  CHECK(ZonesToYaml(again, "the corridor") == text);
}

TEST_CASE("zones file: mistakes are errors naming the line and the key", "[unit][config]") {
  const auto error = [](const std::string& text) {
    return RequireConfigError([&] { ParseZones(text, "z.yaml"); });
  };
  const std::string ok =
      "format: mvtrack.zones/1\nzones:\n  - name: east\n    cameras: [0, 1]\n"
      "    border_cameras: [2]\n  - name: west\n    cameras: [2, 3]\n    neighbours: [east]\n";
  CHECK(ParseZones(ok, "z.yaml").size() == 2);
  std::string text = ok;
  text.replace(text.find("cameras: [2, 3]"), 15, "cameras: [1, 3]");
  CheckLocated(error(text), "z.yaml", LineOf(text, "[1, 3]"), "zones[1].cameras", "zone 'east'");
  text = ok;
  text.replace(text.find("west"), 4, "East");
  CheckLocated(error(text), "z.yaml", LineOf(text, "East"), "zones[1].name", "a-z, 0-9 and _");
  text = ok;
  text.replace(text.find("west"), 4, "east");
  CheckLocated(error(text),
               "z.yaml",
               LineOf(text, "name: east\n    cameras: [2"),
               "zones[1].name",
               "another zone is named 'east'");
  text = ok;
  text.replace(text.find("[east]"), 6, "[north]");
  CheckLocated(error(text),
               "z.yaml",
               LineOf(text, "north"),
               "zones[1].neighbours[0]",
               "no zone is named 'north'");
  text = ok;
  text.replace(text.find("border_cameras: [2]"), 19, "border_cameras: [1]");
  CheckLocated(error(text),
               "z.yaml",
               LineOf(text, "border_cameras"),
               "zones[0].border_cameras",
               "one of the zone's own cameras");
  text = ok;
  text.replace(text.find("border_cameras"), 14, "border_camera");
  CheckLocated(error(text),
               "z.yaml",
               LineOf(text, "border_camera"),
               "zones[0].border_camera",
               "did you mean 'border_cameras'");
  CheckLocated(
      error("format: mvtrack.zones/1\nzones: []\n"), "z.yaml", 2, "zones", "at least one zone");
  CheckLocated(error("format: mvtrack.zones/1\nzones:\n  - name: a\n    cameras: []\n"),
               "z.yaml",
               4,
               "zones[0].cameras",
               "at least one camera");
}

}  // namespace
}  // namespace mvtrack::config
