#include "mvtrack/json.h"

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <utility>

namespace mvtrack::cli {
namespace {

class JsonParser {
 public:
  JsonParser(std::string_view text, std::string_view unit, int max_depth)
      : text_(text), end_name_("end of the " + std::string(unit)), max_depth_(max_depth) {}

  // The text's value (which must be the only value in it), or nullopt with error().
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

  const JsonValueError& error() const { return error_; }

 private:
  bool Fail(std::string reason) { return FailAt(pos_, std::move(reason)); }
  bool FailAt(std::size_t pos, std::string reason) {
    error_.column = pos + 1;
    error_.reason = std::move(reason);
    return false;
  }

  // "'x'", "byte 0xC3" or "end of the <unit>" for the byte at `pos`.
  std::string Describe(std::size_t pos) const {
    if (pos >= text_.size()) return end_name_;
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
    if (pos_ >= text_.size()) return Fail("unexpected " + end_name_ + ", expected a JSON value");
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
    if (depth >= max_depth_) return Fail("nesting deeper than " + std::to_string(max_depth_));
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
    if (depth >= max_depth_) return Fail("nesting deeper than " + std::to_string(max_depth_));
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
  std::string end_name_;
  int max_depth_ = 0;
  JsonValueError error_;
};


}  // namespace

const char* JsonKindName(JsonValue::Kind kind) {
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

std::optional<JsonValue> ParseJson(std::string_view text,
                                   std::string_view unit,
                                   int max_depth,
                                   JsonValueError* error) {
  JsonParser parser(text, unit, max_depth);
  std::optional<JsonValue> root = parser.ParseDocument();
  if (!root.has_value() && error != nullptr) *error = parser.error();
  return root;
}

}  // namespace mvtrack::cli
