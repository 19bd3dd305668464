#include "formats/jsonl_detections.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <system_error>
#include <utility>

#include "core/keypoint_layout.h"
#include "json/json.h"

namespace mvtrack::formats {
namespace {

using LineError = json::Error;

// ---------------------------------------------------------------------------------------------
// The schema.

struct ParsedLine {
  JsonlCameraFrame value;
  std::size_t camera_column = 0;
  std::size_t frame_column = 0;
  std::size_t utime_column = 0;
  std::size_t image_size_column = 0;  // 0 when the line has no image_size
};

class SchemaChecker : public json::Checker {
 public:
  bool Detection(const json::Value& v, const std::string& path, core::Detection2D* d) {
    std::map<std::string, const json::Value*> m;
    if (!Members(v,
                 path,
                 {"box", "score", "keypoints", "layout", "embedding", "embedding_model"},
                 {"box", "score"},
                 &m)) {
      return false;
    }
    // box
    const json::Value& box = *m.at("box");
    const std::string box_path = Join(path, "box");
    if (!ExpectArray(box, box_path, 4, 0, "[x_min, y_min, x_max, y_max]")) return false;
    double b[4];
    for (std::size_t i = 0; i < 4; ++i) {
      if (!GetReal(box.items[i], Index(box_path, i), &b[i])) return false;
    }
    if (!(b[0] < b[2])) {
      return Fail(box,
                  box_path,
                  "x_min " + std::string(box.items[0].number) + " is not smaller than x_max " +
                      std::string(box.items[2].number));
    }
    if (!(b[1] < b[3])) {
      return Fail(box,
                  box_path,
                  "y_min " + std::string(box.items[1].number) + " is not smaller than y_max " +
                      std::string(box.items[3].number));
    }
    d->box = core::BoxPx{b[0], b[1], b[2], b[3]};
    // score
    if (!GetUnit(*m.at("score"), Join(path, "score"), "score", &d->score)) return false;
    // keypoints + layout
    const bool has_keypoints = m.count("keypoints") > 0;
    const bool has_layout = m.count("layout") > 0;
    if (has_keypoints && !has_layout) {
      return Fail(*m.at("keypoints"),
                  Join(path, "keypoints"),
                  "keypoints need a \"layout\" (coco17, body25, shelf14, campus14, panoptic19)");
    }
    if (has_layout && !has_keypoints) {
      return Fail(*m.at("layout"),
                  Join(path, "layout"),
                  "\"layout\" is only allowed together with \"keypoints\"");
    }
    if (has_keypoints) {
      const json::Value& layout = *m.at("layout");
      const std::string layout_path = Join(path, "layout");
      if (!ExpectKind(layout, layout_path, json::Value::Kind::kString)) return false;
      const std::optional<core::KeypointLayoutId> id = core::KeypointLayoutFromName(layout.string);
      if (!id.has_value() || *id == core::KeypointLayoutId::kNone) {
        return Fail(layout,
                    layout_path,
                    "unknown layout \"" + layout.string +
                        "\" (coco17, body25, shelf14, campus14, panoptic19)");
      }
      d->layout = *id;
      const int n = core::GetKeypointLayout(*id).num_joints();
      const json::Value& kps = *m.at("keypoints");
      const std::string kps_path = Join(path, "keypoints");
      if (!ExpectKind(kps, kps_path, json::Value::Kind::kArray)) return false;
      if (kps.items.size() != static_cast<std::size_t>(n)) {
        return Fail(kps,
                    kps_path,
                    "layout " + layout.string + " has " + std::to_string(n) + " joints, found " +
                        std::to_string(kps.items.size()) + " keypoints");
      }
      d->keypoints.resize(kps.items.size());
      for (std::size_t j = 0; j < kps.items.size(); ++j) {
        const json::Value& kp = kps.items[j];
        const std::string kp_path = Index(kps_path, j);
        if (!ExpectArray(kp, kp_path, 3, 0, "[x, y, confidence]")) return false;
        double x = 0.0, y = 0.0;
        if (!GetReal(kp.items[0], Index(kp_path, 0), &x)) return false;
        if (!GetReal(kp.items[1], Index(kp_path, 1), &y)) return false;
        if (!GetUnit(kp.items[2], Index(kp_path, 2), "confidence", &d->keypoints[j].confidence)) {
          return false;
        }
        d->keypoints[j].position_px = Vec2(x, y);
      }
    }
    // embedding
    if (m.count("embedding") > 0) {
      const json::Value& e = *m.at("embedding");
      const std::string e_path = Join(path, "embedding");
      if (!ExpectArray(e, e_path, -1, static_cast<std::size_t>(kJsonlMaxEmbedding), "")) {
        return false;
      }
      d->embedding.resize(e.items.size());
      for (std::size_t i = 0; i < e.items.size(); ++i) {
        double value = 0.0;
        if (!GetReal(e.items[i], Index(e_path, i), &value)) return false;
        d->embedding[i] = static_cast<float>(value);
      }
    }
    if (m.count("embedding_model") > 0) {
      const json::Value& e = *m.at("embedding_model");
      const std::string e_path = Join(path, "embedding_model");
      if (!ExpectKind(e, e_path, json::Value::Kind::kString)) return false;
      if (e.string.size() > static_cast<std::size_t>(kJsonlMaxModelName)) {
        return Fail(e,
                    e_path,
                    std::to_string(e.string.size()) + " characters, more than the limit of " +
                        std::to_string(kJsonlMaxModelName));
      }
      if (!d->embedding.empty()) d->embedding_model = e.string;
    }
    return true;
  }

  bool Line(const json::Value& root, ParsedLine* out) {
    std::map<std::string, const json::Value*> m;
    if (root.kind != json::Value::Kind::kObject) {
      return Fail(root,
                  "",
                  std::string("a line must be a JSON object, found ") + json::KindName(root.kind));
    }
    if (!Members(root,
                 "",
                 {"camera", "frame", "utime", "image_size", "detections"},
                 {"camera", "frame", "utime", "detections"},
                 &m)) {
      return false;
    }
    std::int64_t value = 0;
    if (!GetInt(*m.at("camera"), "camera", 0, std::numeric_limits<CameraId>::max(), &value)) {
      return false;
    }
    out->value.frame.camera_id = static_cast<CameraId>(value);
    out->camera_column = m.at("camera")->column;
    if (!GetInt(*m.at("frame"),
                "frame",
                0,
                std::numeric_limits<std::int64_t>::max(),
                &out->value.frame.frame)) {
      return false;
    }
    out->frame_column = m.at("frame")->column;
    if (!GetInt(*m.at("utime"),
                "utime",
                0,
                std::numeric_limits<std::int64_t>::max(),
                &out->value.frame.utime)) {
      return false;
    }
    out->utime_column = m.at("utime")->column;
    if (m.count("image_size") > 0) {
      const json::Value& size = *m.at("image_size");
      if (!ExpectArray(size, "image_size", 2, 0, "[width, height]")) return false;
      std::int64_t w = 0, h = 0;
      if (!GetInt(size.items[0], "image_size[0]", 1, kJsonlMaxImageSize, &w)) return false;
      if (!GetInt(size.items[1], "image_size[1]", 1, kJsonlMaxImageSize, &h)) return false;
      out->value.image_width_px = static_cast<int>(w);
      out->value.image_height_px = static_cast<int>(h);
      out->image_size_column = size.column;
    }
    const json::Value& dets = *m.at("detections");
    if (!ExpectArray(dets, "detections", -1, static_cast<std::size_t>(kJsonlMaxDetections), "")) {
      return false;
    }
    out->value.frame.detections.resize(dets.items.size());
    for (std::size_t i = 0; i < dets.items.size(); ++i) {
      if (!Detection(dets.items[i], Index("detections", i), &out->value.frame.detections[i])) {
        return false;
      }
    }
    return true;
  }
};

// Parses and checks one line; on failure fills `error`.
std::optional<ParsedLine> ParseLine(std::string_view line, LineError* error) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const std::optional<json::Value> root = json::Parse(line, kJsonlMaxDepth, error);
  if (!root.has_value()) return std::nullopt;
  ParsedLine parsed;
  SchemaChecker checker;
  if (!checker.Line(*root, &parsed)) {
    *error = checker.error();
    return std::nullopt;
  }
  return parsed;
}

// "COLUMN: PATH: REASON" pieces joined after `prefix` ("column 12" or "file:3:12").
std::string FormatError(const std::string& prefix, const LineError& e) {
  std::string s = prefix;
  s += ": ";
  if (!e.path.empty()) s += e.path + ": ";
  s += e.reason;
  return s;
}

}  // namespace

std::optional<JsonlCameraFrame> ParseJsonlDetectionsLine(std::string_view line, std::string* why) {
  LineError error;
  std::optional<ParsedLine> parsed = ParseLine(line, &error);
  if (!parsed.has_value()) {
    if (why != nullptr) *why = FormatError("column " + std::to_string(error.column), error);
    return std::nullopt;
  }
  return std::move(parsed->value);
}

JsonlError::JsonlError(JsonlBadLine bad) : std::runtime_error(bad.message), bad_(std::move(bad)) {}

JsonlDetectionsReader::JsonlDetectionsReader(std::istream* in,
                                             std::string source_name,
                                             JsonlReaderOptions options)
    : in_(in), source_name_(std::move(source_name)), options_(std::move(options)) {}

std::optional<JsonlCameraFrame> JsonlDetectionsReader::Next() {
  std::string line;
  while (std::getline(*in_, line)) {
    ++lines_read_;
    bytes_read_ += static_cast<std::int64_t>(line.size()) + 1;
    LineError error;
    std::optional<ParsedLine> parsed = ParseLine(line, &error);
    if (parsed.has_value()) {
      const JsonlCameraFrame& f = parsed->value;
      const CameraId camera = f.frame.camera_id;
      const std::string at_line = " of line ";
      // Cross-line rules, in the order of the documentation.
      if (!options_.cameras.empty() && options_.cameras.count(camera) == 0) {
        std::string ids;
        for (const auto& [id, info] : options_.cameras) {
          ids += (ids.empty() ? "" : ", ") + std::to_string(id);
        }
        error = {parsed->camera_column,
                 "camera",
                 "camera " + std::to_string(camera) + " is not in the calibration (cameras " + ids +
                     ")"};
      } else if (!options_.cameras.empty() && parsed->image_size_column != 0 &&
                 (f.image_width_px != options_.cameras.at(camera).width_px ||
                  f.image_height_px != options_.cameras.at(camera).height_px)) {
        const JsonlCameraInfo& info = options_.cameras.at(camera);
        error = {parsed->image_size_column,
                 "image_size",
                 "[" + std::to_string(f.image_width_px) + ", " + std::to_string(f.image_height_px) +
                     "] differs from camera " + std::to_string(camera) +
                     "'s calibrated image size [" + std::to_string(info.width_px) + ", " +
                     std::to_string(info.height_px) + "]"};
      } else if (current_frame_.has_value() && f.frame.frame < *current_frame_) {
        error = {parsed->frame_column,
                 "frame",
                 std::to_string(f.frame.frame) + " is smaller than frame " +
                     std::to_string(*current_frame_) + at_line +
                     std::to_string(current_frame_line_) + " (frames must not decrease)"};
      } else if (current_frame_.has_value() && f.frame.frame == *current_frame_ &&
                 cameras_in_frame_.count(camera) > 0) {
        error = {parsed->camera_column,
                 "camera",
                 "camera " + std::to_string(camera) + " already has a line for frame " +
                     std::to_string(f.frame.frame) + " (line " +
                     std::to_string(cameras_in_frame_.at(camera)) + ")"};
      } else if (last_utime_.count(camera) > 0 && f.frame.utime <= last_utime_.at(camera).first) {
        error = {parsed->utime_column,
                 "utime",
                 std::to_string(f.frame.utime) + " is not greater than " +
                     std::to_string(last_utime_.at(camera).first) + ", the utime of camera " +
                     std::to_string(camera) + at_line +
                     std::to_string(last_utime_.at(camera).second) +
                     " (a camera's utime must increase from frame to frame)"};
      } else {
        if (!current_frame_.has_value() || f.frame.frame != *current_frame_) {
          current_frame_ = f.frame.frame;
          current_frame_line_ = lines_read_;
          cameras_in_frame_.clear();
        }
        cameras_in_frame_[camera] = lines_read_;
        last_utime_[camera] = {f.frame.utime, lines_read_};
        return std::move(parsed->value);
      }
    }
    JsonlBadLine bad;
    bad.line = lines_read_;
    bad.message = FormatError(
        source_name_ + ":" + std::to_string(lines_read_) + ":" + std::to_string(error.column),
        error);
    if (!options_.skip_bad_lines) throw JsonlError(std::move(bad));
    ++bad_lines_;
    if (first_bad_lines_.size() < options_.max_kept_bad_lines) {
      first_bad_lines_.push_back(std::move(bad));
    }
  }
  if (in_->bad()) {
    throw std::runtime_error(source_name_ + ": read error after line " +
                             std::to_string(lines_read_));
  }
  return std::nullopt;
}

}  // namespace mvtrack::formats
