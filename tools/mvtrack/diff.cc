// mvtrack diff: compares two track outputs (canonical JSONL or LCM tracks logs) frame by frame,
// exactly (canonical JSON lines) or within a distance tolerance.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "eval/layer_agreement.h"
#include "formats/tracks_io.h"
#include "mvtrack/cli.h"

namespace mvtrack::cli {
namespace {

// Frame indices listed in the summary per category.
constexpr std::size_t kMaxListedFrames = 10;

std::string Metres(double d) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6g m", d);
  return buf;
}

bool Finite(const Vec3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

// Compares two points (a non-finite point is JSON null); returns their distance, +inf when only
// one of them is null, 0 when both are.
double PointDistance(const Vec3& a, const Vec3& b) {
  const bool fa = Finite(a);
  const bool fb = Finite(b);
  if (fa != fb) return std::numeric_limits<double>::infinity();
  return fa ? (a - b).norm() : 0.0;
}

double JointDistance(const std::optional<Vec3>& a, const std::optional<Vec3>& b) {
  if (a.has_value() != b.has_value()) return std::numeric_limits<double>::infinity();
  return a ? PointDistance(*a, *b) : 0.0;
}

std::string IdList(const tracker::Frame3D& f) {
  std::string s = "[";
  for (std::size_t i = 0; i < f.tracks.size(); ++i) {
    s += (i ? ", " : "") + std::to_string(f.tracks[i].id);
  }
  return s + "]";
}

// The result of comparing one frame present in both files.
struct FrameComparison {
  bool equal = true;
  std::string what;  // the first difference, when not equal
  // Largest point distance between corresponding points (positions and joints present on both
  // sides), when the frames have the same track ids and joint counts; nullopt otherwise.
  std::optional<double> max_distance;
};

// Structural comparison (utime, layout, ids, joint counts, null-ness) and point distances;
// `equal` applies `tolerance` to the distances.
FrameComparison CompareFrames(const tracker::Frame3D& a,
                              core::KeypointLayoutId layout_a,
                              const tracker::Frame3D& b,
                              core::KeypointLayoutId layout_b,
                              double tolerance) {
  FrameComparison c;
  auto differ = [&c](const std::string& what) {
    if (c.equal) c.what = what;
    c.equal = false;
  };
  if (a.utime != b.utime) {
    differ("utime " + std::to_string(a.utime) + " vs " + std::to_string(b.utime));
  }
  if (layout_a != layout_b)
    differ("layout " + formats::LayoutName(layout_a) + " vs " + formats::LayoutName(layout_b));
  if (a.tracks.size() != b.tracks.size() ||
      !std::equal(
          a.tracks.begin(),
          a.tracks.end(),
          b.tracks.begin(),
          [](const tracker::Track3D& x, const tracker::Track3D& y) { return x.id == y.id; })) {
    differ("track ids " + IdList(a) + " vs " + IdList(b));
    return c;
  }
  double max_d = 0.0;
  bool comparable = true;
  for (std::size_t i = 0; i < a.tracks.size(); ++i) {
    const tracker::Track3D& ta = a.tracks[i];
    const tracker::Track3D& tb = b.tracks[i];
    const std::string track = "track " + std::to_string(ta.id);
    const double dp = PointDistance(ta.position, tb.position);
    if (std::isinf(dp)) {
      differ(track + ": position is null on one side only");
    } else {
      max_d = std::max(max_d, dp);
      if (dp > tolerance) differ(track + ": position differs by " + Metres(dp));
    }
    if (ta.joints.size() != tb.joints.size()) {
      differ(track + ": " + std::to_string(ta.joints.size()) + " vs " +
             std::to_string(tb.joints.size()) + " joints");
      comparable = false;
      continue;
    }
    for (std::size_t j = 0; j < ta.joints.size(); ++j) {
      const double dj = JointDistance(ta.joints[j], tb.joints[j]);
      const std::string joint = track + ": joint " + std::to_string(j);
      if (std::isinf(dj)) {
        differ(joint + " is null on one side only");
      } else {
        max_d = std::max(max_d, dj);
        if (dj > tolerance) differ(joint + " differs by " + Metres(dj));
      }
    }
  }
  if (comparable) c.max_distance = max_d;
  return c;
}

std::string FrameList(const std::vector<FrameIndex>& frames) {
  std::string s;
  for (std::size_t i = 0; i < frames.size() && i < kMaxListedFrames; ++i) {
    s += (i ? ", " : "") + std::to_string(frames[i]);
  }
  if (frames.size() > kMaxListedFrames) s += ", ...";
  return s;
}

std::string Source(const formats::TrackFile& f, const formats::TrackFileFrame& frame) {
  return (f.format == formats::TrackFileFormat::kJsonl ? "line " : "event ") +
         std::to_string(frame.source);
}

// --layers: B is a provisional layer of the run whose final output is A.
int CompareLayerFiles(const formats::TrackFile& a, const formats::TrackFile& b) {
  const eval::LayerAgreement g = eval::CompareLayers(FootprintSequence(a), FootprintSequence(b));
  std::cout << "A (final): " << a.Describe() << "\n";
  std::cout << "B (provisional): " << b.Describe() << "\n";
  std::cout << "track-frames: " << g.provisional_track_frames << " in B, " << g.final_track_frames
            << " in A\n";
  std::cout << "B's ids that A has at the same frame: " << g.same_id << " of "
            << g.provisional_track_frames << " (" << Fixed(100.0 * g.same_id_fraction(), 2)
            << " %)\n";
  std::cout << "A's track-frames B has under the same id: " << g.final_covered << " of "
            << g.final_track_frames << " (" << Fixed(100.0 * g.coverage(), 2) << " %)\n";
  if (g.same_id > 0) {
    std::cout << "footprint distance over those: median " << Fixed(g.median_distance_m, 3)
              << " m, p90 " << Fixed(g.p90_distance_m, 3) << " m, max "
              << Fixed(g.max_distance_m, 3) << " m\n";
  }
  return 0;
}

}  // namespace

int RunDiff(int argc, char** argv) {
  Args args;
  args.Positional("A", "first track output (canonical JSONL or LCM tracks log)")
      .Positional("B", "second track output (canonical JSONL or LCM tracks log)")
      .Option("tolerance",
              "metres: 0 compares the canonical JSON lines byte for byte; > 0 lets every "
              "position and joint differ by up to this distance (utime, layout, track ids and "
              "missing joints must still agree)",
              "0")
      .Flag("layers",
            "B is the provisional layer of the run whose final output is A (mvtrack replay "
            "--jsonl A --provisional-jsonl B): report how many of B's track-frames carry an id "
            "A has at that frame, how many of A's B covers, and how far apart the footprints are");
  if (!args.Parse(
          argc,
          argv,
          "mvtrack diff A B [--tolerance M | --layers]",
          "Compares two track outputs frame by frame (frames are matched by frame index;\n"
          "either file may be canonical tracks JSONL or an LCM log of tracks3d_t). Prints\n"
          "the first differing frame with both canonical lines, what differs in it, and a\n"
          "summary: frames only in A, only in B, differing frames, and the largest\n"
          "distance between corresponding points (to choose a tolerance). Note that an\n"
          "LCM log stores floats, so a log and a JSONL file of the same run can differ in\n"
          "the last (0.1 mm) digit: compare them with a tolerance such as 0.001.\n\n"
          "With --layers it measures instead how a provisional layer agrees with its final\n"
          "output (exit 0 after the report).\n\n"
          "Exit status: 0 identical (within the tolerance), 1 different, 2 usage error or\n"
          "unreadable input.")) {
    return 0;
  }
  const double tolerance = args.GetDouble("tolerance");
  if (tolerance < 0.0) throw UsageError("--tolerance must be >= 0 (metres)");

  formats::TrackFile a;
  formats::TrackFile b;
  try {
    a = formats::ReadTrackFile(args.Get("A"));
    b = formats::ReadTrackFile(args.Get("B"));
  } catch (const formats::TrackFileError& e) {
    std::cerr << "mvtrack diff: " << e.what() << "\n";
    return 2;
  }
  if (args.Has("layers")) {
    if (args.Has("tolerance")) throw UsageError("--layers and --tolerance exclude each other");
    return CompareLayerFiles(a, b);
  }

  std::map<FrameIndex, const formats::TrackFileFrame*> in_a;
  std::map<FrameIndex, const formats::TrackFileFrame*> in_b;
  for (const formats::TrackFileFrame& f : a.frames) in_a[f.frame.frame] = &f;
  for (const formats::TrackFileFrame& f : b.frames) in_b[f.frame.frame] = &f;
  std::vector<FrameIndex> all;
  all.reserve(in_a.size() + in_b.size());
  for (const auto& [frame, f] : in_a) all.push_back(frame);
  for (const auto& [frame, f] : in_b) {
    if (!in_a.count(frame)) all.push_back(frame);
  }
  std::sort(all.begin(), all.end());

  const core::KeypointLayoutId layout_a = a.layout.value_or(core::KeypointLayoutId::kNone);
  const core::KeypointLayoutId layout_b = b.layout.value_or(core::KeypointLayoutId::kNone);
  std::vector<FrameIndex> only_a, only_b, differing;
  std::optional<double> max_distance;
  bool printed_first = false;
  for (FrameIndex frame : all) {
    const auto ia = in_a.find(frame);
    const auto ib = in_b.find(frame);
    const formats::TrackFileFrame* fa = ia == in_a.end() ? nullptr : ia->second;
    const formats::TrackFileFrame* fb = ib == in_b.end() ? nullptr : ib->second;
    std::string what;
    if (!fa) {
      only_b.push_back(frame);
      what = "only in B";
    } else if (!fb) {
      only_a.push_back(frame);
      what = "only in A";
    } else {
      const FrameComparison c = CompareFrames(fa->frame, layout_a, fb->frame, layout_b, tolerance);
      if (c.max_distance) max_distance = std::max(max_distance.value_or(0.0), *c.max_distance);
      const bool equal = tolerance == 0.0 ? fa->canonical_line == fb->canonical_line : c.equal;
      if (equal) continue;
      differing.push_back(frame);
      what = c.equal ? "the canonical lines differ" : c.what;
    }
    if (!printed_first) {
      printed_first = true;
      std::cout << "first difference: frame " << frame << ": " << what << "\n";
      std::cout << "  A " << (fa ? Source(a, *fa) : std::string("-")) << ": "
                << (fa ? fa->canonical_line : std::string("(no such frame)\n"));
      std::cout << "  B " << (fb ? Source(b, *fb) : std::string("-")) << ": "
                << (fb ? fb->canonical_line : std::string("(no such frame)\n"));
    }
  }

  std::cout << "A: " << a.Describe() << "\n";
  std::cout << "B: " << b.Describe() << "\n";
  if (a.layout && b.layout && *a.layout != *b.layout) {
    std::cout << "layouts differ: A " << formats::LayoutName(*a.layout) << ", B "
              << formats::LayoutName(*b.layout) << "\n";
  }
  const std::size_t common = in_a.size() - only_a.size();
  std::cout << "frames: " << common << " in both, " << only_a.size() << " only in A"
            << (only_a.empty() ? "" : " (" + FrameList(only_a) + ")") << ", " << only_b.size()
            << " only in B" << (only_b.empty() ? "" : " (" + FrameList(only_b) + ")") << "; "
            << differing.size() << " differing"
            << (differing.empty() ? "" : " (" + FrameList(differing) + ")") << "\n";
  if (max_distance) {
    std::cout << "largest distance between corresponding points: " << Metres(*max_distance) << "\n";
  }
  const bool identical = only_a.empty() && only_b.empty() && differing.empty();
  std::cout << (identical ? "identical" : "DIFFERENT")
            << (tolerance == 0.0 ? " (canonical lines, byte for byte)"
                                 : " (tolerance " + Metres(tolerance) + ")")
            << "\n";
  return identical ? 0 : 1;
}

}  // namespace mvtrack::cli
