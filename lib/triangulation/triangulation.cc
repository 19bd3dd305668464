#include "triangulation/triangulation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "core/check.h"
#include "geometry/triangulation.h"

namespace mvtrack::triangulation {
namespace {

/// Whether point k of `obs` may be used: present, finite, confidence > 0 and >= min_confidence.
bool UsablePoint(
    const core::Observation2D& obs, int k, double min_confidence, Vec2* x, double* confidence) {
  const auto uk = static_cast<std::size_t>(k);
  if (uk >= obs.points_px.size() || uk >= obs.confidence.size()) return false;
  const double c = obs.confidence[uk];
  if (!(c > 0.0 && c >= min_confidence && std::isfinite(c))) return false;
  if (!obs.points_px[uk].allFinite()) return false;
  *x = obs.points_px[uk];
  *confidence = c;
  return true;
}

bool InFrontOfAll(std::span<const Mat34> projections, const Vec3& point) {
  return std::all_of(projections.begin(), projections.end(), [&](const Mat34& p) {
    return geometry::InFront(p, point);
  });
}

}  // namespace

std::string_view TriangulationMethodName(TriangulationMethod method) {
  switch (method) {
    case TriangulationMethod::kCmmt:
      return "cmmt";
    case TriangulationMethod::kDlt:
      return "dlt";
    case TriangulationMethod::kRansac:
      return "ransac";
  }
  return "unknown";
}

std::optional<TriangulationMethod> TriangulationMethodFromName(std::string_view name) {
  for (const TriangulationMethod m :
       {TriangulationMethod::kCmmt, TriangulationMethod::kDlt, TriangulationMethod::kRansac}) {
    if (name == TriangulationMethodName(m)) return m;
  }
  return std::nullopt;
}

bool TriangulationOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = std::string("triangulation: ") + reason;
    return false;
  };
  if (method != TriangulationMethod::kCmmt && method != TriangulationMethod::kDlt &&
      method != TriangulationMethod::kRansac) {
    return fail("method must be cmmt, dlt or ransac");
  }
  if (phi < 0) return fail("phi must be >= 0 frames");
  if (!(std::isfinite(kappa_m) && kappa_m > 0.0)) return fail("kappa_m must be finite and > 0");
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0)) {
    return fail("min_confidence must be in [0, 1]");
  }
  if (!(std::isfinite(ransac_threshold_px) && ransac_threshold_px > 0.0)) {
    return fail("ransac_threshold_px must be finite and > 0");
  }
  if (min_inliers < 1) return fail("min_inliers must be >= 1");
  if (max_views != 0 && max_views < 2) return fail("max_views must be 0 (all) or >= 2");
  return true;
}

PersonTriangulator::PersonTriangulator(const TriangulationOptions& options) : options_(options) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
}

int PersonTriangulator::Gather(const std::vector<core::Tracklet2D>& tracklets,
                               FrameIndex t,
                               int k,
                               bool interpolate,
                               bool best_only,
                               TriangulationStats* stats) {
  points_.clear();
  view_offsets_.assign(1, 0);
  view_score_.assign(view_projections_.size(), 0.0);
  const FrameIndex phi = options_.phi;
  const double min_conf = options_.min_confidence;
  int views_with_points = 0;
  const std::size_t num_views = view_projections_.size();
  for (std::size_t v = 0; v < num_views; ++v) {
    const std::size_t view_start = points_.size();
    auto add = [&](const Vec2& x, double c) {
      if (best_only && points_.size() > view_start) {
        if (c > points_[view_start].confidence) points_[view_start] = {x, c};
        return;
      }
      points_.push_back({x, c});
    };
    const auto e_begin = static_cast<std::size_t>(view_tracklet_offsets_[v]);
    const auto e_end = static_cast<std::size_t>(view_tracklet_offsets_[v + 1]);
    for (std::size_t e = e_begin; e < e_end; ++e) {
      const core::Tracklet2D& tr = tracklets[static_cast<std::size_t>(view_tracklets_[e])];
      const auto n = static_cast<int>(tr.frames.size());
      const int cur = cursor_[e];
      const bool observed_here = cur < n && tr.frames[static_cast<std::size_t>(cur)] == t;
      Vec2 x;
      double c = 0.0;
      if (observed_here &&
          UsablePoint(tr.observations[static_cast<std::size_t>(cur)], k, min_conf, &x, &c)) {
        add(x, c);
      }
      if (!interpolate) continue;
      // Eq. 6: nearest valid observations strictly before and strictly after t, within phi.
      int before = -1;
      Vec2 x0;
      double c0 = 0.0;
      for (int i = cur - 1; i >= 0 && tr.frames[static_cast<std::size_t>(i)] >= t - phi; --i) {
        if (UsablePoint(tr.observations[static_cast<std::size_t>(i)], k, min_conf, &x0, &c0)) {
          before = i;
          break;
        }
      }
      if (before < 0) continue;
      int after = -1;
      Vec2 x1;
      double c1 = 0.0;
      for (int i = observed_here ? cur + 1 : cur;
           i < n && tr.frames[static_cast<std::size_t>(i)] <= t + phi;
           ++i) {
        if (UsablePoint(tr.observations[static_cast<std::size_t>(i)], k, min_conf, &x1, &c1)) {
          after = i;
          break;
        }
      }
      if (after < 0) continue;
      const auto f0 = static_cast<double>(tr.frames[static_cast<std::size_t>(before)]);
      const auto f1 = static_cast<double>(tr.frames[static_cast<std::size_t>(after)]);
      const double alpha = (static_cast<double>(t) - f0) / (f1 - f0);
      add((1.0 - alpha) * x0 + alpha * x1, (1.0 - alpha) * c0 + alpha * c1);
      if (stats != nullptr) ++stats->num_interpolated_2d;
    }
    for (std::size_t i = view_start; i < points_.size(); ++i) {
      view_score_[v] = std::max(view_score_[v], points_[i].confidence);
    }
    if (points_.size() > view_start) ++views_with_points;
    view_offsets_.push_back(static_cast<int>(points_.size()));
  }
  return views_with_points;
}

void PersonTriangulator::SelectViews(int max_views, TriangulationStats* stats) {
  sel_views_.clear();
  const std::size_t num_views = view_offsets_.size() - 1;
  for (std::size_t v = 0; v < num_views; ++v) {
    if (view_offsets_[v + 1] > view_offsets_[v]) sel_views_.push_back(static_cast<int>(v));
  }
  if (max_views <= 0 || static_cast<int>(sel_views_.size()) <= max_views) return;
  if (stats != nullptr) ++stats->num_points_view_capped;
  // Greedy farthest-point selection on camera centres, seeded by the most confident view.
  const std::size_t n = sel_views_.size();
  chosen_.assign(n, 0);
  min_distance_.assign(n, std::numeric_limits<double>::infinity());
  auto score = [&](std::size_t i) { return view_score_[static_cast<std::size_t>(sel_views_[i])]; };
  for (int picked = 0; picked < max_views; ++picked) {
    std::size_t best = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (chosen_[i] != 0) continue;
      // sel_views_ is ascending, so on full ties the lower camera id stays.
      if (best == n || min_distance_[i] > min_distance_[best] ||
          (min_distance_[i] == min_distance_[best] && score(i) > score(best))) {
        best = i;
      }
    }
    chosen_[best] = 1;
    const auto vb = static_cast<std::size_t>(sel_views_[best]);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = center_distance_[vb * num_views + static_cast<std::size_t>(sel_views_[i])];
      min_distance_[i] = std::min(min_distance_[i], d);
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (chosen_[i] != 0) sel_views_[kept++] = sel_views_[i];
  }
  sel_views_.resize(kept);
}

std::optional<Vec3> PersonTriangulator::SolveCmmt(TriangulationStats* stats) {
  // Algorithm 2 a): every cross-view pair of (observed or interpolated) points -> Eq. 5.
  candidates_.clear();
  std::int64_t pairs = 0;
  // Each point's DLT rows depend on its own view only: computed once, not once per pair.
  rows_.resize(points_.size());
  for (const int vi : sel_views_) {
    const auto v = static_cast<std::size_t>(vi);
    for (int i = view_offsets_[v]; i < view_offsets_[v + 1]; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      rows_[ui] = geometry::MakeTwoViewRows(view_projections_[v], points_[ui].x_px);
    }
  }
  for (std::size_t sa = 0; sa < sel_views_.size(); ++sa) {
    const auto va = static_cast<std::size_t>(sel_views_[sa]);
    const Mat34& pa = view_projections_[va];
    for (std::size_t sb = sa + 1; sb < sel_views_.size(); ++sb) {
      const auto vb = static_cast<std::size_t>(sel_views_[sb]);
      const Mat34& pb = view_projections_[vb];
      for (int ia = view_offsets_[va]; ia < view_offsets_[va + 1]; ++ia) {
        const geometry::TwoViewRows& ra = rows_[static_cast<std::size_t>(ia)];
        for (int ib = view_offsets_[vb]; ib < view_offsets_[vb + 1]; ++ib) {
          ++pairs;
          const auto x = geometry::TriangulateTwoView(ra, rows_[static_cast<std::size_t>(ib)]);
          if (x && geometry::InFront(pa, *x) && geometry::InFront(pb, *x)) {
            candidates_.push_back(*x);
          }
        }
      }
    }
  }
  if (stats != nullptr) {
    stats->num_pairs_evaluated += pairs;
    stats->num_candidates += static_cast<std::int64_t>(candidates_.size());
    stats->max_candidates_per_point =
        std::max(stats->max_candidates_per_point, static_cast<int>(candidates_.size()));
  }
  if (candidates_.empty()) return std::nullopt;
  // b) complete linkage with cut kappa, c) centroid of the largest cluster (Eq. 7).
  const auto vote = voter_.Vote(candidates_, options_.kappa_m);
  if (!vote) return std::nullopt;
  const int required = std::min(options_.min_inliers, vote->num_candidates);
  if (vote->cluster_size < required) return std::nullopt;
  return vote->point;
}

std::optional<Vec3> PersonTriangulator::SolveDlt() {
  sel_projections_.clear();
  sel_points_.clear();
  sel_weights_.clear();
  for (const int vi : sel_views_) {
    const auto v = static_cast<std::size_t>(vi);
    const ViewPoint& p = points_[static_cast<std::size_t>(view_offsets_[v])];
    sel_projections_.push_back(view_projections_[v]);
    sel_points_.push_back(p.x_px);
    sel_weights_.push_back(p.confidence);
  }
  if (sel_points_.size() < 2) return std::nullopt;
  auto x = geometry::TriangulateDlt(sel_projections_, sel_points_, sel_weights_);
  if (!x || !InFrontOfAll(sel_projections_, *x)) return std::nullopt;
  return x;
}

std::optional<Vec3> PersonTriangulator::SolveRansac(TriangulationStats* stats) {
  sel_projections_.clear();
  sel_points_.clear();
  sel_weights_.clear();
  for (const int vi : sel_views_) {
    const auto v = static_cast<std::size_t>(vi);
    const ViewPoint& p = points_[static_cast<std::size_t>(view_offsets_[v])];
    sel_projections_.push_back(view_projections_[v]);
    sel_points_.push_back(p.x_px);
    sel_weights_.push_back(p.confidence);
  }
  const std::size_t n = sel_points_.size();
  if (n < 2) return std::nullopt;
  inlier_.resize(n);
  best_inlier_.assign(n, 0);
  int best_count = 0;
  double best_error = std::numeric_limits<double>::infinity();
  Vec3 best_point = Vec3::Zero();
  std::int64_t pairs = 0;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      ++pairs;
      const auto x = geometry::TriangulateTwoView(
          sel_projections_[a], sel_points_[a], sel_projections_[b], sel_points_[b]);
      if (!x || !geometry::InFront(sel_projections_[a], *x) ||
          !geometry::InFront(sel_projections_[b], *x)) {
        continue;
      }
      int count = 0;
      double error = 0.0;
      for (std::size_t v = 0; v < n; ++v) {
        inlier_[v] = 0;
        if (!geometry::InFront(sel_projections_[v], *x)) continue;
        const double e = geometry::ReprojectionErrorPx(sel_projections_[v], *x, sel_points_[v]);
        if (e <= options_.ransac_threshold_px) {
          inlier_[v] = 1;
          ++count;
          error += e;
        }
      }
      if (count > best_count || (count == best_count && count > 0 && error < best_error)) {
        best_count = count;
        best_error = error;
        best_point = *x;
        best_inlier_ = inlier_;
      }
    }
  }
  if (stats != nullptr) stats->num_pairs_evaluated += pairs;
  if (best_count < 2) return std::nullopt;
  fit_projections_.clear();
  fit_points_.clear();
  fit_weights_.clear();
  for (std::size_t v = 0; v < n; ++v) {
    if (best_inlier_[v] == 0) continue;
    fit_projections_.push_back(sel_projections_[v]);
    fit_points_.push_back(sel_points_[v]);
    fit_weights_.push_back(sel_weights_[v]);
  }
  auto refit = geometry::TriangulateDlt(fit_projections_, fit_points_, fit_weights_);
  if (refit && InFrontOfAll(fit_projections_, *refit)) return refit;
  return best_point;
}

void PersonTriangulator::set_phi(int phi) {
  MVTRACK_CHECK_MSG(phi >= 0, "PersonTriangulator::set_phi: phi must be >= 0");
  options_.phi = phi;
}

core::Tracklet3D PersonTriangulator::Triangulate(const geometry::CameraRig& rig,
                                                 const std::vector<core::Tracklet2D>& tracklets,
                                                 const std::vector<int>& cluster,
                                                 FrameIndex begin,
                                                 FrameIndex end,
                                                 int num_points,
                                                 TriangulationStats* stats,
                                                 int row_size) {
  MVTRACK_CHECK_MSG(num_points >= 1, "num_points must be >= 1");
  MVTRACK_CHECK_MSG(begin <= end, "window must satisfy begin <= end");
  if (stats != nullptr) *stats = TriangulationStats{};
  core::Tracklet3D out;
  out.source_tracklets = cluster;

  // Views: one per distinct (rig-known) camera, ascending camera id; fragments of one camera
  // share a view and are never paired with each other.
  entries_.clear();
  for (std::size_t pos = 0; pos < cluster.size(); ++pos) {
    const int idx = cluster[pos];
    MVTRACK_CHECK_MSG(idx >= 0 && static_cast<std::size_t>(idx) < tracklets.size(),
                      "cluster index out of range");
    const core::Tracklet2D& tr = tracklets[static_cast<std::size_t>(idx)];
    MVTRACK_CHECK_MSG(tr.frames.size() == tr.observations.size(),
                      "tracklet frames and observations differ in length");
    const auto rig_index = rig.IndexOf(tr.camera_id);
    if (!rig_index) continue;
    entries_.emplace_back(*rig_index, static_cast<int>(pos));
  }
  std::sort(entries_.begin(), entries_.end());
  view_projections_.clear();
  view_centers_.clear();
  view_tracklets_.clear();
  view_tracklet_offsets_.assign(1, 0);
  FrameIndex first = std::numeric_limits<FrameIndex>::max();
  FrameIndex last = std::numeric_limits<FrameIndex>::min();
  for (std::size_t e = 0; e < entries_.size(); ++e) {
    const int rig_index = entries_[e].first;
    if (e == 0 || rig_index != entries_[e - 1].first) {
      if (e > 0) view_tracklet_offsets_.push_back(static_cast<int>(view_tracklets_.size()));
      view_projections_.push_back(rig.projection(rig_index));
      view_centers_.push_back(rig.camera(rig_index).CenterInWorld());
      out.cameras.push_back(rig.camera(rig_index).id);
    }
    const int idx = cluster[static_cast<std::size_t>(entries_[e].second)];
    view_tracklets_.push_back(idx);
    const core::Tracklet2D& tr = tracklets[static_cast<std::size_t>(idx)];
    if (!tr.frames.empty()) {
      first = std::min(first, tr.frames.front());
      last = std::max(last, tr.frames.back());
    }
  }
  if (!entries_.empty()) view_tracklet_offsets_.push_back(static_cast<int>(view_tracklets_.size()));
  const std::size_t num_views = view_projections_.size();
  center_distance_.resize(num_views * num_views);
  for (std::size_t a = 0; a < num_views; ++a) {
    for (std::size_t b = 0; b < num_views; ++b) {
      center_distance_[a * num_views + b] = (view_centers_[a] - view_centers_[b]).norm();
    }
  }
  // A single view cannot be triangulated by any method.
  if (num_views < 2 || first > last) return out;

  // 3D points can only exist where some tracklet has observations on or around the frame.
  const FrameIndex t_begin = std::max(begin, first);
  const FrameIndex t_end = std::min(end, last + 1);
  cursor_.resize(view_tracklets_.size());
  for (std::size_t e = 0; e < view_tracklets_.size(); ++e) {
    const auto& frames = tracklets[static_cast<std::size_t>(view_tracklets_[e])].frames;
    cursor_[e] =
        static_cast<int>(std::lower_bound(frames.begin(), frames.end(), t_begin) - frames.begin());
  }

  const bool cmmt = options_.method == TriangulationMethod::kCmmt;
  const bool interpolate = cmmt && options_.phi > 0;
  if (t_begin < t_end) {
    out.frames.reserve(static_cast<std::size_t>(t_end - t_begin));
    out.points.reserve(static_cast<std::size_t>(t_end - t_begin));
  }
  for (FrameIndex t = t_begin; t < t_end; ++t) {
    for (std::size_t e = 0; e < view_tracklets_.size(); ++e) {
      const auto& frames = tracklets[static_cast<std::size_t>(view_tracklets_[e])].frames;
      while (static_cast<std::size_t>(cursor_[e]) < frames.size() &&
             frames[static_cast<std::size_t>(cursor_[e])] < t) {
        ++cursor_[e];
      }
    }
    row_.assign(static_cast<std::size_t>(std::max(num_points, row_size)), std::nullopt);
    bool any = false;
    for (int k = 0; k < num_points; ++k) {
      if (Gather(tracklets, t, k, interpolate, /*best_only=*/!cmmt, stats) < 2) continue;
      if (stats != nullptr) ++stats->num_points_attempted;
      SelectViews(options_.method == TriangulationMethod::kDlt ? 0 : options_.max_views, stats);
      std::optional<Vec3> point;
      switch (options_.method) {
        case TriangulationMethod::kCmmt:
          point = SolveCmmt(stats);
          break;
        case TriangulationMethod::kDlt:
          point = SolveDlt();
          break;
        case TriangulationMethod::kRansac:
          point = SolveRansac(stats);
          break;
      }
      if (!point) continue;
      row_[static_cast<std::size_t>(k)] = *point;
      any = true;
      if (stats != nullptr) ++stats->num_points_triangulated;
    }
    if (any) {
      out.frames.push_back(t);
      out.points.push_back(row_);
    }
  }
  return out;
}

core::Tracklet3D TriangulatePerson(const geometry::CameraRig& rig,
                                   const std::vector<core::Tracklet2D>& tracklets,
                                   const std::vector<int>& cluster,
                                   FrameIndex begin,
                                   FrameIndex end,
                                   int num_points,
                                   const TriangulationOptions& options) {
  PersonTriangulator triangulator(options);
  return triangulator.Triangulate(rig, tracklets, cluster, begin, end, num_points);
}

}  // namespace mvtrack::triangulation
