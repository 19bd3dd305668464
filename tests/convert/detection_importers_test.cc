// Readers of MOTChallenge det.txt and COCO-style keypoint JSON (lib/formats/
// detection_importers.h): hand-made inputs whose detections are known by construction, the
// accepted variants, and bad inputs (file, line, column and reason in the message).

#include "formats/detection_importers.h"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"

namespace mvtrack::formats {
namespace {

// The ImportError message of reading `text`, or "" when it reads.
template <typename Read>
std::string ErrorOf(Read read) {
  try {
    read();
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

std::string MotError(const std::string& text, MotChallengeOptions options = {}) {
  return ErrorOf([&] { ReadMotChallengeDetections(text, "c0/det.txt", options); });
}

std::string CocoError(const std::string& text, CocoOptions options = {}) {
  return ErrorOf([&] { ReadCocoKeypoints(text, "cam1.json", options); });
}

// 17 keypoints as a flat COCO list: keypoint j at (10 + j, 100 + 2 j) with third value v(j).
template <typename V>
std::string FlatKeypoints(V v) {
  std::string s = "[";
  for (int j = 0; j < kCocoNumKeypoints; ++j) {
    s +=
        (j ? ", " : "") + std::to_string(10 + j) + ", " + std::to_string(100 + 2 * j) + ", " + v(j);
  }
  return s + "]";
}

TEST_CASE("MOTChallenge: boxes, scores and frames as constructed", "[unit]") {
  // Frame 3 before frame 1, CRLF, spaces, a blank line, 7 and 10 columns.
  const std::string text =
      "3, -1, 11, 21, 30, 60, 0.5\r\n"
      "1,-1,101,201,50.5,120,0.75,-1,-1,-1\n"
      "\n"
      "1,7,1,1,10,20,1\n";
  const ImportedDetections d = ReadMotChallengeDetections(text, "det.txt", {});
  REQUIRE(d.records == 3);
  REQUIRE(d.by_frame.size() == 2);
  REQUIRE(d.first_line.at(3) == 1);
  REQUIRE(d.first_line.at(1) == 2);
  const std::vector<core::Detection2D>& f1 = d.by_frame.at(1);
  REQUIRE(f1.size() == 2);
  // Pixel origin 1: one pixel subtracted from left and top.
  CHECK(f1[0].box.x_min == 100.0);
  CHECK(f1[0].box.y_min == 200.0);
  CHECK(f1[0].box.x_max == 150.5);
  CHECK(f1[0].box.y_max == 320.0);
  CHECK(f1[0].score == 0.75);
  CHECK(f1[0].layout == core::KeypointLayoutId::kNone);
  CHECK(f1[0].keypoints.empty());
  CHECK(f1[1].box.x_min == 0.0);
  CHECK(f1[1].box.y_max == 20.0);
  const core::Detection2D& f3 = d.by_frame.at(3).at(0);
  CHECK(f3.box.x_min == 10.0);
  CHECK(f3.box.x_max == 40.0);
  CHECK(f3.score == 0.5);

  MotChallengeOptions zero;
  zero.pixel_origin = 0;
  const ImportedDetections z = ReadMotChallengeDetections(text, "det.txt", zero);
  CHECK(z.by_frame.at(1)[0].box.x_min == 101.0);
  CHECK(z.by_frame.at(1)[0].box.x_max == 151.5);
}

TEST_CASE("MOTChallenge: scores outside [0, 1] fail or are clamped", "[unit]") {
  const std::string text = "1,-1,1,1,10,10,-2.5\n2,-1,1,1,10,10,1.5\n";
  CHECK(MotError(text) ==
        "c0/det.txt:1: column 7 (conf): '-2.5' is outside [0, 1] "
        "(--clamp-scores clamps it)");
  MotChallengeOptions clamp;
  clamp.clamp_scores = true;
  const ImportedDetections d = ReadMotChallengeDetections(text, "det.txt", clamp);
  CHECK(d.clamped == 2);
  CHECK(d.by_frame.at(1)[0].score == 0.0);
  CHECK(d.by_frame.at(2)[0].score == 1.0);
}

TEST_CASE("MOTChallenge: bad lines name file, line, column and reason", "[unit]") {
  CHECK(MotError("1,-1,1,1,10,10,1\n1,-1,1,1,10\n") ==
        "c0/det.txt:2: 5 comma-separated values, expected 7 (frame,id,left,top,width,height,"
        "conf) or 10 (... ,x,y,z)");
  CHECK(MotError("0,-1,1,1,10,10,1\n") ==
        "c0/det.txt:1: column 1 (frame): 0 is not >= 1 (MOTChallenge frames start at 1)");
  CHECK(MotError("1.5,-1,1,1,10,10,1\n") ==
        "c0/det.txt:1: column 1 (frame): '1.5' is not an integer");
  CHECK(MotError("1,x,1,1,10,10,1\n") == "c0/det.txt:1: column 2 (id): 'x' is not an integer");
  CHECK(MotError("1,-1,1,,10,10,1\n") ==
        "c0/det.txt:1: column 4 (top): empty value, expected a number");
  CHECK(MotError("1,-1,1,1,0,10,1\n") == "c0/det.txt:1: column 5 (width): '0' is not > 0");
  CHECK(MotError("1,-1,1,1,10,-3,1\n") == "c0/det.txt:1: column 6 (height): '-3' is not > 0");
  CHECK(MotError("1,-1,nan,1,10,10,1\n") ==
        "c0/det.txt:1: column 3 (left): 'nan' is not finite or beyond the float range");
  CHECK(MotError("1,-1,1e39,1,10,10,1\n") ==
        "c0/det.txt:1: column 3 (left): '1e39' is not finite or beyond the float range");
  CHECK(MotError("1,-1,1,1,10,10,1,-1,-1,z\n") ==
        "c0/det.txt:1: column 10 (z): 'z' is not a number");
  CHECK(MotError("99999999999999999999,-1,1,1,10,10,1\n") ==
        "c0/det.txt:1: column 1 (frame): '99999999999999999999' is out of range");
  CHECK(MotError("") == "");
  CHECK(ReadMotChallengeDetections("\n \n", "det.txt", {}).records == 0);
}

TEST_CASE("COCO: keypoint results array with bbox, score and image ids", "[unit]") {
  const std::string kps = FlatKeypoints([](int j) { return j == 3 ? "0" : "0.5"; });
  const std::string text =
      "[\n"
      "  {\"image_id\": 4, \"category_id\": 1, \"keypoints\": " +
      kps +
      ", \"score\": 0.875, \"bbox\": [10.5, 20, 100, 200]},\n"
      "  {\"image_id\": \"cam1/000002.jpg\", \"keypoints\": " +
      kps +
      ", \"score\": 0.25, \"box\": [1, 2, 3, 4], \"idx\": [7]},\n"
      "  {\"frame\": 4, \"keypoints\": " +
      kps + ", \"score\": 1, \"bbox\": [0, 0, 1, 1]}\n]\n";
  const ImportedDetections d = ReadCocoKeypoints(text, "cam1.json", {});
  REQUIRE(d.records == 3);
  REQUIRE(d.by_frame.size() == 2);
  CHECK(d.first_line.at(4) == 2);
  CHECK(d.first_line.at(2) == 3);
  const core::Detection2D& a = d.by_frame.at(4).at(0);
  CHECK(a.layout == core::KeypointLayoutId::kCoco17);
  REQUIRE(a.keypoints.size() == 17);
  CHECK(a.keypoints[5].position_px.x() == 15.0);
  CHECK(a.keypoints[5].position_px.y() == 110.0);
  CHECK(a.keypoints[5].confidence == 0.5);
  CHECK(a.keypoints[3].confidence == 0.0);
  CHECK(a.score == 0.875);
  CHECK(a.box.x_min == 10.5);
  CHECK(a.box.y_min == 20.0);
  CHECK(a.box.x_max == 110.5);
  CHECK(a.box.y_max == 220.0);
  const core::Detection2D& b = d.by_frame.at(2).at(0);
  CHECK(b.box.x_max == 4.0);
  CHECK(b.box.y_max == 6.0);
  CHECK(b.score == 0.25);
  CHECK(d.by_frame.at(4).at(1).score == 1.0);
}

TEST_CASE("COCO: annotations object, nested triples, derived box and score", "[unit]") {
  // Only keypoints 0 (10, 100) and 16 (26, 132) are detected: bounds 16 x 32.
  std::string nested = "[";
  for (int j = 0; j < 17; ++j) {
    const bool seen = j == 0 || j == 16;
    nested += std::string(j ? ", " : "") + "[" + std::to_string(10 + j) + ", " +
              std::to_string(100 + 2 * j) + ", " + (seen ? (j == 0 ? "0.25" : "0.75") : "0") + "]";
  }
  nested += "]";
  const std::string text =
      "{\"images\": [{\"id\": 9}], \"annotations\": [{\"image_id\": 9, "
      "\"keypoints\": " +
      nested + "}], \"categories\": []}";
  const ImportedDetections d = ReadCocoKeypoints(text, "cam1.json", {});
  const core::Detection2D& a = d.by_frame.at(9).at(0);
  // Score: the mean confidence of the detected keypoints.
  CHECK(a.score == 0.5);
  // Box: bounds grown by 10 % of their height (32 -> 3.2 px) on each side.
  CHECK(a.box.x_min == Approx(10.0 - 3.2));
  CHECK(a.box.x_max == Approx(26.0 + 3.2));
  CHECK(a.box.y_min == Approx(100.0 - 3.2));
  CHECK(a.box.y_max == Approx(132.0 + 3.2));
  CHECK(a.keypoints[16].confidence == 0.75);
}

TEST_CASE("COCO: visibility flags and clamping", "[unit]") {
  const std::string flags = FlatKeypoints([](int j) { return std::to_string(j % 3); });
  const std::string text =
      "[{\"image_id\": 0, \"keypoints\": " + flags + ", \"bbox\": [0, 0, 5, 5]}]";
  CocoOptions visibility;
  visibility.keypoint_score = CocoKeypointScore::kVisibility;
  // A copy: the import result is a temporary.
  const core::Detection2D a = ReadCocoKeypoints(text, "x", visibility).by_frame.at(0).at(0);
  CHECK(a.keypoints[0].confidence == 0.0);
  CHECK(a.keypoints[1].confidence == 1.0);
  CHECK(a.keypoints[2].confidence == 1.0);
  CHECK(a.keypoints[3].confidence == 0.0);
  // As confidences, 2 is out of range: an error naming the value, or clamped.
  CHECK(CocoError(text) == "cam1.json:1:" + std::to_string(text.find(", 2,") + 3) +
                               ": [0].keypoints[8]: confidence 2 of keypoint 2 is outside [0, 1] "
                               "(use --keypoint-score visibility for COCO annotation flags, or "
                               "--clamp-scores)");
  CocoOptions clamp;
  clamp.clamp_scores = true;
  const ImportedDetections c = ReadCocoKeypoints(text, "x", clamp);
  CHECK(c.clamped == 5);  // keypoints 2, 5, 8, 11, 14
  CHECK(c.by_frame.at(0).at(0).keypoints[2].confidence == 1.0);
  const std::string bad_flag =
      "[{\"image_id\": 0, \"keypoints\": " + FlatKeypoints([](int) { return "0.5"; }) + "}]";
  CHECK(CocoError(bad_flag, visibility)
            .find("[0].keypoints[2]: visibility 0.5 of keypoint 0 is "
                  "not 0, 1 or 2") != std::string::npos);
}

TEST_CASE("COCO: bad input names file, line, column, path and reason", "[unit]") {
  const std::string kps = FlatKeypoints([](int) { return "1"; });
  CHECK(CocoError("[\n  {\"image_id\": 1,\n   \"keypoints\": [1, 2]}\n]") ==
        "cam1.json:3:17: [0].keypoints: expected 51 numbers (17 COCO keypoints x, y, v) or 17 "
        "[x, y, v] arrays, found 2 values");
  CHECK(CocoError("[\n  {\"image_id\": 1, \"keypoints\": " + kps + "},\n  {\"keypoints\": " + kps +
                  "}\n]") == "cam1.json:3:3: [1]: missing key \"image_id\" (or \"frame\")");
  CHECK(CocoError("[{\"image_id\": 1}]") == "cam1.json:1:2: [0]: missing key \"keypoints\"");
  CHECK(CocoError("[{\"image_id\": -1, \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:15: [0].image_id: -1 is outside [0, 9223372036854775807]");
  CHECK(CocoError("[{\"image_id\": \"abc.jpg\", \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:15: [0].image_id: \"abc.jpg\" does not end in a frame number (expected "
        "e.g. \"000123.jpg\")");
  CHECK(CocoError("[{\"image_id\": 1, \"frame\": 1, \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:27: [0].frame: a record has both \"image_id\" and \"frame\" (give one)");
  CHECK(CocoError("[{\"image_id\": 1, \"category_id\": 2, \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:33: [0].category_id: 2 is not 1 (person, the only COCO keypoint category)");
  CHECK(CocoError("[{\"image_id\": 1, \"score\": 1.5, \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:27: [0].score: score 1.5 is outside [0, 1] (--clamp-scores clamps it)");
  CHECK(CocoError("[{\"image_id\": 1, \"bbox\": [0, 0, 0, 5], \"keypoints\": " + kps + "}]") ==
        "cam1.json:1:26: [0].bbox: width 0 and height 5 must be > 0");
  CHECK(CocoError("[{\"image_id\": 1, \"bbox\": [0, 0, 1, 5], \"box\": [0, 0, 1, 5], "
                  "\"keypoints\": " +
                  kps + "}]") == "cam1.json:1:47: [0].box: a record has both \"bbox\" and \"box\"");
  // No box and fewer than 2 detected keypoints.
  const std::string one = FlatKeypoints([](int j) { return j == 0 ? "1" : "0"; });
  CHECK(CocoError("[{\"image_id\": 1, \"keypoints\": " + one + "}]") ==
        "cam1.json:1:31: [0].keypoints: no \"bbox\" and fewer than 2 keypoints with confidence "
        "> 0 to derive one");
  // Containers and JSON syntax.
  CHECK(CocoError("{\"images\": []}") ==
        "cam1.json:1:1: expected an array of records or an object with \"annotations\", found an "
        "object without \"annotations\"");
  CHECK(CocoError("{\"annotations\": 3}") ==
        "cam1.json:1:17: annotations: expected an array of records, found a number");
  CHECK(CocoError("[1]") == "cam1.json:1:2: [0]: expected an object, found a number");
  CHECK(CocoError("[\n{\"image_id\": 1,}\n]") ==
        "cam1.json:2:16: syntax error while parsing object key - unexpected '}'; expected string "
        "literal");
  CHECK(CocoError("[\n") ==
        "cam1.json:2:1: syntax error while parsing value - unexpected end of input; expected '[', "
        "'{', or a literal");
  CHECK(CocoError("") ==
        "cam1.json:1:1: syntax error while parsing value - unexpected end of input; expected '[', "
        "'{', or a literal");
  CHECK(ReadCocoKeypoints("[]", "x", {}).records == 0);
}

TEST_CASE("Import frame utime rule", "[unit]") {
  CHECK(ImportFrameUtime(1, 1, 25.0, 1000) == 1000);
  CHECK(ImportFrameUtime(3, 1, 25.0, 1000) == 81000);
  CHECK(ImportFrameUtime(3, 0, 30.0, 0) == 100000);
  CHECK(ImportFrameUtime(1, 0, 30.0, 0) == 33333);
}

}  // namespace
}  // namespace mvtrack::formats
