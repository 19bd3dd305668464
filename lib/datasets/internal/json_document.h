#pragma once
/// @file
/// Internal to lib/datasets (never included by a public header): read-only access to a JSON
/// file parsed with yaml-cpp (JSON is a subset of YAML 1.2's flow syntax), with every failure
/// reported as a DatasetError naming the file, the line:column and the JSON path of the value.
/// Values are cheap handles into the parsed document; single-threaded use.

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::datasets::internal {

/// One value of a parsed JSON document and where it sits ("$.frames[3].poses").
class JsonValue {
 public:
  /// A handle to `node` of the document read from `file`, found at `path`.
  JsonValue(std::string file, YAML::Node node, std::string path);

  /// Member `key` of an object; throws DatasetError if this is not an object or has no `key`.
  JsonValue operator[](const std::string& key) const;
  /// Element `i` of an array; throws DatasetError if this is not an array or `i` is out of range.
  JsonValue At(std::size_t i) const;
  /// Number of elements of an array; throws DatasetError if this is not an array.
  std::size_t Size() const;
  /// Members of an object in document order; throws DatasetError if this is not an object.
  std::vector<std::pair<std::string, JsonValue>> Items() const;

  /// A finite JSON number; throws DatasetError for anything else (strings, NaN, ...).
  double AsDouble() const;
  /// A JSON integer in the range of int64; throws DatasetError otherwise.
  std::int64_t AsInt() const;
  /// A non-negative JSON integer in the range of uint64 (e.g. 64-bit track ids).
  std::uint64_t AsUint64() const;
  /// A JSON string (or any scalar, as text).
  std::string AsString() const;
  /// An array of exactly `n` finite numbers (any `n` when n < 0).
  std::vector<double> AsDoubles(int n = -1) const;
  /// An array of `rows` arrays of `cols` finite numbers, row-major.
  std::vector<double> AsMatrix(int rows, int cols) const;

  /// Throws DatasetError("<file>", "<line>:<col>: <path>: <problem>").
  [[noreturn]] void Fail(const std::string& problem) const;

 private:
  std::string file_;
  YAML::Node node_;
  std::string path_;
};

/// Parses `file` (must exist and be valid JSON) and returns its root value ("$").
/// @throws DatasetError when the file cannot be read or does not parse.
JsonValue LoadJsonFile(const std::filesystem::path& file);

}  // namespace mvtrack::datasets::internal
