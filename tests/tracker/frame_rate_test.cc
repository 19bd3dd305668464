// Frame counts at the stream's rate (TrackerOptions::reference_fps, AtFrameRate) and the frame
// period estimate (FramePeriod) they are scaled with.

#include <catch2/catch.hpp>

#include "tracker/frame_period.h"
#include "tracker/options.h"

namespace mvtrack::tracker {
namespace {

TEST_CASE("AtFrameRate: unchanged at the reference rate and faster", "[unit]") {
  const TrackerOptions base;
  for (const double fps : {25.0, 30.0, 60.0}) {
    const TrackerOptions o = AtFrameRate(base, 1.0 / fps);
    CHECK(o.window_size == 30);
    CHECK(o.window_step == 20);
    CHECK(o.min_tracklet_length == 2);
    CHECK(o.sort.max_age == 5);
    CHECK(o.sort.iou_threshold == 0.5);
    CHECK(o.sort.motion_buffer == 0.0);
    CHECK(o.sort.process_noise_scale == 1.0);
    CHECK(o.triangulation.phi == 7);
    CHECK(o.refinement.box_min_duplicate_frames == 3);
    CHECK(o.refinement.smooth_half_window == 5);
  }
  TrackerOptions off = base;
  off.reference_fps = 0.0;
  CHECK(AtFrameRate(off, 0.5).window_size == 30);
  CHECK(AtFrameRate(off, 0.5).sort.iou_threshold == 0.5);
  CHECK(AtFrameRate(off, 0.5).sort.motion_buffer == 0.0);
}

TEST_CASE("AtFrameRate: a slower stream keeps the durations, counts rounded up", "[unit]") {
  const TrackerOptions base;
  // 2 fps: f = 2 / 25 = 0.08. nu = ceil(2.4) = 3, delta = ceil(1.6) = 2, phi = ceil(0.56) = 1,
  // max_age = ceil(0.4) = 1, min_tracklet_length = ceil(0.16) = 1, duplicates ceil(0.24) = 1,
  // min_hits stays 1; the IoU threshold stays 0.5 and the boxes are buffered by 3 m/s x
  // (0.5 - 0.04) s / 1.7 m = 0.8118 box heights.
  const TrackerOptions o = AtFrameRate(base, 0.5);
  CHECK(o.window_size == 3);
  CHECK(o.window_step == 2);
  CHECK(o.triangulation.phi == 1);
  CHECK(o.sort.max_age == 1);
  CHECK(o.sort.min_hits == 1);
  CHECK(o.min_tracklet_length == 1);
  CHECK(o.refinement.box_min_duplicate_frames == 1);
  CHECK(o.refinement.smooth_half_window == 1);  // ceil(0.4)
  CHECK(o.sort.iou_threshold == 0.5);
  CHECK(o.sort.motion_buffer == Approx(3.0 * 0.46 / 1.7));
  CHECK(o.sort.process_noise_scale == Approx(12.5 * 12.5 * 12.5));
  std::string why;
  CHECK(o.Validate(&why));
  // 12.5 fps: f = 0.5 exactly: 15 / 10 frames, phi ceil(3.5) = 4 (no rounding up past exact).
  const TrackerOptions h = AtFrameRate(base, 0.08);
  CHECK(h.window_size == 15);
  CHECK(h.window_step == 10);
  CHECK(h.triangulation.phi == 4);
  CHECK(h.refinement.smooth_half_window == 3);  // ceil(2.5)
  CHECK(SortOptionsAtFrameRate(base, 0.08).max_age == 3);
  CHECK(SortOptionsAtFrameRate(base, 0.08).iou_threshold == 0.5);
  CHECK(SortOptionsAtFrameRate(base, 0.08).motion_buffer == Approx(3.0 * 0.04 / 1.7));
  CHECK(SortOptionsAtFrameRate(base, 0.08).process_noise_scale == Approx(8.0));
  // Minimums: nu >= 2, delta <= nu, phi 0 and max_age 0 stay 0.
  TrackerOptions z = base;
  z.triangulation.phi = 0;
  z.sort.max_age = 0;
  const TrackerOptions slow = AtFrameRate(z, 10.0);  // 0.1 fps
  CHECK(slow.window_size == 2);
  CHECK(slow.window_step == 1);
  CHECK(slow.triangulation.phi == 0);
  CHECK(slow.sort.max_age == 0);
  CHECK(slow.Validate(&why));
}

TEST_CASE("reference_fps is validated", "[unit]") {
  TrackerOptions o;
  std::string why;
  o.reference_fps = -1.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("reference_fps") != std::string::npos);
  o.reference_fps = 0.001;
  CHECK_FALSE(o.Validate(&why));
  o.reference_fps = 0.0;
  CHECK(o.Validate(&why));
}

TEST_CASE("FramePeriod: median of the recent steps, robust to a bad capture time", "[unit]") {
  FramePeriod p;
  CHECK(p.Seconds() == FramePeriod::kDefaultSeconds);
  p.Add(0, 0);
  CHECK(p.Seconds() == FramePeriod::kDefaultSeconds);  // one frame: no step yet
  p.Add(1, 500'000);
  CHECK(p.Seconds() == Approx(0.5));
  // A skipped frame counts as two steps; a capture time that goes back is ignored.
  p.Add(3, 1'500'000);
  p.Add(4, 1'400'000);
  p.Add(5, 2'500'000);
  p.Add(6, 3'000'000);
  // Steps: 0.5, 0.5 (over 2 frames), [negative: ignored], 1.1, 0.5 -> median 0.5.
  CHECK(p.Seconds() == Approx(0.5));
  CHECK(p.size() == 6);
  for (FrameIndex f = 7; f < 100; ++f) p.Add(f, 3'000'000 + (f - 6) * 40'000);
  CHECK(p.size() == FramePeriod::kFrames);
  CHECK(p.Seconds() == Approx(0.04));  // the old 2 fps steps have left the window
  p.Clear();
  CHECK(p.size() == 0);
  CHECK(p.Seconds() == FramePeriod::kDefaultSeconds);
}

}  // namespace
}  // namespace mvtrack::tracker
