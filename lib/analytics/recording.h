#pragma once
/// @file
/// The analytics of a whole recording (issue 41, `mvtrack analytics`): every visit and crossing
/// of a stream of tracks messages, and the comparison of a tracker's counts with those of the
/// ground truth's tracks under the same rules. Pure and deterministic.

#include <cstdint>
#include <vector>

#include "analytics/site_analytics.h"

namespace mvtrack::analytics {

/// One tracks message: its time and its tracks' floor positions.
struct TimedPositions {
  double time_s = 0.0;
  std::vector<TrackPosition> tracks;
};

/// A visit of a region: from enter_s (the border crossed, or the track appearing inside) to
/// exit_s (the border crossed again, or the track last seen when it ended).
struct Visit {
  int region = 0;
  TrackId3D track = 0;
  double enter_s = 0.0;
  double exit_s = 0.0;
  bool track_ended = false;  ///< the visit ended with its track, not by leaving
  double dwell_s() const { return exit_s - enter_s; }
};

/// A line crossing.
struct Crossing {
  int line = 0;
  TrackId3D track = 0;
  double time_s = 0.0;
  Event::Direction direction = Event::Direction::kLeftToRight;
};

/// Everything SiteAnalytics found in a recording, in the order of the events (time, ...).
struct RecordingAnalytics {
  std::vector<Visit> visits;          ///< ordered by exit time (when they were complete)
  std::vector<Crossing> crossings;    ///< ordered by time
  std::vector<RegionCounts> regions;  ///< final counts (occupancy 0: every visit closed)
  std::vector<LineCounts> lines;
  std::int64_t ignored_messages = 0;
};

/// Runs SiteAnalytics over `messages` (in order) and Finish()es it.
RecordingAnalytics AnalyzeRecording(const Site& site, const std::vector<TimedPositions>& messages);

/// Visits of `region` open at `time_s` (enter_s <= time_s < exit_s).
int OccupancyAt(const std::vector<Visit>& visits, int region, double time_s);

/// OccupancyAt at each of `sorted_times_s` (ascending), in one sweep over the visits.
std::vector<int> OccupancyOver(const std::vector<Visit>& visits,
                               int region,
                               const std::vector<double>& sorted_times_s);

/// A tracker's counts against the ground truth's (both analysed with the same site and rules).
struct RegionComparison {
  std::int64_t gt_entries = 0, entries = 0;
  std::int64_t gt_exits = 0, exits = 0;
  /// Frames (the ground truth's message times) where the occupancy agrees, of all frames.
  std::int64_t occupancy_frames_equal = 0, occupancy_frames = 0;
  /// Sum over those frames of |occupancy - the ground truth's| (divided by occupancy_frames:
  /// the mean absolute error).
  std::int64_t occupancy_abs_error_sum = 0;
  /// Visits matched one to one (the largest time overlap first, same region, overlapping):
  /// |dwell - ground truth's dwell| per matched visit, seconds, ascending.
  std::vector<double> dwell_errors_s;
  std::int64_t gt_visits = 0, visits = 0;
};
struct LineComparison {
  std::int64_t gt_left_to_right = 0, left_to_right = 0;
  std::int64_t gt_right_to_left = 0, right_to_left = 0;
};
struct AnalyticsComparison {
  std::vector<RegionComparison> regions;
  std::vector<LineComparison> lines;
};

/// Compares `predicted` with `truth`; `frame_times_s`: the times occupancy is compared at.
AnalyticsComparison CompareAnalytics(const Site& site,
                                     const RecordingAnalytics& truth,
                                     const RecordingAnalytics& predicted,
                                     const std::vector<double>& frame_times_s);

/// The q-quantile (0..1, nearest rank) of ascending `sorted`; NaN when empty.
double Quantile(const std::vector<double>& sorted, double q);

}  // namespace mvtrack::analytics
