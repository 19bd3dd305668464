#include "eval/pcp.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "core/check.h"
#include "eval/number_format.h"

namespace mvtrack::eval {
namespace {

using internal::kNaN;
using internal::Ratio;

bool Fail(std::string* why, const std::string& text) {
  if (why != nullptr) *why = text;
  return false;
}

// The endpoint sum_k w_k x_{j_k}; std::nullopt when a joint it needs is missing.
std::optional<Vec3> Endpoint(const std::vector<WeightedJoint>& terms,
                             const std::vector<std::optional<Vec3>>& joints) {
  Vec3 sum = Vec3::Zero();
  for (const WeightedJoint& t : terms) {
    const auto& joint = joints[static_cast<std::size_t>(t.joint)];
    if (!joint.has_value()) return std::nullopt;
    sum += t.weight * *joint;
  }
  return sum;
}

int ShelfJoint(const core::KeypointLayout& layout, std::string_view name) {
  const int j = core::JointIndex(layout, name);
  MVTRACK_CHECK_MSG(j >= 0, "shelf14 layout lacks a joint the PCP parts need");
  return j;
}

// Mean of the defined values; NaN when there is none.
double MeanOfDefined(const std::vector<double>& values) {
  double sum = 0.0;
  int count = 0;
  for (const double v : values) {
    if (std::isnan(v)) continue;
    sum += v;
    ++count;
  }
  return count == 0 ? kNaN : sum / static_cast<double>(count);
}

std::string DescribeEndpoint(const std::vector<WeightedJoint>& terms) {
  if (terms.size() == 1 && terms.front().weight == 1.0) return std::to_string(terms.front().joint);
  std::string text = "(";
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (k > 0) text += " + ";
    text += internal::FormatFixed(terms[k].weight, 2) + "*" + std::to_string(terms[k].joint);
  }
  return text + ")";
}

std::string Protocol(const PcpProtocol& protocol,
                     const PcpOptions& options,
                     const std::vector<std::int64_t>& actors,
                     std::int64_t num_frames) {
  std::string text;
  text += "PCP (Belagiannis et al. 2014, as evaluated by MVPose/VoxelPose/4D Association): per GT ";
  text += "actor and frame the prediction with the smallest mean error over joints valid in both ";
  text += "is selected (no identities); a part is correct iff (|p_a - g_a| + |p_b - g_b|) / 2 <= ";
  text += internal::FormatFixed(options.alpha, 2) + " * |g_a - g_b|; no selectable prediction: ";
  text += "every part wrong; a missing predicted endpoint: part wrong; a missing GT endpoint: ";
  text += "part not scored. Actor PCP = correct / scored parts over its frames; average = mean ";
  text += "over scored actors. Parts (" + protocol.name + "): ";
  for (std::size_t b = 0; b < protocol.bones.size(); ++b) {
    if (b > 0) text += ", ";
    const PcpBone& bone = protocol.bones[b];
    text += bone.name + " " + DescribeEndpoint(bone.a) + "-" + DescribeEndpoint(bone.b);
  }
  text += ". Actors: ";
  if (actors.empty()) text += "none";
  for (std::size_t k = 0; k < actors.size(); ++k) {
    if (k > 0) text += ", ";
    text += std::to_string(actors[k]);
  }
  text += options.actor_ids.empty() ? " (all GT ids)" : "";
  text += ". Frames: " + DescribeFrameRanges(options.frame_ranges) + " (" +
          std::to_string(num_frames) + " GT frames scored). Recall: selected mean error < " +
          internal::FormatFixed(options.recall_threshold_m, 3) + " m.";
  return text;
}

}  // namespace

PcpBone PcpBone::Between(std::string name, int joint_a, int joint_b) {
  PcpBone bone;
  bone.name = std::move(name);
  bone.a = {{joint_a, 1.0}};
  bone.b = {{joint_b, 1.0}};
  return bone;
}

bool PcpProtocol::Validate(int num_joints, std::string* why) const {
  if (bones.empty()) return Fail(why, "PCP protocol '" + name + "' has no bones");
  for (std::size_t b = 0; b < bones.size(); ++b) {
    const std::string at = "PCP bone " + std::to_string(b) + " (" + bones[b].name + ")";
    for (const auto* endpoint : {&bones[b].a, &bones[b].b}) {
      if (endpoint->empty()) return Fail(why, at + ": empty endpoint");
      double sum = 0.0;
      for (const WeightedJoint& t : *endpoint) {
        if (t.joint < 0 || t.joint >= num_joints) {
          return Fail(why,
                      at + ": joint " + std::to_string(t.joint) + " outside [0, " +
                          std::to_string(num_joints) + ")");
        }
        if (!std::isfinite(t.weight)) return Fail(why, at + ": non-finite weight");
        sum += t.weight;
      }
      if (std::abs(sum - 1.0) > 1e-9) return Fail(why, at + ": endpoint weights do not sum to 1");
    }
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (const int b : groups[g].bones) {
      if (b < 0 || static_cast<std::size_t>(b) >= bones.size()) {
        return Fail(why,
                    "PCP group " + std::to_string(g) + " (" + groups[g].name + "): bone index " +
                        std::to_string(b) + " out of range");
      }
    }
  }
  return true;
}

PcpProtocol ShelfCampusPcpProtocol() {
  const core::KeypointLayout& layout = core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
  const auto j = [&layout](const char* name) { return ShelfJoint(layout, name); };
  PcpProtocol protocol;
  protocol.name = "shelf_campus";
  protocol.bones = {
      PcpBone::Between("r_lower_leg", j("r_ankle"), j("r_knee")),
      PcpBone::Between("r_upper_leg", j("r_knee"), j("r_hip")),
      PcpBone::Between("l_upper_leg", j("l_hip"), j("l_knee")),
      PcpBone::Between("l_lower_leg", j("l_knee"), j("l_ankle")),
      PcpBone::Between("r_lower_arm", j("r_wrist"), j("r_elbow")),
      PcpBone::Between("r_upper_arm", j("r_elbow"), j("r_shoulder")),
      PcpBone::Between("l_upper_arm", j("l_shoulder"), j("l_elbow")),
      PcpBone::Between("l_lower_arm", j("l_elbow"), j("l_wrist")),
      PcpBone::Between("head", j("head_bottom"), j("head_top")),
  };
  PcpBone torso;
  torso.name = "torso";
  torso.a = {{j("l_hip"), 0.5}, {j("r_hip"), 0.5}};
  torso.b = {{j("head_bottom"), 1.0}};
  protocol.bones.push_back(torso);
  protocol.groups = {{"head", {8}},
                     {"torso", {9}},
                     {"upper_arms", {5, 6}},
                     {"lower_arms", {4, 7}},
                     {"upper_legs", {1, 2}},
                     {"lower_legs", {0, 3}}};
  return protocol;
}

PcpProtocol LayoutPcpProtocol(core::KeypointLayoutId layout_id) {
  const core::KeypointLayout& layout = core::GetKeypointLayout(layout_id);
  PcpProtocol protocol;
  protocol.name = layout.name;
  for (const auto& [a, b] : layout.bones) {
    const std::string& name_a = layout.joints[static_cast<std::size_t>(a)];
    const std::string& name_b = layout.joints[static_cast<std::size_t>(b)];
    protocol.bones.push_back(PcpBone::Between(name_a + "-" + name_b, a, b));
  }
  return protocol;
}

bool PcpOptions::Validate(std::string* why) const {
  if (!std::isfinite(alpha) || alpha <= 0.0) return Fail(why, "PCP alpha must be finite and > 0");
  if (!std::isfinite(recall_threshold_m) || recall_threshold_m <= 0.0) {
    return Fail(why, "PCP recall_threshold_m must be finite and > 0");
  }
  std::set<std::int64_t> unique(actor_ids.begin(), actor_ids.end());
  if (unique.size() != actor_ids.size()) return Fail(why, "PCP actor_ids has duplicates");
  return ValidateFrameRanges(frame_ranges, why);
}

PcpResult EvaluatePcp(const EvalSequence& ground_truth,
                      const EvalSequence& predictions,
                      const PcpProtocol& protocol,
                      const PcpOptions& options) {
  PcpResult result;
  result.alpha = options.alpha;
  result.frame_ranges = options.frame_ranges;
  if (!options.Validate(&result.error)) return result;
  int num_joints = 0;
  if (!ValidateSequencePair(ground_truth, predictions, &result.error, &num_joints)) return result;
  const auto has_objects = [](const EvalSequence& s) {
    return std::any_of(s.begin(), s.end(), [](const EvalFrame& f) { return !f.objects.empty(); });
  };
  // Without any object the joint count is unknown: check only the protocol's own structure.
  const int joints_for_check = has_objects(ground_truth) || has_objects(predictions)
                                   ? num_joints
                                   : std::numeric_limits<int>::max();
  if (!protocol.Validate(joints_for_check, &result.error)) {
    result.error += " (the sequences have " + std::to_string(num_joints) + " joints per object)";
    return result;
  }

  const std::size_t num_bones = protocol.bones.size();
  const std::size_t num_groups = protocol.groups.size();
  for (const PcpBone& bone : protocol.bones) result.bone_names.push_back(bone.name);
  for (const PcpBoneGroup& group : protocol.groups) result.group_names.push_back(group.name);

  // Frames in range, in increasing order; predictions of each frame by frame index.
  std::map<FrameIndex, const EvalFrame*> gt_frames;
  for (const EvalFrame& f : ground_truth) {
    if (InFrameRanges(f.frame, options.frame_ranges)) gt_frames[f.frame] = &f;
  }
  std::map<FrameIndex, const EvalFrame*> pred_frames;
  for (const EvalFrame& f : predictions) pred_frames[f.frame] = &f;

  // Actors scored, in report order.
  std::vector<std::int64_t> actor_ids = options.actor_ids;
  if (actor_ids.empty()) {
    std::set<std::int64_t> ids;
    for (const auto& [index, frame] : gt_frames) {
      for (const EvalObject& o : frame->objects) ids.insert(o.id);
    }
    actor_ids.assign(ids.begin(), ids.end());
  }
  std::map<std::int64_t, std::size_t> slot;
  result.actors.resize(actor_ids.size());
  for (std::size_t k = 0; k < actor_ids.size(); ++k) {
    slot[actor_ids[k]] = k;
    PcpActorResult& actor = result.actors[k];
    actor.actor_id = actor_ids[k];
    actor.bone_correct.assign(num_bones, 0);
    actor.bone_total.assign(num_bones, 0);
  }

  std::int64_t frames_scored = 0;
  for (const auto& [index, gt_frame] : gt_frames) {
    // Predictions of this frame sorted by id, so that selection ties go to the lowest id.
    std::vector<const EvalObject*> candidates;
    if (const auto it = pred_frames.find(index); it != pred_frames.end()) {
      for (const EvalObject& p : it->second->objects) candidates.push_back(&p);
    }
    std::sort(candidates.begin(), candidates.end(), [](const EvalObject* a, const EvalObject* b) {
      return a->id < b->id;
    });

    bool scored_any = false;
    for (const EvalObject& gt : gt_frame->objects) {
      const auto s = slot.find(gt.id);
      if (s == slot.end()) continue;
      scored_any = true;
      PcpActorResult& actor = result.actors[s->second];
      ++actor.num_frames;
      ++result.recall_total;

      const EvalObject* selected = nullptr;
      double best = std::numeric_limits<double>::infinity();
      for (const EvalObject* p : candidates) {
        const std::optional<double> e = MeanJointDistance(gt, *p);
        if (e.has_value() && *e < best) {
          best = *e;
          selected = p;
        }
      }
      if (selected == nullptr) {
        ++actor.num_frames_without_prediction;
      } else if (best < options.recall_threshold_m) {
        ++result.recall_matched;
      }

      for (std::size_t b = 0; b < num_bones; ++b) {
        const PcpBone& bone = protocol.bones[b];
        const std::optional<Vec3> ga = Endpoint(bone.a, gt.joints);
        const std::optional<Vec3> gb = Endpoint(bone.b, gt.joints);
        if (!ga.has_value() || !gb.has_value()) continue;  // not scorable
        ++actor.bone_total[b];
        if (selected == nullptr) continue;
        const std::optional<Vec3> pa = Endpoint(bone.a, selected->joints);
        const std::optional<Vec3> pb = Endpoint(bone.b, selected->joints);
        if (!pa.has_value() || !pb.has_value()) continue;
        const double error = ((*pa - *ga).norm() + (*pb - *gb).norm()) / 2.0;
        if (error <= options.alpha * (*ga - *gb).norm()) ++actor.bone_correct[b];
      }
    }
    if (scored_any) ++frames_scored;
  }

  std::vector<double> actor_pcps;
  std::vector<std::vector<double>> group_values(num_groups);
  for (PcpActorResult& actor : result.actors) {
    for (std::size_t b = 0; b < num_bones; ++b) {
      actor.correct_parts += actor.bone_correct[b];
      actor.total_parts += actor.bone_total[b];
    }
    actor.pcp = Ratio(actor.correct_parts, actor.total_parts);
    actor_pcps.push_back(actor.pcp);
    actor.group_pcp.assign(num_groups, kNaN);
    for (std::size_t g = 0; g < num_groups; ++g) {
      std::int64_t correct = 0;
      std::int64_t total = 0;
      for (const int b : protocol.groups[g].bones) {
        correct += actor.bone_correct[static_cast<std::size_t>(b)];
        total += actor.bone_total[static_cast<std::size_t>(b)];
      }
      actor.group_pcp[g] = Ratio(correct, total);
      group_values[g].push_back(actor.group_pcp[g]);
    }
  }
  result.average_pcp = MeanOfDefined(actor_pcps);
  result.average_group_pcp.resize(num_groups);
  for (std::size_t g = 0; g < num_groups; ++g) {
    result.average_group_pcp[g] = MeanOfDefined(group_values[g]);
  }
  result.recall = Ratio(result.recall_matched, result.recall_total);
  result.protocol = Protocol(protocol, options, actor_ids, frames_scored);
  result.valid = true;
  return result;
}

}  // namespace mvtrack::eval
