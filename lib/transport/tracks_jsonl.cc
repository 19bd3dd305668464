#include "transport/tracks_jsonl.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <system_error>
#include <vector>

namespace mvtrack::transport {
namespace {

// ---------------------------------------------------------------------------------------------
// Formatting

void AppendInt(std::int64_t value, std::string* out) {
  std::array<char, 24> buffer{};
  const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out->append(buffer.data(), end);
}

// `value` (finite) with kTracksJsonDecimals decimals; "-0.0000" becomes "0.0000".
void AppendFixed(double value, std::string* out) {
  // 309 integer digits of DBL_MAX, sign, point and the decimals fit.
  std::array<char, 330> buffer{};
  const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                       std::chars_format::fixed, kTracksJsonDecimals);
  std::string_view text(buffer.data(), static_cast<std::size_t>(end - buffer.data()));
  // A negative value that rounds to zero prints "-0.0000": drop the sign.
  if (text.front() == '-' && text.find_first_not_of("0.", 1) == std::string_view::npos) {
    text.remove_prefix(1);
  }
  out->append(text);
}

bool AllFinite(const Vec3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

void AppendPoint(const Vec3& p, std::string* out) {
  out->push_back('[');
  AppendFixed(p.x(), out);
  out->append(", ");
  AppendFixed(p.y(), out);
  out->append(", ");
  AppendFixed(p.z(), out);
  out->push_back(']');
}

// ---------------------------------------------------------------------------------------------
// Parsing: a recursive-descent reader for exactly this schema.

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {}

  const std::string& error() const { return error_; }

  bool Fail(const std::string& what) {
    if (error_.empty()) {
      error_ = "column " + std::to_string(pos_ + 1) + ": " + what;
    }
    return false;
  }

  void SkipWhitespace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }

  // Skips whitespace, then true (and consumes it) when the next character is `c`.
  bool Accept(char c) {
    SkipWhitespace();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  bool Expect(char c, std::string_view where) {
    if (Accept(c)) return true;
    return Fail(std::string("expected '") + c + "' " + std::string(where) + ", found " +
                Found());
  }

  bool AcceptNull() {
    SkipWhitespace();
    if (text_.substr(pos_, 4) == "null") {
      pos_ += 4;
      return true;
    }
    return false;
  }

  bool AtEnd() {
    SkipWhitespace();
    return pos_ == text_.size();
  }

  // A JSON string without escapes (the schema's keys and layout names need none).
  bool ParseString(std::string* out) {
    SkipWhitespace();
    if (pos_ >= text_.size() || text_[pos_] != '"') {
      return Fail("expected a string, found " + Found());
    }
    const std::size_t begin = ++pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      const char c = text_[pos_];
      if (c == '\\') return Fail("escape sequences are not part of this format");
      if (static_cast<unsigned char>(c) < 0x20) return Fail("control character in a string");
      ++pos_;
    }
    if (pos_ >= text_.size()) return Fail("unterminated string");
    out->assign(text_.substr(begin, pos_ - begin));
    ++pos_;
    return true;
  }

  bool ParseInt64(std::string_view what, std::int64_t* value) {
    SkipWhitespace();
    const std::size_t begin = pos_;
    std::size_t end = begin;
    if (!ScanNumber(&end)) return Fail(std::string(what) + " must be an integer, found " + Found());
    const std::string_view token = text_.substr(begin, end - begin);
    if (token.find_first_of(".eE") != std::string_view::npos) {
      return Fail(std::string(what) + " must be an integer, found " + std::string(token));
    }
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      return Fail(std::string(what) + " " + std::string(token) + " is beyond the int64 range");
    }
    pos_ = end;
    return true;
  }

  bool ParseDouble(std::string_view what, double* value) {
    SkipWhitespace();
    const std::size_t begin = pos_;
    std::size_t end = begin;
    if (!ScanNumber(&end)) return Fail(std::string(what) + " must be a number, found " + Found());
    const std::string_view token = text_.substr(begin, end - begin);
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
    if (ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(*value)) {
      return Fail(std::string(what) + " " + std::string(token) + " is beyond the double range");
    }
    pos_ = end;
    return true;
  }

  // [x, y, z] with three numbers.
  bool ParsePoint(std::string_view what, Vec3* point) {
    if (!Expect('[', "to open " + std::string(what))) return false;
    for (int i = 0; i < 3; ++i) {
      if (i > 0 && !Expect(',', "between coordinates of " + std::string(what))) return false;
      if (!ParseDouble(std::string(what) + " coordinate " + std::to_string(i), &(*point)[i])) {
        return false;
      }
    }
    return Expect(']', "after the 3 coordinates of " + std::string(what));
  }

 private:
  // Scans a JSON number starting at pos_ (no leading whitespace): -?(0|[1-9]d*)(.d+)?([eE][+-]?d+)?
  bool ScanNumber(std::size_t* end) const {
    std::size_t i = pos_;
    auto digit = [&](std::size_t k) {
      return k < text_.size() && text_[k] >= '0' && text_[k] <= '9';
    };
    if (i < text_.size() && text_[i] == '-') ++i;
    if (!digit(i)) return false;
    if (text_[i] == '0') {
      ++i;
    } else {
      while (digit(i)) ++i;
    }
    if (i < text_.size() && text_[i] == '.') {
      ++i;
      if (!digit(i)) return false;
      while (digit(i)) ++i;
    }
    if (i < text_.size() && (text_[i] == 'e' || text_[i] == 'E')) {
      ++i;
      if (i < text_.size() && (text_[i] == '+' || text_[i] == '-')) ++i;
      if (!digit(i)) return false;
      while (digit(i)) ++i;
    }
    *end = i;
    return true;
  }

  std::string Found() const {
    if (pos_ >= text_.size()) return "the end of the line";
    return "'" + std::string(text_.substr(pos_, 12)) + "'";
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  std::string error_;
};

// Parses `{ "key": value, ... }` calling `member(key)` for each key, which parses the value.
// Rejects duplicate keys and (through `member`) unknown ones.
template <typename Member>
bool ParseObject(Parser* p, std::string_view what, Member member) {
  if (!p->Expect('{', "to open " + std::string(what))) return false;
  std::vector<std::string> seen;
  if (p->Accept('}')) return true;
  do {
    std::string key;
    if (!p->ParseString(&key)) return false;
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) {
      return p->Fail("duplicate key \"" + key + "\" in " + std::string(what));
    }
    seen.push_back(key);
    if (!p->Expect(':', "after key \"" + key + "\"")) return false;
    if (!member(key)) return false;
  } while (p->Accept(','));
  return p->Expect('}', "to close " + std::string(what));
}

// Parses `[ item, ... ]` calling `item(index)` for each element.
template <typename Item>
bool ParseArray(Parser* p, std::string_view what, Item item) {
  if (!p->Expect('[', "to open " + std::string(what))) return false;
  if (p->Accept(']')) return true;
  std::size_t index = 0;
  do {
    if (!item(index++)) return false;
  } while (p->Accept(','));
  return p->Expect(']', "to close " + std::string(what));
}

bool ParseTrack(Parser* p, std::size_t index, tracker::Track3D* track) {
  bool has_id = false, has_joints = false, has_position = false;
  const std::string what = "track " + std::to_string(index);
  const bool ok = ParseObject(p, what, [&](const std::string& key) {
    if (key == "id") {
      has_id = true;
      return p->ParseInt64(what + " id", &track->id);
    }
    if (key == "joints") {
      has_joints = true;
      return ParseArray(p, what + " joints", [&](std::size_t j) {
        if (p->AcceptNull()) {
          track->joints.emplace_back(std::nullopt);
          return true;
        }
        Vec3 joint;
        if (!p->ParsePoint(what + " joint " + std::to_string(j), &joint)) return false;
        track->joints.emplace_back(joint);
        return true;
      });
    }
    if (key == "position") {
      has_position = true;
      if (p->AcceptNull()) {
        track->position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
        return true;
      }
      return p->ParsePoint(what + " position", &track->position);
    }
    return p->Fail("unknown key \"" + key + "\" in " + what);
  });
  if (!ok) return false;
  if (!has_id) return p->Fail(what + " has no \"id\"");
  if (!has_joints) return p->Fail(what + " has no \"joints\"");
  if (!has_position) return p->Fail(what + " has no \"position\"");
  return true;
}

}  // namespace

std::string TracksJsonLine(const tracker::Frame3D& frame, core::KeypointLayoutId layout) {
  std::vector<std::size_t> order(frame.tracks.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&frame](std::size_t a, std::size_t b) {
    return frame.tracks[a].id < frame.tracks[b].id;
  });
  std::string out;
  out.reserve(64 + frame.tracks.size() * 64);
  out.append("{\"frame\": ");
  AppendInt(frame.frame, &out);
  out.append(", \"layout\": \"");
  out.append(core::GetKeypointLayout(layout).name);
  out.append("\", \"tracks\": [");
  for (std::size_t k = 0; k < order.size(); ++k) {
    const tracker::Track3D& track = frame.tracks[order[k]];
    if (k > 0) out.append(", ");
    out.append("{\"id\": ");
    AppendInt(track.id, &out);
    out.append(", \"joints\": [");
    for (std::size_t j = 0; j < track.joints.size(); ++j) {
      if (j > 0) out.append(", ");
      const std::optional<Vec3>& joint = track.joints[j];
      if (joint && AllFinite(*joint)) {
        AppendPoint(*joint, &out);
      } else {
        out.append("null");
      }
    }
    out.append("], \"position\": ");
    if (AllFinite(track.position)) {
      AppendPoint(track.position, &out);
    } else {
      out.append("null");
    }
    out.push_back('}');
  }
  out.append("], \"utime\": ");
  AppendInt(frame.utime, &out);
  out.append("}\n");
  return out;
}

std::optional<tracker::Frame3D> ParseTracksJsonLine(std::string_view line,
                                                    core::KeypointLayoutId* layout,
                                                    std::string* why) {
  Parser p(line);
  tracker::Frame3D frame;
  core::KeypointLayoutId parsed_layout = core::KeypointLayoutId::kNone;
  bool has_frame = false, has_layout = false, has_tracks = false, has_utime = false;
  auto fail = [&](const std::string& message) -> std::optional<tracker::Frame3D> {
    if (why != nullptr) *why = message;
    return std::nullopt;
  };
  const bool ok = ParseObject(&p, "the line", [&](const std::string& key) {
    if (key == "frame") {
      has_frame = true;
      return p.ParseInt64("frame", &frame.frame);
    }
    if (key == "utime") {
      has_utime = true;
      return p.ParseInt64("utime", &frame.utime);
    }
    if (key == "layout") {
      has_layout = true;
      std::string name;
      if (!p.ParseString(&name)) return false;
      const std::optional<core::KeypointLayoutId> id = core::KeypointLayoutFromName(name);
      if (!id) return p.Fail("unknown layout \"" + name + "\"");
      parsed_layout = *id;
      return true;
    }
    if (key == "tracks") {
      has_tracks = true;
      return ParseArray(&p, "tracks", [&](std::size_t index) {
        frame.tracks.emplace_back();
        return ParseTrack(&p, index, &frame.tracks.back());
      });
    }
    return p.Fail("unknown key \"" + key + "\"");
  });
  if (!ok) return fail(p.error());
  if (!p.AtEnd()) {
    p.Fail("unexpected text after the closing '}'");
    return fail(p.error());
  }
  if (!has_frame) return fail("missing key \"frame\"");
  if (!has_layout) return fail("missing key \"layout\"");
  if (!has_tracks) return fail("missing key \"tracks\"");
  if (!has_utime) return fail("missing key \"utime\"");

  const std::size_t layout_joints =
      static_cast<std::size_t>(core::GetKeypointLayout(parsed_layout).num_joints());
  for (const tracker::Track3D& track : frame.tracks) {
    if (!track.joints.empty() && track.joints.size() != layout_joints) {
      return fail("track id " + std::to_string(track.id) + " has " +
                  std::to_string(track.joints.size()) + " joints; layout \"" +
                  core::GetKeypointLayout(parsed_layout).name + "\" needs 0 or " +
                  std::to_string(layout_joints));
    }
  }
  std::stable_sort(
      frame.tracks.begin(), frame.tracks.end(),
      [](const tracker::Track3D& a, const tracker::Track3D& b) { return a.id < b.id; });
  for (std::size_t i = 1; i < frame.tracks.size(); ++i) {
    if (frame.tracks[i].id == frame.tracks[i - 1].id) {
      return fail("duplicate track id " + std::to_string(frame.tracks[i].id));
    }
  }
  if (layout != nullptr) *layout = parsed_layout;
  return frame;
}

}  // namespace mvtrack::transport
