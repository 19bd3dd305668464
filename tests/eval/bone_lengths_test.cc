// eval::EvaluateBoneLengths: per track, how much each limb's length varies.

#include "eval/bone_lengths.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace mvtrack::eval {
namespace {

const core::KeypointLayout& Shelf14() {
  return core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
}

// A shelf14 body whose left upper arm (l_shoulder 9 -> l_elbow 10) is `arm` metres long; every
// other limb is 0.4 m; the head joints are missing.
EvalObject Body(std::int64_t id, double arm) {
  EvalObject o;
  o.id = id;
  o.joints.resize(14);
  o.joints[0] = Vec3(0.1, 0, 0.0);  // r_ankle
  o.joints[1] = Vec3(0.1, 0, 0.4);  // r_knee
  o.joints[2] = Vec3(0.1, 0, 0.8);  // r_hip
  o.joints[3] = Vec3(-0.1, 0, 0.8);
  o.joints[4] = Vec3(-0.1, 0, 0.4);
  o.joints[5] = Vec3(-0.1, 0, 0.0);
  o.joints[8] = Vec3(0.2, 0, 1.4);   // r_shoulder
  o.joints[7] = Vec3(0.2, 0, 1.0);   // r_elbow
  o.joints[6] = Vec3(0.2, 0, 0.6);   // r_wrist
  o.joints[9] = Vec3(-0.2, 0, 1.4);  // l_shoulder
  o.joints[10] = Vec3(-0.2, 0, 1.4 - arm);
  o.joints[11] = Vec3(-0.2, 0, 1.0 - arm);  // l_wrist: the lower arm stays 0.4 m
  return o;
}

}  // namespace

TEST_CASE("bone lengths: the coefficient of variation per limb, per track, long tracks only",
          "[unit]") {
  EvalSequence seq;
  for (FrameIndex f = 0; f < 60; ++f) {
    EvalFrame frame;
    frame.frame = f;
    // Track 1: the left upper arm alternates 0.3 / 0.5 m (CV 0.1 / 0.4 = 25 %); the rest fixed.
    frame.objects.push_back(Body(1, f % 2 == 0 ? 0.3 : 0.5));
    // Track 2: constant; track 3 only in 10 frames: left out.
    frame.objects.push_back(Body(2, 0.4));
    if (f < 10) frame.objects.push_back(Body(3, 0.1 + 0.05 * static_cast<double>(f)));
    seq.push_back(frame);
  }
  const BoneLengthStability r = EvaluateBoneLengths(seq, Shelf14(), 50);
  CHECK(r.limbs.size() == 8);
  REQUIRE(r.tracks.size() == 2);
  CHECK(r.tracks[0].id == 1);
  CHECK(r.tracks[0].num_frames == 60);
  CHECK(r.tracks[0].cv_max == Approx(0.25));
  CHECK(r.tracks[0].cv_mean == Approx(0.25 / 8));
  CHECK(r.tracks[1].cv_max == Approx(0.0).margin(1e-12));
  CHECK(r.cv_worst_track == Approx(0.25 / 8));
  CHECK(r.cv_mean == Approx(0.25 / 16));
  CHECK(r.cv_max == Approx(0.25));
  // Frame ranges restrict the frames: in [0, 39] track 1 has 40 frames, below 50.
  CHECK(EvaluateBoneLengths(seq, Shelf14(), 50, {{0, 39}}).tracks.empty());
  // A layout without limbs (no joint names in common) measures nothing.
  CHECK(EvaluateBoneLengths(seq, core::GetKeypointLayout(core::KeypointLayoutId::kNone), 1)
            .tracks.empty());
}

}  // namespace mvtrack::eval
