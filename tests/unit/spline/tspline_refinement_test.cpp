// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/tspline.h"
#include "core/spline/tspline_refinement.h"

using volspline::Error;
using volspline::spline::BlendingKnots;
using volspline::spline::boundary_restricted_knots;
using volspline::spline::BsplineVolume;
using volspline::spline::from_bspline_volume;
using volspline::spline::LocalKnots;
using volspline::spline::NewKnots;
using volspline::spline::refine_blending_functions;
using volspline::spline::refine_until_no_new_knot;
using volspline::spline::TSpline;
using volspline::spline::TSplineForm;

namespace {

TSpline tensor_spline(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::array<std::vector<double>, 3> knots = {boundary_restricted_knots({0.0, 0.2, 0.45, 0.7, 1.0}),
                                              boundary_restricted_knots({0.0, 0.5, 0.6, 1.0}),
                                              boundary_restricted_knots({0.0, 0.1, 0.4, 0.9, 1.0})};
  const int rows = 7 * 6 * 7;
  Eigen::MatrixXd points(rows, 3);
  for (int i = 0; i < rows; ++i) points.row(i) << normal(rng), normal(rng), normal(rng);
  return from_bspline_volume(BsplineVolume(knots, points));
}

std::vector<Eigen::Vector3d> random_parameters(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < 8; ++c) out.emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);  // domain [0, 1]^3
  while (int(out.size()) < count) out.emplace_back(unit(rng), unit(rng), unit(rng));
  return out;
}

// max |F_a − F_b| and max |Σ w B − 1| of the refined spline over the parameters.
void check_same_function(const TSpline& before, const TSpline& after, int count) {
  double worst_value = 0.0, worst_unity = 0.0, worst_rational = 0.0;
  for (const Eigen::Vector3d& p : random_parameters(count, 77)) {
    const Eigen::VectorXd f = after.evaluate(p);
    worst_value = std::max(worst_value, (f - before.evaluate(p)).cwiseAbs().maxCoeff());
    worst_unity = std::max(worst_unity, std::abs(after.weight_sum(p) - 1.0));
    worst_rational = std::max(worst_rational, (after.evaluate(p, TSplineForm::Rational) - f).cwiseAbs().maxCoeff());
  }
  // Refinement is an exact identity; rounding of O(1) values: 1e-12.
  CHECK(worst_value < 1e-12);
  CHECK(worst_unity < 1e-12);
  CHECK(worst_rational < 1e-12);
}

}  // namespace

TEST_CASE("splitting one cell into 8 keeps F and semi-standardness") {
  const TSpline spline = tensor_spline(3);
  // Cell [0.2, 0.45] x [0.5, 0.6] x [0.4, 0.9]: insert its mid-lines into every blending function
  // whose support overlaps the cell.
  const double lo[3] = {0.2, 0.5, 0.4}, hi[3] = {0.45, 0.6, 0.9};
  std::vector<NewKnots> new_knots(spline.num_functions());
  int touched = 0;
  for (int i = 0; i < spline.num_functions(); ++i) {
    const BlendingKnots& k = spline.knots()[i];
    bool overlaps = true;
    for (int a = 0; a < 3; ++a) overlaps = overlaps && k[a][0] < hi[a] && k[a][4] > lo[a];
    if (!overlaps) continue;
    ++touched;
    for (int a = 0; a < 3; ++a) new_knots[i][a] = {0.5 * (lo[a] + hi[a])};
  }
  CHECK(touched == 64);
  const TSpline refined = refine_blending_functions(spline, new_knots);
  CHECK(refined.num_functions() > spline.num_functions());
  check_same_function(spline, refined, 10000);
  // Functions whose support misses the cell come through unchanged, with weight 1.
  CHECK(refined.knots()[0] == spline.knots()[0]);
  CHECK(refined.weights()[0] == 1.0);
}

TEST_CASE("inserting a knot into only some functions gives non-unit weights and the same F") {
  const TSpline spline = tensor_spline(8);
  // u knot 0.3 only into functions centred at u <= 0.2, w knot 0.25 only into functions centred
  // at v >= 0.5: merged functions collect weights c < 1 from a subset of parents.
  std::vector<NewKnots> new_knots(spline.num_functions());
  for (int i = 0; i < spline.num_functions(); ++i) {
    const BlendingKnots& k = spline.knots()[i];
    if (k[0][2] <= 0.2) new_knots[i][0] = {0.3};
    if (k[1][2] >= 0.5) new_knots[i][2] = {0.25};
  }
  const TSpline refined = refine_blending_functions(spline, new_knots);
  CHECK(refined.weights().minCoeff() < 1.0 - 1e-3);
  CHECK(refined.weights().minCoeff() > 0.0);
  check_same_function(spline, refined, 10000);
}

TEST_CASE("inserting a knot into every function is global knot insertion: weights stay 1") {
  const TSpline spline = tensor_spline(4);
  std::vector<NewKnots> new_knots(spline.num_functions());
  for (NewKnots& k : new_knots) k[1] = {0.3, 0.55};
  const TSpline refined = refine_blending_functions(spline, new_knots);
  // Two more basis functions along v: 7 x 8 x 7.
  CHECK(refined.num_functions() == 7 * 8 * 7);
  CHECK((refined.weights().array() - 1.0).abs().maxCoeff() < 1e-12);
  check_same_function(spline, refined, 2000);
}

TEST_CASE("knots at or outside the support are ignored, repeated knots raise multiplicity") {
  const TSpline spline = tensor_spline(5);
  std::vector<NewKnots> new_knots(spline.num_functions());
  for (int i = 0; i < spline.num_functions(); ++i) {
    const BlendingKnots& k = spline.knots()[i];
    new_knots[i][0] = {k[0][0], k[0][4], -5.0};
  }
  const TSpline same = refine_blending_functions(spline, new_knots);
  CHECK(same.num_functions() == spline.num_functions());
  CHECK(same.knots() == spline.knots());
  for (NewKnots& k : new_knots) k[0] = {0.45};  // already an interior knot along u
  const TSpline doubled = refine_blending_functions(spline, new_knots);
  CHECK(doubled.num_functions() == 8 * 6 * 7);
  check_same_function(spline, doubled, 2000);
}

TEST_CASE("refinement until no new knot with a T-mesh oracle") {
  const TSpline spline = tensor_spline(6);
  // Oracle: every u vector must contain 0.3 and 0.35 where they fall strictly inside its support,
  // and the v vectors of functions centred at u >= 0.45 must contain 0.55.
  auto oracle = [](const BlendingKnots& k) {
    NewKnots out;
    for (double x : {0.3, 0.35}) {
      bool present = false;
      for (double r : k[0]) present = present || r == x;
      if (!present && x > k[0][0] && x < k[0][4]) out[0].push_back(x);
    }
    bool present = false;
    for (double r : k[1]) present = present || r == 0.55;
    if (k[0][2] >= 0.45 && !present && 0.55 > k[1][0] && 0.55 < k[1][4]) out[1].push_back(0.55);
    return out;
  };
  const TSpline refined = refine_until_no_new_knot(spline, oracle);
  for (const BlendingKnots& k : refined.knots()) {
    const NewKnots missing = oracle(k);
    CHECK(missing[0].empty());
    CHECK(missing[1].empty());
  }
  check_same_function(spline, refined, 3000);
}

TEST_CASE("refinement rejects broken input with a message") {
  const TSpline spline = tensor_spline(7);
  CHECK_THROWS_WITH_AS(refine_blending_functions(spline, std::vector<NewKnots>(3)),
                       "T-spline refinement: 3 knot lists for 294 blending functions", Error);
  std::vector<NewKnots> new_knots(spline.num_functions());
  new_knots[5][2] = {std::numeric_limits<double>::quiet_NaN()};
  CHECK_THROWS_WITH_AS(refine_blending_functions(spline, new_knots),
                       "T-spline refinement: blending function 5: new w knot is not finite", Error);
  // An oracle that always wants another knot never settles.
  auto greedy = [](const BlendingKnots& k) {
    NewKnots out;
    out[2] = {0.5 * (k[2][2] + k[2][3])};
    return out;
  };
  CHECK_THROWS_WITH_AS(refine_until_no_new_knot(spline, greedy, 2),
                       "T-spline refinement: blending functions still need new knots after 2 rounds", Error);
}
