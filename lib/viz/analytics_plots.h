#pragma once
/// @file
/// The pictures of `mvtrack analytics --plots` (issue 41): the occupancy of each region over
/// time, the histogram of each region's dwell times, and a heat map of where people spent their
/// time on the floor with the site drawn over it. Stateless; CV_8UC3 images.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "analytics/recording.h"
#include "analytics/site_analytics.h"
#include "viz/floor_view.h"

namespace mvtrack::viz {

/// Occupancy over time: one line per region (its colour and name in the legend), x = seconds
/// since `times_s.front()`, y = people. `occupancy[r][k]` is region r's occupancy at
/// `times_s[k]` (times ascending). A width x height image.
cv::Mat RenderOccupancyPlot(const std::vector<std::string>& names,
                            const std::vector<double>& times_s,
                            const std::vector<std::vector<int>>& occupancy,
                            int width = 900,
                            int height = 420);

/// Dwell histogram: per region a row of bars, `bins` equal bins from 0 to the largest dwell
/// (at least 1 s), labelled with the count of visits and their median. A width x height image.
cv::Mat RenderDwellHistogram(const std::vector<std::string>& names,
                             const std::vector<std::vector<double>>& dwell_s,
                             int bins = 20,
                             int width = 900,
                             int height_per_region = 140);

/// Heat map of the seconds tracks spent in each cell of `cell_m` metres (each message's tracks
/// weighted by the time to the next message, at most `max_gap_s`), on a log colour scale, with
/// `site` drawn over it. `messages` in time order.
cv::Mat RenderHeatMap(const FloorMapping& mapping,
                      const std::vector<analytics::TimedPositions>& messages,
                      const analytics::Site& site,
                      double cell_m = 0.25,
                      double max_gap_s = 1.0);

}  // namespace mvtrack::viz
