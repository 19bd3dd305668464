#include "core/linear_assignment.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace mvtrack::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool Feasible(double c, double max_cost) { return std::isfinite(c) && c <= max_cost; }

// Best objective of the problem: the largest number of feasible pairs, then the least total cost.
struct Objective {
  int count = 0;
  double cost = 0.0;
};

// Enumerates every partial matching made of feasible pairs (each row unmatched or matched to a
// free feasible column) and keeps the best objective. Exponential, for small matrices only.
void BruteForce(const Eigen::MatrixXd& cost,
                double max_cost,
                int row,
                std::vector<char>* col_used,
                int count,
                double total,
                Objective* best) {
  if (row == cost.rows()) {
    if (count > best->count || (count == best->count && total < best->cost)) {
      *best = {count, total};
    }
    return;
  }
  BruteForce(cost, max_cost, row + 1, col_used, count, total, best);
  for (int j = 0; j < cost.cols(); ++j) {
    const auto sj = static_cast<std::size_t>(j);
    if ((*col_used)[sj] || !Feasible(cost(row, j), max_cost)) continue;
    (*col_used)[sj] = 1;
    BruteForce(cost, max_cost, row + 1, col_used, count + 1, total + cost(row, j), best);
    (*col_used)[sj] = 0;
  }
}

Objective BruteForceBest(const Eigen::MatrixXd& cost, double max_cost) {
  std::vector<char> col_used(static_cast<std::size_t>(cost.cols()), 0);
  Objective best{0, 0.0};
  BruteForce(cost, max_cost, 0, &col_used, 0, 0.0, &best);
  return best;
}

// Structural contract of Assignment: matches sorted by row, each row/column used at most once,
// only feasible pairs, and unmatched lists that are the sorted complements.
void CheckWellFormed(const Eigen::MatrixXd& cost, double max_cost, const Assignment& a) {
  std::vector<char> row_seen(static_cast<std::size_t>(cost.rows()), 0);
  std::vector<char> col_seen(static_cast<std::size_t>(cost.cols()), 0);
  for (std::size_t k = 0; k < a.matches.size(); ++k) {
    const auto [i, j] = a.matches[k];
    REQUIRE(i >= 0);
    REQUIRE(i < cost.rows());
    REQUIRE(j >= 0);
    REQUIRE(j < cost.cols());
    if (k > 0) REQUIRE(a.matches[k - 1].first < i);
    REQUIRE_FALSE(col_seen[static_cast<std::size_t>(j)]);
    row_seen[static_cast<std::size_t>(i)] = 1;
    col_seen[static_cast<std::size_t>(j)] = 1;
    REQUIRE(Feasible(cost(i, j), max_cost));
  }
  std::vector<int> expected_rows;
  std::vector<int> expected_cols;
  for (int i = 0; i < cost.rows(); ++i) {
    if (!row_seen[static_cast<std::size_t>(i)]) expected_rows.push_back(i);
  }
  for (int j = 0; j < cost.cols(); ++j) {
    if (!col_seen[static_cast<std::size_t>(j)]) expected_cols.push_back(j);
  }
  REQUIRE(a.unmatched_rows == expected_rows);
  REQUIRE(a.unmatched_cols == expected_cols);
}

double TotalCost(const Eigen::MatrixXd& cost, const Assignment& a) {
  double total = 0.0;
  for (const auto& [i, j] : a.matches) total += cost(i, j);
  return total;
}

enum class Flavour { kContinuous, kIntegerTies, kGated, kNonFinite };

Eigen::MatrixXd RandomCost(int rows, int cols, Flavour flavour, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_int_distribution<int> small_int(0, 3);
  Eigen::MatrixXd cost(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      switch (flavour) {
        case Flavour::kIntegerTies:
          cost(i, j) = static_cast<double>(small_int(*rng));
          break;
        case Flavour::kNonFinite: {
          const double u = uniform(*rng);
          const double c = uniform(*rng);
          cost(i, j) = u < 0.15 ? kNaN : (u < 0.3 ? kInf : (u < 0.35 ? -kInf : c));
          break;
        }
        case Flavour::kContinuous:
        case Flavour::kGated:
          cost(i, j) = uniform(*rng);
          break;
      }
    }
  }
  return cost;
}

TEST_CASE("SolveAssignment equals brute force on random small matrices", "[unit]") {
  std::mt19937 rng(20240611);
  const Flavour flavours[] = {
      Flavour::kContinuous, Flavour::kIntegerTies, Flavour::kGated, Flavour::kNonFinite};
  int checked = 0;
  for (int rows = 1; rows <= 6; ++rows) {
    for (int cols = 1; cols <= 6; ++cols) {
      for (const Flavour flavour : flavours) {
        for (int trial = 0; trial < 6; ++trial) {
          const Eigen::MatrixXd cost = RandomCost(rows, cols, flavour, &rng);
          // Gated: a threshold that forbids roughly half the pairs. Integer ties: forbid cost 3.
          const double max_cost =
              flavour == Flavour::kGated ? 0.5 : (flavour == Flavour::kIntegerTies ? 2.0 : kInf);
          const Assignment a = SolveAssignment(cost, max_cost);
          CheckWellFormed(cost, max_cost, a);
          const Objective best = BruteForceBest(cost, max_cost);
          INFO("shape " << rows << "x" << cols << " flavour " << static_cast<int>(flavour)
                        << " trial " << trial << "\n"
                        << cost);
          REQUIRE(static_cast<int>(a.matches.size()) == best.count);
          REQUIRE(TotalCost(cost, a) == Approx(best.cost).margin(1e-9));
          // Deterministic: the same input gives the same answer.
          const Assignment again = SolveAssignment(cost, max_cost);
          REQUIRE(again.matches == a.matches);
          ++checked;
        }
      }
    }
  }
  REQUIRE(checked == 36 * 4 * 6);
}

TEST_CASE("SolveAssignment matches disjoint feasible pairs, as the full solver would", "[unit]") {
  // Every row and column has at most one feasible pair: all of them are matched.
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(4, 5, 0.9);
  cost(0, 3) = 0.2;
  cost(2, 0) = 0.4;
  cost(3, 4) = 0.1;
  const Assignment a = SolveAssignment(cost, 0.5);
  REQUIRE(a.matches == std::vector<std::pair<int, int>>{{0, 3}, {2, 0}, {3, 4}});
  REQUIRE(a.unmatched_rows == std::vector<int>{1});
  REQUIRE(a.unmatched_cols == std::vector<int>{1, 2});
  // A second feasible pair in column 3 makes the pairs compete (the general solver runs): the
  // cheaper one wins and the rest is unchanged.
  cost(1, 3) = 0.3;
  const Assignment b = SolveAssignment(cost, 0.5);
  REQUIRE(b.matches == a.matches);
  REQUIRE(b.unmatched_rows == a.unmatched_rows);
  REQUIRE(b.unmatched_cols == a.unmatched_cols);
  cost(1, 3) = 0.1;
  const Assignment c = SolveAssignment(cost, 0.5);
  REQUIRE(c.matches == std::vector<std::pair<int, int>>{{1, 3}, {2, 0}, {3, 4}});
  REQUIRE(c.unmatched_rows == std::vector<int>{0});
}

TEST_CASE("SolveAssignment with a reused workspace equals the one-shot form", "[unit]") {
  std::mt19937 rng(20240612);
  const Flavour flavours[] = {
      Flavour::kContinuous, Flavour::kIntegerTies, Flavour::kGated, Flavour::kNonFinite};
  AssignmentWorkspace workspace;
  Assignment reused;
  int checked = 0;
  // Shapes grow and shrink so that stale buffer contents would show.
  for (int trial = 0; trial < 400; ++trial) {
    const int rows = 1 + static_cast<int>(rng() % 12);
    const int cols = 1 + static_cast<int>(rng() % 12);
    const Flavour flavour = flavours[rng() % 4];
    const Eigen::MatrixXd cost = RandomCost(rows, cols, flavour, &rng);
    const double max_cost = flavour == Flavour::kGated ? 0.5 : 2.0;
    const Assignment fresh = SolveAssignment(cost, max_cost);
    SolveAssignment(cost, max_cost, &workspace, &reused);
    REQUIRE(reused.matches == fresh.matches);
    REQUIRE(reused.unmatched_rows == fresh.unmatched_rows);
    REQUIRE(reused.unmatched_cols == fresh.unmatched_cols);
    ++checked;
  }
  REQUIRE(checked == 400);
}

TEST_CASE("SolveAssignment prefers more feasible matches over a cheaper partial one", "[unit]") {
  // Solving without the gate and dropping gated pairs afterwards would pick (0,0)+(1,1)
  // (total 0.61) and then lose (1,1) to the gate, leaving one match. Both rows can be
  // matched feasibly with (0,1)+(1,0).
  Eigen::MatrixXd cost(2, 2);
  cost << 0.0, 0.59, 0.59, 0.61;
  const Assignment a = SolveAssignment(cost, 0.6);
  const std::vector<std::pair<int, int>> expected = {{0, 1}, {1, 0}};
  REQUIRE(a.matches == expected);
  REQUIRE(a.unmatched_rows.empty());
  REQUIRE(a.unmatched_cols.empty());
}

TEST_CASE("SolveAssignment gating leaves rows and columns unmatched", "[unit]") {
  Eigen::MatrixXd cost(3, 3);
  cost << 0.1, 0.9, 0.9,  //
      0.9, 0.9, 0.9,      //
      0.9, 0.9, 0.2;
  const Assignment a = SolveAssignment(cost, 0.5);
  CheckWellFormed(cost, 0.5, a);
  const std::vector<std::pair<int, int>> expected = {{0, 0}, {2, 2}};
  REQUIRE(a.matches == expected);
  REQUIRE(a.unmatched_rows == std::vector<int>{1});
  REQUIRE(a.unmatched_cols == std::vector<int>{1});

  SECTION("everything above the gate") {
    const Assignment none = SolveAssignment(cost, 0.05);
    REQUIRE(none.matches.empty());
    REQUIRE(none.unmatched_rows == std::vector<int>{0, 1, 2});
    REQUIRE(none.unmatched_cols == std::vector<int>{0, 1, 2});
  }
  SECTION("a cost exactly at the gate is allowed") {
    const Assignment at_gate = SolveAssignment(cost, 0.9);
    REQUIRE(at_gate.matches.size() == 3);
  }
  SECTION("a NaN gate forbids everything") { REQUIRE(SolveAssignment(cost, kNaN).matches.empty()); }
}

TEST_CASE("SolveAssignment handles empty matrices", "[unit]") {
  const Assignment empty = SolveAssignment(Eigen::MatrixXd(0, 0), 1.0);
  REQUIRE(empty.matches.empty());
  REQUIRE(empty.unmatched_rows.empty());
  REQUIRE(empty.unmatched_cols.empty());

  const Assignment no_rows = SolveAssignment(Eigen::MatrixXd(0, 3), 1.0);
  REQUIRE(no_rows.matches.empty());
  REQUIRE(no_rows.unmatched_rows.empty());
  REQUIRE(no_rows.unmatched_cols == std::vector<int>{0, 1, 2});

  const Assignment no_cols = SolveAssignment(Eigen::MatrixXd(2, 0), 1.0);
  REQUIRE(no_cols.matches.empty());
  REQUIRE(no_cols.unmatched_rows == std::vector<int>{0, 1});
  REQUIRE(no_cols.unmatched_cols.empty());
}

TEST_CASE("SolveAssignment never matches NaN or infinite costs", "[unit]") {
  Eigen::MatrixXd cost(3, 2);
  cost << kNaN, 5.0,  //
      -kInf, kInf,    //
      kNaN, kNaN;
  // Even with an infinite gate, only finite costs are feasible; -inf is not "very cheap".
  const Assignment a = SolveAssignment(cost, kInf);
  CheckWellFormed(cost, kInf, a);
  const std::vector<std::pair<int, int>> expected = {{0, 1}};
  REQUIRE(a.matches == expected);
  REQUIRE(a.unmatched_rows == std::vector<int>{1, 2});
  REQUIRE(a.unmatched_cols == std::vector<int>{0});
}

TEST_CASE("SolveAssignment stays optimal for costs near the double range", "[unit]") {
  // Potentials are sums and differences of costs; at +-1.7e308 they would overflow to inf. A
  // power-of-two rescaling is exact, so the optimum of the huge matrix is the brute-force
  // optimum of its rescaled copy.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double down = std::ldexp(1.0, -1000);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::MatrixXd huge(5, 5);
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) huge(i, j) = 1.7e308 * uniform(rng);
    }
    const Assignment a = SolveAssignment(huge, kInf);
    CheckWellFormed(huge, kInf, a);
    const Eigen::MatrixXd small = huge * down;
    const Objective best = BruteForceBest(small, kInf);
    REQUIRE(static_cast<int>(a.matches.size()) == best.count);
    REQUIRE(TotalCost(small, a) == Approx(best.cost).epsilon(1e-12).margin(1e-6));
  }
}

TEST_CASE("SolveAssignment breaks ties towards low indices", "[unit]") {
  // All assignments cost the same; the solver scans rows and columns in index order.
  const Assignment square = SolveAssignment(Eigen::MatrixXd::Zero(4, 4), 1.0);
  const std::vector<std::pair<int, int>> diagonal = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  REQUIRE(square.matches == diagonal);

  const Assignment wide = SolveAssignment(Eigen::MatrixXd::Zero(2, 4), 1.0);
  const std::vector<std::pair<int, int>> wide_expected = {{0, 0}, {1, 1}};
  REQUIRE(wide.matches == wide_expected);
  REQUIRE(wide.unmatched_cols == std::vector<int>{2, 3});
}

TEST_CASE("SolveAssignment recovers a hidden permutation in a large matrix", "[unit]") {
  // 200 x 230: each row has one zero-cost column (a random injection), everything else costs
  // in [0.5, 1]; the unique optimum is the hidden injection.
  constexpr int kRows = 200;
  constexpr int kCols = 230;
  std::mt19937 rng(7);
  std::vector<int> perm(kCols);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::uniform_real_distribution<double> uniform(0.5, 1.0);
  Eigen::MatrixXd cost(kRows, kCols);
  for (int i = 0; i < kRows; ++i) {
    for (int j = 0; j < kCols; ++j) cost(i, j) = uniform(rng);
    cost(i, perm[static_cast<std::size_t>(i)]) = 0.0;
  }
  for (const bool transpose : {false, true}) {
    const Eigen::MatrixXd c = transpose ? Eigen::MatrixXd(cost.transpose()) : cost;
    const Assignment a = SolveAssignment(c, 1.0);
    CheckWellFormed(c, 1.0, a);
    REQUIRE(a.matches.size() == kRows);
    for (const auto& [i, j] : a.matches) {
      REQUIRE(c(i, j) == 0.0);
    }
  }
}

}  // namespace
}  // namespace mvtrack::core
