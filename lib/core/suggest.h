#pragma once
/// @file
/// "Did you mean ...?": the closest of a list of names to a mistyped one (configuration keys,
/// command-line options). Pure functions.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mvtrack::core {

/// Edit distance by optimal string alignment: insertions, deletions, substitutions and
/// transpositions of adjacent characters each cost 1 (byte-wise; no substring is edited twice).
std::size_t EditDistance(std::string_view a, std::string_view b);
/// The candidate closest to `word` when it is close enough to be a likely typo (distance at
/// most max(1, min(3, (|candidate| + 1) / 3))); ties go to the earlier candidate.
std::optional<std::string> SuggestClosest(std::string_view word,
                                          const std::vector<std::string>& candidates);

}  // namespace mvtrack::core
