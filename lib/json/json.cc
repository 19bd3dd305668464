#include "json/json.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <system_error>
#include <unordered_set>
#include <utility>

#include "json/document.h"

namespace mvtrack::json {
namespace {

// A forward iterator over the text that publishes how many bytes nlohmann's lexer has pulled:
// the SAX events below carry no positions, but each event fires right after the lexer has read
// its token (plus one byte of look-ahead after a number), so that count locates every value.
class TrackedIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackedIterator() = default;
  TrackedIterator(const char* p, const char** read) : p_(p), read_(read) {}

  reference operator*() const { return *p_; }
  TrackedIterator& operator++() {
    ++p_;
    if (read_ != nullptr) *read_ = p_;
    return *this;
  }
  TrackedIterator operator++(int) {
    TrackedIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const TrackedIterator& other) const { return p_ == other.p_; }
  bool operator!=(const TrackedIterator& other) const { return p_ != other.p_; }

 private:
  const char* p_ = nullptr;
  const char** read_ = nullptr;
};

bool IsNumberByte(char c) {
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
}

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1,
// column 5: " prefix (the position is reported separately), with bytes that are not printable
// ASCII shown as \xNN (a message may quote the offending input).
std::string CleanMessage(const std::string& what) {
  std::string_view s = what;
  if (!s.empty() && s.front() == '[') {
    const std::size_t close = s.find("] ");
    if (close != std::string_view::npos) s.remove_prefix(close + 2);
  }
  if (s.substr(0, 11) == "parse error") {
    const std::size_t colon = s.find(": ");
    if (colon != std::string_view::npos) s.remove_prefix(colon + 2);
  }
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7F) {
      out.push_back(ch);
    } else {
      out += "\\x";
      out.push_back(kHex[c >> 4]);
      out.push_back(kHex[c & 15]);
    }
  }
  return out;
}

// Builds the Value tree from nlohmann's SAX events (the interface nlohmann::json::sax_parse
// expects), with positions from the tracked read count.
class TreeBuilder {
 public:
  using Json = nlohmann::json;

  TreeBuilder(std::string_view text, const char* const* read, int max_depth)
      : text_(text), read_(read), max_depth_(max_depth) {}

  std::optional<Value>& root() { return root_; }
  const Error& error() const { return error_; }

  bool null() { return Scalar(Value::Kind::kNull, Read() - 4); }
  bool boolean(bool value) {
    Value* v = Add(Value::Kind::kBool, Read() - (value ? 4 : 5));
    v->boolean = value;
    return true;
  }
  bool number_integer(Json::number_integer_t value) { return Number(static_cast<double>(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return Number(static_cast<double>(value)); }
  bool number_float(Json::number_float_t value, const std::string& /*literal*/) {
    return Number(value);
  }
  bool string(std::string& value) {
    Value* v = Add(Value::Kind::kString, StringStart(Read()));
    v->string = std::move(value);
    return true;
  }
  bool binary(Json::binary_t& /*value*/) { return false; }  // not produced by the JSON lexer

  bool start_object(std::size_t /*elements*/) { return Open(Value::Kind::kObject); }
  bool key(std::string& key) {
    Frame& top = stack_.back();
    const std::size_t start = StringStart(Read());
    if (IsDuplicate(&top, key)) {
      error_ = Error{start + 1, "", "duplicate key \"" + key + "\""};
      return false;
    }
    Member m;
    m.key = std::move(key);
    m.key_column = start + 1;
    m.value = std::make_unique<Value>();
    top.value->members.push_back(std::move(m));
    return true;
  }
  bool end_object() { return Close(); }
  bool start_array(std::size_t /*elements*/) { return Open(Value::Kind::kArray); }
  bool end_array() { return Close(); }

  bool parse_error(std::size_t position,
                   const std::string& /*last_token*/,
                   const nlohmann::detail::exception& ex) {
    // A number beyond the range of a double (406) is reported at its first byte, like every
    // other bad value; syntax errors at the byte that broke the syntax.
    error_ = Error{ex.id == 406 ? NumberStart() + 1 : position, "", CleanMessage(ex.what())};
    return false;
  }

 private:
  struct Frame {
    Value* value = nullptr;
    std::unordered_set<std::string> keys;  // objects with many members: their keys so far
  };

  // Objects with up to kLinearKeys members are searched linearly (the common small objects
  // allocate nothing); larger ones through a hash set of their keys.
  static constexpr std::size_t kLinearKeys = 16;
  static bool IsDuplicate(Frame* frame, const std::string& key) {
    const std::vector<Member>& members = frame->value->members;
    if (members.size() < kLinearKeys) {
      for (const Member& m : members) {
        if (m.key == key) return true;
      }
      return false;
    }
    if (frame->keys.empty()) {
      for (const Member& m : members) frame->keys.insert(m.key);
    }
    return !frame->keys.insert(key).second;
  }

  std::size_t Read() const { return static_cast<std::size_t>(*read_ - text_.data()); }

  // 0-based offset of the opening quote of the string whose closing quote ends before `end`:
  // inside a string a quote is always preceded by an odd number of backslashes, the opening
  // quote by none.
  std::size_t StringStart(std::size_t end) const {
    std::size_t i = end - 1;  // the closing quote
    while (i > 0) {
      --i;
      if (text_[i] != '"') continue;
      std::size_t slashes = 0;
      while (slashes < i && text_[i - 1 - slashes] == '\\') ++slashes;
      if (slashes % 2 == 0) return i;
    }
    return 0;
  }

  // End (exclusive) and start of the number token just read.
  std::size_t NumberEnd() const {
    std::size_t end = Read();
    if (end > 0 && !IsNumberByte(text_[end - 1])) --end;  // the look-ahead byte
    return end;
  }
  std::size_t NumberStart() const {
    std::size_t start = NumberEnd();
    while (start > 0 && IsNumberByte(text_[start - 1])) --start;
    return start;
  }

  bool Number(double value) {
    const std::size_t start = NumberStart();
    Value* v = Add(Value::Kind::kNumber, start);
    v->number = text_.substr(start, NumberEnd() - start);
    v->real = value;
    return true;
  }

  bool Scalar(Value::Kind kind, std::size_t start) {
    Add(kind, start);
    return true;
  }

  // The value that comes next (the root, the next array element or the value of the key just
  // read), of `kind`, starting at 0-based byte `start`.
  Value* Add(Value::Kind kind, std::size_t start) {
    Value* v = nullptr;
    if (stack_.empty()) {
      root_.emplace();
      v = &*root_;
    } else if (Value* top = stack_.back().value; top->kind == Value::Kind::kArray) {
      // Small arrays (points, boxes) are the common case: one allocation instead of three.
      if (top->items.capacity() == 0) top->items.reserve(4);
      v = &top->items.emplace_back();
    } else {
      v = top->members.back().value.get();
    }
    v->kind = kind;
    v->column = start + 1;
    return v;
  }

  bool Open(Value::Kind kind) {
    const std::size_t start = Read() - 1;
    if (static_cast<int>(stack_.size()) >= max_depth_) {
      error_ = Error{start + 1, "", "nesting deeper than " + std::to_string(max_depth_)};
      return false;
    }
    Value* v = Add(kind, start);
    stack_.push_back(Frame{v, {}});
    return true;
  }

  bool Close() {
    stack_.pop_back();
    return true;
  }

  std::string_view text_;
  const char* const* read_;
  int max_depth_;
  std::vector<Frame> stack_;
  std::optional<Value> root_;
  Error error_;
};

}  // namespace

const Value* Value::Find(std::string_view key) const {
  if (kind != Kind::kObject) return nullptr;
  for (const Member& m : members) {
    if (m.key == key) return m.value.get();
  }
  return nullptr;
}

const char* KindName(Value::Kind kind) {
  switch (kind) {
    case Value::Kind::kNull:
      return "null";
    case Value::Kind::kBool:
      return "a boolean";
    case Value::Kind::kNumber:
      return "a number";
    case Value::Kind::kString:
      return "a string";
    case Value::Kind::kArray:
      return "an array";
    case Value::Kind::kObject:
      return "an object";
  }
  return "?";
}

std::optional<Value> Parse(std::string_view text, int max_depth, Error* error) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") {
    if (error != nullptr) {
      *error = Error{1, "", "a byte order mark (EF BB BF) before the JSON value is not allowed"};
    }
    return std::nullopt;
  }
  const char* read = text.data();
  TreeBuilder builder(text, &read, max_depth);
  const TrackedIterator first(text.data(), &read);
  const TrackedIterator last(text.data() + text.size(), nullptr);
  const bool ok = nlohmann::json::sax_parse(first, last, &builder);
  if (!ok || !builder.root().has_value()) {
    if (error != nullptr) *error = builder.error();
    return std::nullopt;
  }
  return std::move(builder.root());
}

LineIndex::LineIndex(std::string_view text) : size_(text.size()) {
  starts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') starts_.push_back(i + 1);
  }
}

LineColumn LineIndex::At(std::size_t offset) const {
  const std::size_t pos = offset == 0 ? 0 : std::min(offset - 1, size_);
  const auto it = std::upper_bound(starts_.begin(), starts_.end(), pos) - 1;
  return LineColumn{static_cast<std::size_t>(it - starts_.begin()) + 1, pos - *it + 1};
}

std::string Quote(std::string_view text) {
  std::string out;
  AppendQuoted(text, &out);
  return out;
}

void AppendQuoted(std::string_view text, std::string* out) {
  out->append(Dump(Document(std::string(text))));
}

std::string Dump(const Document& doc, int indent, Ascii ascii) {
  return doc.dump(indent, ' ', ascii == Ascii::kEscape, Document::error_handler_t::replace);
}

std::string Dump(const OrderedDocument& doc, int indent, Ascii ascii) {
  return doc.dump(indent, ' ', ascii == Ascii::kEscape, OrderedDocument::error_handler_t::replace);
}

// --- Checker ---------------------------------------------------------------------------------

bool Checker::Fail(const Value& at, const std::string& path, std::string reason) {
  return FailAt(at.column, path, std::move(reason));
}

bool Checker::FailAt(std::size_t column, const std::string& path, std::string reason) {
  error_.column = column;
  error_.path = path;
  error_.reason = std::move(reason);
  return false;
}

bool Checker::ExpectKind(const Value& v, const std::string& path, Value::Kind kind) {
  if (v.kind == kind) return true;
  return Fail(v, path, std::string("expected ") + KindName(kind) + ", found " + KindName(v.kind));
}

bool Checker::GetInt(const Value& v,
                     const std::string& path,
                     std::int64_t min,
                     std::int64_t max,
                     std::int64_t* out) {
  if (v.kind != Value::Kind::kNumber) {
    return Fail(v, path, std::string("expected an integer, found ") + KindName(v.kind));
  }
  if (v.number.find_first_of(".eE") != std::string_view::npos) {
    return Fail(v, path, "expected an integer, found " + std::string(v.number));
  }
  const auto [end, ec] = std::from_chars(v.number.data(), v.number.data() + v.number.size(), *out);
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

bool Checker::GetDouble(const Value& v, const std::string& path, double* out) {
  if (v.kind != Value::Kind::kNumber) {
    return Fail(v, path, std::string("expected a number, found ") + KindName(v.kind));
  }
  *out = v.real;
  return true;
}

bool Checker::GetReal(const Value& v, const std::string& path, double* out) {
  if (!GetDouble(v, path, out)) return false;
  if (std::abs(*out) > static_cast<double>(std::numeric_limits<float>::max())) {
    return Fail(
        v, path, std::string(v.number) + " is beyond the float range of the detections log");
  }
  return true;
}

bool Checker::GetUnit(const Value& v, const std::string& path, std::string_view what, double* out) {
  if (!GetReal(v, path, out)) return false;
  if (!(*out >= 0.0 && *out <= 1.0)) {
    return Fail(v, path, std::string(what) + " " + std::string(v.number) + " is outside [0, 1]");
  }
  return true;
}

bool Checker::GetString(const Value& v, const std::string& path, std::string* out) {
  if (!ExpectKind(v, path, Value::Kind::kString)) return false;
  *out = v.string;
  return true;
}

bool Checker::ExpectArray(
    const Value& v, const std::string& path, long n, std::size_t max, std::string_view what) {
  if (!ExpectKind(v, path, Value::Kind::kArray)) return false;
  if (n >= 0 && v.items.size() != static_cast<std::size_t>(n)) {
    return Fail(v,
                path,
                "expected " + std::string(what) + " (" + std::to_string(n) + " values), found " +
                    std::to_string(v.items.size()) + " values");
  }
  if (n < 0 && v.items.size() > max) {
    return Fail(
        v,
        path,
        std::to_string(v.items.size()) + " entries, more than the limit of " + std::to_string(max));
  }
  return true;
}

bool Checker::Members(const Value& v,
                      const std::string& path,
                      const std::vector<std::string_view>& allowed,
                      const std::vector<std::string_view>& required,
                      std::map<std::string, const Value*>* out) {
  if (!ExpectKind(v, path, Value::Kind::kObject)) return false;
  out->clear();
  for (const Member& m : v.members) {
    bool known = false;
    for (std::string_view a : allowed) known = known || m.key == a;
    if (!known) {
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      return FailAt(m.key_column,
                    Join(path, m.key),
                    "unknown key \"" + Shown(m.key) + "\" (allowed: " + list + ")");
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

std::string Checker::Join(const std::string& path, std::string_view key) {
  return path.empty() ? Shown(key) : path + "." + Shown(key);
}

std::string Checker::Shown(std::string_view text) {
  constexpr std::size_t kMaxShown = 64;
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?';  // no terminal control bytes
  }
  if (text.size() > kMaxShown) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

std::string Checker::Index(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

}  // namespace mvtrack::json
