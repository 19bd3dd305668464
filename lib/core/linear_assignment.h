#pragma once
/// @file
/// Optimal rectangular linear assignment (Hungarian / Jonker-Volgenant shortest augmenting
/// path), shared by SORT (tracking2d) and window linking (linking). Stateless, deterministic:
/// ties are broken by the lowest row then column index.

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace mvtrack::core {

/// Result of an assignment: matched (row, col) pairs sorted by row, and the unmatched rows and
/// columns, each sorted ascending.
struct Assignment {
  std::vector<std::pair<int, int>> matches;
  std::vector<int> unmatched_rows;
  std::vector<int> unmatched_cols;
};

/// Minimises the total cost over pairs with cost <= `max_cost`; pairs above it (and non-finite
/// costs) are never matched. Any matrix shape, including empty. NaN entries count as
/// forbidden.
Assignment SolveAssignment(const Eigen::MatrixXd& cost, double max_cost);

}  // namespace mvtrack::core
