// lib/analytics recordings: a whole stream analysed, and a tracker's counts compared with the
// ground truth's (occupancy per frame, visits matched by overlap, dwell errors).

#include "analytics/recording.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace mvtrack::analytics {
namespace {

Site Square() {
  Site site;
  site.regions.push_back({"square", {{0, 0}, {2, 0}, {2, 2}, {0, 2}}});
  site.lines.push_back({"cut", {3, -1}, {3, 3}});
  site.options.hold_s = 0.0;
  return site;
}

// Track `id` inside the square (at (1.5, 1)) over [from, to) s, outside (at (5, 1)) otherwise,
// sampled at 10 Hz over [0, 10) s.
std::vector<TimedPositions> Inside(
    const std::vector<std::tuple<TrackId3D, double, double>>& stays) {
  std::vector<TimedPositions> out;
  for (int i = 0; i < 100; ++i) {
    TimedPositions m;
    m.time_s = 0.1 * i;
    for (const auto& [id, from, to] : stays) {
      const bool in = m.time_s >= from - 1e-9 && m.time_s < to - 1e-9;
      m.tracks.push_back({id, in ? Vec2(1.5, 1) : Vec2(5, 1)});
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

TEST_CASE("analytics recording: visits, occupancy at a time, quantiles", "[unit]") {
  const RecordingAnalytics r = AnalyzeRecording(Square(), Inside({{1, 2.0, 5.0}, {2, 3.0, 8.0}}));
  REQUIRE(r.visits.size() == 2);
  CHECK(r.visits[0].track == 1);
  CHECK(r.visits[0].dwell_s() == Approx(3.0).margin(0.11));  // border crossed between samples
  CHECK(OccupancyAt(r.visits, 0, 2.5) == 1);
  CHECK(OccupancyAt(r.visits, 0, 4.0) == 2);
  CHECK(OccupancyAt(r.visits, 0, 9.0) == 0);
  CHECK(r.regions[0].entries == 2);
  // Jumping from (5, 1) to (1.5, 1) and back crosses the cut (x = 3) each way.
  CHECK(r.lines[0].right_to_left == 2);
  CHECK(r.lines[0].left_to_right == 2);
  CHECK(Quantile({1, 2, 3, 4}, 0.5) == 2);
  CHECK(Quantile({1, 2, 3, 4}, 0.95) == 4);
  CHECK(std::isnan(Quantile({}, 0.5)));
}

TEST_CASE("analytics recording: counts, occupancy and dwell against the ground truth", "[unit]") {
  const Site site = Square();
  const RecordingAnalytics truth = AnalyzeRecording(site, Inside({{1, 2.0, 5.0}, {2, 3.0, 8.0}}));
  // The tracker: track 1's visit 0.5 s late and split by a new id at 4.0 s (ids 7 and 8), track
  // 2 as the truth.
  const RecordingAnalytics tracker =
      AnalyzeRecording(site, Inside({{7, 2.5, 4.0}, {8, 4.0, 5.0}, {2, 3.0, 8.0}}));
  std::vector<double> frames;
  for (int i = 0; i < 100; ++i) frames.push_back(0.1 * i);
  const AnalyticsComparison c = CompareAnalytics(site, truth, tracker, frames);
  REQUIRE(c.regions.size() == 1);
  const RegionComparison& r = c.regions[0];
  CHECK(r.gt_entries == 2);
  CHECK(r.entries == 3);
  CHECK(r.occupancy_frames == 100);
  // Occupancy differs only in [2.0, 2.5): 5 frames, by one.
  CHECK(r.occupancy_frames_equal == 95);
  CHECK(r.occupancy_abs_error_sum == 5);
  // Matched one to one by overlap: truth 2 with tracker 2 (5 s), truth 1 with tracker 7 (1.5 s
  // against 8's 1 s); tracker 8 unmatched.
  REQUIRE(r.dwell_errors_s.size() == 2);
  CHECK(r.dwell_errors_s[0] == Approx(0.0).margin(1e-9));
  CHECK(r.dwell_errors_s[1] == Approx(1.5).margin(1e-6));
  CHECK(r.gt_visits == 2);
  CHECK(r.visits == 3);
}

}  // namespace mvtrack::analytics
