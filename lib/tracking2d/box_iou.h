#pragma once
/// @file
/// Intersection over union of axis-aligned pixel boxes (SORT's association affinity).
/// Stateless.

#include "core/detection.h"

namespace mvtrack::tracking2d {

/// Intersection-over-union of two boxes in [0, 1], computed on continuous coordinates (no
/// "+1 pixel" convention, as in SORT's iou_batch). Returns 0 when either box is degenerate
/// (non-positive width or height), non-finite, or when the boxes do not overlap.
double BoxIou(const core::BoxPx& a, const core::BoxPx& b);

/// BoxIou for two boxes that are known to satisfy IsUsableBox (not checked): the same value
/// without the two validity checks, for SORT's cost matrix (tracks x detections per frame).
double BoxIouOfUsable(const core::BoxPx& a, const core::BoxPx& b);

/// True when all coordinates are finite and the width and height are strictly positive: the
/// boxes SortTracker can turn into a Kalman measurement.
bool IsUsableBox(const core::BoxPx& box);

}  // namespace mvtrack::tracking2d
