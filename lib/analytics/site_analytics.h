#pragma once
/// @file
/// What operators count (issue 41): from the stream of tracks, per named floor region its
/// occupancy, entries, exits and visits (track, enter and exit time, dwell), and per named line
/// its crossings in each direction. docs/DECISIONS.md "Analytics" has the rules and why.
///
/// One rule makes it robust to what trackers do: **a change of side counts once it has held for
/// `hold_s`**, where a side is decided with a band of `hysteresis_m` around the border (a person
/// inside the band keeps the side they had). So a person standing on a region's border does not
/// enter and exit with every jitter, a track that steps out for a moment stays one visit, and a
/// ghost track shorter than `hold_s` never enters. The time reported for a confirmed change is
/// when the border itself was crossed (the first sample past it), not when the change was
/// confirmed: counts and dwell are unbiased, and events are published `hold_s` late. A track
/// that is missing from the messages keeps its state for `max_gap_s` (the tracker continuing a
/// track under its id after a short loss is one visit); after that it has ended where it was
/// last seen.
///
/// Pure and deterministic: no I/O, no clock (times come with the tracks); tracks are processed in
/// id order. Single-owner.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"

namespace mvtrack::analytics {

/// A named floor region: a simple polygon (at least 3 vertices, no edge crossing another, any
/// orientation), metres in the calibration's floor frame (z = 0).
struct Region {
  std::string name;
  std::vector<Vec2> polygon;
};

/// A named line segment on the floor, metres. Its crossings are counted in two directions,
/// named as seen standing at `from` looking towards `to`: left_to_right and right_to_left.
struct Line {
  std::string name;
  Vec2 from = Vec2::Zero();
  Vec2 to = Vec2::Zero();
};

/// The rules' parameters (see the file comment).
struct AnalyticsOptions {
  /// Width of the band around a region's border or a line within which a track keeps its side,
  /// metres, >= 0.
  double hysteresis_m = 0.3;
  /// A change of side counts once it has held this long, seconds, >= 0.
  double hold_s = 0.5;
  /// A track missing from the messages for longer than this has ended, seconds, > 0.
  double max_gap_s = 5.0;
};

/// The site: its regions and lines (names unique among each), and the rules' parameters.
struct Site {
  std::vector<Region> regions;
  std::vector<Line> lines;
  AnalyticsOptions options;
};

/// Bounds on a site (a site file is untrusted input).
inline constexpr int kMaxRegions = 1000;
inline constexpr int kMaxLines = 1000;
inline constexpr int kMaxPolygonVertices = 1000;
/// Longest region or line name, characters.
inline constexpr int kMaxNameLength = 64;

/// Why `name` is not a usable region or line name: names are 1 to kMaxNameLength printable
/// ASCII characters (they travel in LCM strings, which are ASCII); nullopt when it is.
std::optional<std::string> ValidateName(const std::string& name);

/// Why `polygon` is not a usable region (fewer than 3 or more than kMaxPolygonVertices
/// vertices, a non-finite vertex, edges crossing, no area); nullopt when it is.
std::optional<std::string> ValidatePolygon(const std::vector<Vec2>& polygon);

/// Why `site` is not usable (a name empty or repeated, a polygon with fewer than 3 vertices,
/// non-finite coordinates, zero area or crossing edges, a line of zero length, an option out of
/// range), naming the region or line ("regions[2] 'door': ..."); nullopt when it is.
std::optional<std::string> ValidateSite(const Site& site);

/// Signed distance of `p` to `polygon`'s boundary, metres: positive inside, negative outside.
double SignedDistance(const std::vector<Vec2>& polygon, const Vec2& p);

/// A track's position in one tracks message.
struct TrackPosition {
  TrackId3D id = 0;
  Vec2 floor = Vec2::Zero();  ///< footprint on the floor, metres
};

/// A confirmed change.
struct Event {
  enum class Kind {
    kEnter,     ///< a visit of `region` began at `time_s`
    kExit,      ///< the visit that began at `enter_time_s` ended at `time_s`
    kCrossing,  ///< `line` was crossed at `time_s` in `direction`
  };
  enum class Direction { kLeftToRight, kRightToLeft };
  Kind kind = Kind::kEnter;
  int region = -1;  ///< index into Site::regions (enter, exit)
  int line = -1;    ///< index into Site::lines (crossing)
  TrackId3D track = 0;
  double time_s = 0.0;        ///< when it happened (the border crossed, or last seen)
  double enter_time_s = 0.0;  ///< exit: when the visit began
  Direction direction = Direction::kLeftToRight;  ///< crossing
  /// Exit: the visit ended because the track was not seen for max_gap_s (or the input ended),
  /// not by leaving the region.
  bool track_ended = false;
  /// Exit: time_s - enter_time_s.
  double dwell_s() const { return time_s - enter_time_s; }
};

/// "enter", "exit" or "crossing".
const char* ToString(Event::Kind kind);
/// "left_to_right" or "right_to_left".
const char* ToString(Event::Direction direction);

/// Counts per region and line since the start.
struct RegionCounts {
  int occupancy = 0;  ///< visits open now (confirmed, not yet ended)
  std::int64_t entries = 0;
  std::int64_t exits = 0;
};
struct LineCounts {
  std::int64_t left_to_right = 0;
  std::int64_t right_to_left = 0;
};

/// The analytics state of one site over one stream of tracks messages.
class SiteAnalytics {
 public:
  /// `site` must pass ValidateSite (checked: a contract violation otherwise).
  explicit SiteAnalytics(Site site);

  /// One tracks message: its capture time and every track in it (tentative tracks left out by
  /// the caller, if it wants them out). Returns the changes this message confirmed, ordered by
  /// the time they happened (then kind, region or line, track). A message older than the
  /// previous one is ignored (returns nothing, counted in ignored_messages()): time comes from
  /// the input and is not trusted.
  std::vector<Event> Update(double time_s, const std::vector<TrackPosition>& tracks);

  /// Ends the stream (the end of a recording): pending changes that have not held for hold_s
  /// are dropped, every open visit ends where its track was last seen (track_ended).
  std::vector<Event> Finish();

  const Site& site() const { return site_; }
  const std::vector<RegionCounts>& region_counts() const { return region_counts_; }
  const std::vector<LineCounts>& line_counts() const { return line_counts_; }
  /// Messages ignored because their time went backwards or was not finite.
  std::int64_t ignored_messages() const { return ignored_messages_; }
  /// Tracks currently followed (seen within max_gap_s).
  std::size_t num_tracks() const { return tracks_.size(); }

 private:
  // One track against one region or line: the side it has (confirmed), the side it is going
  // to (pending, since pending_since_s), and when it last crossed the border itself.
  struct SideState {
    bool confirmed = false;      // inside the region / on the line's left
    bool known = false;          // the confirmed side is known (a line: once out of the band)
    bool pending = false;        // a change towards !confirmed has passed the band
    double last_distance = 0.0;  // signed distance at the previous sample
    double cross_time_s = 0.0;   // when the border was last crossed towards !confirmed
    bool counted = true;         // a line: that crossing went through the segment
    double enter_time_s = 0.0;   // a region: when the open visit began
  };
  struct TrackState {
    Vec2 last_floor = Vec2::Zero();
    double last_seen_s = 0.0;
    std::vector<SideState> regions;
    std::vector<SideState> lines;
  };
  bool Step(SideState* state,
            double d,
            double previous_time_s,
            double time_s,
            bool first,
            bool* crossed_now = nullptr) const;
  void Confirm(TrackId3D id,
               std::size_t r,
               SideState* state,
               double time_s,
               bool track_ended,
               std::vector<Event>* events);
  void ConfirmCrossing(TrackId3D id, std::size_t l, SideState* state, std::vector<Event>* events);
  void UpdateTrack(TrackId3D id,
                   TrackState* track,
                   const Vec2& floor,
                   double time_s,
                   bool first,
                   std::vector<Event>* events);
  void EndTrack(TrackId3D id, TrackState* track, std::vector<Event>* events);

  Site site_;
  std::vector<RegionCounts> region_counts_;
  std::vector<LineCounts> line_counts_;
  std::vector<std::pair<TrackId3D, TrackState>> tracks_;  // sorted by id
  std::optional<double> last_time_s_;
  std::int64_t ignored_messages_ = 0;
};

/// Sorts events as SiteAnalytics::Update returns them.
void SortEvents(std::vector<Event>* events);

}  // namespace mvtrack::analytics
