#pragma once
/// @file
/// The typed exception of lib/config: every setup error (unreadable file, YAML syntax error,
/// unknown or missing key, wrong type, out-of-range value, invalid camera) is a ConfigError whose
/// message names the file, the line and column when known, the key path and the reason, e.g.
///
///     config.yaml:12:5: tracker.association.lamda: unknown key (did you mean 'lambda'?)
///
/// `main` catches it, logs what() and exits non-zero (docs/ARCHITECTURE.md, "Errors").

#include <stdexcept>
#include <string>

namespace mvtrack::config {

/// A configuration or calibration file could not be read, parsed or validated.
/// Immutable value type; the accessors return the parts of what().
class ConfigError : public std::runtime_error {
 public:
  /// `file`: the path or source name as given by the caller; `line` and `column` are 1-based,
  /// 0 when unknown; `key_path` is the dotted key path (with [i] for list elements), empty when
  /// the error concerns the whole file; `reason` says what is wrong.
  ConfigError(std::string file, int line, int column, std::string key_path, std::string reason);

  /// The file (path or source name) the error refers to.
  const std::string& file() const { return file_; }
  /// 1-based line, 0 when unknown.
  int line() const { return line_; }
  /// 1-based column, 0 when unknown.
  int column() const { return column_; }
  /// Dotted key path such as "tracker.association.lambda" or "cameras[2].K[1]"; may be empty.
  const std::string& key_path() const { return key_path_; }
  /// What is wrong, without the location prefix.
  const std::string& reason() const { return reason_; }

  /// Formats "file[:line[:column]]: [key_path: ]reason" (the text of what()).
  static std::string Format(const std::string& file,
                            int line,
                            int column,
                            const std::string& key_path,
                            const std::string& reason);

 private:
  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string key_path_;
  std::string reason_;
};

}  // namespace mvtrack::config
