#include "eval/report.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <variant>
#include <vector>

#include "eval/number_format.h"
#include "json/json.h"

namespace mvtrack::eval {
namespace {

// ------------------------------------------------------------------------------------------
// Minimal JSON tree: objects keep (key, value) pairs and are sorted by key when written.

struct Json;
using JsonArray = std::vector<Json>;
using JsonObject = std::vector<std::pair<std::string, Json>>;

struct Json {
  std::variant<std::nullptr_t, bool, std::int64_t, double, std::string, JsonArray, JsonObject>
      value;
};

Json Bool(bool v) { return Json{v}; }
Json Int(std::int64_t v) { return Json{v}; }
Json Num(double v) { return Json{v}; }
Json Str(std::string v) { return Json{std::move(v)}; }
Json Arr(JsonArray v) { return Json{std::move(v)}; }
Json Obj(JsonObject v) { return Json{std::move(v)}; }

void Write(const Json& json, int precision, int indent, std::string* out) {
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  const std::string close_pad(static_cast<std::size_t>(indent), ' ');
  if (std::holds_alternative<std::nullptr_t>(json.value)) {
    *out += "null";
  } else if (const auto* b = std::get_if<bool>(&json.value)) {
    *out += *b ? "true" : "false";
  } else if (const auto* i = std::get_if<std::int64_t>(&json.value)) {
    *out += std::to_string(*i);
  } else if (const auto* d = std::get_if<double>(&json.value)) {
    *out += std::isfinite(*d) ? internal::FormatFixed(*d, precision) : "null";
  } else if (const auto* s = std::get_if<std::string>(&json.value)) {
    json::AppendQuoted(*s, out);
  } else if (const auto* a = std::get_if<JsonArray>(&json.value)) {
    // Arrays of scalars stay on one line ("[1, 2, 3]"); arrays of arrays or objects get one
    // element per line.
    const bool scalars = std::none_of(a->begin(), a->end(), [](const Json& e) {
      return std::holds_alternative<JsonArray>(e.value) ||
             std::holds_alternative<JsonObject>(e.value);
    });
    if (scalars) {
      *out += "[";
      for (std::size_t k = 0; k < a->size(); ++k) {
        if (k > 0) *out += ", ";
        Write((*a)[k], precision, indent, out);
      }
      *out += "]";
      return;
    }
    *out += "[\n";
    for (std::size_t k = 0; k < a->size(); ++k) {
      *out += pad;
      Write((*a)[k], precision, indent + 2, out);
      *out += k + 1 < a->size() ? ",\n" : "\n";
    }
    *out += close_pad + "]";
  } else if (const auto* o = std::get_if<JsonObject>(&json.value)) {
    if (o->empty()) {
      *out += "{}";
      return;
    }
    std::vector<const std::pair<std::string, Json>*> members;
    for (const auto& m : *o) members.push_back(&m);
    std::sort(members.begin(), members.end(), [](const auto* x, const auto* y) {
      return x->first < y->first;
    });
    *out += "{\n";
    for (std::size_t k = 0; k < members.size(); ++k) {
      *out += pad;
      json::AppendQuoted(members[k]->first, out);
      *out += ": ";
      Write(members[k]->second, precision, indent + 2, out);
      *out += k + 1 < members.size() ? ",\n" : "\n";
    }
    *out += close_pad + "}";
  }
}

Json NumArray(const std::vector<double>& values) {
  JsonArray a;
  for (const double v : values) a.push_back(Num(v));
  return Arr(std::move(a));
}

Json IntArray(const std::vector<std::int64_t>& values) {
  JsonArray a;
  for (const std::int64_t v : values) a.push_back(Int(v));
  return Arr(std::move(a));
}

Json StrArray(const std::vector<std::string>& values) {
  JsonArray a;
  for (const std::string& v : values) a.push_back(Str(v));
  return Arr(std::move(a));
}

Json Ranges(const std::vector<FrameRange>& ranges) {
  JsonArray a;
  for (const FrameRange& r : ranges) a.push_back(Arr({Int(r.first), Int(r.last)}));
  return Arr(std::move(a));
}

Json TrackingJson(const TrackingEvaluation& t) {
  JsonObject o;
  o.emplace_back("valid", Bool(t.valid));
  o.emplace_back("error", Str(t.error));
  o.emplace_back("protocol", Str(t.protocol));
  o.emplace_back("distance", Str(DistanceKindName(t.distance)));
  o.emplace_back("threshold_m", Num(t.threshold_m));
  o.emplace_back("frame_ranges", Ranges(t.frame_ranges));
  if (!t.valid) return Obj(std::move(o));

  const ClearMotMetrics& c = t.clear;
  o.emplace_back("clear_mot",
                 Obj({{"mota", Num(c.mota)},
                      {"motp_m", Num(c.motp_m)},
                      {"num_frames", Int(c.num_frames)},
                      {"num_objects", Int(c.num_objects)},
                      {"num_predictions", Int(c.num_predictions)},
                      {"num_unique_objects", Int(c.num_unique_objects)},
                      {"num_unique_predictions", Int(c.num_unique_predictions)},
                      {"num_matches", Int(c.num_matches)},
                      {"num_false_positives", Int(c.num_false_positives)},
                      {"num_misses", Int(c.num_misses)},
                      {"num_switches", Int(c.num_switches)},
                      {"num_fragmentations", Int(c.num_fragmentations)},
                      {"mostly_tracked", Int(c.mostly_tracked)},
                      {"partially_tracked", Int(c.partially_tracked)},
                      {"mostly_lost", Int(c.mostly_lost)},
                      {"total_distance_m", Num(c.total_distance_m)}}));

  const IdentityMetrics& id = t.identity;
  JsonArray matches;
  for (const IdentityMatch& m : id.matches) {
    matches.push_back(Obj({{"gt_id", Int(m.gt_id)},
                           {"prediction_id", Int(m.prediction_id)},
                           {"frames_within_gate", Int(m.frames_within_gate)}}));
  }
  o.emplace_back("identity",
                 Obj({{"idf1", Num(id.idf1)},
                      {"idp", Num(id.idp)},
                      {"idr", Num(id.idr)},
                      {"idtp", Int(id.idtp)},
                      {"idfp", Int(id.idfp)},
                      {"idfn", Int(id.idfn)},
                      {"matches", Arr(std::move(matches))}}));

  const HotaMetrics& h = t.hota;
  o.emplace_back("hota",
                 Obj({{"hota", Num(h.mean_hota)},
                      {"det_a", Num(h.mean_det_a)},
                      {"ass_a", Num(h.mean_ass_a)},
                      {"loc_a", Num(h.mean_loc_a)},
                      {"alphas", NumArray(h.alphas)},
                      {"hota_per_alpha", NumArray(h.hota)},
                      {"det_a_per_alpha", NumArray(h.det_a)},
                      {"ass_a_per_alpha", NumArray(h.ass_a)},
                      {"det_re_per_alpha", NumArray(h.det_re)},
                      {"det_pr_per_alpha", NumArray(h.det_pr)},
                      {"ass_re_per_alpha", NumArray(h.ass_re)},
                      {"ass_pr_per_alpha", NumArray(h.ass_pr)},
                      {"loc_a_per_alpha", NumArray(h.loc_a)},
                      {"tp_per_alpha", IntArray(h.tp)},
                      {"fn_per_alpha", IntArray(h.fn)},
                      {"fp_per_alpha", IntArray(h.fp)}}));

  const IdentityCoverage& cov = t.coverage;
  JsonArray transfers;
  for (const IdentityCoverage::Transfer& x : cov.transfers) {
    transfers.push_back(
        Obj({{"prediction_id", Int(x.prediction_id)}, {"gt_ids", IntArray(x.gt_ids)}}));
  }
  JsonArray fragmentations;
  for (const IdentityCoverage::Fragmentation& x : cov.fragmentations) {
    fragmentations.push_back(
        Obj({{"gt_id", Int(x.gt_id)}, {"prediction_ids", IntArray(x.prediction_ids)}}));
  }
  o.emplace_back(
      "coverage",
      Obj({{"cover_min_frames", Int(cov.cover_min_frames)},
           {"num_id_transfers", Int(static_cast<std::int64_t>(cov.transfers.size()))},
           {"num_id_fragmentations", Int(static_cast<std::int64_t>(cov.fragmentations.size()))},
           {"transfers", Arr(std::move(transfers))},
           {"fragmentations", Arr(std::move(fragmentations))}}));
  const ReturnMetrics& ret = t.returns;
  JsonArray returns;
  for (const ReturnMetrics::Return& r : ret.list) {
    returns.push_back(Obj({{"gt_id", Int(r.gt_id)},
                           {"frame", Int(r.frame)},
                           {"gap_frames", Int(r.gap_frames)},
                           {"before_id", Int(r.before_id)},
                           {"after_id", Int(r.after_id)},
                           {"outcome", Str(ReturnOutcomeName(r.outcome))}}));
  }
  o.emplace_back("returns",
                 Obj({{"min_gap_frames", Int(ret.min_gap_frames)},
                      {"num_returns", Int(ret.returns)},
                      {"kept", Int(ret.kept)},
                      {"new_id", Int(ret.new_id)},
                      {"other_person_id", Int(ret.other_person_id)},
                      {"untracked", Int(ret.untracked)},
                      {"list", Arr(std::move(returns))}}));

  const PoseErrorMetrics& p = t.pose;
  o.emplace_back("pose",
                 Obj({{"mpjpe_m", Num(p.mpjpe_m)},
                      {"num_pairs", Int(p.num_pairs)},
                      {"num_joints", Int(p.num_joints)},
                      {"per_joint_mpjpe_m", NumArray(p.per_joint_mpjpe_m)},
                      {"per_joint_count", IntArray(p.per_joint_count)}}));

  JsonArray objects;
  for (const ObjectCoverage& obj : t.objects) {
    objects.push_back(Obj({{"id", Int(obj.id)},
                           {"frames_present", Int(obj.frames_present)},
                           {"frames_matched", Int(obj.frames_matched)},
                           {"coverage", Str(TrackCoverageName(obj.coverage))}}));
  }
  o.emplace_back("objects", Arr(std::move(objects)));

  JsonArray switches;
  for (const IdSwitch& s : t.switches) {
    switches.push_back(Obj({{"frame", Int(s.frame)},
                            {"gt_id", Int(s.gt_id)},
                            {"previous_prediction_id", Int(s.previous_prediction_id)},
                            {"prediction_id", Int(s.prediction_id)}}));
  }
  o.emplace_back("switches", Arr(std::move(switches)));
  return Obj(std::move(o));
}

Json PcpJson(const PcpResult& r) {
  JsonObject o;
  o.emplace_back("valid", Bool(r.valid));
  o.emplace_back("error", Str(r.error));
  o.emplace_back("protocol", Str(r.protocol));
  o.emplace_back("alpha", Num(r.alpha));
  o.emplace_back("frame_ranges", Ranges(r.frame_ranges));
  if (!r.valid) return Obj(std::move(o));
  o.emplace_back("bone_names", StrArray(r.bone_names));
  o.emplace_back("group_names", StrArray(r.group_names));
  JsonArray actors;
  for (const PcpActorResult& a : r.actors) {
    actors.push_back(Obj({{"actor_id", Int(a.actor_id)},
                          {"num_frames", Int(a.num_frames)},
                          {"num_frames_without_prediction", Int(a.num_frames_without_prediction)},
                          {"correct_parts", Int(a.correct_parts)},
                          {"total_parts", Int(a.total_parts)},
                          {"pcp", Num(a.pcp)},
                          {"bone_correct", IntArray(a.bone_correct)},
                          {"bone_total", IntArray(a.bone_total)},
                          {"group_pcp", NumArray(a.group_pcp)}}));
  }
  o.emplace_back("actors", Arr(std::move(actors)));
  o.emplace_back("average_pcp", Num(r.average_pcp));
  o.emplace_back("average_group_pcp", NumArray(r.average_group_pcp));
  o.emplace_back("recall", Num(r.recall));
  o.emplace_back("recall_matched", Int(r.recall_matched));
  o.emplace_back("recall_total", Int(r.recall_total));
  return Obj(std::move(o));
}

Json PointsJson(const PointComparison& r) {
  JsonObject o;
  o.emplace_back("valid", Bool(r.valid));
  o.emplace_back("error", Str(r.error));
  o.emplace_back("protocol", Str(r.protocol));
  o.emplace_back("gate_m", Num(r.gate_m));
  o.emplace_back("frame_ranges", Ranges(r.frame_ranges));
  if (!r.valid) return Obj(std::move(o));
  JsonArray frames;
  for (const PointFrameCounts& f : r.frames) {
    frames.push_back(Obj({{"frame", Int(f.frame)},
                          {"num_reference", Int(f.num_reference)},
                          {"num_predicted", Int(f.num_predicted)},
                          {"num_matched", Int(f.num_matched)}}));
  }
  o.emplace_back("frames", Arr(std::move(frames)));
  o.emplace_back("num_frames", Int(static_cast<std::int64_t>(r.frames.size())));
  o.emplace_back("num_reference", Int(r.num_reference));
  o.emplace_back("num_predicted", Int(r.num_predicted));
  o.emplace_back("num_matched", Int(r.num_matched));
  o.emplace_back("frames_with_equal_count", Int(r.frames_with_equal_count));
  o.emplace_back("mean_abs_count_difference", Num(r.mean_abs_count_difference));
  o.emplace_back("mean_count_difference", Num(r.mean_count_difference));
  o.emplace_back("max_abs_count_difference", Int(r.max_abs_count_difference));
  o.emplace_back("precision", Num(r.precision));
  o.emplace_back("recall", Num(r.recall));
  o.emplace_back("false_positives", Int(r.false_positives));
  o.emplace_back("misses", Int(r.misses));
  o.emplace_back("moda", Num(r.moda));
  o.emplace_back("modp", Num(r.modp));
  o.emplace_back("modp_m", Num(r.mean_distance_m));
  if (r.area) {
    o.emplace_back("area",
                   Obj({{"min_x", Num(r.area->min_x)},
                        {"max_x", Num(r.area->max_x)},
                        {"min_y", Num(r.area->min_y)},
                        {"max_y", Num(r.area->max_y)}}));
  }
  o.emplace_back("num_reference_outside", Int(r.num_reference_outside));
  o.emplace_back("num_predicted_outside", Int(r.num_predicted_outside));
  o.emplace_back("median_distance_m", Num(r.median_distance_m));
  o.emplace_back("mean_distance_m", Num(r.mean_distance_m));
  o.emplace_back("p90_distance_m", Num(r.p90_distance_m));
  o.emplace_back("max_distance_m", Num(r.max_distance_m));
  return Obj(std::move(o));
}

// ------------------------------------------------------------------------------------------
// Text table helpers.

std::string Percent(double ratio) {
  return std::isnan(ratio) ? "n/a" : internal::FormatFixed(100.0 * ratio, 2);
}

std::string Metres(double value) {
  return std::isnan(value) ? "n/a" : internal::FormatFixed(value, 4);
}

// Rows of cells rendered as columns: the first column left-aligned, the others right-aligned,
// each as wide as its widest cell, two spaces apart, every line indented by two spaces.
std::string Columns(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    if (row.size() > width.size()) width.resize(row.size(), 0);
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::string line = " ";
    for (std::size_t c = 0; c < row.size(); ++c) {
      const std::string fill(width[c] - row[c].size(), ' ');
      line += " ";
      line += c == 0 ? row[c] + fill : fill + row[c];
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

std::string TrackingTable(const TrackingEvaluation& t) {
  std::string out = "Tracking (distance " + std::string(DistanceKindName(t.distance)) + ", gate " +
                    internal::FormatFixed(t.threshold_m, 3) + " m, frames " +
                    DescribeFrameRanges(t.frame_ranges) + ")\n";
  if (!t.valid) return out + "  invalid input: " + t.error + "\n";
  const ClearMotMetrics& c = t.clear;
  const IdentityMetrics& id = t.identity;
  out += Columns({{"MOTA%",
                   "MOTP[m]",
                   "IDF1%",
                   "IDP%",
                   "IDR%",
                   "FP",
                   "FN",
                   "IDSW",
                   "FM",
                   "MT",
                   "PT",
                   "ML",
                   "GT",
                   "GT ids",
                   "Pred",
                   "Pred ids",
                   "Frames"},
                  {Percent(c.mota),
                   Metres(c.motp_m),
                   Percent(id.idf1),
                   Percent(id.idp),
                   Percent(id.idr),
                   std::to_string(c.num_false_positives),
                   std::to_string(c.num_misses),
                   std::to_string(c.num_switches),
                   std::to_string(c.num_fragmentations),
                   std::to_string(c.mostly_tracked),
                   std::to_string(c.partially_tracked),
                   std::to_string(c.mostly_lost),
                   std::to_string(c.num_objects),
                   std::to_string(c.num_unique_objects),
                   std::to_string(c.num_predictions),
                   std::to_string(c.num_unique_predictions),
                   std::to_string(c.num_frames)}});
  const HotaMetrics& h = t.hota;
  const IdentityCoverage& cov = t.coverage;
  out += Columns({{"HOTA%", "DetA%", "AssA%", "LocA%", "IDTR", "IDFRAG"},
                  {Percent(h.mean_hota),
                   Percent(h.mean_det_a),
                   Percent(h.mean_ass_a),
                   Percent(h.mean_loc_a),
                   std::to_string(cov.transfers.size()),
                   std::to_string(cov.fragmentations.size())}});
  // The transfers by name (they are the errors that break visit counts), at most 10.
  if (!cov.transfers.empty()) {
    std::string line = "  id transfers (predicted id: GT ids in order):";
    for (std::size_t k = 0; k < cov.transfers.size() && k < 10; ++k) {
      line += (k == 0 ? " " : "; ") + std::to_string(cov.transfers[k].prediction_id) + ":";
      for (std::size_t g = 0; g < cov.transfers[k].gt_ids.size(); ++g) {
        line += (g == 0 ? " " : " -> ") + std::to_string(cov.transfers[k].gt_ids[g]);
      }
    }
    if (cov.transfers.size() > 10) {
      line += "; ... (" + std::to_string(cov.transfers.size() - 10) + " more)";
    }
    out += line + "\n";
  }
  // Returns of people who left and came back (only when there are any).
  if (t.returns.returns > 0) {
    const ReturnMetrics& ret = t.returns;
    const auto share = [&](std::int64_t n) {
      return std::to_string(n) + " (" +
             internal::FormatFixed(
                 100.0 * static_cast<double>(n) / static_cast<double>(ret.returns), 1) +
             "%)";
    };
    out += "  returns after > " + std::to_string(ret.min_gap_frames) +
           " frames away: " + std::to_string(ret.returns) + ", old id kept " + share(ret.kept) +
           ", new id " + share(ret.new_id) + ", another person's id " + share(ret.other_person_id) +
           ", untracked " + share(ret.untracked) + "\n";
  }
  out += "  MPJPE " + Metres(t.pose.mpjpe_m) + " m over " + std::to_string(t.pose.num_pairs) +
         " matched pairs (" + std::to_string(t.pose.num_joints) + " joints)\n";
  out += "  Protocol: " + t.protocol + "\n";
  return out;
}

std::string PcpTable(const PcpResult& r) {
  std::string out = "PCP (alpha " + internal::FormatFixed(r.alpha, 2) + ", frames " +
                    DescribeFrameRanges(r.frame_ranges) + ")\n";
  if (!r.valid) return out + "  invalid input: " + r.error + "\n";
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"actor", "frames", "no pred", "PCP%"};
  for (const std::string& g : r.group_names) header.push_back(g + "%");
  rows.push_back(header);
  for (const PcpActorResult& a : r.actors) {
    std::vector<std::string> row = {std::to_string(a.actor_id),
                                    std::to_string(a.num_frames),
                                    std::to_string(a.num_frames_without_prediction),
                                    Percent(a.pcp)};
    for (const double g : a.group_pcp) row.push_back(Percent(g));
    rows.push_back(row);
  }
  std::vector<std::string> average = {"average", "", "", Percent(r.average_pcp)};
  for (const double g : r.average_group_pcp) average.push_back(Percent(g));
  rows.push_back(average);
  out += Columns(rows);
  out += "  Recall " + Percent(r.recall) + "% (" + std::to_string(r.recall_matched) + " / " +
         std::to_string(r.recall_total) + " actor-frames)\n";
  out += "  Protocol: " + r.protocol + "\n";
  return out;
}

std::string BonesTable(const BoneLengthStability& r) {
  std::string out = "Bone lengths (tracks of >= " + std::to_string(r.min_frames) + " frames)\n";
  std::vector<std::vector<std::string>> rows = {{"track", "frames", "CV mean%", "CV max%"}};
  for (const BoneLengthTrack& t : r.tracks) {
    rows.push_back({std::to_string(t.id),
                    std::to_string(t.num_frames),
                    Percent(t.cv_mean),
                    Percent(t.cv_max)});
  }
  rows.push_back(
      {"all", std::to_string(r.tracks.size()) + " tracks", Percent(r.cv_mean), Percent(r.cv_max)});
  out += Columns(rows);
  out += "  worst track CV mean " + Percent(r.cv_worst_track) + "%\n";
  out += "  Protocol: " + r.protocol + "\n";
  return out;
}

Json BonesJson(const BoneLengthStability& r) {
  JsonObject o;
  o.emplace_back("protocol", Str(r.protocol));
  o.emplace_back("min_frames", Int(r.min_frames));
  JsonArray limbs;
  for (const std::string& l : r.limbs) limbs.push_back(Str(l));
  o.emplace_back("limbs", Arr(std::move(limbs)));
  JsonArray tracks;
  for (const BoneLengthTrack& t : r.tracks) {
    tracks.push_back(Obj({{"id", Int(t.id)},
                          {"num_frames", Int(t.num_frames)},
                          {"cv_mean", Num(t.cv_mean)},
                          {"cv_max", Num(t.cv_max)}}));
  }
  o.emplace_back("tracks", Arr(std::move(tracks)));
  o.emplace_back("num_tracks", Int(static_cast<std::int64_t>(r.tracks.size())));
  o.emplace_back("cv_mean", Num(r.cv_mean));
  o.emplace_back("cv_worst_track", Num(r.cv_worst_track));
  o.emplace_back("cv_max", Num(r.cv_max));
  return Obj(std::move(o));
}

std::string PointsTable(const PointComparison& r) {
  std::string out = "Footprints vs reference points (gate " + internal::FormatFixed(r.gate_m, 3) +
                    " m, frames " + DescribeFrameRanges(r.frame_ranges) + ")\n";
  if (!r.valid) return out + "  invalid input: " + r.error + "\n";
  const auto frames = static_cast<std::int64_t>(r.frames.size());
  out += Columns(
      {{"Frames",
        "Ref",
        "Pred",
        "Matched",
        "Prec%",
        "Rec%",
        "equal count",
        "mean |dN|",
        "mean dN",
        "max |dN|",
        "median[m]",
        "mean[m]",
        "p90[m]",
        "max[m]"},
       {std::to_string(frames),
        std::to_string(r.num_reference),
        std::to_string(r.num_predicted),
        std::to_string(r.num_matched),
        Percent(r.precision),
        Percent(r.recall),
        std::to_string(r.frames_with_equal_count) + "/" + std::to_string(frames),
        std::isnan(r.mean_abs_count_difference)
            ? "n/a"
            : internal::FormatFixed(r.mean_abs_count_difference, 2),
        std::isnan(r.mean_count_difference) ? "n/a"
                                            : internal::FormatFixed(r.mean_count_difference, 2),
        std::to_string(r.max_abs_count_difference),
        Metres(r.median_distance_m),
        Metres(r.mean_distance_m),
        Metres(r.p90_distance_m),
        Metres(r.max_distance_m)}});
  out += Columns(
      {{"MODA%", "MODP%", "MODP[m]", "TP", "FP", "FN", "Prec%", "Rec%", "outside area (ref/pred)"},
       {Percent(r.moda),
        Percent(r.modp),
        Metres(r.mean_distance_m),
        std::to_string(r.num_matched),
        std::to_string(r.false_positives),
        std::to_string(r.misses),
        Percent(r.precision),
        Percent(r.recall),
        r.area ? std::to_string(r.num_reference_outside) + "/" +
                     std::to_string(r.num_predicted_outside)
               : std::string("no area")}});
  out += "  Protocol: " + r.protocol + "\n";
  return out;
}

}  // namespace

std::string FormatReportTable(const EvaluationReport& report) {
  std::string out;
  if (report.tracking.has_value()) out += TrackingTable(*report.tracking);
  if (report.pcp.has_value()) {
    if (!out.empty()) out += "\n";
    out += PcpTable(*report.pcp);
  }
  if (report.points.has_value()) {
    if (!out.empty()) out += "\n";
    out += PointsTable(*report.points);
  }
  if (report.bones.has_value()) {
    if (!out.empty()) out += "\n";
    out += BonesTable(*report.bones);
  }
  if (out.empty()) out = "No evaluation results.\n";
  return out;
}

std::string ReportToJson(const EvaluationReport& report, int precision) {
  JsonObject root;
  root.emplace_back("schema", Str("mvtrack.eval/1"));
  if (report.tracking.has_value()) root.emplace_back("tracking", TrackingJson(*report.tracking));
  if (report.pcp.has_value()) root.emplace_back("pcp", PcpJson(*report.pcp));
  if (report.points.has_value()) root.emplace_back("points", PointsJson(*report.points));
  if (report.bones.has_value()) root.emplace_back("bones", BonesJson(*report.bones));
  std::string out;
  Write(Obj(std::move(root)), std::clamp(precision, 0, 17), 0, &out);
  return out + "\n";
}

}  // namespace mvtrack::eval
