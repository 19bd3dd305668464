#include "tracking2d/box_iou.h"

#include <algorithm>
#include <cmath>

namespace mvtrack::tracking2d {

bool IsUsableBox(const core::BoxPx& box) {
  return std::isfinite(box.x_min) && std::isfinite(box.y_min) && std::isfinite(box.x_max) &&
         std::isfinite(box.y_max) && box.width() > 0.0 && box.height() > 0.0;
}

double BoxIou(const core::BoxPx& a, const core::BoxPx& b) {
  if (!IsUsableBox(a) || !IsUsableBox(b)) return 0.0;
  return BoxIouOfUsable(a, b);
}

double BoxIouOfUsable(const core::BoxPx& a, const core::BoxPx& b) {
  const double inter_w = std::min(a.x_max, b.x_max) - std::max(a.x_min, b.x_min);
  const double inter_h = std::min(a.y_max, b.y_max) - std::max(a.y_min, b.y_min);
  if (inter_w <= 0.0 || inter_h <= 0.0) return 0.0;
  const double inter = inter_w * inter_h;
  const double uni = a.width() * a.height() + b.width() * b.height() - inter;
  if (!(uni > 0.0)) return 0.0;
  return std::clamp(inter / uni, 0.0, 1.0);
}

}  // namespace mvtrack::tracking2d
