// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/common/error.h"
#include "core/spline/knot_insertion.h"

using volspline::Error;
using volspline::spline::BlendingKnots;
using volspline::spline::BlendingSplit;
using volspline::spline::cubic_basis;
using volspline::spline::insert_knot;
using volspline::spline::KnotInsertion;
using volspline::spline::LocalKnots;
using volspline::spline::RightEnd;
using volspline::spline::split_blending_function;

namespace {

// max over a dense sweep of [r0, r4] of |N_R − (c1 N_R1 + c2 N_R2)|, for both end conventions.
double insertion_error(const LocalKnots& r, double k) {
  const KnotInsertion ins = insert_knot(r, k);
  double worst = 0.0;
  std::vector<double> ts(r.begin(), r.end());
  ts.push_back(k);
  for (int i = 0; i <= 2000; ++i) ts.push_back(r[0] + (r[4] - r[0]) * i / 2000.0);
  for (double t : ts) {
    const double open = ins.first_coefficient * cubic_basis(ins.first, t) +
                        ins.second_coefficient * cubic_basis(ins.second, t);
    worst = std::max(worst, std::abs(cubic_basis(r, t) - open));
    // Closed at r4: the children ending at r4 are closed too (a child ending before r4 is not).
    const auto end_of = [&r](const LocalKnots& c) { return c[4] == r[4] ? RightEnd::Closed : RightEnd::Open; };
    const double closed = ins.first_coefficient * cubic_basis(ins.first, t, end_of(ins.first)) +
                          ins.second_coefficient * cubic_basis(ins.second, t, end_of(ins.second));
    worst = std::max(worst, std::abs(cubic_basis(r, t, RightEnd::Closed) - closed));
  }
  return worst;
}

}  // namespace

TEST_CASE("Table 4.1 knot vectors for every row") {
  const LocalKnots r = {0, 1, 2, 4, 8};
  struct Row {
    double k;
    LocalKnots first, second;
  };
  const Row rows[] = {{0.5, {0, 0.5, 1, 2, 4}, {0.5, 1, 2, 4, 8}},
                      {1.5, {0, 1, 1.5, 2, 4}, {1, 1.5, 2, 4, 8}},
                      {3.0, {0, 1, 2, 3, 4}, {1, 2, 3, 4, 8}},
                      {6.0, {0, 1, 2, 4, 6}, {1, 2, 4, 6, 8}},
                      {8.0, {0, 1, 2, 4, 8}, {1, 2, 4, 8, 8}}};
  for (const Row& row : rows) {
    CAPTURE(row.k);
    const KnotInsertion ins = insert_knot(r, row.k);
    CHECK(ins.first == row.first);
    CHECK(ins.second == row.second);
    // Eq. 4.8 weights, by hand.
    CHECK(ins.first_coefficient == doctest::Approx(std::min(row.k / 4.0, 1.0)).epsilon(1e-15));
    CHECK(ins.second_coefficient == doctest::Approx(std::min((8.0 - row.k) / 7.0, 1.0)).epsilon(1e-15));
  }
}

TEST_CASE("knot insertion leaves the basis function unchanged") {
  const std::vector<LocalKnots> vectors = {
      {0, 1, 2, 3, 4},   {0, 0.1, 0.15, 2, 7}, {0, 0, 0, 0, 1},   {0, 1, 1, 1, 1},
      {0, 0, 1, 1, 3},   {-2, 1, 1, 1, 1.5},   {0, 0.5, 0.5, 0.5, 2}, {0, 0, 0, 1, 2}};
  for (const LocalKnots& r : vectors) {
    std::vector<double> ks(r.begin(), r.end());                            // at every knot (repeated)
    for (int i = 0; i < 4; ++i) {
      for (double f : {0.01, 0.5, 0.99}) ks.push_back(r[i] + f * (r[i + 1] - r[i]));  // in every interval
    }
    for (double k : ks) {
      CAPTURE(r[0]);
      CAPTURE(r[4]);
      CAPTURE(k);
      // Exact identity up to rounding: 1e-12.
      CHECK(insertion_error(r, k) < 1e-12);
      const KnotInsertion ins = insert_knot(r, k);
      CHECK(ins.first_coefficient >= 0.0);
      CHECK(ins.first_coefficient <= 1.0);
      CHECK(ins.second_coefficient >= 0.0);
      CHECK(ins.second_coefficient <= 1.0);
    }
  }
}

TEST_CASE("zero denominators at repeated knots") {
  // r3 = r0: c1 = min(x/0, 1) = 1 for k > r0.
  KnotInsertion ins = insert_knot({0, 0, 0, 0, 1}, 0.25);
  CHECK(ins.first_coefficient == 1.0);
  CHECK(ins.second_coefficient == doctest::Approx(0.75).epsilon(1e-15));
  CHECK(ins.first == LocalKnots{0, 0, 0, 0, 0.25});
  // r4 = r1: c2 = 1 for k < r4.
  ins = insert_knot({0, 1, 1, 1, 1}, 0.25);
  CHECK(ins.first_coefficient == doctest::Approx(0.25).epsilon(1e-15));
  CHECK(ins.second_coefficient == 1.0);
  // Inserting at an end knot: a zero coefficient or a zero child, the other child is R itself.
  ins = insert_knot({0, 1, 2, 3, 4}, 0.0);
  CHECK(ins.first_coefficient == 0.0);
  CHECK(ins.second == LocalKnots{0, 1, 2, 3, 4});
  CHECK(ins.second_coefficient == 1.0);
  ins = insert_knot({0, 1, 2, 3, 4}, 4.0);
  CHECK(ins.first == LocalKnots{0, 1, 2, 3, 4});
  CHECK(ins.first_coefficient == 1.0);
  CHECK(ins.second_coefficient == 0.0);
}

TEST_CASE("splitting a blending function along one axis (Eq. 4.9)") {
  const BlendingKnots knots = {LocalKnots{0, 1, 2, 3, 4}, LocalKnots{0, 0, 0.5, 1, 1.5}, LocalKnots{2, 2, 2, 2, 3}};
  for (int axis = 0; axis < 3; ++axis) {
    const double k = 0.5 * (knots[axis][1] + knots[axis][3]) + 0.01;
    const BlendingSplit split = split_blending_function(knots, axis, k);
    for (int other = 0; other < 3; ++other) {
      if (other != axis) {
        CHECK(split.first[other] == knots[other]);
        CHECK(split.second[other] == knots[other]);
      }
    }
    for (int i = 0; i < 200; ++i) {
      double b = 1.0, b1 = 1.0, b2 = 1.0;
      for (int a = 0; a < 3; ++a) {
        const double t = knots[a][0] + (knots[a][4] - knots[a][0]) * std::fmod(0.137 * (i + 1) * (a + 2), 1.0);
        b *= cubic_basis(knots[a], t);
        b1 *= cubic_basis(split.first[a], t);
        b2 *= cubic_basis(split.second[a], t);
      }
      CHECK(std::abs(b - split.first_coefficient * b1 - split.second_coefficient * b2) < 1e-12);
    }
  }
}

TEST_CASE("knot outside the knot vector is refused") {
  CHECK_THROWS_WITH_AS(insert_knot({0, 1, 2, 3, 4}, 5.0),
                       "knot insertion: knot 5.000000 is outside the knot vector [0.000000, 4.000000]", Error);
  CHECK_THROWS_WITH_AS(insert_knot({0, 1, 2, 3, 4}, -1.0),
                       "knot insertion: knot -1.000000 is outside the knot vector [0.000000, 4.000000]", Error);
  CHECK_THROWS_AS(insert_knot({0, 1, 2, 3, 4}, std::numeric_limits<double>::quiet_NaN()), Error);
  const BlendingKnots knots = {LocalKnots{0, 1, 2, 3, 4}, LocalKnots{0, 1, 2, 3, 4}, LocalKnots{0, 1, 2, 3, 4}};
  CHECK_THROWS_AS(split_blending_function(knots, 1, 9.0), Error);
}
