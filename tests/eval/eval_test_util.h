#pragma once
/// @file
/// Small builders for hand-made evaluation sequences used by the eval tests.

#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <vector>

#include "eval/sequence.h"

namespace mvtrack::eval::testing {

/// An object with footprint (x, y, z) and no joints.
inline EvalObject At(std::int64_t id, double x, double y, double z = 0.0) {
  EvalObject o;
  o.id = id;
  o.position = Vec3(x, y, z);
  return o;
}

/// Builds a sequence from (frame -> objects); frames without objects are left out.
inline EvalSequence Sequence(const std::map<FrameIndex, std::vector<EvalObject>>& frames) {
  EvalSequence s;
  for (const auto& [frame, objects] : frames) s.push_back({frame, objects});
  return s;
}

/// Appends `object` to frame `frame` of `sequence` (creating the frame if needed).
inline void Add(EvalSequence* sequence, FrameIndex frame, const EvalObject& object) {
  for (EvalFrame& f : *sequence) {
    if (f.frame == frame) {
      f.objects.push_back(object);
      return;
    }
  }
  sequence->push_back({frame, {object}});
}

}  // namespace mvtrack::eval::testing
