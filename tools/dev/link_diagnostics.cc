// Developer diagnostic (not installed): runs the inline Tracker on a simulated scene and labels
// every window person with the simulator's ground truth, then reports each linking decision
// (overlap link, gap link, birth) as right or wrong with the evidence the linker had. The
// measurements of docs/DECISIONS.md "Window linking" were made with it.
//
//   mvtrack_link_diagnostics --cameras 4 --people 12 --frames 9000 --mode boxes --seed 11
//                            --enter-leave [--embedding-dim 128] [--options tracker.yaml]
//                            [--linger-at X,Y;X,Y] [--linger-s 120] [--dump-window N]
//
// --dump-window N prints window N's PDNC clusters (each 2D tracklet with the person it shows),
// the persons made of them, and Eq. 4 between the tracklets of every person shown in a cluster
// of two or more tracklets, to stderr.
//                            [--decisions out.tsv] [--coverage out.tsv]
//
// --coverage writes, per frame and ground-truth person, the number of cameras that detected it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "association/tracklet_distance.h"
#include "config/tracker_options.h"
#include "core/appearance.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"
#include "sim/scene_presets.h"
#include "tracker/tracker.h"

namespace {

using mvtrack::FrameIndex;
using mvtrack::TrackId3D;
namespace core = mvtrack::core;
namespace sim = mvtrack::sim;
namespace tracker = mvtrack::tracker;
namespace linking = mvtrack::linking;

struct Args {
  int cameras = 4;
  int people = 12;
  int frames = 9000;
  bool poses = false;
  std::uint64_t seed = 11;
  bool enter_leave = false;
  double mean_stay_s = 8.0;
  std::vector<mvtrack::Vec2> linger_spots;
  double mean_linger_s = 120.0;
  int embedding_dim = 0;
  std::string options_file;
  std::string decisions_file;
  std::string coverage_file;
  std::int64_t dump_window = -1;  // print this window's clusters and distances to stderr
};

[[noreturn]] void Usage(const char* why) {
  std::fprintf(stderr, "mvtrack_link_diagnostics: %s\n", why);
  std::exit(2);
}

Args Parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) Usage(("missing value for " + k).c_str());
      return argv[++i];
    };
    if (k == "--cameras") {
      a.cameras = std::stoi(value());
    } else if (k == "--people") {
      a.people = std::stoi(value());
    } else if (k == "--frames") {
      a.frames = std::stoi(value());
    } else if (k == "--mode") {
      const std::string m = value();
      if (m != "boxes" && m != "poses") Usage("--mode must be boxes or poses");
      a.poses = m == "poses";
    } else if (k == "--seed") {
      a.seed = std::stoull(value());
    } else if (k == "--enter-leave") {
      a.enter_leave = true;
    } else if (k == "--mean-stay") {
      a.mean_stay_s = std::stod(value());
    } else if (k == "--linger-at") {  // X,Y;X,Y (as mvtrack sim --linger-at)
      std::string text = value();
      for (char& c : text) c = (c == ';' || c == ',') ? ' ' : c;
      std::istringstream in(text);
      double x = 0.0, y = 0.0;
      while (in >> x >> y) a.linger_spots.emplace_back(x, y);
      if (!in.eof()) Usage("--linger-at: expected X,Y[;X,Y...]");
    } else if (k == "--linger-s") {
      a.mean_linger_s = std::stod(value());
    } else if (k == "--embedding-dim") {
      a.embedding_dim = std::stoi(value());
    } else if (k == "--options") {
      a.options_file = value();
    } else if (k == "--decisions") {
      a.decisions_file = value();
    } else if (k == "--dump-window") {
      a.dump_window = std::stoll(value());
    } else if (k == "--coverage") {
      a.coverage_file = value();
    } else {
      Usage(("unknown argument " + k).c_str());
    }
  }
  return a;
}

// The ground-truth person a window person shows: the GT id nearest to its footprint (within
// 0.5 m) in most of its frames; -1 when no id wins at least half of the frames (a ghost).
// The mean of the person's triangulated points at its f-th frame, if any.
std::optional<mvtrack::Vec3> MeanPoint(const core::Tracklet3D& person, std::size_t f) {
  mvtrack::Vec3 p = mvtrack::Vec3::Zero();
  int n = 0;
  for (const auto& q : person.points[f]) {
    if (q) {
      p += *q;
      ++n;
    }
  }
  if (n == 0) return std::nullopt;
  return mvtrack::Vec3(p / n);
}

int LabelOf(const core::Tracklet3D& person, const std::map<FrameIndex, sim::FrameTruth>& truth) {
  std::map<int, int> votes;
  int frames = 0;
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    const auto it = truth.find(person.frames[f]);
    if (it == truth.end()) continue;
    const std::optional<mvtrack::Vec3> mean_point = MeanPoint(person, f);
    if (!mean_point) continue;
    const mvtrack::Vec3& p = *mean_point;
    ++frames;
    double best = 0.5;
    int id = -1;
    for (const sim::PersonTruth& g : it->second.people) {
      const double d = std::hypot(g.footprint_m.x() - p.x(), g.footprint_m.y() - p.y());
      if (d <= best) {
        best = d;
        id = g.id;
      }
    }
    if (id >= 0) ++votes[id];
  }
  int best_id = -1;
  int best_votes = 0;
  for (const auto& [id, v] : votes) {
    if (v > best_votes) {
      best_votes = v;
      best_id = id;
    }
  }
  return 2 * best_votes >= frames && frames > 0 ? best_id : -1;
}

// Median over the person's frames of the distance to the nearest GT footprint, and the mean
// footprint.
void Describe(const core::Tracklet3D& person,
              const std::map<FrameIndex, sim::FrameTruth>& truth,
              double* median_gt_distance,
              mvtrack::Vec3* mean) {
  std::vector<double> d;
  *mean = mvtrack::Vec3::Zero();
  int frames = 0;
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    const std::optional<mvtrack::Vec3> mean_point = MeanPoint(person, f);
    if (!mean_point) continue;
    const mvtrack::Vec3& p = *mean_point;
    *mean += p;
    ++frames;
    const auto it = truth.find(person.frames[f]);
    if (it == truth.end()) continue;
    double best = 1e9;
    for (const sim::PersonTruth& g : it->second.people) {
      best = std::min(best, std::hypot(g.footprint_m.x() - p.x(), g.footprint_m.y() - p.y()));
    }
    d.push_back(best);
  }
  if (frames > 0) *mean /= frames;
  std::sort(d.begin(), d.end());
  *median_gt_distance = d.empty() ? -1.0 : d[d.size() / 2];
}

int SharedMembers(const std::vector<core::TrackletMember>& a,
                  const std::vector<core::TrackletMember>& b) {
  int n = 0;
  for (const auto& x : a) {
    for (const auto& y : b) n += (x.camera_id == y.camera_id && x.track_id == y.track_id) ? 1 : 0;
  }
  return n;
}

struct TrackInfo {
  int label = -1;
  std::vector<core::TrackletMember> members;
  core::Tracklet3D last;
  FrameIndex last_frame = 0;
  std::vector<std::vector<float>> gallery;  // the last 16 tracklet descriptors
};

}  // namespace

int main(int argc, char** argv) {
  const Args args = Parse(argc, argv);
  sim::SceneOptions o = sim::SizedScene(args.cameras, args.people, args.poses, args.seed);
  o.num_frames = args.frames;
  o.enter_and_leave = args.enter_leave;
  o.mean_stay_s = args.mean_stay_s;
  o.linger_spots = args.linger_spots;
  o.mean_linger_s = args.mean_linger_s;
  o.embedding_dim = args.embedding_dim;
  std::string why;
  if (!o.Validate(&why)) Usage(why.c_str());
  const std::vector<mvtrack::geometry::CameraModel> cameras = sim::MakeCameras(o);

  tracker::TrackerOptions topt;
  topt.mode = args.poses ? tracker::InputMode::kPoses : tracker::InputMode::kBoxes;
  if (!args.options_file.empty()) {
    try {
      const tracker::InputMode mode = topt.mode;
      topt = mvtrack::config::LoadTrackerOptionsFile(args.options_file);
      topt.mode = mode;
    } catch (const std::exception& e) {
      Usage(e.what());
    }
  }
  auto trk = tracker::Tracker::Create(mvtrack::geometry::CameraRig(cameras), topt, &why);
  if (!trk) Usage(why.c_str());

  std::ofstream decisions;
  if (!args.decisions_file.empty()) {
    decisions.open(args.decisions_file);
    decisions
        << "window\tbegin\tperson\tlabel\tkind\ttrack\ttrack_label\tverdict\tdistance\t"
           "shared\tmembers\ttrack_members\tmotion_d2\tgap_frames\tx\ty\tz\tgt_"
           "distance\tframes\tcameras\tz0\tz1\tz2\tapp_gallery\tapp_same_label\tmember_list\n";
  }

  std::map<FrameIndex, sim::FrameTruth> truth;
  // (frame, camera) -> rendered detections: box centre and the person shown (-1: false positive).
  std::map<std::pair<FrameIndex, int>, std::vector<std::pair<mvtrack::Vec2, int>>> rendered;
  // The person a 2D tracklet shows: majority over its observations (matched to the rendered
  // detection with the same box centre), -1 for false positives, -2 when unmatched.
  auto label_2d = [&](const core::Tracklet2D& t) {
    std::map<int, int> votes;
    for (std::size_t f = 0; f < t.frames.size(); ++f) {
      const auto it = rendered.find({t.frames[f], t.camera_id});
      if (it == rendered.end() || t.observations[f].points_px.empty()) continue;
      int id = -2;
      double best = 1e-3;
      for (const auto& [c, pid] : it->second) {
        const double d = (c - t.observations[f].points_px[0]).norm();
        if (d < best) {
          best = d;
          id = pid;
        }
      }
      ++votes[id];
    }
    int best_id = -2;
    int best_votes = 0;
    for (const auto& [id, v] : votes) {
      if (v > best_votes) {
        best_votes = v;
        best_id = id;
      }
    }
    return best_id;
  };
  std::map<TrackId3D, TrackInfo> tracks;
  std::set<int> ever;
  std::map<int, FrameIndex> last_seen_of_label;
  std::map<std::string, int> counts;
  std::int64_t last_window = -1;
  sim::CrowdSimulator crowd(o);

  auto inspect = [&](const tracker::WindowOutput& w) {
    if (w.window_id == args.dump_window) {
      auto name = [&](int i) {
        const core::Tracklet2D& t = w.tracklets[static_cast<std::size_t>(i)];
        return std::to_string(t.camera_id) + ":" + std::to_string(t.track_id) + "[" +
               std::to_string(t.frames.front()) + "-" + std::to_string(t.frames.back()) +
               "]=" + std::to_string(label_2d(t));
      };
      std::fprintf(stderr,
                   "window %lld [%lld, %lld)\n",
                   static_cast<long long>(w.window_id),
                   static_cast<long long>(w.begin),
                   static_cast<long long>(w.end));
      std::set<int> shown;  // people shown by a cluster of two or more tracklets
      for (std::size_t c = 0; c < w.clusters.size(); ++c) {
        std::fprintf(stderr, "  cluster %zu:", c);
        for (const int i : w.clusters[c]) {
          std::fprintf(stderr, " %s", name(i).c_str());
          if (w.clusters[c].size() >= 2)
            shown.insert(label_2d(w.tracklets[static_cast<std::size_t>(i)]));
        }
        std::fprintf(stderr, "\n");
      }
      for (std::size_t p = 0; p < w.persons.size(); ++p) {
        std::fprintf(stderr, "  person %zu (label %d):", p, LabelOf(w.persons[p], truth));
        for (const int i : w.persons[p].source_tracklets)
          std::fprintf(stderr, " %s", name(i).c_str());
        std::fprintf(stderr, "\n");
      }
      const mvtrack::association::AssociationOptions ao = tracker::AssociationOptionsInEffect(topt);
      const auto d = mvtrack::association::ComputeDistanceMatrix(
          mvtrack::geometry::CameraRig(cameras), w.tracklets, ao);
      const int n = static_cast<int>(w.tracklets.size());
      for (const int label : shown) {
        if (label < 0) continue;
        std::vector<int> of;
        for (int i = 0; i < n; ++i) {
          if (label_2d(w.tracklets[static_cast<std::size_t>(i)]) == label) of.push_back(i);
        }
        std::fprintf(stderr,
                     "  Eq. 4 between the tracklets of person %d (lambda %.3f):\n",
                     label,
                     ao.lambda);
        for (std::size_t a = 0; a < of.size(); ++a) {
          for (std::size_t b = a + 1; b < of.size(); ++b) {
            const auto v = d.at(of[a], of[b]);
            const std::string text =
                v.kind == mvtrack::association::TrackletDistance::Kind::kValue
                    ? std::to_string(v.value)
                    : (v.kind == mvtrack::association::TrackletDistance::Kind::kEmpty ? "empty"
                                                                                      : "inf");
            std::fprintf(
                stderr, "    %s  %s  %s\n", name(of[a]).c_str(), name(of[b]).c_str(), text.c_str());
          }
        }
      }
    }
    const linking::LinkResult& link = w.link;
    std::set<TrackId3D> linked_now;
    std::map<int, int> persons_of_label;
    for (std::size_t i = 0; i < w.persons.size(); ++i) {
      if (link.link_kind[i] != linking::LinkKind::kBirth)
        linked_now.insert(link.track_of_tracklet[i]);
      ++persons_of_label[LabelOf(w.persons[i], truth)];
    }
    for (std::size_t i = 0; i < w.persons.size(); ++i) {
      const core::Tracklet3D& person = w.persons[i];
      const int label = LabelOf(person, truth);
      const TrackId3D id = link.track_of_tracklet[i];
      const linking::LinkKind kind = link.link_kind[i];
      std::string verdict;
      std::string kind_name;
      int shared = -1;
      int track_members = 0;
      int track_label = -1;
      std::int64_t gap = 0;
      double motion_d2 = std::nan("");
      double overlap_d = std::nan("");  // a fragment's Eq. 8 distance to its person's track
      if (kind == linking::LinkKind::kBirth) {
        kind_name = "birth";
        if (label < 0) {
          verdict = "ghost";
        } else if (persons_of_label[label] > 1) {
          verdict = "duplicate";
        } else if (ever.count(label) == 0) {
          verdict = "new";
        } else {
          // The person had a track before: alive (lost) now, or ended.
          const linking::LinkedTrack* old = nullptr;
          for (const linking::LinkedTrack& t : trk->linker().tracks()) {
            if (t.id != id && tracks.count(t.id) && tracks[t.id].label == label &&
                linked_now.count(t.id) == 0) {
              old = &t;
            }
          }
          if (old == nullptr) {
            verdict = "fragment_dead";
            gap = person.frames.front() - last_seen_of_label[label];
          } else {
            verdict = "fragment_alive";
            if (const auto ov = linking::MeanOverlapDistance(old->last_tracklet, person)) {
              overlap_d = *ov;
            }
            shared = linking::SharedMembers(old->members, person);
            track_members = static_cast<int>(old->members.size());
            gap = person.frames.front() - old->last_seen_frame;
            const auto init = linking::InitialMotion(person,
                                                     trk->linker().context(),
                                                     trk->linker().options().motion,
                                                     trk->linker().seconds_per_frame());
            FrameIndex first = 0;
            for (std::size_t f = 0; f < person.frames.size(); ++f) {
              if (linking::FrameFootprint(person.points[f],
                                          trk->linker().context().footprint_points)) {
                first = person.frames[f];
                break;
              }
            }
            if (init) {
              const auto pred = trk->linker().PredictedMotion(*old, first);
              motion_d2 = linking::StateDistanceSquared(pred, *init);
            }
          }
          track_label = label;
        }
      } else {
        kind_name = kind == linking::LinkKind::kOverlap      ? "overlap"
                    : kind == linking::LinkKind::kGap        ? "gap"
                    : kind == linking::LinkKind::kDuplicate  ? "duplicate"
                    : kind == linking::LinkKind::kAppearance ? "appearance"
                                                             : "reid";
        const TrackInfo& info = tracks[id];
        track_label = info.label;
        shared = SharedMembers(info.members, person.members);
        track_members = static_cast<int>(info.members.size());
        gap = person.frames.front() - info.last_frame;
        if (label < 0 || info.label < 0) {
          verdict = "ghost";
        } else {
          verdict = label == info.label ? "right" : "WRONG";
        }
      }
      ++counts[kind_name + "/" + verdict];
      if (shared >= 0) {
        ++counts[kind_name + "/" + verdict + "/shared" + std::to_string(std::min(shared, 3))];
      }
      if (decisions.is_open()) {
        decisions << w.window_id << '\t' << w.begin << '\t' << i << '\t' << label << '\t'
                  << kind_name << '\t' << id << '\t' << track_label << '\t' << verdict << '\t'
                  << (kind == linking::LinkKind::kBirth ? overlap_d : link.link_distance_m[i])
                  << '\t' << shared << '\t' << person.members.size() << '\t' << track_members
                  << '\t'
                  << (kind == linking::LinkKind::kGap || kind == linking::LinkKind::kReidentified
                          ? link.link_distance_m[i]
                          : motion_d2)
                  << '\t' << gap;
        double gd = 0.0;
        mvtrack::Vec3 mean;
        Describe(person, truth, &gd, &mean);
        decisions << '\t' << mean.x() << '\t' << mean.y() << '\t' << mean.z() << '\t' << gd << '\t'
                  << person.frames.size() << '\t' << person.cameras.size();
        // Median height of every point index (box center_ends: centre, feet, head).
        for (std::size_t k = 0; k < 3; ++k) {
          std::vector<double> z;
          for (const auto& row : person.points) {
            if (k < row.size() && row[k]) z.push_back(row[k]->z());
          }
          std::sort(z.begin(), z.end());
          decisions << '\t' << (z.empty() ? std::nan("") : z[z.size() / 2]);
        }
        // Appearance distance to the track's previous tracklet (NaN without descriptors).
        const auto prev = tracks.find(id);
        const bool has_prev = kind != linking::LinkKind::kBirth && prev != tracks.end() &&
                              !prev->second.gallery.empty() && !person.appearance.empty();
        decisions << '\t'
                  << (has_prev ? core::GalleryDistance(prev->second.gallery, person.appearance)
                               : std::nan(""));
        // The nearest gallery of another track whose last label is this person's.
        double right = std::nan("");
        for (const auto& [tid, ti] : tracks) {
          if (tid == id || ti.label != label || label < 0 || ti.gallery.empty() ||
              person.appearance.empty()) {
            continue;
          }
          const double d = core::GalleryDistance(ti.gallery, person.appearance);
          if (!(d >= right)) right = d;
        }
        decisions << '\t' << right;
        decisions << '\t';
        for (int ti : person.source_tracklets) {
          const core::Tracklet2D& t = w.tracklets[static_cast<std::size_t>(ti)];
          decisions << t.camera_id << ':' << t.track_id << '[' << t.frames.front() << '-'
                    << t.frames.back() << "]=" << label_2d(t) << ' ';
        }
        decisions << '\n';
      }
      if (label >= 0) {
        ever.insert(label);
        last_seen_of_label[label] = std::max(last_seen_of_label[label], person.frames.back());
      }
      TrackInfo& info = tracks[id];
      info.label = label;
      info.members = person.members;
      info.last = person;
      info.last_frame = person.frames.back();
      if (!person.appearance.empty()) {
        if (info.gallery.size() >= 16) info.gallery.erase(info.gallery.begin());
        info.gallery.push_back(person.appearance);
      }
    }
    (void)0;
  };

  std::ofstream coverage;
  if (!args.coverage_file.empty()) {
    coverage.open(args.coverage_file);
    coverage << "frame\tid\tx\ty\tcameras\n";
  }
  for (int f = 0; f < o.num_frames; ++f) {
    sim::FrameTruth t = crowd.Next();
    const sim::RenderedFrame r = sim::RenderFrame(o, cameras, t);
    if (coverage.is_open()) {
      for (const sim::PersonTruth& g : t.people) {
        int seen = 0;
        for (const std::vector<int>& ids : r.person_ids) {
          seen += std::count(ids.begin(), ids.end(), g.id) > 0 ? 1 : 0;
        }
        coverage << t.frame << '\t' << g.id << '\t' << g.footprint_m.x() << '\t'
                 << g.footprint_m.y() << '\t' << seen << '\n';
      }
    }
    for (std::size_t c = 0; c < r.cameras.size(); ++c) {
      auto& dets = rendered[{t.frame, r.cameras[c].camera_id}];
      for (std::size_t d = 0; d < r.cameras[c].detections.size(); ++d) {
        dets.push_back({r.cameras[c].detections[d].box.center(), r.person_ids[c][d]});
      }
    }
    truth[t.frame] = std::move(t);
    for (const core::CameraFrame& cf : r.cameras) {
      trk->Add(cf);
      const auto& w = trk->last_window();
      if (w && w->window_id != last_window) {
        last_window = w->window_id;
        inspect(*w);
      }
    }
    // Keep the truth of the frames windows can still cover.
    while (!truth.empty() && truth.begin()->first < f - 200) truth.erase(truth.begin());
    while (!rendered.empty() && rendered.begin()->first.first < f - 200) {
      rendered.erase(rendered.begin());
    }
  }
  for (const auto& [k, v] : counts) std::printf("%-32s %d\n", k.c_str(), v);
  return 0;
}
