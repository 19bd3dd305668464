// mvtrack eval: scores a track output against ground truth (CLEAR MOT, identity F1, MPJPE and
// optionally PCP) with lib/eval. Both inputs are canonical tracks JSONL or LCM tracks logs
// (tracks_io.h); ground-truth actors are tracks whose ids are the actor ids.

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/keypoint_layout.h"
#include "eval/head_rule.h"
#include "eval/pcp.h"
#include "eval/point_comparison.h"
#include "eval/report.h"
#include "eval/sequence.h"
#include "eval/tracking_metrics.h"
#include "formats/tracks_io.h"
#include "mvtrack/cli.h"

namespace mvtrack::cli {
namespace {

std::vector<std::int64_t> ParseActors(const std::string& text) {
  std::vector<std::int64_t> ids;
  std::set<std::int64_t> seen;
  for (std::string_view part : SplitCommas(text)) {
    const std::optional<std::int64_t> id = ParseNonNegative(part);
    if (!id) throw UsageError("--actors: '" + std::string(part) + "' is not an actor id");
    if (!seen.insert(*id).second) {
      throw UsageError("--actors: actor " + std::to_string(*id) + " is listed twice");
    }
    ids.push_back(*id);
  }
  return ids;
}

// True when the file's tracks carry joints (or the file has no frames, so nothing to compare).
bool HasJoints(const formats::TrackFile& file) {
  return !file.layout || *file.layout != core::KeypointLayoutId::kNone;
}

// The frames of `file` as an evaluation sequence; joints dropped (`keep_joints` false), kept, or
// mapped with `mapping` (when not null; head_top then follows `head_rule` when the target is
// shelf14).
eval::EvalSequence ToSequence(const formats::TrackFile& file,
                              bool keep_joints,
                              const core::KeypointMapping* mapping,
                              eval::HeadRule head_rule) {
  eval::EvalSequence seq;
  seq.reserve(file.frames.size());
  std::vector<Vec3> points;
  std::vector<bool> valid;
  std::vector<Vec3> mapped_points;
  std::vector<bool> mapped_valid;
  for (const formats::TrackFileFrame& f : file.frames) {
    eval::EvalFrame ef;
    ef.frame = f.frame.frame;
    for (const tracker::Track3D& t : f.frame.tracks) {
      eval::EvalObject o;
      o.id = t.id;
      o.position = t.position;
      if (keep_joints && mapping == nullptr) {
        o.joints = t.joints;
      } else if (keep_joints) {
        points.assign(t.joints.size(), Vec3::Zero());
        valid.assign(t.joints.size(), false);
        for (std::size_t j = 0; j < t.joints.size(); ++j) {
          if (t.joints[j]) {
            points[j] = *t.joints[j];
            valid[j] = true;
          }
        }
        core::ApplyKeypointMapping(*mapping, points, valid, &mapped_points, &mapped_valid);
        o.joints.resize(mapped_points.size());
        for (std::size_t j = 0; j < mapped_points.size(); ++j) {
          if (mapped_valid[j]) o.joints[j] = mapped_points[j];
        }
        if (mapping->to == core::KeypointLayoutId::kShelf14) {
          eval::ApplyHeadRule(head_rule, mapping->from, t.joints, &o.joints);
        }
      }
      ef.objects.push_back(std::move(o));
    }
    seq.push_back(std::move(ef));
  }
  return seq;
}

// One line per target joint: "  neck          <- 0.5 left_shoulder + 0.5 right_shoulder".
std::string DescribeMapping(const core::KeypointMapping& mapping) {
  const core::KeypointLayout& from = core::GetKeypointLayout(mapping.from);
  const core::KeypointLayout& to = core::GetKeypointLayout(mapping.to);
  std::size_t width = 0;
  for (const std::string& name : to.joints) width = std::max(width, name.size());
  std::ostringstream os;
  int derivable = 0;
  for (std::size_t j = 0; j < mapping.targets.size(); ++j) {
    os << "  " << to.joints[j] << std::string(width - to.joints[j].size(), ' ') << " <- ";
    const std::vector<core::JointSource>& sources = mapping.targets[j];
    if (sources.empty()) {
      os << "not derivable (always missing)";
    } else {
      ++derivable;
      for (std::size_t k = 0; k < sources.size(); ++k) {
        const double w = sources[k].weight;
        if (k > 0) os << (w < 0.0 ? " - " : " + ");
        if (k == 0 && w < 0.0) os << "-";
        if (sources.size() > 1 || w != 1.0) os << std::abs(w) << " ";
        os << from.joints[static_cast<std::size_t>(sources[k].source_joint)];
      }
    }
    os << "\n";
  }
  return "  (" + std::to_string(derivable) + " of " + std::to_string(mapping.targets.size()) +
         " joints derivable)\n" + os.str();
}

// Writes `report` as JSON to the --json target (a file, or stdout for '-').
void WriteJsonReport(const Args& args, const eval::EvaluationReport& report) {
  const std::string json = eval::ReportToJson(report);
  if (args.Get("json") == "-") {
    std::cout << json << std::flush;
    if (!std::cout) throw std::runtime_error("stdout: write error");
    return;
  }
  std::ofstream file(args.Get("json"), std::ios::binary | std::ios::trunc);
  if (!file) throw std::runtime_error(args.Get("json") + ": cannot open for writing");
  file << json;
  file.close();
  if (!file) throw std::runtime_error(args.Get("json") + ": write error");
}

// eval --points: footprints of `pred` against the identity-free reference points of `gt`.
// "MIN_X,MAX_X,MIN_Y,MAX_Y" in metres.
eval::PointComparisonOptions::Area ParseArea(const std::string& text) {
  const std::vector<std::string_view> parts = SplitCommas(text);
  std::vector<double> v;
  for (std::string_view part : parts) {
    const std::optional<double> x = ParseFinite(part);
    if (!x) break;
    v.push_back(*x);
  }
  if (parts.size() != 4 || v.size() != 4 || !(v[0] < v[1]) || !(v[2] < v[3])) {
    throw UsageError("--area: '" + text +
                     "' is not MIN_X,MAX_X,MIN_Y,MAX_Y (four finite numbers in metres, min < max)");
  }
  return {v[0], v[1], v[2], v[3]};
}

int RunPointComparison(const Args& args,
                       const formats::TrackFile& gt,
                       const formats::TrackFile& pred,
                       const eval::TrackingOptions& tracking_options) {
  eval::PointComparisonOptions options;
  options.gate_m = tracking_options.footprint_threshold_m;
  options.frame_ranges = tracking_options.frame_ranges;
  if (args.Has("area")) options.area = ParseArea(args.Get("area"));
  std::string why;
  if (!options.Validate(&why)) throw UsageError(why);
  const bool json_to_stdout = args.Has("json") && args.Get("json") == "-";
  std::ostream& out = json_to_stdout ? std::cerr : std::cout;
  out << "reference:    " << gt.Describe() << "\n";
  out << "predictions:  " << pred.Describe() << "\n";
  out << "joints: not compared (--points: footprints only, ids ignored on both sides)\n\n";
  eval::EvaluationReport report;
  report.points = eval::ComparePoints(FootprintSequence(gt), FootprintSequence(pred), options);
  if (!report.points->valid) {
    std::cerr << "mvtrack eval: point comparison failed: " << report.points->error << "\n";
    return 1;
  }
  out << eval::FormatReportTable(report);
  if (args.Has("json")) WriteJsonReport(args, report);
  return 0;
}

}  // namespace

eval::EvalSequence FootprintSequence(const formats::TrackFile& file) {
  return ToSequence(file, false, nullptr, eval::HeadRule::kCampus);
}

int RunEval(int argc, char** argv) {
  Args args;
  args.Positional("TRACKS", "the predictions (instead of --pred)", /*required=*/false)
      .Option("gt",
              "ground truth: canonical tracks JSONL (actors as tracks) or an LCM tracks log "
              "(required)")
      .Option("pred", "the predictions: JSONL or LCM tracks log (or give them as TRACKS)")
      .Option("layout",
              "keypoint layout joints are compared in: coco17, body25, shelf14, "
              "panoptic19 (default: the ground truth's); the other side is mapped to it "
              "with core::MakeKeypointMapping")
      .Option("distance",
              "how GT and tracks are matched: footprint (ground-plane distance) or "
              "joints (mean 3D joint distance)",
              "footprint")
      .Option("threshold", "matching gate, metres", "0.5")
      .Option("frames", "evaluate only these frames: A-B[,C-D...] (inclusive; default: all)")
      .Option("cover-frames",
              "a predicted id covers a GT person when CLEAR MOT matches them in at least this "
              "many frames (IDTR: ids covering >= 2 persons, IDFRAG: persons covered by >= 2 ids)",
              "15")
      .Option("return-gap",
              "a GT person absent for more than this many frames and present again has "
              "returned: its id after the return is scored (old id kept, new id, another "
              "person's id)",
              "150")
      .Option("actors", "PCP only: GT actor ids scored, e.g. 0,1,2 (default: every actor)")
      .Option("head-rule",
              "how head_top is derived when joints are mapped to shelf14: campus (VoxelPose's "
              "coco2campus3D, affine) or shelf-4da (4D Association's Shelf evaluation, "
              "MappingToShelf: facing direction + fixed offsets; the protocol of its published "
              "Shelf numbers)",
              "campus")
      .Flag("points",
            "instead of tracking metrics, compare footprints with reference points that carry no "
            "identities (GT = e.g. WILDTRACK's ground_points.jsonl): per-frame counts and the "
            "distances of the per-frame one-to-one matches within --threshold")
      .Option("area",
              "--points only: MIN_X,MAX_X,MIN_Y,MAX_Y (metres): points of either side outside "
              "this floor rectangle are dropped before matching (a dataset's annotated area; "
              "WILDTRACK: -3,9,-9,27)")
      .Flag("pcp",
            "also score PCP (alpha 0.5): the Shelf/Campus parts when the layout is shelf14, "
            "else every bone of the layout")
      .Option("json",
              "also write the report as JSON (schema mvtrack.eval/1) to this file "
              "('-': stdout, the table then goes to stderr)");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack eval --gt GT [--pred] TRACKS [--layout NAME] "
          "[--distance footprint|joints] [--threshold M] [--frames A-B[,C-D]] [--cover-frames N] "
          "[--return-gap N] "
          "[--actors 0,1,2] [--head-rule campus|shelf-4da] [--pcp | --points [--area X0,X1,Y0,Y1]] "
          "[--json OUT.json]",
          "Scores tracks against ground truth with CLEAR MOT (MOTA, MOTP, FP, FN, IDSW, MT,\n"
          "ML; py-motmetrics semantics), identity F1 (IDF1, IDP, IDR), HOTA (DetA, AssA,\n"
          "LocA; TrackEval's definitions), id transfers and fragmentations (IDTR, IDFRAG)\n"
          "and MPJPE, and with --pcp the PCP of Belagiannis et al. as the Shelf/Campus\n"
          "evaluations compute it.\n"
          "Both files may be canonical tracks JSONL or LCM logs of tracks3d_t (recognised\n"
          "by content). Joints in different keypoint layouts are mapped to one layout\n"
          "(the mapping is printed). The protocol of every metric is printed with it.\n"
          "With --points the ground truth is a set of reference points without\n"
          "identities: each frame's footprints and points are paired one-to-one\n"
          "(min-cost, within --threshold) and the counts, MODA, MODP, precision, recall\n"
          "and distances are reported (e.g. WILDTRACK's ground_truth.jsonl with --area).\n\n"
          "Exit status: 0 evaluated, 1 failure (unreadable input, inputs that cannot be\n"
          "compared), 2 usage error.")) {
    return 0;
  }
  if (!args.Has("gt")) throw UsageError("--gt is required");
  if (args.Has("pred") && args.Has("TRACKS")) {
    throw UsageError("give the predictions either as --pred or as TRACKS, not both");
  }
  if (!args.Has("pred") && !args.Has("TRACKS")) {
    throw UsageError("missing the predictions (--pred TRACKS or TRACKS)");
  }
  const std::string pred_path = args.Has("pred") ? args.Get("pred") : args.Get("TRACKS");

  eval::TrackingOptions tracking_options;
  const std::string distance = args.Get("distance");
  if (distance == "footprint") {
    tracking_options.distance = eval::DistanceKind::kFootprint;
  } else if (distance == "joints") {
    tracking_options.distance = eval::DistanceKind::kMeanJoint;
  } else {
    throw UsageError("--distance must be 'footprint' or 'joints', not '" + distance + "'");
  }
  const double threshold = args.GetDouble("threshold");
  if (!(threshold > 0.0)) throw UsageError("--threshold must be > 0 (metres)");
  tracking_options.footprint_threshold_m = threshold;
  tracking_options.mean_joint_threshold_m = threshold;
  if (args.Has("frames")) {
    tracking_options.frame_ranges = ParseFrameRanges(args.Get("frames"), "--frames");
  }
  tracking_options.cover_min_frames = args.GetInt("cover-frames");
  if (tracking_options.cover_min_frames < 1) throw UsageError("--cover-frames must be >= 1");
  tracking_options.return_min_gap_frames = args.GetInt("return-gap");
  if (tracking_options.return_min_gap_frames < 1) throw UsageError("--return-gap must be >= 1");
  const bool pcp = args.Has("pcp");
  const bool points = args.Has("points");
  if (points && pcp) throw UsageError("--points and --pcp exclude each other");
  if (args.Has("area") && !points) throw UsageError("--area needs --points");
  if (points && tracking_options.distance != eval::DistanceKind::kFootprint) {
    throw UsageError("--points compares footprints: --distance must be footprint");
  }
  if (args.Has("actors") && !pcp) throw UsageError("--actors applies to PCP only: add --pcp");
  const std::optional<eval::HeadRule> head_rule = eval::HeadRuleFromName(args.Get("head-rule"));
  if (!head_rule) {
    throw UsageError("--head-rule must be 'campus' or 'shelf-4da', not '" + args.Get("head-rule") +
                     "'");
  }
  std::optional<core::KeypointLayoutId> requested_layout;
  if (args.Has("layout")) {
    requested_layout = core::KeypointLayoutFromName(args.Get("layout"));
    if (!requested_layout) {
      throw UsageError("--layout: unknown layout '" + args.Get("layout") +
                       "' (coco17, body25, shelf14, campus14, panoptic19, none)");
    }
  }
  const bool needs_joints = tracking_options.distance == eval::DistanceKind::kMeanJoint || pcp;
  if (needs_joints && requested_layout == core::KeypointLayoutId::kNone) {
    throw UsageError("--layout none has no joints: --distance joints and --pcp need joints");
  }

  formats::TrackFile gt;
  formats::TrackFile pred;
  try {
    gt = formats::ReadTrackFile(args.Get("gt"));
    pred = formats::ReadTrackFile(pred_path);
  } catch (const formats::TrackFileError& e) {
    std::cerr << "mvtrack eval: " << e.what() << "\n";
    return 1;
  }

  // The layout joints are compared in, and how each side gets there.
  const core::KeypointLayoutId eval_layout = requested_layout.value_or(
      gt.layout.value_or(pred.layout.value_or(core::KeypointLayoutId::kNone)));
  const bool compare_joints =
      eval_layout != core::KeypointLayoutId::kNone && HasJoints(gt) && HasJoints(pred);
  if (needs_joints && !compare_joints) {
    const std::string side = !HasJoints(gt) ? "the ground truth (" + gt.path + ")"
                                            : "the predictions (" + pred.path + ")";
    std::cerr << "mvtrack eval: no joints in " << side
              << ": layout none (box mode); --distance joints and --pcp need joints on both "
                 "sides\n";
    return 1;
  }
  if (points) return RunPointComparison(args, gt, pred, tracking_options);
  std::optional<core::KeypointMapping> gt_mapping;
  std::optional<core::KeypointMapping> pred_mapping;
  if (compare_joints && gt.layout && *gt.layout != eval_layout) {
    gt_mapping = core::MakeKeypointMapping(*gt.layout, eval_layout);
  }
  if (compare_joints && pred.layout && *pred.layout != eval_layout) {
    pred_mapping = core::MakeKeypointMapping(*pred.layout, eval_layout);
  }
  const eval::EvalSequence gt_seq =
      ToSequence(gt, compare_joints, gt_mapping ? &*gt_mapping : nullptr, *head_rule);
  const eval::EvalSequence pred_seq =
      ToSequence(pred, compare_joints, pred_mapping ? &*pred_mapping : nullptr, *head_rule);

  const bool json_to_stdout = args.Has("json") && args.Get("json") == "-";
  std::ostream& out = json_to_stdout ? std::cerr : std::cout;
  out << "ground truth: " << gt.Describe() << "\n";
  out << "predictions:  " << pred.Describe() << "\n";
  {
    std::set<FrameIndex> gt_frames;
    for (const formats::TrackFileFrame& f : gt.frames) gt_frames.insert(f.frame.frame);
    std::int64_t common = 0;
    for (const formats::TrackFileFrame& f : pred.frames)
      common += gt_frames.count(f.frame.frame) ? 1 : 0;
    out << "frames: " << gt.frames.size() << " in the ground truth, " << pred.frames.size()
        << " predicted, " << common << " in both\n";
  }
  if (!compare_joints) {
    out << "joints: not compared ("
        << (eval_layout == core::KeypointLayoutId::kNone
                ? std::string("layout none")
                : (!HasJoints(gt) ? "the ground truth has none" : "the predictions have none"))
        << "); footprints only\n";
  } else {
    out << "joints: compared in layout " << formats::LayoutName(eval_layout) << "\n";
    const std::pair<const char*, const std::optional<core::KeypointMapping>*> sides[] = {
        {"ground truth", &gt_mapping}, {"predictions", &pred_mapping}};
    for (const auto& [name, mapping] : sides) {
      if (!*mapping) continue;
      out << "  " << name << " mapped " << formats::LayoutName((*mapping)->from) << " -> "
          << formats::LayoutName((*mapping)->to) << " (core::MakeKeypointMapping):\n"
          << DescribeMapping(**mapping);
      if ((*mapping)->to == core::KeypointLayoutId::kShelf14 &&
          *head_rule == eval::HeadRule::kShelf4da) {
        out << "  head_top    <- instead (--head-rule shelf-4da, 4D Association's MappingToShelf): "
               "head_bottom + 0.125 m * unit((neck - mid_hip) x (r_shoulder - l_shoulder)) + "
               "0.145 m * z\n";
      }
    }
  }
  out << "\n";

  std::string why;
  if (!tracking_options.Validate(&why)) throw UsageError(why);
  eval::EvaluationReport report;
  report.tracking = eval::EvaluateTracking(gt_seq, pred_seq, tracking_options);
  if (!report.tracking->valid) {
    std::cerr << "mvtrack eval: tracking evaluation failed: " << report.tracking->error << "\n";
    return 1;
  }
  if (pcp) {
    eval::PcpProtocol protocol = eval_layout == core::KeypointLayoutId::kShelf14
                                     ? eval::ShelfCampusPcpProtocol()
                                     : eval::LayoutPcpProtocol(eval_layout);
    if (eval_layout == core::KeypointLayoutId::kShelf14) {
      protocol.name += std::string(", head_top of mapped predictions by --head-rule ") +
                       std::string(eval::HeadRuleName(*head_rule));
    }
    eval::PcpOptions pcp_options;
    pcp_options.frame_ranges = tracking_options.frame_ranges;
    if (args.Has("actors")) pcp_options.actor_ids = ParseActors(args.Get("actors"));
    if (!pcp_options.Validate(&why)) throw UsageError(why);
    report.pcp = eval::EvaluatePcp(gt_seq, pred_seq, protocol, pcp_options);
    if (!report.pcp->valid) {
      std::cerr << "mvtrack eval: PCP evaluation failed: " << report.pcp->error << "\n";
      return 1;
    }
    // Bodies (issue 40): how much each predicted track's limbs change length, over the tracks
    // of at least 2 s at 25 fps.
    report.bones = eval::EvaluateBoneLengths(
        pred_seq, core::GetKeypointLayout(eval_layout), 50, tracking_options.frame_ranges);
  }
  out << eval::FormatReportTable(report);
  if (args.Has("json")) WriteJsonReport(args, report);
  return 0;
}

}  // namespace mvtrack::cli
