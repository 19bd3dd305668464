#include "linking/window_linker.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <numeric>
#include <utility>

#include "core/check.h"
#include "core/linear_assignment.h"
#include "core/median.h"

namespace mvtrack::linking {
namespace {

using PointsAtFrame = std::vector<std::optional<Vec3>>;

constexpr double kForbidden = std::numeric_limits<double>::infinity();
// Every finite cost is feasible; the gates are applied per pair by writing kForbidden.
constexpr double kAnyFiniteCost = std::numeric_limits<double>::max();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// last_seen_frame of a track that has no footprint yet.
constexpr FrameIndex kNoFrame = std::numeric_limits<FrameIndex>::min();

bool IsValidPoint(const std::optional<Vec3>& point) {
  return point.has_value() && point->allFinite();
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

// Calls f(d) with FrameDistance d of every common frame of `a` and `b` where it is defined
// (tracklets checked by CheckWellFormed); frames are sorted, so a merge walk finds the common
// ones. Returns false when the frame ranges are disjoint (no call).
template <typename F>
bool ForEachCommonFrameDistance(const core::Tracklet3D& a, const core::Tracklet3D& b, F&& f) {
  // Disjoint frame ranges have no overlap at all (the common case for lost tracks).
  if (a.frames.empty() || b.frames.empty() || a.frames.back() < b.frames.front() ||
      b.frames.back() < a.frames.front()) {
    return false;
  }
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.frames.size() && j < b.frames.size()) {
    if (a.frames[i] < b.frames[j]) {
      ++i;
    } else if (b.frames[j] < a.frames[i]) {
      ++j;
    } else {
      if (const auto d = FrameDistance(a.points[i], b.points[j])) f(*d);
      ++i;
      ++j;
    }
  }
  return true;
}

// MeanOverlapDistance of two tracklets already checked by CheckWellFormed (Link checks every
// tracklet once when it arrives, so its pairwise loop skips the re-checks).
std::optional<double> MeanOverlapDistanceOfChecked(const core::Tracklet3D& a,
                                                   const core::Tracklet3D& b) {
  // Eq. 8: D_ij = 1/|Psi_i ∩ Psi_j| * sum over the common frames. Frames without a common
  // valid point carry no measurement and are left out of both the sum and the count.
  double sum = 0.0;
  int frames = 0;
  ForEachCommonFrameDistance(a, b, [&](double d) {
    sum += d;
    ++frames;
  });
  if (frames == 0) return std::nullopt;
  return sum / static_cast<double>(frames);
}

// The median over the common frames of FrameDistance (of an even count: the mean of the two
// middle values), for checked tracklets: like Eq. 8's mean, but a few frames where one of two
// coinciding tracklets is triangulated far off (a wrong view in its cluster) do not move it.
// nullopt without a common frame.
std::optional<double> MedianOverlapDistanceOfChecked(const core::Tracklet3D& a,
                                                     const core::Tracklet3D& b) {
  std::vector<double> d;
  ForEachCommonFrameDistance(a, b, [&](double x) { d.push_back(x); });
  if (d.empty()) return std::nullopt;
  return core::MedianInPlace(&d);
}

// Adds `windows` missed windows to `track`, saturating at INT_MAX.
void AddMisses(LinkedTrack* track, std::uint64_t windows) {
  const auto room =
      static_cast<std::uint64_t>(std::numeric_limits<int>::max() - track->missed_windows);
  track->missed_windows += static_cast<int>(std::min(windows, room));
}

// Seconds from frame `from` to frame `to` (negative backwards). In double: the difference of
// two arbitrary int64 frame indices may not fit in an int64.
double FrameSeconds(FrameIndex from, FrameIndex to, double seconds_per_frame) {
  return (static_cast<double>(to) - static_cast<double>(from)) * seconds_per_frame;
}

bool MemberLess(CameraId ca, TrackId2D ta, CameraId cb, TrackId2D tb) {
  return ca != cb ? ca < cb : ta < tb;
}

// First and last frame of `tracklet` with a footprint, or nullopt.
struct FootprintSpan {
  FrameIndex first = 0;
  FrameIndex last = 0;
};

// Every frame of `tracklet` that has a footprint, with it, in frame order.
std::vector<std::pair<FrameIndex, Vec2>> Footprints(const core::Tracklet3D& tracklet,
                                                    const std::vector<int>& footprint_points) {
  std::vector<std::pair<FrameIndex, Vec2>> out;
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    if (const std::optional<Vec2> xy = FrameFootprint(tracklet.points[f], footprint_points)) {
      out.emplace_back(tracklet.frames[f], *xy);
    }
  }
  return out;
}

std::optional<FootprintSpan> SpanOf(const core::Tracklet3D& tracklet,
                                    const std::vector<int>& footprint_points) {
  std::optional<FootprintSpan> span;
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    if (!FrameFootprint(tracklet.points[f], footprint_points)) continue;
    if (!span) span = FootprintSpan{tracklet.frames[f], tracklet.frames[f]};
    span->last = tracklet.frames[f];
  }
  return span;
}

// Calls f(d) with the footprint distance d of every common frame of `a` and `b` that has
// footprints on both sides.
template <typename F>
void ForEachCommonFootprintDistance(const core::Tracklet3D& a,
                                    const core::Tracklet3D& b,
                                    const std::vector<int>& footprint_points,
                                    F&& f) {
  std::size_t j = 0;
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    while (j < b.frames.size() && b.frames[j] < a.frames[i]) ++j;
    if (j == b.frames.size()) break;
    if (b.frames[j] != a.frames[i]) continue;
    const std::optional<Vec2> pa = FrameFootprint(a.points[i], footprint_points);
    const std::optional<Vec2> pb = FrameFootprint(b.points[j], footprint_points);
    if (pa && pb) f((*pa - *pb).norm());
  }
}

// The smallest footprint distance between `a` and `b` over their common frames, nullopt
// without a common frame with footprints on both sides.
std::optional<double> ClosestApproach(const core::Tracklet3D& a,
                                      const core::Tracklet3D& b,
                                      const std::vector<int>& footprint_points) {
  std::optional<double> closest;
  ForEachCommonFootprintDistance(a, b, footprint_points, [&](double d) {
    if (!closest || d < *closest) closest = d;
  });
  return closest;
}

// The median footprint distance between `a` and `b` over their common frames, nullopt
// without a common frame with footprints on both sides.
std::optional<double> MedianFootprintDistance(const core::Tracklet3D& a,
                                              const core::Tracklet3D& b,
                                              const std::vector<int>& footprint_points) {
  std::vector<double> d;
  ForEachCommonFootprintDistance(a, b, footprint_points, [&](double x) { d.push_back(x); });
  if (d.empty()) return std::nullopt;
  return core::MedianInPlace(&d);
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
  if (!std::isfinite(duplicate_distance_m) || duplicate_distance_m < 0.0 ||
      duplicate_distance_m > max_link_distance_m) {
    return fail("duplicate_distance_m must be finite and in [0, max_link_distance_m]");
  }
  if (!std::isfinite(duplicate_max_gap_s) || duplicate_max_gap_s < 0.0) {
    return fail("duplicate_max_gap_s must be finite and >= 0");
  }
  if (min_hits < 1) return fail("min_hits must be >= 1");
  if (fragment_min_hits < 1) return fail("fragment_min_hits must be >= 1");
  if (strong_birth_cameras < 2) return fail("strong_birth_cameras must be >= 2");
  if (!std::isfinite(isolated_birth_distance_m) || isolated_birth_distance_m < 0.0) {
    return fail("isolated_birth_distance_m must be finite and >= 0");
  }
  if (!std::isfinite(max_lost_s) || max_lost_s < 0.0) {
    return fail("max_lost_s must be finite and >= 0");
  }
  if (!std::isfinite(monocular_max_s) || monocular_max_s < 0.0) {
    return fail("monocular_max_s must be finite and >= 0");
  }
  if (!motion.Validate(why)) return false;
  if (!std::isfinite(gap_gate_chi2) || gap_gate_chi2 <= 0.0) {
    return fail("gap_gate_chi2 must be finite and > 0");
  }
  if (!std::isfinite(reid_gate_chi2) || reid_gate_chi2 < 0.0) {
    return fail("reid_gate_chi2 must be finite and >= 0");
  }
  if (!std::isfinite(reid_margin_chi2) || reid_margin_chi2 < 0.0) {
    return fail("reid_margin_chi2 must be finite and >= 0");
  }
  if (!std::isfinite(max_reid_gap_s) || max_reid_gap_s < 0.0) {
    return fail("max_reid_gap_s must be finite and >= 0");
  }
  return true;
}

bool LinkerContext::Validate(std::string* why) const {
  for (int k : footprint_points) {
    if (k < 0) {
      if (why != nullptr) *why = "footprint_points must be >= 0";
      return false;
    }
  }
  return true;
}

std::optional<double> MeanOverlapDistance(const core::Tracklet3D& a, const core::Tracklet3D& b) {
  CheckWellFormed(a);
  CheckWellFormed(b);
  return MeanOverlapDistanceOfChecked(a, b);
}

std::optional<Vec2> FrameFootprint(const std::vector<std::optional<Vec3>>& points,
                                   const std::vector<int>& footprint_points) {
  if (!footprint_points.empty()) {
    Vec2 sum = Vec2::Zero();
    bool all = true;
    for (int k : footprint_points) {
      const auto uk = static_cast<std::size_t>(k);
      if (uk >= points.size() || !IsValidPoint(points[uk])) {
        all = false;
        break;
      }
      sum += points[uk]->head<2>();
    }
    if (all) return Vec2(sum / static_cast<double>(footprint_points.size()));
  }
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (const std::optional<Vec3>& p : points) {
    if (!IsValidPoint(p)) continue;
    sum += p->head<2>();
    ++n;
  }
  if (n == 0) return std::nullopt;
  return Vec2(sum / static_cast<double>(n));
}

int SharedMembers(const std::vector<TrackMember>& members, const core::Tracklet3D& tracklet) {
  // Both sorted by (camera, track): a merge walk.
  int shared = 0;
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < members.size() && j < tracklet.members.size()) {
    const TrackMember& a = members[i];
    const core::TrackletMember& b = tracklet.members[j];
    if (MemberLess(a.camera_id, a.track_id, b.camera_id, b.track_id)) {
      ++i;
    } else if (MemberLess(b.camera_id, b.track_id, a.camera_id, a.track_id)) {
      ++j;
    } else {
      ++shared;
      ++i;
      ++j;
    }
  }
  return shared;
}

std::optional<FloorMotion> InitialMotion(const core::Tracklet3D& tracklet,
                                         const LinkerContext& context,
                                         const MotionOptions& options,
                                         double seconds_per_frame) {
  std::optional<FloorMotion> motion;
  FrameIndex at = 0;
  for (std::size_t f = tracklet.frames.size(); f-- > 0;) {
    const std::optional<Vec2> xy = FrameFootprint(tracklet.points[f], context.footprint_points);
    if (!xy) continue;
    const FrameIndex frame = tracklet.frames[f];
    if (!motion) {
      motion = FloorMotion::Start(*xy, options);
    } else {
      motion->Predict(FrameSeconds(at, frame, seconds_per_frame), options);
      motion->Update(*xy, options);
    }
    at = frame;
  }
  return motion;
}

bool UnambiguousMinimum(const Eigen::MatrixXd& cost,
                        Eigen::Index row,
                        Eigen::Index col,
                        double margin) {
  const double v = cost(row, col);
  for (Eigen::Index k = 0; k < cost.cols(); ++k) {
    if (k != col && cost(row, k) < v + margin) return false;
  }
  for (Eigen::Index k = 0; k < cost.rows(); ++k) {
    if (k != row && cost(k, col) < v + margin) return false;
  }
  return true;
}

WindowLinker::WindowLinker(LinkerOptions options,
                           LinkerContext context,
                           core::AppearanceOptions appearance)
    : options_(options), context_(std::move(context)), appearance_(appearance) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
  MVTRACK_CHECK_MSG(context_.Validate(&why), why.c_str());
  MVTRACK_CHECK_MSG(appearance_.Validate(&why), why.c_str());
}

namespace {

// The nearest pair of entries of two galleries (cosine distance; 2 when none is comparable).
double GalleriesDistance(const std::vector<std::vector<float>>& a,
                         const std::vector<std::vector<float>>& b) {
  double best = 2.0;
  for (const std::vector<float>& x : a) best = std::min(best, core::GalleryDistance(b, x));
  return best;
}

}  // namespace

void WindowLinker::RecordSamePerson(const std::vector<core::Tracklet3D>& tracklets,
                                    const LinkResult& result) {
  const auto add = [](std::vector<TrackId3D>* list, TrackId3D id) {
    const auto it = std::lower_bound(list->begin(), list->end(), id);
    if (it != list->end() && *it == id) return;
    list->insert(it, id);
    if (static_cast<int>(list->size()) > kMaxSamePerson) list->erase(list->begin());
  };
  const auto find = [&](TrackId3D id) -> LinkedTrack* {
    const auto it = std::lower_bound(
        tracks_.begin(), tracks_.end(), id, [](const LinkedTrack& t, TrackId3D wanted) {
          return t.id < wanted;
        });
    return it != tracks_.end() && it->id == id ? &*it : nullptr;
  };
  const auto looks_alike = [&](const core::Tracklet3D& t,
                               const std::vector<std::vector<float>>& gallery) {
    return !t.appearance.empty() &&
           core::GalleryDistance(gallery, t.appearance) <= appearance_.reid_max_distance;
  };
  // (a) Two tracks of this window, side by side and alike: the person tracked twice.
  for (std::size_t a = 0; a < tracklets.size(); ++a) {
    if (tracklets[a].appearance.empty() || result.link_kind[a] == LinkKind::kDuplicate) continue;
    for (std::size_t b = a + 1; b < tracklets.size(); ++b) {
      if (tracklets[b].appearance.size() != tracklets[a].appearance.size() ||
          result.link_kind[b] == LinkKind::kDuplicate ||
          result.track_of_tracklet[a] == result.track_of_tracklet[b]) {
        continue;
      }
      if (core::CosineDistance(tracklets[a].appearance, tracklets[b].appearance) >
          appearance_.reid_max_distance) {
        continue;
      }
      const std::optional<double> apart =
          ClosestApproach(tracklets[a], tracklets[b], context_.footprint_points);
      if (!apart || *apart > kSamePersonApartM) continue;
      LinkedTrack* ta = find(result.track_of_tracklet[a]);
      LinkedTrack* tb = find(result.track_of_tracklet[b]);
      if (ta == nullptr || tb == nullptr) continue;
      add(&ta->same_person, tb->id);
      add(&tb->same_person, ta->id);
    }
  }
  // (b) A track born where and when a lost or departed one that looks alike was last seen
  // (within max_lost_s, reachable on foot): the person's next fragment.
  for (std::size_t c = 0; c < tracklets.size(); ++c) {
    if (result.link_kind[c] != LinkKind::kBirth || tracklets[c].appearance.empty()) continue;
    LinkedTrack* born = find(result.track_of_tracklet[c]);
    if (born == nullptr) continue;
    const auto footprints = Footprints(tracklets[c], context_.footprint_points);
    if (footprints.empty()) continue;
    const auto& [first_frame, first] = footprints.front();
    const auto continues = [&](FrameIndex last_frame, const Vec2& last_position) {
      const double gap_s = Seconds(last_frame, first_frame);
      return gap_s >= 0.0 && gap_s <= options_.max_lost_s &&
             (first - last_position).norm() <= kMaxReidSpeedMps * gap_s + kSamePersonApartM;
    };
    for (LinkedTrack& t : tracks_) {
      if (t.id == born->id || t.missed_windows == 0 || t.last_seen_frame == kNoFrame) continue;
      if (continues(t.last_seen_frame, t.motion.position()) &&
          looks_alike(tracklets[c], t.gallery)) {
        add(&t.same_person, born->id);
        add(&born->same_person, t.id);
      }
    }
    for (DepartedTrack& d : departed_) {
      if (continues(d.last_seen_frame, d.last_position) && looks_alike(tracklets[c], d.gallery)) {
        add(&d.same_person, born->id);
        add(&born->same_person, d.id);
      }
    }
  }
}

std::size_t WindowLinker::gallery_bytes() const {
  std::size_t bytes = 0;
  const auto add = [&](const std::vector<std::vector<float>>& gallery) {
    for (const std::vector<float>& g : gallery) bytes += g.size() * sizeof(float);
  };
  for (const LinkedTrack& t : tracks_) add(t.gallery);
  for (const DepartedTrack& d : departed_) add(d.gallery);
  return bytes;
}

void WindowLinker::LinkByAppearance(const std::vector<core::Tracklet3D>& tracklets,
                                    const std::vector<bool>& column,
                                    std::vector<int>* tracklet_of_track,
                                    std::vector<int>* track_of_col,
                                    std::vector<int>* revive,
                                    std::vector<int>* same_as,
                                    std::vector<int>* forget,
                                    std::vector<int>* absorbed,
                                    LinkResult* result) const {
  // Candidates: lost tracks left unmatched (rows 0..), then departed tracks.
  struct Candidate {
    int track = -1;     // index into tracks_, or
    int departed = -1;  // index into departed_
    const std::vector<std::vector<float>>* gallery = nullptr;
    FrameIndex last_seen_frame = 0;
    FrameIndex first_seen_frame = 0;
    Vec2 last_position = Vec2::Zero();
    TrackId3D id = 0;
    const std::vector<TrackId3D>* same_person = nullptr;
  };
  std::vector<Candidate> candidates;
  for (std::size_t r = 0; r < tracks_.size(); ++r) {
    const LinkedTrack& t = tracks_[r];
    // Unmatched in this window (lost now or before), confirmed, with a gallery.
    if ((*tracklet_of_track)[r] >= 0 || !t.confirmed || t.gallery.empty() ||
        t.last_seen_frame == kNoFrame) {
      continue;
    }
    candidates.push_back({static_cast<int>(r),
                          -1,
                          &t.gallery,
                          t.last_seen_frame,
                          t.first_seen_frame,
                          t.motion.position(),
                          t.id,
                          &t.same_person});
  }
  for (std::size_t d = 0; d < departed_.size(); ++d) {
    const DepartedTrack& dt = departed_[d];
    candidates.push_back({-1,
                          static_cast<int>(d),
                          &dt.gallery,
                          dt.last_seen_frame,
                          dt.first_seen_frame,
                          dt.last_position,
                          dt.id,
                          &dt.same_person});
  }
  std::vector<int> cols;
  for (std::size_t c = 0; c < tracklets.size(); ++c) {
    if (column[c] && !tracklets[c].appearance.empty()) cols.push_back(static_cast<int>(c));
  }
  if (candidates.empty() || cols.empty()) return;
  const auto rows_n = static_cast<Eigen::Index>(candidates.size());
  const auto cols_n = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd dist = Eigen::MatrixXd::Constant(rows_n, cols_n, kInf);
  std::vector<std::vector<std::pair<FrameIndex, Vec2>>> footprints(cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j) {
    footprints[j] =
        Footprints(tracklets[static_cast<std::size_t>(cols[j])], context_.footprint_points);
  }
  for (Eigen::Index i = 0; i < rows_n; ++i) {
    const Candidate& cand = candidates[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < cols_n; ++j) {
      const core::Tracklet3D& t =
          tracklets[static_cast<std::size_t>(cols[static_cast<std::size_t>(j)])];
      // Physically possible: from the track's last footprint to the tracklet's footprint
      // nearest in time (after it, or overlapping it when the track broke in this window),
      // at most kMaxReidSpeedMps plus a body width.
      Vec2 nearest = Vec2::Zero();
      double dt_s = kInf;
      for (const auto& [frame, xy] : footprints[static_cast<std::size_t>(j)]) {
        const double dt = std::abs(Seconds(cand.last_seen_frame, frame));
        if (dt < dt_s) {
          nearest = xy;
          dt_s = dt;
        }
      }
      if (!(dt_s < kInf) || t.frames.back() <= cand.last_seen_frame) continue;
      if ((nearest - cand.last_position).norm() > kMaxReidSpeedMps * dt_s + kSamePersonApartM) {
        continue;
      }
      dist(i, j) = core::GalleryDistance(*cand.gallery, t.appearance);
    }
  }
  // Greedy by increasing distance (ties: lowest candidate, then lowest column), each match
  // unambiguous against every other entry of its row and column.
  struct Entry {
    double d;
    Eigen::Index i, j;
  };
  std::vector<Entry> entries;
  for (Eigen::Index i = 0; i < rows_n; ++i) {
    for (Eigen::Index j = 0; j < cols_n; ++j) {
      if (dist(i, j) <= appearance_.reid_max_distance) entries.push_back({dist(i, j), i, j});
    }
  }
  std::stable_sort(
      entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.d < b.d; });
  std::vector<bool> row_used(candidates.size(), false), col_used(cols.size(), false);
  for (const Entry& e : entries) {
    const auto ui = static_cast<std::size_t>(e.i);
    const auto uj = static_cast<std::size_t>(e.j);
    if (row_used[ui] || col_used[uj]) continue;
    // A close second on either side is ambiguous, unless it is the same person: another
    // tracklet of this window next to the chosen one (a camera had two 2D tracks on them), or
    // another remembered track that looks the same (the person's earlier fragment).
    bool unambiguous = true;
    std::vector<int> same_columns;
    for (Eigen::Index k = 0; k < cols_n && unambiguous; ++k) {
      if (k == e.j || !(dist(e.i, k) < e.d + appearance_.reid_margin)) continue;
      const std::optional<double> apart =
          ClosestApproach(tracklets[static_cast<std::size_t>(cols[uj])],
                          tracklets[static_cast<std::size_t>(cols[static_cast<std::size_t>(k)])],
                          context_.footprint_points);
      if (apart && *apart <= kSamePersonApartM) {
        same_columns.push_back(static_cast<int>(k));
      } else {
        unambiguous = false;
      }
    }
    std::vector<int> same_rows;
    for (Eigen::Index k = 0; k < rows_n && unambiguous; ++k) {
      if (k == e.i || !(dist(k, e.j) < e.d + appearance_.reid_margin)) continue;
      // The same person only on evidence (LinkedTrack::same_person: a duplicate track of the
      // person, or its next fragment): two look-alikes are two people.
      const Candidate& a = candidates[ui];
      const Candidate& b = candidates[static_cast<std::size_t>(k)];
      // Or two tracks never seen at the same time (one ended before the other began: the
      // person's earlier and later fragments) that look as alike as the margin asks a rival
      // to differ (reid_disjoint_same_person; measured on look-alike twins in
      // docs/DECISIONS.md "Appearance").
      const bool disjoint =
          appearance_.reid_disjoint_same_person &&
          (a.last_seen_frame < b.first_seen_frame || b.last_seen_frame < a.first_seen_frame);
      const bool evidence =
          std::binary_search(a.same_person->begin(), a.same_person->end(), b.id) ||
          std::binary_search(b.same_person->begin(), b.same_person->end(), a.id);
      const double apart = GalleriesDistance(*a.gallery, *b.gallery);
      if ((evidence && apart <= appearance_.reid_max_distance) ||
          (disjoint && apart <= appearance_.reid_margin)) {
        same_rows.push_back(static_cast<int>(k));
      } else {
        unambiguous = false;
      }
    }
    if (!unambiguous) continue;
    row_used[ui] = true;
    col_used[uj] = true;
    const int c = cols[uj];
    for (const int k : same_columns) {
      const auto ck = static_cast<std::size_t>(cols[static_cast<std::size_t>(k)]);
      // (A tentative track's continuation stays with it.)
      if (col_used[static_cast<std::size_t>(k)] || (*track_of_col)[ck] >= 0) continue;
      col_used[static_cast<std::size_t>(k)] = true;
      (*same_as)[ck] = c;
    }
    // Of one person's tracks, the one with the most matched windows takes the tracklet: its id
    // holds most of the person's history (ties: the nearest look); the others are forgotten.
    std::size_t winner = ui;
    const auto hits_of = [&](std::size_t k) {
      const Candidate& x = candidates[k];
      return x.track >= 0 ? tracks_[static_cast<std::size_t>(x.track)].hits
                          : departed_[static_cast<std::size_t>(x.departed)].hits;
    };
    for (const int k : same_rows) {
      if (!row_used[static_cast<std::size_t>(k)] &&
          hits_of(static_cast<std::size_t>(k)) > hits_of(winner)) {
        winner = static_cast<std::size_t>(k);
      }
    }
    if (winner != ui) same_rows.push_back(static_cast<int>(ui));
    for (const int k : same_rows) {
      if (static_cast<std::size_t>(k) == winner) continue;
      row_used[static_cast<std::size_t>(k)] = true;
      const Candidate& other = candidates[static_cast<std::size_t>(k)];
      if (other.departed >= 0) forget->push_back(other.departed);
    }
    row_used[winner] = true;
    const Candidate& cand = candidates[winner];
    if (const int tentative = (*track_of_col)[static_cast<std::size_t>(c)]; tentative >= 0) {
      // The continuation of a tentative track: the older track takes it, the tentative ends.
      (*tracklet_of_track)[static_cast<std::size_t>(tentative)] = -1;
      (*track_of_col)[static_cast<std::size_t>(c)] = -1;
      absorbed->push_back(tentative);
    }
    if (cand.track >= 0) {
      (*tracklet_of_track)[static_cast<std::size_t>(cand.track)] = c;
      (*track_of_col)[static_cast<std::size_t>(c)] = cand.track;
    } else {
      (*revive)[static_cast<std::size_t>(c)] = cand.departed;
    }
    result->link_kind[static_cast<std::size_t>(c)] = LinkKind::kAppearance;
    result->link_distance_m[static_cast<std::size_t>(c)] = e.d;
  }
}

TrackState WindowLinker::StateOf(const LinkedTrack& track) const {
  if (track.missed_windows > 0) return TrackState::kLost;
  return track.confirmed ? TrackState::kConfirmed : TrackState::kTentative;
}

double WindowLinker::Seconds(FrameIndex from, FrameIndex to) const {
  return FrameSeconds(from, to, seconds_per_frame_);
}

FloorMotion WindowLinker::PredictedMotion(const LinkedTrack& track, FrameIndex frame) const {
  FloorMotion m = track.motion;
  m.Predict(Seconds(track.last_seen_frame, frame), options_.motion);
  return m;
}

void WindowLinker::Absorb(LinkedTrack* track,
                          const core::Tracklet3D& tracklet,
                          std::int64_t window_id) {
  ++track->hits;
  const int needed = track->required_hits > 0 ? track->required_hits : options_.min_hits;
  if (track->hits >= needed) track->confirmed = true;
  track->missed_windows = 0;
  track->last_window = window_id;
  if (tracklet.cameras.size() >= 2 && !tracklet.frames.empty()) {
    track->last_multiview_frame = std::max(track->last_multiview_frame, tracklet.frames.back());
  }
  UpdateMotion(track, tracklet);
  MergeMembers(track, tracklet);
  track->last_tracklet = tracklet;
  if (!tracklet.appearance.empty()) {
    auto& gallery = track->gallery;
    if (static_cast<int>(gallery.size()) >= appearance_.gallery_size) {
      gallery.erase(gallery.begin(),
                    gallery.begin() + (static_cast<std::ptrdiff_t>(gallery.size()) -
                                       appearance_.gallery_size + 1));
    }
    gallery.push_back(tracklet.appearance);
  }
}

void WindowLinker::UpdateMotion(LinkedTrack* track, const core::Tracklet3D& tracklet) const {
  // Every footprint after the last one already used, in frame order.
  for (std::size_t f = 0; f < tracklet.frames.size(); ++f) {
    const FrameIndex frame = tracklet.frames[f];
    const bool started = track->last_seen_frame != kNoFrame;
    if (started && frame <= track->last_seen_frame) continue;
    const std::optional<Vec2> xy = FrameFootprint(tracklet.points[f], context_.footprint_points);
    if (!xy) continue;
    if (!started) {
      track->motion = FloorMotion::Start(*xy, options_.motion);
      if (track->first_seen_frame == kNoFrame) track->first_seen_frame = frame;
    } else {
      track->motion.Predict(Seconds(track->last_seen_frame, frame), options_.motion);
      track->motion.Update(*xy, options_.motion);
    }
    track->last_seen_frame = frame;
  }
}

void WindowLinker::LinkMonocular(std::int64_t window_id,
                                 const std::vector<core::Tracklet3D>& monocular,
                                 LinkResult* result) {
  result->track_of_monocular.assign(monocular.size(), 0);
  if (options_.monocular_max_s <= 0.0 || monocular.empty()) return;
  // Longer tracklets first (ties: input order): a lost track continues on its best view, and
  // its other single views of the window then only add frames.
  std::vector<std::size_t> order(monocular.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return monocular[a].frames.size() > monocular[b].frames.size();
  });
  for (const std::size_t m : order) {
    const core::Tracklet3D& tracklet = monocular[m];
    const std::optional<FootprintSpan> span = SpanOf(tracklet, context_.footprint_points);
    if (!span) continue;

    // The holder of its 2D track seen most recently (ties: the lowest id).
    LinkedTrack* holder = nullptr;
    FrameIndex held_until = kNoFrame;
    for (LinkedTrack& t : tracks_) {
      if (!t.confirmed) continue;
      for (const core::TrackletMember& want : tracklet.members) {
        const auto it = std::lower_bound(
            t.members.begin(), t.members.end(), want, [](const TrackMember& a, const auto& b) {
              return MemberLess(a.camera_id, a.track_id, b.camera_id, b.track_id);
            });
        if (it == t.members.end() || it->camera_id != want.camera_id ||
            it->track_id != want.track_id) {
          continue;
        }
        if (holder == nullptr || it->last_frame > held_until) {
          holder = &t;
          held_until = it->last_frame;
        }
      }
    }
    if (holder == nullptr) continue;
    LinkedTrack& track = *holder;
    if (Seconds(track.last_multiview_frame, span->first) > options_.monocular_max_s) continue;
    if (appearance_.enabled && !track.gallery.empty() && !tracklet.appearance.empty() &&
        core::GalleryDistance(track.gallery, tracklet.appearance) > appearance_.link_max_distance) {
      continue;
    }
    const bool matched = track.last_window == window_id;
    const core::Tracklet3D& latest = track.last_tracklet;
    bool pass = false;
    if (const std::optional<double> d =
            MedianFootprintDistance(latest, tracklet, context_.footprint_points)) {
      pass = *d <= options_.max_link_distance_m;
    } else if (span->first > track.last_seen_frame) {
      if (Seconds(track.last_seen_frame, span->first) <= options_.max_lost_s) {
        const std::optional<FloorMotion> initial =
            InitialMotion(tracklet, context_, options_.motion, seconds_per_frame_);
        pass = initial && StateDistanceSquared(PredictedMotion(track, span->first), *initial) <=
                              options_.gap_gate_chi2;
      }
    } else if (const std::optional<FootprintSpan> next = SpanOf(latest, context_.footprint_points);
               matched && next && span->last < next->first) {
      // The footprints at the two spans' facing ends (both exist: the spans are made of them).
      const std::optional<Vec2> a =
          FrameFootprint(tracklet.points[static_cast<std::size_t>(tracklet.IndexOf(span->last))],
                         context_.footprint_points);
      const std::optional<Vec2> b =
          FrameFootprint(latest.points[static_cast<std::size_t>(latest.IndexOf(next->first))],
                         context_.footprint_points);
      pass = (*a - *b).norm() <=
             kSamePersonApartM + kMaxReidSpeedMps * Seconds(span->last, next->first);
    }
    if (!pass) continue;
    result->track_of_monocular[m] = track.id;
    MergeMembers(&track, tracklet);
    if (matched) continue;
    // A lost track continues on the one camera that still sees the person, at the height its
    // points had (Eq. 8 with the next window's tracklet compares them). (Shifting the floor
    // points too, by the median offset from the latest tracklet over common frames, was
    // measured and not adopted: docs/DECISIONS.md "Monocular continuation".)
    track.missed_windows = 0;
    track.last_window = window_id;
    UpdateMotion(&track, tracklet);
    core::Tracklet3D continued = tracklet;
    std::vector<double> z;
    for (const auto& points : latest.points) {
      if (!points.empty() && points[0] && points[0]->allFinite()) z.push_back(points[0]->z());
    }
    if (!z.empty()) {
      const double height = core::MedianInPlace(&z);
      for (auto& points : continued.points) {
        if (!points.empty() && points[0]) points[0]->z() = height;
      }
    }
    track.last_tracklet = std::move(continued);
  }
}

void WindowLinker::MergeMembers(LinkedTrack* track, const core::Tracklet3D& tracklet) const {
  // Members: merge (both sorted), then forget those not seen for longer than a lost track lives.
  std::vector<TrackMember> merged;
  merged.reserve(track->members.size() + tracklet.members.size());
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < track->members.size() || j < tracklet.members.size()) {
    if (j == tracklet.members.size() ||
        (i < track->members.size() && MemberLess(track->members[i].camera_id,
                                                 track->members[i].track_id,
                                                 tracklet.members[j].camera_id,
                                                 tracklet.members[j].track_id))) {
      merged.push_back(track->members[i++]);
    } else if (i == track->members.size() || MemberLess(tracklet.members[j].camera_id,
                                                        tracklet.members[j].track_id,
                                                        track->members[i].camera_id,
                                                        track->members[i].track_id)) {
      const core::TrackletMember& m = tracklet.members[j++];
      merged.push_back({m.camera_id, m.track_id, m.last_frame});
    } else {
      TrackMember m = track->members[i++];
      m.last_frame = std::max(m.last_frame, tracklet.members[j++].last_frame);
      merged.push_back(m);
    }
  }
  const FrameIndex newest =
      tracklet.frames.empty() ? track->last_seen_frame : tracklet.frames.back();
  const double horizon_s = options_.max_lost_s + options_.max_reid_gap_s + 1.0;
  merged.erase(std::remove_if(
                   merged.begin(),
                   merged.end(),
                   [&](const TrackMember& m) { return Seconds(m.last_frame, newest) > horizon_s; }),
               merged.end());
  track->members = std::move(merged);
}

std::vector<EndedTrack> WindowLinker::EndStream() {
  std::vector<EndedTrack> ended;
  ended.reserve(tracks_.size());
  for (const LinkedTrack& t : tracks_) ended.push_back({t.id, EndReason::kStreamEnd});
  tracks_.clear();
  departed_.clear();
  return ended;
}

LinkResult WindowLinker::Link(std::int64_t window_id,
                              FrameIndex window_begin,
                              double seconds_per_frame,
                              const std::vector<core::Tracklet3D>& tracklets,
                              const std::vector<core::TrackletMember>& live_tracks,
                              const std::vector<core::Tracklet3D>& monocular) {
  MVTRACK_CHECK_MSG(!last_window_.has_value() || window_id > *last_window_,
                    "WindowLinker::Link: window ids must be strictly increasing");
  MVTRACK_CHECK_MSG(std::isfinite(seconds_per_frame) && seconds_per_frame > 0.0,
                    "WindowLinker::Link: seconds_per_frame must be finite and > 0");
  seconds_per_frame_ = seconds_per_frame;
  for (const core::Tracklet3D& tracklet : tracklets) CheckWellFormed(tracklet);
  for (const core::Tracklet3D& tracklet : monocular) CheckWellFormed(tracklet);

  LinkResult result;
  result.window_id = window_id;
  const std::size_t num_tracklets = tracklets.size();
  result.track_of_tracklet.assign(num_tracklets, 0);
  result.link_distance_m.assign(num_tracklets, kNaN);
  result.link_kind.assign(num_tracklets, LinkKind::kBirth);
  result.shared_members.assign(num_tracklets, 0);

  // Skipped window ids are windows without tracklets: every track misses them.
  if (last_window_.has_value()) {
    // Unsigned arithmetic: the difference of two int64 values always fits in a uint64.
    const std::uint64_t skipped =
        static_cast<std::uint64_t>(window_id) - static_cast<std::uint64_t>(*last_window_) - 1U;
    if (skipped > 0) {
      for (LinkedTrack& t : tracks_) AddMisses(&t, skipped);
    }
  }
  last_window_ = window_id;

  // Lost tracks end before linking when they waited too long or no camera tracks them any more.
  std::vector<EndedTrack> ended;
  const auto continues = [&](const LinkedTrack& t) {
    // Any member among the live 2D tracks (both sorted by camera, then track).
    std::size_t i = 0;
    std::size_t j = 0;
    while (i < t.members.size() && j < live_tracks.size()) {
      const TrackMember& a = t.members[i];
      const core::TrackletMember& b = live_tracks[j];
      if (MemberLess(a.camera_id, a.track_id, b.camera_id, b.track_id)) {
        ++i;
      } else if (MemberLess(b.camera_id, b.track_id, a.camera_id, a.track_id)) {
        ++j;
      } else {
        return true;
      }
    }
    return false;
  };
  const auto end_reason = [&](const LinkedTrack& t) -> std::optional<EndReason> {
    if (t.missed_windows == 0) return std::nullopt;
    const double lost_s = Seconds(t.last_seen_frame, window_begin);
    if (lost_s > options_.max_lost_s) return EndReason::kLostTooLong;
    const bool reid_possible = options_.reid_gate_chi2 > 0.0 && lost_s <= options_.max_reid_gap_s;
    if (!reid_possible && !continues(t)) return EndReason::kLeftView;
    return std::nullopt;
  };
  for (const LinkedTrack& t : tracks_) {
    if (const auto reason = end_reason(t)) ended.push_back({t.id, *reason});
  }
  if (appearance_.enabled) {
    // Departed tracks are remembered for max_reid_s.
    std::erase_if(departed_, [&](const DepartedTrack& d) {
      return Seconds(d.last_seen_frame, window_begin) > appearance_.max_reid_s;
    });
  }
  if (!ended.empty()) {
    std::size_t e = 0;
    tracks_.erase(
        std::remove_if(tracks_.begin(),
                       tracks_.end(),
                       [&](LinkedTrack& t) {
                         if (e < ended.size() && ended[e].id == t.id) {
                           ++e;
                           if (appearance_.enabled && appearance_.max_departed > 0 && t.confirmed &&
                               !t.gallery.empty() && t.last_seen_frame != kNoFrame) {
                             if (static_cast<int>(departed_.size()) >= appearance_.max_departed) {
                               departed_.erase(departed_.begin());
                             }
                             departed_.push_back({t.id,
                                                  t.hits,
                                                  t.first_window,
                                                  t.last_window,
                                                  t.last_seen_frame,
                                                  t.first_seen_frame,
                                                  t.motion.position(),
                                                  std::move(t.gallery),
                                                  std::move(t.same_person)});
                           }
                           return true;
                         }
                         return false;
                       }),
        tracks_.end());
  }

  const std::size_t num_tracks = tracks_.size();
  const auto rows_n = static_cast<Eigen::Index>(num_tracks);
  const auto cols_n = static_cast<Eigen::Index>(num_tracklets);
  std::vector<int> tracklet_of_track(num_tracks, -1);
  std::vector<int> track_of_col(num_tracklets, -1);

  // Evidence of every pair: Eq. 8 over the overlap (NaN without), shared 2D tracks.
  Eigen::MatrixXd overlap = Eigen::MatrixXd::Constant(rows_n, cols_n, kNaN);
  Eigen::MatrixXi shared = Eigen::MatrixXi::Zero(rows_n, cols_n);
  std::vector<char> col_shares(num_tracklets, 0);
  for (std::size_t r = 0; r < num_tracks; ++r) {
    for (std::size_t c = 0; c < num_tracklets; ++c) {
      const auto er = static_cast<Eigen::Index>(r);
      const auto ec = static_cast<Eigen::Index>(c);
      if (const auto d = MeanOverlapDistanceOfChecked(tracks_[r].last_tracklet, tracklets[c])) {
        overlap(er, ec) = *d;
      }
      shared(er, ec) = SharedMembers(tracks_[r].members, tracklets[c]);
      if (shared(er, ec) > 0) {
        col_shares[c] = 1;
      }
    }
  }

  // The still unmatched tracks (rows) and tracklets (columns), in index order.
  const auto unmatched = [&](std::vector<int>* rows, std::vector<int>* cols) {
    for (std::size_t r = 0; r < num_tracks; ++r) {
      if (tracklet_of_track[r] < 0) rows->push_back(static_cast<int>(r));
    }
    for (std::size_t c = 0; c < num_tracklets; ++c) {
      if (track_of_col[c] < 0) cols->push_back(static_cast<int>(c));
    }
  };

  // Solves one stage over the still unmatched rows and columns; `cost(r, c)` is the cost of a
  // pair or nullopt when the stage forbids it.
  const auto solve_stage = [&](LinkKind kind, const auto& cost) {
    std::vector<int> rows;
    std::vector<int> cols;
    unmatched(&rows, &cols);
    if (rows.empty() || cols.empty()) return;
    Eigen::MatrixXd m = Eigen::MatrixXd::Constant(
        static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()), kForbidden);
    bool any = false;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (const std::optional<double> v = cost(rows[i], cols[j])) {
          m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = *v;
          any = true;
        }
      }
    }
    if (!any) return;
    const core::Assignment a = core::SolveAssignment(m, kAnyFiniteCost);
    for (const auto& [i, j] : a.matches) {
      const int r = rows[static_cast<std::size_t>(i)];
      const int c = cols[static_cast<std::size_t>(j)];
      tracklet_of_track[static_cast<std::size_t>(r)] = c;
      track_of_col[static_cast<std::size_t>(c)] = r;
      result.link_kind[static_cast<std::size_t>(c)] = kind;
      result.link_distance_m[static_cast<std::size_t>(c)] = m(i, j);
      result.shared_members[static_cast<std::size_t>(c)] = shared(r, c);
    }
  };

  // Appearance on: a track never takes a tracklet that looks like somebody else (its gallery
  // farther than link_max_distance from the tracklet's descriptor), at any stage.
  const auto vetoed = [&](int r, int c) {
    if (!appearance_.enabled) return false;
    const auto& gallery = tracks_[static_cast<std::size_t>(r)].gallery;
    const auto& look = tracklets[static_cast<std::size_t>(c)].appearance;
    if (gallery.empty() || look.empty()) return false;
    return core::GalleryDistance(gallery, look) > appearance_.link_max_distance;
  };

  // Stage 1: overlap with a shared 2D track (Eq. 8 + Eq. 9). Each shared 2D track is worth
  // max_link_distance_m of Eq. 8, in the gate and in the cost: one shared 2D track may be a
  // camera's track that passed to a neighbour (a body width away), two or more that continue
  // together are the person, however far a view that joined or left one of the two clusters
  // moved its triangulation (docs/DECISIONS.md "Window linking"). When one person appears twice
  // in a window (split into two clusters), the track keeps the tracklet that continues more of
  // its 2D tracks.
  solve_stage(LinkKind::kOverlap, [&](int r, int c) -> std::optional<double> {
    const double d = overlap(r, c);
    const double per_shared = options_.max_link_distance_m * static_cast<double>(shared(r, c));
    if (std::isnan(d) || shared(r, c) == 0 || d > per_shared) return std::nullopt;
    if (vetoed(r, c)) return std::nullopt;
    return d - per_shared;
  });
  // Without a shared 2D track there is no overlap link: a tracklet whose cameras all changed
  // their 2D tracks is a new candidate (docs/DECISIONS.md "Window linking": the stage that
  // linked such tracklets within 0.25 m changed no output on any benchmark and was removed).

  // Overlap links report their Eq. 8 distance.
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    if (track_of_col[c] >= 0) {
      result.link_distance_m[c] = overlap(track_of_col[c], static_cast<Eigen::Index>(c));
    }
  }

  // The gap stages compare a track's prediction with a tracklet's initial state.
  std::vector<std::optional<FootprintSpan>> spans(num_tracklets);
  std::vector<std::optional<FloorMotion>> initial(num_tracklets);
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    spans[c] = SpanOf(tracklets[c], context_.footprint_points);
  }
  const auto motion_distance = [&](int r, int c, double max_gap_s) -> std::optional<double> {
    const auto uc = static_cast<std::size_t>(c);
    const LinkedTrack& t = tracks_[static_cast<std::size_t>(r)];
    if (!spans[uc] || !std::isnan(overlap(r, c)) || spans[uc]->first <= t.last_seen_frame) {
      return std::nullopt;
    }
    if (Seconds(t.last_seen_frame, spans[uc]->first) > max_gap_s) return std::nullopt;
    if (!initial[uc]) {
      initial[uc] = InitialMotion(tracklets[uc], context_, options_.motion, seconds_per_frame_);
    }
    const FloorMotion predicted = PredictedMotion(t, spans[uc]->first);
    return StateDistanceSquared(predicted, *initial[uc]);
  };

  // Stage 2: gap with a shared 2D track and the motion gate.
  solve_stage(LinkKind::kGap, [&](int r, int c) -> std::optional<double> {
    if (shared(r, c) == 0) return std::nullopt;
    const std::optional<double> d2 = motion_distance(r, c, options_.max_lost_s);
    if (!d2 || !(*d2 <= options_.gap_gate_chi2)) return std::nullopt;
    if (vetoed(r, c)) return std::nullopt;
    return d2;
  });

  // Stage 3: re-identification by motion alone, only when unambiguous on both sides.
  if (options_.reid_gate_chi2 > 0.0) {
    std::vector<int> rows;
    std::vector<int> cols;
    unmatched(&rows, &cols);
    Eigen::MatrixXd d2 = Eigen::MatrixXd::Constant(
        static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()), kForbidden);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (shared(rows[i], cols[j]) > 0 || vetoed(rows[i], cols[j])) continue;
        if (const auto v = motion_distance(rows[i], cols[j], options_.max_reid_gap_s)) {
          d2(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = *v;
        }
      }
    }
    for (Eigen::Index i = 0; i < d2.rows(); ++i) {
      for (Eigen::Index j = 0; j < d2.cols(); ++j) {
        const double v = d2(i, j);
        if (!(v <= options_.reid_gate_chi2)) continue;
        const int r = rows[static_cast<std::size_t>(i)];
        const int c = cols[static_cast<std::size_t>(j)];
        // (With a zero margin, equal candidates would both qualify: the first one wins.)
        if (tracklet_of_track[static_cast<std::size_t>(r)] >= 0 ||
            track_of_col[static_cast<std::size_t>(c)] >= 0) {
          continue;
        }
        if (!UnambiguousMinimum(d2, i, j, options_.reid_margin_chi2)) continue;
        tracklet_of_track[static_cast<std::size_t>(r)] = c;
        track_of_col[static_cast<std::size_t>(c)] = r;
        result.link_kind[static_cast<std::size_t>(c)] = LinkKind::kReidentified;
        result.link_distance_m[static_cast<std::size_t>(c)] = v;
      }
    }
  }

  // One person linked twice (merge_linked_duplicates): the younger track lets its tracklet
  // go to the duplicates below and ends. Nearest pairs first; a track gives up at most once.
  std::vector<int> merged_away;  // tracks (rows) that end as duplicates of an older track
  if (options_.merge_linked_duplicates && options_.duplicate_distance_m > 0.0) {
    struct Twin {
      double distance;
      std::size_t a;
      std::size_t b;
    };
    std::vector<Twin> twins;
    for (std::size_t a = 0; a < num_tracklets; ++a) {
      if (track_of_col[a] < 0) continue;
      for (std::size_t b = a + 1; b < num_tracklets; ++b) {
        if (track_of_col[b] < 0) continue;
        const std::optional<double> d = MedianOverlapDistanceOfChecked(tracklets[a], tracklets[b]);
        if (d && *d <= options_.duplicate_distance_m) twins.push_back({*d, a, b});
      }
    }
    std::stable_sort(twins.begin(), twins.end(), [](const Twin& x, const Twin& y) {
      return x.distance < y.distance;
    });
    for (const Twin& t : twins) {
      const int ra = track_of_col[t.a];
      const int rb = track_of_col[t.b];
      if (ra < 0 || rb < 0) continue;  // one of them already gave up its tracklet
      const LinkedTrack& ta = tracks_[static_cast<std::size_t>(ra)];
      const LinkedTrack& tb = tracks_[static_cast<std::size_t>(rb)];
      // The older track: born in an earlier window, or (same window) the smaller id.
      const bool a_older =
          ta.first_window != tb.first_window ? ta.first_window < tb.first_window : ta.id < tb.id;
      const int older = a_older ? ra : rb;
      const int younger = a_older ? rb : ra;
      const std::size_t younger_col = a_older ? t.b : t.a;
      if (vetoed(older, static_cast<int>(younger_col))) continue;
      tracklet_of_track[static_cast<std::size_t>(younger)] = -1;
      track_of_col[younger_col] = -1;
      result.link_kind[younger_col] = LinkKind::kBirth;
      result.link_distance_m[younger_col] = kNaN;
      result.shared_members[younger_col] = 0;
      merged_away.push_back(younger);
    }
  }

  // Duplicates: an unmatched tracklet of a matched track's person (before appearance, so a
  // person seen twice never revives an old id).
  std::vector<int> duplicate_of(num_tracklets, -1);
  std::vector<double> duplicate_distance(num_tracklets, kNaN);
  // The person of linked tracklet o goes on in tracklet c of the same window (or came from
  // it): c begins at most duplicate_max_gap_s after o ends, or ends that long before o
  // begins, within walking reach. The distance of the facing footprints, else nullopt.
  const auto continues_in_window = [&](std::size_t o, std::size_t c) -> std::optional<double> {
    if (!spans[o] || !spans[c]) return std::nullopt;
    const bool after = spans[c]->first > spans[o]->last;
    if (!after && !(spans[c]->last < spans[o]->first)) return std::nullopt;
    const FrameIndex from = after ? spans[o]->last : spans[c]->last;
    const FrameIndex to = after ? spans[c]->first : spans[o]->first;
    const double gap_s = Seconds(from, to);
    if (gap_s > options_.duplicate_max_gap_s) return std::nullopt;
    const core::Tracklet3D& early = after ? tracklets[o] : tracklets[c];
    const core::Tracklet3D& late = after ? tracklets[c] : tracklets[o];
    // Both exist: the spans are made of frames with a footprint.
    const std::optional<Vec2> a = FrameFootprint(
        early.points[static_cast<std::size_t>(early.IndexOf(from))], context_.footprint_points);
    const std::optional<Vec2> b = FrameFootprint(
        late.points[static_cast<std::size_t>(late.IndexOf(to))], context_.footprint_points);
    const double apart = (*a - *b).norm();
    if (apart > kSamePersonApartM + kMaxReidSpeedMps * gap_s) return std::nullopt;
    return apart;
  };
  // No 2D track ties such a piece to the track, and walking reach alone also joins a
  // newcomer to whoever just left by the same door: only the look of a re-identification
  // (reid_max_distance) vouches for it, so the rule needs appearance and both descriptors.
  const auto looks_alike = [&](int r, std::size_t c) {
    const auto& gallery = tracks_[static_cast<std::size_t>(r)].gallery;
    const auto& look = tracklets[c].appearance;
    return !gallery.empty() && !look.empty() &&
           core::GalleryDistance(gallery, look) <= appearance_.reid_max_distance;
  };
  // The duplicate of unmatched tracklet c among the linked tracklets o with use(o): the
  // nearest coincident one (duplicate_distance_m), else the nearest the person continues in.
  const auto find_duplicate = [&](std::size_t c, const auto& use) {
    double nearest = options_.duplicate_distance_m;
    if (options_.duplicate_distance_m > 0.0) {
      for (std::size_t o = 0; o < num_tracklets; ++o) {
        if (track_of_col[o] < 0 || !use(o)) continue;
        const std::optional<double> d = MedianOverlapDistanceOfChecked(tracklets[o], tracklets[c]);
        if (d && *d <= nearest) {
          nearest = *d;
          duplicate_of[c] = track_of_col[o];
        }
      }
    }
    if (duplicate_of[c] < 0 && appearance_.enabled && options_.duplicate_max_gap_s > 0.0) {
      double nearest_gap = std::numeric_limits<double>::infinity();
      for (std::size_t o = 0; o < num_tracklets; ++o) {
        if (track_of_col[o] < 0 || !use(o) || !looks_alike(track_of_col[o], c)) continue;
        const std::optional<double> d = continues_in_window(o, c);
        if (d && *d < nearest_gap) {
          nearest_gap = *d;
          duplicate_of[c] = track_of_col[o];
        }
      }
      if (duplicate_of[c] >= 0) nearest = nearest_gap;
    }
    duplicate_distance[c] = duplicate_of[c] >= 0 ? nearest : kNaN;
  };
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    if (track_of_col[c] < 0) find_duplicate(c, [](std::size_t) { return true; });
  }
  // Stage 4, appearance.
  std::vector<int> revive(num_tracklets, -1);
  std::vector<int> same_as(num_tracklets, -1);  // a second tracklet of a re-identified person
  std::vector<int> forget;                      // departed fragments of re-identified people
  // A birth confirmed at once: seen by strong_birth_cameras, or far from everybody else of the
  // window (not a split-off duplicate of a person). Asked by stage 4 and again at birth: the
  // answer depends on the window's tracklets only, so it is computed once per tracklet.
  std::vector<signed char> strong_cache(num_tracklets, -1);
  // A piece of a tracked person: it carries a 2D track an alive track holds
  // (fragment_births_wait). It is not strong on its cameras.
  const auto fragment = [&](std::size_t c) {
    return options_.fragment_births_wait && col_shares[c] != 0;
  };
  const auto strong_birth = [&](std::size_t c) {
    signed char& known = strong_cache[c];
    if (known < 0) {
      bool strong = !fragment(c) &&
                    static_cast<int>(tracklets[c].cameras.size()) >= options_.strong_birth_cameras;
      if (!strong && options_.isolated_birth_distance_m > 0.0) {
        strong = true;
        for (std::size_t o = 0; o < num_tracklets && strong; ++o) {
          if (o == c) continue;
          const std::optional<double> d =
              ClosestApproach(tracklets[c], tracklets[o], context_.footprint_points);
          if (d && *d <= options_.isolated_birth_distance_m) strong = false;
        }
      }
      known = strong ? 1 : 0;
    }
    return known == 1;
  };
  std::vector<int> absorbed;  // tentative tracks whose person was re-identified as an older one
  if (appearance_.enabled) {
    // Columns: the tracklets that would be born, and the continuations of tentative tracks
    // born in an earlier window. A birth that would be tentative waits (defer_weak_reid): it
    // is re-identified, if at all, when its track is linked again, on more evidence; until
    // then it is not output, so the wait costs no id.
    std::vector<bool> column(num_tracklets, false);
    for (std::size_t c = 0; c < num_tracklets; ++c) {
      const int r = track_of_col[c];
      if (r < 0) {
        column[c] = duplicate_of[c] < 0 && (!appearance_.defer_weak_reid || strong_birth(c));
      } else {
        const LinkedTrack& t = tracks_[static_cast<std::size_t>(r)];
        column[c] = appearance_.defer_weak_reid && !t.confirmed && t.first_window < window_id;
      }
    }
    LinkByAppearance(tracklets,
                     column,
                     &tracklet_of_track,
                     &track_of_col,
                     &revive,
                     &same_as,
                     &forget,
                     &absorbed,
                     &result);
    for (const int d : forget) departed_[static_cast<std::size_t>(d)].gallery.clear();
    // The same person seen twice beside a tracklet this stage gave an alive track.
    for (std::size_t c = 0; c < num_tracklets; ++c) {
      if (track_of_col[c] >= 0 || same_as[c] >= 0 || revive[c] >= 0 || duplicate_of[c] >= 0) {
        continue;
      }
      find_duplicate(c,
                     [&](std::size_t o) { return result.link_kind[o] == LinkKind::kAppearance; });
    }
  }

  // Track management: update the matched, age the unmatched, then give birth.
  for (std::size_t r = 0; r < num_tracks; ++r) {
    LinkedTrack& track = tracks_[r];
    const int c = tracklet_of_track[r];
    if (c < 0) {
      AddMisses(&track, 1U);
      continue;
    }
    const auto sc = static_cast<std::size_t>(c);
    result.track_of_tracklet[sc] = track.id;
    Absorb(&track, tracklets[sc], window_id);
  }
  std::vector<LinkedTrack> revived;
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    if (track_of_col[c] >= 0 || same_as[c] >= 0) continue;
    if (duplicate_of[c] >= 0) {
      LinkedTrack& person = tracks_[static_cast<std::size_t>(duplicate_of[c])];
      MergeMembers(&person, tracklets[c]);
      result.track_of_tracklet[c] = person.id;
      result.link_kind[c] = LinkKind::kDuplicate;
      result.link_distance_m[c] = duplicate_distance[c];
      continue;
    }
    if (revive[c] >= 0) {
      // A departed track comes back: its id, hits and gallery; motion and members restart.
      DepartedTrack& d = departed_[static_cast<std::size_t>(revive[c])];
      LinkedTrack track;
      track.id = d.id;
      track.hits = d.hits;
      track.confirmed = true;
      track.first_window = d.first_window;
      track.last_seen_frame = kNoFrame;
      track.first_seen_frame = d.first_seen_frame;
      track.gallery = std::move(d.gallery);
      track.same_person = std::move(d.same_person);
      Absorb(&track, tracklets[c], window_id);
      result.track_of_tracklet[c] = track.id;
      result.revived.push_back(track.id);
      revived.push_back(std::move(track));
      continue;
    }
    LinkedTrack track;
    track.id = next_id_++;
    track.first_window = window_id;
    track.last_seen_frame = kNoFrame;
    track.first_seen_frame = kNoFrame;
    // With appearance on and a descriptor, a tentative piece can still be re-identified as
    // its person's own track (defer_weak_reid): it waits fragment_min_hits windows for that.
    if (fragment(c) && appearance_.enabled && !tracklets[c].appearance.empty()) {
      track.required_hits = options_.fragment_min_hits;
    }
    Absorb(&track, tracklets[c], window_id);
    track.confirmed = track.confirmed || strong_birth(c);
    result.track_of_tracklet[c] = track.id;
    result.born.push_back(track.id);
    tracks_.push_back(std::move(track));  // fresh ids are the largest: tracks_ stays sorted
  }
  // Tracks that end in this window, their tracklet taken by an older track of their person:
  // tentative ones re-identified by appearance (never output), and those that gave their
  // tracklet up as one person linked twice, unless the appearance stage linked them again.
  std::vector<TrackId3D> reidentified;
  std::vector<TrackId3D> duplicates;
  for (const int r : absorbed) reidentified.push_back(tracks_[static_cast<std::size_t>(r)].id);
  for (const int r : merged_away) {
    if (tracklet_of_track[static_cast<std::size_t>(r)] < 0) {
      duplicates.push_back(tracks_[static_cast<std::size_t>(r)].id);
    }
  }
  std::sort(reidentified.begin(), reidentified.end());
  std::sort(duplicates.begin(), duplicates.end());
  for (const TrackId3D id : reidentified) ended.push_back({id, EndReason::kReidentified});
  for (const TrackId3D id : duplicates) ended.push_back({id, EndReason::kDuplicate});
  if (!reidentified.empty() || !duplicates.empty()) {
    std::vector<TrackId3D> gone;
    std::merge(reidentified.begin(),
               reidentified.end(),
               duplicates.begin(),
               duplicates.end(),
               std::back_inserter(gone));
    std::erase_if(tracks_, [&](const LinkedTrack& t) {
      return std::binary_search(gone.begin(), gone.end(), t.id);
    });
  }
  if (!revived.empty() || !forget.empty()) {
    std::erase_if(departed_, [](const DepartedTrack& d) { return d.gallery.empty(); });
    for (LinkedTrack& t : revived) tracks_.push_back(std::move(t));
    std::sort(tracks_.begin(), tracks_.end(), [](const LinkedTrack& a, const LinkedTrack& b) {
      return a.id < b.id;
    });
    std::sort(result.revived.begin(), result.revived.end());
  }
  // Second tracklets of people re-identified in this window: duplicates of them.
  for (std::size_t c = 0; c < num_tracklets; ++c) {
    if (same_as[c] < 0) continue;
    const TrackId3D id = result.track_of_tracklet[static_cast<std::size_t>(same_as[c])];
    const auto it = std::lower_bound(
        tracks_.begin(), tracks_.end(), id, [](const LinkedTrack& t, TrackId3D wanted) {
          return t.id < wanted;
        });
    MVTRACK_CHECK(it != tracks_.end() && it->id == id);
    MergeMembers(&*it, tracklets[c]);
    result.track_of_tracklet[c] = id;
    result.link_kind[c] = LinkKind::kDuplicate;
    result.link_distance_m[c] = result.link_distance_m[static_cast<std::size_t>(same_as[c])];
  }
  if (appearance_.enabled) RecordSamePerson(tracklets, result);
  LinkMonocular(window_id, monocular, &result);
  for (LinkedTrack& track : tracks_) track.state = StateOf(track);
  for (const EndedTrack& e : ended) {
    result.died.push_back(e.id);
    result.died_reason.push_back(e.reason);
  }
  return result;
}

}  // namespace mvtrack::linking
