#pragma once
/// @file
/// A strict RFC 8259 JSON parser building a small tree with byte positions, and schema-check
/// helpers, shared by the JSON readers of `mvtrack convert` (JSON-lines detections, COCO-style
/// keypoint JSON). No dependency beyond the standard library; see jsonl_detections.h for why
/// not yaml-cpp. Stateless functions; JsonChecker is a single-owner, single-threaded object.

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace mvtrack::cli {

struct JsonValue;

/// One member of a JSON object.
struct JsonMember {
  std::string key;                  ///< the decoded key
  std::size_t key_column = 0;       ///< 1-based byte offset of the key's opening quote
  std::unique_ptr<JsonValue> value; ///< the value (never null once parsed)
};

/// A parsed JSON value. Numbers keep their literal (a view into the parsed text, which must
/// outlive the value).
struct JsonValue {
  /// The JSON type.
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;          ///< the JSON type
  /// 1-based byte offset of the value's first byte in the parsed text (the column when the
  /// text is one line).
  std::size_t column = 0;
  bool boolean = false;             ///< kBool
  std::string_view number;          ///< kNumber: the literal (a view into the text)
  std::string string;               ///< kString: the decoded UTF-8 text
  std::vector<JsonValue> items;     ///< kArray
  std::vector<JsonMember> members;  ///< kObject, in text order (keys unique)
};

/// An error: where (1-based byte offset, key path) and why.
struct JsonValueError {
  std::size_t column = 0;  ///< 1-based byte offset; 0: the input as a whole
  std::string path;        ///< key path of the offending value ("" for the root)
  std::string reason;      ///< what is wrong
};

/// "null", "a boolean", "a number", "a string", "an array", "an object".
const char* JsonKindName(JsonValue::Kind kind);

/// Parses `text`, which must hold exactly one JSON value (surrounded by optional whitespace).
/// Duplicate keys, invalid UTF-8, lone surrogates, leading zeros and nesting deeper than
/// `max_depth` are errors. `unit` names the input in messages ("line": "unexpected end of the
/// line"). On failure returns nullopt and fills `error` (when not null; path empty).
std::optional<JsonValue> ParseJson(std::string_view text,
                                   std::string_view unit,
                                   int max_depth,
                                   JsonValueError* error);

/// Schema-check helpers: each returns true when the value fits, else records the first failure
/// (error()) and returns false. Values of the detections wire format are floats, hence the float
/// range check of GetReal.
class JsonChecker {
 public:
  /// The first failure (valid after a method returned false).
  const JsonValueError& error() const { return error_; }

  /// Records the failure at `at` (its column), key path `path`; returns false.
  bool Fail(const JsonValue& at, const std::string& path, std::string reason) {
    error_.column = at.column;
    error_.path = path;
    error_.reason = std::move(reason);
    return false;
  }

  /// True when `v` is of `kind`; otherwise fails with "expected K, found K2".
  bool ExpectKind(const JsonValue& v, const std::string& path, JsonValue::Kind kind) {
    if (v.kind == kind) return true;
    return Fail(v,
                path,
                std::string("expected ") + JsonKindName(kind) + ", found " + JsonKindName(v.kind));
  }

  /// An integer literal (no fraction or exponent) in [min, max].
  bool GetInt(const JsonValue& v,
              const std::string& path,
              std::int64_t min,
              std::int64_t max,
              std::int64_t* out) {
    if (v.kind != JsonValue::Kind::kNumber) {
      return Fail(v, path, std::string("expected an integer, found ") + JsonKindName(v.kind));
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

  /// A number within the float range (the detections wire format stores floats).
  bool GetReal(const JsonValue& v, const std::string& path, double* out) {
    if (v.kind != JsonValue::Kind::kNumber) {
      return Fail(v, path, std::string("expected a number, found ") + JsonKindName(v.kind));
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

  /// A number in [0, 1].
  bool GetUnit(const JsonValue& v, const std::string& path, std::string_view what, double* out) {
    if (!GetReal(v, path, out)) return false;
    if (!(*out >= 0.0 && *out <= 1.0)) {
      return Fail(v, path, std::string(what) + " " + std::string(v.number) + " is outside [0, 1]");
    }
    return true;
  }

  /// An array of exactly `n` elements (n >= 0) or of at most `max` (n < 0).
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

  /// Checks the members of object `v` against `allowed` (unknown keys are errors) and returns
  /// them by key; `required` must all be present.
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

  /// `path.key` ("key" for the root).
  static std::string Join(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
  }
  /// `path[i]`.
  static std::string Index(const std::string& path, std::size_t i) {
    return path + "[" + std::to_string(i) + "]";
  }

 private:
  JsonValueError error_;
};

}  // namespace mvtrack::cli
