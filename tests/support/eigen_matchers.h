#pragma once
/// @file
/// Eigen-aware Catch2 (v2) matchers for geometric tolerances in tests:
///
///   REQUIRE_THAT(point, IsApproxVec(expected_point, 1e-9));
///   REQUIRE_THAT(f_ba, IsApproxUpToScale(f_ab.transpose(), 1e-9));
///
/// Both accept any Eigen dense matrix or vector (fixed or dynamic size); the actual value is
/// converted to the expected value's plain type. On failure the description prints the expected
/// and actual values on one line (row-major, `;` between rows) and where the largest deviation
/// occurred. Single-threaded use only (a matcher remembers the last mismatch for its message).

#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace mvtrack::testing {
namespace internal {

/// One-line rendering of a matrix: "[a, b, c]" for vectors, "[a, b; c, d]" for matrices.
template <typename Derived>
std::string FormatMatrix(const Eigen::DenseBase<Derived>& m) {
  std::ostringstream os;
  os << std::setprecision(12) << '[';
  const bool vector = m.rows() == 1 || m.cols() == 1;
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      if (r > 0 || c > 0) os << ((c == 0 && !vector) ? "; " : ", ");
      os << m(r, c);
    }
  }
  os << ']';
  return os.str();
}

/// Largest absolute entry-wise difference; +inf if shapes differ or any entry is non-finite.
/// Stores the offending (row, col) in `*where_row`, `*where_col`.
template <typename A, typename B>
double MaxAbsDiff(const Eigen::DenseBase<A>& a,
                  const Eigen::DenseBase<B>& b,
                  Eigen::Index* where_row,
                  Eigen::Index* where_col) {
  *where_row = -1;
  *where_col = -1;
  if (a.rows() != b.rows() || a.cols() != b.cols()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    for (Eigen::Index c = 0; c < a.cols(); ++c) {
      const double d = std::abs(static_cast<double>(a(r, c)) - static_cast<double>(b(r, c)));
      // `!(d <= worst)` also catches NaN, which then counts as an infinite deviation.
      if (!(d <= worst)) {
        worst = std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
        *where_row = r;
        *where_col = c;
        if (!std::isfinite(d)) return worst;
      }
    }
  }
  return worst;
}

}  // namespace internal

/// Matches when every entry of the actual value is within `tol` (absolute) of the expected one.
/// Shapes must agree; NaN or infinite entries never match.
template <typename Plain>
class IsApproxMatcher final : public Catch::MatcherBase<Plain> {
 public:
  /// `expected`: reference value; `tol`: maximum absolute per-entry difference.
  IsApproxMatcher(Plain expected, double tol) : expected_(std::move(expected)), tol_(tol) {}

  /// Whether `actual` is entry-wise within `tol` of the expected value.
  bool match(const Plain& actual) const override {
    Eigen::Index r = -1, c = -1;
    const double diff = internal::MaxAbsDiff(actual, expected_, &r, &c);
    std::ostringstream os;
    os << std::setprecision(6) << "; actual " << internal::FormatMatrix(actual);
    if (actual.rows() != expected_.rows() || actual.cols() != expected_.cols()) {
      os << " has shape " << actual.rows() << "x" << actual.cols() << ", expected "
         << expected_.rows() << "x" << expected_.cols();
    } else {
      os << ", max |diff| " << diff << " at (" << r << ", " << c << ")";
    }
    last_ = os.str();
    return diff <= tol_;
  }

  /// "is within <tol> (per entry) of [expected]" plus the last actual value and deviation.
  std::string describe() const override {
    std::ostringstream os;
    os << "is within " << tol_ << " (per entry) of " << internal::FormatMatrix(expected_) << last_;
    return os.str();
  }

 private:
  Plain expected_;
  double tol_;
  mutable std::string last_;
};

/// Entry-wise absolute comparison of vectors (or matrices) with tolerance `tol`.
template <typename Derived>
IsApproxMatcher<typename Derived::PlainObject> IsApproxVec(
    const Eigen::MatrixBase<Derived>& expected, double tol) {
  return IsApproxMatcher<typename Derived::PlainObject>(expected.eval(), tol);
}

/// Matches homogeneous quantities (fundamental matrices, lines, homogeneous points) that are
/// equal up to a non-zero scale factor, including its sign: both sides are divided by their
/// Frobenius norm, the sign that best aligns them is chosen, and the result must agree entry-wise
/// within `tol`. Two zero values match each other; a zero value never matches a non-zero one.
template <typename Plain>
class IsApproxUpToScaleMatcher final : public Catch::MatcherBase<Plain> {
 public:
  /// `expected`: reference value (any non-zero scale); `tol`: per-entry tolerance after
  /// normalisation to unit Frobenius norm.
  IsApproxUpToScaleMatcher(Plain expected, double tol)
      : expected_(std::move(expected)), tol_(tol) {}

  /// Whether `actual` equals the expected value up to scale.
  bool match(const Plain& actual) const override {
    std::ostringstream os;
    os << std::setprecision(6) << "; actual " << internal::FormatMatrix(actual);
    if (actual.rows() != expected_.rows() || actual.cols() != expected_.cols()) {
      os << " has a different shape";
      last_ = os.str();
      return false;
    }
    const double na = actual.norm(), ne = expected_.norm();
    if (!std::isfinite(na) || !std::isfinite(ne)) {
      os << " (non-finite)";
      last_ = os.str();
      return false;
    }
    if (na == 0.0 || ne == 0.0) {
      os << " (zero norm: actual " << na << ", expected " << ne << ")";
      last_ = os.str();
      return na == 0.0 && ne == 0.0;
    }
    const Plain a = actual / na;
    const Plain e = expected_ / ne;
    Eigen::Index r1 = -1, c1 = -1, r2 = -1, c2 = -1;
    const double same = internal::MaxAbsDiff(a, e, &r1, &c1);
    const double flipped = internal::MaxAbsDiff(a, (-e).eval(), &r2, &c2);
    const double diff = std::min(same, flipped);
    os << ", max |diff| after normalisation " << diff;
    last_ = os.str();
    return diff <= tol_;
  }

  /// "equals [expected] up to scale within <tol>" plus the last actual value and deviation.
  std::string describe() const override {
    std::ostringstream os;
    os << "equals " << internal::FormatMatrix(expected_)
       << " up to scale (unit-norm entries within " << tol_ << ")" << last_;
    return os.str();
  }

 private:
  Plain expected_;
  double tol_;
  mutable std::string last_;
};

/// Comparison up to a non-zero scale factor (see IsApproxUpToScaleMatcher).
template <typename Derived>
IsApproxUpToScaleMatcher<typename Derived::PlainObject> IsApproxUpToScale(
    const Eigen::MatrixBase<Derived>& expected, double tol) {
  return IsApproxUpToScaleMatcher<typename Derived::PlainObject>(expected.eval(), tol);
}

}  // namespace mvtrack::testing
