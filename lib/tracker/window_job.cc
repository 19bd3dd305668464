#include "tracker/window_job.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

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

// Merges persons of one window that are one person split by association (their common points
// lie within refinement.merge_distance_m): the closest such pair first, its clusters united and
// triangulated again, until no pair qualifies. Keeps the order of first members.
void MergeDuplicates(const geometry::CameraRig& rig, const TrackerOptions& options,
                     const WindowJob& job, WindowWorkspace* workspace,
                     std::vector<std::vector<int>>* clusters,
                     std::vector<core::Tracklet3D>* persons) {
  const triangulation::RefinementOptions& ro = options.refinement;
  if (ro.merge_distance_m <= 0.0) return;
  const int num_points = NumPoints(options);
  while (persons->size() >= 2) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t bi = 0;
    std::size_t bj = 0;
    for (std::size_t i = 0; i < persons->size(); ++i) {
      for (std::size_t j = i + 1; j < persons->size(); ++j) {
        std::int64_t pairs = 0;
        const double d = triangulation::PointDistance((*persons)[i], (*persons)[j], &pairs);
        if (pairs >= ro.min_duplicate_pairs && d <= ro.merge_distance_m && d < best) {
          best = d;
          bi = i;
          bj = j;
        }
      }
    }
    if (!std::isfinite(best)) return;
    std::vector<int> merged = (*clusters)[bi];
    merged.insert(merged.end(), (*clusters)[bj].begin(), (*clusters)[bj].end());
    std::sort(merged.begin(), merged.end());
    core::Tracklet3D person = workspace->triangulator().Triangulate(
        rig, job.tracklets, merged, job.begin, job.end, num_points);
    clusters->erase(clusters->begin() + static_cast<std::ptrdiff_t>(bj));
    persons->erase(persons->begin() + static_cast<std::ptrdiff_t>(bj));
    // The union can lose every point (more candidates that disagree): the first stays as is.
    if (person.frames.empty()) continue;
    (*clusters)[bi] = std::move(merged);
    (*persons)[bi] = std::move(person);
  }
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
  MVTRACK_CHECK(workspace != nullptr);
  MVTRACK_CHECK_MSG(SameTriangulationOptions(workspace->triangulator().options(),
                                             options.triangulation),
                    "the workspace was made for other triangulation options");
  WindowResult r = EmptyWindowResult(job);
  // Cross-view association (Eq. 2-4, PDNC / Algorithm 1).
  r.clusters = association::AssociateTracklets(rig, job.tracklets, options.association);
  // CMMT (Algorithm 2) per person seen by at least two cameras.
  const int num_points = NumPoints(options);
  std::vector<CameraId> cams;
  std::vector<std::vector<int>> person_clusters;
  for (const std::vector<int>& cluster : r.clusters) {
    cams.clear();
    for (int i : cluster) cams.push_back(job.tracklets[static_cast<std::size_t>(i)].camera_id);
    std::sort(cams.begin(), cams.end());
    if (std::unique(cams.begin(), cams.end()) - cams.begin() < 2) continue;
    core::Tracklet3D person = workspace->triangulator().Triangulate(
        rig, job.tracklets, cluster, job.begin, job.end, num_points);
    if (person.frames.empty()) continue;
    r.persons.push_back(std::move(person));
    person_clusters.push_back(cluster);
  }
  if (options.mode == InputMode::kPoses) {
    MergeDuplicates(rig, options, job, workspace, &person_clusters, &r.persons);
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
