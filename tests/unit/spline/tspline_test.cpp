// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/hierarchical_refinement.h"
#include "core/spline/tspline.h"
#include "tests/unit/spline/random_tspline.h"

using volspline::Error;
using volspline::spline::BlendingKnots;
using volspline::spline::boundary_restricted_knots;
using volspline::spline::BsplineVolume;
using volspline::spline::from_bspline_volume;
using volspline::spline::LocalKnots;
using volspline::spline::TSpline;
using volspline::spline::TSplineAcceleration;
using volspline::spline::TSplineForm;
using volspline::test::random_tspline;

namespace {

BsplineVolume random_volume(int dimension, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::array<std::vector<double>, 3> knots = {
      boundary_restricted_knots({0.0, 0.2, 0.25, 0.6, 1.0}),
      boundary_restricted_knots({-1.0, 0.5, 1.0, 3.0}),
      std::vector<double>{2, 2, 2, 2, 2.5, 2.5, 3, 3.1, 3.1, 3.1, 4, 4, 4, 4}};
  const int rows = (int(knots[0].size()) - 4) * (int(knots[1].size()) - 4) * (int(knots[2].size()) - 4);
  Eigen::MatrixXd points(rows, dimension);
  for (int i = 0; i < rows; ++i)
    for (int d = 0; d < dimension; ++d) points(i, d) = normal(rng);
  return BsplineVolume(knots, points);
}

std::vector<Eigen::Vector3d> random_parameters(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int count,
                                               unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < 8; ++c) out.emplace_back(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]);
  while (int(out.size()) < count) {
    out.emplace_back(lo[0] + (hi[0] - lo[0]) * unit(rng), lo[1] + (hi[1] - lo[1]) * unit(rng),
                     lo[2] + (hi[2] - lo[2]) * unit(rng));
  }
  return out;
}

const TSplineAcceleration kAccelerations[] = {TSplineAcceleration::CellPolynomials, TSplineAcceleration::FunctionLists};

}  // namespace

TEST_CASE("T-spline of a full tensor grid equals the B-spline volume") {
  for (int run = 0; run < 8; ++run) {
    const int dimension = 1 + run / 2;
    const TSplineAcceleration acceleration = kAccelerations[run % 2];
    const BsplineVolume volume = random_volume(dimension, 10 + dimension);
    const TSpline spline = from_bspline_volume(volume, acceleration);
    CHECK(spline.has_cell_polynomials() == (acceleration == TSplineAcceleration::CellPolynomials));
    CHECK(spline.num_functions() == volume.control_points().rows());
    CHECK(spline.dimension() == dimension);
    CHECK(spline.domain_min() == volume.domain_min());
    CHECK(spline.domain_max() == volume.domain_max());
    CHECK(spline.max_functions_per_cell() == 64);
    for (const Eigen::Vector3d& p : random_parameters(volume.domain_min(), volume.domain_max(), 1000, 20)) {
      CAPTURE(p.transpose());
      const Eigen::VectorXd expected = volume.evaluate(p);
      // Same function, different evaluation order (power-form pieces): 1e-12 for O(1) values.
      CHECK((spline.evaluate(p) - expected).cwiseAbs().maxCoeff() < 1e-12);
      CHECK(std::abs(spline.weight_sum(p) - 1.0) < 1e-12);
      CHECK((spline.evaluate(p, TSplineForm::Rational) - expected).cwiseAbs().maxCoeff() < 1e-12);
      const Eigen::MatrixXd jac = volume.jacobian(p);
      CHECK((spline.jacobian(p) - jac).cwiseAbs().maxCoeff() < 1e-10);
      CHECK((spline.jacobian(p, TSplineForm::Rational) - jac).cwiseAbs().maxCoeff() < 1e-10);
      if (dimension == 3) {
        for (const std::array<int, 3> order : {std::array<int, 3>{1, 0, 0}, {0, 2, 0}, {1, 1, 1}, {0, 0, 3}}) {
          const Eigen::VectorXd d = volume.derivative(p, order);
          CHECK((spline.derivative(p, order) - d).cwiseAbs().maxCoeff() < 1e-8 * std::max(1.0, d.norm()));
        }
      }
    }
  }
}

TEST_CASE("grid evaluation equals the brute-force sum over all blending functions") {
 for (const TSplineAcceleration acceleration : kAccelerations) {
  const TSpline spline = random_tspline(60, 3, 5, acceleration);
  CHECK(spline.num_cells() > 1);
  std::vector<Eigen::Vector3d> params = random_parameters(spline.domain_min(), spline.domain_max(), 400, 6);
  // Parameters on knot lines, where the half-open convention matters.
  for (double u : spline.knot_lines(0)) params.emplace_back(u, spline.knot_lines(1)[1], 0.5);
  for (double w : spline.knot_lines(2)) params.emplace_back(0.3, 1.0, w);
  std::vector<int> ids;
  std::vector<double> values;
  for (const Eigen::Vector3d& p : params) {
    CAPTURE(p.transpose());
    Eigen::Vector3d numerator = Eigen::Vector3d::Zero();
    double denominator = 0.0;
    for (int i = 0; i < spline.num_functions(); ++i) {
      const double b = spline.blending_function(i, p);
      numerator += spline.weights()[i] * b * spline.points().row(i).transpose();
      denominator += spline.weights()[i] * b;
    }
    CHECK((spline.evaluate(p) - numerator).norm() < 1e-12);
    CHECK(std::abs(spline.weight_sum(p) - denominator) < 1e-12);
    if (denominator > 1e-3) {
      CHECK((spline.evaluate(p, TSplineForm::Rational) - numerator / denominator).norm() < 1e-9);
    }
    spline.basis_at(p, {0, 0, 0}, ids, values);
    CHECK(std::is_sorted(ids.begin(), ids.end()));
    for (size_t m = 0; m < ids.size(); ++m) CHECK(std::abs(values[m] - spline.blending_function(ids[m], p)) < 1e-12);
  }
 }
}

TEST_CASE("semi-standard and rational Jacobians match finite differences") {
 for (const TSplineAcceleration acceleration : kAccelerations) {
  const TSpline spline = random_tspline(80, 3, 8, acceleration);
  const double h = 1e-6;
  int checked = 0;
  for (const Eigen::Vector3d& p : random_parameters(spline.domain_min(), spline.domain_max(), 300, 9)) {
    bool near_line = false;
    for (int a = 0; a < 3; ++a)
      for (double k : spline.knot_lines(a)) near_line = near_line || std::abs(p[a] - k) < 2 * h;
    if (near_line || spline.weight_sum(p) < 0.05) continue;
    ++checked;
    for (const TSplineForm form : {TSplineForm::SemiStandard, TSplineForm::Rational}) {
      const Eigen::MatrixXd jac = spline.jacobian(p, form);
      double value[3], jac_raw[9];
      spline.evaluate_with_jacobian(p, form, value, jac_raw);
      CHECK((spline.evaluate(p, form) - Eigen::Map<Eigen::Vector3d>(value)).norm() < 1e-14);
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e[a] = h;
        const Eigen::VectorXd fd = (spline.evaluate(p + e, form) - spline.evaluate(p - e, form)) / (2 * h);
        // Central differences inside one polynomial cell: O(h²) truncation, O(eps/h) rounding.
        CHECK((fd - jac.col(a)).norm() <= 1e-6 * std::max(1.0, jac.col(a).norm()));
      }
    }
  }
  CHECK(checked > 100);
 }
}

TEST_CASE("set_points keeps the grid and changes F") {
  const BsplineVolume volume = random_volume(3, 1);
  for (const TSplineAcceleration acceleration : kAccelerations) {
    TSpline spline = from_bspline_volume(volume, acceleration);
    const Eigen::MatrixXd doubled = 2.0 * spline.points();
    spline.set_points(doubled);
    const Eigen::Vector3d p(0.4, 0.2, 3.05);
    CHECK((spline.evaluate(p) - 2.0 * volume.evaluate(p)).norm() < 1e-12);
    CHECK((spline.evaluate(p, TSplineForm::Rational) - 2.0 * volume.evaluate(p)).norm() < 1e-12);
    CHECK(std::abs(spline.weight_sum(p) - 1.0) < 1e-12);
  }
  TSpline spline = from_bspline_volume(volume);
  CHECK_THROWS_WITH_AS(spline.set_points(Eigen::MatrixXd::Zero(3, 3)),
                       ("T-spline: new control points are 3x3, expected " + std::to_string(spline.num_functions()) + "x3").c_str(),
                       Error);
}

TEST_CASE("use_cell_polynomials switches a function-list spline to polynomials with the same F, also after moves") {
  TSpline spline = random_tspline(70, 3, 5, TSplineAcceleration::FunctionLists);
  const TSpline reference = random_tspline(70, 3, 5, TSplineAcceleration::FunctionLists);
  REQUIRE_FALSE(spline.has_cell_polynomials());
  CHECK(spline.use_cell_polynomials());
  CHECK(spline.has_cell_polynomials());
  CHECK(spline.use_cell_polynomials());  // already there: a no-op
  // A few moved control points: the incremental cell update (as the untangler moves them).
  Eigen::MatrixXd moved = spline.points();
  for (int i = 0; i < moved.rows(); i += 9) moved.row(i) += Eigen::RowVector3d(0.3, -0.2, 0.1);
  spline.set_points(moved);
  TSpline moved_reference = reference;
  moved_reference.set_points(moved);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int t = 0; t < 200; ++t) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a)
      p(a) = spline.domain_min()(a) + (spline.domain_max()(a) - spline.domain_min()(a)) * unit(rng);
    worst = std::max(worst, (spline.evaluate(p) - moved_reference.evaluate(p)).norm());
  }
  CHECK(worst < 1e-12);  // the same sums in another order: rounding only (values O(1))
}

TEST_CASE("a T-spline built with zero control points and given them later has the bits of one built with them") {
  // The zero-point build sums Σ w_i B_i alone; set_points then rebuilds every cell whole.
  const TSpline reference = random_tspline(70, 3, 6, TSplineAcceleration::CellPolynomials);
  TSpline later(reference.knots(), reference.weights(), Eigen::MatrixXd::Zero(reference.num_functions(), 3),
                TSplineAcceleration::CellPolynomials);
  const Eigen::Vector3d middle = 0.5 * (reference.domain_min() + reference.domain_max());
  CHECK(later.evaluate(middle).norm() == 0.0);
  CHECK(later.weight_sum(middle) == reference.weight_sum(middle));
  later.set_points(reference.points());
  const auto params = random_parameters(reference.domain_min(), reference.domain_max(), 200, 9);
  for (const Eigen::Vector3d& p : params) {
    double a[3], b[3], ja[9], jb[9];
    later.evaluate_with_jacobian(p, TSplineForm::SemiStandard, a, ja);
    reference.evaluate_with_jacobian(p, TSplineForm::SemiStandard, b, jb);
    CHECK(std::memcmp(a, b, sizeof a) == 0);
    CHECK(std::memcmp(ja, jb, sizeof ja) == 0);
    CHECK(later.weight_sum(p) == reference.weight_sum(p));
  }
}

TEST_CASE("batch evaluation equals single evaluation") {
  const TSpline spline = from_bspline_volume(random_volume(2, 4));
  const auto params = random_parameters(spline.domain_min(), spline.domain_max(), 40, 2);
  Eigen::MatrixX3d uvw(params.size(), 3);
  for (size_t i = 0; i < params.size(); ++i) uvw.row(i) = params[i].transpose();
  for (const TSplineForm form : {TSplineForm::SemiStandard, TSplineForm::Rational}) {
    const Eigen::MatrixXd out = spline.evaluate_batch(uvw, form);
    for (size_t i = 0; i < params.size(); ++i) CHECK(out.row(i).transpose() == spline.evaluate(params[i], form));
  }
  uvw(3, 0) = -0.5;
  CHECK_THROWS_WITH_AS(spline.evaluate_batch(uvw),
                       "row 3: T-spline: parameter u = -0.500000 is outside the domain [0.000000, 1.000000]", Error);
}

TEST_CASE("cell-sorted batch evaluation has the bits of the one-point evaluation") {
  // Many points per cell (the four-lane path of the cell polynomials and its remainders), more
  // rows than the comparison sort takes (the radix sort), and a short batch; both accelerations
  // and D = 1..4. Bits are compared as bytes, so a NaN of an uncovered point counts as equal.
  auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (const TSplineAcceleration acceleration : {TSplineAcceleration::CellPolynomials, TSplineAcceleration::FunctionLists}) {
    for (int D = 1; D <= 4; ++D) {
      const TSpline spline = volspline::test::random_tspline(40, D, 7 + unsigned(D), acceleration);
      for (const int rows : {37, 6000}) {
        std::mt19937 rng(unsigned(rows + D));
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
        Eigen::MatrixX3d uvw(rows, 3);
        for (int i = 0; i < rows; ++i)
          for (int a = 0; a < 3; ++a) uvw(i, a) = lo[a] + (hi[a] - lo[a]) * (i % 3 ? 0.3 + 0.1 * unit(rng) : unit(rng));
        uvw.row(0) = hi.transpose();
        for (const TSplineForm form : {TSplineForm::SemiStandard, TSplineForm::Rational}) {
          const Eigen::MatrixXd values = spline.evaluate_batch(uvw, form);
          Eigen::MatrixXd values_j, jacobians;
          spline.evaluate_batch_with_jacobian(uvw, form, values_j, jacobians);
          REQUIRE(values.rows() == rows);
          REQUIRE(values.cols() == D);
          REQUIRE(jacobians.cols() == 3 * D);
          int differ = 0;
          double value[4], value_j[4], jacobian[12];
          for (int i = 0; i < rows; ++i) {
            spline.evaluate_to(uvw.row(i).transpose(), form, value);
            spline.evaluate_with_jacobian(uvw.row(i).transpose(), form, value_j, jacobian);
            for (int d = 0; d < D; ++d) differ += !same_bits(values(i, d), value[d]) + !same_bits(values_j(i, d), value_j[d]);
            for (int c = 0; c < 3 * D; ++c) differ += !same_bits(jacobians(i, c), jacobian[c]);
          }
          CHECK(differ == 0);
        }
      }
    }
  }
  {
    // More than 2^16 cells: the two-pass radix sort (function lists keep the spline small).
    std::array<std::vector<double>, 3> knots;
    std::vector<double> grid(44);
    for (int i = 0; i < 44; ++i) grid[i] = i / 43.0;
    for (int a = 0; a < 3; ++a) knots[a] = boundary_restricted_knots(grid);
    std::mt19937 rng(3);
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::MatrixXd points(46 * 46 * 46, 3);
    for (Eigen::Index i = 0; i < points.size(); ++i) points.data()[i] = normal(rng);
    const TSpline big = from_bspline_volume(BsplineVolume(knots, points), TSplineAcceleration::FunctionLists);
    REQUIRE(big.num_cells() > 65536);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Eigen::MatrixX3d uvw(3000, 3);
    for (Eigen::Index i = 0; i < uvw.size(); ++i) uvw.data()[i] = unit(rng);
    const Eigen::MatrixXd values = big.evaluate_batch(uvw, TSplineForm::SemiStandard);
    int differ = 0;
    double value[3];
    for (int i = 0; i < 3000; ++i) {
      big.evaluate_to(uvw.row(i).transpose(), TSplineForm::SemiStandard, value);
      for (int d = 0; d < 3; ++d) differ += values(i, d) != value[d];
    }
    CHECK(differ == 0);
  }
  const TSpline spline = from_bspline_volume(random_volume(2, 4));
  Eigen::MatrixX3d uvw(5000, 3);
  uvw.rowwise() = (0.5 * (spline.domain_min() + spline.domain_max())).transpose();
  uvw(4321, 2) = spline.domain_max()[2] + 1.0;
  Eigen::MatrixXd values, jacobians;
  CHECK_THROWS_WITH_AS(spline.evaluate_batch_with_jacobian(uvw, TSplineForm::Rational, values, jacobians),
                       doctest::Contains("row 4321: T-spline: parameter w = "), Error);
}

TEST_CASE("T-spline rejects broken input with a message") {
  const std::vector<BlendingKnots> knots = {BlendingKnots{LocalKnots{0, 1, 2, 3, 4}, LocalKnots{0, 1, 2, 3, 4},
                                                          LocalKnots{0, 1, 2, 3, 4}}};
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(1);
  const Eigen::MatrixXd point = Eigen::MatrixXd::Zero(1, 3);
  CHECK_NOTHROW(TSpline(knots, one, point));
  CHECK_THROWS_WITH_AS(TSpline({}, Eigen::VectorXd(), Eigen::MatrixXd(0, 3)), "T-spline: no blending functions", Error);
  CHECK_THROWS_WITH_AS(TSpline(knots, Eigen::VectorXd::Ones(2), point), "T-spline: 2 weights for 1 blending functions",
                       Error);
  CHECK_THROWS_WITH_AS(TSpline(knots, one, Eigen::MatrixXd::Zero(2, 3)),
                       "T-spline: 2 control points for 1 blending functions", Error);
  CHECK_THROWS_WITH_AS(TSpline(knots, one, Eigen::MatrixXd::Zero(1, 5)),
                       "T-spline: control point dimension 5 is not in 1..4", Error);
  auto broken = knots;
  broken[0][1] = {0, 2, 1, 3, 4};
  CHECK_THROWS_WITH_AS(TSpline(broken, one, point),
                       "T-spline: blending function 0: knot vector v is not finite and non-decreasing with r0 < r4",
                       Error);
  broken = knots;
  broken[0][2] = {1, 1, 1, 1, 1};
  CHECK_THROWS_WITH_AS(TSpline(broken, one, point),
                       "T-spline: blending function 0: knot vector w is not finite and non-decreasing with r0 < r4",
                       Error);
  CHECK_THROWS_WITH_AS(TSpline(knots, Eigen::VectorXd::Zero(1), point),
                       "T-spline: blending function 0: weight 0.000000 is not finite and positive", Error);
  Eigen::MatrixXd nan_point = point;
  nan_point(0, 2) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(TSpline(knots, one, nan_point), "T-spline: control point 0 is not finite", Error);
  const TSpline spline(knots, one, point);
  CHECK_THROWS_WITH_AS(spline.evaluate({1.0, 5.0, 1.0}),
                       "T-spline: parameter v = 5.000000 is outside the domain [0.000000, 4.000000]", Error);
  CHECK_THROWS_AS(spline.weight_sum({1.0, 1.0, std::nan("")}), Error);
  // A knot-line grid above the cell limit is refused instead of exhausting memory.
  std::vector<BlendingKnots> many(420);
  for (int i = 0; i < 420; ++i) {
    const double s = i;
    many[i] = {LocalKnots{s, s + 0.1, s + 0.2, s + 0.3, s + 0.4}, LocalKnots{s, s + 0.1, s + 0.2, s + 0.3, s + 0.4},
               LocalKnots{s, s + 0.1, s + 0.2, s + 0.3, s + 0.4}};
  }
  CHECK_THROWS_WITH_AS(TSpline(many, Eigen::VectorXd::Ones(420), Eigen::MatrixXd::Zero(420, 3)),
                       "T-spline: the knot-line grid has more than 67108864 cells", Error);
}

TEST_CASE("weight_sum and basis_at agree with each other and the knot vectors on a refined T-spline") {
  // Refine a uniform 3³ B-spline twice locally: T-junctions, cells overlapping many functions.
  const std::vector<double> knots = boundary_restricted_knots({0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0});
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd points(6 * 6 * 6, 3);
  for (Eigen::Index i = 0; i < points.size(); ++i) points.data()[i] = normal(rng);
  volspline::spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  TSpline spline = grid.split(from_bspline_volume(BsplineVolume({knots, knots, knots}, points)), {0, 4, 13});
  std::vector<int> deeper;
  for (int leaf : grid.leaves())
    if (grid.cell_level(leaf) == 1 && grid.cell_min(leaf).maxCoeff() < 0.2) deeper.push_back(leaf);
  spline = grid.split(spline, deeper);
  std::vector<int> ids, d_ids;
  std::vector<double> values, d_values;
  for (const Eigen::Vector3d& p : random_parameters(spline.domain_min(), spline.domain_max(), 2000, 9)) {
    CAPTURE(p.transpose());
    spline.basis_at(p, {0, 0, 0}, ids, values);
    double sum = 0.0;
    for (size_t m = 0; m < ids.size(); ++m) sum += spline.weights()[ids[m]] * values[m];
    // weight_sum is documented to use the same products in the same order: bitwise equal.
    CHECK(spline.weight_sum(p) == sum);
    CHECK(std::abs(sum - 1.0) < 1e-12);
    for (size_t m = 0; m < ids.size(); m += 7) CHECK(std::abs(values[m] - spline.blending_function(ids[m], p)) < 1e-14);
    // A derivative order changes the values, not the list.
    spline.basis_at(p, {1, 0, 2}, d_ids, d_values);
    CHECK(d_ids == ids);
  }
}

TEST_CASE("basis_gradient_at has the bits of basis_at with each first derivative") {
  const std::vector<double> knots = boundary_restricted_knots({0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0});
  Eigen::MatrixXd points = Eigen::MatrixXd::Zero(6 * 6 * 6, 3);
  volspline::spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  const TSpline spline = grid.split(from_bspline_volume(BsplineVolume({knots, knots, knots}, points)), {0, 4, 13});
  std::vector<int> ids, d_ids;
  std::vector<double> d_values;
  std::array<std::vector<double>, 3> gradient;
  for (const Eigen::Vector3d& p : random_parameters(spline.domain_min(), spline.domain_max(), 500, 4)) {
    CAPTURE(p.transpose());
    spline.basis_gradient_at(p, ids, gradient);
    for (int a = 0; a < 3; ++a) {
      std::array<int, 3> order = {0, 0, 0};
      order[a] = 1;
      spline.basis_at(p, order, d_ids, d_values);
      CHECK(d_ids == ids);
      CHECK(d_values == gradient[a]);
    }
  }
  CHECK_THROWS_AS(spline.basis_gradient_at(Eigen::Vector3d(0.5, 2.0, 0.5), ids, gradient), Error);
}

TEST_CASE("cell_of and cell_functions give the knot-line cell and the basis_at list of a point") {
  const TSpline spline = random_tspline(70, 3, 5, TSplineAcceleration::FunctionLists);
  std::vector<Eigen::Vector3d> points = random_parameters(spline.domain_min(), spline.domain_max(), 500, 4);
  // Points on knot lines and at the domain ends, where the half-open intervals matter.
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d p = points[static_cast<std::size_t>(i)];
    for (int a = 0; a < 3; ++a)
      if ((i >> a) & 1) p[a] = spline.knot_lines(a)[static_cast<std::size_t>(i * 7 + a) % spline.knot_lines(a).size()];
    points.push_back(p);
  }
  points.push_back(spline.domain_min());
  points.push_back(spline.domain_max());
  std::vector<int> ids, cell_ids;
  std::vector<double> values;
  for (const Eigen::Vector3d& p : points) {
    CAPTURE(p.transpose());
    const int cell = spline.cell_of(p);
    // Expected: along each axis the last knot line <= t, the last interval closed.
    int expected = 0, stride = 1;
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& lines = spline.knot_lines(a);
      const int intervals = static_cast<int>(lines.size()) - 1;
      const int k = std::min(intervals - 1, static_cast<int>(std::upper_bound(lines.begin(), lines.end(), p[a]) - lines.begin()) - 1);
      expected += k * stride;
      stride *= intervals;
    }
    CHECK(cell == expected);
    spline.basis_at(p, {0, 0, 0}, ids, values);
    spline.cell_functions(cell, cell_ids);
    CHECK(cell_ids == ids);
  }
  CHECK_THROWS_WITH_AS(spline.cell_of(Eigen::Vector3d(0.5, 1.5, 0.5)), doctest::Contains("parameter v = 1.5"), Error);
}

TEST_CASE("lattice evaluation equals evaluate_with_jacobian at every lattice point") {
  // Both paths: the cells' blending functions, and the cells' power-form polynomials.
  for (TSplineAcceleration acceleration : {TSplineAcceleration::FunctionLists, TSplineAcceleration::CellPolynomials}) {
    for (int dimension : {3, 4}) {
      const TSpline spline = random_tspline(70, dimension, 11 + dimension, acceleration);
      // Random coordinates plus knot lines and the domain ends, where the half-open cells matter;
      // a repeated coordinate too.
      std::mt19937 rng(3);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      std::array<std::vector<double>, 3> coords;
      for (int a = 0; a < 3; ++a) {
        const double lo = spline.domain_min()[a], hi = spline.domain_max()[a];
        for (int i = 0; i < 9; ++i) coords[a].push_back(lo + (hi - lo) * unit(rng));
        coords[a].insert(coords[a].end(), spline.knot_lines(a).begin(), spline.knot_lines(a).end());
        coords[a].push_back(coords[a][0]);
        std::sort(coords[a].begin(), coords[a].end());
      }
      std::vector<int> visits(coords[0].size() * coords[1].size() * coords[2].size(), 0);
      double worst = 0.0;
      spline.evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double* value, const double* jac) {
        ++visits[i + coords[0].size() * (j + coords[1].size() * k)];
        const Eigen::Vector3d p(coords[0][i], coords[1][j], coords[2][k]);
        double expected_value[4], expected_jac[12];
        spline.evaluate_with_jacobian(p, TSplineForm::SemiStandard, expected_value, expected_jac);
        for (int d = 0; d < dimension; ++d) worst = std::max(worst, std::abs(value[d] - expected_value[d]));
        for (int m = 0; m < 3 * dimension; ++m)
          worst = std::max(worst, std::abs(jac[m] - expected_jac[m]) / (1.0 + std::abs(expected_jac[m])));
      });
      CHECK(std::count(visits.begin(), visits.end(), 1) == static_cast<long>(visits.size()));
      // Same sums in another order: rounding only (values O(1), derivatives scaled by 1/width).
      CHECK(worst < 1e-11);
    }
  }
  const TSpline spline = random_tspline(20, 3, 2, TSplineAcceleration::FunctionLists);
  std::array<std::vector<double>, 3> outside = {std::vector<double>{0.5}, std::vector<double>{1.5},
                                                std::vector<double>{0.5}};
  CHECK_THROWS_WITH_AS(spline.evaluate_lattice_with_jacobian(outside, [](int, int, int, const double*, const double*) {}),
                       doctest::Contains("parameter v = 1.5"), Error);
}

TEST_CASE("KnotsHash is equal for equal knot vectors, 0 and -0 alike") {
  const volspline::spline::KnotsHash hash;
  const LocalKnots a = {0.0, 0.0, 0.25, 0.5, 1.0};
  const LocalKnots b = {-0.0, 0.0, 0.25, 0.5, 1.0};
  CHECK(a == b);
  CHECK(hash(a) == hash(b));
  const BlendingKnots ka = {a, a, b}, kb = {b, a, a};
  CHECK(hash(ka) == hash(kb));
  CHECK(hash(a) != hash(LocalKnots{0.0, 0.0, 0.25, 0.5, 0.75}));
}
