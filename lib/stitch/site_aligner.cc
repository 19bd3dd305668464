#include "stitch/site_aligner.h"

#include <algorithm>
#include <string>
#include <utility>

#include "core/check.h"

namespace mvtrack::stitch {

bool AlignerOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (tolerance_us <= 0) return fail("tolerance_us must be > 0");
  if (wait_us < 0) return fail("wait_us must be >= 0");
  if (stale_after_us <= 0) return fail("stale_after_us must be > 0");
  if (max_pending < 1) return fail("max_pending must be >= 1");
  return true;
}

SiteAligner::SiteAligner(int num_zones, const AlignerOptions& options)
    : options_(options),
      pending_(static_cast<std::size_t>(std::max(num_zones, 0))),
      inputs_(static_cast<std::size_t>(std::max(num_zones, 0))) {
  MVTRACK_CHECK(num_zones >= 1);
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
}

void SiteAligner::UpdateStale(std::int64_t now_us) {
  MVTRACK_CHECK_MSG(!start_us_ || now_us >= now_us_, "the aligner's clock went back");
  if (!start_us_) start_us_ = now_us;
  now_us_ = now_us;
  for (std::size_t z = 0; z < inputs_.size(); ++z) {
    inputs_[z].stale = Stale(static_cast<int>(z), now_us);
  }
}

bool SiteAligner::Stale(int zone, std::int64_t now_us) const {
  MVTRACK_CHECK(zone >= 0 && zone < static_cast<int>(inputs_.size()));
  const ZoneInput& in = inputs_[static_cast<std::size_t>(zone)];
  // A zone not heard from yet is waited for as long as a silent one.
  const std::int64_t since = in.frames == 0 ? start_us_.value_or(now_us) : in.last_arrival_us;
  return now_us - since >= options_.stale_after_us;
}

void SiteAligner::Push(int zone, tracker::Frame3D frame, std::int64_t now_us) {
  MVTRACK_CHECK(zone >= 0 && zone < static_cast<int>(pending_.size()));
  UpdateStale(now_us);
  ZoneInput& in = inputs_[static_cast<std::size_t>(zone)];
  std::deque<Pending>& queue = pending_[static_cast<std::size_t>(zone)];
  const bool out_of_order = in.frames > 0 && frame.utime <= in.last_utime;
  const bool released = released_ && frame.utime < *released_ + options_.tolerance_us;
  ++in.frames;
  in.last_arrival_us = now_us;
  in.stale = false;
  if (out_of_order || released) {
    ++in.late;
    return;
  }
  in.last_utime = frame.utime;
  in.latency_us = now_us - frame.utime;
  if (static_cast<int>(queue.size()) >= options_.max_pending) {
    queue.pop_front();
    ++in.late;
  }
  queue.push_back({std::move(frame), now_us});
}

std::vector<ZoneFrameGroup> SiteAligner::Pop(std::int64_t now_us,
                                             bool flush,
                                             std::vector<std::int64_t>* waits) {
  UpdateStale(now_us);
  std::vector<ZoneFrameGroup> out;
  const std::size_t n = pending_.size();
  while (true) {
    std::optional<Utime> open;
    for (const std::deque<Pending>& q : pending_) {
      if (!q.empty() && (!open || q.front().frame.utime < *open)) open = q.front().frame.utime;
    }
    if (!open) break;
    std::vector<bool> member(n, false);
    std::int64_t first_arrival = now_us;
    for (std::size_t z = 0; z < n; ++z) {
      const std::deque<Pending>& q = pending_[z];
      if (!q.empty() && q.front().frame.utime - *open < options_.tolerance_us) {
        member[z] = true;
        first_arrival = std::min(first_arrival, q.front().arrival_us);
      }
    }
    bool ready = flush || now_us - first_arrival >= options_.wait_us;
    if (!ready) {
      ready = true;
      for (std::size_t z = 0; z < n && ready; ++z) {
        // A live zone that delivered nothing at this capture time yet, nor anything later.
        if (!member[z] && !inputs_[z].stale && inputs_[z].last_utime < *open) ready = false;
      }
    }
    if (!ready) break;
    ZoneFrameGroup group(n);
    for (std::size_t z = 0; z < n; ++z) {
      if (!member[z]) continue;
      group[z] = std::move(pending_[z].front().frame);
      pending_[z].pop_front();
    }
    released_ = *open;
    if (waits != nullptr) waits->push_back(now_us - first_arrival);
    out.push_back(std::move(group));
  }
  return out;
}

}  // namespace mvtrack::stitch
