// Numeric checks for the exercise tests that stop the test case at the first failure and say what
// was expected, what the exercise returned, by how much they differ and what tolerance applies.
//
//   REQUIRE_NEAR(got, expected, tol)   |got - expected| <= tol (Eigen: the norm of the difference)
//   REQUIRE_REL(got, expected, rel)    |got - expected| <= rel |expected| (Approx(..).epsilon(rel))
//   REQUIRE_BELOW(got, bound)          got < bound
//   REQUIRE_ABOVE(got, bound)          got > bound
//
// Each is one Catch assertion: it passes silently or FAILs the test case with the numbers in
// scientific notation (for a vector or matrix also the worst entry and its index, and the whole
// difference when it is at most 6x6). A stub's NotImplemented escapes from `got` and ends the test
// case with its one-line message.
#pragma once

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

namespace legkit::exercise_check {

// A check's outcome: ok, or the report FAIL prints.
struct Verdict {
  bool ok = true;
  std::string report;
};

// A value, with every digit a double holds, and a difference or tolerance, short.
inline std::string sci(double x, int digits = 15) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*e", digits, x);
  return buf;
}

// got - expected of a small matrix, one row per line, indented.
template <typename Derived>
std::string differenceLines(const Eigen::MatrixBase<Derived>& diff) {
  std::string out = "    got - expected\n";
  for (Eigen::Index i = 0; i < diff.rows(); ++i) {
    out += "     ";
    for (Eigen::Index j = 0; j < diff.cols(); ++j) {
      char buf[24];
      std::snprintf(buf, sizeof buf, " %10.2e", diff(i, j));
      out += buf;
    }
    out += "\n";
  }
  return out;
}

inline Verdict nearScalar(double got, double expected, double tol, const char* tol_kind,
                          const char* got_expr, const char* expected_expr) {
  const double diff = std::abs(got - expected);
  if (diff <= tol) return {};  // a NaN anywhere fails here
  return {false, std::string(got_expr) + "\n  should be close to " + expected_expr +
                     "\n    expected  " + sci(expected) + "\n    got       " + sci(got) +
                     "\n    |diff|    " + sci(diff, 3) + "  >  " + tol_kind + " " + sci(tol, 3)};
}

inline Verdict near(double got, double expected, double tol, const char* got_expr,
                    const char* expected_expr) {
  return nearScalar(got, expected, tol, "tolerance", got_expr, expected_expr);
}

inline Verdict relative(double got, double expected, double rel, const char* got_expr,
                        const char* expected_expr) {
  return nearScalar(got, expected, rel * std::abs(expected),
                    ("tolerance " + sci(rel, 3) + " x |expected| =").c_str(), got_expr,
                    expected_expr);
}

// Vectors and matrices: the norm (Frobenius) of the difference against tol.
template <typename A, typename B>
Verdict near(const Eigen::MatrixBase<A>& got, const Eigen::MatrixBase<B>& expected, double tol,
             const char* got_expr, const char* expected_expr) {
  const std::string head = std::string(got_expr) + "\n  should be close to " + expected_expr;
  if (got.rows() != expected.rows() || got.cols() != expected.cols())
    return {false, head + "\n    expected a " + std::to_string(expected.rows()) + "x" +
                       std::to_string(expected.cols()) + " result, got " +
                       std::to_string(got.rows()) + "x" + std::to_string(got.cols())};
  const auto diff = (got.template cast<double>() - expected.template cast<double>()).eval();
  const double norm = diff.norm();
  if (norm <= tol) return {};
  Eigen::Index wi = 0, wj = 0;
  for (Eigen::Index i = 0; i < diff.rows(); ++i)
    for (Eigen::Index j = 0; j < diff.cols(); ++j)
      if (!(std::abs(diff(wi, wj)) >= std::abs(diff(i, j)))) wi = i, wj = j;  // NaN wins
  const std::string index = diff.cols() == 1
                                ? "(" + std::to_string(wi) + ")"
                                : "(" + std::to_string(wi) + ", " + std::to_string(wj) + ")";
  std::string report = head + "\n    |got - expected|  " + sci(norm, 3) + "  >  tolerance " +
                       sci(tol, 3) + "\n    worst entry " + index + "\n      expected  " +
                       sci(static_cast<double>(expected(wi, wj))) + "\n      got       " +
                       sci(static_cast<double>(got(wi, wj)));
  if (got.rows() <= 6 && got.cols() <= 6) report += "\n" + differenceLines(diff);
  return {false, report};
}

inline Verdict compare(double got, double bound, bool below, const char* got_expr,
                       const char* bound_expr) {
  if (below ? got < bound : got > bound) return {};
  return {false, std::string(got_expr) + "\n  should be " + (below ? "below " : "above ") +
                     bound_expr + "\n    bound     " + sci(bound) + "\n    got       " + sci(got)};
}

}  // namespace legkit::exercise_check

#define LEGKIT_EXERCISE_VERDICT(verdict_expr)                               \
  do {                                                                      \
    const ::legkit::exercise_check::Verdict legkit_verdict_ = verdict_expr; \
    if (legkit_verdict_.ok)                                                 \
      SUCCEED();                                                            \
    else                                                                    \
      FAIL(legkit_verdict_.report);                                         \
  } while (false)

#define REQUIRE_NEAR(got, expected, tol) \
  LEGKIT_EXERCISE_VERDICT(::legkit::exercise_check::near((got), (expected), (tol), #got, #expected))
#define REQUIRE_REL(got, expected, rel) \
  LEGKIT_EXERCISE_VERDICT(              \
      ::legkit::exercise_check::relative((got), (expected), (rel), #got, #expected))
#define REQUIRE_BELOW(got, bound) \
  LEGKIT_EXERCISE_VERDICT(::legkit::exercise_check::compare((got), (bound), true, #got, #bound))
#define REQUIRE_ABOVE(got, bound) \
  LEGKIT_EXERCISE_VERDICT(::legkit::exercise_check::compare((got), (bound), false, #got, #bound))
