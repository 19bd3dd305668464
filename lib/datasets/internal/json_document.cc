#include "datasets/internal/json_document.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <system_error>

#include "datasets/dataset.h"
#include "json/json.h"

namespace mvtrack::datasets::internal {

/// The text of one file and its parsed tree (whose numbers are views into the text).
struct JsonDocument {
  std::string file;
  std::string text;
  std::optional<json::LineIndex> lines;
  json::Value root;
};

namespace {

// Nesting the dataset files need (a few levels) with a wide margin.
constexpr int kMaxDepth = 64;

bool IsInteger(const json::Value& v) {
  return v.kind == json::Value::Kind::kNumber &&
         v.number.find_first_of(".eE") == std::string_view::npos;
}

}  // namespace

JsonValue::JsonValue(std::shared_ptr<const JsonDocument> document,
                     const json::Value* value,
                     std::string path)
    : document_(std::move(document)), value_(value), path_(std::move(path)) {}

void JsonValue::Fail(const std::string& problem) const {
  const json::LineColumn at = document_->lines->At(value_->column);
  throw DatasetError(
      document_->file,
      std::to_string(at.line) + ":" + std::to_string(at.column) + ": " + path_ + ": " + problem);
}

JsonValue JsonValue::operator[](const std::string& key) const {
  if (value_->kind != json::Value::Kind::kObject) {
    Fail("expected an object (to read member \"" + key + "\")");
  }
  const json::Value* child = value_->Find(key);
  if (child == nullptr) Fail("missing member \"" + key + "\"");
  return JsonValue(document_, child, path_ + "." + key);
}

JsonValue JsonValue::At(std::size_t i) const {
  if (value_->kind != json::Value::Kind::kArray) Fail("expected an array");
  if (i >= value_->items.size()) {
    Fail("index " + std::to_string(i) + " out of range (array of " +
         std::to_string(value_->items.size()) + ")");
  }
  return JsonValue(document_, &value_->items[i], path_ + "[" + std::to_string(i) + "]");
}

std::size_t JsonValue::Size() const {
  if (value_->kind != json::Value::Kind::kArray) Fail("expected an array");
  return value_->items.size();
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::Items() const {
  if (value_->kind != json::Value::Kind::kObject) Fail("expected an object");
  std::vector<std::pair<std::string, JsonValue>> items;
  items.reserve(value_->members.size());
  for (const json::Member& m : value_->members) {
    items.emplace_back(m.key, JsonValue(document_, m.value.get(), path_ + "." + m.key));
  }
  return items;
}

double JsonValue::AsDouble() const {
  if (value_->kind != json::Value::Kind::kNumber) Fail("expected a number");
  return value_->real;  // json::Parse refuses numbers that are not finite doubles
}

std::int64_t JsonValue::AsInt() const {
  if (!IsInteger(*value_)) Fail("expected an integer");
  std::int64_t value = 0;
  const char* end = value_->number.data() + value_->number.size();
  const auto [ptr, ec] = std::from_chars(value_->number.data(), end, value);
  if (ec != std::errc() || ptr != end) {
    Fail("integer \"" + std::string(value_->number) + "\" is out of the range of int64");
  }
  return value;
}

std::uint64_t JsonValue::AsUint64() const {
  if (!IsInteger(*value_) || value_->number.front() == '-') {
    Fail("expected a non-negative integer");
  }
  std::uint64_t value = 0;
  const char* end = value_->number.data() + value_->number.size();
  const auto [ptr, ec] = std::from_chars(value_->number.data(), end, value);
  if (ec != std::errc() || ptr != end) {
    Fail("integer \"" + std::string(value_->number) + "\" is out of the range of uint64");
  }
  return value;
}

std::string JsonValue::AsString() const {
  switch (value_->kind) {
    case json::Value::Kind::kString:
      return value_->string;
    case json::Value::Kind::kNumber:
      return std::string(value_->number);
    case json::Value::Kind::kBool:
      return value_->boolean ? "true" : "false";
    default:
      Fail("expected a string");
  }
}

std::vector<double> JsonValue::AsDoubles(int n) const {
  if (value_->kind != json::Value::Kind::kArray) Fail("expected an array of numbers");
  const std::size_t size = value_->items.size();
  if (n >= 0 && size != static_cast<std::size_t>(n)) {
    Fail("expected an array of " + std::to_string(n) + " numbers, got " + std::to_string(size) +
         " entries");
  }
  std::vector<double> values;
  values.reserve(size);
  for (std::size_t i = 0; i < size; ++i) {
    // Fast path without building a path string; the slow path reports the exact element.
    if (value_->items[i].kind == json::Value::Kind::kNumber) {
      values.push_back(value_->items[i].real);
    } else {
      values.push_back(At(i).AsDouble());
    }
  }
  return values;
}

std::vector<double> JsonValue::AsMatrix(int rows, int cols) const {
  if (value_->kind != json::Value::Kind::kArray) {
    Fail("expected a " + std::to_string(rows) + "x" + std::to_string(cols) +
         " matrix (array of arrays)");
  }
  if (value_->items.size() != static_cast<std::size_t>(rows)) {
    Fail("expected a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix, got " +
         std::to_string(value_->items.size()) + " rows");
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
  auto document = std::make_shared<JsonDocument>();
  document->file = name;
  {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (!in && !in.eof()) throw DatasetError(name, "cannot be read");
    document->text = std::move(buffer).str();
  }
  document->lines.emplace(document->text);
  json::Error error;
  std::optional<json::Value> root = json::Parse(document->text, kMaxDepth, &error);
  if (!root.has_value()) {
    const json::LineColumn at = document->lines->At(error.column);
    throw DatasetError(name,
                       std::to_string(at.line) + ":" + std::to_string(at.column) +
                           ": not valid JSON: " + error.reason);
  }
  if (root->kind != json::Value::Kind::kObject && root->kind != json::Value::Kind::kArray) {
    throw DatasetError(name,
                       "not a JSON document (the top level is neither an object nor an "
                       "array)");
  }
  document->root = std::move(*root);
  const json::Value* root_value = &document->root;
  return JsonValue(std::move(document), root_value, "$");
}

}  // namespace mvtrack::datasets::internal
