#pragma once
/// @file
/// The stitcher of a site split into zones (issue 43): one tracker per zone, each publishing its
/// own track ids; the stitcher joins the zones' tracks into one id space. Along a border both
/// neighbouring zones track the same people from the same border cameras' detections, so a
/// person crossing is, for a while, a track of each zone at the same place and time: the
/// overlap evidence of the window linker (Eq. 8: the mean footprint distance over common
/// frames), here over common capture times. Pure: no threads, no I/O, no clock; deterministic.
///
/// AlignZoneFrames groups the zones' frames by capture time; Stitcher turns each group into one
/// site frame with global ids. docs/DECISIONS.md "The stitcher" has the rules and measurements.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/types.h"
#include "linking/floor_motion.h"
#include "linking/window_linker.h"
#include "tracker/types.h"

namespace mvtrack::stitch {

/// One site frame's input: per zone (by zone index) its frame at this capture time, or null
/// when the zone has none (silent, late beyond the wait, or it produced no frame there).
using ZoneFrames = std::vector<const tracker::Frame3D*>;

/// Groups the frames of every zone (`zones[z]`: zone z's frames, utime strictly increasing;
/// checked) by capture time: a group opens at the earliest frame not grouped yet and takes each
/// zone's next frame whose utime is less than `tolerance_us` later (> 0, checked; half a frame
/// period: the zones' capture times of one frame differ by the cameras' skew only). Groups in
/// increasing time; each holds at most one frame per zone. The pointers point into `zones`.
std::vector<ZoneFrames> AlignZoneFrames(const std::vector<std::vector<tracker::Frame3D>>& zones,
                                        Utime tolerance_us);

/// Half the median step between consecutive utimes of `frames` (of one zone, increasing):
/// the alignment tolerance for AlignZoneFrames. nullopt with fewer than two frames.
std::optional<Utime> HalfFramePeriod(const std::vector<tracker::Frame3D>& frames);

/// One site frame: the zones' tracks under global ids.
struct SiteFrame {
  /// frame and utime of the group's earliest zone frame; tracks sorted by global id, each
  /// with the zones whose tracks make it (Track3D::zones); frame.zones names the site's zones.
  tracker::Frame3D frame;
};

/// Cumulative counters.
struct StitchStats {
  std::int64_t frames = 0;          ///< site frames stitched
  std::int64_t global_ids = 0;      ///< global ids given out
  std::int64_t joined_overlap = 0;  ///< zone tracks joined to a global track in an overlap
  std::int64_t joined_motion = 0;   ///< zone tracks joined to a lost global track by motion
  std::int64_t splits = 0;          ///< joins undone: the two zones' tracks went apart
  std::int64_t merges = 0;          ///< global tracks merged into an older one (rule 5)
  std::int64_t multi_zone_track_frames = 0;  ///< track-frames made by two or more zones
};

/// Joins the zone tracks of consecutive site frames into global tracks. Rules, per site frame:
///  1. A zone track joined before keeps its global id.
///  2. A zone track leaves its global track when, in kSplitFrames consecutive frames, it
///     disagrees with the global track's oldest zone track: farther than 2 x kSamePersonApartM
///     (two zones' footprints of one person differ by 0.19 m at the 90th percentile, 0.5 m at
///     the 99th, 0.74 m at most on the simulated corridor), or nearer a global track its zone
///     does not see, within kSamePersonApartM (it was joined to the wrong one of two people).
///  3. Every zone track without a global id is matched (core::SolveAssignment, cost = the
///     footprint distance) to the global tracks other zones see now, within kSamePersonApartM
///     (the linker's same-person bound: in an overlap both zones triangulate the person from
///     largely the same detections) of the other zones' mean footprint; a global track that a
///     track of the same zone already holds only when the open one is nearer by 0.2 m (the
///     zone has two tracks there, and the worse one was joined first: it starts its own).
///  4. What is left, with LinkerOptions::reid_gate_chi2 > 0, is matched by motion alone to the
///     global tracks no zone sees now, lost for at most max_reid_gap_s by another zone: the
///     linker's re-identification (state test within reid_gate_chi2, unambiguous by
///     reid_margin_chi2). Off with the linker's defaults, as in the zones themselves.
///  5. The rest start global tracks (ids from 1, increasing, never reused); zones are taken in
///     index order, so a person first seen by two zones in the same frame is joined at once.
///  6. Two global tracks seen by disjoint sets of zones within kSamePersonApartM of each other
///     in kSplitFrames consecutive frames are one person whose zone tracks appeared apart: the
///     younger merges into the older (its id ends), as the linker merges a person linked twice.
/// A global track's footprint (and joints) is the mean of its zone tracks in the frame. A zone
/// track unseen for longer than max_lost_s is forgotten, a global track likewise.
/// Single-owner, single-threaded; deterministic (zones in index order, tracks in id order).
class Stitcher {
 public:
  /// Consecutive common frames of rule 2.
  static constexpr int kSplitFrames = 3;

  /// `zone_names`: at least one, non-empty, index = zone (checked); `linker` valid
  /// (checked): the zones' linker options (max_lost_s, the motion model and the
  /// re-identification gates). Global ids start at `first_id` (>= 1; a restarted stitcher
  /// starts past the ids it gave out before, service::IdReservation).
  Stitcher(std::vector<std::string> zone_names,
           const linking::LinkerOptions& linker,
           TrackId3D first_id = 1);

  /// Stitches one site frame: `zone_frames` has one entry per zone (checked), at least one not
  /// null, their utimes after those of the previous call (checked).
  SiteFrame Stitch(const ZoneFrames& zone_frames);

  const StitchStats& stats() const { return stats_; }
  /// The id the next global track gets.
  TrackId3D next_id() const { return next_id_; }

 private:
  struct Join {
    TrackId3D global = 0;
    std::int64_t order = 0;  // when it joined (rule 2: the later leaves)
    int far_frames = 0;      // consecutive common frames too far from the oldest join's track
    Utime last_seen = 0;
  };
  struct Global {
    Utime last_seen = 0;
    FrameIndex first_frame = 0;
    bool moving = false;  // motion started (a finite footprint seen)
    linking::FloorMotion motion;
    Utime motion_utime = 0;
    std::vector<int> last_zones;  // zones that saw it last
  };
  using ZoneTrack = std::pair<int, TrackId3D>;

  double Seconds(Utime from, Utime to) const;

  int num_zones_;
  std::vector<std::string> zone_names_;
  linking::LinkerOptions linker_;
  std::map<ZoneTrack, Join> joins_;
  std::map<TrackId3D, Global> globals_;
  std::map<std::pair<TrackId3D, TrackId3D>, int> close_pairs_;  // rule 6: consecutive frames
  TrackId3D next_id_ = 1;
  std::int64_t next_order_ = 0;
  std::optional<Utime> last_utime_;
  StitchStats stats_;
};

}  // namespace mvtrack::stitch
