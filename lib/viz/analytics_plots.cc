#include "viz/analytics_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "viz/colors.h"

namespace mvtrack::viz {
namespace {

const cv::Scalar kInk(30, 30, 30);
const cv::Scalar kGrid(220, 220, 220);
const cv::Scalar kPaper(255, 255, 255);

void Text(cv::Mat* img,
          const std::string& text,
          cv::Point at,
          double scale = 0.45,
          const cv::Scalar& color = kInk) {
  cv::putText(*img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, color, 1, cv::LINE_AA);
}

std::string Number(double v, int digits = 0) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

// A "nice" tick step for a span: 1, 2 or 5 times a power of ten, about `ticks` ticks.
double TickStep(double span, int ticks) {
  const double raw = std::max(span, 1e-9) / ticks;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

// Distinct colours for series (TrackColor of small ids is such a palette).
cv::Scalar SeriesColor(std::size_t i) { return TrackColor(static_cast<TrackId3D>(i + 1)); }

}  // namespace

cv::Mat RenderOccupancyPlot(const std::vector<std::string>& names,
                            const std::vector<double>& times_s,
                            const std::vector<std::vector<int>>& occupancy,
                            int width,
                            int height) {
  cv::Mat img(height, width, CV_8UC3, kPaper);
  const int left = 60, right = width - 170, top = 30, bottom = height - 45;
  Text(&img, "occupancy (people inside)", {left, 20}, 0.55);
  if (times_s.empty()) return img;
  const double t0 = times_s.front();
  const double span = std::max(1.0, times_s.back() - t0);
  int peak = 1;
  for (const auto& series : occupancy) {
    for (const int v : series) peak = std::max(peak, v);
  }
  const auto px = [&](double t) {
    return left + static_cast<int>(std::lround((t - t0) / span * (right - left)));
  };
  const auto py = [&](double v) {
    return bottom - static_cast<int>(std::lround(v / peak * (bottom - top)));
  };
  const double ystep = std::max(1.0, std::round(TickStep(peak, 5)));
  for (double v = 0; v <= peak + 1e-9; v += ystep) {
    cv::line(img, {left, py(v)}, {right, py(v)}, kGrid, 1);
    Text(&img, Number(v), {left - 30, py(v) + 5});
  }
  const double xstep = TickStep(span, 8);
  for (double t = 0; t <= span + 1e-9; t += xstep) {
    cv::line(img, {px(t0 + t), bottom}, {px(t0 + t), bottom + 4}, kInk, 1);
    Text(&img, Number(t), {px(t0 + t) - 10, bottom + 18});
  }
  Text(&img, "seconds", {(left + right) / 2 - 25, bottom + 38});
  cv::rectangle(img, {left, top}, {right, bottom}, kInk, 1);
  for (std::size_t r = 0; r < occupancy.size() && r < names.size(); ++r) {
    const cv::Scalar color = SeriesColor(r);
    const std::vector<int>& s = occupancy[r];
    for (std::size_t k = 1; k < s.size() && k < times_s.size(); ++k) {
      // A step: the value holds until the next time.
      cv::line(img,
               {px(times_s[k - 1]), py(s[k - 1])},
               {px(times_s[k]), py(s[k - 1])},
               color,
               2,
               cv::LINE_AA);
      if (s[k] != s[k - 1]) {
        cv::line(
            img, {px(times_s[k]), py(s[k - 1])}, {px(times_s[k]), py(s[k])}, color, 2, cv::LINE_AA);
      }
    }
    const int y = top + 15 + 18 * static_cast<int>(r);
    cv::line(img, {right + 12, y - 4}, {right + 32, y - 4}, color, 3);
    Text(&img, names[r], {right + 38, y});
  }
  return img;
}

cv::Mat RenderDwellHistogram(const std::vector<std::string>& names,
                             const std::vector<std::vector<double>>& dwell_s,
                             int bins,
                             int width,
                             int height_per_region) {
  const int rows = std::max<int>(1, static_cast<int>(names.size()));
  cv::Mat img(30 + rows * height_per_region, width, CV_8UC3, kPaper);
  Text(&img, "dwell per visit (seconds)", {60, 20}, 0.55);
  double longest = 1.0;
  for (const auto& d : dwell_s) {
    for (const double v : d) longest = std::max(longest, v);
  }
  bins = std::max(1, bins);
  const double bin_s = longest / bins;
  for (std::size_t r = 0; r < names.size() && r < dwell_s.size(); ++r) {
    const int top = 30 + static_cast<int>(r) * height_per_region + 20;
    const int bottom = top + height_per_region - 45;
    const int left = 60, right = width - 20;
    std::vector<int> counts(static_cast<std::size_t>(bins), 0);
    for (const double v : dwell_s[r]) {
      const int b = std::min(bins - 1, static_cast<int>(std::floor(v / bin_s)));
      ++counts[static_cast<std::size_t>(std::max(0, b))];
    }
    const int peak = std::max(1, *std::max_element(counts.begin(), counts.end()));
    std::vector<double> sorted = dwell_s[r];
    std::sort(sorted.begin(), sorted.end());
    const std::string median = sorted.empty() ? "-" : Number(sorted[(sorted.size() - 1) / 2], 1);
    Text(&img,
         names[r] + ": " + std::to_string(sorted.size()) + " visits, median " + median + " s",
         {left, top - 4});
    const double bar = static_cast<double>(right - left) / bins;
    for (int b = 0; b < bins; ++b) {
      const int x0 = left + static_cast<int>(std::lround(b * bar));
      const int x1 = left + static_cast<int>(std::lround((b + 1) * bar)) - 1;
      const int h = static_cast<int>(std::lround(
          static_cast<double>(counts[static_cast<std::size_t>(b)]) / peak * (bottom - top - 8)));
      if (h > 0) cv::rectangle(img, {x0, bottom - h}, {x1, bottom}, SeriesColor(r), cv::FILLED);
    }
    cv::line(img, {left, bottom}, {right, bottom}, kInk, 1);
    Text(&img, std::to_string(peak), {left - 35, top + 12});
    const double step = TickStep(longest, 8);
    for (double t = 0; t <= longest + 1e-9; t += step) {
      const int x = left + static_cast<int>(std::lround(t / longest * (right - left)));
      cv::line(img, {x, bottom}, {x, bottom + 4}, kInk, 1);
      Text(&img, Number(t, step < 1.0 ? 1 : 0), {x - 8, bottom + 17}, 0.4);
    }
  }
  return img;
}

cv::Mat RenderHeatMap(const FloorMapping& mapping,
                      const std::vector<analytics::TimedPositions>& messages,
                      const analytics::Site& site,
                      double cell_m,
                      double max_gap_s) {
  const config::FloorRegion& region = mapping.region;
  const int cols = std::max(1, static_cast<int>(std::ceil(region.width_m() / cell_m)));
  const int rows = std::max(1, static_cast<int>(std::ceil(region.depth_m() / cell_m)));
  cv::Mat seconds(rows, cols, CV_64F, cv::Scalar(0.0));
  for (std::size_t k = 0; k < messages.size(); ++k) {
    const double dt = k + 1 < messages.size()
                          ? std::clamp(messages[k + 1].time_s - messages[k].time_s, 0.0, max_gap_s)
                          : 0.0;
    for (const analytics::TrackPosition& t : messages[k].tracks) {
      const int c = static_cast<int>(std::floor((t.floor.x() - region.x_min_m) / cell_m));
      const int r = static_cast<int>(std::floor((region.y_max_m - t.floor.y()) / cell_m));
      if (c >= 0 && c < cols && r >= 0 && r < rows) seconds.at<double>(r, c) += dt;
    }
  }
  double peak = 0.0;
  cv::minMaxLoc(seconds, nullptr, &peak);
  cv::Mat level(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double v = seconds.at<double>(r, c);
      level.at<unsigned char>(r, c) =
          v > 0.0 && peak > 0.0 ? static_cast<unsigned char>(
                                      std::lround(40.0 + 215.0 * std::log1p(v) / std::log1p(peak)))
                                : 0;
    }
  }
  cv::Mat colored;
  cv::applyColorMap(level, colored, cv::COLORMAP_BONE);  // grey-blue: the site stays visible
  cv::Mat image;
  cv::resize(
      colored, image, cv::Size(mapping.width_px, mapping.height_px), 0, 0, cv::INTER_NEAREST);
  DrawSite(mapping, site, &image);
  char legend[96];
  std::snprintf(
      legend, sizeof(legend), "time spent per %.2f m cell, log scale, max %.0f s", cell_m, peak);
  Text(&image, legend, {8, mapping.height_px - 10}, 0.45, cv::Scalar(255, 255, 255));
  return image;
}

}  // namespace mvtrack::viz
