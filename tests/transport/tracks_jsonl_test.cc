// The canonical tracks JSON-lines format: exact output (the lines below are the format's
// specification), number formatting, and the parser.

#include "transport/tracks_jsonl.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <locale>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "transport/test_messages.h"

namespace mvtrack::transport {
namespace {

tracker::Track3D MakeTrack(TrackId3D id, Vec3 position) {
  tracker::Track3D t;
  t.id = id;
  t.position = position;
  return t;
}

// Two tracks in a shelf14 frame, given out of id order: id 2 with three joints set (one of
// them a tiny negative that must print as 0), id 1 without joints.
tracker::Frame3D HandMadePoseFrame() {
  tracker::Frame3D frame;
  frame.frame = 12;
  frame.utime = 1700000000123456;
  tracker::Track3D two = MakeTrack(2, Vec3(1.5, -0.25, 0.0));
  two.joints.assign(14, std::nullopt);
  two.joints[0] = Vec3(0.1, 0.2, 1.7);
  two.joints[2] = Vec3(-0.00001, 3.14159265, 2.0);
  two.confidence = 0.5;  // not part of the format
  two.cameras = {1, 2};
  frame.tracks.push_back(two);
  frame.tracks.push_back(MakeTrack(1, Vec3(-3.0, 4.00006, 0.0)));
  return frame;
}

// The position text of a one-track line for x = `value`.
std::string FormatX(double value) {
  tracker::Frame3D frame;
  frame.tracks.push_back(MakeTrack(1, Vec3(value, 0.0, 0.0)));
  const std::string line = TracksJsonLine(frame, core::KeypointLayoutId::kNone);
  const std::string key = "\"position\": [";
  const std::size_t begin = line.find(key) + key.size();
  return line.substr(begin, line.find(',', begin) - begin);
}

TEST_CASE("the canonical line of a hand-made pose frame", "[unit]") {
  const std::string expected =
      "{\"frame\": 12, \"layout\": \"shelf14\", \"tracks\": ["
      "{\"id\": 1, \"joints\": [], \"position\": [-3.0000, 4.0001, 0.0000]}, "
      "{\"id\": 2, \"joints\": [[0.1000, 0.2000, 1.7000], null, [0.0000, 3.1416, 2.0000], "
      "null, null, null, null, null, null, null, null, null, null, null], "
      "\"position\": [1.5000, -0.2500, 0.0000]}"
      "], \"utime\": 1700000000123456}\n";
  CHECK(TracksJsonLine(HandMadePoseFrame(), core::KeypointLayoutId::kShelf14) == expected);
}

TEST_CASE("bone lengths follow the joints, when the track has them", "[unit]") {
  tracker::Frame3D frame = HandMadePoseFrame();
  frame.tracks[0].bone_lengths.assign(9, 0.0);  // shelf14: 9 bones
  frame.tracks[0].bone_lengths[0] = 0.45;
  frame.tracks[0].bone_lengths[8] = 0.23456;
  const std::string line = TracksJsonLine(frame, core::KeypointLayoutId::kShelf14);
  CHECK_THAT(line,
             Catch::Contains("{\"bone_lengths\": [0.4500, 0.0000, 0.0000, 0.0000, 0.0000, "
                             "0.0000, 0.0000, 0.0000, 0.2346], \"id\": 2, \"joints\": "));
}

TEST_CASE("the canonical line in box mode and of an empty frame", "[unit]") {
  tracker::Frame3D frame;
  frame.frame = 0;
  frame.utime = -5;
  frame.tracks.push_back(MakeTrack(9, Vec3(10.0, -0.00012, -0.0)));
  CHECK(TracksJsonLine(frame, core::KeypointLayoutId::kNone) ==
        "{\"frame\": 0, \"layout\": \"none\", \"tracks\": [{\"id\": 9, \"joints\": [], "
        "\"position\": [10.0000, -0.0001, 0.0000]}], \"utime\": -5}\n");
  tracker::Frame3D empty;
  empty.frame = 3;
  empty.utime = 4;
  CHECK(TracksJsonLine(empty, core::KeypointLayoutId::kNone) ==
        "{\"frame\": 3, \"layout\": \"none\", \"tracks\": [], \"utime\": 4}\n");
}

TEST_CASE("a stitched site's line names its zones and which saw each track", "[unit]") {
  tracker::Frame3D frame;
  frame.frame = 7;
  frame.utime = 8;
  frame.zones = {"zone1", "west_hall"};
  frame.tracks.push_back(MakeTrack(2, Vec3(1.0, 2.0, 0.0)));
  frame.tracks.push_back(MakeTrack(1, Vec3(3.0, 4.0, 0.0)));
  frame.tracks[0].zones = {0, 1};
  frame.tracks[1].zones = {1};
  const std::string line = TracksJsonLine(frame, core::KeypointLayoutId::kNone);
  CHECK(line ==
        "{\"frame\": 7, \"layout\": \"none\", \"tracks\": [{\"id\": 1, \"joints\": [], "
        "\"position\": [3.0000, 4.0000, 0.0000], \"zones\": [1]}, {\"id\": 2, \"joints\": [], "
        "\"position\": [1.0000, 2.0000, 0.0000], \"zones\": [0, 1]}], \"utime\": 8, "
        "\"zones\": [\"zone1\", \"west_hall\"]}\n");
  std::string why;
  const std::optional<tracker::Frame3D> back = ParseTracksJsonLine(line, nullptr, &why);
  REQUIRE(back.has_value());
  CHECK(back->zones == frame.zones);
  CHECK(back->tracks[0].zones == std::vector<int>{1});
  CHECK(back->tracks[1].zones == std::vector<int>{0, 1});
  CHECK(TracksJsonLine(*back, core::KeypointLayoutId::kNone) == line);
}

TEST_CASE("tracks are sorted by id", "[unit]") {
  tracker::Frame3D frame;
  for (TrackId3D id : {5, 2, 9, 100, 11}) frame.tracks.push_back(MakeTrack(id, Vec3::Zero()));
  const std::string line = TracksJsonLine(frame, core::KeypointLayoutId::kNone);
  std::vector<std::size_t> at;
  for (const char* id : {"\"id\": 2,", "\"id\": 5,", "\"id\": 9,", "\"id\": 11,", "\"id\": 100,"}) {
    at.push_back(line.find(id));
    REQUIRE(at.back() != std::string::npos);
  }
  CHECK(std::is_sorted(at.begin(), at.end()));
}

TEST_CASE("coordinates have 4 decimals, round to nearest, and never print -0", "[unit]") {
  CHECK(FormatX(1.23456) == "1.2346");
  CHECK(FormatX(1.23454) == "1.2345");
  CHECK(FormatX(-7.5) == "-7.5000");
  CHECK(FormatX(12345.6) == "12345.6000");
  CHECK(FormatX(123456789.123) == "123456789.1230");
  CHECK(FormatX(0.00005000001) == "0.0001");
  CHECK(FormatX(-0.00006) == "-0.0001");
  CHECK(FormatX(-0.00004) == "0.0000");
  CHECK(FormatX(-0.0) == "0.0000");
  CHECK(FormatX(1e-9) == "0.0000");
  CHECK(FormatX(-1e-300) == "0.0000");
  CHECK(FormatX(1e20) == "100000000000000000000.0000");
}

TEST_CASE("non-finite joints print null, a non-finite position prints null", "[unit]") {
  tracker::Frame3D frame;
  tracker::Track3D t = MakeTrack(1, Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0));
  t.joints = {Vec3(std::nan(""), 0.0, 0.0), std::nullopt, Vec3(1.0, 2.0, 3.0)};
  frame.tracks.push_back(t);
  // Three joints: not a real layout, so format with kNone and check the text only.
  CHECK(TracksJsonLine(frame, core::KeypointLayoutId::kNone) ==
        "{\"frame\": 0, \"layout\": \"none\", \"tracks\": [{\"id\": 1, \"joints\": [null, null, "
        "[1.0000, 2.0000, 3.0000]], \"position\": null}], \"utime\": 0}\n");
  // A null position parses back as NaN.
  const std::optional<tracker::Frame3D> parsed = ParseTracksJsonLine(
      "{\"frame\": 0, \"layout\": \"none\", \"tracks\": [{\"id\": 1, \"joints\": [], "
      "\"position\": null}], \"utime\": 0}",
      nullptr,
      nullptr);
  REQUIRE(parsed.has_value());
  CHECK(std::isnan(parsed->tracks[0].position.x()));
}

// A numpunct that writes "1.234,5": a stream-based formatter would pick it up.
struct CommaDecimal : std::numpunct<char> {
  char do_decimal_point() const override { return ','; }
  char do_thousands_sep() const override { return '.'; }
  std::string do_grouping() const override { return "\3"; }
};

TEST_CASE("formatting ignores the global locale", "[unit]") {
  const tracker::Frame3D frame = HandMadePoseFrame();
  const std::string before = TracksJsonLine(frame, core::KeypointLayoutId::kShelf14);
  const std::locale previous =
      std::locale::global(std::locale(std::locale::classic(), new CommaDecimal));
  const std::string during = TracksJsonLine(frame, core::KeypointLayoutId::kShelf14);
  const std::optional<tracker::Frame3D> parsed = ParseTracksJsonLine(during, nullptr, nullptr);
  std::locale::global(previous);
  CHECK(during == before);
  CHECK(parsed.has_value());
}

TEST_CASE("parse(format(x)) == x within the printed precision", "[unit]") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> coordinate(-50.0, 50.0);
  for (int trial = 0; trial < 50; ++trial) {
    const bool pose = trial % 2 == 0;
    const core::KeypointLayoutId layout =
        pose ? core::KeypointLayoutId::kCoco17 : core::KeypointLayoutId::kNone;
    tracker::Frame3D frame;
    frame.frame = static_cast<FrameIndex>(rng());
    frame.utime = static_cast<Utime>(rng()) * 1000;
    const int n = static_cast<int>(rng() % 6);
    for (int i = 0; i < n; ++i) {
      tracker::Track3D t = MakeTrack(static_cast<TrackId3D>(rng() % 1000) * 10 + i,
                                     Vec3(coordinate(rng), coordinate(rng), coordinate(rng)));
      if (pose) {
        for (int j = 0; j < 17; ++j) {
          if (rng() % 4 == 0) {
            t.joints.emplace_back(std::nullopt);
          } else {
            t.joints.emplace_back(Vec3(coordinate(rng), coordinate(rng), coordinate(rng)));
          }
        }
        // With the skeleton fit: the track's bone lengths (coco17: 19 bones).
        if (trial % 4 == 0) {
          for (int b = 0; b < 19; ++b) t.bone_lengths.push_back(std::abs(coordinate(rng)) / 50.0);
        }
      }
      frame.tracks.push_back(t);
    }
    const std::string line = TracksJsonLine(frame, layout);
    core::KeypointLayoutId parsed_layout = core::KeypointLayoutId::kBody25;
    std::string why;
    const std::optional<tracker::Frame3D> parsed = ParseTracksJsonLine(line, &parsed_layout, &why);
    INFO(line << why);
    REQUIRE(parsed.has_value());
    CHECK(parsed_layout == layout);
    CHECK(parsed->frame == frame.frame);
    CHECK(parsed->utime == frame.utime);
    REQUIRE(parsed->tracks.size() == frame.tracks.size());
    std::vector<tracker::Track3D> sorted = frame.tracks;
    std::sort(sorted.begin(),
              sorted.end(),
              [](const tracker::Track3D& a, const tracker::Track3D& b) { return a.id < b.id; });
    constexpr double kTolerance = 0.5e-4 + 1e-12;
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const tracker::Track3D& want = sorted[i];
      const tracker::Track3D& got = parsed->tracks[i];
      CHECK(got.id == want.id);
      CHECK((got.position - want.position).cwiseAbs().maxCoeff() <= kTolerance);
      REQUIRE(got.joints.size() == want.joints.size());
      for (std::size_t j = 0; j < want.joints.size(); ++j) {
        REQUIRE(got.joints[j].has_value() == want.joints[j].has_value());
        if (want.joints[j]) {
          CHECK((*got.joints[j] - *want.joints[j]).cwiseAbs().maxCoeff() <= kTolerance);
        }
      }
      REQUIRE(got.bone_lengths.size() == want.bone_lengths.size());
      for (std::size_t b = 0; b < want.bone_lengths.size(); ++b) {
        CHECK(std::abs(got.bone_lengths[b] - want.bone_lengths[b]) <= kTolerance);
      }
    }
    // The canonical form is a fixed point.
    CHECK(TracksJsonLine(*parsed, parsed_layout) == line);
  }
}

TEST_CASE("the parser accepts any whitespace, key order and JSON number syntax", "[unit]") {
  const std::string canonical =
      "{\"frame\": 12, \"layout\": \"none\", \"tracks\": [{\"id\": 2, \"joints\": [], "
      "\"position\": [1.5000, -0.2500, 0.0000]}, {\"id\": -1, \"joints\": [], "
      "\"position\": [0.0000, 0.0000, 100.0000]}], \"utime\": 1700000000123456}\n";
  const std::string loose =
      " \t{\r\n  \"utime\" :1700000000123456 ,\"tracks\":[ {\"position\":[ 1.5 , -25E-2,0 ] ,"
      "\"joints\" : [ ], \"id\":2},{\"joints\":[],\"position\":[0,0.0e0,1e2],\"id\":-1}] ,\n"
      "  \"layout\":\"none\",\"frame\":12\n}\r\n";
  core::KeypointLayoutId layout = core::KeypointLayoutId::kCoco17;
  std::string why;
  const std::optional<tracker::Frame3D> a = ParseTracksJsonLine(canonical, nullptr, &why);
  const std::optional<tracker::Frame3D> b = ParseTracksJsonLine(loose, &layout, &why);
  INFO(why);
  REQUIRE(a.has_value());
  REQUIRE(b.has_value());
  CHECK(layout == core::KeypointLayoutId::kNone);
  CHECK(testing::DiffFrames3D(*a, *b).empty());
  // Parsed tracks come out sorted by id.
  CHECK(b->tracks[0].id == -1);
  CHECK(TracksJsonLine(*b, layout) ==
        "{\"frame\": 12, \"layout\": \"none\", \"tracks\": [{\"id\": -1, \"joints\": [], "
        "\"position\": [0.0000, 0.0000, 100.0000]}, {\"id\": 2, \"joints\": [], "
        "\"position\": [1.5000, -0.2500, 0.0000]}], \"utime\": 1700000000123456}\n");
  // Layout aliases are accepted.
  const std::optional<tracker::Frame3D> campus = ParseTracksJsonLine(
      "{\"frame\": 1, \"layout\": \"campus14\", \"tracks\": [], \"utime\": 2}", &layout, &why);
  REQUIRE(campus.has_value());
  CHECK(layout == core::KeypointLayoutId::kShelf14);
  // Any valid JSON spelling is read: escapes in strings, keys in any order, free whitespace.
  const std::optional<tracker::Frame3D> escaped = ParseTracksJsonLine(
      "{ \"utime\":2,\"tracks\":[ ],\"layout\":\"co\\u0063o17\",\"frame\":1 }\r\n", &layout, &why);
  REQUIRE(escaped.has_value());
  CHECK(layout == core::KeypointLayoutId::kCoco17);
}

TEST_CASE("the parser rejects malformed lines with a reason", "[unit]") {
  const std::string head = "{\"frame\": 1, \"layout\": \"none\", \"tracks\": [";
  const std::string tail = "], \"utime\": 2}";
  const std::string track = "{\"id\": 4, \"joints\": [], \"position\": [1, 2, 3]}";
  // Syntax errors are lib/json's (nlohmann-json's words, at the byte that broke the syntax);
  // schema errors name the column and key path of the offending value.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "column 1: syntax error while parsing value - unexpected end of input"},
      {"[]", "column 1: a line must be a JSON object, found an array"},
      {"{\"frame\": 1, \"layout\": \"none\", \"tracks\": []}", "column 1: missing key \"utime\""},
      {"{\"utime\": 1, \"layout\": \"none\", \"tracks\": []}", "missing key \"frame\""},
      {"{\"frame\": 1, \"frame\": 2, \"layout\": \"none\", \"tracks\": [], \"utime\": 2}",
       "column 14: duplicate key \"frame\""},
      {head + tail.substr(0, tail.size() - 1) + ", \"extra\": 1}",
       "extra: unknown key \"extra\" (allowed: frame, layout, tracks, utime, zones)"},
      {head + tail + " x", "column 58: syntax error while parsing value - invalid literal"},
      {head + tail + "\n{}",
       "column 58: syntax error while parsing value - unexpected '{'; expected "
       "end of input"},
      {"{\"frame\": \"1\", \"layout\": \"none\", \"tracks\": [], \"utime\": 2}",
       "column 11: frame: expected an integer, found a string"},
      {"{\"frame\": 1.5, \"layout\": \"none\", \"tracks\": [], \"utime\": 2}",
       "column 11: frame: expected an integer, found 1.5"},
      {"{\"frame\": 1, \"layout\": \"none\", \"tracks\": [], \"utime\": 99999999999999999999}",
       "column 55: utime: 99999999999999999999 is beyond the 64-bit integer range"},
      {"{\"frame\": 01, \"layout\": \"none\", \"tracks\": [], \"utime\": 2}",
       "column 12: syntax error while parsing object - unexpected number literal"},
      {"{\"frame\": 1 \"layout\": \"none\", \"tracks\": [], \"utime\": 2}",
       "column 20: syntax error while parsing object - unexpected string literal; expected '}'"},
      {"{\"frame\": 1, \"layout\": \"coco18\", \"tracks\": [], \"utime\": 2}",
       "column 24: layout: unknown layout \"coco18\""},
      {"{\"frame\": 1, \"layout\": \"none", "missing closing quote"},
      {"{\"frame\": 1, \"layout\": none, \"tracks\": [], \"utime\": 2}",
       "column 25: syntax error while parsing value - invalid literal"},
      {"{\"frame\": 1, \"layout\": 7, \"tracks\": [], \"utime\": 2}",
       "column 24: layout: expected a string, found a number"},
      {"{\"frame\": 1, \"layout\": \"none\", \"tracks\": {}, \"utime\": 2}",
       "tracks: expected an array, found an object"},
      {head + track + ", " + track + tail, "duplicate track id 4"},
      {head + "{\"joints\": [], \"position\": [1, 2, 3]}" + tail, "tracks[0]: missing key \"id\""},
      {head + "{\"id\": 1, \"position\": [1, 2, 3]}" + tail, "tracks[0]: missing key \"joints\""},
      {head + "{\"id\": 1, \"joints\": []}" + tail, "tracks[0]: missing key \"position\""},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [1, 2]}" + tail,
       "tracks[0].position: expected [x, y, z] (3 values), found 2 values"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [1, 2, 3, 4]}" + tail,
       "tracks[0].position: expected [x, y, z] (3 values), found 4 values"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [1., 2, 3]}" + tail,
       "expected digit after '.'"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [NaN, 2, 3]}" + tail, "invalid literal"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [1e999, 2, 3]}" + tail,
       "column 80: number overflow parsing '1e999'"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [\"1\", 2, 3]}" + tail,
       "column 80: tracks[0].position[0]: expected a number, found a string"},
      {head + "{\"id\": 1, \"joints\": [null], \"position\": [1, 2, 3]}" + tail,
       "track id 1 has 1 joints; layout \"none\" needs 0 or 0"},
      {"{\"frame\": 1, \"layout\": \"coco17\", \"tracks\": [{\"id\": 1, \"joints\": [null, "
       "[1, 2, 3]], \"position\": [1, 2, 3]}], \"utime\": 2}",
       "track id 1 has 2 joints; layout \"coco17\" needs 0 or 17"},
      {head + "{\"id\": 1, \"joints\": [[1, 2]], \"position\": [1, 2, 3]}" + tail,
       "tracks[0].joints[0]: expected [x, y, z] (3 values), found 2 values"},
      {head + "{\"id\": 1, \"joints\": 3, \"position\": [1, 2, 3]}" + tail,
       "tracks[0].joints: expected an array, found a number"},
      {head + "{\"id\": 1, \"joints\": [], \"position\": [1, 2, 3], \"cameras\": []}" + tail,
       "tracks[0].cameras: unknown key \"cameras\" (allowed: bone_lengths, id, joints, position, "
       "zones)"},
      {head + track + "], \"utime\": 2, \"zones\": [\"a\", 3]}",
       "zones[1]: expected a string, found a number"},
      {head + track + "], \"utime\": 2, \"zones\": [\"\"]}", "zones[0] is an empty zone name"},
      {head + track + "], \"utime\": 2, \"zones\": \"a\"}", "zones: expected an array"},
      {head + "{\"id\": 4, \"joints\": [], \"position\": [1, 2, 3], \"zones\": [1]}" +
           "], \"utime\": 2, \"zones\": [\"a\"]}",
       "track id 4: zones must be ascending indices of the line's 1 zones"},
      {head + "{\"id\": 4, \"joints\": [], \"position\": [1, 2, 3], \"zones\": [1, 0]}" +
           "], \"utime\": 2, \"zones\": [\"a\", \"b\"]}",
       "track id 4: zones must be ascending indices of the line's 2 zones"},
      {head + "{\"id\": 4, \"joints\": [], \"position\": [1, 2, 3], \"zones\": [-1]}" + tail,
       "tracks[0].zones[0]: "},
      {std::string(head) + "[[[[[[1]]]]]]" + tail, "nesting deeper than 5"},
  };
  for (const auto& [line, needle] : cases) {
    INFO("line: " << line);
    std::string why;
    core::KeypointLayoutId layout = core::KeypointLayoutId::kBody25;
    CHECK_FALSE(ParseTracksJsonLine(line, &layout, &why).has_value());
    CHECK_THAT(why, Catch::Matchers::Contains(needle));
    CHECK(layout == core::KeypointLayoutId::kBody25);  // untouched on failure
  }
}

}  // namespace
}  // namespace mvtrack::transport
