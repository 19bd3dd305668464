#include "tracker/window_job.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

#include "association/association.h"
#include "core/check.h"
#include "triangulation/refinement.h"

namespace mvtrack::tracker {
namespace {

bool SameTriangulationOptions(const triangulation::TriangulationOptions& a,
                              const triangulation::TriangulationOptions& b) {
  return a.method == b.method && a.phi == b.phi && a.kappa_m == b.kappa_m &&
         a.min_confidence == b.min_confidence && a.ransac_threshold_px == b.ransac_threshold_px &&
         a.min_inliers == b.min_inliers && a.max_views == b.max_views;
}

// Box mode: removes a person's points outside the plausible heights of a box point
// (RefinementOptions::box_min_height_m, box_max_height_m above the floor).
void GateBoxHeights(const TrackerOptions& options, core::Tracklet3D* person) {
  triangulation::RemovePointsOutsideHeights(
      person, options.ground_height_m + options.refinement.box_min_height_m,
      options.ground_height_m + options.refinement.box_max_height_m);
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
void SplitInconsistent(const geometry::CameraRig& rig, const TrackerOptions& options,
                       const WindowJob& job, WindowWorkspace* workspace,
                       std::vector<std::vector<int>>* clusters,
                       std::vector<core::Tracklet3D>* persons) {
  const double max_residual = options.refinement.box_split_residual;
  if (max_residual <= 0.0) return;
  const int num_points = NumPoints(options);
  const std::size_t n = persons->size();
  for (std::size_t p = 0; p < n; ++p) {
    const std::vector<int> out = triangulation::InconsistentTracklets(
        rig, job.tracklets, (*clusters)[p], (*persons)[p], max_residual,
        options.association.min_confidence);
    if (out.empty()) continue;
    std::vector<int> keep;
    for (int i : (*clusters)[p]) {
      if (!std::binary_search(out.begin(), out.end(), i)) keep.push_back(i);
    }
    if (NumCameras(job, keep) < 2) continue;
    core::Tracklet3D kept = workspace->triangulator().Triangulate(rig, job.tracklets, keep,
                                                                  job.begin, job.end, num_points);
    GateBoxHeights(options, &kept);
    if (kept.frames.empty()) continue;
    (*clusters)[p] = std::move(keep);
    (*persons)[p] = std::move(kept);
    if (NumCameras(job, out) < 2) continue;
    core::Tracklet3D other = workspace->triangulator().Triangulate(rig, job.tracklets, out,
                                                                   job.begin, job.end, num_points);
    GateBoxHeights(options, &other);
    if (other.frames.empty()) continue;
    clusters->push_back(out);
    persons->push_back(std::move(other));
  }
}

// Merges persons of one window that are one person split by association: in pose mode when their
// common joints lie within refinement.merge_distance_m on average (PointDistance), in box mode
// when their footprints lie within refinement.box_merge_distance_m (median, FootprintDistance),
// each over at least min_duplicate_pairs common points / frames. The closest such pair first,
// its clusters united and triangulated again, until no pair qualifies. Keeps the order of first
// members. Pair distances are computed once (pairs whose ground-plane rectangles are farther
// apart than the limit cannot qualify and are skipped) and afterwards only the merged person's.
void MergeDuplicates(const geometry::CameraRig& rig, const TrackerOptions& options,
                     const WindowJob& job, WindowWorkspace* workspace,
                     std::vector<std::vector<int>>* clusters,
                     std::vector<core::Tracklet3D>* persons) {
  const triangulation::RefinementOptions& ro = options.refinement;
  const bool boxes = options.mode == InputMode::kBoxes;
  const double limit = boxes ? ro.box_merge_distance_m : ro.merge_distance_m;
  if (limit <= 0.0 || persons->size() < 2) return;
  const int num_points = NumPoints(options);
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
    return pairs >= ro.min_duplicate_pairs && d <= limit ? d : kInf;
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
    core::Tracklet3D person = workspace->triangulator().Triangulate(
        rig, job.tracklets, merged, job.begin, job.end, num_points);
    if (boxes) GateBoxHeights(options, &person);
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
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
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

}  // namespace

WindowResult EmptyWindowResult(const WindowJob& job) {
  WindowResult r;
  r.window_id = job.window_id;
  r.begin = job.begin;
  r.end = job.end;
  r.finalize_from = job.finalize_from;
  r.finalize_to = job.finalize_to;
  return r;
}

WindowWorkspace::WindowWorkspace(const triangulation::TriangulationOptions& options)
    : triangulator_(options) {}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig, const TrackerOptions& options,
                              const WindowJob& job, WindowWorkspace* workspace) {
  return ProcessWindowJob(rig, options, job, workspace, PersonLoop());
}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig, const TrackerOptions& options,
                              const WindowJob& job, WindowWorkspace* workspace,
                              const PersonLoop& person_loop) {
  MVTRACK_CHECK(workspace != nullptr);
  MVTRACK_CHECK_MSG(SameTriangulationOptions(workspace->triangulator().options(),
                                             options.triangulation),
                    "the workspace was made for other triangulation options");
  WindowResult r = EmptyWindowResult(job);
  // Cross-view association (Eq. 2-4, PDNC / Algorithm 1).
  r.clusters = association::AssociateTracklets(rig, job.tracklets, options.association);
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
    triangulated[ui] = ws->triangulator().Triangulate(rig, job.tracklets, *multi_view[ui],
                                                      job.begin, job.end, num_points);
    if (options.mode == InputMode::kBoxes) GateBoxHeights(options, &triangulated[ui]);
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
  if (options.mode == InputMode::kBoxes) {
    SplitInconsistent(rig, options, job, workspace, &person_clusters, &r.persons);
  }
  MergeDuplicates(rig, options, job, workspace, &person_clusters, &r.persons);
  if (options.mode == InputMode::kPoses) {
    // Fragments of a few joints are not people (RefinementOptions::min_person_point_fraction).
    const double min_points = options.refinement.min_person_point_fraction * num_points;
    r.persons.erase(std::remove_if(r.persons.begin(), r.persons.end(),
                                   [&](const core::Tracklet3D& person) {
                                     return triangulation::MaxPointsPerFrame(person) < min_points;
                                   }),
                    r.persons.end());
    for (core::Tracklet3D& person : r.persons) {
      triangulation::RejectTemporalOutliers(&person, options.refinement);
      triangulation::CompleteMissingPoints(&person, options.refinement);
    }
  }
  return r;
}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig, const TrackerOptions& options,
                              const WindowJob& job) {
  WindowWorkspace workspace(options.triangulation);
  return ProcessWindowJob(rig, options, job, &workspace);
}

}  // namespace mvtrack::tracker
