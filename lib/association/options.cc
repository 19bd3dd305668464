#include "association/options.h"

#include <array>
#include <cmath>
#include <utility>

namespace mvtrack::association {
namespace {

constexpr std::array<std::pair<ClusteringMethod, std::string_view>, 4> kMethodNames = {{
    {ClusteringMethod::kPdnc, "pdnc"},
    {ClusteringMethod::kCompleteLinkageEmptyAsZero, "complete_linkage_empty_as_zero"},
    {ClusteringMethod::kCompleteLinkageEmptyAsUpper, "complete_linkage_empty_as_upper"},
    {ClusteringMethod::kSingleLinkageEmptyAsUpper, "single_linkage_empty_as_upper"},
}};

}  // namespace

std::string_view ClusteringMethodName(ClusteringMethod method) {
  for (const auto& [m, name] : kMethodNames) {
    if (m == method) return name;
  }
  return "unknown";
}

std::optional<ClusteringMethod> ClusteringMethodFromName(std::string_view name) {
  for (const auto& [m, n] : kMethodNames) {
    if (n == name) return m;
  }
  return std::nullopt;
}

bool AssociationOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!std::isfinite(lambda) || !(lambda > 0.0)) {
    return fail("lambda must be finite and > 0 (a fraction of the person's image scale)");
  }
  if (!std::isfinite(min_confidence) || min_confidence < 0.0 || min_confidence > 1.0) {
    return fail("min_confidence must be in [0, 1]");
  }
  if (num_points < 0) return fail("num_points must be >= 0");
  if (floor_point < -1) return fail("floor_point must be >= -1 (-1: no point on the floor)");
  if (!std::isfinite(floor_height_m)) return fail("floor_height_m must be finite");
  if (!std::isfinite(appearance_weight) || appearance_weight < 0.0) {
    return fail("appearance_weight must be finite and >= 0");
  }
  if (!(appearance_gate >= 0.0 && appearance_gate <= 2.0)) {
    return fail("appearance_gate must be in [0, 2]");
  }
  if (!std::isfinite(empty_upper_bound) || empty_upper_bound < 0.0) {
    return fail("empty_upper_bound must be finite and >= 0");
  }
  bool known_method = false;
  for (const auto& entry : kMethodNames) known_method = known_method || entry.first == method;
  if (!known_method) return fail("method is not a known ClusteringMethod");
  return true;
}

}  // namespace mvtrack::association
