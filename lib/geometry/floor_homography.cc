#include "geometry/floor_homography.h"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>

namespace mvtrack::geometry {
namespace {

// The check grid: kGridSteps + 1 pixels per side, evenly spaced over [0, width] x [0, height].
constexpr int kGridSteps = 10;
// H is singular when its smallest singular value is below this fraction of its largest.
constexpr double kMinSingularRatio = 1e-12;
// A pixel is on the horizon when |(H p).z| <= kHorizon |H p|.
constexpr double kHorizon = 1e-12;
// The focal length is not determined when both constraints' coefficients of 1/f² are below this
// fraction of the squared image-side norms of H⁻¹'s first two columns (image plane parallel to
// the floor).
constexpr double kMinConstraint = 1e-9;
// A box is cut by the image border when its top is above this row or its bottom below
// height - 1 - kBorderPx.
constexpr double kBorderPx = 1.0;
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// `v` with 6 significant digits.
std::string Num(double v) {
  char buffer[32];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), v, std::chars_format::general, 6);
  return std::string(buffer, r.ptr);
}

std::vector<Vec2> GridPixels(int width_px, int height_px) {
  std::vector<Vec2> pixels;
  pixels.reserve((kGridSteps + 1) * (kGridSteps + 1));
  for (int j = 0; j <= kGridSteps; ++j) {
    for (int i = 0; i <= kGridSteps; ++i) {
      pixels.emplace_back(static_cast<double>(width_px) * i / kGridSteps,
                          static_cast<double>(height_px) * j / kGridSteps);
    }
  }
  return pixels;
}

// The q-quantile (0..1) of ascending `sorted` (non-empty), linear between order statistics.
double Quantile(const std::vector<double>& sorted, double q) {
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = at - static_cast<double>(below);
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

// The (non-negative) field of view from the principal point coordinate `c` to the image edges
// 0 and `size`, degrees.
double FieldOfViewDeg(double c, double size, double f) {
  return (std::atan(c / f) + std::atan((size - c) / f)) * kRadToDeg;
}

// Sum of squared distances between `pixels` and the projections of their floor points
// `points`, with the residuals (x, y per point) when `residuals` is not null; nullopt when a
// point is not in front of the camera.
std::optional<double> GridCost(const CameraModel& cam,
                               const std::vector<Vec2>& pixels,
                               const std::vector<Vec3>& points,
                               Eigen::VectorXd* residuals) {
  if (residuals != nullptr) residuals->resize(static_cast<Eigen::Index>(2 * pixels.size()));
  double cost = 0.0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const std::optional<Vec2> back = cam.ProjectUndistorted(points[i]);
    if (!back.has_value()) return std::nullopt;
    const Vec2 r = *back - pixels[i];
    if (residuals != nullptr) residuals->segment<2>(static_cast<Eigen::Index>(2 * i)) = r;
    cost += r.squaredNorm();
  }
  return cost;
}

// `cam` moved by `delta`: rotation Rodrigues(delta[0..2]) R, translation t + delta[3..5], and
// focal length f + delta[6] when `delta` has 7 entries.
CameraModel Moved(const CameraModel& cam, const Eigen::VectorXd& delta) {
  CameraModel out = cam;
  out.cam_from_world.rotation =
      RotationFromRodrigues(Vec3(delta(0), delta(1), delta(2))) * cam.cam_from_world.rotation;
  out.cam_from_world.translation += Vec3(delta(3), delta(4), delta(5));
  if (delta.size() == 7) {
    out.K(0, 0) += delta(6);
    out.K(1, 1) += delta(6);
  }
  return out;
}

// Levenberg-Marquardt on GridCost over the rotation, the translation and, when `refine_focal`,
// the focal length (forward-difference Jacobian; Zhang 2000, section 3.2). Stops when a step no
// longer lowers the cost by a relative kMinGain, or after kMaxIterations.
void RefineOnGrid(const std::vector<Vec2>& pixels,
                  const std::vector<Vec3>& points,
                  bool refine_focal,
                  CameraModel* cam) {
  constexpr int kMaxIterations = 100;
  constexpr double kMinGain = 1e-12;
  constexpr double kDifferenceStep = 1e-7;  // relative to each parameter's scale
  const Eigen::Index n = refine_focal ? 7 : 6;
  std::optional<double> cost = GridCost(*cam, pixels, points, nullptr);
  if (!cost.has_value()) return;
  double damping = 1e-3;
  Eigen::VectorXd r0;
  Eigen::VectorXd r1;
  for (int iteration = 0; iteration<kMaxIterations&& * cost> 0.0; ++iteration) {
    GridCost(*cam, pixels, points, &r0);
    Eigen::MatrixXd J(r0.size(), n);
    const double t_scale = std::max(1.0, cam->cam_from_world.translation.norm());
    for (Eigen::Index k = 0; k < n; ++k) {
      const double scale = k < 3 ? 1.0 : (k < 6 ? t_scale : cam->K(0, 0));
      const double h = kDifferenceStep * scale;
      Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
      d(k) = h;
      if (!GridCost(Moved(*cam, d), pixels, points, &r1).has_value()) return;
      J.col(k) = (r1 - r0) / h;
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd Jtr = J.transpose() * r0;
    bool improved = false;
    while (damping < 1e10) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += damping * JtJ.diagonal();
      const CameraModel next = Moved(*cam, A.ldlt().solve(-Jtr));
      const std::optional<double> next_cost = GridCost(next, pixels, points, nullptr);
      if (next_cost.has_value() && *next_cost < *cost) {
        improved = (*cost - *next_cost) > kMinGain * *cost;
        *cam = next;
        cost = next_cost;
        damping = std::max(damping / 10.0, 1e-12);
        break;
      }
      damping *= 10.0;
    }
    if (!improved) break;
  }
}

}  // namespace

bool FloorHomographyOptions::Validate(std::string* why) const {
  const auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!std::isfinite(floor_unit_m) || !(floor_unit_m > 0.0)) {
    return fail("floor_unit_m must be finite and > 0, got " + Num(floor_unit_m));
  }
  if (focal_px.has_value() && (!std::isfinite(*focal_px) || !(*focal_px > 0.0))) {
    return fail("the focal length must be finite and > 0 pixels, got " + Num(*focal_px));
  }
  if (principal_point_px.has_value() && !principal_point_px->allFinite()) {
    return fail("the principal point must be finite");
  }
  return true;
}

std::optional<Vec2> ImageToFloor(const Mat3& image_to_floor, const Vec2& pixel) {
  const Vec3 p = image_to_floor * Vec3(pixel.x(), pixel.y(), 1.0);
  if (!(std::abs(p.z()) > kHorizon * p.norm())) return std::nullopt;
  const Vec2 floor = p.head<2>() / p.z();
  if (!floor.allFinite()) return std::nullopt;
  return floor;
}

Vec3 FloorToWorld(const Vec2& floor_point, double floor_unit_m, bool mirrored_y) {
  return floor_unit_m * Vec3(floor_point.x(), mirrored_y ? -floor_point.y() : floor_point.y(), 0.0);
}

FloorHomographyCamera CameraFromFloorHomography(const Mat3& image_to_floor,
                                                CameraId id,
                                                int width_px,
                                                int height_px,
                                                const FloorHomographyOptions& options) {
  FloorHomographyCamera out;
  out.camera.id = id;
  out.camera.width_px = width_px;
  out.camera.height_px = height_px;
  const auto fail = [&out](std::string reason) {
    out.ok = false;
    out.reason = std::move(reason);
    return out;
  };
  std::string why;
  if (!options.Validate(&why)) return fail(why);
  if (width_px <= 0 || height_px <= 0) return fail("the image size must be positive");
  const Mat3& H = image_to_floor;
  if (!H.allFinite()) return fail("the homography has non-finite entries");
  const Eigen::JacobiSVD<Mat3> svd_h(H);
  const Vec3 singular = svd_h.singularValues();
  if (!(singular(0) > 0.0) || !(singular(2) > kMinSingularRatio * singular(0))) {
    return fail("the homography is singular (singular values " + Num(singular(0)) + ", " +
                Num(singular(1)) + ", " + Num(singular(2)) + ")");
  }

  // floor -> image, G = k H⁻¹ with k > 0 (unit Frobenius norm), then relative to the principal
  // point: Gc = [a b c] = k' diag(f, f, 1) [r1 r2 t].
  Mat3 G = H.inverse();
  G /= G.norm();
  const Vec2 pp = options.principal_point_px.value_or(
      Vec2(0.5 * static_cast<double>(width_px), 0.5 * static_cast<double>(height_px)));
  Mat3 shift = Mat3::Identity();
  shift(0, 2) = -pp.x();
  shift(1, 2) = -pp.y();
  const Mat3 Gc = shift * G;
  const Vec3 a = Gc.col(0);
  const Vec3 b = Gc.col(1);

  double f = 0.0;
  if (options.focal_px.has_value()) {
    f = *options.focal_px;
  } else {
    // With w = 1/f²: r1 . r2 = 0 -> w (a1 b1 + a2 b2) + a3 b3 = 0, and |r1|² = |r2|² ->
    // w (a1² + a2² - b1² - b2²) + a3² - b3² = 0; least squares over both.
    const double c1 = a.x() * b.x() + a.y() * b.y();
    const double d1 = a.z() * b.z();
    const double c2 = a.head<2>().squaredNorm() - b.head<2>().squaredNorm();
    const double d2 = a.z() * a.z() - b.z() * b.z();
    const double denom = c1 * c1 + c2 * c2;
    const double scale = a.head<2>().squaredNorm() + b.head<2>().squaredNorm();
    if (!(std::sqrt(denom) > kMinConstraint * scale)) {
      return fail(
          "the homography does not determine the focal length (the image plane is parallel to "
          "the floor): give the focal length");
    }
    const double w = -(c1 * d1 + c2 * d2) / denom;
    if (!(w > 0.0) || !std::isfinite(w)) {
      return fail("the homography's constraints give no positive focal length (1/f^2 = " + Num(w) +
                  "): it is not a pinhole camera with square pixels and this principal point; "
                  "give the focal length");
    }
    f = 1.0 / std::sqrt(w);
    out.focal_estimated = true;
  }
  out.initial_focal_px = f;

  const Vec3 A(a.x() / f, a.y() / f, a.z());
  const Vec3 B(b.x() / f, b.y() / f, b.z());
  const Vec3 T(Gc(0, 2) / f, Gc(1, 2) / f, Gc(2, 2));
  const double norm_a = A.norm();
  const double norm_b = B.norm();
  if (!(norm_a > 0.0) || !(norm_b > 0.0)) return fail("the homography is degenerate");

  // The depth of the floor point of pixel p is lambda k / (H p).z: choose the sign of lambda so
  // that most grid pixels see the floor in front of the camera.
  const std::vector<Vec2> grid = GridPixels(width_px, height_px);
  int positive = 0;
  int negative = 0;
  for (const Vec2& px : grid) {
    const double hz = H.row(2).dot(Vec3(px.x(), px.y(), 1.0));
    if (hz > 0.0) ++positive;
    if (hz < 0.0) ++negative;
  }
  double sign = positive > negative ? 1.0 : -1.0;
  if (positive == negative) {
    const double hz = H.row(2).dot(Vec3(pp.x(), pp.y(), 1.0));
    if (hz == 0.0)
      return fail("the horizon divides the image in two halves: no sign can be chosen");
    sign = hz > 0.0 ? 1.0 : -1.0;
  }
  const double lambda = sign * 2.0 / (norm_a + norm_b);
  const Vec3 r1 = lambda * A;
  const Vec3 r2 = lambda * B;
  const Vec3 t = lambda * T;
  out.orthogonality_residual = std::max(std::abs(r1.dot(r2)), std::abs(r1.norm() - r2.norm()));
  Mat3 R0;
  R0.col(0) = r1;
  R0.col(1) = r2;
  R0.col(2) = r1.cross(r2);
  const Eigen::JacobiSVD<Mat3> svd_r(R0, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 R = svd_r.matrixU() * svd_r.matrixV().transpose();
  const double centre_z = -(R.transpose() * t).z();
  if (!(std::abs(centre_z) > 0.0)) return fail("the camera lies in the floor plane");
  if (centre_z < 0.0) {
    // (x, y) with z towards the camera is left-handed: world = (x, -y, -z_old).
    out.mirrored_y = true;
    R.col(1) *= -1.0;
    R.col(2) *= -1.0;
  }
  geometry::CameraModel& cam = out.camera;
  cam.K << f, 0.0, pp.x(), 0.0, f, pp.y(), 0.0, 0.0, 1.0;
  cam.cam_from_world.rotation = R;
  cam.cam_from_world.translation = options.floor_unit_m * t;
  if (!cam.Validate(&why)) return fail(why);

  // The grid pixels that see the floor in front of the camera, and their floor points.
  std::vector<Vec2> pixels;
  std::vector<Vec3> points;
  for (const Vec2& px : grid) {
    const std::optional<Vec2> floor = ImageToFloor(H, px);
    if (!floor.has_value()) continue;
    const Vec3 world = FloorToWorld(*floor, options.floor_unit_m, out.mirrored_y);
    if (!cam.ProjectUndistorted(world).has_value()) continue;  // above the horizon
    pixels.push_back(px);
    points.push_back(world);
  }
  if (pixels.empty()) return fail("no pixel of the image sees the floor in front of the camera");
  RefineOnGrid(pixels, points, out.focal_estimated, &cam);
  const Eigen::JacobiSVD<Mat3> svd_refined(cam.cam_from_world.rotation,
                                           Eigen::ComputeFullU | Eigen::ComputeFullV);
  cam.cam_from_world.rotation = svd_refined.matrixU() * svd_refined.matrixV().transpose();
  if (!cam.Validate(&why)) return fail(why);
  f = cam.K(0, 0);
  out.focal_px = f;

  out.height_m = cam.CenterInWorld().z();
  out.horizontal_fov_deg = FieldOfViewDeg(pp.x(), static_cast<double>(width_px), f);
  out.vertical_fov_deg = FieldOfViewDeg(pp.y(), static_cast<double>(height_px), f);
  std::vector<double> errors;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const std::optional<Vec2> back = cam.ProjectUndistorted(points[i]);
    if (!back.has_value()) return fail("the refined camera lost sight of the floor");
    errors.push_back((*back - pixels[i]).norm());
  }
  std::sort(errors.begin(), errors.end());
  out.floor_reprojection_median_px = Quantile(errors, 0.5);
  out.floor_reprojection_max_px = errors.back();
  out.floor_check_points = static_cast<int>(errors.size());
  out.ok = true;
  return out;
}

PersonHeightEstimate EstimateFloorUnitFromPersonHeight(const std::vector<PersonBoxes>& cameras,
                                                       double person_height_m) {
  PersonHeightEstimate out;
  for (const PersonBoxes& c : cameras) out.boxes_total += static_cast<int>(c.boxes.size());
  if (!std::isfinite(person_height_m) || !(person_height_m > 0.0)) {
    out.reason = "the person height must be finite and > 0 m, got " + Num(person_height_m);
    return out;
  }
  std::vector<double> heights;
  for (const PersonBoxes& c : cameras) {
    const CameraModel& cam = c.camera;
    const Mat3 world_from_cam_rotation = cam.cam_from_world.rotation.transpose();
    const Mat3 k_inv = cam.K.inverse();
    const Vec3 centre = cam.CenterInWorld();
    const double bottom_limit = static_cast<double>(cam.height_px) - 1.0 - kBorderPx;
    for (const core::BoxPx& box : c.boxes) {
      if (!(box.y_min >= kBorderPx && box.y_max <= bottom_limit && box.y_max > box.y_min)) {
        continue;
      }
      const std::optional<Vec3> feet =
          cam.PointOnRayAtHeight(cam.UndistortPixel(box.bottom_center()), 0.0);
      if (!feet.has_value()) continue;
      const Vec2 head_px = cam.UndistortPixel(box.top_center());
      const Vec3 direction =
          world_from_cam_rotation * (k_inv * Vec3(head_px.x(), head_px.y(), 1.0));
      const double horizontal = direction.head<2>().squaredNorm();
      if (!(horizontal > 1e-12 * direction.squaredNorm())) continue;  // a vertical ray
      const double s = (*feet - centre).head<2>().dot(direction.head<2>()) / horizontal;
      if (!(s > 0.0)) continue;
      const double height = centre.z() + s * direction.z();
      if (!(height > 0.0) || !std::isfinite(height)) continue;
      heights.push_back(height);
    }
  }
  if (heights.empty()) {
    out.reason = "none of the " + std::to_string(out.boxes_total) +
                 " boxes has its top and bottom inside the image and a positive height";
    return out;
  }
  std::sort(heights.begin(), heights.end());
  out.boxes_used = static_cast<int>(heights.size());
  out.median_height = Quantile(heights, 0.5);
  out.p10_height = Quantile(heights, 0.1);
  out.p90_height = Quantile(heights, 0.9);
  out.unit_m = person_height_m / out.median_height;
  out.ok = true;
  return out;
}

}  // namespace mvtrack::geometry
