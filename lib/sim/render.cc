#include "sim/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/check.h"
#include "core/keypoint_layout.h"
#include "sim/body.h"
#include "sim/random.h"

namespace mvtrack::sim {
namespace {

using internal::DeriveSeed;
using internal::Random;
using internal::Stream;

// COCO-17 indices of the shoulders and hips (body centre = their mean).
constexpr std::array<std::size_t, 4> kTorsoJoints = {5, 6, 11, 12};

bool Overlap(const core::BoxPx& a, const core::BoxPx& b) {
  return a.x_min < b.x_max && b.x_min < a.x_max && a.y_min < b.y_max && b.y_min < a.y_max;
}

double Area(const core::BoxPx& b) { return std::max(0.0, b.width()) * std::max(0.0, b.height()); }

bool Contains(const core::BoxPx& b, const Vec2& p) {
  return p.x() >= b.x_min && p.x() <= b.x_max && p.y() >= b.y_min && p.y() <= b.y_max;
}

core::BoxPx Clip(const core::BoxPx& b, int width_px, int height_px) {
  const double w = width_px, h = height_px;
  return {std::clamp(b.x_min, 0.0, w),
          std::clamp(b.y_min, 0.0, h),
          std::clamp(b.x_max, 0.0, w),
          std::clamp(b.y_max, 0.0, h)};
}

// Makes [lo, hi] at least 1 px long inside [0, limit] around its centre.
void EnsureExtent(double* lo, double* hi, double limit) {
  if (*hi - *lo >= 1.0) return;
  const double c = std::clamp(0.5 * (*lo + *hi), 0.5, limit - 0.5);
  *lo = c - 0.5;
  *hi = c + 0.5;
}

bool InImage(const geometry::CameraModel& camera, const Vec2& p) {
  return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= camera.width_px && p.y() <= camera.height_px;
}

std::uint64_t CameraKey(CameraId id) {
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(id));
}

// Per-person data shared by all cameras of a frame: the box points and a bounding sphere.
struct PersonGeometry {
  std::vector<std::array<double, 3>> box_points;
  std::array<double, 3> centre{};         // body centre (mean of shoulders and hips)
  std::array<double, 3> sphere_centre{};  // bounding sphere of box_points
  double sphere_radius_m = 0.0;
};

PersonGeometry MakePersonGeometry(const PersonTruth& person) {
  MVTRACK_CHECK(person.joints_m.size() == static_cast<std::size_t>(kNumCocoJoints));
  PersonGeometry g;
  for (const Vec3& p : BoxPoints(person)) g.box_points.push_back({p.x(), p.y(), p.z()});
  double cx = 0.0, cy = 0.0, cz = 0.0;
  for (const std::size_t j : kTorsoJoints) {
    cx += person.joints_m[j].x();
    cy += person.joints_m[j].y();
    cz += person.joints_m[j].z();
  }
  const double n = static_cast<double>(kTorsoJoints.size());
  g.centre = {cx / n, cy / n, cz / n};
  std::array<double, 3> lo = g.box_points.front(), hi = lo;
  for (const std::array<double, 3>& p : g.box_points) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  g.sphere_centre = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  g.sphere_radius_m =
      0.5 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
  return g;
}

// Scalar projection (no Eigen temporaries: this is the inner loop of large scenes, and must stay
// fast in debug builds too). Same arithmetic as CameraModel::Project.
class Projector {
 public:
  explicit Projector(const geometry::CameraModel& camera) : camera_(camera) {
    const Mat3& r = camera.cam_from_world.rotation;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r_[3 * i + j] = r(i, j);
      t_[i] = camera.cam_from_world.translation(i);
    }
    fx_ = camera.K(0, 0);
    fy_ = camera.K(1, 1);
    cx_ = camera.K(0, 2);
    cy_ = camera.K(1, 2);
    skew_ = camera.K(0, 1);
    distorted_ = !camera.distortion.IsZero();
    width_ = camera.width_px;
    height_ = camera.height_px;
  }

  // Camera-frame coordinates of a world point.
  std::array<double, 3> ToCamera(const std::array<double, 3>& p) const {
    const double x = p[0], y = p[1], z = p[2];
    return {r_[0] * x + r_[1] * y + r_[2] * z + t_[0],
            r_[3] * x + r_[4] * y + r_[5] * z + t_[1],
            r_[6] * x + r_[7] * y + r_[8] * z + t_[2]};
  }

  // Raw pixel of a camera-frame point with positive depth.
  std::array<double, 2> Pixel(const std::array<double, 3>& c) const {
    const double u = c[0] / c[2], v = c[1] / c[2];
    const double x = fx_ * u + skew_ * v + cx_, y = fy_ * v + cy_;
    if (!distorted_) return {x, y};
    const Vec2 raw = camera_.DistortPixel(Vec2(x, y));
    return {raw.x(), raw.y()};
  }

  bool InImage(const std::array<double, 2>& px) const {
    return px[0] >= 0.0 && px[1] >= 0.0 && px[0] <= width_ && px[1] <= height_;
  }

  // Whether a sphere is certainly outside the image: behind the near plane or beyond one of the
  // four side planes of the viewing frustum. Conservative; never culls with lens distortion
  // (distortion can bend points from outside the frustum into the image).
  bool Culled(const std::array<double, 3>& centre, double radius) const {
    const std::array<double, 3> c = ToCamera(centre);
    if (c[2] + radius < kNearPlaneM) return true;
    if (distorted_ || skew_ != 0.0) return false;
    const double w = camera_.width_px, h = camera_.height_px;
    auto outside = [&](double a, double b, double value) {  // plane a*x + b*z >= 0 (or y)
      return value < -radius * std::hypot(a, b);
    };
    return outside(fx_, cx_, fx_ * c[0] + cx_ * c[2]) ||
           outside(fx_, w - cx_, (w - cx_) * c[2] - fx_ * c[0]) ||
           outside(fy_, cy_, fy_ * c[1] + cy_ * c[2]) ||
           outside(fy_, h - cy_, (h - cy_) * c[2] - fy_ * c[1]);
  }

  const geometry::CameraModel& camera() const { return camera_; }

 private:
  const geometry::CameraModel& camera_;
  double r_[9] = {};
  double t_[3] = {};
  double fx_ = 1.0, fy_ = 1.0, cx_ = 0.0, cy_ = 0.0, skew_ = 0.0;
  bool distorted_ = false;
  double width_ = 0.0, height_ = 0.0;
};

std::optional<PersonProjection> Project(const Projector& projector, const PersonGeometry& g) {
  const geometry::CameraModel& camera = projector.camera();
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  PersonProjection p;
  p.keypoints_px.resize(static_cast<std::size_t>(kNumCocoJoints));
  p.keypoint_in_image.resize(static_cast<std::size_t>(kNumCocoJoints));
  for (std::size_t i = 0; i < g.box_points.size(); ++i) {
    const std::array<double, 3> c = projector.ToCamera(g.box_points[i]);
    if (!(c[2] > kNearPlaneM)) return std::nullopt;
    const std::array<double, 2> px = projector.Pixel(c);
    x_lo = std::min(x_lo, px[0]);
    x_hi = std::max(x_hi, px[0]);
    y_lo = std::min(y_lo, px[1]);
    y_hi = std::max(y_hi, px[1]);
    if (i < static_cast<std::size_t>(kNumCocoJoints)) {
      p.keypoints_px[i] = Vec2(px[0], px[1]);
      p.keypoint_in_image[i] = projector.InImage(px);
    }
  }
  const double pad_x = kBoxPadX * (x_hi - x_lo), pad_y = kBoxPadY * (y_hi - y_lo);
  p.padded_box = {x_lo - pad_x, y_lo - pad_y, x_hi + pad_x, y_hi + pad_y};
  p.clipped_box = Clip(p.padded_box, camera.width_px, camera.height_px);
  p.in_view = projector.InImage({0.5 * (p.padded_box.x_min + p.padded_box.x_max),
                                 0.5 * (p.padded_box.y_min + p.padded_box.y_max)});
  p.depth_m = projector.ToCamera(g.centre)[2];
  return p;
}

// One uniform draw -> confidence in (0.5, 1] (visible) or (0.05, 0.5] (occluded).
double VisibleConfidence(double u) { return 0.5 + 0.5 * (1.0 - u); }
double OccludedConfidence(double u) { return 0.05 + 0.45 * (1.0 - u); }

// A false positive: a box of plausible person size and (with poses) a frontal walking skeleton
// stretched over it.
core::Detection2D FalsePositive(const SceneOptions& o,
                                const geometry::CameraModel& camera,
                                Random* rng) {
  const double img_w = camera.width_px, img_h = camera.height_px;
  const double h = rng->Uniform(0.15, 0.6) * img_h;
  const double w = h * rng->Uniform(0.3, 0.5);
  const double cx = rng->Uniform(0.0, img_w), cy = rng->Uniform(0.0, img_h);
  const core::BoxPx unclipped{cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h};
  core::Detection2D d;
  d.box = Clip(unclipped, camera.width_px, camera.height_px);
  EnsureExtent(&d.box.x_min, &d.box.x_max, img_w);
  EnsureExtent(&d.box.y_min, &d.box.y_max, img_h);
  d.score = rng->Uniform(0.5, 0.8);
  BodyState body;  // facing -y, seen from a camera looking along +y: image x = world x
  body.heading_rad = -0.5 * std::numbers::pi;
  body.walk_phase_rad = rng->Uniform(0.0, 2.0 * std::numbers::pi);
  body.gait_amplitude = rng->Uniform();
  if (!o.poses) return d;
  const auto joints = Coco17Joints(body);
  const std::vector<Vec3> bounds =
      BoxPoints(joints, HeadTop(body), body.heading_rad, body.height_m);
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  for (const Vec3& p : bounds) {
    x_lo = std::min(x_lo, p.x());
    x_hi = std::max(x_hi, p.x());
  }
  const double z_hi = body.height_m;
  d.layout = core::KeypointLayoutId::kCoco17;
  d.keypoints.resize(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const double u = (joints[j].x() - x_lo) / (x_hi - x_lo);
    const double v = 1.0 - joints[j].z() / z_hi;
    const Vec2 clean(unclipped.x_min + u * w, unclipped.y_min + v * h);
    const double nx = rng->Normal(), ny = rng->Normal();
    const double u_conf = rng->Uniform(), u_drop = rng->Uniform();
    core::Keypoint2D& k = d.keypoints[j];
    k.position_px = clean + 0.02 * h * Vec2(nx, ny);
    const bool visible = InImage(camera, clean) && !(u_drop < o.keypoint_dropout);
    k.confidence = visible ? VisibleConfidence(u_conf) : 0.0;
  }
  return d;
}

}  // namespace

std::optional<PersonProjection> ProjectPerson(const geometry::CameraModel& camera,
                                              const PersonTruth& person) {
  return Project(Projector(camera), MakePersonGeometry(person));
}

double CoveredArea(const core::BoxPx& target, const std::vector<core::BoxPx>& rects) {
  std::vector<core::BoxPx> clipped;
  clipped.reserve(rects.size());
  for (const core::BoxPx& r : rects) {
    const core::BoxPx c{std::max(r.x_min, target.x_min),
                        std::max(r.y_min, target.y_min),
                        std::min(r.x_max, target.x_max),
                        std::min(r.y_max, target.y_max)};
    if (c.x_max > c.x_min && c.y_max > c.y_min) clipped.push_back(c);
  }
  if (clipped.empty()) return 0.0;
  std::vector<double> xs;
  xs.reserve(2 * clipped.size());
  for (const core::BoxPx& c : clipped) {
    xs.push_back(c.x_min);
    xs.push_back(c.x_max);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  double area = 0.0;
  std::vector<std::pair<double, double>> spans;
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
    const double x0 = xs[k], x1 = xs[k + 1];
    spans.clear();
    for (const core::BoxPx& c : clipped) {
      if (c.x_min <= x0 && c.x_max >= x1) spans.emplace_back(c.y_min, c.y_max);
    }
    if (spans.empty()) continue;
    std::sort(spans.begin(), spans.end());
    double covered = 0.0, lo = spans[0].first, hi = spans[0].second;
    for (std::size_t s = 1; s < spans.size(); ++s) {
      if (spans[s].first > hi) {
        covered += hi - lo;
        lo = spans[s].first;
        hi = spans[s].second;
      } else {
        hi = std::max(hi, spans[s].second);
      }
    }
    covered += hi - lo;
    area += covered * (x1 - x0);
  }
  return area;
}

namespace {

core::CameraFrame RenderCameraImpl(const SceneOptions& options,
                                   const geometry::CameraModel& camera,
                                   const FrameTruth& truth,
                                   const std::vector<PersonGeometry>& geometry,
                                   std::vector<int>* person_ids) {
  const auto frame_key = static_cast<std::uint64_t>(truth.frame);
  const std::uint64_t camera_key = CameraKey(camera.id);
  Random miss_rng(DeriveSeed(options.seed, Stream::kMiss, frame_key, camera_key));
  Random noise_rng(DeriveSeed(options.seed, Stream::kNoise, frame_key, camera_key));
  Random confidence_rng(DeriveSeed(options.seed, Stream::kConfidence, frame_key, camera_key));
  Random fp_rng(DeriveSeed(options.seed, Stream::kFalsePositive, frame_key, camera_key));
  Random shuffle_rng(DeriveSeed(options.seed, Stream::kShuffle, frame_key, camera_key));
  // Embeddings: a stream of their own, drawn from only when they are on (scenes without them
  // are unchanged).
  const bool embeddings = options.embedding_dim > 0;
  Random embedding_rng(DeriveSeed(options.seed, Stream::kEmbedding, frame_key, camera_key));
  std::vector<double> embedding_noise(static_cast<std::size_t>(options.embedding_dim));
  const Vec3 camera_centre =
      -camera.cam_from_world.rotation.transpose() * camera.cam_from_world.translation;

  core::CameraFrame out;
  out.utime = truth.utime;
  out.frame = truth.frame;
  out.camera_id = camera.id;
  std::vector<int> ids;

  // Clean projections, and everyone who can occlude, nearest first (ties by id).
  const std::size_t n = truth.people.size();
  std::vector<std::optional<PersonProjection>> projections(n);
  std::vector<std::size_t> by_depth;
  const Projector projector(camera);
  for (std::size_t i = 0; i < n; ++i) {
    const PersonGeometry& g = geometry[i];
    if (projector.Culled(g.sphere_centre, g.sphere_radius_m)) continue;
    projections[i] = Project(projector, g);
    if (projections[i] && Area(projections[i]->clipped_box) > 0.0) by_depth.push_back(i);
  }
  std::stable_sort(by_depth.begin(), by_depth.end(), [&](std::size_t a, std::size_t b) {
    return projections[a]->depth_m < projections[b]->depth_m;
  });
  std::vector<std::size_t> rank(n, n);
  for (std::size_t r = 0; r < by_depth.size(); ++r) rank[by_depth[r]] = r;

  const double sigma = options.pixel_noise_px;
  std::vector<core::BoxPx> occluders;
  // The random numbers of one candidate's keypoints, drawn whether or not it is detected.
  struct KeypointDraws {
    double nx = 0.0, ny = 0.0, u_confidence = 0.0, u_dropout = 0.0;
  };
  std::array<KeypointDraws, kNumCocoJoints> keypoint_draws;
  for (std::size_t i = 0; i < n; ++i) {  // people are sorted by id
    if (!projections[i] || !projections[i]->in_view) continue;
    const PersonProjection& p = *projections[i];
    // Fixed number of draws per candidate, whatever the outcome (see the header).
    const bool missed = miss_rng.Bernoulli(options.miss_rate);
    const double u_score = confidence_rng.Uniform();
    std::array<double, 4> box_noise;
    for (double& e : box_noise) e = noise_rng.Normal();
    if (options.poses) {
      for (std::size_t j = 0; j < keypoint_draws.size(); ++j) {
        KeypointDraws& k = keypoint_draws[j];
        k.nx = noise_rng.Normal();
        k.ny = noise_rng.Normal();
        k.u_confidence = confidence_rng.Uniform();
        k.u_dropout = confidence_rng.Uniform();
      }
    }
    if (embeddings) {
      for (double& e : embedding_noise) e = embedding_rng.Normal();
    }
    if (missed) continue;

    occluders.clear();
    std::size_t nearest_occluder = n;  // index into truth.people of the nearest occluder
    if (options.occlusion && rank[i] < n) {
      for (std::size_t r = 0; r < rank[i]; ++r) {
        const core::BoxPx& b = projections[by_depth[r]]->clipped_box;
        if (!Overlap(b, p.clipped_box)) continue;
        occluders.push_back(b);
        if (nearest_occluder == n) nearest_occluder = by_depth[r];
      }
    }
    const double own_area = Area(p.clipped_box);
    const double covered =
        own_area > 0.0 ? std::min(1.0, CoveredArea(p.clipped_box, occluders) / own_area) : 1.0;
    if (options.occlusion && covered >= options.occlusion_threshold) continue;

    core::Detection2D d;
    if (options.poses) {
      d.layout = core::KeypointLayoutId::kCoco17;
      d.keypoints.reserve(p.keypoints_px.size());
      for (std::size_t j = 0; j < p.keypoints_px.size(); ++j) {
        const KeypointDraws& k = keypoint_draws[j];
        const Vec2& clean = p.keypoints_px[j];
        double confidence = 0.0;
        if (p.keypoint_in_image[j] && !(k.u_dropout < options.keypoint_dropout)) {
          const bool occluded =
              std::any_of(occluders.begin(), occluders.end(), [&](const core::BoxPx& b) {
                return Contains(b, clean);
              });
          confidence =
              occluded ? OccludedConfidence(k.u_confidence) : VisibleConfidence(k.u_confidence);
        }
        d.keypoints.push_back(
            {Vec2(clean.x() + sigma * k.nx, clean.y() + sigma * k.ny), confidence});
      }
    }
    core::BoxPx box{p.padded_box.x_min + sigma * box_noise[0],
                    p.padded_box.y_min + sigma * box_noise[1],
                    p.padded_box.x_max + sigma * box_noise[2],
                    p.padded_box.y_max + sigma * box_noise[3]};
    if (box.x_max < box.x_min) std::swap(box.x_min, box.x_max);
    if (box.y_max < box.y_min) std::swap(box.y_min, box.y_max);
    d.box = Clip(box, camera.width_px, camera.height_px);
    EnsureExtent(&d.box.x_min, &d.box.x_max, camera.width_px);
    EnsureExtent(&d.box.y_min, &d.box.y_max, camera.height_px);
    d.score = 0.5 + 0.5 * (1.0 - 0.6 * u_score) * (1.0 - covered);
    if (embeddings) {
      const PersonTruth& person = truth.people[i];
      MVTRACK_CHECK_MSG(person.appearance != nullptr, "embeddings need people with appearance");
      const Vec2 to_camera(camera_centre.x() - person.footprint_m.x(),
                           camera_centre.y() - person.footprint_m.y());
      const double norm = to_camera.norm();
      const double view_cos = norm > 1e-9 ? (std::cos(person.heading_rad) * to_camera.x() +
                                             std::sin(person.heading_rad) * to_camera.y()) /
                                                norm
                                          : 1.0;
      const PersonAppearance* occluder =
          nearest_occluder < n ? truth.people[nearest_occluder].appearance.get() : nullptr;
      ObserveEmbedding(
          options, *person.appearance, view_cos, occluder, covered, embedding_noise, &d.embedding);
      d.embedding_model = kSimEmbeddingModel;
    }
    out.detections.push_back(std::move(d));
    ids.push_back(truth.people[i].id);
  }

  const int false_positives = fp_rng.Poisson(options.false_positives_per_frame);
  for (int k = 0; k < false_positives; ++k) {
    out.detections.push_back(FalsePositive(options, camera, &fp_rng));
    if (embeddings) {
      out.detections.back().embedding = StrangerEmbedding(options, &embedding_rng);
      out.detections.back().embedding_model = kSimEmbeddingModel;
    }
    ids.push_back(-1);
  }

  // Random order (Fisher-Yates), applied to the detections and their labels alike.
  for (std::size_t i = out.detections.size(); i > 1; --i) {
    const std::size_t j = static_cast<std::size_t>(shuffle_rng.Index(i));
    std::swap(out.detections[i - 1], out.detections[j]);
    std::swap(ids[i - 1], ids[j]);
  }
  if (person_ids != nullptr) *person_ids = std::move(ids);
  return out;
}

std::vector<PersonGeometry> MakeGeometry(const FrameTruth& truth) {
  std::vector<PersonGeometry> g;
  g.reserve(truth.people.size());
  for (const PersonTruth& p : truth.people) g.push_back(MakePersonGeometry(p));
  return g;
}

}  // namespace

core::CameraFrame RenderCamera(const SceneOptions& options,
                               const geometry::CameraModel& camera,
                               const FrameTruth& truth,
                               std::vector<int>* person_ids) {
  return RenderCameraImpl(options, camera, truth, MakeGeometry(truth), person_ids);
}

RenderedFrame RenderFrame(const SceneOptions& options,
                          const std::vector<geometry::CameraModel>& cameras,
                          const FrameTruth& truth) {
  const std::vector<PersonGeometry> geometry = MakeGeometry(truth);
  RenderedFrame f;
  f.cameras.reserve(cameras.size());
  f.person_ids.resize(cameras.size());
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    f.cameras.push_back(RenderCameraImpl(options, cameras[c], truth, geometry, &f.person_ids[c]));
  }
  return f;
}

}  // namespace mvtrack::sim
