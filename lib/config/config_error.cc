#include "config/config_error.h"

#include <utility>

namespace mvtrack::config {

ConfigError::ConfigError(
    std::string file, int line, int column, std::string key_path, std::string reason)
    : std::runtime_error(Format(file, line, column, key_path, reason)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_path_(std::move(key_path)),
      reason_(std::move(reason)) {}

std::string ConfigError::Format(const std::string& file,
                                int line,
                                int column,
                                const std::string& key_path,
                                const std::string& reason) {
  std::string text = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    text += ':' + std::to_string(line);
    if (column > 0) text += ':' + std::to_string(column);
  }
  text += ": ";
  if (!key_path.empty()) text += key_path + ": ";
  text += reason;
  return text;
}

}  // namespace mvtrack::config
