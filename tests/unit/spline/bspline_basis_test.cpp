// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/spline/bspline_basis.h"

using volspline::spline::BasisDerivatives;
using volspline::spline::cubic_basis;
using volspline::spline::cubic_basis_derivatives;
using volspline::spline::cubic_basis_interval;
using volspline::spline::local_knots_valid;
using volspline::spline::LocalKnots;
using volspline::spline::RightEnd;

namespace {

// Σ_i N_i(t) over all cubic basis functions of a clamped global knot vector, with the functions
// that end at the domain end closed there.
double basis_sum(const std::vector<double>& knots, double t) {
  double sum = 0.0;
  for (size_t i = 0; i + 4 < knots.size(); ++i) {
    const LocalKnots r = {knots[i], knots[i + 1], knots[i + 2], knots[i + 3], knots[i + 4]};
    sum += cubic_basis(r, t, r[4] == knots.back() ? RightEnd::Closed : RightEnd::Open);
  }
  return sum;
}

// Parameters over [a, b]: the knots themselves, both ends, and a regular sweep.
std::vector<double> sample_parameters(const std::vector<double>& knots) {
  std::vector<double> ts(knots.begin(), knots.end());
  const double a = knots.front(), b = knots.back();
  for (int i = 0; i <= 997; ++i) ts.push_back(a + (b - a) * i / 997.0);
  return ts;
}

}  // namespace

TEST_CASE("uniform cubic basis has the textbook values") {
  const LocalKnots r = {0, 1, 2, 3, 4};
  CHECK(cubic_basis(r, 0.0) == 0.0);
  CHECK(cubic_basis(r, 1.0) == doctest::Approx(1.0 / 6.0).epsilon(1e-15));
  CHECK(cubic_basis(r, 2.0) == doctest::Approx(2.0 / 3.0).epsilon(1e-15));
  CHECK(cubic_basis(r, 3.0) == doctest::Approx(1.0 / 6.0).epsilon(1e-15));
  CHECK(cubic_basis(r, 4.0) == 0.0);
  CHECK(cubic_basis(r, 0.5) == doctest::Approx(0.125 / 6.0).epsilon(1e-15));
  // Symmetry N(t) = N(4 - t).
  for (double t = 0.0; t < 4.0; t += 0.1) CHECK(std::abs(cubic_basis(r, t) - cubic_basis(r, 4.0 - t)) < 1e-15);
  CHECK(cubic_basis(r, -0.1) == 0.0);
  CHECK(cubic_basis(r, 4.1) == 0.0);
  CHECK(cubic_basis(r, std::numeric_limits<double>::quiet_NaN()) == 0.0);
}

TEST_CASE("partition of unity on clamped knot vectors") {
  // Exact identity up to rounding: tolerance 1e-12.
  const std::vector<std::vector<double>> knot_vectors = {
      {0, 0, 0, 0, 1, 1, 1, 1},                                  // Bernstein (Bezier) basis
      {0, 0, 0, 0, 1, 2, 3, 4, 5, 5, 5, 5},                      // uniform interior
      {-1, -1, -1, -1, -0.7, 0.01, 0.02, 1.5, 3, 3, 3, 3},       // non-uniform
      {0, 0, 0, 0, 0.3, 0.3, 0.5, 0.9, 0.9, 0.9, 1, 1, 1, 1},    // interior multiplicity 2 and 3
  };
  for (const auto& knots : knot_vectors) {
    for (double t : sample_parameters(knots)) {
      CAPTURE(t);
      CHECK(std::abs(basis_sum(knots, t) - 1.0) < 1e-12);
    }
  }
}

TEST_CASE("repeated knots give the closed forms and follow 0/0 := 0") {
  const LocalKnots left_end = {0, 0, 0, 0, 1};   // (1 - t)^3
  const LocalKnots right_end = {0, 1, 1, 1, 1};  // t^3
  const LocalKnots double_knot = {0, 0, 0, 1, 2};
  for (double t = 0.0; t < 1.0; t += 0.03125) {
    CHECK(cubic_basis(left_end, t) == doctest::Approx(std::pow(1 - t, 3)).epsilon(1e-14));
    CHECK(cubic_basis(right_end, t) == doctest::Approx(t * t * t).epsilon(1e-14));
    const BasisDerivatives d = cubic_basis_derivatives(left_end, t);
    CHECK(d.d1 == doctest::Approx(-3 * (1 - t) * (1 - t)).epsilon(1e-14));
    CHECK(d.d2 == doctest::Approx(6 * (1 - t)).epsilon(1e-14));
    CHECK(d.d3 == doctest::Approx(-6.0).epsilon(1e-14));
  }
  // [0,0,0,1,2] on [0,1): t(4 - 3t)... check via its value at 1 = 1/4 and the C1 knot at 0.
  CHECK(cubic_basis(double_knot, 1.0) == doctest::Approx(0.25).epsilon(1e-15));
  CHECK(cubic_basis(double_knot, 0.0) == 0.0);
  // At the right end: open support gives 0, closed gives the left limit.
  CHECK(cubic_basis(right_end, 1.0, RightEnd::Open) == 0.0);
  CHECK(cubic_basis(right_end, 1.0, RightEnd::Closed) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(cubic_basis_derivatives(right_end, 1.0, RightEnd::Closed).d1 == doctest::Approx(3.0).epsilon(1e-15));
  // All knots equal: the zero function, even when closed.
  const LocalKnots zero = {1, 1, 1, 1, 1};
  CHECK(cubic_basis(zero, 1.0, RightEnd::Closed) == 0.0);
  CHECK(cubic_basis_interval(zero, 1.0, RightEnd::Closed) == -1);
  // Interval lookup skips empty intervals.
  CHECK(cubic_basis_interval(double_knot, 0.0, RightEnd::Open) == 2);
  CHECK(cubic_basis_interval(right_end, 1.0, RightEnd::Closed) == 0);
  CHECK(cubic_basis_interval({0, 1, 2, 3, 4}, 2.0, RightEnd::Open) == 2);
}

TEST_CASE("derivatives match central finite differences") {
  const std::vector<LocalKnots> vectors = {
      {0, 1, 2, 3, 4}, {0, 0.1, 0.15, 2, 7}, {0, 0, 0, 0, 1}, {0, 0, 1, 1, 3}, {-2, 1, 1, 1, 1.5}, {0, 0.5, 0.5, 0.5, 2}};
  const double h = 1e-6;
  for (const LocalKnots& r : vectors) {
    for (int i = 1; i < 400; ++i) {
      const double t = r[0] + (r[4] - r[0]) * i / 400.0;
      // Keep the stencil inside one polynomial piece.
      bool near_knot = false;
      for (double k : r) near_knot = near_knot || std::abs(t - k) < 2 * h;
      if (near_knot) continue;
      CAPTURE(t);
      const BasisDerivatives d = cubic_basis_derivatives(r, t);
      const BasisDerivatives plus = cubic_basis_derivatives(r, t + h);
      const BasisDerivatives minus = cubic_basis_derivatives(r, t - h);
      // Central differences: truncation O(h² |f'''|) plus rounding O(eps/h), far below 1e-6.
      CHECK(std::abs((plus.value - minus.value) / (2 * h) - d.d1) <= 1e-6 * std::max(1.0, std::abs(d.d1)));
      CHECK(std::abs((plus.d1 - minus.d1) / (2 * h) - d.d2) <= 1e-6 * std::max(1.0, std::abs(d.d2)));
      CHECK(std::abs((plus.d2 - minus.d2) / (2 * h) - d.d3) <= 1e-6 * std::max(1.0, std::abs(d.d3)));
      CHECK(d.value == doctest::Approx(cubic_basis(r, t)).epsilon(1e-15));
    }
  }
}

TEST_CASE("knot vector validity") {
  CHECK(local_knots_valid({0, 1, 2, 3, 4}));
  CHECK(local_knots_valid({0, 0, 0, 0, 1}));
  CHECK_FALSE(local_knots_valid({1, 1, 1, 1, 1}));
  CHECK_FALSE(local_knots_valid({0, 2, 1, 3, 4}));
  CHECK_FALSE(local_knots_valid({0, 1, 2, 3, std::numeric_limits<double>::infinity()}));
  CHECK_FALSE(local_knots_valid({0, 1, std::numeric_limits<double>::quiet_NaN(), 3, 4}));
}
