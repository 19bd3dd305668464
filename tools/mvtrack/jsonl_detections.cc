#include "mvtrack/jsonl_detections.h"

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

namespace mvtrack::cli {
namespace {

// ---------------------------------------------------------------------------------------------
// A strict RFC 8259 JSON parser for one line, building a small tree with byte columns.

struct JsonValue;

struct JsonMember {
  std::string key;
  std::size_t key_column = 0;
  std::unique_ptr<JsonValue> value;
};

struct JsonValue {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;
  std::size_t column = 0;           // 1-based byte column of the first byte of the value
  bool boolean = false;             // kBool
  std::string_view number;          // kNumber: the literal (a view into the line)
  std::string string;               // kString: the decoded UTF-8 text
  std::vector<JsonValue> items;     // kArray
  std::vector<JsonMember> members;  // kObject, in line order (keys unique)
};

const char* KindName(JsonValue::Kind kind) {
  switch (kind) {
    case JsonValue::Kind::kNull:
      return "null";
    case JsonValue::Kind::kBool:
      return "a boolean";
    case JsonValue::Kind::kNumber:
      return "a number";
    case JsonValue::Kind::kString:
      return "a string";
    case JsonValue::Kind::kArray:
      return "an array";
    case JsonValue::Kind::kObject:
      return "an object";
  }
  return "?";
}

// An error: where (column, key path) and why.
struct LineError {
  std::size_t column = 0;  // 0: the line as a whole (cross-line errors without a value)
  std::string path;
  std::string reason;
};

class JsonParser {
 public:
  explicit JsonParser(std::string_view text) : text_(text) {}

  // The line's value (which must be the only value on the line), or nullopt with error().
  std::optional<JsonValue> ParseDocument() {
    JsonValue root;
    if (!ParseValue(&root, 0)) return std::nullopt;
    SkipWhitespace();
    if (pos_ != text_.size()) {
      Fail("unexpected " + Describe(pos_) + " after the end of the JSON value");
      return std::nullopt;
    }
    return root;
  }

  const LineError& error() const { return error_; }

 private:
  bool Fail(std::string reason) { return FailAt(pos_, std::move(reason)); }
  bool FailAt(std::size_t pos, std::string reason) {
    error_.column = pos + 1;
    error_.reason = std::move(reason);
    return false;
  }

  // "'x'", "byte 0xC3" or "the end of the line" for the byte at `pos`.
  std::string Describe(std::size_t pos) const {
    if (pos >= text_.size()) return "end of the line";
    const auto c = static_cast<unsigned char>(text_[pos]);
    if (c >= 0x21 && c < 0x7F) return std::string("'") + static_cast<char>(c) + "'";
    static const char kHex[] = "0123456789ABCDEF";
    return std::string("byte 0x") + kHex[c >> 4] + kHex[c & 15];
  }

  void SkipWhitespace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }

  bool ParseValue(JsonValue* out, int depth) {
    SkipWhitespace();
    out->column = pos_ + 1;
    if (pos_ >= text_.size()) return Fail("unexpected end of the line, expected a JSON value");
    const char c = text_[pos_];
    if (c == '{') return ParseObject(out, depth);
    if (c == '[') return ParseArray(out, depth);
    if (c == '"') {
      out->kind = JsonValue::Kind::kString;
      return ParseString(&out->string);
    }
    if (c == '-' || (c >= '0' && c <= '9')) return ParseNumber(out);
    if (ParseLiteral("true")) {
      out->kind = JsonValue::Kind::kBool;
      out->boolean = true;
      return true;
    }
    if (ParseLiteral("false")) {
      out->kind = JsonValue::Kind::kBool;
      return true;
    }
    if (ParseLiteral("null")) {
      out->kind = JsonValue::Kind::kNull;
      return true;
    }
    return Fail("unexpected " + Describe(pos_) + ", expected a JSON value");
  }

  bool ParseLiteral(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) return false;
    // "trueish" is not a literal followed by garbage but an invalid token.
    const std::size_t end = pos_ + word.size();
    if (end < text_.size() &&
        ((text_[end] >= 'a' && text_[end] <= 'z') || (text_[end] >= 'A' && text_[end] <= 'Z'))) {
      return false;
    }
    pos_ = end;
    return true;
  }

  bool ParseObject(JsonValue* out, int depth) {
    if (depth >= kJsonlMaxDepth)
      return Fail("nesting deeper than " + std::to_string(kJsonlMaxDepth));
    out->kind = JsonValue::Kind::kObject;
    ++pos_;  // '{'
    SkipWhitespace();
    if (pos_ < text_.size() && text_[pos_] == '}') {
      ++pos_;
      return true;
    }
    std::set<std::string> keys;
    while (true) {
      SkipWhitespace();
      if (pos_ >= text_.size() || text_[pos_] != '"') {
        return Fail("unexpected " + Describe(pos_) +
                    ", expected a key (a string in double quotes)");
      }
      JsonMember member;
      member.key_column = pos_ + 1;
      if (!ParseString(&member.key)) return false;
      if (!keys.insert(member.key).second) {
        return FailAt(member.key_column - 1, "duplicate key \"" + member.key + "\"");
      }
      SkipWhitespace();
      if (pos_ >= text_.size() || text_[pos_] != ':') {
        return Fail("unexpected " + Describe(pos_) + ", expected ':' after the key");
      }
      ++pos_;
      member.value = std::make_unique<JsonValue>();
      if (!ParseValue(member.value.get(), depth + 1)) return false;
      out->members.push_back(std::move(member));
      SkipWhitespace();
      if (pos_ < text_.size() && text_[pos_] == ',') {
        ++pos_;
        continue;
      }
      if (pos_ < text_.size() && text_[pos_] == '}') {
        ++pos_;
        return true;
      }
      return Fail("unexpected " + Describe(pos_) + ", expected ',' or '}' in an object");
    }
  }

  bool ParseArray(JsonValue* out, int depth) {
    if (depth >= kJsonlMaxDepth)
      return Fail("nesting deeper than " + std::to_string(kJsonlMaxDepth));
    out->kind = JsonValue::Kind::kArray;
    ++pos_;  // '['
    SkipWhitespace();
    if (pos_ < text_.size() && text_[pos_] == ']') {
      ++pos_;
      return true;
    }
    while (true) {
      out->items.emplace_back();
      if (!ParseValue(&out->items.back(), depth + 1)) return false;
      SkipWhitespace();
      if (pos_ < text_.size() && text_[pos_] == ',') {
        ++pos_;
        continue;
      }
      if (pos_ < text_.size() && text_[pos_] == ']') {
        ++pos_;
        return true;
      }
      return Fail("unexpected " + Describe(pos_) + ", expected ',' or ']' in an array");
    }
  }

  // -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
  bool ParseNumber(JsonValue* out) {
    const std::size_t begin = pos_;
    auto digit = [&](std::size_t p) {
      return p < text_.size() && text_[p] >= '0' && text_[p] <= '9';
    };
    if (text_[pos_] == '-') ++pos_;
    if (!digit(pos_)) return Fail("invalid number: expected a digit after '-'");
    if (text_[pos_] == '0') {
      ++pos_;
      if (digit(pos_)) return Fail("invalid number: leading zeros are not allowed");
    } else {
      while (digit(pos_)) ++pos_;
    }
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      if (!digit(pos_)) return Fail("invalid number: expected a digit after '.'");
      while (digit(pos_)) ++pos_;
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      if (!digit(pos_)) return Fail("invalid number: expected a digit in the exponent");
      while (digit(pos_)) ++pos_;
    }
    out->kind = JsonValue::Kind::kNumber;
    out->number = text_.substr(begin, pos_ - begin);
    return true;
  }

  static void AppendUtf8(std::uint32_t cp, std::string* out) {
    if (cp < 0x80) {
      out->push_back(static_cast<char>(cp));
    } else if (cp < 0x800) {
      out->push_back(static_cast<char>(0xC0 | (cp >> 6)));
      out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    } else if (cp < 0x10000) {
      out->push_back(static_cast<char>(0xE0 | (cp >> 12)));
      out->push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
      out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    } else {
      out->push_back(static_cast<char>(0xF0 | (cp >> 18)));
      out->push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
      out->push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
      out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    }
  }

  // Four hex digits at pos_ (consumed) into `value`.
  bool ParseHex4(std::uint32_t* value) {
    *value = 0;
    for (int i = 0; i < 4; ++i, ++pos_) {
      if (pos_ >= text_.size()) return Fail("unterminated \\u escape");
      const char c = text_[pos_];
      std::uint32_t d = 0;
      if (c >= '0' && c <= '9') {
        d = static_cast<std::uint32_t>(c - '0');
      } else if (c >= 'a' && c <= 'f') {
        d = static_cast<std::uint32_t>(c - 'a' + 10);
      } else if (c >= 'A' && c <= 'F') {
        d = static_cast<std::uint32_t>(c - 'A' + 10);
      } else {
        return Fail("invalid \\u escape: " + Describe(pos_) + " is not a hex digit");
      }
      *value = *value * 16 + d;
    }
    return true;
  }

  // One UTF-8 encoded code point starting at pos_ (a byte >= 0x80), validated and copied.
  bool CopyUtf8(std::string* out) {
    const auto b0 = static_cast<unsigned char>(text_[pos_]);
    std::size_t length = 0;
    std::uint32_t cp = 0;
    std::uint32_t min = 0;
    if (b0 >= 0xC2 && b0 <= 0xDF) {
      length = 2, cp = b0 & 0x1Fu, min = 0x80;
    } else if (b0 >= 0xE0 && b0 <= 0xEF) {
      length = 3, cp = b0 & 0x0Fu, min = 0x800;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
      length = 4, cp = b0 & 0x07u, min = 0x10000;
    } else {
      return Fail("invalid UTF-8 (" + Describe(pos_) + ")");
    }
    if (pos_ + length > text_.size()) return Fail("invalid UTF-8 (truncated sequence)");
    for (std::size_t i = 1; i < length; ++i) {
      const auto b = static_cast<unsigned char>(text_[pos_ + i]);
      if ((b & 0xC0u) != 0x80u) return Fail("invalid UTF-8 (" + Describe(pos_ + i) + ")");
      cp = (cp << 6) | (b & 0x3Fu);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
      return Fail("invalid UTF-8 (overlong, surrogate or out-of-range code point)");
    }
    out->append(text_.substr(pos_, length));
    pos_ += length;
    return true;
  }

  bool ParseString(std::string* out) {
    ++pos_;  // '"'
    out->clear();
    while (true) {
      if (pos_ >= text_.size()) return Fail("unterminated string");
      const char c = text_[pos_];
      if (c == '"') {
        ++pos_;
        return true;
      }
      if (static_cast<unsigned char>(c) < 0x20) {
        return Fail("control character " + Describe(pos_) + " in a string (escape it)");
      }
      if (static_cast<unsigned char>(c) >= 0x80) {
        if (!CopyUtf8(out)) return false;
        continue;
      }
      if (c != '\\') {
        out->push_back(c);
        ++pos_;
        continue;
      }
      ++pos_;
      if (pos_ >= text_.size()) return Fail("unterminated string");
      const char e = text_[pos_++];
      switch (e) {
        case '"':
          out->push_back('"');
          break;
        case '\\':
          out->push_back('\\');
          break;
        case '/':
          out->push_back('/');
          break;
        case 'b':
          out->push_back('\b');
          break;
        case 'f':
          out->push_back('\f');
          break;
        case 'n':
          out->push_back('\n');
          break;
        case 'r':
          out->push_back('\r');
          break;
        case 't':
          out->push_back('\t');
          break;
        case 'u': {
          std::uint32_t cp = 0;
          if (!ParseHex4(&cp)) return false;
          if (cp >= 0xDC00 && cp <= 0xDFFF) return Fail("invalid \\u escape: lone low surrogate");
          if (cp >= 0xD800 && cp <= 0xDBFF) {
            std::uint32_t low = 0;
            if (text_.substr(pos_, 2) != "\\u") {
              return Fail("invalid \\u escape: high surrogate without a low surrogate");
            }
            pos_ += 2;
            if (!ParseHex4(&low)) return false;
            if (low < 0xDC00 || low > 0xDFFF) {
              return Fail("invalid \\u escape: high surrogate without a low surrogate");
            }
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
          }
          AppendUtf8(cp, out);
          break;
        }
        default:
          --pos_;
          return Fail("invalid escape '\\" + std::string(1, e) + "'");
      }
    }
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  LineError error_;
};

// ---------------------------------------------------------------------------------------------
// The schema.

struct ParsedLine {
  JsonlCameraFrame value;
  std::size_t camera_column = 0;
  std::size_t frame_column = 0;
  std::size_t utime_column = 0;
  std::size_t image_size_column = 0;  // 0 when the line has no image_size
};

class SchemaChecker {
 public:
  const LineError& error() const { return error_; }

  bool Fail(const JsonValue& at, const std::string& path, std::string reason) {
    error_.column = at.column;
    error_.path = path;
    error_.reason = std::move(reason);
    return false;
  }

  bool ExpectKind(const JsonValue& v, const std::string& path, JsonValue::Kind kind) {
    if (v.kind == kind) return true;
    return Fail(v, path, std::string("expected ") + KindName(kind) + ", found " + KindName(v.kind));
  }

  // An integer literal (no fraction or exponent) in [min, max].
  bool GetInt(const JsonValue& v,
              const std::string& path,
              std::int64_t min,
              std::int64_t max,
              std::int64_t* out) {
    if (v.kind != JsonValue::Kind::kNumber) {
      return Fail(v, path, std::string("expected an integer, found ") + KindName(v.kind));
    }
    if (v.number.find_first_of(".eE") != std::string_view::npos) {
      return Fail(v, path, "expected an integer, found " + std::string(v.number));
    }
    const auto [end, ec] =
        std::from_chars(v.number.data(), v.number.data() + v.number.size(), *out);
    if (ec != std::errc() || end != v.number.data() + v.number.size()) {
      return Fail(v, path, std::string(v.number) + " is beyond the 64-bit integer range");
    }
    if (*out < min || *out > max) {
      return Fail(v,
                  path,
                  std::string(v.number) + " is outside [" + std::to_string(min) + ", " +
                      std::to_string(max) + "]");
    }
    return true;
  }

  // A number within the float range (the detections wire format stores floats).
  bool GetReal(const JsonValue& v, const std::string& path, double* out) {
    if (v.kind != JsonValue::Kind::kNumber) {
      return Fail(v, path, std::string("expected a number, found ") + KindName(v.kind));
    }
    const auto [end, ec] =
        std::from_chars(v.number.data(), v.number.data() + v.number.size(), *out);
    if (ec == std::errc::result_out_of_range) {
      return Fail(v, path, std::string(v.number) + " is beyond the range of a double");
    }
    if (ec != std::errc() || end != v.number.data() + v.number.size()) {
      return Fail(v, path, "invalid number " + std::string(v.number));
    }
    if (std::abs(*out) > static_cast<double>(std::numeric_limits<float>::max())) {
      return Fail(
          v, path, std::string(v.number) + " is beyond the float range of the detections log");
    }
    return true;
  }

  // A number in [0, 1].
  bool GetUnit(const JsonValue& v, const std::string& path, std::string_view what, double* out) {
    if (!GetReal(v, path, out)) return false;
    if (!(*out >= 0.0 && *out <= 1.0)) {
      return Fail(v, path, std::string(what) + " " + std::string(v.number) + " is outside [0, 1]");
    }
    return true;
  }

  // An array of exactly `n` elements (n >= 0) or of at most `max` (n < 0).
  bool ExpectArray(
      const JsonValue& v, const std::string& path, long n, std::size_t max, std::string_view what) {
    if (!ExpectKind(v, path, JsonValue::Kind::kArray)) return false;
    if (n >= 0 && v.items.size() != static_cast<std::size_t>(n)) {
      return Fail(v,
                  path,
                  "expected " + std::string(what) + " (" + std::to_string(n) + " values), found " +
                      std::to_string(v.items.size()) + " values");
    }
    if (n < 0 && v.items.size() > max) {
      return Fail(v,
                  path,
                  std::to_string(v.items.size()) + " entries, more than the limit of " +
                      std::to_string(max));
    }
    return true;
  }

  // Checks the members of object `v` against `allowed` (unknown keys are errors) and returns
  // them by key; `required` must all be present.
  bool Members(const JsonValue& v,
               const std::string& path,
               const std::vector<std::string_view>& allowed,
               const std::vector<std::string_view>& required,
               std::map<std::string, const JsonValue*>* out) {
    if (!ExpectKind(v, path, JsonValue::Kind::kObject)) return false;
    out->clear();
    for (const JsonMember& m : v.members) {
      bool known = false;
      for (std::string_view a : allowed) known = known || m.key == a;
      if (!known) {
        std::string list;
        for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        JsonValue at;
        at.column = m.key_column;
        return Fail(at, Join(path, m.key), "unknown key \"" + m.key + "\" (allowed: " + list + ")");
      }
      (*out)[m.key] = m.value.get();
    }
    for (std::string_view r : required) {
      if (out->count(std::string(r)) == 0) {
        return Fail(v, path, "missing key \"" + std::string(r) + "\"");
      }
    }
    return true;
  }

  static std::string Join(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
  }
  static std::string Index(const std::string& path, std::size_t i) {
    return path + "[" + std::to_string(i) + "]";
  }

  bool Detection(const JsonValue& v, const std::string& path, core::Detection2D* d) {
    std::map<std::string, const JsonValue*> m;
    if (!Members(
            v, path, {"box", "score", "keypoints", "layout", "embedding"}, {"box", "score"}, &m)) {
      return false;
    }
    // box
    const JsonValue& box = *m.at("box");
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
      const JsonValue& layout = *m.at("layout");
      const std::string layout_path = Join(path, "layout");
      if (!ExpectKind(layout, layout_path, JsonValue::Kind::kString)) return false;
      const std::optional<core::KeypointLayoutId> id = core::KeypointLayoutFromName(layout.string);
      if (!id.has_value() || *id == core::KeypointLayoutId::kNone) {
        return Fail(layout,
                    layout_path,
                    "unknown layout \"" + layout.string +
                        "\" (coco17, body25, shelf14, campus14, panoptic19)");
      }
      d->layout = *id;
      const int n = core::GetKeypointLayout(*id).num_joints();
      const JsonValue& kps = *m.at("keypoints");
      const std::string kps_path = Join(path, "keypoints");
      if (!ExpectKind(kps, kps_path, JsonValue::Kind::kArray)) return false;
      if (kps.items.size() != static_cast<std::size_t>(n)) {
        return Fail(kps,
                    kps_path,
                    "layout " + layout.string + " has " + std::to_string(n) + " joints, found " +
                        std::to_string(kps.items.size()) + " keypoints");
      }
      d->keypoints.resize(kps.items.size());
      for (std::size_t j = 0; j < kps.items.size(); ++j) {
        const JsonValue& kp = kps.items[j];
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
      const JsonValue& e = *m.at("embedding");
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
    return true;
  }

  bool Line(const JsonValue& root, ParsedLine* out) {
    std::map<std::string, const JsonValue*> m;
    if (root.kind != JsonValue::Kind::kObject) {
      return Fail(
          root, "", std::string("a line must be a JSON object, found ") + KindName(root.kind));
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
      const JsonValue& size = *m.at("image_size");
      if (!ExpectArray(size, "image_size", 2, 0, "[width, height]")) return false;
      std::int64_t w = 0, h = 0;
      if (!GetInt(size.items[0], "image_size[0]", 1, kJsonlMaxImageSize, &w)) return false;
      if (!GetInt(size.items[1], "image_size[1]", 1, kJsonlMaxImageSize, &h)) return false;
      out->value.image_width_px = static_cast<int>(w);
      out->value.image_height_px = static_cast<int>(h);
      out->image_size_column = size.column;
    }
    const JsonValue& dets = *m.at("detections");
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

 private:
  LineError error_;
};

// Parses and checks one line; on failure fills `error`.
std::optional<ParsedLine> ParseLine(std::string_view line, LineError* error) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  JsonParser parser(line);
  const std::optional<JsonValue> root = parser.ParseDocument();
  if (!root.has_value()) {
    *error = parser.error();
    return std::nullopt;
  }
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

}  // namespace mvtrack::cli
