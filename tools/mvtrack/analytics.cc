// mvtrack analytics: region visits and line crossings of a recorded track output (issue 41),
// written as CSV, and compared with the ground truth's under the same rules (--gt).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "analytics/recording.h"
#include "config/config_error.h"
#include "config/site.h"
#include "formats/tracks_io.h"
#include "json/document.h"
#include "mvtrack/cli.h"

namespace mvtrack::cli {
namespace {

// A CSV field: quoted when it holds a comma, a quote or a line break (names are free text).
std::string Field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// The tracks of a file as analytics messages: time from each frame's utime (seconds), or from
// its frame index at `fps` when the file has no times (every utime 0).
std::vector<analytics::TimedPositions> Messages(const formats::TrackFile& file, double fps) {
  bool has_time = false;
  for (const formats::TrackFileFrame& f : file.frames) has_time = has_time || f.frame.utime != 0;
  std::vector<analytics::TimedPositions> out;
  out.reserve(file.frames.size());
  for (const formats::TrackFileFrame& f : file.frames) {
    analytics::TimedPositions m;
    m.time_s = has_time ? static_cast<double>(f.frame.utime) * 1e-6
                        : static_cast<double>(f.frame.frame) / fps;
    for (const tracker::Track3D& t : f.frame.tracks) {
      m.tracks.push_back({t.id, t.position.head<2>()});
    }
    out.push_back(std::move(m));
  }
  return out;
}

void WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

// visits.csv, crossings.csv and summary.csv (per region and hour of the enter time, UTC hours
// since the epoch when the input has capture times).
void WriteCsv(const std::filesystem::path& dir,
              const analytics::Site& site,
              const analytics::RecordingAnalytics& result) {
  std::string visits = "region,track,enter_s,exit_s,dwell_s,ended_by\n";
  for (const analytics::Visit& v : result.visits) {
    visits += Field(site.regions[static_cast<std::size_t>(v.region)].name) + "," +
              std::to_string(v.track) + "," + Fixed(v.enter_s, 3) + "," + Fixed(v.exit_s, 3) + "," +
              Fixed(v.dwell_s(), 3) + "," + (v.track_ended ? "track_end" : "exit") + "\n";
  }
  WriteFile(dir / "visits.csv", visits);
  std::string crossings = "line,track,time_s,direction\n";
  for (const analytics::Crossing& c : result.crossings) {
    crossings += Field(site.lines[static_cast<std::size_t>(c.line)].name) + "," +
                 std::to_string(c.track) + "," + Fixed(c.time_s, 3) + "," +
                 analytics::ToString(c.direction) + "\n";
  }
  WriteFile(dir / "crossings.csv", crossings);
  // Per region and hour: visits begun in the hour, their mean dwell; per line and hour: the
  // crossings in each direction.
  struct Hour {
    std::int64_t visits = 0;
    double dwell = 0.0;
    std::int64_t left_to_right = 0, right_to_left = 0;
  };
  std::map<std::pair<std::string, std::int64_t>, Hour> hours;
  for (const analytics::Visit& v : result.visits) {
    Hour& h = hours[{"region:" + site.regions[static_cast<std::size_t>(v.region)].name,
                     static_cast<std::int64_t>(std::floor(v.enter_s / 3600.0))}];
    ++h.visits;
    h.dwell += v.dwell_s();
  }
  for (const analytics::Crossing& c : result.crossings) {
    Hour& h = hours[{"line:" + site.lines[static_cast<std::size_t>(c.line)].name,
                     static_cast<std::int64_t>(std::floor(c.time_s / 3600.0))}];
    ++(c.direction == analytics::Event::Direction::kLeftToRight ? h.left_to_right
                                                                : h.right_to_left);
  }
  std::string summary = "kind,name,hour_start_s,visits,mean_dwell_s,left_to_right,right_to_left\n";
  for (const auto& [key, h] : hours) {
    const std::string kind = key.first.substr(0, key.first.find(':'));
    const std::string name = key.first.substr(key.first.find(':') + 1);
    summary += kind + "," + Field(name) + "," + std::to_string(key.second * 3600) + ",";
    if (kind == "region") {
      summary += std::to_string(h.visits) + "," +
                 Fixed(h.dwell / static_cast<double>(h.visits), 3) + ",,\n";
    } else {
      summary +=
          ",," + std::to_string(h.left_to_right) + "," + std::to_string(h.right_to_left) + "\n";
    }
  }
  WriteFile(dir / "summary.csv", summary);
}

std::string Percent(std::int64_t part, std::int64_t whole) {
  return whole > 0 ? Fixed(100.0 * static_cast<double>(part) / static_cast<double>(whole), 2)
                   : std::string("n/a");
}

// Relative count error, percent of the ground truth's count.
std::string CountError(std::int64_t count, std::int64_t truth) {
  if (truth == 0) return count == 0 ? "0.00" : "n/a";
  return Fixed(100.0 * static_cast<double>(count - truth) / static_cast<double>(truth), 2);
}

}  // namespace

int RunAnalytics(int argc, char** argv) { return RunAnalyticsWith(argc, argv, nullptr); }

int RunAnalyticsWith(int argc, char** argv, AnalyticsPlots plots) {
  Args args;
  args.Option("tracks", "track output to analyse (tracks JSONL or an LCM tracks log)")
      .Option("regions", "site file with the regions and lines (format mvtrack.site/1)")
      .Option("out", "write visits.csv, crossings.csv and summary.csv into this directory")
      .Option("gt", "ground-truth tracks (JSONL or log): also analysed, and the counts compared")
      .Option("json", "also write the counts (and the comparison) as JSON to this file")
      .Flag("plots",
            "with --out: also draw occupancy.png (per region over time), dwell.png (histogram "
            "per region) and heatmap.png (time spent on the floor, with the site)")
      .Option("fps", "frame rate for files without capture times (every utime 0)", "25")
      .Flag("quiet", "no progress lines on stderr");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack analytics --tracks TRACKS --regions SITE.yaml [--out DIR] [--gt GT]",
          "Counts what operators ask of tracks: per region of the site file its visits (track,\n"
          "enter and exit time, dwell), entries and exits; per line its crossings in each\n"
          "direction (left_to_right / right_to_left, seen from the line's `from` towards its\n"
          "`to`). The rules (hysteresis band, hold time, gap) are the site file's `rules:`;\n"
          "docs/FORMATS.md \"Site file\" and docs/DECISIONS.md \"Analytics\" explain them.\n"
          "Times are the tracks' capture times in seconds (utime / 1e6).\n\n"
          "With --out DIR: visits.csv (region,track,enter_s,exit_s,dwell_s,ended_by),\n"
          "crossings.csv (line,track,time_s,direction) and summary.csv (per region and\n"
          "hour: visits begun and their mean dwell; per line and hour: crossings); with\n"
          "--plots also occupancy.png, dwell.png and heatmap.png.\n"
          "With --gt: the ground truth's tracks are analysed with the same site and rules,\n"
          "and per region the entries, exits, occupancy (per ground-truth frame, from the\n"
          "visits) and dwell (visits matched by time overlap), per line the crossings, are\n"
          "compared.\n\n"
          "Exit status: 0 done, 1 invalid site file or unreadable tracks, 2 usage error.")) {
    return 0;
  }
  if (!args.Has("tracks")) throw UsageError("--tracks is required");
  if (args.Has("plots") && !args.Has("out")) throw UsageError("--plots needs --out DIR");
  // The pictures need OpenCV, which only the helper links: run the whole command there.
  if (args.Has("plots") && plots == nullptr) return ExecPictures("analytics", argc - 1, argv + 1);
  if (!args.Has("regions")) throw UsageError("--regions is required");
  const double fps = args.GetDouble("fps");
  if (!(fps > 0.0 && fps <= 1000.0)) throw UsageError("--fps must be in (0, 1000]");
  const bool quiet = args.Has("quiet");
  const auto progress = [&](const std::string& message) {
    if (!quiet) std::cerr << "mvtrack analytics: " << message << "\n";
  };

  analytics::Site site;
  formats::TrackFile tracks, truth;
  try {
    site = config::LoadSiteFile(args.Get("regions"));
    progress("reading " + args.Get("tracks"));
    tracks = formats::ReadTrackFile(args.Get("tracks"));
    if (args.Has("gt")) {
      progress("reading " + args.Get("gt"));
      truth = formats::ReadTrackFile(args.Get("gt"));
    }
  } catch (const config::ConfigError& e) {
    std::cerr << "mvtrack analytics: " << e.what() << "\n";
    return 1;
  } catch (const formats::TrackFileError& e) {
    std::cerr << "mvtrack analytics: " << e.what() << "\n";
    return 1;
  }
  progress("analysing " + std::to_string(tracks.frames.size()) + " frames, " +
           std::to_string(site.regions.size()) + " region(s), " +
           std::to_string(site.lines.size()) + " line(s)");
  const std::vector<analytics::TimedPositions> messages = Messages(tracks, fps);
  const auto started = std::chrono::steady_clock::now();
  const analytics::RecordingAnalytics result = analytics::AnalyzeRecording(site, messages);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  char timing[160];
  std::snprintf(timing,
                sizeof(timing),
                "analysed %zu frames in %.3f s (%.0f frames/s; reading not included)",
                messages.size(),
                seconds,
                seconds > 0.0 ? static_cast<double>(messages.size()) / seconds : 0.0);
  progress(timing);
  if (result.ignored_messages > 0) {
    std::cerr << "mvtrack analytics: warning: " << result.ignored_messages
              << " frame(s) ignored: their time went backwards\n";
  }

  json::OrderedDocument doc;
  doc["tracks"] = tracks.path;
  doc["frames"] = tracks.frames.size();
  doc["ignored_frames"] = result.ignored_messages;
  doc["regions"] = json::OrderedDocument::array();
  doc["lines"] = json::OrderedDocument::array();
  std::cout << "regions (" << tracks.path << "):\n"
            << "  region               entries    exits  visits  dwell median s  dwell p95 s\n";
  for (std::size_t r = 0; r < site.regions.size(); ++r) {
    std::vector<double> dwell;
    for (const analytics::Visit& v : result.visits) {
      if (v.region == static_cast<int>(r)) dwell.push_back(v.dwell_s());
    }
    std::sort(dwell.begin(), dwell.end());
    doc["regions"].push_back({{"name", site.regions[r].name},
                              {"entries", result.regions[r].entries},
                              {"exits", result.regions[r].exits},
                              {"visits", dwell.size()},
                              {"dwell_median_s", analytics::Quantile(dwell, 0.5)},
                              {"dwell_p95_s", analytics::Quantile(dwell, 0.95)}});
    char line[256];
    std::snprintf(line,
                  sizeof(line),
                  "  %-20s %8lld %8lld %7zu %15s %12s\n",
                  site.regions[r].name.c_str(),
                  static_cast<long long>(result.regions[r].entries),
                  static_cast<long long>(result.regions[r].exits),
                  dwell.size(),
                  Fixed(analytics::Quantile(dwell, 0.5), 2).c_str(),
                  Fixed(analytics::Quantile(dwell, 0.95), 2).c_str());
    std::cout << line;
  }
  if (!site.lines.empty()) {
    std::cout << "lines:\n  line                 left_to_right  right_to_left\n";
    for (std::size_t l = 0; l < site.lines.size(); ++l) {
      doc["lines"].push_back({{"name", site.lines[l].name},
                              {"left_to_right", result.lines[l].left_to_right},
                              {"right_to_left", result.lines[l].right_to_left}});
      char line[256];
      std::snprintf(line,
                    sizeof(line),
                    "  %-20s %13lld %14lld\n",
                    site.lines[l].name.c_str(),
                    static_cast<long long>(result.lines[l].left_to_right),
                    static_cast<long long>(result.lines[l].right_to_left));
      std::cout << line;
    }
  }

  if (args.Has("gt")) {
    const std::vector<analytics::TimedPositions> gt_messages = Messages(truth, fps);
    const analytics::RecordingAnalytics gt = analytics::AnalyzeRecording(site, gt_messages);
    std::vector<double> times;
    times.reserve(gt_messages.size());
    for (const analytics::TimedPositions& m : gt_messages) times.push_back(m.time_s);
    const analytics::AnalyticsComparison c = analytics::CompareAnalytics(site, gt, result, times);
    doc["gt"] = truth.path;
    std::cout << "against the ground truth (" << truth.path << ", same rules):\n"
              << "  region               entries (gt)  error %  exits (gt)  error %  "
                 "occupancy exact %  MAE  visits matched  dwell error median s  p95 s\n";
    for (std::size_t r = 0; r < site.regions.size(); ++r) {
      const analytics::RegionComparison& rc = c.regions[r];
      json::OrderedDocument& d = doc["regions"][r];
      d["gt_entries"] = rc.gt_entries;
      d["gt_exits"] = rc.gt_exits;
      d["gt_visits"] = rc.gt_visits;
      d["occupancy_frames"] = rc.occupancy_frames;
      d["occupancy_frames_exact"] = rc.occupancy_frames_equal;
      d["occupancy_abs_error_sum"] = rc.occupancy_abs_error_sum;
      d["visits_matched"] = rc.dwell_errors_s.size();
      d["dwell_error_median_s"] = analytics::Quantile(rc.dwell_errors_s, 0.5);
      d["dwell_error_p95_s"] = analytics::Quantile(rc.dwell_errors_s, 0.95);
      char line[320];
      std::snprintf(line,
                    sizeof(line),
                    "  %-20s %6lld (%lld) %8s %6lld (%lld) %8s %18s %5s %8zu / %-6lld %21s %6s\n",
                    site.regions[r].name.c_str(),
                    static_cast<long long>(rc.entries),
                    static_cast<long long>(rc.gt_entries),
                    CountError(rc.entries, rc.gt_entries).c_str(),
                    static_cast<long long>(rc.exits),
                    static_cast<long long>(rc.gt_exits),
                    CountError(rc.exits, rc.gt_exits).c_str(),
                    Percent(rc.occupancy_frames_equal, rc.occupancy_frames).c_str(),
                    rc.occupancy_frames > 0
                        ? Fixed(static_cast<double>(rc.occupancy_abs_error_sum) /
                                    static_cast<double>(rc.occupancy_frames),
                                2)
                              .c_str()
                        : "n/a",
                    rc.dwell_errors_s.size(),
                    static_cast<long long>(rc.gt_visits),
                    Fixed(analytics::Quantile(rc.dwell_errors_s, 0.5), 2).c_str(),
                    Fixed(analytics::Quantile(rc.dwell_errors_s, 0.95), 2).c_str());
      std::cout << line;
    }
    for (std::size_t l = 0; l < site.lines.size(); ++l) {
      const analytics::LineComparison& lc = c.lines[l];
      doc["lines"][l]["gt_left_to_right"] = lc.gt_left_to_right;
      doc["lines"][l]["gt_right_to_left"] = lc.gt_right_to_left;
      std::cout << "  line " << site.lines[l].name << ": left_to_right " << lc.left_to_right << " ("
                << lc.gt_left_to_right << ") error "
                << CountError(lc.left_to_right, lc.gt_left_to_right) << " %, right_to_left "
                << lc.right_to_left << " (" << lc.gt_right_to_left << ") error "
                << CountError(lc.right_to_left, lc.gt_right_to_left) << " %\n";
    }
  }

  if (args.Has("json")) {
    try {
      WriteFile(args.Get("json"), json::Dump(doc, 2) + "\n");
    } catch (const std::exception& e) {
      std::cerr << "mvtrack analytics: " << e.what() << "\n";
      return 1;
    }
  }
  if (args.Has("out")) {
    const std::filesystem::path dir = args.Get("out");
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
      std::cerr << "mvtrack analytics: cannot create " << dir.string() << ": " << ec.message()
                << "\n";
      return 1;
    }
    try {
      WriteCsv(dir, site, result);
    } catch (const std::exception& e) {
      std::cerr << "mvtrack analytics: " << e.what() << "\n";
      return 1;
    }
    progress("wrote visits.csv, crossings.csv and summary.csv in " + dir.string());
    if (plots != nullptr && args.Has("plots")) {
      try {
        plots(dir.string(), site, messages, result);
      } catch (const std::exception& e) {
        std::cerr << "mvtrack analytics: " << e.what() << "\n";
        return 1;
      }
      progress("wrote occupancy.png, dwell.png and heatmap.png in " + dir.string());
    }
  }
  return 0;
}

}  // namespace mvtrack::cli
