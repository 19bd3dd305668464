#pragma once
/// @file
/// Helpers for the config tests: a private temporary directory, file writing, line lookup in
/// test text, and a checker for ConfigError locations.

#include <stdlib.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "config/config_error.h"

namespace mvtrack::config::testing {

/// A fresh directory under the system temp dir (mkdtemp), removed with its content on
/// destruction; unique per process, so parallel ctest runs do not collide.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "mvtrack_config_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// Path of `name` inside the directory.
  std::string File(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `text` to `name` and returns its path.
  std::string Write(const std::string& name, std::string_view text) const {
    const std::string path = File(name);
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path);
    return path;
  }

 private:
  std::filesystem::path path_;
};

/// 1-based line of the first occurrence of `needle` in `text` (0 if absent).
inline int LineOf(std::string_view text, std::string_view needle) {
  const std::size_t pos = text.find(needle);
  if (pos == std::string_view::npos) return 0;
  int line = 1;
  for (std::size_t i = 0; i < pos; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

/// 1-based column of the first occurrence of `needle` in `text` (0 if absent).
inline int ColumnOf(std::string_view text, std::string_view needle) {
  const std::size_t pos = text.find(needle);
  if (pos == std::string_view::npos) return 0;
  const std::size_t line_start = text.rfind('\n', pos);
  return static_cast<int>(line_start == std::string_view::npos ? pos + 1 : pos - line_start);
}

/// Runs `fn`, which must throw ConfigError, and returns the error.
template <typename Fn>
ConfigError RequireConfigError(Fn&& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e;
  }
  FAIL("expected a ConfigError, nothing was thrown");
  throw std::logic_error("unreachable");
}

/// Checks that `e` names `file`, `line` (> 0) and `key_path`, that what() spells them as
/// "file:line:col: key_path: reason", and that the reason contains `reason_part`.
inline void CheckLocated(const ConfigError& e,
                         const std::string& file,
                         int line,
                         const std::string& key_path,
                         const std::string& reason_part) {
  INFO("what(): " << e.what());
  REQUIRE(line > 0);
  CHECK(e.file() == file);
  CHECK(e.line() == line);
  CHECK(e.column() > 0);
  CHECK(e.key_path() == key_path);
  CHECK_THAT(e.reason(), Catch::Contains(reason_part));
  const std::string prefix = file + ":" + std::to_string(line) + ":" + std::to_string(e.column()) +
                             ": " + (key_path.empty() ? std::string() : key_path + ": ");
  CHECK(std::string(e.what()).rfind(prefix, 0) == 0);
}

}  // namespace mvtrack::config::testing
