// SPDX-License-Identifier: MIT
// The cell-polynomial evaluation of TSpline (AVX2 Horner where the CPU has it, else the portable
// one) against two references: the nested Horner of cell_power_form written out here (the same
// bits), and the function-list evaluation (Eq. 4.1 / 4.3 summed over the cell's blending
// functions, 1e-13 relative). On single patches and on GPC-splines across glued, periodic and
// clamped faces, D = 1..4.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"
#include "tests/unit/spline/gpc_test_domains.h"
#include "tests/unit/spline/random_tspline.h"

using volspline::polycube::GpcDomain;
using volspline::spline::gpc_uniform_intervals;
using volspline::spline::GpcFaceJoin;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineOptions;
using volspline::spline::TSpline;
using volspline::spline::TSplineAcceleration;
using volspline::spline::TSplineForm;
using namespace volspline::test;

// Named, not anonymous: the unity build puts this file next to others with helpers of these names.
namespace cell_polynomial_test {

// Tricubic power form p (monomial m = (4a + b)·4 + c, K values each) and its s-gradient at s by
// nested Horner, u outermost: the order of the evaluation under test.
void horner(const std::vector<double>& p, int K, const double* s, double* value, double* grad) {
  for (int d = 0; d < K; ++d) {
    double out = 0.0;
    for (int a = 3; a >= 0; --a) {
      double acc = 0.0;
      for (int b = 3; b >= 0; --b) {
        const double* q = p.data() + (4 * a + b) * 4 * K + d;
        acc = acc * s[1] + (((q[3 * K] * s[2] + q[2 * K]) * s[2] + q[K]) * s[2] + q[0]);
      }
      out = out * s[0] + acc;
    }
    value[d] = out;
  }
  if (!grad) return;
  for (int d = 0; d < K; ++d) {
    double t2[4], t2_1[4], t2_2[4];
    for (int a = 0; a < 4; ++a) {
      double t1[4], t1_2[4];
      for (int b = 0; b < 4; ++b) {
        const double* q = p.data() + (4 * a + b) * 4 * K + d;
        t1[b] = ((q[3 * K] * s[2] + q[2 * K]) * s[2] + q[K]) * s[2] + q[0];
        t1_2[b] = (3.0 * q[3 * K] * s[2] + 2.0 * q[2 * K]) * s[2] + q[K];
      }
      t2[a] = ((t1[3] * s[1] + t1[2]) * s[1] + t1[1]) * s[1] + t1[0];
      t2_1[a] = (3.0 * t1[3] * s[1] + 2.0 * t1[2]) * s[1] + t1[1];
      t2_2[a] = ((t1_2[3] * s[1] + t1_2[2]) * s[1] + t1_2[1]) * s[1] + t1_2[0];
    }
    value[d] = ((t2[3] * s[0] + t2[2]) * s[0] + t2[1]) * s[0] + t2[0];
    grad[0 * K + d] = (3.0 * t2[3] * s[0] + 2.0 * t2[2]) * s[0] + t2[1];
    grad[1 * K + d] = ((t2_1[3] * s[0] + t2_1[2]) * s[0] + t2_1[1]) * s[0] + t2_1[0];
    grad[2 * K + d] = ((t2_2[3] * s[0] + t2_2[2]) * s[0] + t2_2[1]) * s[0] + t2_2[0];
  }
}

// F and its Jacobian (column-major, D×3) from the cell's power form: Eq. 4.3, or Eq. 4.1 with
// the quotient rule, as TSpline states them. Returns the largest inverse cell width.
double from_power_form(const TSpline& spline, const Eigen::Vector3d& uvw, TSplineForm form, double* value,
                       double* jacobian, double* value_only) {
  const int D = spline.dimension();
  const int cell = spline.cell_of(uvw);
  const std::array<int, 3> k = spline.cell_index(cell);
  double s[3], inverse_width[3];
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& b = spline.knot_lines(a);
    inverse_width[a] = 1.0 / (b[k[a] + 1] - b[k[a]]);
    s[a] = (uvw[a] - b[k[a]]) * inverse_width[a];
  }
  const double largest_inverse_width = std::max({inverse_width[0], inverse_width[1], inverse_width[2]});
  std::vector<double> numerator(64 * D), denominator(64);
  spline.cell_power_form(cell, numerator.data(), denominator.data());
  double grad[12], weight, weight_grad[3];
  horner(numerator, D, s, value_only, nullptr);
  horner(numerator, D, s, value, grad);
  if (form == TSplineForm::SemiStandard) {
    for (int a = 0; a < 3; ++a)
      for (int d = 0; d < D; ++d) jacobian[d + D * a] = grad[a * D + d] * inverse_width[a];
    return largest_inverse_width;
  }
  horner(denominator, 1, s, &weight, nullptr);
  const double inverse_weight = 1.0 / weight;
  for (int d = 0; d < D; ++d) value_only[d] *= inverse_weight;
  horner(denominator, 1, s, &weight, weight_grad);
  for (int d = 0; d < D; ++d) value[d] /= weight;
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < D; ++d)
      jacobian[d + D * a] = (grad[a * D + d] - value[d] * weight_grad[a]) / weight * inverse_width[a];
  return largest_inverse_width;
}

// Points of [lo, hi]: the 8 corners, points on each face, then uniform ones.
std::vector<Eigen::Vector3d> box_points(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int count,
                                        std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < 8; ++c) out.emplace_back(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]);
  while (int(out.size()) < count) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * unit(rng);
    if (out.size() % 4 == 0) {
      const int face = int(out.size() / 4) % 6;
      p[face / 2] = face % 2 ? hi[face / 2] : lo[face / 2];
    }
    out.push_back(p);
  }
  return out;
}

struct Worst {
  double value = 0.0, jacobian = 0.0;
  int bits_differ = 0;
  int points = 0;
};

// The cell-polynomial spline `fast` against the same spline with function lists and against its
// power form, at `points`: errors relative to the size of the terms summed (control points P,
// over the weight sum W for the rational form, and per unit of the cell width for the Jacobian),
// and the count of points whose bits differ from the power form.
void compare(const TSpline& fast, const std::vector<Eigen::Vector3d>& points, Worst& worst) {
  REQUIRE(fast.has_cell_polynomials());
  const TSpline lists(fast.knots(), fast.weights(), fast.points(), TSplineAcceleration::FunctionLists);
  const int D = fast.dimension();
  const double largest_point = std::max(1.0, fast.points().cwiseAbs().maxCoeff());
  for (const TSplineForm form : {TSplineForm::SemiStandard, TSplineForm::Rational}) {
    for (const Eigen::Vector3d& p : points) {
      const double weight_sum = lists.weight_sum(p);
      // Eq. 4.1 far from an uncovered part of the box, where W -> 0 amplifies every rounding.
      if (form == TSplineForm::Rational && weight_sum < 0.05) continue;
      double v[4], j[12], v_ref[4], j_ref[12], v_only[4], v_form[4], j_form[12], v_form_only[4];
      fast.evaluate_with_jacobian(p, form, v, j);
      fast.evaluate_to(p, form, v_only);
      lists.evaluate_with_jacobian(p, form, v_ref, j_ref);
      const double inverse_width = from_power_form(fast, p, form, v_form, j_form, v_form_only);
      const double amplify = form == TSplineForm::Rational ? 1.0 / (weight_sum * weight_sum) : 1.0;
      const double scale_v = largest_point * amplify;
      const double scale_j = largest_point * inverse_width * amplify;
      bool same_bits = true;
      for (int d = 0; d < D; ++d) {
        worst.value = std::max(
            {worst.value, std::abs(v[d] - v_ref[d]) / scale_v, std::abs(v_only[d] - v_ref[d]) / scale_v});
        same_bits = same_bits && v[d] == v_form[d] && v_only[d] == v_form_only[d];
      }
      for (int e = 0; e < 3 * D; ++e) {
        worst.jacobian = std::max(worst.jacobian, std::abs(j[e] - j_ref[e]) / scale_j);
        same_bits = same_bits && j[e] == j_form[e];
      }
      worst.bits_differ += !same_bits;
      ++worst.points;
    }
  }
}

void random_points(GpcSpline& spline, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd p(spline.num_functions(), spline.dimension());
  for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = normal(rng);
  spline.set_points(p);
}

// Every cuboid of a GPC-spline: GpcSpline::evaluate_with_jacobian, evaluate and evaluate_to
// against the patch's function lists and power form, at points of the cuboid box (its glued
// faces included).
Worst compare_gpc(const GpcDomain& domain, GpcSplineOptions options, unsigned seed) {
  Worst worst;
  for (int dimension = 1; dimension <= 4; ++dimension) {
    options.dimension = dimension;
    GpcSpline spline(domain, options);
    random_points(spline, seed + dimension);
    std::mt19937 rng(seed);
    for (int c = 0; c < spline.num_cuboids(); ++c) {
      const std::vector<Eigen::Vector3d> points = box_points(Eigen::Vector3d::Zero(), cuboid_size(domain, c), 300, rng);
      compare(spline.patch(c), points, worst);
      const TSpline lists(spline.patch(c).knots(), spline.patch(c).weights(), spline.patch(c).points(),
                          TSplineAcceleration::FunctionLists);
      for (const Eigen::Vector3d& p : points) {
        double v[4], j[12], v_ref[4], j_ref[12];
        spline.evaluate_with_jacobian(c, p, v, j);
        lists.evaluate_with_jacobian(p, TSplineForm::SemiStandard, v_ref, j_ref);
        const Eigen::VectorXd value = spline.evaluate(c, p);
        double value_to[4];
        spline.evaluate_to(c, p, value_to);
        for (int d = 0; d < dimension; ++d) CHECK(value_to[d] == value[d]);
        double v_form[4], j_form[12], v_form_only[4];
        const double scale_v = std::max(1.0, spline.points().cwiseAbs().maxCoeff());
        const double scale_j =
            scale_v * from_power_form(spline.patch(c), p, TSplineForm::SemiStandard, v_form, j_form, v_form_only);
        for (int d = 0; d < dimension; ++d)
          worst.value = std::max(
              {worst.value, std::abs(v[d] - v_ref[d]) / scale_v, std::abs(value[d] - v_ref[d]) / scale_v});
        for (int e = 0; e < 3 * dimension; ++e)
          worst.jacobian = std::max(worst.jacobian, std::abs(j[e] - j_ref[e]) / scale_j);
      }
    }
  }
  return worst;
}

void check(const Worst& worst, const std::string& name) {
  MESSAGE(name << ": " << worst.points << " points, worst relative error value " << worst.value << ", Jacobian "
               << worst.jacobian);
  CHECK(worst.points > 0);
  // Two summation orders of the same tricubic (power form vs blending functions): rounding.
  CHECK(worst.value <= 1e-13);
  CHECK(worst.jacobian <= 1e-13);
  CHECK(worst.bits_differ == 0);
}

}  // namespace cell_polynomial_test

using namespace cell_polynomial_test;

TEST_CASE("cell polynomials: single patches (tensor, T-spline, not semi-standard) give the power form's bits") {
  for (int dimension = 1; dimension <= 4; ++dimension) {
    CAPTURE(dimension);
    Worst worst;
    const TSpline spline = random_tspline(80, dimension, 40 + dimension, TSplineAcceleration::CellPolynomials);
    std::mt19937 rng(dimension);
    std::vector<Eigen::Vector3d> points =
        cell_polynomial_test::box_points(spline.domain_min(), spline.domain_max(), 600, rng);
    // On knot lines, where the half-open cell rule picks the cell.
    for (double u : spline.knot_lines(0)) points.emplace_back(u, spline.knot_lines(1)[1], 0.5);
    for (double w : spline.knot_lines(2)) points.emplace_back(0.3, spline.knot_lines(1).back(), w);
    cell_polynomial_test::compare(spline, points, worst);
    cell_polynomial_test::check(worst, "random T-spline, D = " + std::to_string(dimension));
  }
}

TEST_CASE("cell polynomials: GPC-splines across glued, periodic and clamped faces") {
  GpcSplineOptions options;
  const GpcDomain two = glue_boxes(two_cube_boxes());
  options.intervals = {{3, 4, 3}, {4, 3, 4}};
  cell_polynomial_test::check(compare_gpc(two, options, 1), "two cuboids, quarter turn, continued");
  options.clamped_interfaces = {0};
  {
    GpcSpline probe(two, options);
    REQUIRE(probe.interface_join(0) == GpcFaceJoin::Clamped);
  }
  cell_polynomial_test::check(compare_gpc(two, options, 2), "two cuboids, clamped face");
  options.clamped_interfaces.clear();

  const GpcDomain block = glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11));
  options.intervals = gpc_uniform_intervals(block, 0.29);
  cell_polynomial_test::check(compare_gpc(block, options, 3), "block of 8 rotated cuboids");

  for (bool twist : {false, true}) {
    const GpcDomain tube = torus_domain(twist);
    options.intervals = {{5, 2, twist ? 2 : 1}};
    cell_polynomial_test::check(compare_gpc(tube, options, 4), twist ? "twisted periodic tube" : "periodic tube");
  }

  const GpcDomain t_shape = t_shape_domain();
  options.intervals = gpc_uniform_intervals(t_shape, 0.5);
  cell_polynomial_test::check(compare_gpc(t_shape, options, 5), "T with Type-1 ill-points (clamped faces)");
}
