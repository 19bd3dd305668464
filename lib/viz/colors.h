#pragma once
/// @file
/// Colours of mvtrack's pictures (OpenCV BGR). A track's colour is a function of its id alone, so
/// it is the same in every frame, panel and picture. Stateless functions.

#include <opencv2/core.hpp>

#include "core/types.h"

namespace mvtrack::viz {

/// The colour of track `id`: hue = frac(id * φ⁻¹) of the colour circle (φ⁻¹ = 0.618..., the
/// golden-ratio sequence spreads consecutive ids far apart; ids are taken modulo 1000003),
/// saturation 0.85, value 1. The same id always gives the same colour; any 10 consecutive ids
/// have hues at least 20° apart.
cv::Scalar TrackColor(TrackId3D id);

/// HSV to BGR: hue in degrees [0, 360), saturation and value in [0, 1] (clamped); channels 0-255.
cv::Scalar HsvToBgr(double hue_deg, double saturation, double value);

/// `color` mixed with `background`: (1 - amount) * color + amount * background, amount in [0, 1].
cv::Scalar Fade(const cv::Scalar& color, const cv::Scalar& background, double amount);

/// Background of the floor view and of panels without an image.
inline const cv::Scalar kBackground{32, 32, 32};
/// Floor grid lines.
inline const cv::Scalar kGridColor{64, 64, 64};
/// Cameras (centre marker, field of view outline) and labels.
inline const cv::Scalar kCameraColor{220, 200, 160};
/// 2D detections drawn under the reprojected tracks.
inline const cv::Scalar kDetectionColor{170, 170, 170};
/// Text.
inline const cv::Scalar kTextColor{235, 235, 235};

}  // namespace mvtrack::viz
