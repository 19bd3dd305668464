#pragma once
// Bit-exact comparison of tracker outputs (test support only): every field of every Frame3D,
// doubles compared by their bit patterns.

#include <bit>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "tracker/tracker.h"

namespace mvtrack::testing {

inline bool SameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline bool SameBits(const Vec3& a, const Vec3& b) {
  return SameBits(a.x(), b.x()) && SameBits(a.y(), b.y()) && SameBits(a.z(), b.z());
}

/// Empty when `a` and `b` are identical in every field (bit-exact), else the first difference.
inline std::string FirstDifference(const std::vector<tracker::Frame3D>& a,
                                   const std::vector<tracker::Frame3D>& b) {
  std::ostringstream os;
  if (a.size() != b.size()) {
    os << "frame count " << a.size() << " vs " << b.size();
    return os.str();
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    const tracker::Frame3D& fa = a[i];
    const tracker::Frame3D& fb = b[i];
    os << "output " << i << " (frame " << fa.frame << "): ";
    if (fa.frame != fb.frame) return os.str() + "frame index differs";
    if (fa.utime != fb.utime) return os.str() + "utime differs";
    if (fa.tracks.size() != fb.tracks.size()) return os.str() + "track count differs";
    for (std::size_t k = 0; k < fa.tracks.size(); ++k) {
      const tracker::Track3D& ta = fa.tracks[k];
      const tracker::Track3D& tb = fb.tracks[k];
      os << "track " << k << ": ";
      if (ta.id != tb.id) return os.str() + "id differs";
      if (!SameBits(ta.position, tb.position)) return os.str() + "position differs";
      if (!SameBits(ta.confidence, tb.confidence)) return os.str() + "confidence differs";
      if (ta.cameras != tb.cameras) return os.str() + "cameras differ";
      if (ta.age_frames != tb.age_frames) return os.str() + "age differs";
      if (ta.state != tb.state) return os.str() + "state differs";
      if (ta.joints.size() != tb.joints.size()) return os.str() + "joint count differs";
      for (std::size_t j = 0; j < ta.joints.size(); ++j) {
        if (ta.joints[j].has_value() != tb.joints[j].has_value()) {
          return os.str() + "joint presence differs";
        }
        if (ta.joints[j] && !SameBits(*ta.joints[j], *tb.joints[j])) {
          return os.str() + "joint " + std::to_string(j) + " differs";
        }
      }
    }
    os.str("");
  }
  return "";
}

/// Empty when every counter of `a` and `b` is equal, else the first difference.
inline std::string StatsDifference(const tracker::TrackerStats& a, const tracker::TrackerStats& b) {
  auto field = [](const char* name, std::int64_t x, std::int64_t y) {
    return x == y ? std::string()
                  : std::string(name) + " " + std::to_string(x) + " vs " + std::to_string(y);
  };
  for (const std::string& d :
       {field("camera_frames_accepted", a.camera_frames_accepted, b.camera_frames_accepted),
        field("camera_frames_rejected", a.camera_frames_rejected, b.camera_frames_rejected),
        field("detections_used", a.detections_used, b.detections_used),
        field("detections_rejected", a.detections_rejected, b.detections_rejected),
        field("detections_repaired", a.detections_repaired, b.detections_repaired),
        field("detections_filtered", a.detections_filtered, b.detections_filtered),
        field("frames_finalized", a.frames_finalized, b.frames_finalized),
        field("windows_processed", a.windows_processed, b.windows_processed),
        field("reanchors", a.reanchors, b.reanchors),
        field("tracks_born", a.tracks_born, b.tracks_born)}) {
    if (!d.empty()) return d;
  }
  if (a.rejections != b.rejections) return "rejections by reason differ";
  return "";
}

}  // namespace mvtrack::testing
