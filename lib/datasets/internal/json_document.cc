#include "datasets/internal/json_document.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "datasets/dataset.h"

namespace mvtrack::datasets::internal {
namespace {

// yaml-cpp gives plain (unquoted) scalars the non-specific tag "?" and quoted scalars "!".
// JSON numbers are plain scalars; a quoted "1.5" is a string and must not read as a number.
bool IsPlainScalar(const YAML::Node& node) { return node.IsScalar() && node.Tag() != "!"; }

// A JSON number: optional '-', digits, optional fraction, optional exponent. (YAML would also
// accept forms such as ".inf" or "0x10"; JSON does not.)
bool LooksLikeJsonNumber(const std::string& s) {
  std::size_t i = 0;
  const std::size_t n = s.size();
  if (i < n && s[i] == '-') ++i;
  const std::size_t int_start = i;
  while (i < n && s[i] >= '0' && s[i] <= '9') ++i;
  if (i == int_start) return false;
  if (i < n && s[i] == '.') {
    ++i;
    const std::size_t frac_start = i;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i;
    if (i == frac_start) return false;
  }
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    const std::size_t exp_start = i;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i;
    if (i == exp_start) return false;
  }
  return i == n;
}

bool LooksLikeJsonInteger(const std::string& s) {
  if (!LooksLikeJsonNumber(s)) return false;
  return s.find_first_of(".eE") == std::string::npos;
}

}  // namespace

JsonValue::JsonValue(std::string file, YAML::Node node, std::string path)
    : file_(std::move(file)), node_(std::move(node)), path_(std::move(path)) {}

void JsonValue::Fail(const std::string& problem) const {
  const YAML::Mark mark = node_.Mark();
  std::string where;
  if (!mark.is_null()) {
    where = std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1) + ": ";
  }
  throw DatasetError(file_, where + path_ + ": " + problem);
}

JsonValue JsonValue::operator[](const std::string& key) const {
  if (!node_.IsMap()) Fail("expected an object (to read member \"" + key + "\")");
  const YAML::Node child = node_[key];
  if (!child.IsDefined()) Fail("missing member \"" + key + "\"");
  return JsonValue(file_, child, path_ + "." + key);
}

JsonValue JsonValue::At(std::size_t i) const {
  if (!node_.IsSequence()) Fail("expected an array");
  if (i >= node_.size()) {
    Fail("index " + std::to_string(i) + " out of range (array of " +
         std::to_string(node_.size()) + ")");
  }
  return JsonValue(file_, node_[i], path_ + "[" + std::to_string(i) + "]");
}

std::size_t JsonValue::Size() const {
  if (!node_.IsSequence()) Fail("expected an array");
  return node_.size();
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::Items() const {
  if (!node_.IsMap()) Fail("expected an object");
  std::vector<std::pair<std::string, JsonValue>> items;
  items.reserve(node_.size());
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) {
      JsonValue(file_, kv.first, path_).Fail("object key is not a string");
    }
    const std::string key = kv.first.Scalar();
    items.emplace_back(key, JsonValue(file_, kv.second, path_ + "." + key));
  }
  return items;
}

double JsonValue::AsDouble() const {
  if (!IsPlainScalar(node_) || !LooksLikeJsonNumber(node_.Scalar())) Fail("expected a number");
  const std::string& s = node_.Scalar();
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(value)) {
    Fail("number \"" + s + "\" is not a finite double");
  }
  return value;
}

std::int64_t JsonValue::AsInt() const {
  if (!IsPlainScalar(node_) || !LooksLikeJsonInteger(node_.Scalar())) {
    Fail("expected an integer");
  }
  const std::string& s = node_.Scalar();
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(s.c_str(), &end, 10);
  if (errno == ERANGE || end != s.c_str() + s.size()) {
    Fail("integer \"" + s + "\" is out of the range of int64");
  }
  return static_cast<std::int64_t>(value);
}

std::uint64_t JsonValue::AsUint64() const {
  if (!IsPlainScalar(node_) || !LooksLikeJsonInteger(node_.Scalar()) ||
      node_.Scalar().front() == '-') {
    Fail("expected a non-negative integer");
  }
  const std::string& s = node_.Scalar();
  errno = 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(s.c_str(), &end, 10);
  if (errno == ERANGE || end != s.c_str() + s.size()) {
    Fail("integer \"" + s + "\" is out of the range of uint64");
  }
  return static_cast<std::uint64_t>(value);
}

std::string JsonValue::AsString() const {
  if (!node_.IsScalar()) Fail("expected a string");
  return node_.Scalar();
}

std::vector<double> JsonValue::AsDoubles(int n) const {
  if (!node_.IsSequence()) Fail("expected an array of numbers");
  const std::size_t size = node_.size();
  if (n >= 0 && size != static_cast<std::size_t>(n)) {
    Fail("expected an array of " + std::to_string(n) + " numbers, got " + std::to_string(size) +
         " entries");
  }
  std::vector<double> values;
  values.reserve(size);
  for (std::size_t i = 0; i < size; ++i) {
    const YAML::Node element = node_[i];
    // Fast path without building a path string; the slow path reports the exact element.
    if (IsPlainScalar(element) && LooksLikeJsonNumber(element.Scalar())) {
      const double v = std::strtod(element.Scalar().c_str(), nullptr);
      if (std::isfinite(v)) {
        values.push_back(v);
        continue;
      }
    }
    values.push_back(At(i).AsDouble());
  }
  return values;
}

std::vector<double> JsonValue::AsMatrix(int rows, int cols) const {
  if (!node_.IsSequence()) Fail("expected a " + std::to_string(rows) + "x" +
                                std::to_string(cols) + " matrix (array of arrays)");
  if (node_.size() != static_cast<std::size_t>(rows)) {
    Fail("expected a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix, got " +
         std::to_string(node_.size()) + " rows");
  }
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols));
  for (std::size_t r = 0; r < static_cast<std::size_t>(rows); ++r) {
    const std::vector<double> row = At(r).AsDoubles(cols);
    values.insert(values.end(), row.begin(), row.end());
  }
  return values;
}

JsonValue LoadJsonFile(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw DatasetError(name, "file not found (or not a regular file)");
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(name);
  } catch (const YAML::ParserException& e) {
    throw DatasetError(name, std::to_string(e.mark.line + 1) + ":" +
                                 std::to_string(e.mark.column + 1) + ": not valid JSON: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw DatasetError(name, std::string("cannot be read: ") + e.what());
  }
  if (!root.IsMap() && !root.IsSequence()) {
    throw DatasetError(name, "not a JSON document (the top level is neither an object nor an "
                             "array)");
  }
  return JsonValue(name, root, "$");
}

}  // namespace mvtrack::datasets::internal
