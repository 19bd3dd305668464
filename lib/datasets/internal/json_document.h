#pragma once
/// @file
/// Internal to lib/datasets (never included by a public header): read-only access to a JSON
/// file parsed by lib/json, with every failure reported as a DatasetError naming the file, the
/// line:column and the JSON path of the value. Values are cheap handles into the shared parsed
/// document (which they keep alive); single-threaded use.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::json {
struct Value;
}  // namespace mvtrack::json

namespace mvtrack::datasets::internal {

struct JsonDocument;

/// One value of a parsed JSON document and where it sits ("$.frames[3].poses").
class JsonValue {
 public:
  /// A handle to `value` of `document`, found at `path`.
  JsonValue(std::shared_ptr<const JsonDocument> document,
            const json::Value* value,
            std::string path);

  /// Member `key` of an object; throws DatasetError if this is not an object or has no `key`.
  JsonValue operator[](const std::string& key) const;
  /// Element `i` of an array; throws DatasetError if this is not an array or `i` is out of range.
  JsonValue At(std::size_t i) const;
  /// Number of elements of an array; throws DatasetError if this is not an array.
  std::size_t Size() const;
  /// Members of an object in document order; throws DatasetError if this is not an object.
  std::vector<std::pair<std::string, JsonValue>> Items() const;

  /// A finite JSON number; throws DatasetError for anything else (strings, ...).
  double AsDouble() const;
  /// A JSON integer in the range of int64; throws DatasetError otherwise.
  std::int64_t AsInt() const;
  /// A non-negative JSON integer in the range of uint64 (e.g. 64-bit track ids).
  std::uint64_t AsUint64() const;
  /// A JSON string (or a number or boolean, as its text).
  std::string AsString() const;
  /// An array of exactly `n` finite numbers (any `n` when n < 0).
  std::vector<double> AsDoubles(int n = -1) const;
  /// An array of `rows` arrays of `cols` finite numbers, row-major.
  std::vector<double> AsMatrix(int rows, int cols) const;

  /// Throws DatasetError("<file>", "<line>:<col>: <path>: <problem>").
  [[noreturn]] void Fail(const std::string& problem) const;

 private:
  std::shared_ptr<const JsonDocument> document_;
  const json::Value* value_;
  std::string path_;
};

/// Parses `file` (must exist and be valid JSON with an object or array at the top) and returns
/// its root value ("$").
/// @throws DatasetError when the file cannot be read or does not parse.
JsonValue LoadJsonFile(const std::filesystem::path& file);

}  // namespace mvtrack::datasets::internal
