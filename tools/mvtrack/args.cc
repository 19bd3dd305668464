#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/suggest.h"
#include "mvtrack/cli.h"

namespace mvtrack::cli {

Args& Args::Option(const std::string& name,
                   const std::string& help,
                   const std::string& default_value) {
  options_[name] = Spec{help, default_value, false};
  option_order_.push_back(name);
  values_[name] = default_value;
  return *this;
}

Args& Args::Flag(const std::string& name, const std::string& help) {
  options_[name] = Spec{help, "", true};
  option_order_.push_back(name);
  return *this;
}

Args& Args::Positional(const std::string& name, const std::string& help, bool required) {
  positional_specs_.emplace_back(name, help);
  positional_required_.push_back(required);
  return *this;
}

Args& Args::Rest(const std::string& name, const std::string& help) {
  rest_spec_ = std::make_pair(name, help);
  return *this;
}

std::string Args::Help(const std::string& usage_line, const std::string& description) const {
  std::ostringstream os;
  os << "usage: " << usage_line << "\n\n" << description << "\n";
  if (!positional_specs_.empty()) {
    os << "\narguments:\n";
    for (const auto& [name, help] : positional_specs_)
      os << "  " << name << "\n      " << help << "\n";
    if (rest_spec_) os << "  " << rest_spec_->first << "\n      " << rest_spec_->second << "\n";
  }
  os << "\noptions:\n";
  for (const std::string& name : option_order_) {
    const Spec& s = options_.at(name);
    os << "  --" << name << (s.is_flag ? "" : " VALUE") << "\n      " << s.help;
    if (!s.is_flag && !s.default_value.empty()) os << " (default: " << s.default_value << ")";
    os << "\n";
  }
  os << "  --help\n      show this help and exit\n";
  return os.str();
}

bool Args::Parse(int argc,
                 char** argv,
                 const std::string& usage_line,
                 const std::string& description) {
  std::vector<std::string> positionals;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << Help(usage_line, description);
      return false;
    }
    if (arg.rfind("--", 0) == 0) {
      std::string name = arg.substr(2);
      std::optional<std::string> value;
      const auto eq = name.find('=');
      if (eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      auto it = options_.find(name);
      if (it == options_.end()) {
        std::vector<std::string> names;
        for (const auto& [known, spec] : options_) names.push_back(known);
        const std::optional<std::string> close = core::SuggestClosest(name, names);
        throw UsageError("unknown option --" + name +
                         (close ? " (did you mean --" + *close + "?)" : " (see --help)"));
      }
      if (it->second.is_flag) {
        if (value) throw UsageError("--" + name + " takes no value");
        given_[name] = true;
        continue;
      }
      if (!value) {
        if (i + 1 >= argc) throw UsageError("--" + name + " needs a value");
        value = argv[++i];
      }
      values_[name] = *value;
      given_[name] = true;
      continue;
    }
    positionals.push_back(arg);
  }
  if (rest_spec_) {
    for (std::size_t i = positional_specs_.size(); i < positionals.size(); ++i) {
      rest_.push_back(positionals[i]);
    }
  } else if (positionals.size() > positional_specs_.size()) {
    throw UsageError("unexpected argument '" + positionals[positional_specs_.size()] + "'");
  }
  for (std::size_t i = 0; i < positional_specs_.size(); ++i) {
    if (i < positionals.size()) {
      values_[positional_specs_[i].first] = positionals[i];
      given_[positional_specs_[i].first] = true;
    } else if (positional_required_[i]) {
      throw UsageError("missing argument " + positional_specs_[i].first);
    }
  }
  return true;
}

std::string Args::Get(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::string() : it->second;
}

bool Args::Has(const std::string& name) const {
  auto it = given_.find(name);
  return it != given_.end() && it->second;
}

double Args::GetDouble(const std::string& name) const {
  const std::string s = Get(name);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end == s.c_str() || *end != '\0' || errno != 0 || !std::isfinite(v)) {
    throw UsageError("--" + name + ": '" + s + "' is not a finite number");
  }
  return v;
}

std::int64_t Args::GetInt(const std::string& name) const {
  const std::string s = Get(name);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end == s.c_str() || *end != '\0' || errno != 0) {
    throw UsageError("--" + name + ": '" + s + "' is not an integer");
  }
  return v;
}

// A non-negative decimal integer, the whole of `text`.
std::optional<std::int64_t> ParseNonNegative(std::string_view text) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v < 0) {
    return std::nullopt;
  }
  return v;
}

std::optional<double> ParseFinite(std::string_view text) {
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::vector<std::string_view> SplitCommas(std::string_view text) {
  std::vector<std::string_view> parts;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    parts.push_back(text.substr(begin, comma == std::string_view::npos ? comma : comma - begin));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return parts;
}

std::vector<eval::FrameRange> ParseFrameRanges(const std::string& text, const std::string& option) {
  std::vector<eval::FrameRange> ranges;
  for (std::string_view part : SplitCommas(text)) {
    const std::size_t dash = part.find('-');
    const std::optional<std::int64_t> first = ParseNonNegative(part.substr(0, dash));
    const std::optional<std::int64_t> last =
        dash == std::string_view::npos ? first : ParseNonNegative(part.substr(dash + 1));
    if (!first || !last) {
      throw UsageError(option + ": '" + std::string(part) +
                       "' is not a frame range A-B (non-negative frame indices, A <= B)");
    }
    if (*first > *last) {
      throw UsageError(option + ": range '" + std::string(part) + "' ends before it starts");
    }
    ranges.push_back({*first, *last});
  }
  return ranges;
}

int RunSubcommand(
    const char* program, const char* name, int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << program << " " << name << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << program << " " << name << ": error: " << e.what() << "\n";
    return 1;
  }
}

std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, value);
  return buf;
}

std::string PicturesHelper() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const std::filesystem::path helper = self.parent_path() / "mvtrack-pictures";
  return std::filesystem::exists(helper, ec) ? helper.string() : "";
}

int ExecPictures(const char* command, int argc, char** args) {
  const std::string helper = PicturesHelper();
  if (helper.empty()) {
    std::cerr << "mvtrack " << command
              << ": error: the helper mvtrack-pictures is not installed "
                 "next to mvtrack (Debian package mvtrack-tools; a build from source has it "
                 "when OpenCV imgproc, imgcodecs and videoio are installed: "
                 "tools/dev/install_deps.sh pictures, then build again)\n";
    return 1;
  }
  std::vector<char*> argv = {const_cast<char*>("mvtrack-pictures"), const_cast<char*>(command)};
  for (int i = 0; i < argc; ++i) argv.push_back(args[i]);
  argv.push_back(nullptr);
  execv(helper.c_str(), argv.data());
  std::cerr << "mvtrack " << command << ": error: cannot run " << helper << ": "
            << std::strerror(errno) << "\n";
  return 1;
}

}  // namespace mvtrack::cli
