#include "eval/layer_agreement.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace mvtrack::eval {
namespace {

EvalFrame Frame(FrameIndex f, std::vector<std::pair<std::int64_t, double>> objects) {
  EvalFrame e;
  e.frame = f;
  for (const auto& [id, x] : objects) e.objects.push_back({id, Vec3(x, 0.0, 0.0), {}});
  return e;
}

TEST_CASE("CompareLayers counts shared ids per frame and their footprint distances",
          "[unit][eval]") {
  const EvalSequence final_output = {Frame(0, {{1, 0.0}, {2, 5.0}}), Frame(1, {{1, 0.1}})};
  // Frame 0: id 1 0.2 m off, id 3 unknown to the final output; frame 1: id 1 exact; frame 2 is
  // not in the final output.
  const EvalSequence provisional = {
      Frame(0, {{1, 0.2}, {3, 5.0}}), Frame(1, {{1, 0.1}}), Frame(2, {{1, 0.3}})};
  const LayerAgreement a = CompareLayers(final_output, provisional);
  CHECK(a.provisional_track_frames == 4);
  CHECK(a.final_track_frames == 3);
  CHECK(a.same_id == 2);
  CHECK(a.final_covered == 2);
  CHECK(a.same_id_fraction() == Approx(0.5));
  CHECK(a.coverage() == Approx(2.0 / 3.0));
  CHECK(a.median_distance_m == Approx(0.0).margin(1e-12));
  CHECK(a.max_distance_m == Approx(0.2));
  const LayerAgreement none = CompareLayers(final_output, {});
  CHECK(none.same_id_fraction() == 1.0);
  CHECK(std::isnan(none.median_distance_m));
}

}  // namespace
}  // namespace mvtrack::eval
