#include "config/internal/yaml_node.h"

#include <yaml-cpp/depthguard.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace mvtrack::config::internal {
namespace {

// yaml-cpp marks are 0-based with -1 for "unknown"; ours are 1-based with 0 for unknown.
int ToOneBased(int zero_based) { return zero_based >= 0 ? zero_based + 1 : 0; }

// Position of a node; {0, 0} for nodes without a mark.
std::pair<int, int> PositionOf(const YAML::Node& node) {
  if (!node.IsDefined()) return {0, 0};
  const YAML::Mark mark = node.Mark();
  if (mark.is_null()) return {0, 0};
  return {ToOneBased(mark.line), ToOneBased(mark.column)};
}

// A scalar written in quotes ("..." or '...'), or explicitly tagged !!str.
bool IsStringScalar(const YAML::Node& node) {
  return node.IsScalar() && (node.Tag() == "!" || node.Tag() == "tag:yaml.org,2002:str");
}

// Short description of what a node is, for "expected X, got Y" messages.
std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing (null)";
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return "a list";
  if (IsStringScalar(node)) return "the quoted string " + QuoteString(node.Scalar());
  return "'" + node.Scalar() + "'";
}

enum class RealStatus { kOk, kNotANumber, kNonFinite, kOutOfRange };

// Parses a YAML 1.2 core-schema real written in decimal notation. YAML's own spellings of the
// non-finite values (.nan, .inf, -.inf, in their three case forms) are recognised so that they
// are reported as non-finite rather than as words.
RealStatus ParseReal(std::string_view text, double* value) {
  static constexpr std::string_view kNonFinite[] = {".nan", ".NaN", ".NAN", ".inf", ".Inf", ".INF"};
  std::string_view body = text;
  if (!body.empty() && (body.front() == '+' || body.front() == '-')) body.remove_prefix(1);
  for (std::string_view special : kNonFinite) {
    if (body == special) return RealStatus::kNonFinite;
  }
  std::string_view digits = text;
  if (!digits.empty() && digits.front() == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && digits.front() == '-') return RealStatus::kNotANumber;
  }
  if (digits.empty()) return RealStatus::kNotANumber;
  double parsed = 0.0;
  const char* begin = digits.data();
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(begin, end, parsed, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) return RealStatus::kOutOfRange;
  if (ec != std::errc() || ptr != end) return RealStatus::kNotANumber;
  if (!std::isfinite(parsed)) return RealStatus::kNonFinite;  // "inf", "nan", "infinity"
  *value = parsed;
  return RealStatus::kOk;
}

void RequireNumberScalar(const NodeRef& ref, std::string_view expected) {
  const YAML::Node& node = ref.node();
  if (!node.IsDefined() || !node.IsScalar() || IsStringScalar(node)) {
    ref.Fail("expected " + std::string(expected) + ", got " + Describe(node));
  }
  const std::string& tag = node.Tag();
  if (tag != "?" && tag != "tag:yaml.org,2002:float" && tag != "tag:yaml.org,2002:int") {
    ref.Fail("expected " + std::string(expected) + ", got a value tagged '" + tag + "'");
  }
}

std::string FormatInt(std::int64_t value) { return std::to_string(value); }

// The bounds of the int and int64 types are not limits a user needs to read about.
std::string DescribeIntRange(std::int64_t min, std::int64_t max) {
  const bool has_min =
      min != std::numeric_limits<std::int64_t>::min() && min != std::numeric_limits<int>::min();
  const bool has_max =
      max != std::numeric_limits<std::int64_t>::max() && max != std::numeric_limits<int>::max();
  if (has_min && has_max) return "must be in [" + FormatInt(min) + ", " + FormatInt(max) + "]";
  if (has_min) return "must be >= " + FormatInt(min);
  if (has_max) return "must be <= " + FormatInt(max);
  return "must be an integer";
}

// Compact text of a range bound ("1" rather than "1.0").
std::string FormatBound(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

}  // namespace

// --- NodeRef -------------------------------------------------------------------------------------

NodeRef::NodeRef(const YAML::Node& node, std::string file, std::string path, int line, int column)
    : node_(node), file_(std::move(file)), path_(std::move(path)), line_(line), column_(column) {}

NodeRef NodeRef::Root(const YAML::Node& node, std::string file, std::string path) {
  const auto [line, column] = PositionOf(node);
  return NodeRef(node, std::move(file), std::move(path), line, column);
}

bool NodeRef::IsNull() const { return !node_.IsDefined() || node_.IsNull(); }

std::string NodeRef::ChildPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

std::string NodeRef::ElementPath(std::size_t index) const {
  return path_ + "[" + std::to_string(index) + "]";
}

ConfigError NodeRef::Error(const std::string& reason) const {
  return ConfigError(file_, line_, column_, path_, reason);
}

void NodeRef::Fail(const std::string& reason) const { throw Error(reason); }

// --- MapRef --------------------------------------------------------------------------------------

MapRef::MapRef(const NodeRef& node,
               std::vector<std::string> allowed,
               bool null_is_empty,
               const std::vector<KeyHint>& hints)
    : ref_(node) {
  if (node.IsNull() && null_is_empty) return;
  if (!node.node().IsMap()) node.Fail("expected a map, got " + Describe(node.node()));
  for (auto it = node.node().begin(); it != node.node().end(); ++it) {
    // Copies: yaml-cpp's operator-> returns a proxy, so references into it would dangle.
    const YAML::Node key_node = it->first;
    const auto [key_line, key_column] = PositionOf(key_node);
    if (!key_node.IsScalar()) {
      NodeRef(key_node, node.file(), node.path(), key_line, key_column)
          .Fail("map keys must be scalars, got " + Describe(key_node));
    }
    const std::string& key = key_node.Scalar();
    NodeRef key_ref(key_node, node.file(), node.ChildPath(key), key_line, key_column);
    if (const Entry* first = FindEntry(key)) {
      key_ref.Fail("duplicate key (first given at line " + std::to_string(first->key_ref.line()) +
                   ")");
    }
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string reason = "unknown key";
      const auto hint =
          std::find_if(hints.begin(), hints.end(), [&](const KeyHint& h) { return h.key == key; });
      std::vector<std::string> hint_keys;
      hint_keys.reserve(hints.size());
      for (const KeyHint& h : hints) hint_keys.push_back(h.key);
      const std::optional<std::string> close_hint = SuggestClosest(key, hint_keys);
      if (hint != hints.end()) {
        reason += " (did you mean " + hint->suggestion + "?)";
      } else if (const std::optional<std::string> close = SuggestClosest(key, allowed)) {
        reason += " (did you mean '" + *close + "'?)";
      } else if (close_hint.has_value()) {
        const auto closest = std::find_if(
            hints.begin(), hints.end(), [&](const KeyHint& h) { return h.key == *close_hint; });
        reason += " (did you mean " + closest->suggestion + "?)";
      } else if (allowed.empty()) {
        reason += " (this map takes no keys)";
      } else {
        reason += " (allowed keys: " + QuoteList(allowed) + ")";
      }
      key_ref.Fail(reason);
    }
    const YAML::Node value_node = it->second;
    auto [line, column] = PositionOf(value_node);
    // yaml-cpp places an empty value at the start of the next token (often the next line), so
    // a null value is reported at its key.
    if (value_node.IsNull() || line == 0) {
      line = key_line;
      column = key_column;
    }
    entries_.push_back(
        Entry{key, key_ref, NodeRef(value_node, node.file(), node.ChildPath(key), line, column)});
  }
}

const MapRef::Entry* MapRef::FindEntry(std::string_view key) const {
  for (const Entry& entry : entries_) {
    if (entry.key == key) return &entry;
  }
  return nullptr;
}

std::vector<std::string> MapRef::keys() const {
  std::vector<std::string> out;
  out.reserve(entries_.size());
  for (const Entry& entry : entries_) out.push_back(entry.key);
  return out;
}

bool MapRef::Has(std::string_view key) const { return FindEntry(key) != nullptr; }

std::optional<NodeRef> MapRef::Find(std::string_view key) const {
  const Entry* entry = FindEntry(key);
  if (entry == nullptr) return std::nullopt;
  return entry->value;
}

NodeRef MapRef::Get(std::string_view key) const {
  const Entry* entry = FindEntry(key);
  if (entry == nullptr) ref_.Fail("missing required key '" + std::string(key) + "'");
  return entry->value;
}

NodeRef MapRef::KeyRef(std::string_view key) const {
  const Entry* entry = FindEntry(key);
  if (entry == nullptr) return ref_;
  return entry->key_ref;
}

std::string MapRef::RequireExactlyOne(std::initializer_list<std::string_view> keys,
                                      std::string_view what) const {
  std::vector<std::string> names;
  std::vector<std::string> present;
  for (std::string_view key : keys) {
    names.emplace_back(key);
    if (Has(key)) present.emplace_back(key);
  }
  if (present.empty()) {
    ref_.Fail("missing " + std::string(what) + ": give exactly one of " + QuoteList(names));
  }
  if (present.size() > 1) {
    KeyRef(present[1])
        .Fail("give exactly one " + std::string(what) + " form, not both " +
              QuoteList({present[0], present[1]}));
  }
  return present.front();
}

void RequireOnlyKeys(const NodeRef& node,
                     const std::vector<std::string>& allowed,
                     const std::vector<KeyHint>& hints) {
  const MapRef checked(node, allowed, /*null_is_empty=*/false, hints);
  static_cast<void>(checked);
}

// --- Scalars -------------------------------------------------------------------------------------

bool DoubleRange::Contains(double value) const {
  const bool above = min_open ? value > min : value >= min;
  const bool below = max_open ? value < max : value <= max;
  return above && below;
}

std::string DoubleRange::Describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return std::string("must be in ") + (min_open ? "(" : "[") + FormatBound(min) + ", " +
           FormatBound(max) + (max_open ? ")" : "]");
  }
  if (has_min) return std::string("must be ") + (min_open ? "> " : ">= ") + FormatBound(min);
  if (has_max) return std::string("must be ") + (max_open ? "< " : "<= ") + FormatBound(max);
  return "must be a finite number";
}

namespace {

// A scalar as echoed in an error: whole when short, else its start and its length (a value of
// thousands of digits must not flood the message).
std::string Echo(const std::string& text) {
  constexpr std::size_t kMax = 32;
  if (text.size() <= kMax) return text;
  return text.substr(0, kMax) + "... (" + std::to_string(text.size()) + " characters)";
}

}  // namespace

double GetDouble(const NodeRef& node, const DoubleRange& range) {
  RequireNumberScalar(node, "a number");
  const std::string& text = node.node().Scalar();
  double value = 0.0;
  switch (ParseReal(text, &value)) {
    case RealStatus::kOk:
      break;
    case RealStatus::kNonFinite:
      node.Fail("non-finite number '" + Echo(text) + "' (must be finite)");
    case RealStatus::kOutOfRange:
      node.Fail("number '" + Echo(text) + "' is out of the range of a double");
    case RealStatus::kNotANumber:
      node.Fail("expected a number, got '" + Echo(text) + "'");
  }
  if (!range.Contains(value)) {
    node.Fail("value " + Echo(text) + " out of range: " + range.Describe());
  }
  return value;
}

std::int64_t GetInt64(const NodeRef& node, std::int64_t min, std::int64_t max) {
  RequireNumberScalar(node, "an integer");
  const std::string& text = node.node().Scalar();
  std::string_view digits = text;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  std::int64_t value = 0;
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, value, 10);
  const bool signed_twice = digits.size() < text.size() && !digits.empty() &&
                            (digits.front() == '+' || digits.front() == '-');
  const bool well_formed = !digits.empty() && !signed_twice && ptr == end;
  if (ec == std::errc::result_out_of_range && well_formed) {
    node.Fail("integer '" + Echo(text) + "' does not fit in 64 bits");
  }
  if (ec != std::errc() || !well_formed) {
    double real = 0.0;
    switch (ParseReal(text, &real)) {
      case RealStatus::kOk:
      case RealStatus::kOutOfRange:
        node.Fail("expected an integer, got '" + Echo(text) +
                  "' (no fraction or exponent allowed)");
      case RealStatus::kNonFinite:
        node.Fail("expected an integer, got the non-finite number '" + Echo(text) + "'");
      case RealStatus::kNotANumber:
        node.Fail("expected an integer, got '" + Echo(text) + "'");
    }
  }
  if (value < min || value > max) {
    node.Fail("value " + Echo(text) + " out of range: " + DescribeIntRange(min, max));
  }
  return value;
}

int GetInt(const NodeRef& node, int min, int max) {
  const std::int64_t value = GetInt64(node);
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    node.Fail("integer '" + node.node().Scalar() + "' does not fit in 32 bits");
  }
  if (value < min || value > max) {
    node.Fail("value " + node.node().Scalar() + " out of range: " + DescribeIntRange(min, max));
  }
  return static_cast<int>(value);
}

bool GetBool(const NodeRef& node) {
  const YAML::Node& yaml = node.node();
  if (yaml.IsDefined() && yaml.IsScalar() && !IsStringScalar(yaml)) {
    const std::string& text = yaml.Scalar();
    if (text == "true" || text == "True" || text == "TRUE") return true;
    if (text == "false" || text == "False" || text == "FALSE") return false;
  }
  node.Fail("expected true or false, got " + Describe(yaml));
}

std::string GetString(const NodeRef& node, bool allow_empty) {
  const YAML::Node& yaml = node.node();
  if (!yaml.IsDefined() || !yaml.IsScalar()) node.Fail("expected a string, got " + Describe(yaml));
  if (!allow_empty && yaml.Scalar().empty()) node.Fail("expected a non-empty string");
  return yaml.Scalar();
}

std::vector<NodeRef> GetSequence(const NodeRef& node, std::optional<std::size_t> expected_size) {
  const YAML::Node& yaml = node.node();
  const std::string expected = expected_size.has_value()
                                   ? "a list of " + std::to_string(*expected_size) + " values"
                                   : std::string("a list");
  if (!yaml.IsDefined() || !yaml.IsSequence()) {
    node.Fail("expected " + expected + ", got " + Describe(yaml));
  }
  if (expected_size.has_value() && yaml.size() != *expected_size) {
    node.Fail("expected " + expected + ", got " + std::to_string(yaml.size()));
  }
  std::vector<NodeRef> out;
  out.reserve(yaml.size());
  std::size_t index = 0;
  for (auto it = yaml.begin(); it != yaml.end(); ++it, ++index) {
    auto [line, column] = PositionOf(*it);
    if (it->IsNull() || line == 0) {
      line = node.line();
      column = node.column();
    }
    out.emplace_back(*it, node.file(), node.ElementPath(index), line, column);
  }
  return out;
}

// --- Suggestions ---------------------------------------------------------------------------------

// --- Documents and files -------------------------------------------------------------------------

NodeRef ParseDocument(std::string_view text, const std::string& source_name) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(std::string(text));
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp reports its recursion guard as "bad file"; say what happened instead.
    throw ConfigError(source_name,
                      ToOneBased(e.mark.line),
                      ToOneBased(e.mark.column),
                      "",
                      "YAML nested too deeply here (parser depth " + std::to_string(e.depth()) +
                          ", yaml-cpp's limit; a configuration nests a few levels)");
  } catch (const YAML::Exception& e) {
    throw ConfigError(source_name,
                      ToOneBased(e.mark.line),
                      ToOneBased(e.mark.column),
                      "",
                      "YAML syntax error: " + e.msg);
  }
  if (documents.empty()) return NodeRef(YAML::Node(), source_name, "", 0, 0);
  if (documents.size() > 1) {
    const auto [line, column] = PositionOf(documents[1]);
    throw ConfigError(source_name,
                      line,
                      column,
                      "",
                      "expected one YAML document, found " + std::to_string(documents.size()));
  }
  return NodeRef::Root(documents.front(), source_name);
}

std::string ReadTextFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) {
    throw ConfigError(path, 0, 0, "", "file does not exist");
  }
  if (ec) throw ConfigError(path, 0, 0, "", "cannot access file: " + ec.message());
  if (!fs::is_regular_file(status)) throw ConfigError(path, 0, 0, "", "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, 0, 0, "", "cannot open file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ConfigError(path, 0, 0, "", "read error");
  return text.str();
}

void WriteTextFile(const std::string& path, std::string_view text) {
  namespace fs = std::filesystem;
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw ConfigError(path, 0, 0, "", "cannot open '" + temporary + "' for writing");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw ConfigError(path, 0, 0, "", "write error");
    }
  }
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw ConfigError(path, 0, 0, "", "cannot replace the file: " + ec.message());
  }
}

// --- Output --------------------------------------------------------------------------------------

std::string FormatDouble(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

std::string QuoteString(std::string_view text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"') {
      out += "\\\"";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7F) {
      out += "\\u00";
      out += kHex[byte >> 4];
      out += kHex[byte & 0x0F];
    } else {
      out += c;
    }
  }
  out += '"';
  return out;
}

std::string QuoteList(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += ", ";
    out += "'" + names[i] + "'";
  }
  return out;
}

}  // namespace mvtrack::config::internal
