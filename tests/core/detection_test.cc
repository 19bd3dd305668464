#include "core/detection.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

DetectionLimits Limits640x480() {
  DetectionLimits limits;
  limits.image_width_px = 640;
  limits.image_height_px = 480;
  return limits;  // margin 0.5 -> allowed region [-320, 960] x [-240, 720]
}

// A plausible COCO-17 detection: a 100x200 box with every keypoint inside it.
Detection2D ValidPoseDetection() {
  Detection2D d;
  d.box = BoxPx{200.0, 100.0, 300.0, 300.0};
  d.score = 0.9;
  d.layout = KeypointLayoutId::kCoco17;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(205.0, 295.0);
  std::uniform_real_distribution<double> uy(105.0, 295.0);
  std::uniform_real_distribution<double> uc(0.3, 1.0);
  for (int j = 0; j < 17; ++j) {
    d.keypoints.push_back(Keypoint2D{Vec2(ux(rng), uy(rng)), uc(rng)});
  }
  d.embedding.assign(128, 0.125f);
  return d;
}

bool SameKeypoints(const Detection2D& a, const Detection2D& b) {
  if (a.keypoints.size() != b.keypoints.size()) return false;
  for (std::size_t i = 0; i < a.keypoints.size(); ++i) {
    if (a.keypoints[i].position_px != b.keypoints[i].position_px) return false;
    if (a.keypoints[i].confidence != b.keypoints[i].confidence) return false;
  }
  return true;
}

void RequireRejected(Detection2D d, const DetectionLimits& limits, const std::string& needle) {
  const DetectionCheck check = ValidateDetection(&d, limits);
  CHECK(check.verdict == DetectionVerdict::kRejected);
  INFO("reason: " << check.reason);
  CHECK(check.reason.find(needle) != std::string::npos);
}

TEST_CASE("a clean detection is accepted unchanged", "[unit]") {
  for (const DetectionLimits& limits : {Limits640x480(), DetectionLimits{}}) {
    Detection2D d = ValidPoseDetection();
    const Detection2D original = d;
    const DetectionCheck check = ValidateDetection(&d, limits);
    CHECK(check.verdict == DetectionVerdict::kAccepted);
    CHECK(check.reason.empty());
    CHECK(SameKeypoints(d, original));
    CHECK(d.embedding == original.embedding);
  }
}

TEST_CASE("non-finite box coordinates are rejected", "[unit]") {
  for (double bad : {kNaN, kInf, -kInf}) {
    for (int coord = 0; coord < 4; ++coord) {
      INFO("coordinate " << coord << " = " << bad);
      Detection2D d = ValidPoseDetection();
      double* fields[] = {&d.box.x_min, &d.box.y_min, &d.box.x_max, &d.box.y_max};
      *fields[coord] = bad;
      RequireRejected(d, Limits640x480(), "non-finite");
      // Also without image bounds: the finiteness check does not depend on them.
      RequireRejected(d, DetectionLimits{}, "non-finite");
    }
  }
}

TEST_CASE("degenerate and tiny boxes are rejected", "[unit]") {
  SECTION("zero width") {
    Detection2D d = ValidPoseDetection();
    d.box.x_max = d.box.x_min;
    RequireRejected(d, Limits640x480(), "non-positive");
  }
  SECTION("negative width") {
    Detection2D d = ValidPoseDetection();
    std::swap(d.box.x_min, d.box.x_max);
    RequireRejected(d, Limits640x480(), "non-positive");
  }
  SECTION("negative height") {
    Detection2D d = ValidPoseDetection();
    std::swap(d.box.y_min, d.box.y_max);
    RequireRejected(d, Limits640x480(), "non-positive");
  }
  SECTION("below min_box_size_px, and exactly at it") {
    DetectionLimits limits = Limits640x480();
    limits.min_box_size_px = 4.0;
    Detection2D d;
    d.box = BoxPx{10.0, 10.0, 13.5, 50.0};
    RequireRejected(d, limits, "min_box_size_px");
    d.box.x_max = 14.0;
    CHECK(ValidateDetection(&d, limits).verdict == DetectionVerdict::kAccepted);
  }
}

TEST_CASE("boxes outside the image are rejected, partly visible ones kept", "[unit]") {
  const DetectionLimits limits = Limits640x480();
  Detection2D d;
  d.score = 0.5;
  SECTION("entirely left of the image but inside the margin") {
    d.box = BoxPx{-200.0, 100.0, -20.0, 300.0};
    RequireRejected(d, limits, "outside the image");
  }
  SECTION("entirely below the image but inside the margin") {
    d.box = BoxPx{100.0, 500.0, 200.0, 700.0};
    RequireRejected(d, limits, "outside the image");
  }
  SECTION("visible sliver thinner than min_box_size_px") {
    d.box = BoxPx{639.0, 100.0, 700.0, 300.0};  // 1 px inside
    RequireRejected(d, limits, "outside the image");
  }
  SECTION("sticking out further than the margin") {
    d.box = BoxPx{-400.0, 100.0, 100.0, 300.0};  // margin is 320 px
    RequireRejected(d, limits, "box_margin_fraction");
  }
  SECTION("partly outside within the margin is accepted as is") {
    d.box = BoxPx{-50.0, -30.0, 60.0, 200.0};
    const BoxPx before = d.box;
    CHECK(ValidateDetection(&d, limits).verdict == DetectionVerdict::kAccepted);
    CHECK(d.box.x_min == before.x_min);  // boxes are never clipped
    CHECK(d.box.y_min == before.y_min);
  }
  SECTION("without image size there are no bounds checks") {
    d.box = BoxPx{-5000.0, -5000.0, -4000.0, -3000.0};
    CHECK(ValidateDetection(&d, DetectionLimits{}).verdict == DetectionVerdict::kAccepted);
  }
}

TEST_CASE("invalid scores are rejected", "[unit]") {
  for (double bad : {kNaN, kInf, 1.0 + 1e-9, 1.5, -1e-9, -0.5}) {
    INFO("score " << bad);
    Detection2D d = ValidPoseDetection();
    d.score = bad;
    RequireRejected(d, Limits640x480(), "score");
  }
  for (double ok : {0.0, 1.0}) {
    Detection2D d = ValidPoseDetection();
    d.score = ok;
    CHECK(ValidateDetection(&d, Limits640x480()).verdict == DetectionVerdict::kAccepted);
  }
}

TEST_CASE("bad keypoints are invalidated and the detection kept", "[unit]") {
  const DetectionLimits limits = Limits640x480();
  Detection2D d = ValidPoseDetection();
  d.keypoints[0].position_px.x() = kNaN;
  d.keypoints[1].position_px.y() = kInf;
  d.keypoints[2].position_px = Vec2(1000.0, 200.0);  // beyond the 960 px right margin
  d.keypoints[3].position_px = Vec2(250.0, -300.0);  // beyond the -240 px top margin
  d.keypoints[4].confidence = 1.5;
  d.keypoints[5].confidence = -0.2;
  d.keypoints[6].confidence = kNaN;
  d.keypoints[7].position_px = Vec2(-100.0, 200.0);  // outside the image, inside the margin
  const Detection2D original = d;

  const DetectionCheck check = ValidateDetection(&d, limits);
  CHECK(check.verdict == DetectionVerdict::kAcceptedRepaired);
  INFO("reason: " << check.reason);
  CHECK(check.reason.find("2 with non-finite position") != std::string::npos);
  CHECK(check.reason.find("3 with confidence") != std::string::npos);
  CHECK(check.reason.find("2 outside the image margin") != std::string::npos);
  REQUIRE(d.keypoints.size() == 17);
  for (int j = 0; j <= 6; ++j) {
    INFO("keypoint " << j);
    CHECK(d.keypoints[static_cast<std::size_t>(j)].confidence == 0.0);
    CHECK(d.keypoints[static_cast<std::size_t>(j)].position_px.allFinite());
  }
  // Finite positions are kept for inspection; only the confidence changes.
  CHECK(d.keypoints[2].position_px == original.keypoints[2].position_px);
  CHECK(d.keypoints[4].position_px == original.keypoints[4].position_px);
  // Untouched keypoints keep their values, including the one inside the margin.
  for (std::size_t j = 7; j < 17; ++j) {
    CHECK(d.keypoints[j].position_px == original.keypoints[j].position_px);
    CHECK(d.keypoints[j].confidence == original.keypoints[j].confidence);
  }
  // Nothing else about the detection changes.
  CHECK(d.score == original.score);
  CHECK(d.box.x_min == original.box.x_min);
}

TEST_CASE("already-missing keypoints outside the image need no repair", "[unit]") {
  Detection2D d = ValidPoseDetection();
  d.keypoints[3].position_px = Vec2(5000.0, 5000.0);
  d.keypoints[3].confidence = 0.0;
  const DetectionCheck check = ValidateDetection(&d, Limits640x480());
  CHECK(check.verdict == DetectionVerdict::kAccepted);
  // Without image size the same far-away point with confidence is not judged.
  Detection2D e = ValidPoseDetection();
  e.keypoints[3].position_px = Vec2(5000.0, 5000.0);
  CHECK(ValidateDetection(&e, DetectionLimits{}).verdict == DetectionVerdict::kAccepted);
  CHECK(e.keypoints[3].confidence > 0.0);
}

TEST_CASE("keypoint count must match the layout", "[unit]") {
  SECTION("one keypoint short") {
    Detection2D d = ValidPoseDetection();
    d.keypoints.pop_back();
    RequireRejected(d, Limits640x480(), "do not match layout 'coco17'");
  }
  SECTION("right count for another layout") {
    Detection2D d = ValidPoseDetection();
    d.layout = KeypointLayoutId::kBody25;
    RequireRejected(d, Limits640x480(), "do not match layout 'body25'");
  }
  SECTION("keypoints on a box-only detection") {
    Detection2D d = ValidPoseDetection();
    d.layout = KeypointLayoutId::kNone;
    RequireRejected(d, Limits640x480(), "do not match layout 'none'");
  }
  SECTION("more than max_keypoints") {
    Detection2D d = ValidPoseDetection();
    DetectionLimits limits = Limits640x480();
    limits.max_keypoints = 16;
    RequireRejected(d, limits, "max_keypoints");
  }
  SECTION("unknown layout id") {
    Detection2D d = ValidPoseDetection();
    d.layout = static_cast<KeypointLayoutId>(42);
    RequireRejected(d, Limits640x480(), "unknown keypoint layout");
  }
  SECTION("every known layout accepts its own joint count") {
    for (KeypointLayoutId id : AllKeypointLayouts()) {
      Detection2D d = ValidPoseDetection();
      d.layout = id;
      d.keypoints.assign(static_cast<std::size_t>(GetKeypointLayout(id).num_joints()),
                         Keypoint2D{Vec2(250.0, 200.0), 0.8});
      CHECK(ValidateDetection(&d, Limits640x480()).verdict == DetectionVerdict::kAccepted);
    }
  }
}

TEST_CASE("box-only detections need no keypoints", "[unit]") {
  for (KeypointLayoutId id : {KeypointLayoutId::kNone, KeypointLayoutId::kCoco17}) {
    Detection2D d = ValidPoseDetection();
    d.layout = id;
    d.keypoints.clear();
    const DetectionCheck check = ValidateDetection(&d, Limits640x480());
    CHECK(check.verdict == DetectionVerdict::kAccepted);
    CHECK(d.keypoints.empty());
  }
}

TEST_CASE("oversized or non-finite embeddings are dropped, the detection is kept", "[unit]") {
  DetectionLimits limits = Limits640x480();
  limits.max_embedding_size = 512;
  const auto require_dropped = [&](Detection2D d, const std::string& why) {
    d.embedding_model = "osnet";
    const Detection2D before = d;
    const DetectionCheck check = ValidateDetection(&d, limits);
    CHECK(check.verdict == DetectionVerdict::kAcceptedRepaired);
    CHECK(check.reason.find("embedding dropped: ") != std::string::npos);
    CHECK(check.reason.find(why) != std::string::npos);
    CHECK(d.embedding.empty());
    CHECK(d.embedding_model.empty());
    CHECK(d.keypoints.size() == before.keypoints.size());
    CHECK(d.box.x_min == before.box.x_min);
  };
  SECTION("huge embedding") {
    Detection2D d = ValidPoseDetection();
    d.embedding.assign(1000000, 0.001f);
    require_dropped(d, "embedding of size 1000000 exceeds max_embedding_size");
  }
  SECTION("one over the limit dropped, at the limit kept") {
    Detection2D d = ValidPoseDetection();
    d.embedding.assign(513, 0.5f);
    require_dropped(d, "exceeds max_embedding_size");
    d.embedding.pop_back();
    CHECK(ValidateDetection(&d, limits).verdict == DetectionVerdict::kAccepted);
    CHECK(d.embedding.size() == 512);
  }
  SECTION("non-finite value") {
    Detection2D d = ValidPoseDetection();
    d.embedding[17] = std::numeric_limits<float>::quiet_NaN();
    require_dropped(d, "embedding has a non-finite value");
    d = ValidPoseDetection();
    d.embedding[3] = -std::numeric_limits<float>::infinity();
    require_dropped(d, "embedding has a non-finite value");
  }
  SECTION("with repaired keypoints both are reported") {
    Detection2D d = ValidPoseDetection();
    d.embedding[0] = std::numeric_limits<float>::quiet_NaN();
    d.keypoints[0].confidence = 3.0;
    const DetectionCheck check = ValidateDetection(&d, limits);
    CHECK(check.verdict == DetectionVerdict::kAcceptedRepaired);
    CHECK(check.reason.find("invalidated keypoints") != std::string::npos);
    CHECK(check.reason.find("embedding dropped") != std::string::npos);
  }
  SECTION("no embedding is fine") {
    Detection2D d = ValidPoseDetection();
    d.embedding.clear();
    CHECK(ValidateDetection(&d, limits).verdict == DetectionVerdict::kAccepted);
  }
}

TEST_CASE("the first failed check is reported", "[unit]") {
  // A detection with several problems is rejected for the box first, before keypoint repairs.
  Detection2D d = ValidPoseDetection();
  d.box.x_min = kNaN;
  d.score = 7.0;
  d.keypoints[0].confidence = 3.0;
  const DetectionCheck check = ValidateDetection(&d, Limits640x480());
  CHECK(check.verdict == DetectionVerdict::kRejected);
  CHECK(check.reason.find("box") != std::string::npos);
  CHECK(check.reason.find("score") == std::string::npos);
}

TEST_CASE("DetectionLimits::Validate accepts usable limits and names the bad field", "[unit]") {
  std::string why = "untouched";
  CHECK(DetectionLimits{}.Validate(&why));
  CHECK(Limits640x480().Validate(&why));
  // Boundary values that are allowed: unknown image size, no margin, no keypoints/embeddings.
  DetectionLimits edge;
  edge.box_margin_fraction = 0.0;
  edge.max_keypoints = 0;
  edge.max_embedding_size = 0;
  edge.min_box_size_px = 1e-9;
  CHECK(edge.Validate(&why));
  CHECK(why == "untouched");  // success leaves `why` alone

  struct Case {
    const char* field;
    void (*apply)(DetectionLimits*);
  };
  const Case cases[] = {
      {"image_width_px", [](DetectionLimits* l) { l->image_width_px = -1; }},
      {"image_height_px", [](DetectionLimits* l) { l->image_height_px = -640; }},
      {"box_margin_fraction", [](DetectionLimits* l) { l->box_margin_fraction = -0.01; }},
      {"box_margin_fraction", [](DetectionLimits* l) { l->box_margin_fraction = kNaN; }},
      {"box_margin_fraction", [](DetectionLimits* l) { l->box_margin_fraction = kInf; }},
      {"min_box_size_px", [](DetectionLimits* l) { l->min_box_size_px = 0.0; }},
      {"min_box_size_px", [](DetectionLimits* l) { l->min_box_size_px = -2.0; }},
      {"min_box_size_px", [](DetectionLimits* l) { l->min_box_size_px = kNaN; }},
      {"min_box_size_px", [](DetectionLimits* l) { l->min_box_size_px = kInf; }},
      {"max_keypoints", [](DetectionLimits* l) { l->max_keypoints = -1; }},
      {"max_embedding_size", [](DetectionLimits* l) { l->max_embedding_size = -1; }},
  };
  for (const Case& c : cases) {
    for (const DetectionLimits& base : {DetectionLimits{}, Limits640x480()}) {
      DetectionLimits limits = base;
      c.apply(&limits);
      std::string reason;
      INFO("field " << c.field);
      CHECK_FALSE(limits.Validate(&reason));
      INFO("reason: " << reason);
      CHECK(reason.find(c.field) != std::string::npos);
      CHECK_FALSE(limits.Validate(nullptr));  // a null `why` is allowed
    }
  }
}

}  // namespace
}  // namespace mvtrack::core
