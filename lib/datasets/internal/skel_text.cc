#include "datasets/internal/skel_text.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "datasets/dataset.h"

namespace mvtrack::datasets::internal {
namespace {

// Sequential whitespace tokenizer that knows the line of every token.
class Tokenizer {
 public:
  Tokenizer(std::string name, std::string text) : name_(std::move(name)), text_(std::move(text)) {}

  [[noreturn]] void Fail(const std::string& problem) const {
    throw DatasetError(name_, "line " + std::to_string(line_) + ": " + problem);
  }

  // The next token, or an error naming `what` at the end of the file.
  std::string Next(const std::string& what) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) != 0) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) Fail("unexpected end of file, expected " + what);
    const std::size_t start = pos_;
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) == 0) {
      ++pos_;
    }
    return text_.substr(start, pos_ - start);
  }

  std::int64_t NextInt(const std::string& what) {
    const std::string token = Next(what);
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(token.c_str(), &end, 10);
    if (errno == ERANGE || end != token.c_str() + token.size()) {
      Fail("expected " + what + " (an integer), got \"" + token + "\"");
    }
    return static_cast<std::int64_t>(v);
  }

  // The next token as a finite number; `what` builds the description for error messages only
  // (it is not evaluated on the hot path).
  template <typename What>
  double NextDouble(const What& what) {
    if (AtEnd()) Fail("unexpected end of file, expected " + what());
    const std::string token = Next("a number");
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || !std::isfinite(v)) {
      Fail("expected " + what() + " (a finite number), got \"" + token + "\"");
    }
    return v;
  }

  bool AtEnd() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])) != 0) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    return pos_ >= text_.size();
  }

 private:
  std::string name_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

SkelTextFile ReadSkelText(const std::filesystem::path& file, int expected_joints) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw DatasetError(name, "file not found or not readable");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  Tokenizer tok(name, buffer.str());

  constexpr std::int64_t kMaxJoints = 1000;
  constexpr std::int64_t kMaxFrames = 10'000'000;
  constexpr std::int64_t kMaxPeople = 10'000;
  const std::int64_t joints = tok.NextInt("the joint count J");
  if (joints <= 0 || joints > kMaxJoints) {
    tok.Fail("joint count " + std::to_string(joints) + " out of range [1, 1000]");
  }
  if (expected_joints > 0 && joints != expected_joints) {
    tok.Fail("expected " + std::to_string(expected_joints) +
             " joints per skeleton, the header says " + std::to_string(joints));
  }
  const std::int64_t frames = tok.NextInt("the frame count F");
  if (frames < 0 || frames > kMaxFrames) {
    tok.Fail("frame count " + std::to_string(frames) + " out of range");
  }
  static const char* const kRowNames[4] = {"x", "y", "z", "confidence"};

  SkelTextFile out;
  out.num_joints = static_cast<int>(joints);
  out.frames.resize(static_cast<std::size_t>(frames));
  for (std::int64_t f = 0; f < frames; ++f) {
    const std::string at_frame = "frame " + std::to_string(f);
    const std::int64_t people = tok.NextInt("the person count of " + at_frame);
    if (people < 0 || people > kMaxPeople) {
      tok.Fail("person count " + std::to_string(people) + " of " + at_frame + " out of range");
    }
    std::set<std::int64_t> ids;
    auto& frame = out.frames[static_cast<std::size_t>(f)];
    frame.reserve(static_cast<std::size_t>(people));
    for (std::int64_t p = 0; p < people; ++p) {
      SkelTextPerson person;
      person.id = tok.NextInt("a person id in " + at_frame);
      if (person.id < 0) tok.Fail("negative person id in " + at_frame);
      if (!ids.insert(person.id).second) {
        tok.Fail("person id " + std::to_string(person.id) + " appears twice in " + at_frame);
      }
      person.rows.resize(4, joints);
      for (int r = 0; r < 4; ++r) {
        for (Eigen::Index j = 0; j < joints; ++j) {
          person.rows(r, j) = tok.NextDouble([&] {
            return std::string(kRowNames[r]) + " of joint " + std::to_string(j) + " of person " +
                   std::to_string(person.id) + " in " + at_frame;
          });
        }
      }
      frame.push_back(std::move(person));
    }
  }
  if (!tok.AtEnd()) tok.Fail("unexpected content after the last frame");
  return out;
}

}  // namespace mvtrack::datasets::internal
