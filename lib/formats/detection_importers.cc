#include "formats/detection_importers.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/keypoint_layout.h"
#include "datasets/dataset.h"
#include "json/json.h"

namespace mvtrack::formats {
namespace {

constexpr double kFloatMax = static_cast<double>(std::numeric_limits<float>::max());

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// "'text'" shortened to 40 bytes, for messages.
std::string Quote(std::string_view s) {
  if (s.size() > 40) return "'" + std::string(s.substr(0, 40)) + "...'";
  return "'" + std::string(s) + "'";
}

// Clamps `*value` into [0, 1] when allowed; false when it is outside and clamping is off.
bool UnitOrClamp(double* value, bool clamp, std::int64_t* clamped) {
  if (*value >= 0.0 && *value <= 1.0) return true;
  if (!clamp) return false;
  *value = std::clamp(*value, 0.0, 1.0);
  ++*clamped;
  return true;
}

// ---------------------------------------------------------------------------------------------
// MOTChallenge.

constexpr const char* kMotColumns[] = {
    "frame", "id", "left", "top", "width", "height", "conf", "x", "y", "z"};

class MotLine {
 public:
  MotLine(const std::string& source, std::int64_t line) : source_(source), line_(line) {}

  [[noreturn]] void Fail(std::size_t column, const std::string& reason) const {
    throw ImportError(source_ + ":" + std::to_string(line_) + ": column " +
                      std::to_string(column + 1) + " (" + kMotColumns[column] + "): " + reason);
  }

  std::int64_t Int(std::string_view field, std::size_t column) const {
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (field.empty()) Fail(column, "empty value, expected an integer");
    if (ec == std::errc::result_out_of_range) Fail(column, Quote(field) + " is out of range");
    if (ec != std::errc() || end != field.data() + field.size()) {
      Fail(column, Quote(field) + " is not an integer");
    }
    return v;
  }

  double Real(std::string_view field, std::size_t column) const {
    if (field.empty()) Fail(column, "empty value, expected a number");
    // from_chars does not accept a leading '+'; MOT files never write one, so neither do we.
    double v = 0.0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (ec != std::errc() || end != field.data() + field.size()) {
      Fail(column, Quote(field) + " is not a number");
    }
    if (!std::isfinite(v) || std::abs(v) > kFloatMax) {
      Fail(column, Quote(field) + " is not finite or beyond the float range");
    }
    return v;
  }

 private:
  const std::string& source_;
  std::int64_t line_;
};

// ---------------------------------------------------------------------------------------------
// COCO.

// The frame of an image file name: the decimal digits that end its base name without
// extension ("cam0/000123.jpg" -> 123).
std::optional<FrameIndex> FrameFromFileName(const std::string& name) {
  std::string_view s = name;
  const std::size_t slash = s.find_last_of("/\\");
  if (slash != std::string_view::npos) s.remove_prefix(slash + 1);
  const std::size_t dot = s.rfind('.');
  if (dot != std::string_view::npos) s = s.substr(0, dot);
  std::size_t begin = s.size();
  while (begin > 0 && s[begin - 1] >= '0' && s[begin - 1] <= '9') --begin;
  if (begin == s.size()) return std::nullopt;
  FrameIndex frame = 0;
  const auto [end, ec] = std::from_chars(s.data() + begin, s.data() + s.size(), frame);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return frame;
}

class CocoChecker : public json::Checker {
 public:
  CocoChecker(const CocoOptions& options, ImportedDetections* out) : options_(options), out_(out) {}

  bool Record(const json::Value& v,
              const std::string& path,
              FrameIndex* frame,
              core::Detection2D* d) {
    if (!ExpectKind(v, path, json::Value::Kind::kObject)) return false;
    const json::Value* image_id = nullptr;
    const json::Value* frame_value = nullptr;
    const json::Value* keypoints = nullptr;
    const json::Value* score = nullptr;
    const json::Value* box = nullptr;
    std::string box_key;
    const json::Value* category = nullptr;
    for (const json::Member& m : v.members) {
      if (m.key == "image_id") image_id = m.value.get();
      if (m.key == "frame") frame_value = m.value.get();
      if (m.key == "keypoints") keypoints = m.value.get();
      if (m.key == "score") score = m.value.get();
      if (m.key == "category_id") category = m.value.get();
      if (m.key == "bbox" || m.key == "box") {
        if (box != nullptr) {
          return Fail(*m.value, Join(path, m.key), "a record has both \"bbox\" and \"box\"");
        }
        box = m.value.get();
        box_key = m.key;
      }
    }
    // frame
    if (image_id != nullptr && frame_value != nullptr) {
      return Fail(*frame_value,
                  Join(path, "frame"),
                  "a record has both \"image_id\" and \"frame\" (give one)");
    }
    if (image_id == nullptr && frame_value == nullptr) {
      return Fail(v, path, "missing key \"image_id\" (or \"frame\")");
    }
    if (frame_value != nullptr) {
      if (!GetInt(*frame_value,
                  Join(path, "frame"),
                  0,
                  std::numeric_limits<FrameIndex>::max(),
                  frame)) {
        return false;
      }
    } else if (image_id->kind == json::Value::Kind::kString) {
      const std::optional<FrameIndex> f = FrameFromFileName(image_id->string);
      if (!f.has_value()) {
        return Fail(*image_id,
                    Join(path, "image_id"),
                    "\"" + image_id->string +
                        "\" does not end in a frame number (expected e.g. \"000123.jpg\")");
      }
      *frame = *f;
    } else if (!GetInt(*image_id,
                       Join(path, "image_id"),
                       0,
                       std::numeric_limits<FrameIndex>::max(),
                       frame)) {
      return false;
    }
    // category
    if (category != nullptr) {
      std::int64_t c = 0;
      if (!GetInt(*category,
                  Join(path, "category_id"),
                  std::numeric_limits<std::int64_t>::min(),
                  std::numeric_limits<std::int64_t>::max(),
                  &c)) {
        return false;
      }
      if (c != 1) {
        return Fail(*category,
                    Join(path, "category_id"),
                    std::to_string(c) + " is not 1 (person, the only COCO keypoint category)");
      }
    }
    // keypoints
    if (keypoints == nullptr) return Fail(v, path, "missing key \"keypoints\"");
    if (!Keypoints(*keypoints, Join(path, "keypoints"), d)) return false;
    // score
    if (score != nullptr) {
      const std::string score_path = Join(path, "score");
      if (!GetReal(*score, score_path, &d->score)) return false;
      if (!UnitOrClamp(&d->score, options_.clamp_scores, &out_->clamped)) {
        return Fail(*score,
                    score_path,
                    "score " + std::string(score->number) +
                        " is outside [0, 1] (--clamp-scores clamps it)");
      }
    } else {
      d->score = datasets::MeanKeypointScore(d->keypoints);
    }
    // box
    if (box != nullptr) {
      const std::string box_path = Join(path, box_key);
      if (!ExpectArray(*box, box_path, 4, 0, "[x, y, width, height]")) return false;
      double b[4];
      for (std::size_t i = 0; i < 4; ++i) {
        if (!GetReal(box->items[i], Index(box_path, i), &b[i])) return false;
      }
      if (!(b[2] > 0.0) || !(b[3] > 0.0)) {
        return Fail(*box,
                    box_path,
                    "width " + std::string(box->items[2].number) + " and height " +
                        std::string(box->items[3].number) + " must be > 0");
      }
      d->box = core::BoxPx{b[0], b[1], b[0] + b[2], b[1] + b[3]};
    } else {
      const std::optional<core::BoxPx> from_keypoints = datasets::BoxFromKeypoints(d->keypoints);
      if (!from_keypoints.has_value()) {
        return Fail(*keypoints,
                    Join(path, "keypoints"),
                    "no \"bbox\" and fewer than 2 keypoints with confidence > 0 to derive one");
      }
      d->box = *from_keypoints;
    }
    return true;
  }

  bool Keypoints(const json::Value& v, const std::string& path, core::Detection2D* d) {
    if (!ExpectKind(v, path, json::Value::Kind::kArray)) return false;
    const std::size_t n = kCocoNumKeypoints;
    const bool nested = !v.items.empty() && v.items.front().kind == json::Value::Kind::kArray;
    if (!nested && v.items.size() != 3 * n) {
      return Fail(v,
                  path,
                  "expected " + std::to_string(3 * n) + " numbers (17 COCO keypoints x, y, v) or " +
                      std::to_string(n) + " [x, y, v] arrays, found " +
                      std::to_string(v.items.size()) + " values");
    }
    if (nested && v.items.size() != n) {
      return Fail(v,
                  path,
                  "expected " + std::to_string(n) +
                      " [x, y, v] arrays (17 COCO keypoints), found " +
                      std::to_string(v.items.size()));
    }
    d->layout = core::KeypointLayoutId::kCoco17;
    d->keypoints.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      const json::Value* xyv[3];
      std::string at[3];
      if (nested) {
        const std::string kp_path = Index(path, j);
        if (!ExpectArray(v.items[j], kp_path, 3, 0, "[x, y, v]")) return false;
        for (std::size_t k = 0; k < 3; ++k) {
          xyv[k] = &v.items[j].items[k];
          at[k] = Index(kp_path, k);
        }
      } else {
        for (std::size_t k = 0; k < 3; ++k) {
          xyv[k] = &v.items[3 * j + k];
          at[k] = Index(path, 3 * j + k);
        }
      }
      double x = 0.0, y = 0.0, c = 0.0;
      if (!GetReal(*xyv[0], at[0], &x) || !GetReal(*xyv[1], at[1], &y) ||
          !GetReal(*xyv[2], at[2], &c)) {
        return false;
      }
      if (options_.keypoint_score == CocoKeypointScore::kVisibility) {
        if (c != 0.0 && c != 1.0 && c != 2.0) {
          return Fail(*xyv[2],
                      at[2],
                      "visibility " + std::string(xyv[2]->number) + " of keypoint " +
                          std::to_string(j) + " is not 0, 1 or 2 (--keypoint-score visibility)");
        }
        c = c > 0.0 ? 1.0 : 0.0;
      } else if (!UnitOrClamp(&c, options_.clamp_scores, &out_->clamped)) {
        return Fail(*xyv[2],
                    at[2],
                    "confidence " + std::string(xyv[2]->number) + " of keypoint " +
                        std::to_string(j) +
                        " is outside [0, 1] (use --keypoint-score visibility for COCO "
                        "annotation flags, or --clamp-scores)");
      }
      d->keypoints[j].position_px = Vec2(x, y);
      d->keypoints[j].confidence = c;
    }
    return true;
  }

 private:
  const CocoOptions& options_;
  ImportedDetections* out_;
};

}  // namespace

ImportedDetections ReadMotChallengeDetections(std::string_view text,
                                              const std::string& source,
                                              const MotChallengeOptions& options) {
  if (options.pixel_origin != 0 && options.pixel_origin != 1) {
    throw std::invalid_argument("pixel_origin must be 0 or 1");
  }
  ImportedDetections out;
  const double origin = static_cast<double>(options.pixel_origin);
  std::int64_t line_number = 0;
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    std::string_view line = text.substr(0, newline);
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (Trim(line).empty()) continue;
    const MotLine at(source, line_number);
    std::vector<std::string_view> fields;
    std::size_t begin = 0;
    while (true) {
      const std::size_t comma = line.find(',', begin);
      fields.push_back(Trim(line.substr(begin, comma - begin)));
      if (comma == std::string_view::npos) break;
      begin = comma + 1;
    }
    if (fields.size() != 7 && fields.size() != 10) {
      throw ImportError(source + ":" + std::to_string(line_number) + ": " +
                        std::to_string(fields.size()) +
                        " comma-separated values, expected 7 (frame,id,left,top,width,height,"
                        "conf) or 10 (... ,x,y,z)");
    }
    const std::int64_t frame = at.Int(fields[0], 0);
    if (frame < 1) {
      at.Fail(0, std::to_string(frame) + " is not >= 1 (MOTChallenge frames start at 1)");
    }
    at.Int(fields[1], 1);
    const double left = at.Real(fields[2], 2);
    const double top = at.Real(fields[3], 3);
    const double width = at.Real(fields[4], 4);
    const double height = at.Real(fields[5], 5);
    if (!(width > 0.0)) at.Fail(4, Quote(fields[4]) + " is not > 0");
    if (!(height > 0.0)) at.Fail(5, Quote(fields[5]) + " is not > 0");
    double conf = at.Real(fields[6], 6);
    if (!UnitOrClamp(&conf, options.clamp_scores, &out.clamped)) {
      at.Fail(6, Quote(fields[6]) + " is outside [0, 1] (--clamp-scores clamps it)");
    }
    for (std::size_t i = 7; i < fields.size(); ++i) at.Real(fields[i], i);
    if (std::abs(left - origin + width) > kFloatMax ||
        std::abs(top - origin + height) > kFloatMax) {
      at.Fail(4, "the box's right or bottom edge is beyond the float range");
    }
    core::Detection2D d;
    d.box = core::BoxPx{left - origin, top - origin, left - origin + width, top - origin + height};
    d.score = conf;
    out.by_frame[frame].push_back(std::move(d));
    out.first_line.emplace(frame, line_number);
    ++out.records;
  }
  return out;
}

ImportedDetections ReadCocoKeypoints(std::string_view text,
                                     const std::string& source,
                                     const CocoOptions& options) {
  ImportedDetections out;
  const json::LineIndex lines(text);
  auto fail = [&](const json::Error& e) {
    std::string where = source;
    if (e.column > 0) {
      const json::LineColumn at = lines.At(e.column);
      where += ":" + std::to_string(at.line) + ":" + std::to_string(at.column);
    }
    throw ImportError(where + ": " + (e.path.empty() ? "" : e.path + ": ") + e.reason);
  };
  json::Error error;
  const std::optional<json::Value> root = json::Parse(text, 16, &error);
  if (!root.has_value()) fail(error);
  const json::Value* records = &*root;
  std::string path;
  if (root->kind == json::Value::Kind::kObject) {
    records = nullptr;
    for (const json::Member& m : root->members) {
      if (m.key == "annotations") records = m.value.get();
    }
    if (records == nullptr) {
      fail({root->column,
            "",
            "expected an array of records or an object with \"annotations\", found an object "
            "without \"annotations\""});
    }
    path = "annotations";
  }
  if (records->kind != json::Value::Kind::kArray) {
    fail({records->column,
          path,
          std::string("expected an array of records, found ") + json::KindName(records->kind)});
  }
  CocoChecker checker(options, &out);
  for (std::size_t i = 0; i < records->items.size(); ++i) {
    FrameIndex frame = 0;
    core::Detection2D d;
    const json::Value& record = records->items[i];
    if (!checker.Record(record, path + "[" + std::to_string(i) + "]", &frame, &d)) {
      fail(checker.error());
    }
    out.by_frame[frame].push_back(std::move(d));
    out.first_line.emplace(frame, static_cast<std::int64_t>(lines.At(record.column).line));
    ++out.records;
  }
  return out;
}

Utime ImportFrameUtime(FrameIndex frame,
                       FrameIndex first_frame_number,
                       double fps,
                       Utime start_utime) {
  return start_utime + datasets::FrameUtime(frame - first_frame_number, fps);
}

}  // namespace mvtrack::formats
