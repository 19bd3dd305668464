#include "tracking2d/sort_tracker.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>

#include "core/check.h"
#include "core/linear_assignment.h"
#include "tracking2d/box_iou.h"

namespace mvtrack::tracking2d {

bool SortOptions::Validate(std::string* why) const {
  const auto fail = [why](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (max_age < 0) return fail("max_age must be >= 0");
  if (min_hits < 1) return fail("min_hits must be >= 1");
  if (!std::isfinite(iou_threshold) || iou_threshold <= 0.0 || iou_threshold > 1.0) {
    return fail("iou_threshold must be in (0, 1]");
  }
  return true;
}

SortTracker::SortTracker(SortOptions options) : options_(options) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
}

void SortTracker::set_options(const SortOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  options_ = options;
}

std::vector<TrackedDetection> SortTracker::Update(FrameIndex frame,
                                                  const std::vector<core::BoxPx>& boxes) {
  if (last_frame_.has_value() && frame <= *last_frame_) return {};
  const FrameIndex previous_frame = last_frame_.value_or(frame);
  last_frame_ = frame;

  // 1. Drop tracks that were already dead at this frame: they could have been matched at most
  //    max_age + 1 frames after their last match (only reachable through a frame gap).
  const auto max_age = static_cast<FrameIndex>(options_.max_age);
  std::erase_if(tracks_,
                [&](const Track& t) { return frame - t.last_matched_frame > max_age + 1; });

  // 2. Predict every track to this frame, one constant-velocity step per elapsed frame. The
  //    surviving tracks were matched at most max_age + 1 frames ago, which bounds the steps.
  const FrameIndex steps = frame - previous_frame;
  for (Track& t : tracks_) {
    for (FrameIndex s = 0; s < steps; ++s) t.filter.Predict();
  }
  // SORT removes trackers whose prediction is invalid (NaN); a non-positive area or aspect
  // ratio cannot be compared by IoU either. The survivors' predicted boxes are kept for step 3.
  predicted_.clear();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const std::optional<core::BoxPx> box = tracks_[i].filter.ValidBox();
    if (!box) continue;
    predicted_.push_back(*box);
    if (kept != i) tracks_[kept] = std::move(tracks_[i]);
    ++kept;
  }
  tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(kept), tracks_.end());

  // 3. Associate (SORT Sec. 3.3): cost 1 - IoU between predicted track boxes (rows) and usable
  //    detections (columns); pairs with IoU < iou_threshold are forbidden. Both sides are usable
  //    boxes here (HasValidBox above, IsUsableBox below), so the unchecked IoU applies.
  std::vector<int>& usable = usable_;
  usable.clear();
  for (std::size_t d = 0; d < boxes.size(); ++d) {
    if (IsUsableBox(boxes[d])) usable.push_back(static_cast<int>(d));
  }
  const auto num_tracks_before = static_cast<Eigen::Index>(tracks_.size());
  const auto num_usable = static_cast<Eigen::Index>(usable.size());
  Eigen::MatrixXd& cost = cost_;
  cost.resize(num_tracks_before, num_usable);
  for (Eigen::Index r = 0; r < num_tracks_before; ++r) {
    const core::BoxPx& predicted = predicted_[static_cast<std::size_t>(r)];
    for (Eigen::Index c = 0; c < num_usable; ++c) {
      const auto detection = static_cast<std::size_t>(usable[static_cast<std::size_t>(c)]);
      cost(r, c) = 1.0 - BoxIouOfUsable(predicted, boxes[detection]);
    }
  }
  core::SolveAssignment(cost, 1.0 - options_.iou_threshold, &assignment_workspace_, &assignment_);
  const core::Assignment& assignment = assignment_;

  std::vector<TrackedDetection> reported;
  reported.reserve(usable.size());

  // 4. Update matched tracks with their detection.
  for (const auto& [row, col] : assignment.matches) {
    Track& t = tracks_[static_cast<std::size_t>(row)];
    const int detection = usable[static_cast<std::size_t>(col)];
    t.filter.Update(boxes[static_cast<std::size_t>(detection)]);
    t.hit_streak = t.last_matched_frame == previous_frame ? t.hit_streak + 1 : 1;
    t.last_matched_frame = frame;
    if (t.hit_streak >= options_.min_hits) t.confirmed = true;
    if (t.confirmed) reported.push_back({t.id, detection});
  }

  // 5. Delete tracks unmatched for more than max_age frames: they could not be matched at the
  //    next frame. (Tracks matched above have last_matched_frame == frame and stay.)
  std::erase_if(tracks_, [&](const Track& t) { return frame - t.last_matched_frame > max_age; });

  // 6. Start a track for every unmatched usable detection, in detection order.
  for (const int col : assignment.unmatched_cols) {
    const int detection = usable[static_cast<std::size_t>(col)];
    Track t{next_id_++,
            KalmanBoxTracker(boxes[static_cast<std::size_t>(detection)]),
            frame,
            1,
            options_.min_hits <= 1};
    if (t.confirmed) reported.push_back({t.id, detection});
    tracks_.push_back(std::move(t));
  }

  // Matched tracks are visited in id order and births get larger ids, so `reported` is already
  // sorted; keep the guarantee explicit.
  std::sort(
      reported.begin(), reported.end(), [](const TrackedDetection& a, const TrackedDetection& b) {
        return a.track_id < b.track_id;
      });
  return reported;
}

std::vector<TrackSnapshot> SortTracker::Tracks() const {
  std::vector<TrackSnapshot> out;
  out.reserve(tracks_.size());
  for (const Track& t : tracks_) {
    out.push_back({t.id, t.filter.Box(), t.last_matched_frame, t.confirmed});
  }
  return out;
}

}  // namespace mvtrack::tracking2d
