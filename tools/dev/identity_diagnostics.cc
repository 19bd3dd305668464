// Developer diagnostic (not installed): where each identity error on a real dataset comes
// from. Runs the inline Tracker on a dataset whose detections carry their person (WILDTRACK's
// annotated boxes, or MVDeTr's boxes labelled by IoU with the annotated ones; EPFL Terrace),
// then
//  - 2D tracking: per camera, how often one person's consecutive detections stay on one 2D
//    track (continued), start another (broken) or a 2D track passes to another person
//    (2D switch);
//  - output: matches ground truth to the output per frame (1 m, or --threshold; kept matches
//    first, then nearest) and attributes every identity switch and every extra id to a stage:
//      2d        the new id's tracklet shares no 2D track with the old id's last tracklet (every
//                camera's 2D track of the person broke, nothing tied the windows together);
//      linking   it shares one, and the linker still started a new id or linked elsewhere;
//      swap      the new id was another person's (a wrong link or a wrong association);
//      association  the new id's window tracklet mixed people (impure cluster);
//      gap       the old id was lost and came back later (a miss, not a decision);
//    extra ids: output ids whose person already had an earlier id (fragment: same causes) or
//    that match nobody (ghost).
//
//   mvtrack_identity_diagnostics --dataset wildtrack|wildtrack-mvdetr|epfl [--frames A-B]
//       [--corruption clean|default|hard] [--seed N] [--data DIR] [--options tracker.yaml]
//       [--miss-rate R] [--noise-px P] [--false-positives F] [--threshold M] [--verbose]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/tracker_options.h"
#include "core/linear_assignment.h"
#include "datasets/dataset.h"
#include "datasets/epfl.h"
#include "datasets/wildtrack.h"
#include "tracker/tracker.h"
#include "tracking2d/box_iou.h"

namespace {

using mvtrack::CameraId;
using mvtrack::FrameIndex;
using mvtrack::TrackId2D;
using mvtrack::TrackId3D;
namespace core = mvtrack::core;
namespace datasets = mvtrack::datasets;
namespace tracker = mvtrack::tracker;
namespace linking = mvtrack::linking;

struct Args {
  std::string dataset = "wildtrack";
  std::optional<std::pair<FrameIndex, FrameIndex>> frames;
  std::string corruption = "clean";
  std::uint64_t seed = 1;
  std::string data;
  std::string options_file;
  double threshold_m = 1.0;
  bool verbose = false;
  // Overrides of the corruption level's rates (negative: the level's).
  double miss_rate = -1.0, noise_px = -1.0, false_positives = -1.0;
  // --dump-windows A-B: every window person whose frames meet A..B, with its members.
  std::optional<std::pair<FrameIndex, FrameIndex>> dump;
};

[[noreturn]] void Usage(const std::string& why) {
  std::fprintf(stderr, "mvtrack_identity_diagnostics: %s\n", why.c_str());
  std::exit(2);
}

Args Parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) Usage("missing value for " + k);
      return argv[++i];
    };
    if (k == "--dataset") {
      a.dataset = value();
    } else if (k == "--frames") {
      const std::string v = value();
      const auto dash = v.find('-');
      if (dash == std::string::npos) Usage("--frames A-B");
      a.frames = std::make_pair(std::stoll(v.substr(0, dash)), std::stoll(v.substr(dash + 1)));
    } else if (k == "--corruption") {
      a.corruption = value();
    } else if (k == "--seed") {
      a.seed = std::stoull(value());
    } else if (k == "--data") {
      a.data = value();
    } else if (k == "--options") {
      a.options_file = value();
    } else if (k == "--threshold") {
      a.threshold_m = std::stod(value());
    } else if (k == "--dump-windows") {
      const std::string v = value();
      const auto dash = v.find('-');
      if (dash == std::string::npos) Usage("--dump-windows A-B");
      a.dump = std::make_pair(std::stoll(v.substr(0, dash)), std::stoll(v.substr(dash + 1)));
    } else if (k == "--miss-rate") {
      a.miss_rate = std::stod(value());
    } else if (k == "--noise-px") {
      a.noise_px = std::stod(value());
    } else if (k == "--false-positives") {
      a.false_positives = std::stod(value());
    } else if (k == "--verbose") {
      a.verbose = true;
    } else {
      Usage("unknown argument " + k);
    }
  }
  return a;
}

// MVDeTr's boxes carry no person: each takes the person whose annotated box in the same view
// overlaps it most (IoU >= 0.5), else it stays unknown.
void LabelByAnnotations(datasets::Dataset* ds, const datasets::Dataset& annotated) {
  std::map<std::pair<FrameIndex, CameraId>, std::size_t> index;
  for (std::size_t f = 0; f < annotated.detections.size(); ++f) {
    for (std::size_t c = 0; c < annotated.detections[f].size(); ++c) {
      index[{annotated.detections[f][c].frame, annotated.detections[f][c].camera_id}] = f;
    }
  }
  for (std::size_t f = 0; f < ds->detections.size(); ++f) {
    for (std::size_t c = 0; c < ds->detections[f].size(); ++c) {
      const core::CameraFrame& cf = ds->detections[f][c];
      const auto it = index.find({cf.frame, cf.camera_id});
      if (it == index.end()) continue;
      const core::CameraFrame& ann = annotated.detections[it->second][c];
      for (std::size_t d = 0; d < cf.detections.size(); ++d) {
        double best = 0.5;
        for (std::size_t a = 0; a < ann.detections.size(); ++a) {
          const double iou =
              mvtrack::tracking2d::BoxIou(cf.detections[d].box, ann.detections[a].box);
          if (iou >= best) {
            best = iou;
            ds->source_ids[f][c][d] = annotated.source_ids[it->second][c][a];
          }
        }
      }
    }
  }
}

datasets::Dataset Load(const Args& a) {
  const std::filesystem::path root =
      a.data.empty() ? datasets::DefaultDataRoot() : std::filesystem::path(a.data);
  datasets::CorruptionOptions corruption;
  const auto level = datasets::CorruptionLevelFromName(a.corruption);
  if (!level) Usage("--corruption clean|default|hard");
  if (a.dataset == "wildtrack" || a.dataset == "wildtrack-mvdetr") {
    datasets::WildtrackAnnotatedOptions o;
    if (a.frames) {
      o.first = a.frames->first;
      o.last = a.frames->second;
    }
    corruption = datasets::CorruptionForLevel(*level, datasets::WildtrackCorruptionDefaults());
    corruption.seed = a.seed;
    if (a.miss_rate >= 0.0) corruption.miss_rate = a.miss_rate;
    if (a.noise_px >= 0.0) corruption.pixel_noise_px = a.noise_px;
    if (a.false_positives >= 0.0) corruption.false_positives_per_frame = a.false_positives;
    o.corruption = corruption;
    if (a.dataset == "wildtrack") return datasets::LoadWildtrackAnnotated(root, o);
    datasets::Dataset ds = datasets::LoadWildtrack(root, corruption);
    o.first = 360;
    o.last = 399;
    o.corruption = datasets::CorruptionOptions::Clean();
    const datasets::Dataset annotated = datasets::LoadWildtrackAnnotated(root, o);
    LabelByAnnotations(&ds, annotated);
    ds.ground_truth = annotated.ground_truth;
    return ds;
  }
  if (a.dataset == "epfl") {
    datasets::EpflOptions o;
    o.corruption = datasets::CorruptionForLevel(*level, o.corruption);
    o.corruption.seed = a.seed;
    datasets::Dataset ds = datasets::LoadEpflTerrace(root, o);
    if (a.frames) {
      auto keep = [&](FrameIndex f) { return f >= a.frames->first && f <= a.frames->second; };
      std::vector<std::vector<core::CameraFrame>> d;
      std::vector<std::vector<std::vector<std::int64_t>>> s;
      for (std::size_t f = 0; f < ds.detections.size(); ++f) {
        if (!keep(ds.detections[f].front().frame)) continue;
        d.push_back(ds.detections[f]);
        s.push_back(ds.source_ids[f]);
      }
      ds.detections = std::move(d);
      ds.source_ids = std::move(s);
      std::erase_if(ds.ground_truth, [&](const auto& g) { return !keep(g.frame); });
    }
    return ds;
  }
  Usage("--dataset wildtrack|wildtrack-mvdetr|epfl");
}

// Window tracklet of one person with what the diagnostic needs.
struct WindowPerson {
  std::int64_t window = 0;
  FrameIndex begin = 0, end = 0;  // the window's frames [begin, end)
  TrackId3D track = 0;
  linking::LinkKind kind = linking::LinkKind::kBirth;
  std::int64_t label = -1;  // majority person of its observations, -1 none
  double purity = 1.0;      // fraction of labelled observations of that person
  std::set<std::pair<CameraId, TrackId2D>> members;
  bool impure_2d = false;  // one of its 2D tracklets itself shows two people (a 2D switch)
};

std::int64_t Majority(const std::map<std::int64_t, int>& votes, double* purity) {
  std::int64_t best = -1;
  int n = 0, total = 0;
  for (const auto& [id, v] : votes) {
    total += v;
    if (id >= 0 && v > n) {
      n = v;
      best = id;
    }
  }
  *purity = total > 0 ? static_cast<double>(n) / total : 0.0;
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = Parse(argc, argv);
  datasets::Dataset ds;
  try {
    ds = Load(args);
  } catch (const std::exception& e) {
    Usage(e.what());
  }
  tracker::TrackerOptions topt;
  topt.mode = tracker::InputMode::kBoxes;
  if (!args.options_file.empty()) {
    topt = mvtrack::config::LoadTrackerOptionsFile(args.options_file);
    topt.mode = tracker::InputMode::kBoxes;
  }
  std::string why;
  auto trk = tracker::Tracker::Create(mvtrack::geometry::CameraRig(ds.cameras), topt, &why);
  if (!trk) Usage(why);

  // Detection -> person, by (frame, camera) and box centre.
  std::map<std::pair<FrameIndex, CameraId>, std::pair<std::size_t, std::size_t>> where;
  for (std::size_t f = 0; f < ds.detections.size(); ++f) {
    for (std::size_t c = 0; c < ds.detections[f].size(); ++c) {
      where[{ds.detections[f][c].frame, ds.detections[f][c].camera_id}] = {f, c};
    }
  }
  auto label_of = [&](CameraId cam, FrameIndex frame, const mvtrack::Vec2& p) -> std::int64_t {
    const auto it = where.find({frame, cam});
    if (it == where.end()) return -3;
    const auto [f, c] = it->second;
    const core::CameraFrame& cf = ds.detections[f][c];
    double best = 1e18;
    std::int64_t id = -3;
    for (std::size_t d = 0; d < cf.detections.size(); ++d) {
      // The observation's point is the box centre (completed for cut boxes: nearest centre).
      const double dist = (cf.detections[d].box.center() - p).squaredNorm();
      if (dist < best) {
        best = dist;
        id = ds.source_ids[f][c][d];
      }
    }
    return id;
  };

  // 2D: per (camera, 2D track) the person per frame.
  std::map<std::pair<CameraId, TrackId2D>, std::map<FrameIndex, std::int64_t>> track2d;
  std::vector<WindowPerson> persons;
  std::int64_t last_window = -1;
  auto inspect = [&]() {
    const auto& w = trk->last_window();
    if (!w || w->window_id == last_window) return;
    last_window = w->window_id;
    std::vector<std::int64_t> tracklet_label(w->tracklets.size(), -1);
    std::vector<std::map<std::int64_t, int>> tracklet_votes(w->tracklets.size());
    for (std::size_t t = 0; t < w->tracklets.size(); ++t) {
      const core::Tracklet2D& tl = w->tracklets[t];
      for (std::size_t i = 0; i < tl.frames.size(); ++i) {
        if (tl.observations[i].points_px.empty()) continue;
        const std::int64_t l =
            label_of(tl.camera_id, tl.frames[i], tl.observations[i].points_px[0]);
        ++tracklet_votes[t][l];
        track2d[{tl.camera_id, tl.track_id}][tl.frames[i]] = l;
      }
    }
    for (std::size_t p = 0; p < w->persons.size(); ++p) {
      WindowPerson wp;
      wp.window = w->window_id;
      wp.begin = w->begin;
      wp.end = w->end;
      wp.track = w->link.track_of_tracklet[p];
      wp.kind = w->link.link_kind[p];
      std::map<std::int64_t, int> votes;
      for (const int t : w->persons[p].source_tracklets) {
        for (const auto& [l, v] : tracklet_votes[static_cast<std::size_t>(t)]) votes[l] += v;
      }
      wp.label = Majority(votes, &wp.purity);
      for (const int t : w->persons[p].source_tracklets) {
        double tp = 1.0;
        Majority(tracklet_votes[static_cast<std::size_t>(t)], &tp);
        wp.impure_2d = wp.impure_2d || tp < 0.999;
      }
      if (args.dump && w->end > args.dump->first && w->begin <= args.dump->second) {
        std::printf(
            "window %lld [%lld, %lld) person %zu -> track %llu kind %d label %lld purity %.2f:",
            static_cast<long long>(w->window_id),
            static_cast<long long>(w->begin),
            static_cast<long long>(w->end),
            p,
            static_cast<unsigned long long>(wp.track),
            static_cast<int>(wp.kind),
            static_cast<long long>(wp.label),
            wp.purity);
        for (const int t : w->persons[p].source_tracklets) {
          const core::Tracklet2D& tl = w->tracklets[static_cast<std::size_t>(t)];
          double tp = 1.0;
          const std::int64_t tl_label = Majority(tracklet_votes[static_cast<std::size_t>(t)], &tp);
          std::printf(" c%d/t%llu=%lld(%zu fr %lld-%lld)",
                      tl.camera_id,
                      static_cast<unsigned long long>(tl.track_id),
                      static_cast<long long>(tl_label),
                      tl.frames.size(),
                      static_cast<long long>(tl.frames.front()),
                      static_cast<long long>(tl.frames.back()));
        }
        const auto& pts = w->persons[p];
        for (std::size_t f = 0; f < pts.frames.size();
             f += std::max<std::size_t>(1, pts.frames.size() / 3)) {
          if (!pts.points[f].empty() && pts.points[f][0]) {
            std::printf(" @%lld(%.2f,%.2f)",
                        static_cast<long long>(pts.frames[f]),
                        pts.points[f][0]->x(),
                        pts.points[f][0]->y());
          }
        }
        std::printf("\n");
      }
      for (const core::TrackletMember& m : w->persons[p].members)
        wp.members.insert({m.camera_id, m.track_id});
      persons.push_back(std::move(wp));
    }
  };
  std::vector<tracker::Frame3D> output;
  for (const auto& frame : ds.detections) {
    for (const core::CameraFrame& cf : frame) {
      tracker::AddResult r = trk->Add(cf);
      for (auto& f : r.finalized) output.push_back(std::move(f));
      inspect();
    }
  }
  for (auto& f : trk->Flush()) output.push_back(std::move(f));
  inspect();

  // ---- 2D tracking: consecutive detections of one person in one camera.
  // Person -> (camera -> frame -> 2D track).
  std::map<std::int64_t, std::map<CameraId, std::map<FrameIndex, TrackId2D>>> by_person;
  int switches2d = 0;
  for (const auto& [key, frames] : track2d) {
    std::int64_t prev = -10;
    for (const auto& [f, l] : frames) {
      if (l >= 0) by_person[l][key.first][f] = key.second;
      if (prev >= 0 && l >= 0 && l != prev) ++switches2d;
      if (l >= 0) prev = l;
    }
  }
  // Each 2D switch (p at the track's previous labelled frame, q at this one): was p detected
  // in that camera at this frame (its track left it for q) or missed? Was q tracked before?
  std::map<std::string, int> switch_kinds;
  for (const auto& [key, frames] : track2d) {
    std::int64_t prev = -10;
    FrameIndex prev_frame = 0;
    for (const auto& [f, l] : frames) {
      if (prev >= 0 && l >= 0 && l != prev) {
        const auto pit = by_person.find(prev);
        const bool p_seen = pit != by_person.end() && pit->second.count(key.first) &&
                            pit->second.at(key.first).count(f);
        const auto qit = by_person.find(l);
        bool q_before = false;
        if (qit != by_person.end() && qit->second.count(key.first)) {
          const auto& qf = qit->second.at(key.first);
          const auto it = qf.lower_bound(f);
          q_before = it != qf.begin() && std::prev(it)->first >= prev_frame;
        }
        ++switch_kinds[std::string(p_seen ? "its person detected" : "its person missed") +
                       (q_before ? ", the other person tracked just before"
                                 : ", the other person new in this camera")];
      }
      if (l >= 0) {
        prev = l;
        prev_frame = f;
      }
    }
  }
  int continued = 0, broken = 0;
  for (const auto& [person, cams] : by_person) {
    for (const auto& [cam, frames] : cams) {
      const std::pair<const FrameIndex, TrackId2D>* prev = nullptr;
      for (const auto& entry : frames) {
        if (prev != nullptr && entry.first - prev->first <= 1) {
          (entry.second == prev->second ? continued : broken) += 1;
        }
        prev = &entry;
      }
    }
  }
  std::printf(
      "2D tracking: consecutive frames of one person in one camera: %d continued, %d broken"
      " (%.1f %%); 2D tracks passing to another person: %d\n",
      continued,
      broken,
      100.0 * broken / std::max(1, continued + broken),
      switches2d);

  for (const auto& [k, n] : switch_kinds) std::printf("  2D switches, %s: %d\n", k.c_str(), n);

  // ---- Output: GT <-> output per frame (kept matches first, then min-cost).
  std::map<FrameIndex, const tracker::Frame3D*> out_by_frame;
  for (const auto& f : output) out_by_frame[f.frame] = &f;
  std::map<std::int64_t, TrackId3D> last_match;  // GT -> last output id
  std::map<TrackId3D, std::int64_t> id_person;   // output id -> person of most matches
  std::map<TrackId3D, std::map<std::int64_t, int>> id_votes;
  struct Switch {
    FrameIndex frame;
    std::int64_t person;
    TrackId3D from, to;
  };
  std::vector<Switch> switches;
  const double gate = args.threshold_m;
  for (const auto& g : ds.ground_truth) {
    const auto it = out_by_frame.find(g.frame);
    std::vector<const tracker::Track3D*> preds;
    if (it != out_by_frame.end()) {
      for (const auto& t : it->second->tracks) preds.push_back(&t);
    }
    std::vector<int> gt_match(g.objects.size(), -1);
    std::vector<bool> used(preds.size(), false);
    auto dist = [&](std::size_t gi, std::size_t pi) {
      return std::hypot(g.objects[gi].position.x() - preds[pi]->position.x(),
                        g.objects[gi].position.y() - preds[pi]->position.y());
    };
    for (std::size_t gi = 0; gi < g.objects.size(); ++gi) {
      const auto lm = last_match.find(g.objects[gi].id);
      if (lm == last_match.end()) continue;
      for (std::size_t pi = 0; pi < preds.size(); ++pi) {
        if (!used[pi] && preds[pi]->id == lm->second && dist(gi, pi) <= gate) {
          gt_match[gi] = static_cast<int>(pi);
          used[pi] = true;
        }
      }
    }
    Eigen::MatrixXd cost(static_cast<Eigen::Index>(g.objects.size()),
                         static_cast<Eigen::Index>(preds.size()));
    for (std::size_t gi = 0; gi < g.objects.size(); ++gi) {
      for (std::size_t pi = 0; pi < preds.size(); ++pi) {
        cost(static_cast<Eigen::Index>(gi), static_cast<Eigen::Index>(pi)) =
            gt_match[gi] >= 0 || used[pi] ? 1e9 : dist(gi, pi);
      }
    }
    core::Assignment assignment;
    core::AssignmentWorkspace ws;
    core::SolveAssignment(cost, gate, &ws, &assignment);
    for (const auto& [r, c] : assignment.matches) gt_match[static_cast<std::size_t>(r)] = c;
    for (std::size_t gi = 0; gi < g.objects.size(); ++gi) {
      if (gt_match[gi] < 0) continue;
      const TrackId3D id = preds[static_cast<std::size_t>(gt_match[gi])]->id;
      const std::int64_t person = g.objects[gi].id;
      ++id_votes[id][person];
      const auto lm = last_match.find(person);
      if (lm != last_match.end() && lm->second != id)
        switches.push_back({g.frame, person, lm->second, id});
      last_match[person] = id;
    }
  }
  for (const auto& [id, votes] : id_votes) {
    double purity = 0.0;
    id_person[id] = Majority(votes, &purity);
  }

  // First window tracklet of each output id, and the latest of each id before a window.
  std::map<TrackId3D, const WindowPerson*> first_of_id;
  for (const WindowPerson& wp : persons) first_of_id.emplace(wp.track, &wp);
  auto last_before = [&](TrackId3D id, std::int64_t window) -> const WindowPerson* {
    const WindowPerson* best = nullptr;
    for (const WindowPerson& wp : persons) {
      if (wp.track == id && wp.window < window) best = &wp;
    }
    return best;
  };
  std::map<std::string, int> causes;
  for (const Switch& s : switches) {
    std::string cause;
    const WindowPerson* to = first_of_id.count(s.to) ? first_of_id[s.to] : nullptr;
    if (id_person[s.to] != s.person && id_votes[s.to][s.person] * 2 < [&] {
          int n = 0;
          for (const auto& [p, v] : id_votes[s.to]) n += v;
          return n;
        }()) {
      // The window tracklet that gave the person the other person's id.
      const WindowPerson* via = nullptr;
      for (const WindowPerson& wp : persons) {
        if (wp.track == s.to && wp.label == s.person && wp.begin <= s.frame && s.frame < wp.end) {
          via = &wp;
        }
      }
      static const char* const kKinds[] = {
          "birth", "overlap", "gap", "reidentified", "duplicate", "appearance"};
      cause = "swap (the new id is mostly another person's)";
      if (via == nullptr) {
        cause += " via no tracklet of the person";
      } else {
        cause += std::string(" via ") + kKinds[static_cast<int>(via->kind)] +
                 (via->impure_2d ? ", a 2D switch in it"
                                 : (via->purity < 0.999 ? ", mixed cluster" : ", pure cluster"));
      }
    } else if (to == nullptr) {
      cause = "unknown (no window tracklet)";
    } else if (to->purity < 0.999 && to->impure_2d) {
      cause = "2d switch (a 2D tracklet of the new id's first tracklet shows two people)";
    } else if (to->purity < 0.999) {
      cause = "association (the new id's first tracklet mixes people's tracklets)";
    } else {
      const WindowPerson* from = last_before(s.from, to->window + 1);
      if (from == nullptr || from->window < to->window - 3) {
        cause = "gap (the old id was lost for more than 3 windows)";
      } else {
        bool shared = false;
        for (const auto& m : to->members) shared = shared || from->members.count(m) > 0;
        cause = shared ? "linking (a 2D track continued, still a new id)"
                       : "2d (no 2D track continued from the old id)";
      }
    }
    ++causes[cause];
    if (args.verbose) {
      std::printf("  switch frame %lld person %lld: %llu -> %llu: %s\n",
                  static_cast<long long>(s.frame),
                  static_cast<long long>(s.person),
                  static_cast<unsigned long long>(s.from),
                  static_cast<unsigned long long>(s.to),
                  cause.c_str());
    }
  }
  std::printf("identity switches (matched id changes, gate %.2f m): %zu\n", gate, switches.size());
  for (const auto& [c, n] : causes) std::printf("  %4d  %s\n", n, c.c_str());
  // Extra ids.
  std::map<std::int64_t, std::vector<TrackId3D>> ids_of_person;
  int ghosts = 0;
  std::set<TrackId3D> output_ids;
  for (const auto& f : output) {
    for (const auto& t : f.tracks) output_ids.insert(t.id);
  }
  for (const TrackId3D id : output_ids) {
    if (!id_person.count(id) || id_person[id] < 0) {
      ++ghosts;
      continue;
    }
    ids_of_person[id_person[id]].push_back(id);
  }
  int extra = 0;
  std::set<std::int64_t> persons_gt;
  for (const auto& g : ds.ground_truth) {
    for (const auto& o : g.objects) persons_gt.insert(o.id);
  }
  for (const auto& [p, ids] : ids_of_person) extra += static_cast<int>(ids.size()) - 1;
  std::printf(
      "output ids: %zu for %zu people: %d extra ids of tracked people, %d ids matching "
      "nobody (ghosts)\n",
      output_ids.size(),
      persons_gt.size(),
      extra,
      ghosts);
  return 0;
}
