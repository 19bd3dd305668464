#include "triangulation/refinement.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "core/check.h"
#include "core/median.h"
#include "geometry/triangulation.h"

namespace mvtrack::triangulation {
namespace {

// Neighbour sets whose second principal spread (RMS, metres) is below this are treated as
// collinear: their rotation about the line is undetermined, so only their translation is used.
constexpr double kMinRigidSpreadM = 0.02;

using Row = std::vector<std::optional<Vec3>>;

// The checks every temporal stage makes of its input (checked: a tracklet, valid options, one
// row of points per frame, every row as long); returns the number of points per frame (0
// without frames).
std::size_t CheckedPointsPerFrame(const core::Tracklet3D* tracklet,
                                  const RefinementOptions& options) {
  MVTRACK_CHECK(tracklet != nullptr);
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  MVTRACK_CHECK_MSG(tracklet->frames.size() == tracklet->points.size(),
                    "tracklet frames and points differ in length");
  if (tracklet->points.empty()) return 0;
  const std::size_t num_points = tracklet->points.front().size();
  for (const Row& row : tracklet->points) {
    MVTRACK_CHECK_MSG(row.size() == num_points, "every frame needs the same number of points");
  }
  return num_points;
}

// Estimate of point k at row `to` carried from row `from` by the motion of k's nearest
// neighbours (points present in both rows), or nullopt without neighbours.
std::optional<Vec3> Carry(
    const Row& from, const Row& to, std::size_t k, int max_neighbors, bool* rigid) {
  const Vec3 anchor = *from[k];
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t j = 0; j < from.size(); ++j) {
    if (j == k || !from[j] || !to[j]) continue;
    near.emplace_back((*from[j] - anchor).squaredNorm(), j);
  }
  if (near.empty()) return std::nullopt;
  const auto n = std::min(near.size(), static_cast<std::size_t>(max_neighbors));
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(n), near.end());
  Vec3 mean_from = Vec3::Zero();
  Vec3 mean_to = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mean_from += *from[near[i].second];
    mean_to += *to[near[i].second];
  }
  mean_from /= static_cast<double>(n);
  mean_to /= static_cast<double>(n);
  *rigid = false;
  if (n >= 3) {
    Eigen::Matrix<double, Eigen::Dynamic, 3> src(static_cast<Eigen::Index>(n), 3);
    Eigen::Matrix<double, Eigen::Dynamic, 3> dst(static_cast<Eigen::Index>(n), 3);
    for (std::size_t i = 0; i < n; ++i) {
      src.row(static_cast<Eigen::Index>(i)) = (*from[near[i].second] - mean_from).transpose();
      dst.row(static_cast<Eigen::Index>(i)) = (*to[near[i].second] - mean_to).transpose();
    }
    const Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, 3>> spread(src);
    const double second_rms = spread.singularValues()(1) / std::sqrt(static_cast<double>(n));
    if (second_rms >= kMinRigidSpreadM) {
      // Kabsch: R = V diag(1, 1, det(V U^T)) U^T for H = src^T dst = U S V^T.
      const Mat3 h = src.transpose() * dst;
      const Eigen::JacobiSVD<Mat3> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Mat3 d = Mat3::Identity();
      d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
      const Mat3 r = svd.matrixV() * d * svd.matrixU().transpose();
      *rigid = true;
      return Vec3(r * (anchor - mean_from) + mean_to);
    }
  }
  return Vec3(anchor + (mean_to - mean_from));
}

}  // namespace

bool RefinementOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = std::string("refinement: ") + reason;
    return false;
  };
  if (!(std::isfinite(merge_distance_m) && merge_distance_m >= 0.0)) {
    return fail("merge_distance_m must be finite and >= 0");
  }
  if (min_duplicate_pairs < 1) return fail("min_duplicate_pairs must be >= 1");
  if (box_min_duplicate_frames < 1) return fail("box_min_duplicate_frames must be >= 1");
  if (!(std::isfinite(box_merge_distance_m) && box_merge_distance_m >= 0.0)) {
    return fail("box_merge_distance_m must be finite and >= 0");
  }
  if (!(std::isfinite(box_min_height_m) && std::isfinite(box_max_height_m) &&
        box_min_height_m < box_max_height_m)) {
    return fail("box_min_height_m and box_max_height_m must be finite, min < max");
  }
  if (!(std::isfinite(box_bottom_min_height_m) && std::isfinite(box_bottom_max_height_m) &&
        box_bottom_min_height_m < box_bottom_max_height_m)) {
    return fail("box_bottom_min_height_m and box_bottom_max_height_m must be finite, min < max");
  }
  if (!(std::isfinite(box_top_min_height_m) && std::isfinite(box_top_max_height_m) &&
        box_top_min_height_m < box_top_max_height_m)) {
    return fail("box_top_min_height_m and box_top_max_height_m must be finite, min < max");
  }
  if (!(std::isfinite(jump_gate_chi2) && jump_gate_chi2 >= 0.0)) {
    return fail("jump_gate_chi2 must be finite and >= 0");
  }
  if (!(std::isfinite(box_split_residual) && box_split_residual >= 0.0)) {
    return fail("box_split_residual must be finite and >= 0");
  }
  if (!(min_person_point_fraction >= 0.0 && min_person_point_fraction <= 1.0)) {
    return fail("min_person_point_fraction must be in [0, 1]");
  }
  if (outlier_half_window < 0) return fail("outlier_half_window must be >= 0 frames");
  if (!(std::isfinite(outlier_distance_m) && outlier_distance_m > 0.0)) {
    return fail("outlier_distance_m must be finite and > 0");
  }
  if (smooth_half_window < 0) return fail("smooth_half_window must be >= 0 frames");
  if (smooth_max_views < 0) return fail("smooth_max_views must be >= 0");
  if (max_fill_gap < 0) return fail("max_fill_gap must be >= 0 frames");
  if (fill_neighbors < 1) return fail("fill_neighbors must be >= 1");
  if (min_points_to_fill < 1) return fail("min_points_to_fill must be >= 1");
  return true;
}

double PointDistance(const core::Tracklet3D& a, const core::Tracklet3D& b, std::int64_t* pairs) {
  double sum = 0.0;
  std::int64_t count = 0;
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.frames.size() && j < b.frames.size()) {
    if (a.frames[i] < b.frames[j]) {
      ++i;
    } else if (b.frames[j] < a.frames[i]) {
      ++j;
    } else {
      const Row& pa = a.points[i];
      const Row& pb = b.points[j];
      const std::size_t n = std::min(pa.size(), pb.size());
      for (std::size_t k = 0; k < n; ++k) {
        if (pa[k] && pb[k]) {
          sum += (*pa[k] - *pb[k]).norm();
          ++count;
        }
      }
      ++i;
      ++j;
    }
  }
  if (pairs != nullptr) *pairs = count;
  if (count == 0) return std::numeric_limits<double>::infinity();
  return sum / static_cast<double>(count);
}

double FootprintDistance(const core::Tracklet3D& a,
                         const core::Tracklet3D& b,
                         std::int64_t* frames) {
  // The (x, y) of the mean of the present points of one frame; nullopt without a point.
  auto footprint = [](const Row& row) -> std::optional<Vec2> {
    Vec2 sum = Vec2::Zero();
    int n = 0;
    for (const std::optional<Vec3>& p : row) {
      if (!p) continue;
      sum += p->head<2>();
      ++n;
    }
    if (n == 0) return std::nullopt;
    return Vec2(sum / static_cast<double>(n));
  };
  std::vector<double> d;
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.frames.size() && j < b.frames.size()) {
    if (a.frames[i] < b.frames[j]) {
      ++i;
    } else if (b.frames[j] < a.frames[i]) {
      ++j;
    } else {
      const std::optional<Vec2> fa = footprint(a.points[i]);
      const std::optional<Vec2> fb = footprint(b.points[j]);
      if (fa && fb) d.push_back((*fa - *fb).norm());
      ++i;
      ++j;
    }
  }
  if (frames != nullptr) *frames = static_cast<std::int64_t>(d.size());
  if (d.empty()) return std::numeric_limits<double>::infinity();
  return core::MedianInPlace(&d);
}

std::int64_t RemovePointsOutsideHeights(core::Tracklet3D* tracklet, double min_z, double max_z) {
  MVTRACK_CHECK(tracklet != nullptr);
  std::size_t points = 0;
  for (const Row& row : tracklet->points) points = std::max(points, row.size());
  return RemovePointsOutsideHeights(tracklet, std::vector<HeightRange>(points, {min_z, max_z}));
}

std::int64_t RemovePointsOutsideHeights(core::Tracklet3D* tracklet,
                                        const std::vector<HeightRange>& ranges) {
  MVTRACK_CHECK(tracklet != nullptr);
  MVTRACK_CHECK_MSG(tracklet->frames.size() == tracklet->points.size(),
                    "tracklet frames and points differ in length");
  std::int64_t removed = 0;
  std::size_t kept = 0;
  for (std::size_t f = 0; f < tracklet->frames.size(); ++f) {
    Row& row = tracklet->points[f];
    MVTRACK_CHECK_MSG(row.size() <= ranges.size(), "a height range is needed for every point");
    bool any = false;
    for (std::size_t k = 0; k < row.size(); ++k) {
      std::optional<Vec3>& p = row[k];
      if (!p) continue;
      if (p->z() >= ranges[k].min_z && p->z() <= ranges[k].max_z) {
        any = true;
      } else {
        p.reset();
        ++removed;
      }
    }
    if (!any) continue;
    if (kept != f) {
      tracklet->frames[kept] = tracklet->frames[f];
      tracklet->points[kept] = std::move(row);
    }
    ++kept;
  }
  tracklet->frames.resize(kept);
  tracklet->points.resize(kept);
  return removed;
}

BoxEndsStats TriangulateBoxEnds(const geometry::CameraRig& rig,
                                const std::vector<core::Tracklet2D>& tracklets,
                                const std::vector<int>& cluster,
                                int first_point,
                                const std::vector<HeightRange>& ranges,
                                double min_confidence,
                                core::Tracklet3D* person) {
  MVTRACK_CHECK(person != nullptr);
  MVTRACK_CHECK_MSG(first_point >= 0, "first_point must be >= 0");
  BoxEndsStats stats;
  const std::size_t num_points = static_cast<std::size_t>(first_point) + ranges.size();
  // The cluster's tracklets with their projection matrix and a cursor into their frames (the
  // person's frames increase, so each tracklet is walked once).
  struct View {
    const core::Tracklet2D* tracklet;
    const Mat34* projection;
    std::size_t cursor;
  };
  std::vector<View> views;
  views.reserve(cluster.size());
  for (int i : cluster) {
    MVTRACK_CHECK_MSG(i >= 0 && static_cast<std::size_t>(i) < tracklets.size(),
                      "cluster index out of range");
    const core::Tracklet2D& t = tracklets[static_cast<std::size_t>(i)];
    if (const std::optional<int> index = rig.IndexOf(t.camera_id)) {
      views.push_back({&t, &rig.projection(*index), 0});
    }
  }
  // Per frame and end: the usable views' (projection, pixel).
  std::vector<const Mat34*> projections;
  std::vector<Vec2> pixels;
  std::vector<const Mat34*> subset_p;
  std::vector<Vec2> subset_x;
  std::vector<const core::Observation2D*> observed;
  std::size_t kept = 0;
  for (std::size_t r = 0; r < person->frames.size(); ++r) {
    const FrameIndex frame = person->frames[r];
    Row& row = person->points[r];
    row.resize(num_points);
    observed.clear();
    for (View& v : views) {
      const std::vector<FrameIndex>& f = v.tracklet->frames;
      while (v.cursor < f.size() && f[v.cursor] < frame) ++v.cursor;
      observed.push_back(v.cursor < f.size() && f[v.cursor] == frame
                             ? &v.tracklet->observations[v.cursor]
                             : nullptr);
    }
    bool implausible = false;
    for (std::size_t e = 0; e < ranges.size(); ++e) {
      const std::size_t k = static_cast<std::size_t>(first_point) + e;
      row[k].reset();
      projections.clear();
      pixels.clear();
      if (views.size() == 2) {
        // The common two-camera person: one two-view solve, no candidate lists.
        const core::Observation2D* a = observed[0];
        const core::Observation2D* b = observed[1];
        const auto usable = [&](const core::Observation2D* o) {
          if (o == nullptr || k >= o->points_px.size() || k >= o->confidence.size()) return false;
          const double c = o->confidence[k];
          return c > 0.0 && c >= min_confidence;
        };
        if (!usable(a) || !usable(b)) continue;
        const std::optional<Vec3> x = geometry::TriangulateTwoView(
            *views[0].projection, a->points_px[k], *views[1].projection, b->points_px[k]);
        if (x && x->allFinite() && x->z() >= ranges[e].min_z && x->z() <= ranges[e].max_z &&
            geometry::InFront(*views[0].projection, *x) &&
            geometry::InFront(*views[1].projection, *x)) {
          row[k] = x;
          ++stats.points;
        } else {
          implausible = true;
        }
        continue;
      }
      for (std::size_t v = 0; v < views.size(); ++v) {
        const core::Observation2D* o = observed[v];
        if (o == nullptr || k >= o->points_px.size() || k >= o->confidence.size()) continue;
        const double c = o->confidence[k];
        if (!(c > 0.0) || c < min_confidence) continue;
        projections.push_back(views[v].projection);
        pixels.push_back(o->points_px[k]);
      }
      const std::size_t n = projections.size();
      if (n < 2) continue;
      // Candidates: all views, then (with >= 3, if all views give no plausible point) every
      // leave-one-out subset; the plausible one with the smallest mean reprojection error.
      std::optional<Vec3> best;
      double best_error = std::numeric_limits<double>::infinity();
      for (std::size_t leave = 0; leave <= (n >= 3 ? n : 0); ++leave) {
        subset_p.clear();
        subset_x.clear();
        for (std::size_t v = 0; v < n; ++v) {
          if (leave > 0 && v == leave - 1) continue;
          subset_p.push_back(projections[v]);
          subset_x.push_back(pixels[v]);
        }
        const std::optional<Vec3> x = geometry::TriangulateLinear(subset_p, subset_x);
        const std::size_t used = subset_p.size();
        if (!x || !x->allFinite() || x->z() < ranges[e].min_z || x->z() > ranges[e].max_z) {
          continue;
        }
        bool in_front = true;
        for (std::size_t v = 0; v < n && in_front; ++v) {
          if (leave > 0 && v == leave - 1) continue;
          in_front = geometry::InFront(*projections[v], *x);
        }
        if (!in_front) continue;
        if (leave == 0) {  // all views agree on a plausible point: no subset needed
          best = x;
          break;
        }
        double error = 0.0;
        for (std::size_t v = 0; v < n; ++v) {
          if (v != leave - 1)
            error += geometry::ReprojectionErrorPx(*projections[v], *x, pixels[v]);
        }
        error /= static_cast<double>(used);
        if (error < best_error) {
          best_error = error;
          best = x;
        }
      }
      if (best) {
        row[k] = best;
        ++stats.points;
      } else {
        implausible = true;
      }
    }
    if (implausible) {
      ++stats.implausible_frames;
      continue;  // the frame is dropped
    }
    bool any = false;
    for (const std::optional<Vec3>& p : row) any = any || p.has_value();
    if (!any) continue;
    if (kept != r) {
      person->frames[kept] = frame;
      person->points[kept] = std::move(row);
    }
    ++kept;
  }
  person->frames.resize(kept);
  person->points.resize(kept);
  return stats;
}

std::optional<double> ReprojectionResidual(const geometry::CameraRig& rig,
                                           const core::Tracklet2D& tracklet,
                                           const core::Tracklet3D& person,
                                           double min_confidence,
                                           int max_points) {
  const std::optional<int> index = rig.IndexOf(tracklet.camera_id);
  MVTRACK_CHECK_MSG(index.has_value(), "the tracklet's camera is not in the rig");
  const geometry::CameraModel& camera = rig.camera(*index);
  std::vector<double> per_frame;
  per_frame.reserve(tracklet.frames.size());
  // Both frame lists are strictly increasing: one forward walk over person.frames finds each
  // tracklet frame's row (what person.IndexOf would find by bisection).
  std::size_t r = 0;
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    const FrameIndex frame = tracklet.frames[f];
    while (r < person.frames.size() && person.frames[r] < frame) ++r;
    if (r == person.frames.size()) break;
    if (person.frames[r] != frame) continue;
    const Row& row = person.points[r];
    const core::Observation2D& obs = tracklet.observations[f];
    if (!(obs.scale_px > 0.0)) continue;
    std::size_t n = std::min({row.size(), obs.points_px.size(), obs.confidence.size()});
    if (max_points > 0) n = std::min(n, static_cast<std::size_t>(max_points));
    double sum = 0.0;
    int count = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double c = obs.confidence[k];
      if (!row[k] || !(c > 0.0) || c < min_confidence) continue;
      const std::optional<Vec2> x = camera.ProjectUndistorted(*row[k]);
      if (!x) {
        sum += std::numeric_limits<double>::infinity();
      } else {
        Vec2 d = *x - obs.points_px[k];
        // Past a cut edge the person goes on out of the image: the box's point moved inwards.
        const std::uint8_t ce = obs.cut_edges;
        if ((ce & core::kCutLeft) != 0) d.x() = std::max(d.x(), 0.0);
        if ((ce & core::kCutRight) != 0) d.x() = std::min(d.x(), 0.0);
        if ((ce & core::kCutTop) != 0) d.y() = std::max(d.y(), 0.0);
        if ((ce & core::kCutBottom) != 0) d.y() = std::min(d.y(), 0.0);
        sum += d.norm() / obs.scale_px;
      }
      ++count;
    }
    if (count > 0) per_frame.push_back(sum / static_cast<double>(count));
  }
  if (per_frame.empty()) return std::nullopt;
  const std::size_t mid = per_frame.size() / 2;
  std::nth_element(
      per_frame.begin(), per_frame.begin() + static_cast<std::ptrdiff_t>(mid), per_frame.end());
  double m = per_frame[mid];
  if (per_frame.size() % 2 == 0) {
    m = 0.5 * (m + *std::max_element(per_frame.begin(),
                                     per_frame.begin() + static_cast<std::ptrdiff_t>(mid)));
  }
  return m;
}

std::vector<int> InconsistentTracklets(const geometry::CameraRig& rig,
                                       const std::vector<core::Tracklet2D>& tracklets,
                                       const std::vector<int>& cluster,
                                       const core::Tracklet3D& person,
                                       double max_residual,
                                       double min_confidence,
                                       int max_points) {
  std::vector<int> out;
  if (max_residual <= 0.0) return out;
  for (const int i : cluster) {
    MVTRACK_CHECK(i >= 0 && static_cast<std::size_t>(i) < tracklets.size());
    const std::optional<double> r = ReprojectionResidual(
        rig, tracklets[static_cast<std::size_t>(i)], person, min_confidence, max_points);
    if (r && *r > max_residual) out.push_back(i);
  }
  return out;
}

int MaxPointsPerFrame(const core::Tracklet3D& tracklet) {
  int best = 0;
  for (const Row& row : tracklet.points) {
    const auto n = std::count_if(
        row.begin(), row.end(), [](const std::optional<Vec3>& p) { return p.has_value(); });
    best = std::max(best, static_cast<int>(n));
  }
  return best;
}

std::int64_t RejectTemporalOutliers(core::Tracklet3D* tracklet, const RefinementOptions& options) {
  const std::size_t num_points = CheckedPointsPerFrame(tracklet, options);
  const std::size_t num_frames = tracklet->frames.size();
  const FrameIndex h = options.outlier_half_window;
  if (h == 0 || num_frames < 3) return 0;
  const auto& frames = tracklet->frames;
  std::vector<std::pair<std::size_t, std::size_t>> removals;  // (frame, point)
  std::array<std::vector<double>, 3> values;
  for (std::size_t f = 0; f < num_frames; ++f) {
    // A window symmetric about the frame (truncated at the tracklet's ends), so that the median
    // of a straight-line motion is the point itself; the end frames cannot be judged.
    const FrameIndex half = std::min({h, frames[f] - frames.front(), frames.back() - frames[f]});
    if (half < 1) continue;
    std::size_t lo = f;
    while (lo > 0 && frames[f] - frames[lo - 1] <= half) --lo;
    for (std::size_t k = 0; k < num_points; ++k) {
      if (!tracklet->points[f][k]) continue;
      for (auto& v : values) v.clear();
      for (std::size_t r = lo; r < num_frames && frames[r] - frames[f] <= half; ++r) {
        const std::optional<Vec3>& p = tracklet->points[r][k];
        if (!p) continue;
        for (int a = 0; a < 3; ++a) values[static_cast<std::size_t>(a)].push_back((*p)(a));
      }
      if (values[0].size() < 3) continue;
      Vec3 median;
      for (int a = 0; a < 3; ++a) {
        median(a) = core::MedianInPlace(&values[static_cast<std::size_t>(a)]);
      }
      if ((*tracklet->points[f][k] - median).norm() > options.outlier_distance_m) {
        removals.emplace_back(f, k);
      }
    }
  }
  for (const auto& [f, k] : removals) tracklet->points[f][k].reset();
  return static_cast<std::int64_t>(removals.size());
}

CompletionStats CompleteMissingPoints(core::Tracklet3D* tracklet,
                                      const RefinementOptions& options) {
  const std::size_t num_points = CheckedPointsPerFrame(tracklet, options);
  CompletionStats stats;
  const std::size_t num_frames = tracklet->frames.size();
  if (num_frames < 2 || options.max_fill_gap == 0) return stats;
  if (num_points < 2) return stats;
  const std::vector<Row> original = tracklet->points;
  const auto& frames = tracklet->frames;
  const FrameIndex max_gap = options.max_fill_gap;
  for (std::size_t f = 0; f < num_frames; ++f) {
    const Row& here = original[f];
    const auto present = std::count_if(
        here.begin(), here.end(), [](const std::optional<Vec3>& p) { return p.has_value(); });
    if (present < options.min_points_to_fill) continue;
    for (std::size_t k = 0; k < num_points; ++k) {
      if (here[k]) continue;
      std::optional<std::size_t> before;
      for (std::size_t r = f; r-- > 0 && frames[f] - frames[r] <= max_gap;) {
        if (original[r][k]) {
          before = r;
          break;
        }
      }
      std::optional<std::size_t> after;
      for (std::size_t r = f + 1; r < num_frames && frames[r] - frames[f] <= max_gap; ++r) {
        if (original[r][k]) {
          after = r;
          break;
        }
      }
      bool rigid_before = false;
      bool rigid_after = false;
      const std::optional<Vec3> from_before =
          before ? Carry(original[*before], here, k, options.fill_neighbors, &rigid_before)
                 : std::nullopt;
      const std::optional<Vec3> from_after =
          after ? Carry(original[*after], here, k, options.fill_neighbors, &rigid_after)
                : std::nullopt;
      std::optional<Vec3> estimate;
      if (from_before && from_after) {
        const auto t0 = static_cast<double>(frames[*before]);
        const auto t1 = static_cast<double>(frames[*after]);
        const double w = (static_cast<double>(frames[f]) - t0) / (t1 - t0);
        estimate = (1.0 - w) * *from_before + w * *from_after;
      } else if (from_before) {
        estimate = from_before;
      } else if (from_after) {
        estimate = from_after;
      }
      if (!estimate) continue;
      tracklet->points[f][k] = *estimate;
      ++stats.filled;
      if ((from_before && rigid_before) || (from_after && rigid_after)) ++stats.filled_rigid;
    }
  }
  return stats;
}

std::vector<std::vector<int>> ObservingViews(const std::vector<core::Tracklet2D>& tracklets,
                                             const std::vector<int>& cluster,
                                             const core::Tracklet3D& person,
                                             double min_confidence) {
  const std::size_t num_points = person.points.empty() ? 0 : person.points.front().size();
  std::vector<std::vector<int>> views(person.frames.size(), std::vector<int>(num_points, 0));
  // Tracklets of one camera (fragments of one person) count as one view.
  std::vector<std::pair<CameraId, int>> members;
  for (const int i : cluster) {
    MVTRACK_CHECK(i >= 0 && static_cast<std::size_t>(i) < tracklets.size());
    members.emplace_back(tracklets[static_cast<std::size_t>(i)].camera_id, i);
  }
  std::sort(members.begin(), members.end());
  std::vector<char> seen(num_points);
  for (std::size_t f = 0; f < person.frames.size(); ++f) {
    for (std::size_t m = 0; m < members.size();) {
      std::fill(seen.begin(), seen.end(), 0);
      const CameraId camera = members[m].first;
      for (; m < members.size() && members[m].first == camera; ++m) {
        const core::Tracklet2D& t = tracklets[static_cast<std::size_t>(members[m].second)];
        const int at = t.IndexOf(person.frames[f]);
        if (at < 0) continue;
        const std::vector<double>& c = t.observations[static_cast<std::size_t>(at)].confidence;
        for (std::size_t k = 0; k < num_points && k < c.size(); ++k) {
          if (c[k] > 0.0 && c[k] >= min_confidence) seen[k] = 1;
        }
      }
      for (std::size_t k = 0; k < num_points; ++k) views[f][k] += seen[k];
    }
  }
  return views;
}

std::int64_t SmoothTemporally(core::Tracklet3D* tracklet,
                              const RefinementOptions& options,
                              const std::vector<std::vector<int>>* views) {
  const std::size_t num_points = CheckedPointsPerFrame(tracklet, options);
  const std::size_t num_frames = tracklet->frames.size();
  const FrameIndex h = options.smooth_half_window;
  if (h == 0 || num_frames < 3) return 0;
  if (views != nullptr) {
    MVTRACK_CHECK_MSG(views->size() == num_frames, "one view count row per frame");
    for (const std::vector<int>& row : *views) {
      MVTRACK_CHECK_MSG(row.size() == num_points, "one view count per point");
    }
  }
  const auto& frames = tracklet->frames;
  // Tricube weights by frame offset |x| <= h.
  std::vector<double> weight(static_cast<std::size_t>(h) + 1);
  const double reach = static_cast<double>(h + 1);
  for (std::size_t x = 0; x < weight.size(); ++x) {
    const double u = static_cast<double>(x) / reach;
    weight[x] = std::pow(1.0 - u * u * u, 3);
  }
  // Point by point: the points of one index do not enter another's fits, so each column is
  // read once into `present` / `values` and written back after its fits.
  std::vector<std::size_t> present;  // frame positions where point k is triangulated
  std::vector<Vec3> values;
  std::vector<std::pair<std::size_t, Vec3>> smoothed;
  std::int64_t changed = 0;
  for (std::size_t k = 0; k < num_points; ++k) {
    present.clear();
    values.clear();
    smoothed.clear();
    bool any_smoothable = false;
    for (std::size_t f = 0; f < num_frames; ++f) {
      const std::optional<Vec3>& p = tracklet->points[f][k];
      if (!p) continue;
      present.push_back(f);
      values.push_back(*p);
      any_smoothable =
          any_smoothable || views == nullptr || (*views)[f][k] <= options.smooth_max_views;
    }
    if (!any_smoothable || present.size() < 3) continue;
    std::size_t lo = 0;
    for (std::size_t i = 0; i < present.size(); ++i) {
      const std::size_t f = present[i];
      while (frames[f] - frames[present[lo]] > h) ++lo;
      if (views != nullptr && (*views)[f][k] > options.smooth_max_views) continue;
      // Weighted least squares of p(x) = a + b x, x = frame offset; the fit's value at x = 0 is
      // a = (S2 T0 - S1 T1) / (S0 S2 - S1^2).
      double s0 = 0.0;
      double s1 = 0.0;
      double s2 = 0.0;
      Vec3 t0 = Vec3::Zero();
      Vec3 t1 = Vec3::Zero();
      int samples = 0;
      for (std::size_t j = lo; j < present.size() && frames[present[j]] - frames[f] <= h; ++j) {
        const FrameIndex offset = frames[present[j]] - frames[f];
        const auto x = static_cast<double>(offset);
        const double w = weight[static_cast<std::size_t>(offset < 0 ? -offset : offset)];
        s0 += w;
        s1 += w * x;
        s2 += w * x * x;
        t0 += w * values[j];
        t1 += (w * x) * values[j];
        ++samples;
      }
      if (samples < 3) continue;
      const double det = s0 * s2 - s1 * s1;
      if (!(det > 1e-12 * s0 * s0)) continue;
      smoothed.emplace_back(f, (s2 * t0 - s1 * t1) / det);
    }
    for (const auto& [f, value] : smoothed) {
      if (value != *tracklet->points[f][k]) ++changed;
      tracklet->points[f][k] = value;
    }
  }
  return changed;
}

}  // namespace mvtrack::triangulation
