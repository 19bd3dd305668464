// `mvtrack analytics --plots` (issue 41), in the helper mvtrack-pictures: the occupancy, dwell
// and heat-map pictures of lib/viz, next to the CSVs.

#include "viz/analytics_plots.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "analytics/recording.h"
#include "mvtrack/cli.h"
#include "viz/floor_view.h"
#include "viz/image_io.h"

namespace mvtrack::cli {
namespace {

void Write(const std::filesystem::path& path, const cv::Mat& image) {
  std::string why;
  if (!viz::WriteImage(path.string(), image, &why)) throw std::runtime_error(why);
}

void WriteAnalyticsPlots(const std::string& dir,
                         const analytics::Site& site,
                         const std::vector<analytics::TimedPositions>& messages,
                         const analytics::RecordingAnalytics& result) {
  std::vector<std::string> names;
  for (const analytics::Region& r : site.regions) names.push_back(r.name);
  // Occupancy at each message, from the visits (as `--gt` compares it), at most 2000 times.
  std::vector<double> times;
  const std::size_t step = std::max<std::size_t>(1, messages.size() / 2000);
  for (std::size_t k = 0; k < messages.size(); k += step) times.push_back(messages[k].time_s);
  std::vector<std::vector<int>> occupancy;
  for (std::size_t r = 0; r < site.regions.size(); ++r) {
    occupancy.push_back(analytics::OccupancyOver(result.visits, static_cast<int>(r), times));
  }
  const std::filesystem::path out(dir);
  Write(out / "occupancy.png", viz::RenderOccupancyPlot(names, times, occupancy));
  std::vector<std::vector<double>> dwell(site.regions.size());
  for (const analytics::Visit& v : result.visits) {
    dwell[static_cast<std::size_t>(v.region)].push_back(v.dwell_s());
  }
  Write(out / "dwell.png", viz::RenderDwellHistogram(names, dwell));
  // The heat map covers the site and every position, with half a metre around.
  config::FloorRegion region{0.0, 0.0, 0.0, 0.0};
  bool any = false;
  for (const analytics::TimedPositions& m : messages) {
    for (const analytics::TrackPosition& t : m.tracks) {
      const config::FloorRegion point{
          t.floor.x() - 0.5, t.floor.y() - 0.5, t.floor.x() + 0.5, t.floor.y() + 0.5};
      if (!any) {
        region = point;
        any = true;
      }
      region.x_min_m = std::min(region.x_min_m, point.x_min_m);
      region.y_min_m = std::min(region.y_min_m, point.y_min_m);
      region.x_max_m = std::max(region.x_max_m, point.x_max_m);
      region.y_max_m = std::max(region.y_max_m, point.y_max_m);
    }
  }
  if (!any) region = {-1.0, -1.0, 1.0, 1.0};
  viz::IncludeSite(site, 0.5, &region);
  const viz::FloorMapping mapping = viz::FloorMapping::Fit(region, 900);
  Write(out / "heatmap.png",
        viz::RenderHeatMap(mapping, messages, site, 0.25, site.options.max_gap_s));
}

}  // namespace

int RunAnalyticsPictures(int argc, char** argv) {
  return RunAnalyticsWith(argc, argv, &WriteAnalyticsPlots);
}

}  // namespace mvtrack::cli
