#include "eval/sequence.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <set>
#include <utility>

namespace mvtrack::eval {
namespace {

void SetWhy(std::string* why, const std::string& text) {
  if (why != nullptr) *why = text;
}

bool IsFinite(const Vec3& v) { return v.allFinite(); }

}  // namespace

bool InFrameRanges(FrameIndex frame, const std::vector<FrameRange>& ranges) {
  if (ranges.empty()) return true;
  for (const FrameRange& r : ranges) {
    if (frame >= r.first && frame <= r.last) return true;
  }
  return false;
}

std::string DescribeFrameRanges(const std::vector<FrameRange>& ranges) {
  if (ranges.empty()) return "all";
  std::string text;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (i > 0) text += " + ";
    text += "[" + std::to_string(ranges[i].first) + ", " + std::to_string(ranges[i].last) + "]";
  }
  return text;
}

bool ValidateFrameRanges(const std::vector<FrameRange>& ranges, std::string* why) {
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (ranges[i].first > ranges[i].last) {
      SetWhy(why,
             "frame range " + std::to_string(i) + " has first > last (" +
                 std::to_string(ranges[i].first) + " > " + std::to_string(ranges[i].last) + ")");
      return false;
    }
  }
  return true;
}

bool ValidateSequence(const EvalSequence& sequence, const std::string& name, std::string* why) {
  std::set<FrameIndex> frames;
  std::optional<std::size_t> num_joints;
  for (const EvalFrame& frame : sequence) {
    const std::string where = name + ", frame " + std::to_string(frame.frame);
    if (!frames.insert(frame.frame).second) {
      SetWhy(why, where + ": frame index appears more than once");
      return false;
    }
    std::set<std::int64_t> ids;
    for (const EvalObject& object : frame.objects) {
      const std::string at = where + ", id " + std::to_string(object.id);
      if (!ids.insert(object.id).second) {
        SetWhy(why, at + ": id appears more than once in the frame");
        return false;
      }
      if (!IsFinite(object.position)) {
        SetWhy(why, at + ": position is not finite");
        return false;
      }
      for (std::size_t j = 0; j < object.joints.size(); ++j) {
        if (object.joints[j].has_value() && !IsFinite(*object.joints[j])) {
          SetWhy(why, at + ": joint " + std::to_string(j) + " is not finite");
          return false;
        }
      }
      if (!num_joints.has_value()) {
        num_joints = object.joints.size();
      } else if (*num_joints != object.joints.size()) {
        SetWhy(why,
               at + ": has " + std::to_string(object.joints.size()) + " joints, expected " +
                   std::to_string(*num_joints) + " as for the first object");
        return false;
      }
    }
  }
  return true;
}

bool ValidateSequencePair(const EvalSequence& ground_truth,
                          const EvalSequence& predictions,
                          std::string* why,
                          int* num_joints) {
  if (!ValidateSequence(ground_truth, "ground truth", why)) return false;
  if (!ValidateSequence(predictions, "predictions", why)) return false;
  const auto first_count = [](const EvalSequence& s) -> std::optional<std::size_t> {
    for (const EvalFrame& f : s) {
      if (!f.objects.empty()) return f.objects.front().joints.size();
    }
    return std::nullopt;
  };
  const std::optional<std::size_t> gt_joints = first_count(ground_truth);
  const std::optional<std::size_t> pred_joints = first_count(predictions);
  if (gt_joints.has_value() && pred_joints.has_value() && *gt_joints != *pred_joints) {
    SetWhy(why,
           "ground truth has " + std::to_string(*gt_joints) + " joints per object, predictions " +
               std::to_string(*pred_joints) +
               " (map both to one layout with core::MakeKeypointMapping first)");
    return false;
  }
  if (num_joints != nullptr) {
    *num_joints = static_cast<int>(gt_joints.value_or(pred_joints.value_or(0)));
  }
  return true;
}

const char* DistanceKindName(DistanceKind kind) {
  switch (kind) {
    case DistanceKind::kFootprint:
      return "footprint_xy";
    case DistanceKind::kMeanJoint:
      return "mean_joint";
  }
  return "unknown";
}

double FootprintDistance(const EvalObject& a, const EvalObject& b) {
  return (a.position.head<2>() - b.position.head<2>()).norm();
}

std::optional<double> MeanJointDistance(const EvalObject& a, const EvalObject& b) {
  const std::size_t n = std::min(a.joints.size(), b.joints.size());
  double sum = 0.0;
  int count = 0;
  for (std::size_t j = 0; j < n; ++j) {
    if (!a.joints[j].has_value() || !b.joints[j].has_value()) continue;
    sum += (*a.joints[j] - *b.joints[j]).norm();
    ++count;
  }
  if (count == 0) return std::nullopt;
  return sum / static_cast<double>(count);
}

std::optional<double> ObjectDistance(DistanceKind kind, const EvalObject& a, const EvalObject& b) {
  if (kind == DistanceKind::kFootprint) return FootprintDistance(a, b);
  return MeanJointDistance(a, b);
}

namespace {

std::vector<const EvalObject*> SortedById(const EvalFrame* frame) {
  std::vector<const EvalObject*> objects;
  if (frame == nullptr) return objects;
  objects.reserve(frame->objects.size());
  for (const EvalObject& o : frame->objects) objects.push_back(&o);
  std::sort(objects.begin(), objects.end(), [](const EvalObject* a, const EvalObject* b) {
    return a->id < b->id;
  });
  return objects;
}

}  // namespace

std::vector<AlignedFrame> AlignFrames(const EvalSequence& ground_truth,
                                      const EvalSequence& predictions,
                                      const std::vector<FrameRange>& ranges) {
  std::map<FrameIndex, std::pair<const EvalFrame*, const EvalFrame*>> by_frame;
  for (const EvalFrame& f : ground_truth) {
    if (InFrameRanges(f.frame, ranges)) by_frame[f.frame].first = &f;
  }
  for (const EvalFrame& f : predictions) {
    if (InFrameRanges(f.frame, ranges)) by_frame[f.frame].second = &f;
  }
  std::vector<AlignedFrame> frames;
  frames.reserve(by_frame.size());
  for (const auto& [index, sides] : by_frame) {
    frames.push_back({index, SortedById(sides.first), SortedById(sides.second)});
  }
  return frames;
}

}  // namespace mvtrack::eval
