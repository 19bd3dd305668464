#include "config/internal/yaml_node.h"

#include <bit>
#include <catch2/catch.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "config/config_error.h"
#include "config_test_util.h"

namespace mvtrack::config {
namespace {

using internal::DoubleRange;
using internal::MapRef;
using internal::NodeRef;
using testing::CheckLocated;
using testing::LineOf;
using testing::RequireConfigError;

// The value of key `v` in the one-line document "v: <scalar>".
NodeRef ValueOf(const std::string& scalar) {
  const NodeRef root = internal::ParseDocument("v: " + scalar + "\n", "t.yaml");
  return *MapRef(root, {"v"}).Find("v");
}

TEST_CASE("ConfigError formats file, position, key path and reason", "[unit]") {
  const ConfigError full("a.yaml", 12, 5, "tracker.association.lamda", "unknown key");
  CHECK(std::string(full.what()) == "a.yaml:12:5: tracker.association.lamda: unknown key");
  CHECK(full.line() == 12);
  CHECK(full.column() == 5);
  CHECK(full.reason() == "unknown key");
  CHECK(std::string(ConfigError("a.yaml", 0, 0, "", "file does not exist").what()) ==
        "a.yaml: file does not exist");
  CHECK(std::string(ConfigError("a.yaml", 3, 0, "k", "bad").what()) == "a.yaml:3: k: bad");
}

TEST_CASE("GetDouble accepts plain decimal reals and nothing else", "[unit]") {
  CHECK(internal::GetDouble(ValueOf("1")) == 1.0);
  CHECK(internal::GetDouble(ValueOf("-2.5")) == -2.5);
  CHECK(internal::GetDouble(ValueOf("1e-3")) == 1e-3);
  CHECK(internal::GetDouble(ValueOf("2.5E+2")) == 250.0);
  CHECK(internal::GetDouble(ValueOf(".5")) == 0.5);
  CHECK(internal::GetDouble(ValueOf("+3")) == 3.0);
  CHECK(internal::GetDouble(ValueOf("!!float 4")) == 4.0);

  struct Bad {
    std::string scalar;
    std::string reason;
  };
  const std::vector<Bad> bad = {
      {"abc", "expected a number, got 'abc'"},
      {"\"0.3\"", "expected a number, got the quoted string \"0.3\""},
      {"'0.3'", "quoted string"},
      {"", "expected a number, got nothing (null)"},
      {"~", "nothing (null)"},
      {"[1, 2]", "got a list"},
      {"{a: 1}", "got a map"},
      {".nan", "non-finite number '.nan'"},
      {".NaN", "non-finite"},
      {".inf", "non-finite"},
      {"-.Inf", "non-finite"},
      {"+.INF", "non-finite"},
      {"nan", "non-finite"},
      {"inf", "non-finite"},
      {"1e999", "out of the range of a double"},
      {"0x10", "expected a number"},
      {"+-1", "expected a number"},
      {"1,5", "expected a number"},
      {"!!str 1", "quoted string"},
  };
  for (const Bad& b : bad) {
    INFO("scalar: " << b.scalar);
    const ConfigError e = RequireConfigError([&] { internal::GetDouble(ValueOf(b.scalar)); });
    CheckLocated(e, "t.yaml", 1, "v", b.reason);
  }
}

TEST_CASE("GetDouble enforces its range with a readable bound", "[unit]") {
  CHECK(internal::GetDouble(ValueOf("0"), DoubleRange::Closed(0.0, 1.0)) == 0.0);
  CHECK(internal::GetDouble(ValueOf("1"), DoubleRange::LeftOpen(0.0, 1.0)) == 1.0);
  CheckLocated(RequireConfigError(
                   [] { internal::GetDouble(ValueOf("0"), DoubleRange::LeftOpen(0.0, 1.0)); }),
               "t.yaml",
               1,
               "v",
               "value 0 out of range: must be in (0, 1]");
  CheckLocated(RequireConfigError(
                   [] { internal::GetDouble(ValueOf("1.5"), DoubleRange::Closed(0.0, 1.0)); }),
               "t.yaml",
               1,
               "v",
               "must be in [0, 1]");
  CheckLocated(RequireConfigError(
                   [] { internal::GetDouble(ValueOf("-1e-300"), DoubleRange::AtLeast(0.0)); }),
               "t.yaml",
               1,
               "v",
               "must be >= 0");
  CheckLocated(
      RequireConfigError([] { internal::GetDouble(ValueOf("0"), DoubleRange::GreaterThan(0.0)); }),
      "t.yaml",
      1,
      "v",
      "must be > 0");
}

TEST_CASE("GetInt64 and GetInt accept decimal integers only", "[unit]") {
  CHECK(internal::GetInt64(ValueOf("7")) == 7);
  CHECK(internal::GetInt64(ValueOf("-3")) == -3);
  CHECK(internal::GetInt64(ValueOf("+4")) == 4);
  CHECK(internal::GetInt64(ValueOf("9223372036854775807")) == INT64_MAX);
  CHECK(internal::GetInt(ValueOf("5"), 1, 5) == 5);

  struct Bad {
    std::string scalar;
    std::string reason;
  };
  const std::vector<Bad> bad = {
      {"7.0", "expected an integer, got '7.0' (no fraction or exponent allowed)"},
      {"1e3", "no fraction or exponent"},
      {"abc", "expected an integer, got 'abc'"},
      {"0x10", "expected an integer"},
      {"+-1", "expected an integer"},
      {".inf", "non-finite"},
      {"\"3\"", "quoted string"},
      {"", "nothing (null)"},
      {"9223372036854775808", "does not fit in 64 bits"},
      // A huge value is echoed by its first 32 characters and its length, not whole.
      {std::string(5000, '9'),
       "integer '" + std::string(32, '9') + "... (5000 characters)' does not fit in 64 bits"},
  };
  for (const Bad& b : bad) {
    INFO("scalar: " << b.scalar);
    CheckLocated(RequireConfigError([&] { internal::GetInt64(ValueOf(b.scalar)); }),
                 "t.yaml",
                 1,
                 "v",
                 b.reason);
  }
  CheckLocated(RequireConfigError([] { internal::GetInt(ValueOf("0"), 1, 10); }),
               "t.yaml",
               1,
               "v",
               "value 0 out of range: must be in [1, 10]");
  CheckLocated(RequireConfigError([] { internal::GetInt(ValueOf("0"), 1); }),
               "t.yaml",
               1,
               "v",
               "value 0 out of range: must be >= 1");
  CheckLocated(RequireConfigError([] { internal::GetInt(ValueOf("4294967296")); }),
               "t.yaml",
               1,
               "v",
               "integer '4294967296' does not fit in 32 bits");
}

TEST_CASE("GetBool accepts the YAML 1.2 booleans only", "[unit]") {
  CHECK(internal::GetBool(ValueOf("true")));
  CHECK(internal::GetBool(ValueOf("True")));
  CHECK_FALSE(internal::GetBool(ValueOf("FALSE")));
  CHECK_FALSE(internal::GetBool(ValueOf("false")));
  for (const std::string scalar : {"yes", "on", "1", "\"true\"", "y", ""}) {
    INFO("scalar: " << scalar);
    CheckLocated(RequireConfigError([&] { internal::GetBool(ValueOf(scalar)); }),
                 "t.yaml",
                 1,
                 "v",
                 "expected true or false");
  }
}

TEST_CASE("GetString and GetEnum", "[unit]") {
  CHECK(internal::GetString(ValueOf("hello")) == "hello");
  CHECK(internal::GetString(ValueOf("\"a: b\"")) == "a: b");
  CHECK(internal::GetString(ValueOf("\"\""), /*allow_empty=*/true).empty());
  CheckLocated(RequireConfigError([] { internal::GetString(ValueOf("\"\"")); }),
               "t.yaml",
               1,
               "v",
               "non-empty");
  CheckLocated(RequireConfigError([] { internal::GetString(ValueOf("[a]")); }),
               "t.yaml",
               1,
               "v",
               "expected a string, got a list");

  enum class Color { kRed, kGreen };
  const auto from_name = [](std::string_view n) -> std::optional<Color> {
    if (n == "red") return Color::kRed;
    if (n == "green") return Color::kGreen;
    return std::nullopt;
  };
  CHECK(internal::GetEnum<Color>(ValueOf("green"), from_name, {"red", "green"}) == Color::kGreen);
  CheckLocated(RequireConfigError([&] {
                 internal::GetEnum<Color>(ValueOf("gren"), from_name, {"red", "green"});
               }),
               "t.yaml",
               1,
               "v",
               "unknown value 'gren' (did you mean 'green'?)");
  CheckLocated(RequireConfigError([&] {
                 internal::GetEnum<Color>(ValueOf("blue"), from_name, {"red", "green"});
               }),
               "t.yaml",
               1,
               "v",
               "unknown value 'blue' (expected one of 'red', 'green')");
}

TEST_CASE("MapRef rejects unknown, duplicate and non-scalar keys at the key's position", "[unit]") {
  const std::string text =
      "outer:\n"
      "  alpha: 1\n"
      "  betta: 2\n";
  const NodeRef root = internal::ParseDocument(text, "m.yaml");
  const MapRef outer(root, {"outer"});
  CheckLocated(RequireConfigError([&] {
                 MapRef(outer.Get("outer"), {"alpha", "beta"});
               }),
               "m.yaml",
               LineOf(text, "betta"),
               "outer.betta",
               "unknown key (did you mean 'beta'?)");
  CheckLocated(RequireConfigError([&] {
                 MapRef(outer.Get("outer"), {"alpha", "gamma"});
               }),
               "m.yaml",
               LineOf(text, "betta"),
               "outer.betta",
               "unknown key (allowed keys: 'alpha', 'gamma')");
  // A hint for a key that belongs elsewhere wins over the edit distance.
  CheckLocated(RequireConfigError([&] {
                 MapRef(outer.Get("outer"),
                        {"alpha", "beta"},
                        false,
                        {internal::KeyHint{"betta", "'elsewhere.betta'"}});
               }),
               "m.yaml",
               LineOf(text, "betta"),
               "outer.betta",
               "unknown key (did you mean 'elsewhere.betta'?)");

  const std::string duplicated = "a: 1\nb: 2\na: 3\n";
  const NodeRef dup_root = internal::ParseDocument(duplicated, "d.yaml");
  CheckLocated(RequireConfigError([&] {
                 MapRef(dup_root, {"a", "b"});
               }),
               "d.yaml",
               3,
               "a",
               "duplicate key (first given at line 1)");

  const NodeRef complex_key = internal::ParseDocument("? [1, 2]\n: 3\n", "c.yaml");
  const ConfigError e = RequireConfigError([&] { MapRef(complex_key, {"a"}); });
  CHECK_THAT(e.reason(), Catch::Contains("map keys must be scalars"));
  CHECK(e.line() == 1);

  const NodeRef list_root = internal::ParseDocument("[1, 2]\n", "l.yaml");
  CHECK_THAT(RequireConfigError([&] { MapRef(list_root, {"a"}); }).reason(),
             Catch::Contains("expected a map, got a list"));
}

TEST_CASE("MapRef lookups, required keys and exclusive alternatives", "[unit]") {
  const std::string text = "a: 1\nb:\nc: 3\n";
  const NodeRef root = internal::ParseDocument(text, "m.yaml");
  const MapRef map(root, {"a", "b", "c", "d"});
  CHECK(map.keys() == std::vector<std::string>{"a", "b", "c"});
  CHECK(map.Has("a"));
  CHECK_FALSE(map.Has("d"));
  CHECK_FALSE(map.Find("d").has_value());
  // A null value is located at its key (yaml-cpp would place it on the next line).
  CHECK(map.Find("b")->line() == 2);
  CHECK(map.Find("b")->IsNull());
  CheckLocated(
      RequireConfigError([&] { map.Get("d"); }), "m.yaml", 1, "", "missing required key 'd'");
  CHECK(map.RequireExactlyOne({"a", "d"}, "thing") == "a");
  CheckLocated(RequireConfigError([&] {
                 map.RequireExactlyOne({"a", "c"}, "thing");
               }),
               "m.yaml",
               3,
               "c",
               "give exactly one thing form, not both 'a', 'c'");
  CHECK_THAT(RequireConfigError([&] {
               map.RequireExactlyOne({"d", "e"}, "thing");
             }).reason(),
             Catch::Contains("missing thing: give exactly one of 'd', 'e'"));

  // null_is_empty: a null map is an empty map.
  const NodeRef null_root = internal::ParseDocument("s:\n", "n.yaml");
  const NodeRef s = *MapRef(null_root, {"s"}).Find("s");
  CHECK(MapRef(s, {"x"}, /*null_is_empty=*/true).keys().empty());
  CHECK_THAT(RequireConfigError([&] { MapRef(s, {"x"}); }).reason(),
             Catch::Contains("expected a map, got nothing (null)"));
}

TEST_CASE("GetSequence checks length and gives element paths", "[unit]") {
  const std::string text = "v:\n  - 1\n  - 2\n  - x\n";
  const NodeRef root = internal::ParseDocument(text, "s.yaml");
  const NodeRef v = *MapRef(root, {"v"}).Find("v");
  const std::vector<NodeRef> items = internal::GetSequence(v, 3);
  REQUIRE(items.size() == 3);
  CHECK(items[1].path() == "v[1]");
  CHECK(internal::GetDouble(items[1]) == 2.0);
  CheckLocated(RequireConfigError([&] { internal::GetDouble(items[2]); }),
               "s.yaml",
               LineOf(text, "- x"),
               "v[2]",
               "expected a number, got 'x'");
  CHECK_THAT(RequireConfigError([&] { internal::GetSequence(v, 2); }).reason(),
             Catch::Contains("expected a list of 2 values, got 3"));
}

TEST_CASE("EditDistance and SuggestClosest", "[unit]") {
  CHECK(internal::EditDistance("kitten", "sitting") == 3);
  CHECK(internal::EditDistance("", "abc") == 3);
  CHECK(internal::EditDistance("abc", "") == 3);
  CHECK(internal::EditDistance("lamda", "lambda") == 1);
  CHECK(internal::EditDistance("flaw", "lawn") == 2);
  CHECK(internal::EditDistance("same", "same") == 0);
  // Adjacent transpositions cost 1 (optimal string alignment, not full Damerau: "ca" -> "abc"
  // would be 2 with unrestricted edits).
  CHECK(internal::EditDistance("pdcn", "pdnc") == 1);
  CHECK(internal::EditDistance("ca", "abc") == 3);
  CHECK(internal::EditDistance("box", "boxes") == 2);
  const std::vector<std::string> keys = {"lambda", "min_confidence", "method", "empty_upper_bound"};
  CHECK(internal::SuggestClosest("lamda", keys) == std::optional<std::string>("lambda"));
  CHECK(internal::SuggestClosest("methd", keys) == std::optional<std::string>("method"));
  CHECK(internal::SuggestClosest("min_confidance", keys) ==
        std::optional<std::string>("min_confidence"));
  CHECK_FALSE(internal::SuggestClosest("zzz", keys).has_value());
  // A short key tolerates a single edit only.
  CHECK(internal::SuggestClosest("phy", {"phi"}) == std::optional<std::string>("phi"));
  CHECK(internal::SuggestClosest("pho", {"t", "phi"}) == std::optional<std::string>("phi"));
  CHECK_FALSE(internal::SuggestClosest("xyz", {"phi"}).has_value());
  // Ties go to the earlier candidate; a closer later candidate wins.
  CHECK(internal::SuggestClosest("abcdefx", {"abcdefy", "abcdefz"}) ==
        std::optional<std::string>("abcdefy"));
  CHECK(internal::SuggestClosest("abcdefx", {"abcdyzz", "abcdefy"}) ==
        std::optional<std::string>("abcdefy"));
}

TEST_CASE("FormatDouble is shortest, exact and reads as a real", "[unit]") {
  CHECK(internal::FormatDouble(0.3) == "0.3");
  CHECK(internal::FormatDouble(15.0) == "15.0");
  CHECK(internal::FormatDouble(-0.0) == "-0.0");
  CHECK(internal::FormatDouble(1e-5) == "1e-05");
  CHECK(internal::FormatDouble(std::nan("")) == ".nan");
  CHECK(internal::FormatDouble(-INFINITY) == "-.inf");
  std::mt19937_64 rng(20240611);
  for (int i = 0; i < 2000; ++i) {
    // Random bit patterns cover every exponent; non-finite ones are skipped.
    const double value = std::bit_cast<double>(static_cast<std::uint64_t>(rng()));
    if (!std::isfinite(value)) continue;
    const std::string text = internal::FormatDouble(value);
    INFO(text);
    const double back = internal::GetDouble(ValueOf(text));
    CHECK(std::bit_cast<std::uint64_t>(back) == std::bit_cast<std::uint64_t>(value));
  }
}

TEST_CASE("QuoteString round-trips through yaml-cpp", "[unit]") {
  for (const std::string& text : {std::string("plain"),
                                  std::string("with \"quotes\" and \\"),
                                  std::string("colon: hash # [brackets]"),
                                  std::string("tab\tnew\nline"),
                                  std::string("ctrl\x01\x7f"),
                                  std::string("unicode \xC3\xA9\xE2\x86\x92")}) {
    INFO(text);
    CHECK(internal::GetString(ValueOf(internal::QuoteString(text))) == text);
  }
}

TEST_CASE("ParseDocument reports syntax errors with their line", "[unit]") {
  const std::string text = "a: 1\nb: [1, 2\nc: 3\n";
  const ConfigError e = RequireConfigError([&] { internal::ParseDocument(text, "syntax.yaml"); });
  CHECK(e.file() == "syntax.yaml");
  CHECK(e.line() >= 2);
  CHECK(e.key_path().empty());
  CHECK_THAT(e.reason(), Catch::StartsWith("YAML syntax error: "));
  CHECK_THAT(std::string(e.what()), Catch::StartsWith("syntax.yaml:" + std::to_string(e.line())));

  const ConfigError bad_value =
      RequireConfigError([] { internal::ParseDocument("a: b: c\n", "x"); });
  CHECK(bad_value.line() == 1);
  CHECK(bad_value.column() == 5);

  const ConfigError two =
      RequireConfigError([] { internal::ParseDocument("--- 1\n--- 2\n", "x"); });
  CHECK(two.line() == 2);
  CHECK_THAT(two.reason(), Catch::Contains("expected one YAML document, found 2"));

  // Hostile nesting: yaml-cpp's recursion guard ("bad file") becomes a message that says so,
  // at the line where the nesting went too deep.
  const ConfigError deep = RequireConfigError([] {
    internal::ParseDocument(
        "a: 1\nb: " + std::string(100000, '[') + std::string(100000, ']') + "\nc: 2\n",
        "deep.yaml");
  });
  CHECK(deep.line() == 2);
  CHECK_THAT(deep.reason(), Catch::StartsWith("YAML nested too deeply here"));
  CHECK_THAT(deep.reason(), !Catch::Contains("bad file"));
  std::string blocks = "a:\n";
  for (int i = 1; i < 3000; ++i)
    blocks += std::string(static_cast<std::size_t>(2 * i), ' ') + "k:\n";
  const ConfigError deep_blocks =
      RequireConfigError([&] { internal::ParseDocument(blocks, "blocks.yaml"); });
  CHECK(deep_blocks.line() > 100);
  CHECK_THAT(deep_blocks.reason(), Catch::StartsWith("YAML nested too deeply here"));

  CHECK(internal::ParseDocument("", "x").IsNull());
  CHECK(internal::ParseDocument("# only a comment\n", "x").IsNull());
}

TEST_CASE("ReadTextFile and WriteTextFile", "[unit]") {
  const testing::TempDir dir;
  const std::string path = dir.File("a.txt");
  internal::WriteTextFile(path, "line 1\nline 2\n");
  CHECK(internal::ReadTextFile(path) == "line 1\nline 2\n");
  internal::WriteTextFile(path, "replaced");
  CHECK(internal::ReadTextFile(path) == "replaced");
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));

  const std::string missing = dir.File("missing.yaml");
  const ConfigError e = RequireConfigError([&] { internal::ReadTextFile(missing); });
  CHECK(std::string(e.what()) == missing + ": file does not exist");
  CHECK_THAT(RequireConfigError([&] { internal::ReadTextFile(dir.File("")); }).reason(),
             Catch::Contains("not a regular file"));
  CHECK(RequireConfigError([&] {
          internal::WriteTextFile(dir.File("no/such/dir.txt"), "x");
        }).file() == dir.File("no/such/dir.txt"));
}

}  // namespace
}  // namespace mvtrack::config
