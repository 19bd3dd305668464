#pragma once
/// @file
/// Link Sliding Windows (paper Sec. "Link Sliding Windows", Eq. 8-9): the short-term 3D
/// tracklets U_{k,p} that each sliding window produces are linked into long-term 3D tracks by
/// an online track-to-track data association with explicit track management. Beyond the
/// paper's Eq. 8 distance over the windows' overlap it uses the evidence the earlier stages
/// already have: the (camera, 2D track) members a tracklet was built from, which continue
/// from window to window while a camera keeps seeing the person, and a constant-velocity
/// motion model whose uncertainty grows with the length of a gap (floor_motion.h). Pure: no
/// threads, no I/O, no clock. docs/DECISIONS.md "Window linking" has the measurements.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/appearance.h"
#include "core/observation.h"
#include "core/types.h"
#include "linking/floor_motion.h"

namespace mvtrack::linking {

/// WindowLinker settings (tunable; the stream's facts are in LinkerContext).
struct LinkerOptions {
  /// Gate on the Eq. 8 distance, metres, per shared 2D track: a tracklet and a track that share
  /// k 2D tracks and whose overlapping parts are farther apart than k times this are never
  /// linked on the overlap. In the overlap both tracklets are triangulated from (largely) the
  /// same 2D observations, so for the same person Eq. 8 only measures the disagreement of two
  /// triangulations (centimetres), whereas two people are at least a body width apart: one
  /// shared 2D track may be a camera's track that passed to a neighbour. Two or more that
  /// continue together are the person even when a view that joined or left one of the two
  /// clusters moved its triangulation further (docs/DECISIONS.md "Window linking"). Finite,
  /// > 0.
  double max_link_distance_m = 0.5;
  /// A tracklet left unmatched whose distance to a tracklet of the same window linked to an
  /// existing track is at most this (metres: the median over the frames both have of Eq. 8's
  /// per-frame distance, so that the few frames where one of them is triangulated from a
  /// wrong view do not hide the coincidence) is that
  /// person seen twice (a camera had two 2D tracks on them at once, so association had to put
  /// them in two clusters): no id is born, its 2D tracks join that track's members, so the
  /// window that continues them links to the person's id. 0 disables. Finite, in
  /// [0, max_link_distance_m].
  double duplicate_distance_m = 0.4;
  /// A tracklet left unmatched that begins at most this long (seconds) after a tracklet of
  /// the same window linked to an existing track ends, or ends at most this long before it
  /// begins, with the facing footprints within walking reach (kSamePersonApartM +
  /// kMaxReidSpeedMps x the gap), is that person too, the window's cluster of them split in
  /// time (the cameras that saw them changed within the window): a duplicate as above, taken
  /// only where no tracklet qualifies by duplicate_distance_m, and only with appearance on
  /// and the track's gallery within core::AppearanceOptions::reid_max_distance of the
  /// tracklet's descriptor (no 2D track ties the piece to the track, and walking reach alone
  /// also joins a newcomer to whoever just left by the same door). It also applies to the
  /// tracklets the appearance stage linked to alive tracks. 0 disables.
  /// Finite, >= 0. docs/DECISIONS.md "Window linking".
  double duplicate_max_gap_s = 0.5;
  /// One person linked twice: two tracklets of a window, each linked to its own track, within
  /// duplicate_distance_m of each other (the same median) are that person seen twice, and the
  /// two tracks one person's: the younger track (born later) gives its tracklet up, which then
  /// becomes a duplicate of the older track's person, and it ends (EndReason::kDuplicate).
  /// Appearance on: not when the older track's gallery vetoes the tracklet
  /// (core::AppearanceOptions::link_max_distance). Needs duplicate_distance_m > 0. The tracker
  /// applies it in box mode only (tracker::WindowFinalizer).
  bool merge_linked_duplicates = true;
  /// Matched windows (the birth window counts as the first) before a track is confirmed (and
  /// output); once confirmed it stays confirmed. A birth from strong evidence (see
  /// strong_birth_cameras) is confirmed at once. Must be >= 1.
  int min_hits = 2;
  /// A birth whose tracklet is supported by at least this many cameras is confirmed at birth.
  /// Two-camera births wait for a second window: they are mostly a person split off its own
  /// cluster or the crossing rays of two people (docs/DECISIONS.md "Window linking"). Must
  /// be >= 2.
  int strong_birth_cameras = 3;
  /// A birth whose tracklet carries a 2D track that an alive track (matched or lost) holds (a
  /// camera tracks the person under that track: the tracklet is a piece of a tracked person
  /// that association split off, or the person seen twice) is not confirmed on its
  /// cameras (strong_birth_cameras): it waits min_hits windows (fragment_min_hits with
  /// appearance), unless it is isolated (isolated_birth_distance_m). Of the short-lived births on a
  /// 32 x 100 store, most were such pieces (docs/DECISIONS.md "Window linking"). false: the camera
  /// rule alone. The tracker applies it in box mode only (tracker::WindowFinalizer).
  bool fragment_births_wait = true;
  /// Appearance on (core::AppearanceOptions::enabled) and the birth's tracklet has a
  /// descriptor (Tracklet3D::appearance): matched windows (the birth window counts as the
  /// first) before such a birth is confirmed; in them it can still be re-identified as its
  /// person's own track (defer_weak_reid). Otherwise min_hits (waiting longer only delays the
  /// person). Must be >= 1.
  int fragment_min_hits = 3;
  /// A birth whose footprint stays farther than this (metres) from every other tracklet of the
  /// window is confirmed at birth too: a duplicate split off a person lies next to that person
  /// (of the ghost births on a simulated 6 x 16 enter/leave floor, 56 of 62 were within 2 m
  /// of a real person). 0 disables. Finite, >= 0.
  double isolated_birth_distance_m = 2.0;
  /// A lost track (no tracklet linked in the latest window) waits this long, in seconds of
  /// stream time since its last triangulated frame, for a continuation; then it is removed and
  /// its id is never given out again. Finite, >= 0.
  double max_lost_s = 3.0;
  /// Box mode, monocular continuation: a confirmed track that holds the 2D track of a tracklet
  /// no camera pair placed (Link's `monocular` tracklets: one camera's floor positions) takes
  /// that tracklet's frames, for at most this long (seconds of stream time) after its last
  /// frame placed by two or more cameras: while only one camera sees the person the track
  /// goes on instead of being lost. Only continuations of a 2D track the track already holds,
  /// within the overlap or motion gates; never a birth. 0 disables. Finite, >= 0.
  double monocular_max_s = 5.0;
  /// The motion model's noise (the gates below are chi-square values of its 4-D state test).
  MotionOptions motion;
  /// Gap links supported by a shared 2D track (one camera kept tracking the person while the
  /// 3D track was lost): the tracklet's initial state (position, velocity) must lie within
  /// this squared Mahalanobis distance of the track's prediction. 18.47 = chi-square, 4 degrees
  /// of freedom, 99.9 %. Finite, > 0.
  double gap_gate_chi2 = 18.47;
  /// Re-identification of a lost track by motion alone (no shared 2D track): the squared
  /// Mahalanobis distance of the state test must be <= this (9.49 = chi-square, 4 degrees of
  /// freedom, 95 %). 0 disables re-identification by motion. Finite, >= 0.
  double reid_gate_chi2 = 0.0;
  /// Re-identification by motion alone also needs the match to be at least this much smaller
  /// (squared Mahalanobis distance) than the second-best candidate on both sides: the track's
  /// other tracklets and the tracklet's other lost tracks. An ambiguous match starts a new id.
  /// Finite, >= 0.
  double reid_margin_chi2 = 6.0;
  /// Re-identification by motion alone only across gaps up to this long, seconds. Finite, >= 0.
  double max_reid_gap_s = 1.5;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Facts of the scene the linker needs beyond its options.
struct LinkerContext {
  /// Point indices whose mean is the footprint of a frame when all are valid (pose mode: the
  /// hips); otherwise, or when empty, the mean of the frame's valid points. Only x and y count.
  std::vector<int> footprint_points;

  /// Checks that footprint_points are >= 0; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Life-cycle state of a long-term track.
enum class TrackState {
  kTentative,  ///< matched in its latest window, fewer than min_hits matched windows so far
  kConfirmed,  ///< matched in its latest window, at least min_hits matched windows
  kLost,       ///< missed >= 1 window, still waiting (confirmed or not: compare hits to min_hits)
};

/// Why a track ended.
enum class EndReason {
  kLostTooLong,   ///< no continuation within max_lost_s
  kLeftView,      ///< none of its 2D tracks continues (every camera lost the person) and
                  ///< re-identification cannot take it any more
  kStreamEnd,     ///< WindowLinker::EndStream
  kReidentified,  ///< tentative, its person re-identified by appearance as an older track,
                  ///< which took its tracklet (core::AppearanceOptions::defer_weak_reid)
  kDuplicate,     ///< the same person as an older track, both linked in one window
                  ///< (LinkerOptions::merge_linked_duplicates)
};

/// A (camera, 2D track) a long-term track was built from, and the last frame it was seen in.
struct TrackMember {
  CameraId camera_id = 0;
  TrackId2D track_id = 0;
  FrameIndex last_frame = 0;
};

/// One alive long-term 3D track.
struct LinkedTrack {
  /// Unique per WindowLinker, starts at 1, never reused.
  TrackId3D id = 0;
  /// Derived after every Link: kLost when missed_windows > 0, else kConfirmed when
  /// `confirmed`, else kTentative.
  TrackState state = TrackState::kTentative;
  /// Windows in which a tracklet was linked to it (including the birth window).
  int hits = 0;
  /// Confirmed: output (min_hits windows linked, or a strong birth); stays confirmed.
  bool confirmed = false;
  /// Matched windows it needs to be confirmed: fragment_min_hits for a birth that was a piece
  /// of a tracked person (LinkerOptions::fragment_births_wait); 0: min_hits.
  int required_hits = 0;
  /// Consecutive windows (skipped window ids included, saturating) without a linked tracklet.
  int missed_windows = 0;
  /// Window of birth.
  std::int64_t first_window = 0;
  /// Last window in which a tracklet was linked to it (or its birth window).
  std::int64_t last_window = 0;
  /// Last frame with a footprint (valid point) among its linked tracklets.
  FrameIndex last_seen_frame = 0;
  /// First frame with a footprint under its id (kept when a departed track is revived).
  FrameIndex first_seen_frame = 0;
  /// Last frame of a linked tracklet that two or more cameras placed (monocular_max_s).
  FrameIndex last_multiview_frame = 0;
  /// The most recent short-term tracklet linked to it.
  core::Tracklet3D last_tracklet;
  /// Its 2D tracks, sorted by (camera, track); those not seen for longer than max_lost_s plus
  /// a window are forgotten.
  std::vector<TrackMember> members;
  /// Footprint motion, updated with every frame of its tracklets (at last_seen_frame).
  FloorMotion motion;
  /// Appearance on: the descriptors (Tracklet3D::appearance) of its latest windows, oldest
  /// first, at most AppearanceOptions::gallery_size.
  std::vector<std::vector<float>> gallery;
  /// Appearance on: tracks that are, on evidence, the same person: they look alike
  /// (reid_max_distance) and either were seen within kSamePersonApartM of it at the same time
  /// (a duplicate track) or one was born where and when the other was lost (within max_lost_s,
  /// reachable on foot: the next fragment). Such a pair does not make a re-identification
  /// ambiguous; two look-alikes without such evidence do. Sorted, at most kMaxSamePerson (the
  /// oldest forgotten).
  std::vector<TrackId3D> same_person;
};

/// How an input tracklet was linked.
enum class LinkKind {
  kBirth,         ///< unmatched: started a new track
  kOverlap,       ///< linked on the Eq. 8 distance over overlapping frames
  kGap,           ///< linked across a gap: a shared 2D track and the motion gate
  kReidentified,  ///< linked across a gap by motion alone, unambiguously
  kDuplicate,     ///< unmatched, but a second tracklet of a linked track's person (not output)
  kAppearance,    ///< unmatched, re-identified by appearance: a lost or departed track's id
};

/// A track that ended in a Link or EndStream call.
struct EndedTrack {
  TrackId3D id = 0;
  EndReason reason = EndReason::kLostTooLong;
};

/// The outcome of WindowLinker::Link for one window.
struct LinkResult {
  /// The window_id passed to Link.
  std::int64_t window_id = 0;
  /// Parallel to the input tracklets: the long-term id each was linked to (new ids for births).
  std::vector<TrackId3D> track_of_tracklet;
  /// Tracks started in this window (sorted ascending).
  std::vector<TrackId3D> born;
  /// Tracks that had ended and came back in this window by appearance (sorted ascending).
  std::vector<TrackId3D> revived;
  /// Tracks that ended in this window (sorted ascending).
  std::vector<TrackId3D> died;
  /// Parallel to `died`: why.
  std::vector<EndReason> died_reason;
  /// Parallel to the input: for kOverlap the Eq. 8 distance to the linked track (metres), for
  /// kGap and kReidentified the squared Mahalanobis distance of the motion test, for kDuplicate
  /// the Eq. 8 distance to the person's other tracklet, for kAppearance the appearance (cosine)
  /// distance, NaN for births.
  std::vector<double> link_distance_m;
  /// Parallel to the input: how each tracklet was linked.
  std::vector<LinkKind> link_kind;
  /// Parallel to the input: 2D tracks shared with the linked track (0 for births).
  std::vector<int> shared_members;
  /// Parallel to Link's `monocular` tracklets: the track that took each (0: none; such a
  /// tracklet is dropped, never born).
  std::vector<TrackId3D> track_of_monocular;
};

/// Eq. 8 distance between two 3D tracklets: per overlapping frame the mean over points valid
/// in both (same point index; a point is valid when present and finite) of ||X_m - X_n||, then
/// the mean over the overlapping frames that have at least one common valid point. nullopt when
/// there is no such frame. Stateless. Both tracklets must be well formed (frames strictly
/// increasing, points parallel to frames; checked).
std::optional<double> MeanOverlapDistance(const core::Tracklet3D& a, const core::Tracklet3D& b);

/// The footprint (x, y) of one frame's points under `footprint_points` (see LinkerContext);
/// nullopt without a valid point.
std::optional<Vec2> FrameFootprint(const std::vector<std::optional<Vec3>>& points,
                                   const std::vector<int>& footprint_points);

/// Number of `tracklet` members whose (camera, 2D track) is among `members` (both sorted by
/// camera then track, as WindowLinker keeps and ProcessWindowJob makes them).
int SharedMembers(const std::vector<TrackMember>& members, const core::Tracklet3D& tracklet);

/// The motion of `tracklet` estimated backwards over all its footprints, at its first frame
/// with a footprint (frames are `seconds_per_frame` apart): a new tracklet's initial state
/// with its uncertainty. nullopt without a footprint.
std::optional<FloorMotion> InitialMotion(const core::Tracklet3D& tracklet,
                                         const LinkerContext& context,
                                         const MotionOptions& options,
                                         double seconds_per_frame);

/// Whether entry (row, col) of `cost` is smaller by at least `margin` than every other entry of
/// its row and of its column: a match by motion alone that no other candidate of either side
/// comes near (re-identification's reid_margin_chi2). Stateless.
bool UnambiguousMinimum(const Eigen::MatrixXd& cost,
                        Eigen::Index row,
                        Eigen::Index col,
                        double margin);

/// Appearance re-identification never links a tracklet to a track whose footprint would have
/// had to move faster than this since the track's last frame (a brisk walk is 1.5-2 m/s).
inline constexpr double kMaxReidSpeedMps = 3.0;
/// Two tracklets of one window closer than this (metres, footprints at a common frame) may be
/// one person; farther, they are two.
inline constexpr double kSamePersonApartM = 0.5;
/// "Same person" tracks remembered per track (LinkedTrack::same_person).
inline constexpr int kMaxSamePerson = 16;

/// Online track-to-track data association across sliding windows (paper Sec. "Link Sliding
/// Windows", Eq. 8-9) with the track management of the mature online trackers (tentative,
/// confirmed, lost with a time to live, removed). Per window, alive tracks as rows and the
/// window's tracklets as columns, each stage solved optimally (core::SolveAssignment, Eq. 9)
/// among what the earlier stages left:
///  1. Overlap: k >= 1 shared (camera, 2D track) and Eq. 8 <= k x max_link_distance_m (cost:
///     Eq. 8 - k x max_link_distance_m).
///  2. Gap: no overlap, a shared 2D track, the gap <= max_lost_s, and the tracklet's initial
///     state within gap_gate_chi2 of the track's prediction (cost: that distance).
///  3. Re-identification: no overlap, no shared 2D track, a lost track, the gap <=
///     max_reid_gap_s, the motion distance <= reid_gate_chi2 and smaller by reid_margin_chi2
///     than every other candidate of the track and of the tracklet.
/// Then two matched tracklets within duplicate_distance_m of each other are one person linked
/// twice (merge_linked_duplicates): the younger track's tracklet is unmatched again, and that
/// track ends (EndReason::kDuplicate). Then an unmatched tracklet within duplicate_distance_m
/// (Eq. 8) of a matched one is a duplicate of that person (its 2D tracks join the track's members,
/// track_of_tracklet is that track's id, nothing is born). With appearance
/// (core::AppearanceOptions::enabled and tracklets that carry one):
///  4. Appearance: each remaining tracklet with an appearance descriptor (with
///     AppearanceOptions::defer_weak_reid only one that would be a strong birth, plus the
///     tracklets linked in stages 1-3 to tentative tracks born in an earlier window: a weak
///     birth is re-identified, if at all, when its track is linked again, and the tentative
///     track then ends, EndReason::kReidentified) against the confirmed
///     tracks left unmatched by stages 1-3 (lost before or in this window) and the departed
///     tracks (ended within max_reid_s): the gallery distance (core::GalleryDistance) must be
///     <= reid_max_distance and smaller by reid_margin than every other candidate of the track
///     and of the tracklet (candidates that are on evidence the same person,
///     LinkedTrack::same_person, and tracklets within kSamePersonApartM of the chosen one do
///     not count; such a tracklet becomes a duplicate), and the footprint may not have moved
///     faster than kMaxReidSpeedMps (plus kSamePersonApartM) since the track's last frame. A
///     departed track matched so is revived with its old id (LinkResult::revived).
///  With appearance, no stage links a track to a tracklet whose descriptor is farther than
///  link_max_distance from the track's gallery.
/// Matched tracks take their tracklet, the other unmatched tracklets are born (fresh ids, in
/// input order); unmatched tracks are lost. A lost track ends
/// (before a window is linked) when its last footprint is older than max_lost_s; when none of its
/// 2D tracks is alive any more (the person left every camera's view or every camera lost them: 2D
/// track ids are never reused, so only re-identification could link it) and re-identification is
/// off or its gap exceeds max_reid_gap_s.
///
/// Single-owner, single-threaded; deterministic (ties go to the lowest track id, then the lowest
/// tracklet index).
class WindowLinker {
 public:
  /// `options`, `context` and `appearance` must be valid (checked; validate configuration
  /// beforehand).
  explicit WindowLinker(LinkerOptions options = {},
                        LinkerContext context = {},
                        core::AppearanceOptions appearance = {});

  /// Links the next window, which starts at frame `window_begin`; frames are
  /// `seconds_per_frame` apart (the stream's measured period; finite, > 0, checked): it
  /// converts frame gaps to the seconds of the options and the motion model. `live_tracks` are the
  /// 2D tracks observed in the window (sorted by camera then track, as WindowJob::live_tracks): a
  /// lost track none of whose 2D tracks is among them can only come back by re-identification.
  /// Window ids must be strictly increasing (checked); a skipped id counts as a window with no
  /// tracklets. Tracklets must be well formed (checked); a tracklet without any valid point cannot
  /// be linked and is born. `monocular` are the window's tracklets of one camera each
  /// (LinkerOptions::monocular_max_s; well formed, checked): after the stages above, each goes
  /// to the confirmed track that holds its 2D track (the most recently seen holder; ties: the
  /// lowest id), when the track was placed by two or more cameras within monocular_max_s and
  /// the tracklet passes the gate: over common frames with the track's latest tracklet the
  /// median footprint distance <= max_link_distance_m; without common frames, after the track's
  /// last footprint, the gap motion test (gap_gate_chi2, max_lost_s); before the tracklet a
  /// track took in this window, its footprint within kSamePersonApartM plus kMaxReidSpeedMps
  /// times the time between them; with appearance, not vetoed by the gallery. A track matched in
  /// this window only takes the frames; a lost one continues on them (it is matched, its hits do
  /// not change). Longer tracklets first.
  LinkResult Link(std::int64_t window_id,
                  FrameIndex window_begin,
                  double seconds_per_frame,
                  const std::vector<core::Tracklet3D>& tracklets,
                  const std::vector<core::TrackletMember>& live_tracks,
                  const std::vector<core::Tracklet3D>& monocular = {});

  /// The stream ended: every track ends (kStreamEnd), returned sorted by id; the departed
  /// tracks are forgotten.
  std::vector<EndedTrack> EndStream();

  /// A track that ended (kLostTooLong or kLeftView) while confirmed and with a gallery,
  /// remembered for re-identification by appearance.
  struct DepartedTrack {
    TrackId3D id = 0;
    int hits = 0;
    std::int64_t first_window = 0;
    std::int64_t last_window = 0;
    FrameIndex last_seen_frame = 0;
    FrameIndex first_seen_frame = 0;  ///< see LinkedTrack::first_seen_frame
    Vec2 last_position = Vec2::Zero();
    std::vector<std::vector<float>> gallery;
    std::vector<TrackId3D> same_person;  ///< see LinkedTrack::same_person
  };
  /// The departed tracks, in order of ending (AppearanceOptions::max_departed, max_reid_s).
  const std::vector<DepartedTrack>& departed() const { return departed_; }
  /// Bytes held by the galleries of alive and departed tracks (the appearance memory).
  std::size_t gallery_bytes() const;

  /// Alive tracks sorted by id.
  const std::vector<LinkedTrack>& tracks() const { return tracks_; }

  /// The options in use.
  const LinkerOptions& options() const { return options_; }
  const LinkerContext& context() const { return context_; }

  /// The track's motion predicted to `frame`, with the frame period of the latest Link
  /// (diagnostics and tests).
  FloorMotion PredictedMotion(const LinkedTrack& track, FrameIndex frame) const;
  /// The frame period of the latest Link (1/30 s before the first).
  double seconds_per_frame() const { return seconds_per_frame_; }
  /// The id the next new track gets (ids are given out in increasing order, never twice).
  TrackId3D next_id() const { return next_id_; }

 private:
  TrackState StateOf(const LinkedTrack& track) const;
  double Seconds(FrameIndex from, FrameIndex to) const;
  void Absorb(LinkedTrack* track, const core::Tracklet3D& tracklet, std::int64_t window_id);
  void MergeMembers(LinkedTrack* track, const core::Tracklet3D& tracklet) const;
  // The motion update of Absorb: every footprint of `tracklet` after the track's last one.
  void UpdateMotion(LinkedTrack* track, const core::Tracklet3D& tracklet) const;
  // Monocular continuation (see Link): fills result->track_of_monocular.
  void LinkMonocular(std::int64_t window_id,
                     const std::vector<core::Tracklet3D>& monocular,
                     LinkResult* result);
  // Stage 4 of Link (see the class comment): fills `revive` (departed index per tracklet, -1)
  // and links lost tracks into tracklet_of_track / track_of_col.
  void LinkByAppearance(const std::vector<core::Tracklet3D>& tracklets,
                        const std::vector<bool>& column,
                        std::vector<int>* tracklet_of_track,
                        std::vector<int>* track_of_col,
                        std::vector<int>* revive,
                        std::vector<int>* same_as,
                        std::vector<int>* forget,
                        std::vector<int>* absorbed,
                        LinkResult* result) const;

  // Appearance on: records tracks of this window that are, on evidence, the same person
  // (LinkedTrack::same_person).
  void RecordSamePerson(const std::vector<core::Tracklet3D>& tracklets, const LinkResult& result);

  LinkerOptions options_;
  LinkerContext context_;
  core::AppearanceOptions appearance_;
  std::vector<DepartedTrack> departed_;  // in order of ending
  std::vector<LinkedTrack> tracks_;      // increasing id order
  std::optional<std::int64_t> last_window_;
  TrackId3D next_id_ = 1;
  double seconds_per_frame_ = 1.0 / 30.0;
};

}  // namespace mvtrack::linking
