#include "core/detection.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "core/check.h"

namespace mvtrack::core {
namespace {

// Outcomes (the text of docs for each verdict lives in docs/DECISIONS.md, "Detection
// validation"):
//  kRejected          the first failed check, in this order: unknown layout id; non-finite box;
//                     non-positive width/height; box smaller than min_box_size_px; box sticking
//                     out of the image by more than the margin; visible part of the box thinner
//                     than min_box_size_px; score non-finite or outside [0, 1]; more keypoints
//                     than max_keypoints; keypoint count != layout joint count (non-empty
//                     keypoints only).
//  kAcceptedRepaired  at least one keypoint was invalidated (confidence set to 0): non-finite
//                     position (also moved to the box centre), non-finite or out-of-range
//                     confidence, or position outside the image plus margin; or the embedding
//                     was dropped (longer than max_embedding_size, a non-finite value): the
//                     box and keypoints are still good.
//  kAccepted          nothing to do; `reason` is empty.

DetectionCheck Rejected(std::string reason) {
  return DetectionCheck{DetectionVerdict::kRejected, std::move(reason)};
}

// kNone or one of AllKeypointLayouts(), without building that list (this runs per detection).
bool IsKnownLayout(KeypointLayoutId id) {
  switch (id) {
    case KeypointLayoutId::kNone:
    case KeypointLayoutId::kCoco17:
    case KeypointLayoutId::kBody25:
    case KeypointLayoutId::kShelf14:
    case KeypointLayoutId::kPanoptic19:
      return true;
  }
  return false;
}

// The region in which boxes and keypoints may lie: the image grown by the margin on every side.
struct AllowedRegion {
  double x_lo = 0.0;
  double y_lo = 0.0;
  double x_hi = 0.0;
  double y_hi = 0.0;

  bool Contains(const Vec2& p) const {
    return p.x() >= x_lo && p.x() <= x_hi && p.y() >= y_lo && p.y() <= y_hi;
  }
};

AllowedRegion MakeAllowedRegion(const DetectionLimits& limits) {
  const double w = static_cast<double>(limits.image_width_px);
  const double h = static_cast<double>(limits.image_height_px);
  const double mx = limits.box_margin_fraction * w;
  const double my = limits.box_margin_fraction * h;
  return AllowedRegion{-mx, -my, w + mx, h + my};
}

void AppendCount(std::string* out, int count, const char* what) {
  if (count == 0) return;
  if (out->back() != ':') out->append(",");
  out->append(" ");
  out->append(std::to_string(count));
  out->append(" ");
  out->append(what);
}

}  // namespace

bool DetectionLimits::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = std::string("detection limits: ") + reason;
    return false;
  };
  if (image_width_px < 0) return fail("image_width_px must be >= 0");
  if (image_height_px < 0) return fail("image_height_px must be >= 0");
  if (!(std::isfinite(box_margin_fraction) && box_margin_fraction >= 0.0)) {
    return fail("box_margin_fraction must be finite and >= 0");
  }
  if (!(std::isfinite(min_box_size_px) && min_box_size_px > 0.0)) {
    return fail("min_box_size_px must be finite and > 0");
  }
  if (max_keypoints < 0) return fail("max_keypoints must be >= 0");
  if (max_embedding_size < 0) return fail("max_embedding_size must be >= 0");
  return true;
}

DetectionCheck ValidateDetection(Detection2D* detection, const DetectionLimits& limits) {
  MVTRACK_CHECK(detection != nullptr);
  Detection2D& d = *detection;

  if (!IsKnownLayout(d.layout)) {
    return Rejected("unknown keypoint layout id " + std::to_string(static_cast<int>(d.layout)));
  }

  // --- Box. ---------------------------------------------------------------------------------
  const BoxPx& box = d.box;
  if (!std::isfinite(box.x_min) || !std::isfinite(box.y_min) || !std::isfinite(box.x_max) ||
      !std::isfinite(box.y_max)) {
    return Rejected("box has a non-finite coordinate");
  }
  if (!(box.width() > 0.0) || !(box.height() > 0.0)) {
    return Rejected("box has non-positive width or height");
  }
  if (box.width() < limits.min_box_size_px || box.height() < limits.min_box_size_px) {
    return Rejected("box is smaller than min_box_size_px");
  }
  const bool image_known = limits.image_width_px > 0 && limits.image_height_px > 0;
  const AllowedRegion region = MakeAllowedRegion(limits);
  if (image_known) {
    if (box.x_min < region.x_lo || box.y_min < region.y_lo || box.x_max > region.x_hi ||
        box.y_max > region.y_hi) {
      return Rejected("box sticks out of the image by more than box_margin_fraction");
    }
    const double visible_w =
        std::min(box.x_max, static_cast<double>(limits.image_width_px)) - std::max(box.x_min, 0.0);
    const double visible_h =
        std::min(box.y_max, static_cast<double>(limits.image_height_px)) - std::max(box.y_min, 0.0);
    if (visible_w < limits.min_box_size_px || visible_h < limits.min_box_size_px) {
      return Rejected("box is (almost) entirely outside the image");
    }
  }

  // --- Score. -------------------------------------------------------------------------------
  if (!std::isfinite(d.score) || d.score < 0.0 || d.score > 1.0) {
    return Rejected("score is non-finite or outside [0, 1]");
  }

  // --- Keypoint count. ----------------------------------------------------------------------
  const std::size_t num_keypoints = d.keypoints.size();
  if (num_keypoints > 0 && (limits.max_keypoints < 0 ||
                            num_keypoints > static_cast<std::size_t>(limits.max_keypoints))) {
    return Rejected(std::to_string(num_keypoints) + " keypoints exceed max_keypoints");
  }
  if (num_keypoints > 0) {
    const KeypointLayout& layout = GetKeypointLayout(d.layout);
    if (num_keypoints != layout.joints.size()) {
      return Rejected(std::to_string(num_keypoints) + " keypoints do not match layout '" +
                      layout.name + "' (" + std::to_string(layout.joints.size()) + " joints)");
    }
  }

  // --- Embedding (dropped, the detection is kept). -------------------------------------------
  std::string embedding_problem;
  if (!d.embedding.empty() &&
      (limits.max_embedding_size < 0 ||
       d.embedding.size() > static_cast<std::size_t>(limits.max_embedding_size))) {
    embedding_problem =
        "embedding of size " + std::to_string(d.embedding.size()) + " exceeds max_embedding_size";
  } else if (std::any_of(d.embedding.begin(), d.embedding.end(), [](float v) {
               return !std::isfinite(v);
             })) {
    embedding_problem = "embedding has a non-finite value";
  }
  if (!embedding_problem.empty()) {
    d.embedding.clear();
    d.embedding.shrink_to_fit();
    d.embedding_model.clear();
  }

  // --- Keypoint repairs (the detection is kept). ----------------------------------------------
  int non_finite_position = 0;
  int bad_confidence = 0;
  int outside_image = 0;
  for (Keypoint2D& kp : d.keypoints) {
    if (!std::isfinite(kp.position_px.x()) || !std::isfinite(kp.position_px.y())) {
      // Keep every number finite downstream even though the point is never used.
      kp.position_px = box.center();
      kp.confidence = 0.0;
      ++non_finite_position;
      continue;
    }
    if (!std::isfinite(kp.confidence) || kp.confidence < 0.0 || kp.confidence > 1.0) {
      kp.confidence = 0.0;
      ++bad_confidence;
      continue;
    }
    if (image_known && kp.confidence > 0.0 && !region.Contains(kp.position_px)) {
      kp.confidence = 0.0;
      ++outside_image;
    }
  }
  if (non_finite_position + bad_confidence + outside_image == 0) {
    if (!embedding_problem.empty()) {
      return DetectionCheck{
          DetectionVerdict::kAcceptedRepaired, "embedding dropped: " + embedding_problem, true};
    }
    return DetectionCheck{DetectionVerdict::kAccepted, std::string()};
  }
  std::string reason = "invalidated keypoints:";
  AppendCount(&reason, non_finite_position, "with non-finite position");
  AppendCount(&reason, bad_confidence, "with confidence non-finite or outside [0, 1]");
  AppendCount(&reason, outside_image, "outside the image margin");
  if (!embedding_problem.empty()) reason += "; embedding dropped: " + embedding_problem;
  return DetectionCheck{
      DetectionVerdict::kAcceptedRepaired, std::move(reason), !embedding_problem.empty()};
}

}  // namespace mvtrack::core
