#pragma once
/// @file
/// Optimal rectangular linear assignment (Hungarian / Jonker-Volgenant shortest augmenting
/// path), shared by SORT (tracking2d) and window linking (linking). Stateless, deterministic:
/// ties are broken by the lowest row then column index.

#include <Eigen/Core>
#include <cstdint>
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

namespace internal {
/// A cost in the lexicographically ordered group Z x R used by the solver (see
/// linear_assignment.cc): the number of forbidden pairs first, the real cost second.
struct LexCost {
  std::int64_t forbidden = 0;  ///< forbidden pairs used
  double cost = 0.0;           ///< summed cost of the feasible pairs
};
}  // namespace internal

/// Scratch buffers of SolveAssignment, kept between calls by a caller that solves one problem
/// per frame (SORT), so that a warmed-up solve does not allocate. Results do not depend on what
/// the workspace was used for before. Single-owner, single-threaded object.
class AssignmentWorkspace {
 public:
  AssignmentWorkspace() = default;

 private:
  friend void SolveAssignment(const Eigen::MatrixXd& cost,
                              double max_cost,
                              AssignmentWorkspace* workspace,
                              Assignment* result);
  std::vector<int> active_rows_;
  std::vector<int> active_cols_;
  std::vector<char> col_flag_;
  std::vector<int> col_of_row_;
  std::vector<internal::LexCost> lex_;
  std::vector<internal::LexCost> u_;
  std::vector<internal::LexCost> v_;
  std::vector<internal::LexCost> min_reduced_;
  std::vector<int> row_of_col_;
  std::vector<int> way_;
  std::vector<char> used_;
  std::vector<int> solved_;
};

/// SolveAssignment with caller-owned scratch space and result (its vectors are overwritten and
/// keep their capacity). Identical results to the two-argument form.
void SolveAssignment(const Eigen::MatrixXd& cost,
                     double max_cost,
                     AssignmentWorkspace* workspace,
                     Assignment* result);

}  // namespace mvtrack::core
