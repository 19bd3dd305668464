#pragma once
/// @file
/// The project's one way to read and write JSON: a strict RFC 8259 reader that builds a small
/// tree in which every value and key keeps its byte position (so errors name file:line:column),
/// schema-check helpers, and the JSON string quoting every writer uses. Parsing and quoting are
/// nlohmann-json's (Debian's nlohmann-json3-dev, confined to json.cc); this module adds only the
/// positions, which nlohmann's DOM does not keep, and the project's limits (nesting depth,
/// duplicate keys). Stateless functions; Checker is a single-owner, single-threaded object.
///
/// Canonical writers that fix number formatting byte for byte (the tracks JSONL, the eval
/// report) format their numbers themselves and quote strings with Quote()/AppendQuoted().

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mvtrack::json {

struct Value;

/// One member of a JSON object.
struct Member {
  std::string key;               ///< the decoded key
  std::size_t key_column = 0;    ///< 1-based byte offset of the key's opening quote
  std::unique_ptr<Value> value;  ///< the value (never null once parsed)
};

/// A parsed JSON value. Numbers keep their literal (a view into the parsed text, which must
/// outlive the value).
struct Value {
  /// The JSON type.
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;  ///< the JSON type
  /// 1-based byte offset of the value's first byte in the parsed text (the column when the
  /// text is one line; LocateOffset() turns it into line:column otherwise).
  std::size_t column = 0;
  bool boolean = false;         ///< kBool
  std::string_view number;      ///< kNumber: the literal (a view into the text)
  double real = 0.0;            ///< kNumber: its value as a double (finite: Parse checks)
  std::string string;           ///< kString: the decoded UTF-8 text
  std::vector<Value> items;     ///< kArray
  std::vector<Member> members;  ///< kObject, in text order (keys unique)

  /// The member `key` of an object, or null (also when this is not an object).
  const Value* Find(std::string_view key) const;
};

/// An error: where (1-based byte offset, key path) and why.
struct Error {
  std::size_t column = 0;  ///< 1-based byte offset; 0: the input as a whole
  std::string path;        ///< key path of the offending value ("" for the root)
  std::string reason;      ///< what is wrong
};

/// "null", "a boolean", "a number", "a string", "an array", "an object".
const char* KindName(Value::Kind kind);

/// Parses `text`, which must hold exactly one JSON value (surrounded by optional whitespace).
/// Syntax errors, duplicate keys, invalid UTF-8, lone surrogates, leading zeros, a byte order
/// mark, numbers beyond the range of a double and nesting deeper than `max_depth` are errors.
/// On failure returns nullopt and fills `error` (when not null; path empty).
std::optional<Value> Parse(std::string_view text, int max_depth, Error* error);

/// A 1-based line and column (bytes) in a text.
struct LineColumn {
  std::size_t line = 1;    ///< 1-based line
  std::size_t column = 1;  ///< 1-based byte column within the line
};

/// The line starts of a text, to turn the 1-based byte offsets of Value and Error into
/// line:column (lines end with '\n'). Keeps no reference to the text.
class LineIndex {
 public:
  /// Indexes `text` (one pass).
  explicit LineIndex(std::string_view text);
  /// Line and column of the 1-based byte `offset` (offsets past the end count from the end).
  LineColumn At(std::size_t offset) const;

 private:
  std::size_t size_ = 0;
  std::vector<std::size_t> starts_;
};

/// `text` as a JSON string literal, quotes included: '"', '\\' and control characters escaped
/// (\n, \t, ... or \u00XX), other UTF-8 kept as is, invalid UTF-8 replaced by U+FFFD.
std::string Quote(std::string_view text);
/// Appends Quote(text) to `out`.
void AppendQuoted(std::string_view text, std::string* out);

/// Schema-check helpers: each returns true when the value fits, else records the first failure
/// (error()) and returns false.
class Checker {
 public:
  /// The first failure (valid after a method returned false).
  const Error& error() const { return error_; }

  /// Records the failure at `at` (its column), key path `path`; returns false.
  bool Fail(const Value& at, const std::string& path, std::string reason);
  /// Records the failure at byte `column` (1-based), key path `path`; returns false.
  bool FailAt(std::size_t column, const std::string& path, std::string reason);

  /// True when `v` is of `kind`; otherwise fails with "expected K, found K2".
  bool ExpectKind(const Value& v, const std::string& path, Value::Kind kind);

  /// An integer literal (no fraction or exponent) in [min, max].
  bool GetInt(const Value& v,
              const std::string& path,
              std::int64_t min,
              std::int64_t max,
              std::int64_t* out);

  /// A number within the range of a double (every parsed number is).
  bool GetDouble(const Value& v, const std::string& path, double* out);

  /// A number within the float range (the detections wire format stores floats).
  bool GetReal(const Value& v, const std::string& path, double* out);

  /// A number in [0, 1]; `what` names it in the message.
  bool GetUnit(const Value& v, const std::string& path, std::string_view what, double* out);

  /// A string.
  bool GetString(const Value& v, const std::string& path, std::string* out);

  /// An array of exactly `n` elements (n >= 0) or of at most `max` (n < 0); `what` names the
  /// expected content in the message.
  bool ExpectArray(
      const Value& v, const std::string& path, long n, std::size_t max, std::string_view what);

  /// Checks the members of object `v` against `allowed` (unknown keys are errors) and returns
  /// them by key; `required` must all be present.
  bool Members(const Value& v,
               const std::string& path,
               const std::vector<std::string_view>& allowed,
               const std::vector<std::string_view>& required,
               std::map<std::string, const Value*>* out);

  /// `path.key` ("key" for the root), the key as Shown.
  static std::string Join(const std::string& path, std::string_view key);
  /// Text from the input as an error message shows it: at most 64 characters (then "...
  /// (N characters)"), bytes that are not printable ASCII as '?' (a key of 100,000 characters or
  /// with terminal control bytes is not echoed whole).
  static std::string Shown(std::string_view text);
  /// `path[i]`.
  static std::string Index(const std::string& path, std::size_t i);

 private:
  Error error_;
};

}  // namespace mvtrack::json
