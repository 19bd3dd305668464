// lib/config site files (issue 41): the example parses, errors name the file, line and key, and
// the canonical YAML parses back to the same site.

#include "config/site.h"

#include <catch2/catch.hpp>
#include <string>

#include "config_test_util.h"

namespace mvtrack::config {
namespace {

using testing::CheckLocated;
using testing::LineOf;
using testing::RequireConfigError;

constexpr const char* kSite = R"(format: mvtrack.site/1
regions:
  - name: shelf
    polygon: [[0, 0], [2, 0], [2, 1], [0, 1]]
lines:
  - name: door
    from: [0, 1]
    to: [0, 3]
rules:
  hold_s: 0.75
)";

}  // namespace

TEST_CASE("site file: the documented example and a minimal site", "[unit]") {
  const analytics::Site example =
      LoadSiteFile(std::string(MVTRACK_SOURCE_DIR) + "/docs/examples/sites/demo.yaml");
  CHECK(example.regions.size() == 3);
  CHECK(example.lines.size() == 1);
  CHECK(example.options.hysteresis_m == 0.3);
  const analytics::Site site = ParseSite(kSite, "site.yaml");
  REQUIRE(site.regions.size() == 1);
  CHECK(site.regions[0].name == "shelf");
  CHECK(site.regions[0].polygon[2] == Vec2(2, 1));
  CHECK(site.lines[0].to == Vec2(0, 3));
  CHECK(site.options.hold_s == 0.75);
  CHECK(site.options.max_gap_s == analytics::AnalyticsOptions{}.max_gap_s);
  CHECK(LooksLikeSite(kSite));
  CHECK_FALSE(LooksLikeSite("tracker: {}\n"));
  // The canonical form parses back to the same site.
  const analytics::Site again = ParseSite(SiteToYaml(site), "canonical");
  CHECK(again.regions[0].polygon == site.regions[0].polygon);
  CHECK(again.lines[0].from == site.lines[0].from);
  CHECK(again.options.hold_s == site.options.hold_s);
  CHECK(SiteToYaml(again) == SiteToYaml(site));
}

TEST_CASE("site file: mistakes are errors naming the line and the key", "[unit]") {
  const auto error = [](const std::string& text) {
    return RequireConfigError([&] { ParseSite(text, "s.yaml"); });
  };
  std::string text = kSite;
  text.replace(text.find("hold_s"), 6, "hold_sec");
  CheckLocated(
      error(text), "s.yaml", LineOf(text, "hold_sec"), "rules.hold_sec", "did you mean 'hold_s'");
  text = kSite;
  text.replace(text.find("[2, 1], [0, 1]"), 14, "[0, 1], [2, 1]");
  CheckLocated(error(text),
               "s.yaml",
               LineOf(text, "polygon"),
               "regions[0].polygon",
               "cross (the polygon must be simple)");
  text = kSite;
  text.replace(text.find("[0, 0], "), 8, "");
  text.replace(text.find("[2, 1], "), 8, "");
  CheckLocated(error(text),
               "s.yaml",
               LineOf(text, "polygon"),
               "regions[0].polygon",
               "3 to 1000 vertices, not 2");
  text = kSite;
  text.replace(text.find("to: [0, 3]"), 10, "to: [0, 1]");
  CheckLocated(
      error(text), "s.yaml", LineOf(text, "to: [0, 1]"), "lines[0].to", "the line has no length");
  text = kSite;
  text.replace(text.find("[2, 0]"), 6, "[.nan, 0]");
  CheckLocated(error(text), "s.yaml", LineOf(text, "polygon"), "regions[0].polygon[1][0]", "");
  text = std::string(kSite) + "  - name: door\n    from: [5, 5]\n    to: [6, 6]\n";
  text.replace(text.find("rules:\n  hold_s: 0.75\n"), 22, "");
  CheckLocated(error(text),
               "s.yaml",
               LineOf(text, "  - name: door\n    from: [5"),
               "lines[1].name",
               "another line is named 'door'");
  text = kSite;
  text.replace(text.find("hold_s: 0.75"), 12, "hold_s: -1");
  CheckLocated(error(text), "s.yaml", LineOf(text, "hold_s"), "rules.hold_s", "[0, 3600]");
  text = kSite;
  text.replace(text.find("name: shelf"), 11, "name: caf\xc3\xa9");
  CheckLocated(
      error(text), "s.yaml", LineOf(text, "name: caf"), "regions[0].name", "not printable ASCII");
  CHECK_THAT(error("format: mvtrack.site/1\n").what(),
             Catch::Contains("a site needs at least one region or line"));
  CHECK_THAT(error("format: mvtrack.site/2\nregions: []\n").what(),
             Catch::Contains("expected 'mvtrack.site/1'"));
}

}  // namespace mvtrack::config
