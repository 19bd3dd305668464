#include "linking/window_linker.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

#include "core/check.h"
#include "core/linear_assignment.h"

namespace mvtrack::linking {
namespace {

using PointsAtFrame = std::vector<std::optional<Vec3>>;

constexpr double kForbidden = std::numeric_limits<double>::infinity();
// Every finite cost is feasible; the gates are applied per pair by writing kForbidden.
constexpr double kAnyFiniteCost = std::numeric_limits<double>::max();

bool IsValidPoint(const std::optional<Vec3>& point) {
  return point.has_value() && point->allFinite();
}

bool HasValidPoint(const PointsAtFrame& points) {
  return std::any_of(points.begin(), points.end(), IsValidPoint);
}

void CheckWellFormed(const core::Tracklet3D& tracklet) {
  MVTRACK_CHECK_MSG(tracklet.frames.size() == tracklet.points.size(),
                    "Tracklet3D: points must be parallel to frames");
  MVTRACK_CHECK_MSG(std::adjacent_find(tracklet.frames.begin(),
                                       tracklet.frames.end(),
                                       [](FrameIndex x, FrameIndex y) { return x >= y; }) ==
                        tracklet.frames.end(),
                    "Tracklet3D: frames must be strictly increasing");
}

// Inner term of Eq. 8 for one frame: mean over point indices valid in both of ||X_m - X_n||.
std::optional<double> FrameDistance(const PointsAtFrame& a, const PointsAtFrame& b) {
  const std::size_t n = std::min(a.size(), b.size());
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (IsValidPoint(a[k]) && IsValidPoint(b[k])) {
      sum += (*a[k] - *b[k]).norm();
      ++count;
    }
  }
  if (count == 0) return std::nullopt;
  return sum / static_cast<double>(count);
}

// Centroid of the valid points of `points` whose index is selected by `use`.
Vec3 Centroid(const PointsAtFrame& points, const std::vector<char>& use) {
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (use[k] != 0) {
      sum += *points[k];
      ++count;
    }
  }
  MVTRACK_DCHECK(count > 0);
  return sum / static_cast<double>(count);
}

// Adds `windows` missed windows to `track`, saturating at max_missed_windows + 1 (enough to die).
void AddMisses(LinkedTrack* track, std::uint64_t windows, int max_missed_windows) {
  const auto room = static_cast<std::uint64_t>(max_missed_windows + 1 - track->missed_windows);
  track->missed_windows += static_cast<int>(std::min(windows, room));
}

}  // namespace

bool LinkerOptions::Validate(std::string* why) const {
  const auto fail = [why](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!std::isfinite(max_link_distance_m) || max_link_distance_m <= 0.0) {
    return fail("max_link_distance_m must be finite and > 0");
  }
  if (min_hits < 1) return fail("min_hits must be >= 1");
  if (max_missed_windows < 0) return fail("max_missed_windows must be >= 0");
  // Keeps max_missed_windows + 1 representable (AddMisses saturates there).
  if (max_missed_windows == std::numeric_limits<int>::max()) {
    return fail("max_missed_windows must be < INT_MAX");
  }
  if (!std::isfinite(max_speed_m_per_frame) || max_speed_m_per_frame < 0.0) {
    return fail("max_speed_m_per_frame must be finite and >= 0");
  }
  return true;
}

namespace {

// MeanOverlapDistance of two tracklets already checked by CheckWellFormed (WindowLinker::Link
// checks every tracklet once when it arrives, so its pairwise loop skips the re-checks).
std::optional<double> MeanOverlapDistanceOfChecked(const core::Tracklet3D& a,
                                                   const core::Tracklet3D& b) {
  // Eq. 8: D_ij = 1/|Psi_i ∩ Psi_j| * sum over the common frames; the frames are sorted, so a
  // merge walk finds Psi_i ∩ Psi_j. Frames without a common valid point carry no measurement
  // and are left out of both the sum and the count.
  double sum = 0.0;
  int frames = 0;
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.frames.size() && j < b.frames.size()) {
    if (a.frames[i] < b.frames[j]) {
      ++i;
    } else if (b.frames[j] < a.frames[i]) {
      ++j;
    } else {
      if (const auto d = FrameDistance(a.points[i], b.points[j])) {
        sum += *d;
        ++frames;
      }
      ++i;
      ++j;
    }
  }
  if (frames == 0) return std::nullopt;
  return sum / static_cast<double>(frames);
}

}  // namespace

std::optional<double> MeanOverlapDistance(const core::Tracklet3D& a, const core::Tracklet3D& b) {
  CheckWellFormed(a);
  CheckWellFormed(b);
  return MeanOverlapDistanceOfChecked(a, b);
}

std::optional<GapMeasurement> MeasureGap(const core::Tracklet3D& from, const core::Tracklet3D& to) {
  CheckWellFormed(from);
  CheckWellFormed(to);
  const auto last = std::find_if(from.points.rbegin(), from.points.rend(), HasValidPoint);
  const auto first = std::find_if(to.points.begin(), to.points.end(), HasValidPoint);
  if (last == from.points.rend() || first == to.points.end()) return std::nullopt;
  const auto from_index = static_cast<std::size_t>(from.points.rend() - last) - 1;
  const auto to_index = static_cast<std::size_t>(first - to.points.begin());
  const PointsAtFrame& p = *last;
  const PointsAtFrame& q = *first;

  // Prefer the point indices valid in both frames (the same joints); otherwise each frame's own.
  std::vector<char> use_p(p.size(), 0);
  std::vector<char> use_q(q.size(), 0);
  bool any_common = false;
  for (std::size_t k = 0; k < std::min(p.size(), q.size()); ++k) {
    if (IsValidPoint(p[k]) && IsValidPoint(q[k])) {
      use_p[k] = 1;
      use_q[k] = 1;
      any_common = true;
    }
  }
  if (!any_common) {
    for (std::size_t k = 0; k < p.size(); ++k) use_p[k] = IsValidPoint(p[k]) ? 1 : 0;
    for (std::size_t k = 0; k < q.size(); ++k) use_q[k] = IsValidPoint(q[k]) ? 1 : 0;
  }
  GapMeasurement gap;
  gap.distance_m = (Centroid(p, use_p) - Centroid(q, use_q)).norm();
  const FrameIndex from_frame = from.frames[from_index];
  const FrameIndex to_frame = to.frames[to_index];
  gap.gap_frames = to_frame >= from_frame ? to_frame - from_frame : from_frame - to_frame;
  return gap;
}

WindowLinker::WindowLinker(LinkerOptions options) : options_(options) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
}

TrackState WindowLinker::StateOf(const LinkedTrack& track) const {
  if (track.missed_windows > 0) return TrackState::kLost;
  return track.hits >= options_.min_hits ? TrackState::kConfirmed : TrackState::kTentative;
}

LinkResult WindowLinker::Link(std::int64_t window_id,
                              const std::vector<core::Tracklet3D>& tracklets) {
  MVTRACK_CHECK_MSG(!last_window_.has_value() || window_id > *last_window_,
                    "WindowLinker::Link: window ids must be strictly increasing");
  for (const core::Tracklet3D& tracklet : tracklets) CheckWellFormed(tracklet);

  LinkResult result;
  result.window_id = window_id;
  const std::size_t num_tracklets = tracklets.size();
  result.track_of_tracklet.assign(num_tracklets, 0);
  result.link_distance_m.assign(num_tracklets, std::numeric_limits<double>::quiet_NaN());
  result.link_kind.assign(num_tracklets, LinkKind::kBirth);

  // Skipped window ids are windows without tracklets: every track misses them.
  const auto remove_dead = [this, &result]() {
    const auto dead = [this](const LinkedTrack& t) {
      return t.missed_windows > options_.max_missed_windows;
    };
    for (const LinkedTrack& t : tracks_) {
      if (dead(t)) result.died.push_back(t.id);
    }
    tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(), dead), tracks_.end());
  };
  if (last_window_.has_value()) {
    // Unsigned arithmetic: the difference of two int64 values always fits in a uint64.
    const std::uint64_t skipped = static_cast<std::uint64_t>(window_id) -
                                  static_cast<std::uint64_t>(*last_window_) - 1U;
    if (skipped > 0) {
      for (LinkedTrack& t : tracks_) AddMisses(&t, skipped, options_.max_missed_windows);
      remove_dead();
    }
  }
  last_window_ = window_id;

  const auto num_tracks = static_cast<Eigen::Index>(tracks_.size());
  const auto num_cols = static_cast<Eigen::Index>(num_tracklets);
  std::vector<int> tracklet_of_track(tracks_.size(), -1);

  // Stage 1 (Eq. 8 + Eq. 9): overlapping pairs, gated by max_link_distance_m.
  Eigen::MatrixXd overlap_cost = Eigen::MatrixXd::Constant(num_tracks, num_cols, kForbidden);
  std::vector<char> has_overlap(tracks_.size() * num_tracklets, 0);
  for (Eigen::Index r = 0; r < num_tracks; ++r) {
    const auto sr = static_cast<std::size_t>(r);
    for (Eigen::Index c = 0; c < num_cols; ++c) {
      const auto sc = static_cast<std::size_t>(c);
      const auto d = MeanOverlapDistanceOfChecked(tracks_[sr].last_tracklet, tracklets[sc]);
      if (!d.has_value()) continue;
      has_overlap[sr * num_tracklets + sc] = 1;
      if (*d <= options_.max_link_distance_m) overlap_cost(r, c) = *d;
    }
  }
  const core::Assignment overlap = core::SolveAssignment(overlap_cost, kAnyFiniteCost);
  for (const auto& [r, c] : overlap.matches) {
    tracklet_of_track[static_cast<std::size_t>(r)] = c;
    result.link_distance_m[static_cast<std::size_t>(c)] = overlap_cost(r, c);
    result.link_kind[static_cast<std::size_t>(c)] = LinkKind::kOverlap;
  }

  // Stage 2 (gap rule): leftover pairs that share no measurable frame.
  const std::vector<int>& rows = overlap.unmatched_rows;
  const std::vector<int>& cols = overlap.unmatched_cols;
  Eigen::MatrixXd gap_cost = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(rows.size()),
                                                       static_cast<Eigen::Index>(cols.size()),
                                                       kForbidden);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto sr = static_cast<std::size_t>(rows[i]);
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const auto sc = static_cast<std::size_t>(cols[j]);
      if (has_overlap[sr * num_tracklets + sc] != 0) continue;
      const auto gap = MeasureGap(tracks_[sr].last_tracklet, tracklets[sc]);
      if (!gap.has_value()) continue;
      const double gate = options_.max_link_distance_m +
                          options_.max_speed_m_per_frame * static_cast<double>(gap->gap_frames);
      if (gap->distance_m <= gate) {
        gap_cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = gap->distance_m;
      }
    }
  }
  const core::Assignment gap = core::SolveAssignment(gap_cost, kAnyFiniteCost);
  for (const auto& [i, j] : gap.matches) {
    const int r = rows[static_cast<std::size_t>(i)];
    const int c = cols[static_cast<std::size_t>(j)];
    tracklet_of_track[static_cast<std::size_t>(r)] = c;
    result.link_distance_m[static_cast<std::size_t>(c)] = gap_cost(i, j);
    result.link_kind[static_cast<std::size_t>(c)] = LinkKind::kGap;
  }

  // Track management: update the matched, age the unmatched, then bury and give birth.
  std::vector<char> tracklet_linked(num_tracklets, 0);
  for (std::size_t r = 0; r < tracks_.size(); ++r) {
    LinkedTrack& track = tracks_[r];
    const int c = tracklet_of_track[r];
    if (c < 0) {
      AddMisses(&track, 1U, options_.max_missed_windows);
      continue;
    }
    const auto sc = static_cast<std::size_t>(c);
    tracklet_linked[sc] = 1;
    result.track_of_tracklet[sc] = track.id;
    ++track.hits;
    track.missed_windows = 0;
    track.last_window = window_id;
    track.last_tracklet = tracklets[sc];
  }
  remove_dead();
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    if (tracklet_linked[c] != 0) continue;
    LinkedTrack track;
    track.id = next_id_++;
    track.hits = 1;
    track.missed_windows = 0;
    track.first_window = window_id;
    track.last_window = window_id;
    track.last_tracklet = tracklets[c];
    result.track_of_tracklet[c] = track.id;
    result.born.push_back(track.id);
    tracks_.push_back(std::move(track));  // fresh ids are the largest: tracks_ stays sorted
  }
  for (LinkedTrack& track : tracks_) track.state = StateOf(track);
  std::sort(result.died.begin(), result.died.end());
  return result;
}

}  // namespace mvtrack::linking
