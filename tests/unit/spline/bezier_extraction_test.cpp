// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/spline/bezier_extraction.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/tspline.h"
#include "tests/unit/spline/random_tspline.h"

using volspline::spline::BezierCell;
using volspline::spline::BlendingKnots;
using volspline::spline::boundary_restricted_knots;
using volspline::spline::BsplineVolume;
using volspline::spline::evaluate_bezier_cell;
using volspline::spline::extract_bezier_cells;
using volspline::spline::from_bspline_volume;
using volspline::spline::LocalKnots;
using volspline::spline::TSpline;
using volspline::spline::TSplineAcceleration;
using volspline::spline::TSplineForm;
using volspline::test::random_tspline;

namespace {

// Boehm's knot insertion of t into a clamped cubic curve (knots U, control rows P, D columns).
void insert_knot_curve(std::vector<double>& U, std::vector<std::vector<double>>& P, double t) {
  int s = 3;
  while (s + 1 < int(U.size()) - 4 && U[s + 1] <= t) ++s;
  std::vector<std::vector<double>> Q;
  for (int i = 0; i <= int(P.size()); ++i) {
    if (i <= s - 3) {
      Q.push_back(P[i]);
    } else if (i > s) {
      Q.push_back(P[i - 1]);
    } else {
      const double a = (t - U[i]) / (U[i + 3] - U[i]);
      std::vector<double> q(P[i].size());
      for (size_t d = 0; d < q.size(); ++d) q[d] = (1 - a) * P[i - 1][d] + a * P[i][d];
      Q.push_back(q);
    }
  }
  U.insert(U.begin() + s + 1, t);
  P = Q;
}

}  // namespace

TEST_CASE("Bézier cells evaluate like the T-spline (both forms, values and Jacobians)") {
  for (TSplineAcceleration acceleration : {TSplineAcceleration::CellPolynomials, TSplineAcceleration::FunctionLists}) {
    for (int dimension = 1; dimension <= 4; ++dimension) {
      const TSpline spline = random_tspline(40, dimension, 7 + dimension, acceleration);
      const std::vector<BezierCell> cells = extract_bezier_cells(spline);
      REQUIRE(int(cells.size()) == spline.num_cells());
      std::mt19937 rng(3);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      double worst = 0, worst_rational = 0, worst_jacobian = 0;
      for (int sample = 0; sample < 2000; ++sample) {
        const BezierCell& cell = cells[sample % cells.size()];
        const Eigen::Vector3d s(unit(rng), unit(rng), unit(rng));
        const Eigen::Vector3d uvw = cell.uvw_min + s.cwiseProduct(cell.uvw_max - cell.uvw_min);
        if (spline.cell_of(uvw) != cell.cell) continue;  // s = 1 rounds into the next cell
        double value[4], jacobian[12];
        evaluate_bezier_cell(cell, s, value, jacobian);
        const Eigen::VectorXd expected = spline.evaluate(uvw, TSplineForm::SemiStandard);
        const Eigen::MatrixXd expected_jacobian = spline.jacobian(uvw, TSplineForm::SemiStandard);
        double b[3][4];
        for (int a = 0; a < 3; ++a) volspline::spline::cubic_bernstein(s[a], b[a]);
        double weight = 0;
        Eigen::VectorXd rational = Eigen::VectorXd::Zero(dimension);
        for (int n = 0; n < 64; ++n) {
          const double basis = b[0][n % 4] * b[1][(n / 4) % 4] * b[2][n / 16];
          weight += basis * cell.weights[n];
          for (int d = 0; d < dimension; ++d) rational[d] += basis * cell.points[n * dimension + d];
        }
        rational /= weight;
        if (spline.weight_sum(uvw) < 0.1) continue;  // near an uncovered part the quotient is ill-conditioned
        const Eigen::VectorXd expected_rational = spline.evaluate(uvw, TSplineForm::Rational);
        for (int d = 0; d < dimension; ++d) {
          worst = std::max(worst, std::abs(value[d] - expected[d]));
          worst_rational = std::max(worst_rational, std::abs(rational[d] - expected_rational[d]));
          for (int a = 0; a < 3; ++a)
            worst_jacobian = std::max(worst_jacobian, std::abs(jacobian[d + dimension * a] - expected_jacobian(d, a)));
        }
      }
      CHECK(worst < 1e-13);
      CHECK(worst_rational < 1e-13);
      CHECK(worst_jacobian < 1e-11);  // widths down to 0.05: derivatives scale by 1/width
    }
  }
}

TEST_CASE("Bézier nets of a B-spline volume equal knot insertion to full multiplicity") {
  std::array<std::vector<double>, 3> knots = {boundary_restricted_knots({0.0, 0.2, 0.25, 0.6, 1.0}),
                                              boundary_restricted_knots({-1.0, 0.5, 1.0, 3.0}),
                                              std::vector<double>{2, 2, 2, 2, 2.5, 2.5, 3, 3, 3, 3}};
  const int n0 = int(knots[0].size()) - 4, n1 = int(knots[1].size()) - 4, n2 = int(knots[2].size()) - 4;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd points(n0 * n1 * n2, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int d = 0; d < 3; ++d) points(i, d) = normal(rng);
  const BsplineVolume volume(knots, points);
  const TSpline spline = from_bspline_volume(volume, TSplineAcceleration::FunctionLists);

  // Knot insertion per axis until every interior knot has multiplicity 3: the control grid is
  // then the union of the Bézier nets (cell c's net starts at control index 3·c per axis).
  std::array<int, 3> n = {n0, n1, n2};
  std::vector<std::vector<double>> cp(points.rows(), std::vector<double>(3));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int d = 0; d < 3; ++d) cp[i][d] = points(i, d);
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> U = knots[axis];
    std::vector<double> inserts;
    for (size_t k = 4; k + 4 < knots[axis].size(); ++k) {
      const double t = knots[axis][k];
      const int mult = int(std::count(knots[axis].begin(), knots[axis].end(), t));
      if (k == 4 || knots[axis][k - 1] != t)
        for (int m = mult; m < 3; ++m) inserts.push_back(t);
    }
    std::array<int, 3> m = n;
    m[axis] = n[axis] + int(inserts.size());
    std::vector<std::vector<double>> next(size_t(m[0]) * m[1] * m[2]);
    const int other[2] = {axis == 0 ? 1 : 0, axis == 2 ? 1 : 2};
    for (int p = 0; p < n[other[0]]; ++p)
      for (int q = 0; q < n[other[1]]; ++q) {
        auto at = [&](const std::array<int, 3>& dims, int t) {
          std::array<int, 3> idx{};
          idx[axis] = t, idx[other[0]] = p, idx[other[1]] = q;
          return idx[0] + dims[0] * (idx[1] + dims[1] * idx[2]);
        };
        std::vector<std::vector<double>> curve;
        for (int t = 0; t < n[axis]; ++t) curve.push_back(cp[at(n, t)]);
        std::vector<double> Ucopy = U;
        for (double t : inserts) insert_knot_curve(Ucopy, curve, t);
        for (int t = 0; t < m[axis]; ++t) next[at(m, t)] = curve[t];
      }
    cp = next;
    n = m;
  }
  double worst = 0;
  for (int c = 0; c < spline.num_cells(); ++c) {
    const BezierCell cell = volspline::spline::extract_bezier_cell(spline, c);
    const std::array<int, 3> k = spline.cell_index(c);
    for (int node = 0; node < 64; ++node) {
      const int i = node % 4, j = (node / 4) % 4, l = node / 16;
      const std::vector<double>& expected = cp[(3 * k[0] + i) + n[0] * ((3 * k[1] + j) + n[1] * (3 * k[2] + l))];
      for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(cell.points[node * 3 + d] - expected[d]));
      CHECK(cell.weights[node] == doctest::Approx(1.0).epsilon(1e-13));
    }
  }
  CHECK(worst < 1e-12);  // both sides round: Boehm's convex combinations and the basis change
}
