#include "transport/tracks_jsonl.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <system_error>
#include <vector>

#include "json/json.h"

namespace mvtrack::transport {
namespace {

// Nesting of the format: line, tracks, track, joints, joint.
constexpr int kMaxDepth = 5;

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
  const auto [end, ec] = std::to_chars(buffer.data(),
                                       buffer.data() + buffer.size(),
                                       value,
                                       std::chars_format::fixed,
                                       kTracksJsonDecimals);
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
// Parsing: lib/json's reader, then this schema.

// "[x, y, z]" with three numbers. The key path (`base`.`key`, with [index] when index >= 0) is
// built only to report a failure.
bool GetPoint(json::Checker* c,
              const json::Value& v,
              const std::string& base,
              const char* key,
              long index,
              Vec3* point) {
  if (v.kind == json::Value::Kind::kArray && v.items.size() == 3 &&
      v.items[0].kind == json::Value::Kind::kNumber &&
      v.items[1].kind == json::Value::Kind::kNumber &&
      v.items[2].kind == json::Value::Kind::kNumber) {
    *point = Vec3(v.items[0].real, v.items[1].real, v.items[2].real);
    return true;
  }
  std::string path = json::Checker::Join(base, key);
  if (index >= 0) path = json::Checker::Index(path, static_cast<std::size_t>(index));
  if (!c->ExpectArray(v, path, 3, 0, "[x, y, z]")) return false;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!c->GetDouble(v.items[i], json::Checker::Index(path, i), &(*point)[static_cast<int>(i)])) {
      return false;
    }
  }
  return true;
}

bool GetTrack(json::Checker* c,
              const json::Value& v,
              const std::string& path,
              tracker::Track3D* track) {
  std::map<std::string, const json::Value*> m;
  if (!c->Members(v,
                  path,
                  {"bone_lengths", "id", "joints", "position", "zones"},
                  {"id", "joints", "position"},
                  &m)) {
    return false;
  }
  const json::Value& id = *m.at("id");
  if (!c->GetInt(id,
                 json::Checker::Join(path, "id"),
                 std::numeric_limits<std::int64_t>::min(),
                 std::numeric_limits<std::int64_t>::max(),
                 &track->id)) {
    return false;
  }
  const json::Value& position = *m.at("position");
  if (position.kind == json::Value::Kind::kNull) {
    track->position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  } else if (!GetPoint(c, position, path, "position", -1, &track->position)) {
    return false;
  }
  const json::Value& joints = *m.at("joints");
  if (joints.kind != json::Value::Kind::kArray) {
    return c->ExpectKind(joints, json::Checker::Join(path, "joints"), json::Value::Kind::kArray);
  }
  track->joints.reserve(joints.items.size());
  for (std::size_t j = 0; j < joints.items.size(); ++j) {
    const json::Value& joint = joints.items[j];
    if (joint.kind == json::Value::Kind::kNull) {
      track->joints.emplace_back(std::nullopt);
      continue;
    }
    Vec3 point;
    if (!GetPoint(c, joint, path, "joints", static_cast<long>(j), &point)) return false;
    track->joints.emplace_back(point);
  }
  if (const auto bones = m.find("bone_lengths"); bones != m.end()) {
    const std::string bones_path = json::Checker::Join(path, "bone_lengths");
    if (bones->second->kind != json::Value::Kind::kArray) {
      return c->ExpectKind(*bones->second, bones_path, json::Value::Kind::kArray);
    }
    for (std::size_t b = 0; b < bones->second->items.size(); ++b) {
      double length = 0.0;
      if (!c->GetDouble(bones->second->items[b], json::Checker::Index(bones_path, b), &length)) {
        return false;
      }
      track->bone_lengths.push_back(length);
    }
  }
  if (const auto zones = m.find("zones"); zones != m.end()) {
    const std::string zones_path = json::Checker::Join(path, "zones");
    if (zones->second->kind != json::Value::Kind::kArray) {
      return c->ExpectKind(*zones->second, zones_path, json::Value::Kind::kArray);
    }
    for (std::size_t z = 0; z < zones->second->items.size(); ++z) {
      std::int64_t zone = 0;
      if (!c->GetInt(zones->second->items[z],
                     json::Checker::Index(zones_path, z),
                     0,
                     std::numeric_limits<std::int16_t>::max(),
                     &zone)) {
        return false;
      }
      track->zones.push_back(static_cast<int>(zone));
    }
  }
  return true;
}

// "column C: PATH: REASON" (no path for a syntax error or a key of the line itself).
std::string Describe(const json::Error& e) {
  std::string out = "column " + std::to_string(e.column) + ": ";
  if (!e.path.empty()) out += e.path + ": ";
  return out + e.reason;
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
    out.push_back('{');
    if (!track.bone_lengths.empty()) {
      out.append("\"bone_lengths\": [");
      for (std::size_t b = 0; b < track.bone_lengths.size(); ++b) {
        if (b > 0) out.append(", ");
        AppendFixed(std::isfinite(track.bone_lengths[b]) ? track.bone_lengths[b] : 0.0, &out);
      }
      out.append("], ");
    }
    out.append("\"id\": ");
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
    if (!track.zones.empty()) {
      out.append(", \"zones\": [");
      for (std::size_t z = 0; z < track.zones.size(); ++z) {
        if (z > 0) out.append(", ");
        AppendInt(track.zones[z], &out);
      }
      out.push_back(']');
    }
    out.push_back('}');
  }
  out.append("], \"utime\": ");
  AppendInt(frame.utime, &out);
  if (!frame.zones.empty()) {
    out.append(", \"zones\": [");
    for (std::size_t z = 0; z < frame.zones.size(); ++z) {
      if (z > 0) out.append(", ");
      json::AppendQuoted(frame.zones[z], &out);
    }
    out.push_back(']');
  }
  out.append("}\n");
  return out;
}

std::optional<tracker::Frame3D> ParseTracksJsonLine(std::string_view line,
                                                    core::KeypointLayoutId* layout,
                                                    std::string* why) {
  auto fail = [&](const std::string& message) -> std::optional<tracker::Frame3D> {
    if (why != nullptr) *why = message;
    return std::nullopt;
  };
  json::Error error;
  const std::optional<json::Value> root = json::Parse(line, kMaxDepth, &error);
  if (!root.has_value()) return fail(Describe(error));
  json::Checker c;
  std::map<std::string, const json::Value*> m;
  const std::vector<std::string_view> keys = {"frame", "layout", "tracks", "utime", "zones"};
  const std::vector<std::string_view> required = {"frame", "layout", "tracks", "utime"};
  if (root->kind != json::Value::Kind::kObject) {
    c.Fail(*root,
           "",
           std::string("a line must be a JSON object, found ") + json::KindName(root->kind));
    return fail(Describe(c.error()));
  }
  if (!c.Members(*root, "", keys, required, &m)) return fail(Describe(c.error()));
  tracker::Frame3D frame;
  constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  if (!c.GetInt(*m.at("frame"), "frame", kMin, kMax, &frame.frame) ||
      !c.GetInt(*m.at("utime"), "utime", kMin, kMax, &frame.utime)) {
    return fail(Describe(c.error()));
  }
  std::string name;
  if (!c.GetString(*m.at("layout"), "layout", &name)) return fail(Describe(c.error()));
  const std::optional<core::KeypointLayoutId> parsed_layout = core::KeypointLayoutFromName(name);
  if (!parsed_layout) {
    c.Fail(*m.at("layout"), "layout", "unknown layout \"" + name + "\"");
    return fail(Describe(c.error()));
  }
  if (const auto zones = m.find("zones"); zones != m.end()) {
    if (!c.ExpectKind(*zones->second, "zones", json::Value::Kind::kArray)) {
      return fail(Describe(c.error()));
    }
    for (std::size_t z = 0; z < zones->second->items.size(); ++z) {
      std::string zone;
      if (!c.GetString(zones->second->items[z], json::Checker::Index("zones", z), &zone)) {
        return fail(Describe(c.error()));
      }
      if (zone.empty()) return fail("zones[" + std::to_string(z) + "] is an empty zone name");
      frame.zones.push_back(std::move(zone));
    }
  }
  const json::Value& tracks = *m.at("tracks");
  if (!c.ExpectKind(tracks, "tracks", json::Value::Kind::kArray)) return fail(Describe(c.error()));
  frame.tracks.resize(tracks.items.size());
  for (std::size_t i = 0; i < tracks.items.size(); ++i) {
    if (!GetTrack(&c, tracks.items[i], json::Checker::Index("tracks", i), &frame.tracks[i])) {
      return fail(Describe(c.error()));
    }
  }

  const std::size_t layout_joints =
      static_cast<std::size_t>(core::GetKeypointLayout(*parsed_layout).num_joints());
  for (const tracker::Track3D& track : frame.tracks) {
    if (!track.joints.empty() && track.joints.size() != layout_joints) {
      return fail("track id " + std::to_string(track.id) + " has " +
                  std::to_string(track.joints.size()) + " joints; layout \"" +
                  core::GetKeypointLayout(*parsed_layout).name + "\" needs 0 or " +
                  std::to_string(layout_joints));
    }
  }
  for (const tracker::Track3D& track : frame.tracks) {
    for (std::size_t z = 0; z < track.zones.size(); ++z) {
      if (static_cast<std::size_t>(track.zones[z]) >= frame.zones.size() ||
          (z > 0 && track.zones[z] <= track.zones[z - 1])) {
        return fail("track id " + std::to_string(track.id) +
                    ": zones must be ascending indices of the line's " +
                    std::to_string(frame.zones.size()) + " zones");
      }
    }
  }
  if (const std::optional<TrackId3D> twice = tracker::SortTracksById(&frame)) {
    return fail("duplicate track id " + std::to_string(*twice));
  }
  if (layout != nullptr) *layout = *parsed_layout;
  return frame;
}

}  // namespace mvtrack::transport
