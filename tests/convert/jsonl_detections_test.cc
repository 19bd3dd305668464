// The JSON-lines detection reader of `mvtrack convert jsonl` (lib/formats/jsonl_detections.h):
// valid lines in every spelling the format allows, every class of invalid line with the column
// and key path of the error, the cross-line rules with line numbers, --skip-bad-lines, a seeded
// round trip and a seeded mutation loop.

#include "formats/jsonl_detections.h"

#include <catch2/catch.hpp>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"

namespace mvtrack::formats {
namespace {

// Column (1-based) of the first occurrence of `marker` in `line`.
std::size_t ColumnOf(const std::string& line, const std::string& marker, std::size_t from = 0) {
  const std::size_t pos = line.find(marker, from);
  REQUIRE(pos != std::string::npos);
  return pos + 1;
}

// Parses `line`, requires failure, and returns the message.
std::string ErrorOf(const std::string& line) {
  std::string why;
  const std::optional<JsonlCameraFrame> parsed = ParseJsonlDetectionsLine(line, &why);
  INFO(line);
  REQUIRE_FALSE(parsed.has_value());
  REQUIRE_FALSE(why.empty());
  return why;
}

// Requires that `line` fails at `column` with a message containing every one of `parts`.
void RequireError(const std::string& line,
                  std::size_t column,
                  const std::vector<std::string>& parts) {
  const std::string why = ErrorOf(line);
  INFO("line: " << line << "\nerror: " << why);
  CHECK(why.rfind("column " + std::to_string(column) + ": ", 0) == 0);
  for (const std::string& p : parts) CHECK(why.find(p) != std::string::npos);
}

std::string Coco17Keypoints(double x0, double conf) {
  std::string s = "[";
  for (int j = 0; j < 17; ++j) {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%s[%g, %g, %g]", j ? ", " : "", x0 + j, 2.0 * j, conf);
    s += buffer;
  }
  return s + "]";
}

TEST_CASE("jsonl: a full line parses into the camera-frame it describes", "[unit]") {
  const std::string line =
      "{\"camera\": 3, \"frame\": 120, \"utime\": 1700000004000000, \"image_size\": [1920, 1080], "
      "\"detections\": [{\"box\": [812.5, 300, 901.0, 560.25], \"score\": 0.93, \"keypoints\": " +
      Coco17Keypoints(100.0, 0.5) +
      ", \"layout\": \"coco17\", \"embedding\": [0.5, -1.25e-1, 3]}, "
      "{\"score\": 1, \"box\": [-10, -20.5, 1e1, 2E+1]}]}";
  std::string why;
  const std::optional<JsonlCameraFrame> f = ParseJsonlDetectionsLine(line, &why);
  INFO(why);
  REQUIRE(f.has_value());
  CHECK(f->frame.camera_id == 3);
  CHECK(f->frame.frame == 120);
  CHECK(f->frame.utime == 1700000004000000);
  CHECK(f->image_width_px == 1920);
  CHECK(f->image_height_px == 1080);
  REQUIRE(f->frame.detections.size() == 2);
  const core::Detection2D& a = f->frame.detections[0];
  CHECK(a.box.x_min == 812.5);
  CHECK(a.box.y_min == 300.0);
  CHECK(a.box.x_max == 901.0);
  CHECK(a.box.y_max == 560.25);
  CHECK(a.score == 0.93);
  CHECK(a.layout == core::KeypointLayoutId::kCoco17);
  REQUIRE(a.keypoints.size() == 17);
  for (int j = 0; j < 17; ++j) {
    CHECK(a.keypoints[static_cast<std::size_t>(j)].position_px.x() == 100.0 + j);
    CHECK(a.keypoints[static_cast<std::size_t>(j)].position_px.y() == 2.0 * j);
    CHECK(a.keypoints[static_cast<std::size_t>(j)].confidence == 0.5);
  }
  CHECK(a.embedding == std::vector<float>{0.5f, -0.125f, 3.0f});
  const core::Detection2D& b = f->frame.detections[1];
  CHECK(b.box.x_min == -10.0);
  CHECK(b.box.y_min == -20.5);
  CHECK(b.box.x_max == 10.0);
  CHECK(b.box.y_max == 20.0);
  CHECK(b.score == 1.0);
  CHECK(b.layout == core::KeypointLayoutId::kNone);
  CHECK(b.keypoints.empty());
  CHECK(b.embedding.empty());
}

TEST_CASE("jsonl: optional keys, key order, whitespace, CRLF and escapes", "[unit]") {
  std::string why;
  // Minimal line: no image_size, no detections.
  auto f = ParseJsonlDetectionsLine(R"({"camera":0,"frame":0,"utime":0,"detections":[]})", &why);
  REQUIRE(f.has_value());
  CHECK(f->image_width_px == 0);
  CHECK(f->image_height_px == 0);
  CHECK(f->frame.detections.empty());
  // Any key order, free whitespace (spaces, tabs), CRLF ending.
  f = ParseJsonlDetectionsLine(
      " {\t\"detections\" : [ ] , \"utime\":5,\"frame\" :7, \"camera\": 2147483647 }\r", &why);
  REQUIRE(f.has_value());
  CHECK(f->frame.camera_id == 2147483647);
  CHECK(f->frame.frame == 7);
  CHECK(f->frame.utime == 5);
  // Escaped characters in a string: "\u0063oco\u00317" is "coco17"; the campus14 alias works.
  const std::string kps14 =
      "[[1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], "
      "[1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], "
      "[1, 2, 1], [1, 2, 0]]";
  f = ParseJsonlDetectionsLine(
      R"({"camera": 1, "frame": 2, "utime": 3, "detections": [{"box": [0, 0, 1, 1], "score": 0, )"
      R"("keypoints": )" +
          Coco17Keypoints(0.0, 1.0) +
          R"(, "layout": "\u0063oco\u00317"}, )"
          R"({"box": [0, 0, 1, 1], "score": 0.5, "layout": "campus14", "keypoints": )" +
          kps14 + "}]}",
      &why);
  INFO(why);
  REQUIRE(f.has_value());
  REQUIRE(f->frame.detections.size() == 2);
  CHECK(f->frame.detections[0].layout == core::KeypointLayoutId::kCoco17);
  CHECK(f->frame.detections[1].layout == core::KeypointLayoutId::kShelf14);
  CHECK(f->frame.detections[1].keypoints[13].confidence == 0.0);
  // An empty embedding is the same as none.
  f = ParseJsonlDetectionsLine(
      R"({"camera": 1, "frame": 2, "utime": 3, )"
      R"("detections": [{"box": [0, 0, 1, 1], "score": 0.5, "embedding": []}]})",
      &why);
  REQUIRE(f.has_value());
  CHECK(f->frame.detections[0].embedding.empty());
}

TEST_CASE("jsonl: syntax errors give the byte column", "[unit]") {
  const std::string head = R"({"camera": 0, "frame": 1, "utime": 2, "detections": [)";
  std::string line;

  line = head + "],}";
  RequireError(line, ColumnOf(line, "}"), {"unexpected '}'", "expected string literal"});
  line = head + "]} x";
  RequireError(line, ColumnOf(line, "x"), {"expected end of input"});
  line = head + "]";
  RequireError(line, line.size() + 1, {"unexpected end of input", "expected '}'"});
  line = R"({'camera': 0})";
  RequireError(line, 2, {"expected string literal"});
  line = head + R"({"box": [0, 0, 1, 1], "score": NaN}]})";
  RequireError(line, ColumnOf(line, "NaN"), {"invalid literal"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 01}]})";
  RequireError(line, ColumnOf(line, "01") + 1, {"unexpected number literal"});
  line = head + R"({"box": [0, 0, 1., 1], "score": 1}]})";
  RequireError(line, ColumnOf(line, "1.,") + 2, {"expected digit after '.'"});
  line = head + R"({"box": [0, 0, 1, 1], "score": +1}]})";
  RequireError(line, ColumnOf(line, "+1"), {"invalid literal"});
  line = head + R"({"box": [0, 0, 1, 1,], "score": 1}]})";
  RequireError(line, ColumnOf(line, ",]") + 1, {"unexpected ']'"});
  line = head + "]} // comment";
  RequireError(line, ColumnOf(line, "//"), {"expected end of input"});
  line = "";
  RequireError(line, 1, {"unexpected end of input"});
  line = "   \r";
  RequireError(line, 4, {"unexpected end of input"});
  line = "[1, 2]";
  RequireError(line, 1, {"must be a JSON object", "an array"});
  line = R"({"camera": 0, "camera": 1, "frame": 1, "utime": 2, "detections": []})";
  RequireError(line, ColumnOf(line, "\"camera\"", 2), {"duplicate key \"camera\""});
  line =
      head + "{\"box\": [0, 0, 1, 1], \"score\": 1, \"layout\": \"co\x01\", \"keypoints\": []}]}";
  RequireError(line, ColumnOf(line, "\x01"), {"control character"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "\ud800x", "keypoints": []}]})";
  RequireError(line, ColumnOf(line, "\\ud800") + 6, {"must be followed by U+DC00..U+DFFF"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "\q", "keypoints": []}]})";
  RequireError(line, ColumnOf(line, "q"), {"forbidden character after backslash"});
  line =
      head + "{\"box\": [0, 0, 1, 1], \"score\": 1, \"layout\": \"\xC3\x28\", \"keypoints\": []}]}";
  RequireError(
      line, ColumnOf(line, "\xC3") + 1, {"ill-formed UTF-8 byte"});  // the byte that breaks it
  // Nesting deeper than kJsonlMaxDepth.
  line = head + R"({"embedding": )" + std::string(20, '[') + std::string(20, ']') + "}]}";
  RequireError(line,
               ColumnOf(line, "[[") + static_cast<std::size_t>(kJsonlMaxDepth) - 3,
               {"nesting deeper than"});
}

TEST_CASE("jsonl: schema errors name the key path and the reason", "[unit]") {
  const std::string head = R"({"camera": 0, "frame": 1, "utime": 2, "detections": [)";
  std::string line;

  line = R"({"camera": 0, "frame": 1, "detections": []})";
  RequireError(line, 1, {"missing key \"utime\""});
  line = R"({"camera": 0, "frame": 1, "utime": 2, "detections": [], "cam": 1})";
  RequireError(line, ColumnOf(line, "\"cam\""), {"cam: unknown key \"cam\"", "allowed: camera"});
  line = R"({"camera": -1, "frame": 1, "utime": 2, "detections": []})";
  RequireError(line, ColumnOf(line, "-1"), {"camera: -1 is outside [0, 2147483647]"});
  line = R"({"camera": 2147483648, "frame": 1, "utime": 2, "detections": []})";
  RequireError(line, ColumnOf(line, "2147483648"), {"camera: ", "outside"});
  line = R"({"camera": 0, "frame": 1.0, "utime": 2, "detections": []})";
  RequireError(line, ColumnOf(line, "1.0"), {"frame: expected an integer, found 1.0"});
  line = R"({"camera": 0, "frame": "1", "utime": 2, "detections": []})";
  RequireError(line, ColumnOf(line, "\"1\""), {"frame: expected an integer, found a string"});
  line = R"({"camera": 0, "frame": 1, "utime": 9223372036854775808, "detections": []})";
  RequireError(line, ColumnOf(line, "9223"), {"utime: ", "beyond the 64-bit integer range"});
  line = R"({"camera": 0, "frame": 1, "utime": 2, "image_size": [0, 1080], "detections": []})";
  RequireError(line, ColumnOf(line, "0, 1080"), {"image_size[0]: 0 is outside [1, 1048576]"});
  line = R"({"camera": 0, "frame": 1, "utime": 2, "image_size": [1920], "detections": []})";
  RequireError(line, ColumnOf(line, "[1920]"), {"image_size: expected [width, height]"});
  line = R"({"camera": 0, "frame": 1, "utime": 2, "detections": {}})";
  RequireError(line, ColumnOf(line, "{}"), {"detections: expected an array, found an object"});

  line = head + R"({"score": 1}]})";
  RequireError(line, ColumnOf(line, "{\"score\""), {"detections[0]: missing key \"box\""});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1}, {"box": [0, 0, 1], "score": 1}]})";
  RequireError(line, ColumnOf(line, "[0, 0, 1]"), {"detections[1].box: expected [x_min"});
  line = head + R"({"box": [5, 0, 5, 1], "score": 1}]})";
  RequireError(
      line, ColumnOf(line, "[5, 0"), {"detections[0].box: x_min 5 is not smaller than x_max 5"});
  line = head + R"({"box": [0, 3, 1, 2], "score": 1}]})";
  RequireError(line, ColumnOf(line, "[0, 3"), {"y_min 3 is not smaller than y_max 2"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1.5}]})";
  RequireError(line, ColumnOf(line, "1.5"), {"detections[0].score: score 1.5 is outside [0, 1]"});
  line = head + R"({"box": [0, 0, 1, 1], "score": "0.9"}]})";
  RequireError(
      line, ColumnOf(line, "\"0.9\""), {"detections[0].score: expected a number, found a string"});
  line = head + R"({"box": [0, 0, 1e39, 1], "score": 1}]})";
  RequireError(line, ColumnOf(line, "1e39"), {"detections[0].box[2]: ", "float range"});
  line = head + R"({"box": [0, 0, 1e400, 1], "score": 1}]})";
  RequireError(line, ColumnOf(line, "1e400"), {"number overflow parsing '1e400'"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "keypoints": []}]})";
  RequireError(
      line, ColumnOf(line, "[]"), {"detections[0].keypoints: keypoints need a \"layout\""});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "coco17"}]})";
  RequireError(
      line, ColumnOf(line, "\"coco17\""), {"detections[0].layout: ", "only allowed together"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "none", "keypoints": []}]})";
  RequireError(line, ColumnOf(line, "\"none\""), {"detections[0].layout: unknown layout \"none\""});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "coco18", "keypoints": []}]})";
  RequireError(line, ColumnOf(line, "\"coco18\""), {"unknown layout \"coco18\""});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "body25", "keypoints": )" +
         Coco17Keypoints(0.0, 1.0) + "}]}";
  RequireError(line,
               ColumnOf(line, "[[0"),
               {"detections[0].keypoints: layout body25 has 25 joints, found 17"});
  std::string kps = Coco17Keypoints(0.0, 1.0);
  const std::size_t third = kps.find("[2, 4, 1]");
  kps.replace(third, 9, "[2, 4, -0.1]");
  line =
      head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "coco17", "keypoints": )" + kps + "}]}";
  RequireError(line,
               ColumnOf(line, "-0.1"),
               {"detections[0].keypoints[2][2]: confidence -0.1 is outside [0, 1]"});
  kps = Coco17Keypoints(0.0, 1.0);
  kps.replace(kps.find("[3, 6, 1]"), 9, "[3, 6]");
  line =
      head + R"({"box": [0, 0, 1, 1], "score": 1, "layout": "coco17", "keypoints": )" + kps + "}]}";
  RequireError(
      line, ColumnOf(line, "[3, 6]"), {"detections[0].keypoints[3]: expected [x, y, confidence]"});
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "embedding": [1, null]}]})";
  RequireError(
      line, ColumnOf(line, "null"), {"detections[0].embedding[1]: expected a number, found null"});
  std::string big = "[0";
  for (int i = 1; i <= kJsonlMaxEmbedding; ++i) big += ", 0";
  line = head + R"({"box": [0, 0, 1, 1], "score": 1, "embedding": )" + big + "]}]}";
  RequireError(line,
               ColumnOf(line, "[0, 0, 0"),
               {"detections[0].embedding: 4097 entries, more than the limit of 4096"});
  std::string many = head;
  for (int i = 0; i <= kJsonlMaxDetections; ++i)
    many += std::string(i ? ", " : "") + R"({"box": [0, 0, 1, 1], "score": 1})";
  many += "]}";
  RequireError(
      many, ColumnOf(many, "[{"), {"detections: 1001 entries, more than the limit of 1000"});
}

std::string Line(int camera, long frame, long utime, const std::string& extra = "") {
  return "{\"camera\": " + std::to_string(camera) + ", \"frame\": " + std::to_string(frame) +
         ", \"utime\": " + std::to_string(utime) + extra + ", \"detections\": []}";
}

TEST_CASE("jsonl reader: cross-line rules with line numbers", "[unit]") {
  JsonlReaderOptions options;
  options.cameras = {{0, {640, 480}}, {1, {640, 480}}, {4, {1920, 1080}}};

  // Each case: lines 1-2 are good, line 3 breaks one rule.
  struct Case {
    std::string third;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {Line(2, 11, 2000),
       "src.jsonl:3:" + std::to_string(ColumnOf(Line(2, 11, 2000), "2,")) +
           ": camera: camera 2 is not in the calibration (cameras 0, 1, 4)"},
      {Line(4, 11, 2000, ", \"image_size\": [1280, 720]"),
       "image_size: [1280, 720] differs from camera 4's calibrated image size [1920, 1080]"},
      {Line(4, 9, 2000),
       "src.jsonl:3:" + std::to_string(ColumnOf(Line(4, 9, 2000), "9,")) +
           ": frame: 9 is smaller than frame 10 of line 1 (frames must not decrease)"},
      {Line(0, 10, 2000), "camera: camera 0 already has a line for frame 10 (line 1)"},
      {Line(0, 11, 1000), "utime: 1000 is not greater than 1000, the utime of camera 0 of line 1"},
  };
  for (const Case& c : cases) {
    std::istringstream in(Line(0, 10, 1000) + "\n" + Line(1, 10, 1000) + "\n" + c.third + "\n" +
                          Line(0, 12, 3000) + "\n");
    JsonlDetectionsReader reader(&in, "src.jsonl", options);
    REQUIRE(reader.Next().has_value());
    REQUIRE(reader.Next().has_value());
    INFO(c.third);
    try {
      reader.Next();
      FAIL("no error for line 3");
    } catch (const JsonlError& e) {
      CHECK(e.line() == 3);
      CHECK(std::string(e.what()).find(c.expected) != std::string::npos);
      CHECK(std::string(e.what()).rfind("src.jsonl:3:", 0) == 0);
    }
  }

  // The same rules pass when respected; cameras of a frame in any order; gaps in frames.
  std::istringstream ok(Line(4, 10, 1000, ", \"image_size\": [1920, 1080]") + "\r\n" +
                        Line(0, 10, 999) + "\n" + Line(0, 15, 5000) + "\n" + Line(4, 15, 5001));
  JsonlDetectionsReader reader(&ok, "ok.jsonl", options);
  std::vector<std::pair<int, long>> seen;
  while (auto f = reader.Next()) seen.emplace_back(f->frame.camera_id, f->frame.frame);
  CHECK(seen == std::vector<std::pair<int, long>>{{4, 10}, {0, 10}, {0, 15}, {4, 15}});
  CHECK(reader.lines_read() == 4);
  CHECK(reader.bad_lines() == 0);
}

TEST_CASE("jsonl reader: without a calibration any camera and image size pass", "[unit]") {
  std::istringstream in(Line(77, 1, 10, ", \"image_size\": [7, 9]") + "\n" + Line(3, 1, 10));
  JsonlDetectionsReader reader(&in, "x", JsonlReaderOptions{});
  int n = 0;
  while (reader.Next()) ++n;
  CHECK(n == 2);
}

TEST_CASE("jsonl reader: --skip-bad-lines skips, counts and keeps the first messages", "[unit]") {
  JsonlReaderOptions options;
  options.skip_bad_lines = true;
  options.max_kept_bad_lines = 2;
  std::istringstream in(Line(0, 10, 100) + "\n" +  // 1 good
                        "not json\n" +             // 2 bad (syntax)
                        Line(0, 9, 200) + "\n" +   // 3 bad (frame decreases)
                        "\n" +                     // 4 bad (empty line)
                        // 5 good: checked against line 1, not against the skipped line 3 (a
                        // utime of 150 > 100 passes although line 3 had 200).
                        Line(0, 11, 150) + "\n" + Line(0, 12, 150) +
                        "\n");  // 6 bad (utime not increasing)
  JsonlDetectionsReader reader(&in, "d.jsonl", options);
  std::vector<long> frames;
  while (auto f = reader.Next()) frames.push_back(static_cast<long>(f->frame.frame));
  CHECK(frames == std::vector<long>{10, 11});
  CHECK(reader.lines_read() == 6);
  CHECK(reader.bad_lines() == 4);
  REQUIRE(reader.first_bad_lines().size() == 2);
  CHECK(reader.first_bad_lines()[0].line == 2);
  CHECK(reader.first_bad_lines()[0].message.rfind("d.jsonl:2:2: ", 0) == 0);  // "no" is no literal
  CHECK(reader.first_bad_lines()[1].line == 3);
  CHECK(reader.first_bad_lines()[1].message.find("frame: 9 is smaller than frame 10") !=
        std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Seeded round trip and mutation loop.

std::string Num(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

TEST_CASE("jsonl: seeded random camera-frames round-trip exactly", "[unit]") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> px(-500.0, 2500.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<core::KeypointLayoutId> layouts = core::AllKeypointLayouts();
  for (int trial = 0; trial < 200; ++trial) {
    core::CameraFrame cf;
    cf.camera_id = static_cast<CameraId>(rng() % 1000);
    cf.frame = static_cast<FrameIndex>(rng() % 100000);
    cf.utime = static_cast<Utime>(rng()) * 1000;
    const int n = static_cast<int>(rng() % 5);
    std::string text = "{\"detections\": [";
    for (int i = 0; i < n; ++i) {
      core::Detection2D d;
      const double x = px(rng), y = px(rng);
      d.box = {x, y, x + 1.0 + 300.0 * unit(rng), y + 1.0 + 300.0 * unit(rng)};
      d.score = unit(rng);
      text += std::string(i ? ", " : "") + "{\"box\": [" + Num(d.box.x_min) + ", " +
              Num(d.box.y_min) + ", " + Num(d.box.x_max) + ", " + Num(d.box.y_max) +
              "], \"score\": " + Num(d.score);
      if (rng() % 2 == 0) {
        d.layout = layouts[rng() % layouts.size()];
        const auto& layout = core::GetKeypointLayout(d.layout);
        text += ", \"layout\": \"" + layout.name + "\", \"keypoints\": [";
        for (int j = 0; j < layout.num_joints(); ++j) {
          core::Keypoint2D kp;
          kp.position_px = Vec2(px(rng), px(rng));
          kp.confidence = (rng() % 4 == 0) ? 0.0 : unit(rng);
          d.keypoints.push_back(kp);
          text += std::string(j ? ", " : "") + "[" + Num(kp.position_px.x()) + ", " +
                  Num(kp.position_px.y()) + ", " + Num(kp.confidence) + "]";
        }
        text += "]";
      }
      if (rng() % 3 == 0) {
        text += ", \"embedding\": [";
        const int m = 1 + static_cast<int>(rng() % 8);
        for (int k = 0; k < m; ++k) {
          const float v = static_cast<float>(unit(rng) - 0.5);
          d.embedding.push_back(v);
          text += std::string(k ? ", " : "") + Num(static_cast<double>(v));
        }
        text += "]";
      }
      text += "}";
      cf.detections.push_back(d);
    }
    text += "], \"utime\": " + std::to_string(cf.utime) +
            ", \"camera\": " + std::to_string(cf.camera_id) +
            ", \"frame\": " + std::to_string(cf.frame) + "}";
    std::string why;
    const auto parsed = ParseJsonlDetectionsLine(text, &why);
    INFO(text << "\n" << why);
    REQUIRE(parsed.has_value());
    const core::CameraFrame& got = parsed->frame;
    CHECK(got.camera_id == cf.camera_id);
    CHECK(got.frame == cf.frame);
    CHECK(got.utime == cf.utime);
    REQUIRE(got.detections.size() == cf.detections.size());
    for (std::size_t i = 0; i < cf.detections.size(); ++i) {
      const core::Detection2D& a = got.detections[i];
      const core::Detection2D& b = cf.detections[i];
      CHECK(a.box.x_min == b.box.x_min);
      CHECK(a.box.y_min == b.box.y_min);
      CHECK(a.box.x_max == b.box.x_max);
      CHECK(a.box.y_max == b.box.y_max);
      CHECK(a.score == b.score);
      CHECK(a.layout == b.layout);
      REQUIRE(a.keypoints.size() == b.keypoints.size());
      for (std::size_t j = 0; j < a.keypoints.size(); ++j) {
        CHECK(a.keypoints[j].position_px == b.keypoints[j].position_px);
        CHECK(a.keypoints[j].confidence == b.keypoints[j].confidence);
      }
      CHECK(a.embedding == b.embedding);
    }
  }
}

TEST_CASE("jsonl: seeded byte mutations never crash and errors stay in the line", "[unit]") {
  const std::string base =
      R"({"camera": 3, "frame": 120, "utime": 1700000004000000, "image_size": [1920, 1080], )"
      R"("detections": [{"box": [812.5, 300, 901.0, 560.25], "score": 0.93, )"
      R"("embedding": [0.5, -1e-3]}, )"
      R"({"box": [1, 2, 3, 4], "score": 1, "layout": "shelf14", )"
      R"("keypoints": [[1, 2, 1], [1, 2, 1], )"
      R"([1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 1], )"
      R"([1, 2, 1], [1, 2, 1], [1, 2, 1], [1, 2, 0.5]]}]})";
  REQUIRE(ParseJsonlDetectionsLine(base, nullptr).has_value());
  std::mt19937 rng(7);
  const std::string alphabet = "{}[]\",:0123456789.eE+-tfnul \\x\x80\xff";
  int failures = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string line = base;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits && !line.empty(); ++e) {
      const std::size_t pos = rng() % line.size();
      switch (rng() % 3) {
        case 0:
          line.erase(pos, 1);
          break;
        case 1:
          line[pos] = alphabet[rng() % alphabet.size()];
          break;
        default:
          line.insert(pos, 1, alphabet[rng() % alphabet.size()]);
          break;
      }
    }
    std::string why;
    const auto parsed = ParseJsonlDetectionsLine(line, &why);
    if (parsed.has_value()) continue;
    ++failures;
    // "column C: ..." with 1 <= C <= size + 1.
    INFO(line << "\n" << why);
    REQUIRE(why.rfind("column ", 0) == 0);
    const std::size_t column = std::stoul(why.substr(7));
    CHECK(column >= 1);
    CHECK(column <= line.size() + 1);
  }
  CHECK(failures > 1000);  // the mutations do exercise the error paths
}

}  // namespace
}  // namespace mvtrack::formats
