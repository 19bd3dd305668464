#pragma once
/// @file
/// Live alignment of the zones' frames for the stitcher (issue 43): zone daemons publish their
/// frames when their windows are linked, each on its own schedule, and some may be slow, silent
/// or dead. SiteAligner keeps each zone's frames that arrived and releases a site frame (one
/// capture time, at most one frame per zone) once every live zone has delivered it or the
/// oldest of them has waited `wait_us`; a zone silent for `stale_after_us` (or not heard from in
/// that long since the aligner started) is not waited for (it is stale until it delivers again).
/// Frames of a capture time already released arrive too late and are dropped, counted. Pure: the
/// caller passes its clock; deterministic.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "tracker/types.h"

namespace mvtrack::stitch {

/// SiteAligner settings.
struct AlignerOptions {
  /// Zone frames whose capture times differ by less than this are one site frame, µs (> 0):
  /// half a frame period.
  Utime tolerance_us = 16'666;
  /// Longest wait for a late zone, µs (>= 0), counted from the arrival of the site frame's
  /// first zone frame.
  std::int64_t wait_us = 1'000'000;
  /// A zone that delivered nothing for this long is stale, µs (> 0).
  std::int64_t stale_after_us = 2'000'000;
  /// Frames kept per zone at most (>= 1); beyond, the oldest is dropped (counted as late).
  int max_pending = 4096;
  /// Checks the ranges above; on failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// One zone's input health.
struct ZoneInput {
  std::int64_t frames = 0;           ///< frames received
  std::int64_t late = 0;             ///< frames dropped: their site frame was already released
  std::int64_t last_arrival_us = 0;  ///< caller's clock at the latest frame (0: none yet)
  Utime last_utime = 0;              ///< capture time of the latest frame (0: none yet)
  /// Arrival minus capture time of the latest frame, µs: the zone's output latency as the
  /// stitcher sees it (clocks assumed synchronised).
  std::int64_t latency_us = 0;
  /// Nothing for stale_after_us (a zone not heard from yet: since the aligner's first call).
  bool stale = false;
};

/// A released site frame: per zone its frame, or nothing.
using ZoneFrameGroup = std::vector<std::optional<tracker::Frame3D>>;

/// See the file comment. Single-owner, single-threaded.
class SiteAligner {
 public:
  /// `num_zones` >= 1, `options` valid (checked).
  SiteAligner(int num_zones, const AlignerOptions& options);

  /// Zone `zone` (an index, checked) delivered `frame` at `now_us` (the caller's clock, never
  /// going back; checked). A frame not after the zone's previous one is dropped (late).
  void Push(int zone, tracker::Frame3D frame, std::int64_t now_us);

  /// The site frames ready at `now_us`, oldest first; with `flush`, every frame kept. With
  /// `waits`, also how long each waited: `now_us` minus the arrival of its first zone frame.
  std::vector<ZoneFrameGroup> Pop(std::int64_t now_us,
                                  bool flush = false,
                                  std::vector<std::int64_t>* waits = nullptr);

  /// Zone inputs as of the latest Push or Pop.
  const std::vector<ZoneInput>& zones() const { return inputs_; }

  /// Whether zone `zone` (an index, checked) is stale at `now_us` (ZoneInput::stale computed
  /// for that time instead of the latest call's).
  bool Stale(int zone, std::int64_t now_us) const;

 private:
  struct Pending {
    tracker::Frame3D frame;
    std::int64_t arrival_us = 0;
  };
  void UpdateStale(std::int64_t now_us);

  AlignerOptions options_;
  std::vector<std::deque<Pending>> pending_;  // per zone, increasing utime
  std::vector<ZoneInput> inputs_;
  std::optional<Utime> released_;         // capture time of the latest released site frame
  std::optional<std::int64_t> start_us_;  // the clock at the first call
  std::int64_t now_us_ = 0;
};

}  // namespace mvtrack::stitch
