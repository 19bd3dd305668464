#include "tracker/window_job.h"

#include <algorithm>

#include "association/association.h"
#include "core/check.h"

namespace mvtrack::tracker {
namespace {

bool SameTriangulationOptions(const triangulation::TriangulationOptions& a,
                              const triangulation::TriangulationOptions& b) {
  return a.method == b.method && a.phi == b.phi && a.kappa_m == b.kappa_m &&
         a.min_confidence == b.min_confidence && a.ransac_threshold_px == b.ransac_threshold_px &&
         a.min_inliers == b.min_inliers && a.max_views == b.max_views;
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
  for (const std::vector<int>& cluster : r.clusters) {
    cams.clear();
    for (int i : cluster) cams.push_back(job.tracklets[static_cast<std::size_t>(i)].camera_id);
    std::sort(cams.begin(), cams.end());
    if (std::unique(cams.begin(), cams.end()) - cams.begin() < 2) continue;
    core::Tracklet3D person = workspace->triangulator().Triangulate(
        rig, job.tracklets, cluster, job.begin, job.end, num_points);
    if (!person.frames.empty()) r.persons.push_back(std::move(person));
  }
  return r;
}

WindowResult ProcessWindowJob(const geometry::CameraRig& rig, const TrackerOptions& options,
                              const WindowJob& job) {
  WindowWorkspace workspace(options.triangulation);
  return ProcessWindowJob(rig, options, job, &workspace);
}

}  // namespace mvtrack::tracker
