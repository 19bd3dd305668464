// lib/json: the positions of every value and key (checked against a seeded generator that
// records where it wrote each one), strictness (the RFC 8259 rules and the project's limits),
// the error positions, LocateOffset and Quote.

#include "json/json.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace mvtrack::json {
namespace {

std::string ErrorOf(const std::string& text, std::size_t* column, int max_depth = 16) {
  Error error;
  const std::optional<Value> v = Parse(text, max_depth, &error);
  INFO(text);
  REQUIRE_FALSE(v.has_value());
  REQUIRE_FALSE(error.reason.empty());
  *column = error.column;
  return error.reason;
}

TEST_CASE("json: values and keys keep their byte positions", "[unit]") {
  const std::string text = R"( {"a": 12, "b\"c": [true, null, -1.5e3, "x\\"], "d": {}} )";
  Error error;
  const std::optional<Value> root = Parse(text, 16, &error);
  REQUIRE(root.has_value());
  REQUIRE(root->kind == Value::Kind::kObject);
  CHECK(root->column == 2);
  REQUIRE(root->members.size() == 3);
  CHECK(root->members[0].key == "a");
  CHECK(root->members[0].key_column == 3);
  CHECK(root->members[0].value->number == "12");
  CHECK(root->members[0].value->column == 8);
  CHECK(root->members[1].key == "b\"c");
  CHECK(root->members[1].key_column == text.find("\"b\\") + 1);
  const Value& array = *root->members[1].value;
  REQUIRE(array.items.size() == 4);
  CHECK(array.column == text.find('[') + 1);
  CHECK(array.items[0].boolean);
  CHECK(array.items[0].column == text.find("true") + 1);
  CHECK(array.items[1].kind == Value::Kind::kNull);
  CHECK(array.items[1].column == text.find("null") + 1);
  CHECK(array.items[2].number == "-1.5e3");
  CHECK(array.items[2].column == text.find("-1.5") + 1);
  CHECK(array.items[3].string == "x\\");
  CHECK(array.items[3].column == text.find("\"x") + 1);
  CHECK(root->Find("d") != nullptr);
  CHECK(root->Find("d")->column == text.find("{}") + 1);
  CHECK(root->Find("zz") == nullptr);
}

TEST_CASE("json: a number at the very end of the text", "[unit]") {
  Error error;
  const std::optional<Value> v = Parse("  -0.25", 4, &error);
  REQUIRE(v.has_value());
  CHECK(v->number == "-0.25");
  CHECK(v->column == 3);
}

// A random document written with random whitespace and escapes; `expected` gets, in pre-order,
// the 1-based column of every value and key (keys as negative numbers to tell them apart).
class Generator {
 public:
  explicit Generator(std::uint32_t seed) : rng_(seed) {}

  std::string Document(std::vector<long>* expected) {
    text_.clear();
    expected_ = expected;
    Space();
    Write(0);
    Space();
    return text_;
  }

 private:
  int Pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }

  void Space() {
    static const char* const kSpace[] = {"", "", " ", "\n", "\t ", "\r\n  "};
    text_ += kSpace[Pick(6)];
  }

  void String() {
    static const char* const kPieces[] = {"a",
                                          "\\\"",
                                          "\\\\",
                                          "\\n",
                                          "\\u00e9",
                                          "\xc3\xa9",
                                          "\\ud83d\\ude00",
                                          "/",
                                          "\\/",
                                          "xyz",
                                          "\\\\\\\""};
    text_ += '"';
    const int n = Pick(4);
    for (int i = 0; i < n; ++i) text_ += kPieces[Pick(11)];
    text_ += '"';
  }

  void Write(int depth) {
    expected_->push_back(static_cast<long>(text_.size()) + 1);
    const int kind = depth > 4 ? Pick(4) : Pick(6);
    switch (kind) {
      case 0: {
        static const char* const kNumbers[] = {
            "0", "-0", "12", "3.25", "-1e5", "6E-2", "1.5e+300", "123456789012345678901234567890"};
        text_ += kNumbers[Pick(8)];
        break;
      }
      case 1:
        String();
        break;
      case 2: {
        static const char* const kLiterals[] = {"true", "false", "null"};
        text_ += kLiterals[Pick(3)];
        break;
      }
      case 3:
      case 4: {
        text_ += '[';
        const int n = Pick(4);
        for (int i = 0; i < n; ++i) {
          if (i > 0) text_ += ',';
          Space();
          Write(depth + 1);
          Space();
        }
        text_ += ']';
        break;
      }
      default: {
        text_ += '{';
        const int n = Pick(4);
        for (int i = 0; i < n; ++i) {
          if (i > 0) text_ += ',';
          Space();
          expected_->push_back(-(static_cast<long>(text_.size()) + 1));
          text_ += "\"k" + std::to_string(i) + "\"";  // unique keys
          Space();
          text_ += ':';
          Space();
          Write(depth + 1);
          Space();
        }
        text_ += '}';
      }
    }
  }

  std::mt19937 rng_;
  std::string text_;
  std::vector<long>* expected_ = nullptr;
};

void Collect(const Value& v, std::vector<long>* out) {
  out->push_back(static_cast<long>(v.column));
  for (const Value& item : v.items) Collect(item, out);
  for (const Member& m : v.members) {
    out->push_back(-static_cast<long>(m.key_column));
    Collect(*m.value, out);
  }
}

TEST_CASE("json: positions match the generator's on 2000 seeded documents", "[unit]") {
  for (std::uint32_t seed = 1; seed <= 2000; ++seed) {
    Generator gen(seed);
    std::vector<long> expected;
    const std::string text = gen.Document(&expected);
    Error error;
    const std::optional<Value> root = Parse(text, 16, &error);
    INFO("seed " << seed << ": " << text << "\n" << error.column << ": " << error.reason);
    REQUIRE(root.has_value());
    std::vector<long> got;
    Collect(*root, &got);
    REQUIRE(got == expected);
  }
}

// Every value of a parse that succeeded starts where its position says.
void RequirePositionsConsistent(const std::string& text, const Value& v) {
  REQUIRE(v.column >= 1);
  REQUIRE(v.column <= text.size());
  const char c = text[v.column - 1];
  switch (v.kind) {
    case Value::Kind::kNull:
      REQUIRE(text.compare(v.column - 1, 4, "null") == 0);
      break;
    case Value::Kind::kBool:
      REQUIRE(text.compare(v.column - 1, v.boolean ? 4 : 5, v.boolean ? "true" : "false") == 0);
      break;
    case Value::Kind::kNumber:
      REQUIRE(text.compare(v.column - 1, v.number.size(), v.number) == 0);
      REQUIRE(std::isfinite(v.real));
      break;
    case Value::Kind::kString:
      REQUIRE(c == '"');
      break;
    case Value::Kind::kArray:
      REQUIRE(c == '[');
      break;
    case Value::Kind::kObject:
      REQUIRE(c == '{');
      break;
  }
  for (const Value& item : v.items) RequirePositionsConsistent(text, item);
  for (const Member& m : v.members) {
    REQUIRE(m.key_column >= 1);
    REQUIRE(text[m.key_column - 1] == '"');
    RequirePositionsConsistent(text, *m.value);
  }
}

TEST_CASE("json: 20000 seeded mutations parse or fail cleanly, positions stay right", "[unit]") {
  std::mt19937 rng(99);
  const std::string bytes = "{}[]\",:0123456789.eE+-tfnul \\\n\xC3\xA9\x01x";
  int parsed = 0;
  for (int n = 0; n < 20000; ++n) {
    Generator gen(static_cast<std::uint32_t>(n % 500) + 1);
    std::vector<long> unused;
    std::string text = gen.Document(&unused);
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = rng() % text.size();
      const char b = bytes[rng() % bytes.size()];
      switch (rng() % 3) {
        case 0:
          text[at] = b;
          break;
        case 1:
          text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), b);
          break;
        default:
          text.erase(at, 1);
      }
    }
    Error error;
    const std::optional<Value> v = Parse(text, 8, &error);
    INFO(text);
    if (v.has_value()) {
      ++parsed;
      RequirePositionsConsistent(text, *v);
    } else {
      REQUIRE_FALSE(error.reason.empty());
      REQUIRE(error.column >= 1);
      REQUIRE(error.column <= text.size() + 1);
    }
  }
  CHECK(parsed > 1000);  // the loop also exercises valid documents
}

TEST_CASE("json: strings are decoded", "[unit]") {
  Error error;
  const auto v = Parse(R"(["\u0063oco", "\ud83d\ude00", "a\/b", "\t"])", 4, &error);
  REQUIRE(v.has_value());
  CHECK(v->items[0].string == "coco");
  CHECK(v->items[1].string == "\xF0\x9F\x98\x80");
  CHECK(v->items[2].string == "a/b");
  CHECK(v->items[3].string == "\t");
}

TEST_CASE("json: strict syntax, with the column of the offending byte", "[unit]") {
  std::size_t column = 0;
  CHECK_FALSE(ErrorOf("{\"a\": 1,}", &column).empty());
  CHECK(column == 9);
  CHECK(ErrorOf("[1, 2", &column).find("end of input") != std::string::npos);
  CHECK(column == 6);
  ErrorOf("[01]", &column);
  CHECK(column == 3);
  ErrorOf("[1] x", &column);
  CHECK(column == 5);
  ErrorOf("{\"a\": tru}", &column);
  CHECK(column == 10);
  ErrorOf("[1e999]", &column);
  CHECK(column >= 2);
  CHECK(ErrorOf("", &column).find("end of input") != std::string::npos);
  // Invalid UTF-8, a lone surrogate, a control character: named, and no raw byte in the text.
  const std::string utf8 = ErrorOf("[\"a\xC3(\"]", &column);
  CHECK(utf8.find("UTF-8") != std::string::npos);
  CHECK(utf8.find('\xC3') == std::string::npos);
  CHECK(column == 5);  // the byte that breaks the sequence
  CHECK(ErrorOf(R"(["\ud800"])", &column).find("surrogate") != std::string::npos);
  CHECK(ErrorOf("[\"a\nb\"]", &column).find("control character") != std::string::npos);
  CHECK(ErrorOf("\xEF\xBB\xBF[]", &column).find("byte order mark") != std::string::npos);
  CHECK(column == 1);
}

TEST_CASE("json: duplicate keys and nesting depth are errors at their position", "[unit]") {
  std::size_t column = 0;
  CHECK(ErrorOf(R"({"a": 1, "b": 2, "a": 3})", &column) == "duplicate key \"a\"");
  CHECK(column == 18);
  CHECK(ErrorOf("[[[[1]]]]", &column, 3) == "nesting deeper than 3");
  CHECK(column == 4);
  Error error;
  CHECK(Parse("[[[1]]]", 3, &error).has_value());
  // The same key in sibling objects is fine.
  CHECK(Parse(R"([{"a": 1}, {"a": 2}])", 3, &error).has_value());
  // Deep nesting is refused before it can exhaust the stack.
  CHECK(ErrorOf(std::string(100000, '['), &column, 64) == "nesting deeper than 64");
}

TEST_CASE("json: LineIndex turns byte offsets into line:column", "[unit]") {
  const std::string text = "{\n  \"a\": 1,\n  \"b\": x\n}";
  const LineIndex lines(text);
  const LineColumn at = lines.At(text.find('x') + 1);
  CHECK(at.line == 3);
  CHECK(at.column == 8);
  CHECK(lines.At(1).line == 1);
  CHECK(lines.At(1).column == 1);
  CHECK(lines.At(text.find('\n') + 2).line == 2);
  CHECK(lines.At(text.find('\n') + 2).column == 1);
  const LineColumn end = LineIndex("ab").At(3);
  CHECK(end.line == 1);
  CHECK(end.column == 3);
}

TEST_CASE("json: Quote escapes what JSON requires and round-trips through Parse", "[unit]") {
  CHECK(Quote("plain") == "\"plain\"");
  CHECK(Quote("a\"b\\c\n\t\x01") == R"("a\"b\\c\n\t\u0001")");
  CHECK(Quote("caf\xC3\xA9") == "\"caf\xC3\xA9\"");
  CHECK(Quote("bad\xC3(") == "\"bad\xEF\xBF\xBD(\"");
  const std::string s = "x\"\\\x1f\xC3\xA9/";
  Error error;
  const auto v = Parse(Quote(s), 2, &error);
  REQUIRE(v.has_value());
  CHECK(v->string == s);
}

TEST_CASE("json: Checker reports kinds, ranges and keys with the value's position", "[unit]") {
  const std::string text = R"({"n": 1.5, "i": 9223372036854775808, "s": "x", "u": 2, "z": 1})";
  Error error;
  const auto root = Parse(text, 4, &error);
  REQUIRE(root.has_value());
  Checker c;
  std::int64_t i = 0;
  double d = 0;
  CHECK_FALSE(c.GetInt(*root->Find("n"), "n", 0, 10, &i));
  CHECK(c.error().reason == "expected an integer, found 1.5");
  CHECK(c.error().column == text.find("1.5") + 1);
  CHECK_FALSE(c.GetInt(*root->Find("i"), "i", 0, 10, &i));
  CHECK(c.error().reason.find("64-bit integer range") != std::string::npos);
  CHECK_FALSE(c.GetDouble(*root->Find("s"), "s", &d));
  CHECK(c.error().reason == "expected a number, found a string");
  CHECK_FALSE(c.GetUnit(*root->Find("u"), "u", "score", &d));
  CHECK(c.error().reason == "score 2 is outside [0, 1]");
  std::map<std::string, const Value*> members;
  CHECK_FALSE(c.Members(*root, "", {"n", "i", "s", "u"}, {"n"}, &members));
  CHECK(c.error().reason.find("unknown key \"z\"") != std::string::npos);
  CHECK(c.error().column == text.find("\"z\"") + 1);
  CHECK(c.error().path == "z");
  CHECK_FALSE(c.Members(*root, "", {"n", "i", "s", "u", "z"}, {"q"}, &members));
  CHECK(c.error().reason == "missing key \"q\"");
  CHECK(c.Members(*root, "", {"n", "i", "s", "u", "z"}, {"n"}, &members));
  CHECK(members.size() == 5);
}

TEST_CASE("json: an unknown key is not echoed whole (length, control bytes)", "[unit]") {
  // Issue 39: a 100,000-character key came back twice in the error message.
  const std::string key(100000, 'k');
  const std::string text = "{\"" + key + "\": 1}";
  Error error;
  const auto root = Parse(text, 4, &error);
  REQUIRE(root.has_value());
  Checker c;
  std::map<std::string, const Value*> members;
  CHECK_FALSE(c.Members(*root, "", {"n"}, {}, &members));
  const std::string shown = std::string(64, 'k') + "... (100000 characters)";
  CHECK(c.error().reason == "unknown key \"" + shown + "\" (allowed: n)");
  CHECK(c.error().path == shown);
  CHECK(c.error().column == 2);
  const auto escape = Parse("{\"esc\\u001b[2J\": 2}", 4, &error);
  REQUIRE(escape.has_value());
  CHECK_FALSE(c.Members(*escape, "", {"n"}, {}, &members));
  CHECK(c.error().reason == "unknown key \"esc?[2J\" (allowed: n)");
  CHECK(Checker::Shown("ok") == "ok");
}

}  // namespace
}  // namespace mvtrack::json
