#include "tracker/window_job.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>

#include "association/association.h"
#include "core/check.h"
#include "linking/window_linker.h"
#include "triangulation/refinement.h"

namespace mvtrack::tracker {
namespace {

bool SameTriangulationOptions(const triangulation::TriangulationOptions& a,
                              const triangulation::TriangulationOptions& b) {
  // phi is set per window (PersonTriangulator::set_phi, AtFrameRate).
  return a.method == b.method && a.kappa_m == b.kappa_m && a.min_confidence == b.min_confidence &&
         a.ransac_threshold_px == b.ransac_threshold_px && a.min_inliers == b.min_inliers &&
         a.max_views == b.max_views;
}

// Box mode: removes a person's points outside the plausible heights of a box point
// (RefinementOptions::box_min_height_m, box_max_height_m above the floor; center_ends: the
// centre's range, the ends were gated by TriangulateBoxEnds).
void GateBoxHeights(const TrackerOptions& options, core::Tracklet3D* person) {
  const triangulation::RefinementOptions& r = options.refinement;
  const double g = options.ground_height_m;
  triangulation::RemovePointsOutsideHeights(person, g + r.box_min_height_m, g + r.box_max_height_m);
}

// One person of `cluster`: CMMT (Algorithm 2) of the points it triangulates; in box mode the
// ends by DLT (center_ends) and the height gates.
core::Tracklet3D TriangulateCluster(const geometry::CameraRig& rig,
                                    const TrackerOptions& options,
                                    const WindowJob& job,
                                    const std::vector<int>& cluster,
                                    WindowWorkspace* workspace) {
  // `options` are the window's (AtFrameRate): φ follows the stream's frame rate.
  workspace->triangulator().set_phi(options.triangulation.phi);
  core::Tracklet3D person = workspace->triangulator().Triangulate(rig,
                                                                  job.tracklets,
                                                                  cluster,
                                                                  job.begin,
                                                                  job.end,
                                                                  NumTriangulatedPoints(options),
                                                                  nullptr,
                                                                  NumPoints(options));
  if (options.mode != InputMode::kBoxes) return person;
  if (options.box_point == BoxPoint::kCenterEnds) {
    const triangulation::RefinementOptions& r = options.refinement;
    const double g = options.ground_height_m;
    std::vector<triangulation::HeightRange> ranges(2);
    ranges[0] = {g + r.box_bottom_min_height_m, g + r.box_bottom_max_height_m};
    ranges[1] = {g + r.box_top_min_height_m, g + r.box_top_max_height_m};
    triangulation::TriangulateBoxEnds(rig,
                                      job.tracklets,
                                      cluster,
                                      kBoxBottomPoint,
                                      ranges,
                                      options.association.min_confidence,
                                      &person);
  }
  GateBoxHeights(options, &person);
  return person;
}

// Number of distinct cameras among the tracklets `members` of the job.
int NumCameras(const WindowJob& job, const std::vector<int>& members) {
  std::vector<CameraId> cams;
  cams.reserve(members.size());
  for (int i : members) cams.push_back(job.tracklets[static_cast<std::size_t>(i)].camera_id);
  std::sort(cams.begin(), cams.end());
  return static_cast<int>(std::unique(cams.begin(), cams.end()) - cams.begin());
}

// Box mode: splits the tracklets a person does not reproject onto (RefinementOptions::
// box_split_residual) off its cluster. When the rest still spans two cameras, the person is
// triangulated again from it; the split-off tracklets, when they span two cameras, are
// triangulated as a new person (appended). Persons are examined in order, new ones are not.
void SplitInconsistent(const geometry::CameraRig& rig,
                       const TrackerOptions& options,
                       const WindowJob& job,
                       WindowWorkspace* workspace,
                       std::vector<std::vector<int>>* clusters,
                       std::vector<core::Tracklet3D>* persons) {
  const double max_residual = options.refinement.box_split_residual;
  if (max_residual <= 0.0) return;
  const std::size_t n = persons->size();
  for (std::size_t p = 0; p < n; ++p) {
    // The box point only (box_split_residual is a fraction of the box scale at the centre).
    const std::vector<int> out =
        triangulation::InconsistentTracklets(rig,
                                             job.tracklets,
                                             (*clusters)[p],
                                             (*persons)[p],
                                             max_residual,
                                             options.association.min_confidence,
                                             NumTriangulatedPoints(options));
    if (out.empty()) continue;
    std::vector<int> keep;
    for (int i : (*clusters)[p]) {
      if (!std::binary_search(out.begin(), out.end(), i)) keep.push_back(i);
    }
    if (NumCameras(job, keep) < 2) continue;
    core::Tracklet3D kept = TriangulateCluster(rig, options, job, keep, workspace);
    if (kept.frames.empty()) continue;
    (*clusters)[p] = std::move(keep);
    (*persons)[p] = std::move(kept);
    if (NumCameras(job, out) < 2) continue;
    core::Tracklet3D other = TriangulateCluster(rig, options, job, out, workspace);
    if (other.frames.empty()) continue;
    clusters->push_back(out);
    persons->push_back(std::move(other));
  }
}

// The first frame where `person`'s footprint breaks the motion model: at a boundary between
// two consecutive triangulated frames where the footprint moves more than 0.25 m, the state
// (position, velocity) filtered forward over the frames before it and the one filtered
// backward over the frames from it on (linking::FloorMotion with the linker's noise) disagree
// by more than
// RefinementOptions::jump_gate_chi2 (squared Mahalanobis distance). A person who walks,
// turns or stops stays within it; two people whose tracklets association joined (one
// leaving while another arrives) do not. nullopt without a jump.
std::optional<FrameIndex> FirstJump(const TrackerOptions& options,
                                    const std::vector<int>& footprint_points,
                                    double seconds_per_frame,
                                    const core::Tracklet3D& person) {
  const double gate = options.refinement.jump_gate_chi2;
  if (gate <= 0.0) return std::nullopt;
  const linking::MotionOptions& mo = options.linking.motion;
  std::vector<FrameIndex> frames;
  std::vector<Vec2> xy;
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    if (const std::optional<Vec2> p = linking::FrameFootprint(person.points[f], footprint_points)) {
      frames.push_back(person.frames[f]);
      xy.push_back(*p);
    }
  }
  const std::size_t n = xy.size();
  if (n < 2) return std::nullopt;
  // Only a boundary where the footprint moves by more than this between two triangulated
  // frames can be where two people were joined; elsewhere the motion test is not run (a
  // smooth but sharply accelerating footprint is one person walking).
  constexpr double kMinJumpStepM = 0.25;
  bool any_step = false;
  for (std::size_t k = 1; k < n && !any_step; ++k) {
    any_step = (xy[k] - xy[k - 1]).squaredNorm() > kMinJumpStepM * kMinJumpStepM;
  }
  if (!any_step) return std::nullopt;
  const auto dt = [&](std::size_t from, std::size_t to) {
    return (static_cast<double>(frames[to]) - static_cast<double>(frames[from])) *
           seconds_per_frame;
  };
  // forward[i]: filtered over frames [0, i]; backward[i]: over frames [i, n).
  std::vector<linking::FloorMotion> forward(n);
  std::vector<linking::FloorMotion> backward(n);
  forward[0] = linking::FloorMotion::Start(xy[0], mo);
  for (std::size_t i = 1; i < n; ++i) {
    forward[i] = forward[i - 1];
    forward[i].Predict(dt(i - 1, i), mo);
    forward[i].Update(xy[i], mo);
  }
  backward[n - 1] = linking::FloorMotion::Start(xy[n - 1], mo);
  for (std::size_t i = n - 1; i-- > 0;) {
    backward[i] = backward[i + 1];
    backward[i].Predict(dt(i + 1, i), mo);
    backward[i].Update(xy[i], mo);
  }
  for (std::size_t k = 1; k < n; ++k) {
    if ((xy[k] - xy[k - 1]).squaredNorm() <= kMinJumpStepM * kMinJumpStepM) continue;
    linking::FloorMotion predicted = forward[k - 1];
    predicted.Predict(dt(k - 1, k), mo);
    const double d2 = linking::StateDistanceSquared(predicted, backward[k]);
    if (d2 > gate) return frames[k];
  }
  return std::nullopt;
}

// Splits persons whose footprint jumps (FirstJump): the cluster's tracklets observed mostly
// before the jump and those observed mostly from it on become two clusters, each triangulated
// again when it still spans two cameras (the first in the person's place, the second
// appended; a part that does not is dropped, a person left with neither is removed). A person
// whose every 2D tracklet crosses the jump is kept whole (cutting it in time would leave the
// same 2D tracks in both halves, measured to cost identity on store floors). Parts are
// examined again, so a cluster of three people is cut twice.
void SplitAtJumps(const geometry::CameraRig& rig,
                  const TrackerOptions& options,
                  const WindowJob& job,
                  WindowWorkspace* workspace,
                  std::vector<std::vector<int>>* clusters,
                  std::vector<core::Tracklet3D>* persons) {
  if (options.refinement.jump_gate_chi2 <= 0.0) return;
  const std::vector<int> footprint_points = FootprintPoints(options);
  for (std::size_t p = 0; p < persons->size(); ++p) {
    // Bounded: every cut leaves each part with fewer tracklets than the cluster had.
    const std::optional<FrameIndex> jump =
        FirstJump(options, footprint_points, job.seconds_per_frame, (*persons)[p]);
    if (!jump) continue;
    std::vector<int> before;
    std::vector<int> after;
    for (int i : (*clusters)[p]) {
      const core::Tracklet2D& t = job.tracklets[static_cast<std::size_t>(i)];
      const auto split = std::lower_bound(t.frames.begin(), t.frames.end(), *jump);
      const auto n_before = split - t.frames.begin();
      const auto n_after = t.frames.end() - split;
      (n_before > n_after ? before : after).push_back(i);
    }
    if (before.empty() || after.empty()) continue;  // no 2D track ends there: keep it whole
    const bool keep_before = NumCameras(job, before) >= 2;
    const bool keep_after = NumCameras(job, after) >= 2;
    core::Tracklet3D first;
    core::Tracklet3D second;
    if (keep_before) first = TriangulateCluster(rig, options, job, before, workspace);
    if (keep_after) second = TriangulateCluster(rig, options, job, after, workspace);
    const bool has_first = keep_before && !first.frames.empty();
    const bool has_second = keep_after && !second.frames.empty();
    if (has_first) {
      (*clusters)[p] = std::move(before);
      (*persons)[p] = std::move(first);
      if (has_second) {
        clusters->push_back(std::move(after));
        persons->push_back(std::move(second));
      }
    } else if (has_second) {
      (*clusters)[p] = std::move(after);
      (*persons)[p] = std::move(second);
    } else {
      clusters->erase(clusters->begin() + static_cast<std::ptrdiff_t>(p));
      persons->erase(persons->begin() + static_cast<std::ptrdiff_t>(p));
    }
    --p;  // examine the (new) person at p again
  }
}

// Drops the clusters and persons whose `alive` entry is 0, keeping the order of the rest.
void KeepAlive(const std::vector<char>& alive,
               std::vector<std::vector<int>>* clusters,
               std::vector<core::Tracklet3D>* persons) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < alive.size(); ++i) {
    if (!alive[i]) continue;
    if (kept != i) {
      (*clusters)[kept] = std::move((*clusters)[i]);
      (*persons)[kept] = std::move((*persons)[i]);
    }
    ++kept;
  }
  clusters->resize(kept);
  persons->resize(kept);
}

// A cheap test before ReprojectionResidual: at the middle frame `tracklet` and `person` share,
// the person's box point projects farther than one box scale |w + h| from the tracklet's
// observation (it cannot fit within a fraction of it). False without a shared frame.
bool FarInImage(const geometry::CameraRig& rig,
                const core::Tracklet2D& tracklet,
                const core::Tracklet3D& person) {
  std::size_t shared = 0;
  for (const FrameIndex f : tracklet.frames) shared += person.IndexOf(f) >= 0 ? 1 : 0;
  if (shared == 0) return false;
  std::size_t k = shared / 2;
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    const int at = person.IndexOf(tracklet.frames[f]);
    if (at < 0) continue;
    if (k-- > 0) continue;
    const core::Observation2D& obs = tracklet.observations[f];
    const auto& row = person.points[static_cast<std::size_t>(at)];
    if (row.empty() || !row[0] || obs.points_px.empty() || !(obs.scale_px > 0.0)) return false;
    const std::optional<int> c = rig.IndexOf(tracklet.camera_id);
    if (!c) return false;
    const std::optional<Vec2> x = rig.camera(*c).ProjectUndistorted(*row[0]);
    if (!x) return true;  // behind the camera
    return (*x - obs.points_px[0]).norm() > obs.scale_px;
  }
  return false;
}

// Merges persons of one window that are one person split by association: in pose mode when their
// common joints lie within refinement.merge_distance_m on average (PointDistance), in box mode
// when their footprints lie within refinement.box_merge_distance_m (median, FootprintDistance),
// each over at least min_duplicate_pairs common points / box_min_duplicate_frames frames. The
// closest such pair first, its clusters united and triangulated again, until no pair qualifies.
// Keeps the order of first members. Pair distances are computed once (pairs whose ground-plane
// rectangles are farther apart than the limit cannot qualify and are skipped) and afterwards only
// the merged person's.
void MergeDuplicates(const geometry::CameraRig& rig,
                     const TrackerOptions& options,
                     const WindowJob& job,
                     WindowWorkspace* workspace,
                     std::vector<std::vector<int>>* clusters,
                     std::vector<core::Tracklet3D>* persons) {
  const triangulation::RefinementOptions& ro = options.refinement;
  const bool boxes = options.mode == InputMode::kBoxes;
  const double limit = boxes ? ro.box_merge_distance_m : ro.merge_distance_m;
  if (limit <= 0.0 || persons->size() < 2) return;
  const std::size_t n = persons->size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Ground-plane bounding rectangle of a person's points {x_min, y_min, x_max, y_max}: every
  // point distance (and footprint distance) between two persons is at least their rectangles'.
  auto rectangle = [](const core::Tracklet3D& person) {
    std::array<double, 4> r{kInf, kInf, -kInf, -kInf};
    for (const auto& row : person.points) {
      for (const std::optional<Vec3>& p : row) {
        if (!p) continue;
        r[0] = std::min(r[0], p->x());
        r[1] = std::min(r[1], p->y());
        r[2] = std::max(r[2], p->x());
        r[3] = std::max(r[3], p->y());
      }
    }
    return r;
  };
  std::vector<std::array<double, 4>> rects;
  rects.reserve(n);
  for (const core::Tracklet3D& person : *persons) rects.push_back(rectangle(person));
  // The merge distance of persons i and j, +infinity when they do not qualify.
  auto distance = [&](std::size_t i, std::size_t j) {
    const std::array<double, 4>& a = rects[i];
    const std::array<double, 4>& b = rects[j];
    const double gap_x = std::max({0.0, a[0] - b[2], b[0] - a[2]});
    const double gap_y = std::max({0.0, a[1] - b[3], b[1] - a[3]});
    if (!(gap_x * gap_x + gap_y * gap_y <= limit * limit)) return kInf;
    std::int64_t pairs = 0;
    const double d = boxes ? triangulation::FootprintDistance((*persons)[i], (*persons)[j], &pairs)
                           : triangulation::PointDistance((*persons)[i], (*persons)[j], &pairs);
    const int min_pairs = boxes ? ro.box_min_duplicate_frames : ro.min_duplicate_pairs;
    return pairs >= min_pairs && d <= limit ? d : kInf;
  };
  std::vector<double> dist(n * n, kInf);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) dist[i * n + j] = distance(i, j);
  }
  std::vector<char> alive(n, 1);
  while (true) {
    double best = kInf;
    std::size_t bi = 0;
    std::size_t bj = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!alive[i]) continue;
      for (std::size_t j = i + 1; j < n; ++j) {
        if (alive[j] && dist[i * n + j] < best) {
          best = dist[i * n + j];
          bi = i;
          bj = j;
        }
      }
    }
    if (!std::isfinite(best)) break;
    std::vector<int> merged = (*clusters)[bi];
    merged.insert(merged.end(), (*clusters)[bj].begin(), (*clusters)[bj].end());
    std::sort(merged.begin(), merged.end());
    core::Tracklet3D person = TriangulateCluster(rig, options, job, merged, workspace);
    alive[bj] = 0;
    // The union can lose every point (more candidates that disagree): the first stays as is.
    if (person.frames.empty()) continue;
    (*clusters)[bi] = std::move(merged);
    (*persons)[bi] = std::move(person);
    rects[bi] = rectangle((*persons)[bi]);
    for (std::size_t k = 0; k < n; ++k) {
      if (k == bi || !alive[k]) continue;
      const double d = distance(std::min(k, bi), std::max(k, bi));
      dist[std::min(k, bi) * n + std::max(k, bi)] = d;
    }
  }
  KeepAlive(alive, clusters, persons);
}

// Box mode: whether `person` stands on cut boxes (core::Observation2D::cut_edges): in fewer
// than half of its frames do two cameras of `cluster` see it uncut. Triangulated from the cut
// boxes' displaced centres, such a person lies off the real one.
bool StandsOnCutBoxes(const WindowJob& job,
                      const std::vector<int>& cluster,
                      const core::Tracklet3D& person) {
  std::size_t supported = 0;
  std::vector<CameraId> cams;
  for (const FrameIndex frame : person.frames) {
    cams.clear();
    for (const int i : cluster) {
      const core::Tracklet2D& t = job.tracklets[static_cast<std::size_t>(i)];
      const int at = t.IndexOf(frame);
      if (at >= 0 && t.observations[static_cast<std::size_t>(at)].cut_edges == 0) {
        cams.push_back(t.camera_id);
      }
    }
    std::sort(cams.begin(), cams.end());
    if (std::unique(cams.begin(), cams.end()) - cams.begin() >= 2) ++supported;
  }
  return 2 * supported < person.frames.size();
}

// Box mode: a person that stands on cut boxes (StandsOnCutBoxes) is merged into the nearest
// person (FootprintDistance at most kMaxCutMergeDistanceM over box_min_duplicate_frames
// common frames) that does not and onto whom every one of its tracklets reprojects
// (ReprojectionResidual, which forgives the displacement past a cut edge, at most
// box_split_residual): the same person, seen whole by other cameras, that association could
// not join because the cut boxes' centres lie off their epipolar lines. The merged person keeps
// its own triangulation (its whole views put it where it is; re-triangulating with the cut
// views pulls it off, measured in docs/DECISIONS.md) and takes the cut tracklets as sources
// (members for linking, embeddings for appearance). Persons are examined in order; a person no
// one explains stays (it may be somebody only cut boxes see).
void MergeCutPersons(const geometry::CameraRig& rig,
                     const TrackerOptions& options,
                     const WindowJob& job,
                     std::vector<std::vector<int>>* clusters,
                     std::vector<core::Tracklet3D>* persons) {
  // A cut box displaces its centre by half the cut-off part: on a ceiling grid up to about a
  // body length on the floor.
  constexpr double kMaxCutMergeDistanceM = 1.0;
  const triangulation::RefinementOptions& ro = options.refinement;
  if (ro.box_split_residual <= 0.0 || persons->size() < 2) return;
  const std::size_t n = persons->size();
  std::vector<char> on_cut(n, 0);
  for (std::size_t p = 0; p < n; ++p) {
    on_cut[p] = StandsOnCutBoxes(job, (*clusters)[p], (*persons)[p]) ? 1 : 0;
  }
  std::vector<char> alive(n, 1);
  for (std::size_t p = 0; p < n; ++p) {
    if (!on_cut[p]) continue;
    std::size_t best = n;
    double best_d = kMaxCutMergeDistanceM;
    for (std::size_t q = 0; q < n; ++q) {
      if (q == p || on_cut[q] || !alive[q]) continue;
      std::int64_t frames = 0;
      const double d = triangulation::FootprintDistance((*persons)[p], (*persons)[q], &frames);
      if (frames < ro.box_min_duplicate_frames || !(d <= best_d)) continue;
      const std::vector<int> out =
          triangulation::InconsistentTracklets(rig,
                                               job.tracklets,
                                               (*clusters)[p],
                                               (*persons)[q],
                                               ro.box_split_residual,
                                               options.association.min_confidence,
                                               NumTriangulatedPoints(options));
      if (!out.empty()) continue;
      best = q;
      best_d = d;
    }
    if (best == n) continue;
    std::vector<int> merged = (*clusters)[best];
    merged.insert(merged.end(), (*clusters)[p].begin(), (*clusters)[p].end());
    std::sort(merged.begin(), merged.end());
    // The person keeps its triangulation (from its whole views); the cut tracklets join its
    // sources (members, appearance).
    (*persons)[best].source_tracklets = merged;
    (*clusters)[best] = std::move(merged);
    alive[p] = 0;
  }
  KeepAlive(alive, clusters, persons);
}

// Pose mode: fills person->views, per frame the observations of its source tracklets there
// (for the skeleton fit, body::FitJoints).
void SetViews(const geometry::CameraRig& rig, const WindowJob& job, core::Tracklet3D* person) {
  person->views.assign(person->frames.size(), {});
  for (int i : person->source_tracklets) {
    const core::Tracklet2D& t = job.tracklets[static_cast<std::size_t>(i)];
    const std::optional<int> camera = rig.IndexOf(t.camera_id);
    if (!camera) continue;
    for (std::size_t f = 0; f < person->frames.size(); ++f) {
      const int at = t.IndexOf(person->frames[f]);
      if (at < 0) continue;
      person->views[f].push_back({*camera, t.observations[static_cast<std::size_t>(at)]});
    }
  }
}

// Fills person->members from its source tracklets (sorted by camera, then 2D track), each
// with its observations inside the person's frame span.
void SetMembers(const WindowJob& job, core::Tracklet3D* person) {
  person->members.clear();
  if (person->frames.empty()) return;
  person->members.reserve(person->source_tracklets.size());
  const FrameIndex from = person->frames.front();
  const FrameIndex to = person->frames.back();
  for (int i : person->source_tracklets) {
    const core::Tracklet2D& t = job.tracklets[static_cast<std::size_t>(i)];
    const auto first = std::lower_bound(t.frames.begin(), t.frames.end(), from);
    const auto last = std::upper_bound(first, t.frames.end(), to);
    if (first == last) continue;
    person->members.push_back(
        {t.camera_id, t.track_id, *first, *(last - 1), static_cast<int>(last - first)});
  }
  std::sort(person->members.begin(),
            person->members.end(),
            [](const core::TrackletMember& a, const core::TrackletMember& b) {
              return a.camera_id != b.camera_id ? a.camera_id < b.camera_id
                                                : a.track_id < b.track_id;
            });
}

// The height given to a monocular tracklet's box centre (the linker replaces it with the
// track's own when the track continues on it): the middle of a standing adult.
constexpr double kMonocularCenterHeightM = 0.9;

// Box mode, monocular continuation: every tracklet of the job that no person in `persons` was
// triangulated from, placed by its camera alone (WindowResult::monocular).
std::vector<core::Tracklet3D> MonocularTracklets(const geometry::CameraRig& rig,
                                                 const TrackerOptions& options,
                                                 const WindowJob& job,
                                                 const std::vector<core::Tracklet3D>& persons) {
  if (options.box_point == BoxPoint::kCenter) return {};
  std::vector<char> used(job.tracklets.size(), 0);
  for (const core::Tracklet3D& person : persons) {
    for (const int i : person.source_tracklets) used[static_cast<std::size_t>(i)] = 1;
  }
  const int num_points = NumPoints(options);
  const double height = options.ground_height_m + kMonocularCenterHeightM;
  std::vector<core::Tracklet3D> out;
  for (std::size_t i = 0; i < job.tracklets.size(); ++i) {
    if (used[i] != 0) continue;
    const core::Tracklet2D& t = job.tracklets[i];
    const std::optional<int> camera = rig.IndexOf(t.camera_id);
    if (!camera) continue;
    const geometry::CameraModel& model = rig.camera(*camera);
    core::Tracklet3D mono;
    for (std::size_t f = 0; f < t.frames.size(); ++f) {
      std::optional<Vec3> p = FeetOnFloor(model, options, t.observations[f]);
      if (!p) continue;
      p->z() = height;
      mono.frames.push_back(t.frames[f]);
      mono.points.emplace_back(static_cast<std::size_t>(num_points));
      mono.points.back()[0] = *p;
    }
    if (mono.frames.empty()) continue;
    mono.cameras = {t.camera_id};
    mono.source_tracklets = {static_cast<int>(i)};
    SetMembers(job, &mono);
    out.push_back(std::move(mono));
  }
  return out;
}

}  // namespace

std::optional<Vec3> FeetOnFloor(const geometry::CameraModel& camera,
                                const TrackerOptions& options,
                                const core::Observation2D& observation) {
  // The box's bottom among an observation's points (BoxPoint::kCenter has none).
  std::size_t bottom = 0;
  if (options.mode != InputMode::kBoxes) return std::nullopt;
  if (options.box_point == BoxPoint::kCenterEnds) {
    bottom = static_cast<std::size_t>(kBoxBottomPoint);
  } else if (options.box_point != BoxPoint::kBottomCenter) {
    return std::nullopt;
  }
  // The feet: the bottom of the box on the person's vertical axis (CameraStage), on the floor;
  // unknown when the box is cut there.
  if (observation.points_px.size() <= bottom || (observation.cut_edges & core::kCutBottom) != 0) {
    return std::nullopt;
  }
  std::optional<Vec3> p =
      camera.PointOnRayAtHeight(observation.points_px[bottom], options.ground_height_m);
  if (!p || !p->allFinite()) return std::nullopt;
  // A flat ray puts a pixel's error far along the floor (the error grows as 1 / sin^2 of the
  // angle below the horizontal).
  const double min_sine = std::sin(options.monocular_min_elevation_deg * std::numbers::pi / 180.0);
  const Vec3 ray = *p - camera.CenterInWorld();
  if (-ray.z() < min_sine * ray.norm()) return std::nullopt;
  return p;
}

// Sets person->appearance: the normalised mean of its observations' embeddings (those of the
// first embedding's dimension, in the order of source_tracklets and frames).
void SetAppearance(const WindowJob& job, core::Tracklet3D* person) {
  core::EmbeddingMean mean;
  for (const int t : person->source_tracklets) {
    for (const core::Observation2D& obs : job.tracklets[static_cast<std::size_t>(t)].observations) {
      if (obs.embedding) mean.Add(*obs.embedding);
    }
  }
  person->appearance = mean.Unit();
  person->appearance_count = person->appearance.empty() ? 0 : mean.count();
}

WindowResult EmptyWindowResult(const WindowJob& job) {
  WindowResult r;
  r.window_id = job.window_id;
  r.begin = job.begin;
  r.end = job.end;
  r.finalize_from = job.finalize_from;
  r.finalize_to = job.finalize_to;
  r.live_tracks = job.live_tracks;
  r.seconds_per_frame = job.seconds_per_frame;
  return r;
}

WindowWorkspace::WindowWorkspace(const triangulation::TriangulationOptions& options)
    : triangulator_(options) {}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& options,
                              const WindowJob& job,
                              WindowWorkspace* workspace) {
  return ProcessWindowJob(rig, options, job, workspace, PersonLoop());
}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& base_options,
                              const WindowJob& job,
                              WindowWorkspace* workspace,
                              const PersonLoop& person_loop) {
  MVTRACK_CHECK(workspace != nullptr);
  MVTRACK_CHECK_MSG(
      SameTriangulationOptions(workspace->triangulator().options(), base_options.triangulation),
      "the workspace was made for other triangulation options");
  // The frame counts in effect at the stream's measured rate (TrackerOptions::reference_fps).
  const TrackerOptions options = AtFrameRate(base_options, job.seconds_per_frame);
  WindowResult r = EmptyWindowResult(job);
  // Cross-view association (Eq. 2-4, PDNC / Algorithm 1).
  r.clusters =
      association::AssociateTracklets(rig, job.tracklets, AssociationOptionsInEffect(options));
  // CMMT (Algorithm 2) per person seen by at least two cameras.
  const int num_points = NumPoints(options);
  std::vector<const std::vector<int>*> multi_view;
  for (const std::vector<int>& cluster : r.clusters) {
    if (NumCameras(job, cluster) >= 2) multi_view.push_back(&cluster);
  }
  // Persons are independent: `person_loop` may run them concurrently (each on its own
  // workspace); they are kept in cluster order, so the result does not depend on how.
  std::vector<core::Tracklet3D> triangulated(multi_view.size());
  const PersonTask task = [&](int i, WindowWorkspace* ws) {
    const auto ui = static_cast<std::size_t>(i);
    triangulated[ui] = TriangulateCluster(rig, options, job, *multi_view[ui], ws);
  };
  if (person_loop) {
    person_loop(static_cast<int>(multi_view.size()), task);
  } else {
    for (std::size_t i = 0; i < multi_view.size(); ++i) task(static_cast<int>(i), workspace);
  }
  std::vector<std::vector<int>> person_clusters;
  for (std::size_t i = 0; i < multi_view.size(); ++i) {
    if (triangulated[i].frames.empty()) continue;
    r.persons.push_back(std::move(triangulated[i]));
    person_clusters.push_back(*multi_view[i]);
  }
  SplitAtJumps(rig, options, job, workspace, &person_clusters, &r.persons);
  if (options.mode == InputMode::kBoxes) {
    SplitInconsistent(rig, options, job, workspace, &person_clusters, &r.persons);
  }
  if (options.mode == InputMode::kBoxes) {
    RegroupTwoCameraPersons(rig, options, job, workspace, &person_clusters, &r.persons);
  }
  MergeDuplicates(rig, options, job, workspace, &person_clusters, &r.persons);
  if (options.mode == InputMode::kBoxes) {
    MergeCutPersons(rig, options, job, &person_clusters, &r.persons);
  }
  if (options.mode == InputMode::kPoses) {
    // Fragments of a few joints are not people (RefinementOptions::min_person_point_fraction).
    const double min_points = options.refinement.min_person_point_fraction * num_points;
    r.persons.erase(std::remove_if(r.persons.begin(),
                                   r.persons.end(),
                                   [&](const core::Tracklet3D& person) {
                                     return triangulation::MaxPointsPerFrame(person) < min_points;
                                   }),
                    r.persons.end());
    for (core::Tracklet3D& person : r.persons) {
      triangulation::RejectTemporalOutliers(&person, options.refinement);
      triangulation::CompleteMissingPoints(&person, options.refinement);
      // Smoothing off: no view counts either.
      if (options.refinement.smooth_half_window > 0) {
        const std::vector<std::vector<int>> views = triangulation::ObservingViews(
            job.tracklets, person.source_tracklets, person, options.triangulation.min_confidence);
        triangulation::SmoothTemporally(&person, options.refinement, &views);
      }
    }
  }
  for (core::Tracklet3D& person : r.persons) {
    SetMembers(job, &person);
    if (options.mode == InputMode::kPoses && options.refinement.fit_skeleton) {
      SetViews(rig, job, &person);
    }
    if (options.appearance.enabled) SetAppearance(job, &person);
  }
  if (options.mode == InputMode::kBoxes && options.linking.monocular_max_s > 0.0) {
    r.monocular = MonocularTracklets(rig, options, job, r.persons);
    if (options.appearance.enabled) {
      for (core::Tracklet3D& mono : r.monocular) SetAppearance(job, &mono);
    }
  }
  return r;
}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig,
                              const TrackerOptions& options,
                              const WindowJob& job) {
  WindowWorkspace workspace(options.triangulation);
  return ProcessWindowJob(rig, options, job, &workspace);
}

// See the header. Persons are judged on the triangulations before any move; a tracklet goes to
// the person it fits best.
void RegroupTwoCameraPersons(const geometry::CameraRig& rig,
                             const TrackerOptions& options,
                             const WindowJob& job,
                             WindowWorkspace* workspace,
                             std::vector<std::vector<int>>* clusters,
                             std::vector<core::Tracklet3D>* persons) {
  const double max_residual = 0.5 * options.refinement.box_split_residual;
  if (max_residual <= 0.0 || persons->size() < 2) return;
  const std::size_t n = persons->size();
  std::vector<int> cameras(n);
  for (std::size_t p = 0; p < n; ++p) cameras[p] = NumCameras(job, (*clusters)[p]);
  // Whether person q's cluster holds a tracklet of tracklet i's camera in one of i's frames.
  const auto camera_taken = [&](std::size_t q, int i) {
    const core::Tracklet2D& t = job.tracklets[static_cast<std::size_t>(i)];
    for (const int j : (*clusters)[q]) {
      const core::Tracklet2D& u = job.tracklets[static_cast<std::size_t>(j)];
      if (u.camera_id != t.camera_id) continue;
      for (const FrameIndex f : t.frames) {
        if (u.IndexOf(f) >= 0) return true;
      }
    }
    return false;
  };
  std::vector<std::vector<int>> joins(n);
  std::vector<char> dissolved(n, 0);
  // A person that received a tracklet is not dissolved afterwards, and a dissolved one
  // receives none (two two-camera persons cannot dissolve each other).
  std::vector<char> receiving(n, 0);
  for (std::size_t p = 0; p < n; ++p) {
    if (cameras[p] != 2 || receiving[p]) continue;
    std::vector<std::pair<std::size_t, int>> moves;
    for (const int i : (*clusters)[p]) {
      std::size_t best = n;
      double best_residual = max_residual;
      for (std::size_t q = 0; q < n; ++q) {
        if (q == p || cameras[q] < 2 || dissolved[q] ||
            FarInImage(rig, job.tracklets[static_cast<std::size_t>(i)], (*persons)[q]) ||
            camera_taken(q, i)) {
          continue;
        }
        const std::optional<double> r =
            triangulation::ReprojectionResidual(rig,
                                                job.tracklets[static_cast<std::size_t>(i)],
                                                (*persons)[q],
                                                options.association.min_confidence,
                                                NumTriangulatedPoints(options));
        if (r && *r <= best_residual && (best == n || *r < best_residual)) {
          best = q;
          best_residual = *r;
        }
      }
      if (best == n) continue;
      moves.emplace_back(best, i);
    }
    if (moves.empty()) continue;
    for (const auto& [q, i] : moves) {
      joins[q].push_back(i);
      receiving[q] = 1;
    }
    dissolved[p] = 1;
  }
  std::vector<char> alive(n, 1);
  for (std::size_t q = 0; q < n; ++q) {
    if (joins[q].empty()) continue;
    std::vector<int> merged = (*clusters)[q];
    merged.insert(merged.end(), joins[q].begin(), joins[q].end());
    std::sort(merged.begin(), merged.end());
    core::Tracklet3D person = TriangulateCluster(rig, options, job, merged, workspace);
    if (person.frames.empty()) continue;
    (*clusters)[q] = std::move(merged);
    (*persons)[q] = std::move(person);
  }
  for (std::size_t p = 0; p < n; ++p) {
    if (dissolved[p]) alive[p] = 0;
  }
  KeepAlive(alive, clusters, persons);
}

}  // namespace mvtrack::tracker
