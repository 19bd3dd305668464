#include "tracking2d/sort_tracker.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>

#include "core/appearance.h"
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
  if (!std::isfinite(motion_buffer) || motion_buffer < 0.0) {
    return fail("motion_buffer must be finite and >= 0");
  }
  if (!std::isfinite(process_noise_scale) || !(process_noise_scale > 0.0)) {
    return fail("process_noise_scale must be finite and > 0");
  }
  return true;
}

namespace {

// `box` grown by `buffer` times its height on every side (SortOptions::motion_buffer).
core::BoxPx Buffered(const core::BoxPx& box, double buffer) {
  const double grow = buffer * box.height();
  return {box.x_min - grow, box.y_min - grow, box.x_max + grow, box.y_max + grow};
}

}  // namespace

SortTracker::SortTracker(SortOptions options) : options_(options) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
}

bool SortAppearance::Validate(std::string* why) const {
  auto fail = [&](const char* msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  if (!std::isfinite(weight) || weight < 0.0 || weight > 1.0)
    return fail("weight must be in [0, 1]");
  if (!std::isfinite(gate) || gate < 0.0 || gate > 2.0) return fail("gate must be in [0, 2]");
  if (gallery_size < 1) return fail("gallery_size must be >= 1");
  return true;
}

void SortTracker::set_appearance(const SortAppearance& appearance) {
  std::string why;
  MVTRACK_CHECK_MSG(appearance.Validate(&why), why.c_str());
  appearance_ = appearance;
}

void SortTracker::RecordSameTrackDistance(double d) {
  if (same_track_distances_.size() < kSameTrackSamples) {
    same_track_distances_.push_back(d);
  } else {
    same_track_distances_[next_sample_] = d;
  }
  next_sample_ = (next_sample_ + 1) % kSameTrackSamples;
}

bool SortTracker::AppearanceReliable() const {
  if (same_track_distances_.size() < kMinSameTrackSamples) return false;
  std::vector<double> d = same_track_distances_;
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid <= 0.5 * appearance_->gate;
}

void SortTracker::AddToGallery(Track* track, const std::vector<float>* embedding) const {
  if (!appearance_ || embedding == nullptr || embedding->empty()) return;
  auto& gallery = track->gallery;
  if (!gallery.empty() && gallery.front().size() != embedding->size()) return;
  if (static_cast<int>(gallery.size()) >= appearance_->gallery_size) gallery.erase(gallery.begin());
  gallery.push_back(*embedding);
}

std::size_t SortTracker::gallery_bytes() const {
  std::size_t bytes = 0;
  for (const Track& t : tracks_) {
    for (const auto& g : t.gallery) bytes += g.size() * sizeof(float);
  }
  return bytes;
}

void SortTracker::set_options(const SortOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  options_ = options;
}

std::vector<TrackedDetection> SortTracker::Update(
    FrameIndex frame,
    const std::vector<core::BoxPx>& boxes,
    const std::vector<const std::vector<float>*>* embeddings) {
  MVTRACK_CHECK(embeddings == nullptr || embeddings->size() == boxes.size());
  const bool use_appearance = appearance_.has_value() && embeddings != nullptr;
  const auto embedding_of = [&](int detection) -> const std::vector<float>* {
    return use_appearance ? (*embeddings)[static_cast<std::size_t>(detection)] : nullptr;
  };
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
    for (FrameIndex s = 0; s < steps; ++s) t.filter.Predict(options_.process_noise_scale);
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
  // The compared detection boxes, buffered once per frame (SortOptions::motion_buffer).
  const double buffer = options_.motion_buffer;
  compared_.clear();
  for (const int d : usable) {
    const core::BoxPx& box = boxes[static_cast<std::size_t>(d)];
    compared_.push_back(buffer > 0.0 ? Buffered(box, buffer) : box);
  }
  if (buffer > 0.0) {
    for (core::BoxPx& box : predicted_) box = Buffered(box, buffer);
  }
  for (Eigen::Index r = 0; r < num_tracks_before; ++r) {
    const core::BoxPx& predicted = predicted_[static_cast<std::size_t>(r)];
    for (Eigen::Index c = 0; c < num_usable; ++c) {
      cost(r, c) = 1.0 - BoxIouOfUsable(predicted, compared_[static_cast<std::size_t>(c)]);
    }
  }
  double max_cost = 1.0 - options_.iou_threshold;
  // Row / column counts of pairs inside the IoU gate (appearance only).
  if (use_appearance) {
    row_feasible_.assign(static_cast<std::size_t>(num_tracks_before), 0);
    col_feasible_.assign(static_cast<std::size_t>(num_usable), 0);
    for (Eigen::Index r = 0; r < num_tracks_before; ++r) {
      for (Eigen::Index c = 0; c < num_usable; ++c) {
        if (cost(r, c) > max_cost) continue;
        ++row_feasible_[static_cast<std::size_t>(r)];
        ++col_feasible_[static_cast<std::size_t>(c)];
      }
    }
  }
  if (use_appearance && AppearanceReliable()) {
    // Where motion is ambiguous (a track with two detections inside its IoU gate, or a
    // detection inside two tracks' gates): the fused cost and the appearance gate. Elsewhere
    // motion alone decides, as in SORT: appearance only arbitrates between candidates, so
    // embeddings too noisy to tell people apart cannot break tracks that motion alone keeps.
    // Forbidden pairs get a cost above every allowed one (allowed costs are <= 2).
    constexpr double kForbidden = 4.0;
    const double w = appearance_->weight;
    for (Eigen::Index r = 0; r < num_tracks_before; ++r) {
      const auto& gallery = tracks_[static_cast<std::size_t>(r)].gallery;
      for (Eigen::Index c = 0; c < num_usable; ++c) {
        const double motion = cost(r, c);
        if (motion > max_cost) {
          cost(r, c) = kForbidden;
          continue;
        }
        if (row_feasible_[static_cast<std::size_t>(r)] < 2 &&
            col_feasible_[static_cast<std::size_t>(c)] < 2) {
          continue;
        }
        const std::vector<float>* e = embedding_of(usable[static_cast<std::size_t>(c)]);
        if (e == nullptr || gallery.empty() || gallery.front().size() != e->size()) continue;
        const double d = core::GalleryDistance(gallery, *e);
        cost(r, c) = d > appearance_->gate ? kForbidden : (1.0 - w) * motion + w * d;
      }
    }
    max_cost = 3.0;
  }
  core::SolveAssignment(cost, max_cost, &assignment_workspace_, &assignment_);
  const core::Assignment& assignment = assignment_;

  std::vector<TrackedDetection> reported;
  reported.reserve(usable.size());

  // 4. Update matched tracks with their detection.
  for (const auto& [row, col] : assignment.matches) {
    Track& t = tracks_[static_cast<std::size_t>(row)];
    const int detection = usable[static_cast<std::size_t>(col)];
    // How far apart one person's embeddings are in this camera: sampled on every 4th frame
    // from continuations motion alone made certain (one candidate on both sides).
    if (use_appearance && frame % 4 == 0 && row_feasible_[static_cast<std::size_t>(row)] == 1 &&
        col_feasible_[static_cast<std::size_t>(col)] == 1) {
      const std::vector<float>* e = embedding_of(detection);
      if (e != nullptr && !t.gallery.empty() && t.gallery.front().size() == e->size()) {
        RecordSameTrackDistance(core::GalleryDistance(t.gallery, *e));
      }
    }
    t.filter.Update(boxes[static_cast<std::size_t>(detection)]);
    t.hit_streak = t.last_matched_frame == previous_frame ? t.hit_streak + 1 : 1;
    t.last_matched_frame = frame;
    if (t.hit_streak >= options_.min_hits) t.confirmed = true;
    if (t.confirmed) reported.push_back({t.id, detection});
    AddToGallery(&t, embedding_of(detection));
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
            options_.min_hits <= 1,
            {}};
    AddToGallery(&t, embedding_of(detection));
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
