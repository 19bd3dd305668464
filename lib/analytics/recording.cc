#include "analytics/recording.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace mvtrack::analytics {
namespace {

void Collect(const std::vector<Event>& events, RecordingAnalytics* out) {
  for (const Event& e : events) {
    if (e.kind == Event::Kind::kExit) {
      out->visits.push_back({e.region, e.track, e.enter_time_s, e.time_s, e.track_ended});
    } else if (e.kind == Event::Kind::kCrossing) {
      out->crossings.push_back({e.line, e.track, e.time_s, e.direction});
    }
  }
}

// The visits of `region`.
std::vector<const Visit*> OfRegion(const std::vector<Visit>& visits, int region) {
  std::vector<const Visit*> out;
  for (const Visit& v : visits) {
    if (v.region == region) out.push_back(&v);
  }
  return out;
}

}  // namespace

RecordingAnalytics AnalyzeRecording(const Site& site, const std::vector<TimedPositions>& messages) {
  SiteAnalytics analytics(site);
  RecordingAnalytics out;
  for (const TimedPositions& m : messages) Collect(analytics.Update(m.time_s, m.tracks), &out);
  Collect(analytics.Finish(), &out);
  out.regions = analytics.region_counts();
  out.lines = analytics.line_counts();
  out.ignored_messages = analytics.ignored_messages();
  return out;
}

int OccupancyAt(const std::vector<Visit>& visits, int region, double time_s) {
  int n = 0;
  for (const Visit& v : visits) n += v.region == region && v.enter_s <= time_s && time_s < v.exit_s;
  return n;
}

std::vector<int> OccupancyOver(const std::vector<Visit>& visits,
                               int region,
                               const std::vector<double>& sorted_times_s) {
  // +1 at each visit's enter time, -1 at its exit time, in time order.
  std::vector<std::pair<double, int>> changes;
  for (const Visit& v : visits) {
    if (v.region != region) continue;
    changes.emplace_back(v.enter_s, +1);
    changes.emplace_back(v.exit_s, -1);
  }
  std::sort(changes.begin(), changes.end());
  std::vector<int> out;
  out.reserve(sorted_times_s.size());
  std::size_t next = 0;
  int open = 0;
  for (const double t : sorted_times_s) {
    // Open at t: enter_s <= t < exit_s.
    while (next < changes.size() && changes[next].first <= t) open += changes[next++].second;
    out.push_back(open);
  }
  return out;
}

double Quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(sorted.size()));
  const auto i = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  return sorted[std::min(i, sorted.size() - 1)];
}

AnalyticsComparison CompareAnalytics(const Site& site,
                                     const RecordingAnalytics& truth,
                                     const RecordingAnalytics& predicted,
                                     const std::vector<double>& frame_times_s) {
  AnalyticsComparison out;
  out.regions.resize(site.regions.size());
  out.lines.resize(site.lines.size());
  std::vector<double> times = frame_times_s;
  std::sort(times.begin(), times.end());
  for (std::size_t r = 0; r < site.regions.size(); ++r) {
    RegionComparison& c = out.regions[r];
    const int region = static_cast<int>(r);
    if (r < truth.regions.size()) {
      c.gt_entries = truth.regions[r].entries;
      c.gt_exits = truth.regions[r].exits;
    }
    if (r < predicted.regions.size()) {
      c.entries = predicted.regions[r].entries;
      c.exits = predicted.regions[r].exits;
    }
    // Occupancy per frame.
    const std::vector<int> occ_gt = OccupancyOver(truth.visits, region, times);
    const std::vector<int> occ_pred = OccupancyOver(predicted.visits, region, times);
    for (std::size_t k = 0; k < times.size(); ++k) {
      ++c.occupancy_frames;
      c.occupancy_frames_equal += occ_gt[k] == occ_pred[k];
      c.occupancy_abs_error_sum += std::abs(occ_gt[k] - occ_pred[k]);
    }
    const std::vector<const Visit*> gt = OfRegion(truth.visits, region);
    const std::vector<const Visit*> pred = OfRegion(predicted.visits, region);
    // Dwell: visits matched one to one, the largest overlap first.
    c.gt_visits = static_cast<std::int64_t>(gt.size());
    c.visits = static_cast<std::int64_t>(pred.size());
    // The overlapping pairs only (a day of visits would make every pair too many): the
    // tracker's visits sorted by enter time, each ground-truth visit scanning those that enter
    // before it ends and no earlier than the longest visit before it begins.
    std::vector<std::size_t> by_enter(pred.size());
    double longest = 0.0;
    for (std::size_t j = 0; j < pred.size(); ++j) {
      by_enter[j] = j;
      longest = std::max(longest, pred[j]->dwell_s());
    }
    std::sort(by_enter.begin(), by_enter.end(), [&](std::size_t a, std::size_t b) {
      return pred[a]->enter_s < pred[b]->enter_s;
    });
    std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
    for (std::size_t i = 0; i < gt.size(); ++i) {
      auto k = std::lower_bound(
          by_enter.begin(), by_enter.end(), gt[i]->enter_s - longest, [&](std::size_t j, double t) {
            return pred[j]->enter_s < t;
          });
      for (; k != by_enter.end() && pred[*k]->enter_s < gt[i]->exit_s; ++k) {
        const std::size_t j = *k;
        const double overlap =
            std::min(gt[i]->exit_s, pred[j]->exit_s) - std::max(gt[i]->enter_s, pred[j]->enter_s);
        if (overlap > 0.0) pairs.emplace_back(-overlap, i, j);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<char> gt_used(gt.size(), 0), pred_used(pred.size(), 0);
    for (const auto& [negative_overlap, i, j] : pairs) {
      if (gt_used[i] || pred_used[j]) continue;
      gt_used[i] = pred_used[j] = 1;
      c.dwell_errors_s.push_back(std::abs(pred[j]->dwell_s() - gt[i]->dwell_s()));
    }
    std::sort(c.dwell_errors_s.begin(), c.dwell_errors_s.end());
  }
  for (std::size_t l = 0; l < site.lines.size(); ++l) {
    LineComparison& c = out.lines[l];
    if (l < truth.lines.size()) {
      c.gt_left_to_right = truth.lines[l].left_to_right;
      c.gt_right_to_left = truth.lines[l].right_to_left;
    }
    if (l < predicted.lines.size()) {
      c.left_to_right = predicted.lines[l].left_to_right;
      c.right_to_left = predicted.lines[l].right_to_left;
    }
  }
  return out;
}

}  // namespace mvtrack::analytics
