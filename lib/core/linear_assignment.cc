#include "core/linear_assignment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/check.h"

namespace mvtrack::core {
namespace {

// A cost in the lexicographically ordered group Z x R: the number of forbidden pairs used
// comes first, the real cost of the feasible pairs second. Solving the square/rectangular
// problem in this group finds, exactly and without a "big M" that could swamp the real costs in
// floating point, the assignment that (1) uses the fewest forbidden pairs -- i.e. matches the
// largest possible number of feasible pairs -- and (2) among those has the least total feasible
// cost. The shortest-augmenting-path algorithm only adds, subtracts and compares costs, so it
// is valid in any totally ordered abelian group.
using internal::LexCost;

LexCost operator+(const LexCost& a, const LexCost& b) {
  return {a.forbidden + b.forbidden, a.cost + b.cost};
}
LexCost operator-(const LexCost& a, const LexCost& b) {
  return {a.forbidden - b.forbidden, a.cost - b.cost};
}
bool operator<(const LexCost& a, const LexCost& b) {
  return a.forbidden < b.forbidden || (a.forbidden == b.forbidden && a.cost < b.cost);
}

// Larger than any reduced cost that can occur: |forbidden| of a reduced cost is bounded by the
// number of rows plus columns.
constexpr LexCost kInfinity{std::numeric_limits<std::int64_t>::max() / 4, 0.0};

// Feasible costs above this magnitude are rescaled before solving (see SolveAssignment).
constexpr double kLargeCost = 1e100;

bool IsFeasible(double cost, double max_cost) { return std::isfinite(cost) && cost <= max_cost; }

// Shortest augmenting path (Hungarian with potentials, the O(n^2 m) form of Jonker-Volgenant's
// Dijkstra-like augmentation) for n <= m. `a` is row-major n x m. Returns the column of each row.
// Rows are inserted in increasing order; within a scan the first (lowest-index) column with the
// strictly smallest reduced cost wins, so ties resolve towards low indices and the result is a
// pure function of the input.
// Scratch vectors of one solve (owned by an AssignmentWorkspace).
struct SolverBuffers {
  std::vector<LexCost>& u;
  std::vector<LexCost>& v;
  std::vector<int>& row_of_col;
  std::vector<int>& way;
  std::vector<LexCost>& min_reduced;
  std::vector<char>& used;
};

void SolveRowsNotMoreThanCols(const std::vector<LexCost>& a,
                              int n,
                              int m,
                              SolverBuffers buf,
                              std::vector<int>* col_of_row_out) {
  const auto at = [&](int i, int j) {
    return a[static_cast<std::size_t>(i) * static_cast<std::size_t>(m) +
             static_cast<std::size_t>(j)];
  };
  const auto sm = static_cast<std::size_t>(m) + 1;
  // 1-based rows and columns; column 0 is the virtual root of each search tree.
  std::vector<LexCost>& u = buf.u;
  std::vector<LexCost>& v = buf.v;
  std::vector<int>& row_of_col = buf.row_of_col;  // p in the classical formulation; 0 = free
  std::vector<int>& way = buf.way;
  std::vector<LexCost>& min_reduced = buf.min_reduced;
  std::vector<char>& used = buf.used;
  u.assign(static_cast<std::size_t>(n) + 1, LexCost{});
  v.assign(sm, LexCost{});
  row_of_col.assign(sm, 0);
  way.assign(sm, 0);
  min_reduced.resize(sm);
  used.resize(sm);

  for (int i = 1; i <= n; ++i) {
    row_of_col[0] = i;
    int j0 = 0;
    std::fill(min_reduced.begin(), min_reduced.end(), kInfinity);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[static_cast<std::size_t>(j0)] = 1;
      const int i0 = row_of_col[static_cast<std::size_t>(j0)];
      LexCost delta = kInfinity;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        const auto sj = static_cast<std::size_t>(j);
        if (used[sj]) continue;
        const LexCost reduced = at(i0 - 1, j - 1) - u[static_cast<std::size_t>(i0)] - v[sj];
        if (reduced < min_reduced[sj]) {
          min_reduced[sj] = reduced;
          way[sj] = j0;
        }
        if (min_reduced[sj] < delta) {
          delta = min_reduced[sj];
          j1 = j;
        }
      }
      for (std::size_t j = 0; j < sm; ++j) {
        if (used[j]) {
          const auto r = static_cast<std::size_t>(row_of_col[j]);
          u[r] = u[r] + delta;
          v[j] = v[j] - delta;
        } else {
          min_reduced[j] = min_reduced[j] - delta;
        }
      }
      // n <= m guarantees a free column with a finite reduced cost.
      MVTRACK_DCHECK(j1 != 0);
      j0 = j1;
    } while (row_of_col[static_cast<std::size_t>(j0)] != 0);
    // Augment along the alternating path back to the root.
    do {
      const int j1 = way[static_cast<std::size_t>(j0)];
      row_of_col[static_cast<std::size_t>(j0)] = row_of_col[static_cast<std::size_t>(j1)];
      j0 = j1;
    } while (j0 != 0);
  }

  std::vector<int>& col_of_row = *col_of_row_out;
  col_of_row.assign(static_cast<std::size_t>(n), -1);
  for (int j = 1; j <= m; ++j) {
    const int r = row_of_col[static_cast<std::size_t>(j)];
    if (r != 0) col_of_row[static_cast<std::size_t>(r - 1)] = j - 1;
  }
}

}  // namespace

Assignment SolveAssignment(const Eigen::MatrixXd& cost, double max_cost) {
  AssignmentWorkspace workspace;
  Assignment result;
  SolveAssignment(cost, max_cost, &workspace, &result);
  return result;
}

void SolveAssignment(const Eigen::MatrixXd& cost,
                     double max_cost,
                     AssignmentWorkspace* workspace,
                     Assignment* result_out) {
  MVTRACK_CHECK(workspace != nullptr && result_out != nullptr);
  AssignmentWorkspace& ws = *workspace;
  Assignment& result = *result_out;
  result.matches.clear();
  result.unmatched_rows.clear();
  result.unmatched_cols.clear();
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());

  // Rows and columns without a single feasible pair can only ever be matched to forbidden
  // pairs; removing them shrinks the problem without changing the optimum.
  std::vector<int>& active_rows = ws.active_rows_;
  std::vector<int>& active_cols = ws.active_cols_;
  active_rows.clear();
  active_cols.clear();
  std::vector<int>& col_of_row = ws.col_of_row_;
  col_of_row.assign(static_cast<std::size_t>(rows), -1);
  // Whether every row and every column has at most one feasible pair. Then the feasible pairs
  // are disjoint, and the one assignment that matches all of them is the unique optimum (it is
  // the only one without a forbidden pair among the active rows and columns), so it is taken
  // directly: the solver would return exactly it.
  bool disjoint_pairs = true;
  {
    // Per column: 0, 1 or 2 (two or more) feasible pairs.
    std::vector<char>& col_feasible = ws.col_flag_;
    col_feasible.assign(static_cast<std::size_t>(cols), 0);
    for (int i = 0; i < rows; ++i) {
      int row_feasible = 0;
      int feasible_col = -1;
      for (int j = 0; j < cols; ++j) {
        if (IsFeasible(cost(i, j), max_cost)) {
          ++row_feasible;
          feasible_col = j;
          char& count = col_feasible[static_cast<std::size_t>(j)];
          if (count < 2) ++count;
        }
      }
      if (row_feasible > 0) active_rows.push_back(i);
      if (row_feasible == 1) {
        col_of_row[static_cast<std::size_t>(i)] = feasible_col;
      } else if (row_feasible > 1) {
        disjoint_pairs = false;
      }
    }
    for (int j = 0; j < cols; ++j) {
      const char count = col_feasible[static_cast<std::size_t>(j)];
      if (count > 0) active_cols.push_back(j);
      if (count > 1) disjoint_pairs = false;
    }
  }

  const int n_rows = static_cast<int>(active_rows.size());
  const int n_cols = static_cast<int>(active_cols.size());
  if (!disjoint_pairs) col_of_row.assign(static_cast<std::size_t>(rows), -1);
  if (!disjoint_pairs && n_rows > 0 && n_cols > 0) {
    // Solve with the smaller side as rows (the algorithm needs rows <= columns).
    const bool transpose = n_rows > n_cols;
    const int n = transpose ? n_cols : n_rows;
    const int m = transpose ? n_rows : n_cols;
    // Costs of astronomical magnitude could overflow the potentials to inf (and inf - inf to
    // NaN); scale them by an exact power of two into [1, 2) so sums stay finite. Matches are
    // reported against the original matrix.
    double max_abs = 0.0;
    for (const int i : active_rows) {
      for (const int j : active_cols) {
        if (IsFeasible(cost(i, j), max_cost)) max_abs = std::max(max_abs, std::abs(cost(i, j)));
      }
    }
    const double scale = max_abs > kLargeCost ? std::ldexp(1.0, -std::ilogb(max_abs)) : 1.0;
    std::vector<LexCost>& lex = ws.lex_;
    lex.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(m));
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < m; ++b) {
        const int i = active_rows[static_cast<std::size_t>(transpose ? b : a)];
        const int j = active_cols[static_cast<std::size_t>(transpose ? a : b)];
        const double c = cost(i, j);
        const std::size_t k =
            static_cast<std::size_t>(a) * static_cast<std::size_t>(m) + static_cast<std::size_t>(b);
        lex[k] = IsFeasible(c, max_cost) ? LexCost{0, c * scale} : LexCost{1, 0.0};
      }
    }
    std::vector<int>& solved = ws.solved_;
    SolveRowsNotMoreThanCols(
        lex,
        n,
        m,
        SolverBuffers{ws.u_, ws.v_, ws.row_of_col_, ws.way_, ws.min_reduced_, ws.used_},
        &solved);
    for (int a = 0; a < n; ++a) {
      const int b = solved[static_cast<std::size_t>(a)];
      if (b < 0) continue;
      const int i = active_rows[static_cast<std::size_t>(transpose ? b : a)];
      const int j = active_cols[static_cast<std::size_t>(transpose ? a : b)];
      // Forbidden pairs only fill up the square problem; they are never reported.
      if (IsFeasible(cost(i, j), max_cost)) col_of_row[static_cast<std::size_t>(i)] = j;
    }
  }

  std::vector<char>& col_matched = ws.col_flag_;
  col_matched.assign(static_cast<std::size_t>(cols), 0);
  for (int i = 0; i < rows; ++i) {
    const int j = col_of_row[static_cast<std::size_t>(i)];
    if (j >= 0) {
      result.matches.emplace_back(i, j);
      col_matched[static_cast<std::size_t>(j)] = 1;
    } else {
      result.unmatched_rows.push_back(i);
    }
  }
  for (int j = 0; j < cols; ++j) {
    if (!col_matched[static_cast<std::size_t>(j)]) result.unmatched_cols.push_back(j);
  }
}

}  // namespace mvtrack::core
