#include "association/tracklet_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "core/appearance.h"
#include "core/check.h"
#include "geometry/epipolar.h"

namespace mvtrack::association {
namespace {

constexpr double kEmptyCode = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfiniteCode = std::numeric_limits<double>::infinity();

bool Usable(const core::Observation2D& o, std::size_t k, double min_confidence) {
  if (k >= o.confidence.size()) return false;
  const double c = o.confidence[k];
  return c > 0.0 && c >= min_confidence;
}

/// The floor point's term (AssociationOptions::floor_point) is the mean, not the sum, of its
/// two one-way normalized distances: see DECISIONS "Feet on the floor".
constexpr double kFloorTermWeight = 0.5;

/// The pixel of camera `to` that sees the floor point (z = h) seen by undistorted pixel `x` of
/// camera `from`; nullopt when x's ray does not meet the floor in front of `from`, or the floor
/// point is behind `to`.
std::optional<Vec2> CarryOverFloor(const geometry::CameraModel& from,
                                   const geometry::CameraModel& to,
                                   double h,
                                   const Vec2& x) {
  const std::optional<Vec3> on_floor = from.PointOnRayAtHeight(x, h);
  if (!on_floor) return std::nullopt;
  return to.ProjectUndistorted(*on_floor);
}

/// The cameras of a pair and the floor height, for the floor point.
struct FloorPair {
  const geometry::CameraModel* a = nullptr;
  const geometry::CameraModel* b = nullptr;
  double h = 0.0;
};

/// Eq. 2 averaged over the points usable in both observations; nullopt if there is none.
/// The floor point is compared through `floor` (required when options.floor_point >= 0).
std::optional<double> FrameDistance(const core::Observation2D& a,
                                    const core::Observation2D& b,
                                    const Mat3& f_a_to_b,
                                    const FloorPair* floor,
                                    const AssociationOptions& options) {
  MVTRACK_DCHECK(a.scale_px > 0.0 && b.scale_px > 0.0);
  std::size_t num_points = std::min(a.points_px.size(), b.points_px.size());
  if (options.num_points > 0) {
    num_points = std::min(num_points, static_cast<std::size_t>(options.num_points));
  }
  double sum = 0.0;
  int used = 0;
  for (std::size_t k = 0; k < num_points; ++k) {
    if (!Usable(a, k, options.min_confidence) || !Usable(b, k, options.min_confidence)) continue;
    const Vec2& xa = a.points_px[k];
    const Vec2& xb = b.points_px[k];
    double d = 0.0;
    if (static_cast<int>(k) == options.floor_point) {
      const std::optional<Vec2> ta = CarryOverFloor(*floor->a, *floor->b, floor->h, xa);
      const std::optional<Vec2> tb = CarryOverFloor(*floor->b, *floor->a, floor->h, xb);
      if (!ta || !tb) continue;
      d = kFloorTermWeight *
          ((*tb - xa).norm() / std::abs(a.scale_px) + (*ta - xb).norm() / std::abs(b.scale_px));
    } else {
      d = geometry::NormalizedEpipolarDistance(xa, a.scale_px, xb, b.scale_px, f_a_to_b);
    }
    if (!std::isfinite(d)) continue;
    sum += d;
    ++used;
  }
  if (used == 0) return std::nullopt;
  return sum / static_cast<double>(used);
}

/// Eq. 4's mean(S) as a value. Sums of finite non-negative terms can only overflow to +inf
/// (absurd inputs, e.g. a scale of 1e-300 px); that is clamped to the largest finite double so
/// that the result stays a valid kValue (and far above any lambda).
TrackletDistance MeanValue(double sum, int frames) {
  return TrackletDistance::Value(
      std::min(sum / static_cast<double>(frames), std::numeric_limits<double>::max()));
}

// A tracklet's appearance: the unit-length mean of its embeddings (those of the first one's
// length; empty when it has none), how many there were and the length of their sum.
struct Look {
  std::vector<float> unit;
  int count = 0;
  double length = 0.0;
};

Look MeanLook(const core::Tracklet2D& t) {
  core::EmbeddingMean mean;
  for (const core::Observation2D& o : t.observations) {
    if (o.embedding) mean.Add(*o.embedding);
  }
  return {mean.Unit(), mean.count(), mean.Length()};
}

bool UsesAppearance(const AssociationOptions& options) {
  return options.appearance_weight > 0.0 || options.appearance_gate < 2.0;
}

// Appearance fusion of a cross-camera distance (AssociationOptions::appearance_weight and
// appearance_gate).
TrackletDistance Fuse(TrackletDistance d,
                      const Look& a,
                      const Look& b,
                      const AssociationOptions& options) {
  if (!d.is_value() || a.unit.empty() || a.unit.size() != b.unit.size()) return d;
  const double look = core::CosineDistance(a.unit, b.unit);
  if (look > options.appearance_gate &&
      ExpectedLookDistance(a.count, a.length, b.count, b.length) <= 0.5 * options.appearance_gate) {
    return TrackletDistance::Infinite();
  }
  if (options.appearance_weight <= 0.0) return d;
  return TrackletDistance::Value(
      std::min(d.value + options.appearance_weight * look, std::numeric_limits<double>::max()));
}

bool DisjointRanges(const core::Tracklet2D& a, const core::Tracklet2D& b) {
  return a.frames.empty() || b.frames.empty() || a.frames.back() < b.frames.front() ||
         b.frames.back() < a.frames.front();
}

/// The all-pairs computation of Eq. 3-4 behind ComputeDistanceMatrix*, organised for speed:
/// tracklets are flattened camera by camera into contiguous arrays (usable points only, inverse
/// scales), and for every pair of cameras (c, d) each point of c's tracklets gets its epipolar
/// line in d once, pre-divided by the line's norm, so that Eq. 2 for a pair of points costs two
/// dot products. Values equal the pairwise definition (ComputeTrackletDistance) up to rounding.
class AllPairs {
 public:
  AllPairs(const geometry::CameraRig& rig,
           const std::vector<core::Tracklet2D>& tracklets,
           const AssociationOptions& options)
      : rig_(rig), n_(tracklets.size()), options_(options) {
    std::string why;
    MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
    // Group tracklets by camera (rig order), keeping input order inside a camera.
    std::vector<int> camera_index(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const std::optional<int> index = rig.IndexOf(tracklets[i].camera_id);
      MVTRACK_CHECK_MSG(index.has_value(),
                        "ComputeDistanceMatrix: a tracklet's camera is not in the rig");
      camera_index[i] = *index;
    }
    order_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) order_[i] = i;
    std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
      return camera_index[a] < camera_index[b];
    });
    // Flatten: frames, inverse scales, points (x = NaN when unusable).
    frame_begin_.assign(n_ + 1, 0);
    point_begin_.assign(n_ + 1, 0);
    num_points_.assign(n_, 0);
    for (std::size_t s = 0; s < n_; ++s) {
      const core::Tracklet2D& t = tracklets[order_[s]];
      MVTRACK_DCHECK(t.frames.size() == t.observations.size());
      std::size_t max_points = 0;
      for (const core::Observation2D& o : t.observations) {
        max_points = std::max(max_points, o.points_px.size());
      }
      if (options.num_points > 0) {
        max_points = std::min(max_points, static_cast<std::size_t>(options.num_points));
      }
      num_points_[s] = max_points;
      frame_begin_[s + 1] = frame_begin_[s] + t.frames.size();
      point_begin_[s + 1] = point_begin_[s] + t.frames.size() * max_points;
    }
    if (UsesAppearance(options_)) {
      looks_.resize(n_);
      for (std::size_t s = 0; s < n_; ++s) looks_[s] = MeanLook(tracklets[order_[s]]);
    }
    frames_.resize(frame_begin_[n_]);
    inv_scale_.resize(frame_begin_[n_]);
    px_.assign(point_begin_[n_], std::numeric_limits<double>::quiet_NaN());
    py_.assign(point_begin_[n_], 0.0);
    for (std::size_t s = 0; s < n_; ++s) {
      const core::Tracklet2D& t = tracklets[order_[s]];
      for (std::size_t f = 0; f < t.frames.size(); ++f) {
        const core::Observation2D& o = t.observations[f];
        MVTRACK_DCHECK(o.scale_px > 0.0);
        frames_[frame_begin_[s] + f] = t.frames[f];
        inv_scale_[frame_begin_[s] + f] = 1.0 / std::abs(o.scale_px);
        for (std::size_t k = 0; k < std::min(o.points_px.size(), num_points_[s]); ++k) {
          if (!Usable(o, k, options.min_confidence)) continue;
          const std::size_t p = point_begin_[s] + f * num_points_[s] + k;
          px_[p] = o.points_px[k].x();
          py_[p] = o.points_px[k].y();
        }
      }
    }
    // The floor point of every observation on the floor, once (ComputeFloorTransfers projects
    // it into each other camera).
    if (options.floor_point >= 0) {
      const auto k = static_cast<std::size_t>(options.floor_point);
      on_floor_.resize(frame_begin_[n_]);
      for (std::size_t s = 0; s < n_; ++s) {
        if (k >= num_points_[s]) continue;
        const geometry::CameraModel& camera = rig.camera(camera_index[order_[s]]);
        for (std::size_t f = frame_begin_[s]; f < frame_begin_[s + 1]; ++f) {
          const std::size_t p = point_begin_[s] + (f - frame_begin_[s]) * num_points_[s] + k;
          if (std::isnan(px_[p])) continue;
          on_floor_[f] = camera.PointOnRayAtHeight(Vec2(px_[p], py_[p]), options.floor_height_m);
        }
      }
    }
    // Camera groups [group_begin_[g], group_begin_[g + 1]) in flat order.
    for (std::size_t s = 0; s < n_; ++s) {
      if (s == 0 || camera_index[order_[s]] != camera_index[order_[s - 1]]) {
        group_begin_.push_back(s);
        group_camera_.push_back(camera_index[order_[s]]);
      }
    }
    group_begin_.push_back(n_);
    std::size_t max_group_points = 0;
    for (std::size_t g = 0; g + 1 < group_begin_.size(); ++g) {
      max_group_points = std::max(
          max_group_points, point_begin_[group_begin_[g + 1]] - point_begin_[group_begin_[g]]);
    }
    lines_a_.resize(3 * max_group_points);
    lines_b_.resize(3 * max_group_points);
  }

  DistanceMatrix Compute(double cutoff) {
    DistanceMatrix matrix(static_cast<int>(n_));
    const std::size_t num_groups = group_begin_.size() - 1;
    for (std::size_t g = 0; g < num_groups; ++g) {
      // Same camera: ∞ with a common frame, else ∅ (Eq. 4).
      for (std::size_t a = group_begin_[g]; a < group_begin_[g + 1]; ++a) {
        for (std::size_t b = a + 1; b < group_begin_[g + 1]; ++b) {
          if (HaveCommonFrame(a, b)) Set(&matrix, a, b, TrackletDistance::Infinite());
        }
      }
      for (std::size_t h = g + 1; h < num_groups; ++h) {
        if (!rig_.SharesView(group_camera_[g], group_camera_[h])) {
          // Cameras that never see one place: at a common frame not one person (∞, as two
          // tracklets of one camera), else ∅.
          for (std::size_t a = group_begin_[g]; a < group_begin_[g + 1]; ++a) {
            for (std::size_t b = group_begin_[h]; b < group_begin_[h + 1]; ++b) {
              if (HaveCommonFrame(a, b)) Set(&matrix, a, b, TrackletDistance::Infinite());
            }
          }
          continue;
        }
        ComputeLines(g, rig_.fundamental(group_camera_[g], group_camera_[h]), &lines_a_);
        ComputeLines(h, rig_.fundamental(group_camera_[h], group_camera_[g]), &lines_b_);
        if (options_.floor_point >= 0) {
          ComputeFloorTransfers(g, group_camera_[h], &lines_a_);
          ComputeFloorTransfers(h, group_camera_[g], &lines_b_);
        }
        for (std::size_t a = group_begin_[g]; a < group_begin_[g + 1]; ++a) {
          for (std::size_t b = group_begin_[h]; b < group_begin_[h + 1]; ++b) {
            TrackletDistance d = CrossCamera(g, a, h, b, cutoff);
            if (!looks_.empty()) d = Fuse(d, looks_[a], looks_[b], options_);
            if (!d.is_empty()) Set(&matrix, a, b, d);
          }
        }
      }
    }
    return matrix;
  }

 private:
  void Set(DistanceMatrix* matrix, std::size_t a, std::size_t b, TrackletDistance d) const {
    matrix->set(static_cast<int>(order_[a]), static_cast<int>(order_[b]), d);
  }

  /// Epipolar lines (in the other camera, via `f`) of every usable point of group g, divided by
  /// the norm of their (a, b) part; indexed by flat point index minus the group's first one.
  void ComputeLines(std::size_t g, const Mat3& f, std::vector<double>* lines) const {
    const std::size_t begin = point_begin_[group_begin_[g]];
    const std::size_t end = point_begin_[group_begin_[g + 1]];
    double* l = lines->data();
    for (std::size_t p = begin; p < end; ++p) {
      const double x = px_[p];
      const double y = py_[p];
      double* out = l + 3 * (p - begin);
      if (std::isnan(x)) continue;  // unusable point; never read
      const double a = f(0, 0) * x + f(0, 1) * y + f(0, 2);
      const double b = f(1, 0) * x + f(1, 1) * y + f(1, 2);
      const double c = f(2, 0) * x + f(2, 1) * y + f(2, 2);
      const double inv_norm = 1.0 / std::sqrt(a * a + b * b);  // inf for a degenerate line
      out[0] = a * inv_norm;
      out[1] = b * inv_norm;
      out[2] = c * inv_norm;
    }
  }

  /// Replaces the line of every floor point (AssociationOptions::floor_point) of group g by the
  /// point carried over the floor into rig camera `to` (CarryOverFloor, with the floor points
  /// found once in the constructor), stored as (x, y, NaN); (NaN, NaN, NaN) when there is none.
  void ComputeFloorTransfers(std::size_t g, int to, std::vector<double>* lines) const {
    const geometry::CameraModel& camera = rig_.camera(to);
    const std::size_t base = point_begin_[group_begin_[g]];
    const auto k = static_cast<std::size_t>(options_.floor_point);
    for (std::size_t s = group_begin_[g]; s < group_begin_[g + 1]; ++s) {
      if (k >= num_points_[s]) continue;
      for (std::size_t f = frame_begin_[s]; f < frame_begin_[s + 1]; ++f) {
        const std::size_t p = point_begin_[s] + (f - frame_begin_[s]) * num_points_[s] + k;
        if (std::isnan(px_[p])) continue;  // unusable point; never read
        double* out = lines->data() + 3 * (p - base);
        const std::optional<Vec2> t =
            on_floor_[f] ? camera.ProjectUndistorted(*on_floor_[f]) : std::nullopt;
        out[0] = t ? t->x() : std::numeric_limits<double>::quiet_NaN();
        out[1] = t ? t->y() : std::numeric_limits<double>::quiet_NaN();
        out[2] = std::numeric_limits<double>::quiet_NaN();
      }
    }
  }

  /// Whether flat tracklets a and b share a frame.
  bool HaveCommonFrame(std::size_t a, std::size_t b) const {
    std::size_t ia = frame_begin_[a], ib = frame_begin_[b];
    const std::size_t ea = frame_begin_[a + 1], eb = frame_begin_[b + 1];
    while (ia < ea && ib < eb) {
      if (frames_[ia] < frames_[ib]) {
        ++ia;
      } else if (frames_[ib] < frames_[ia]) {
        ++ib;
      } else {
        return true;
      }
    }
    return false;
  }

  /// Eq. 3-4 for a in group g and b in group h (different cameras); lines_a_ / lines_b_ hold
  /// the lines of groups g / h. Early exit as documented for ComputeDistanceMatrixForClustering.
  TrackletDistance CrossCamera(
      std::size_t g, std::size_t a, std::size_t h, std::size_t b, double cutoff) const {
    const std::size_t ea = frame_begin_[a + 1], eb = frame_begin_[b + 1];
    if (frame_begin_[a] == ea || frame_begin_[b] == eb ||
        frames_[ea - 1] < frames_[frame_begin_[b]] || frames_[eb - 1] < frames_[frame_begin_[a]]) {
      return TrackletDistance::Empty();  // Ψ_a ∩ Ψ_b = ∅
    }
    // Upper bound of |Ψ_a ∩ Ψ_b| (frames are distinct integers): the early exit's denominator.
    const FrameIndex overlap = std::min(frames_[ea - 1], frames_[eb - 1]) -
                               std::max(frames_[frame_begin_[a]], frames_[frame_begin_[b]]) + 1;
    const double bound_frames =
        std::isfinite(cutoff)
            ? static_cast<double>(std::min(
                  {static_cast<std::size_t>(overlap), ea - frame_begin_[a], eb - frame_begin_[b]}))
            : 0.0;
    // A relative margin far above rounding keeps "proven >= cutoff" true for the exact mean.
    const double stop_sum = cutoff * bound_frames * (1.0 + 1e-9);
    const std::size_t points = std::min(num_points_[a], num_points_[b]);
    const std::size_t floor_point = options_.floor_point >= 0
                                        ? static_cast<std::size_t>(options_.floor_point)
                                        : std::numeric_limits<std::size_t>::max();
    const std::size_t line_base_a = point_begin_[group_begin_[g]];
    const std::size_t line_base_b = point_begin_[group_begin_[h]];
    double sum = 0.0;
    int used_frames = 0;
    std::size_t ia = frame_begin_[a], ib = frame_begin_[b];
    while (ia < ea && ib < eb) {
      if (frames_[ia] < frames_[ib]) {
        ++ia;
        continue;
      }
      if (frames_[ib] < frames_[ia]) {
        ++ib;
        continue;
      }
      const std::size_t pa = point_begin_[a] + (ia - frame_begin_[a]) * num_points_[a];
      const std::size_t pb = point_begin_[b] + (ib - frame_begin_[b]) * num_points_[b];
      const double inv_sa = inv_scale_[ia];
      const double inv_sb = inv_scale_[ib];
      double frame_sum = 0.0;
      int used_points = 0;
      for (std::size_t k = 0; k < points; ++k) {
        const double xa = px_[pa + k], xb = px_[pb + k];
        if (std::isnan(xa) || std::isnan(xb)) continue;  // not usable in both
        const double ya = py_[pa + k], yb = py_[pb + k];
        const double* la = &lines_a_[3 * (pa + k - line_base_a)];  // a's point, line in b
        const double* lb = &lines_b_[3 * (pb + k - line_base_b)];  // b's point, line in a
        double d = 0.0;
        if (k == floor_point) {
          // The floor point: la / lb hold the points carried over the floor (or NaN).
          if (std::isnan(la[0]) || std::isnan(lb[0])) continue;
          d = kFloorTermWeight * (std::hypot(lb[0] - xa, lb[1] - ya) * inv_sa +
                                  std::hypot(la[0] - xb, la[1] - yb) * inv_sb);
        } else {
          // Eq. 2: d(x_a, l_a(x_b)) / |w_a + h_a| + d(x_b, l_b(x_a)) / |w_b + h_b|.
          d = std::abs(lb[0] * xa + lb[1] * ya + lb[2]) * inv_sa +
              std::abs(la[0] * xb + la[1] * yb + la[2]) * inv_sb;
        }
        if (!std::isfinite(d)) continue;  // a point at an epipole
        frame_sum += d;
        ++used_points;
      }
      if (used_points > 0) {
        sum += frame_sum / static_cast<double>(used_points);
        ++used_frames;
        if (bound_frames > 0.0 && sum >= stop_sum) {
          // Proven: mean >= sum / bound_frames >= cutoff. Report that lower bound.
          return TrackletDistance::Value(
              std::min(std::max(cutoff, sum / bound_frames), std::numeric_limits<double>::max()));
        }
      }
      ++ia;
      ++ib;
    }
    if (used_frames == 0) return TrackletDistance::Empty();  // no common usable point
    return MeanValue(sum, used_frames);                      // Eq. 4, mean(S)
  }

  const geometry::CameraRig& rig_;
  std::size_t n_;
  AssociationOptions options_;
  std::vector<Look> looks_;               ///< appearance on: per flat tracklet, MeanLook
  std::vector<std::size_t> order_;        ///< flat position -> input index
  std::vector<std::size_t> frame_begin_;  ///< per flat tracklet (+1), into frames_/inv_scale_
  std::vector<std::size_t> point_begin_;  ///< per flat tracklet (+1), into px_/py_
  std::vector<std::size_t> num_points_;   ///< points per observation slot of a flat tracklet
  std::vector<FrameIndex> frames_;
  std::vector<double> inv_scale_;
  std::vector<double> px_, py_;  ///< px_ is NaN for an unusable point
  /// Per flat observation, its floor point on the floor (AssociationOptions::floor_point).
  std::vector<std::optional<Vec3>> on_floor_;
  std::vector<std::size_t> group_begin_;   ///< flat tracklet ranges of one camera each (+ end)
  std::vector<int> group_camera_;          ///< rig index of each group
  std::vector<double> lines_a_, lines_b_;  ///< normalized lines of the two current groups
};

}  // namespace

DistanceMatrix::DistanceMatrix(int n) : n_(n) {
  MVTRACK_CHECK_MSG(n >= 0, "DistanceMatrix: size must be >= 0");
  const auto count = static_cast<std::size_t>(n);
  packed_.assign(count > 0 ? count * (count - 1) / 2 : 0, kEmptyCode);
}

std::size_t DistanceMatrix::PackedIndex(int i, int j) const {
  MVTRACK_CHECK_MSG(i >= 0 && j >= 0 && i < n_ && j < n_ && i != j,
                    "DistanceMatrix: index out of range or on the diagonal");
  if (i > j) std::swap(i, j);
  const auto n = static_cast<std::size_t>(n_);
  const auto r = static_cast<std::size_t>(i);
  const auto c = static_cast<std::size_t>(j);
  return r * n - r * (r + 1) / 2 + (c - r - 1);
}

TrackletDistance DistanceMatrix::at(int i, int j) const {
  const double code = packed_[PackedIndex(i, j)];
  if (std::isnan(code)) return TrackletDistance::Empty();
  if (std::isinf(code)) return TrackletDistance::Infinite();
  return TrackletDistance::Value(code);
}

void DistanceMatrix::set(int i, int j, TrackletDistance d) {
  double code = kEmptyCode;
  switch (d.kind) {
    case TrackletDistance::Kind::kEmpty:
      code = kEmptyCode;
      break;
    case TrackletDistance::Kind::kInfinite:
      code = kInfiniteCode;
      break;
    case TrackletDistance::Kind::kValue:
      MVTRACK_CHECK_MSG(std::isfinite(d.value) && d.value >= 0.0,
                        "DistanceMatrix::set: a value must be finite and >= 0");
      code = d.value;
      break;
  }
  packed_[PackedIndex(i, j)] = code;
}

namespace {

TrackletDistance PairDistance(const core::Tracklet2D& a,
                              const core::Tracklet2D& b,
                              const Mat3& f_a_to_b,
                              const FloorPair* floor,
                              const AssociationOptions& options) {
  MVTRACK_DCHECK(a.frames.size() == a.observations.size());
  MVTRACK_DCHECK(b.frames.size() == b.observations.size());
  if (DisjointRanges(a, b)) return TrackletDistance::Empty();  // Eq. 4, Ψ_a ∩ Ψ_b = ∅
  const bool same_camera = a.camera_id == b.camera_id;
  // Eq. 3: walk the common frames Ψ_a ∩ Ψ_b (both frame lists are strictly increasing).
  double sum = 0.0;
  int used_frames = 0;
  std::size_t ia = 0;
  std::size_t ib = 0;
  while (ia < a.frames.size() && ib < b.frames.size()) {
    if (a.frames[ia] < b.frames[ib]) {
      ++ia;
    } else if (b.frames[ib] < a.frames[ia]) {
      ++ib;
    } else {
      if (same_camera) return TrackletDistance::Infinite();  // Eq. 4, c_a = c_b with overlap
      if (auto d =
              FrameDistance(a.observations[ia], b.observations[ib], f_a_to_b, floor, options)) {
        sum += *d;
        ++used_frames;
      }
      ++ia;
      ++ib;
    }
  }
  if (used_frames == 0) return TrackletDistance::Empty();  // no common (usable) frame
  const TrackletDistance d = MeanValue(sum, used_frames);  // Eq. 4, mean(S)
  if (!UsesAppearance(options)) return d;
  return Fuse(d, MeanLook(a), MeanLook(b), options);
}

}  // namespace

TrackletDistance ComputeTrackletDistance(const core::Tracklet2D& a,
                                         const core::Tracklet2D& b,
                                         const Mat3& f_a_to_b,
                                         const AssociationOptions& options) {
  MVTRACK_CHECK_MSG(options.floor_point < 0,
                    "ComputeTrackletDistance: a floor point needs the cameras (the rig overload)");
  return PairDistance(a, b, f_a_to_b, nullptr, options);
}

TrackletDistance ComputeTrackletDistance(const geometry::CameraRig& rig,
                                         const core::Tracklet2D& a,
                                         const core::Tracklet2D& b,
                                         const AssociationOptions& options) {
  const std::optional<int> ia = rig.IndexOf(a.camera_id);
  const std::optional<int> ib = rig.IndexOf(b.camera_id);
  MVTRACK_CHECK_MSG(ia.has_value() && ib.has_value(),
                    "ComputeTrackletDistance: a tracklet's camera is not in the rig");
  if (*ia == *ib) return PairDistance(a, b, Mat3::Zero(), nullptr, options);
  if (!rig.SharesView(*ia, *ib)) {
    // Cameras that never see one place: at a common frame not one person, else ∅.
    const bool common =
        std::find_first_of(a.frames.begin(), a.frames.end(), b.frames.begin(), b.frames.end()) !=
        a.frames.end();
    return common ? TrackletDistance::Infinite() : TrackletDistance::Empty();
  }
  const FloorPair floor{&rig.camera(*ia), &rig.camera(*ib), options.floor_height_m};
  return PairDistance(
      a, b, rig.fundamental(*ia, *ib), options.floor_point >= 0 ? &floor : nullptr, options);
}

double ExpectedLookDistance(int count_a, double length_a, int count_b, double length_b) {
  if (count_a < 2 || count_b < 2 || !(length_a > 0.0) || !(length_b > 0.0)) return 2.0;
  const auto self_cosine = [](int count, double length) {
    const double n = static_cast<double>(count);
    return std::clamp((length * length - n) / (n * (n - 1.0)), 0.0, 1.0);
  };
  const double s = std::sqrt(self_cosine(count_a, length_a) * self_cosine(count_b, length_b));
  const double cosine =
      static_cast<double>(count_a) * static_cast<double>(count_b) * s / (length_a * length_b);
  return std::clamp(1.0 - cosine, 0.0, 2.0);
}

DistanceMatrix ComputeDistanceMatrix(const geometry::CameraRig& rig,
                                     const std::vector<core::Tracklet2D>& tracklets,
                                     const AssociationOptions& options) {
  return AllPairs(rig, tracklets, options).Compute(kInfiniteCode);
}

DistanceMatrix ComputeDistanceMatrixForClustering(const geometry::CameraRig& rig,
                                                  const std::vector<core::Tracklet2D>& tracklets,
                                                  const AssociationOptions& options) {
  return AllPairs(rig, tracklets, options).Compute(options.lambda);
}

}  // namespace mvtrack::association
