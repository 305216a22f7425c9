// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bspline_multipatch.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"
#include "tests/unit/spline/gpc_test_domains.h"
#include "tests/unit/spline/random_tspline.h"

using volspline::Error;
using volspline::spline::BsplineMultipatch;
using volspline::spline::BsplineVolume;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineOptions;
using volspline::spline::TSpline;
using volspline::spline::TSplineAcceleration;
using namespace volspline::test;

namespace {

void random_gpc_points(GpcSpline& spline, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd p(spline.num_functions(), 3);
  for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = normal(rng);
  spline.set_points(p);
}

// Largest |patch − spline| over random points of every patch box.
double multipatch_error(const BsplineMultipatch& m, const GpcSpline& spline, int per_patch, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (std::size_t p = 0; p < m.patches.size(); ++p)
    for (int k = 0; k < per_patch; ++k) {
      Eigen::Vector3d h;
      for (int a = 0; a < 3; ++a) h[a] = m.box_min[p][a] + unit(rng) * (m.box_max[p][a] - m.box_min[p][a]);
      worst = std::max(worst, (m.patches[p].evaluate(h) - spline.evaluate(m.cuboid[p], h)).cwiseAbs().maxCoeff());
    }
  return worst;
}

// Largest gap between the two sides of every interface at random points of the first side.
double interface_gap(const BsplineMultipatch& m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (const auto& in : m.interfaces) {
    const int p = in.patch[0], q = in.patch[1], n = in.side[0] / 2;
    for (int k = 0; k < 20; ++k) {
      Eigen::Vector3d t, h, g;
      for (int a = 0; a < 3; ++a) t[a] = unit(rng);
      t[n] = in.side[0] % 2;
      for (int a = 0; a < 3; ++a) {
        h[a] = m.box_min[p][a] + t[a] * (m.box_max[p][a] - m.box_min[p][a]);
        const int b = in.axis[a];
        const double s = a == n ? double(in.side[1] % 2) : (in.sign[a] > 0 ? t[a] : 1.0 - t[a]);
        g[b] = m.box_min[q][b] + s * (m.box_max[q][b] - m.box_min[q][b]);
      }
      worst = std::max(worst, (m.patches[p].evaluate(h) - m.patches[q].evaluate(g)).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("tspline_box_to_bspline: a B-spline volume's T-spline gives back its knots and control points") {
  const std::vector<double> grid = {0.0, 0.15, 0.4, 0.45, 0.8, 1.0};
  std::array<std::vector<double>, 3> knots = {volspline::spline::boundary_restricted_knots(grid),
                                              volspline::spline::boundary_restricted_knots({0.0, 0.5, 2.0}),
                                              volspline::spline::boundary_restricted_knots({-1.0, -0.2, 0.1, 0.3})};
  const int n = int((knots[0].size() - 4) * (knots[1].size() - 4) * (knots[2].size() - 4));
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd p(n, 3);
  for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = normal(rng);
  const BsplineVolume volume(knots, p);
  const TSpline spline = volspline::spline::from_bspline_volume(volume);
  const BsplineVolume back = volspline::spline::tspline_box_to_bspline(spline, spline.domain_min(), spline.domain_max());
  for (int a = 0; a < 3; ++a) CHECK(back.knots(a) == volume.knots(a));
  const double error = (back.control_points() - p).cwiseAbs().maxCoeff();
  MESSAGE("B-spline volume round trip: max control point error " << error);
  CHECK(error <= 1e-12);
  // An extra knot line is knot insertion: same function, one more control point per row.
  const BsplineVolume finer = volspline::spline::tspline_box_to_bspline(spline, spline.domain_min(), spline.domain_max(),
                                                                      {std::vector<double>{0.6}, {}, {}});
  CHECK(finer.num_control(0) == volume.num_control(0) + 1);
  CHECK((finer.evaluate({0.61, 0.7, 0.0}) - volume.evaluate({0.61, 0.7, 0.0})).norm() <= 1e-12);
}

TEST_CASE("tspline_box_to_bspline: random T-splines and sub-boxes equal the spline's semi-standard form") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int converted = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const TSpline spline = random_tspline(40, 3, seed, TSplineAcceleration::Auto);
    for (const bool sub_box : {false, true}) {
      Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
      if (sub_box) {
        lo = lo + 0.2 * (hi - lo);
        hi = hi - 0.3 * (hi - lo);
      }
      try {
        const BsplineVolume v = volspline::spline::tspline_box_to_bspline(spline, lo, hi);
        double worst = 0.0, scale = 0.0;
        for (int k = 0; k < 300; ++k) {
          Eigen::Vector3d h;
          for (int a = 0; a < 3; ++a) h[a] = lo[a] + unit(rng) * (hi[a] - lo[a]);
          const Eigen::VectorXd f = spline.evaluate(h);
          worst = std::max(worst, (v.evaluate(h) - f).cwiseAbs().maxCoeff());
          scale = std::max(scale, f.cwiseAbs().maxCoeff());
        }
        CHECK(worst <= 1e-12 * std::max(1.0, scale));
        ++converted;
      } catch (const Error& e) {
        // A local knot vector with a 4-fold interior knot: F breaks there, no C⁻¹ patch.
        CHECK(std::string(e.what()).find("times inside the box") != std::string::npos);
      }
    }
  }
  MESSAGE("random T-splines converted: " << converted << " of 24");
  CHECK(converted >= 12);
}

TEST_CASE("multipatch_from_gpc_spline: conforming patches equal the GPC spline; glued sides agree") {
  SUBCASE("two cuboids glued with a quarter turn, one hierarchical split") {
    GpcSplineOptions o;
    o.intervals = {{3, 4, 3}, {4, 3, 4}};
    GpcSpline base(glue_boxes(two_cube_boxes()), o);
    GpcSpline spline = base.refined({5, 77, 130});
    random_gpc_points(spline, 9);
    const BsplineMultipatch m = volspline::spline::multipatch_from_gpc_spline(spline);
    CHECK(m.patches.size() == 2);
    CHECK(m.interfaces.size() == 1);
    CHECK(m.boundary.size() == 10);
    CHECK(m.num_vertices == 12);
    CHECK(multipatch_error(m, spline, 200, 1) <= 1e-12);
    CHECK(interface_gap(m, 2) <= 1e-12);
    CHECK(volspline::spline::multipatch_topology_is_vertex_based(m));
    // The glued tangent axes carry the same knot vectors (A's v is B's w).
    CHECK(m.patches[0].knots(1).size() == m.patches[1].knots(2).size());
  }
  SUBCASE("a cuboid glued to itself with a twist needs thirds for a vertex-based reader") {
    GpcSplineOptions o;
    o.intervals = {{6, 2, 2}};
    GpcSpline spline(torus_domain(true), o);
    random_gpc_points(spline, 4);
    const BsplineMultipatch one = volspline::spline::multipatch_from_gpc_spline(spline);
    CHECK(one.patches.size() == 1);
    CHECK(one.interfaces.size() == 1);
    CHECK(multipatch_error(one, spline, 300, 3) <= 1e-12);
    CHECK(interface_gap(one, 4) <= 1e-12);
    CHECK_FALSE(volspline::spline::multipatch_topology_is_vertex_based(one));
    const BsplineMultipatch thirds = volspline::spline::vertex_based_multipatch(spline);
    CHECK(thirds.patches.size() == 27);
    CHECK(thirds.boundary.size() == 4 * 9);
    CHECK(thirds.interfaces.size() == 3 * 2 * 9 + 9);
    CHECK(multipatch_error(thirds, spline, 30, 5) <= 1e-12);
    CHECK(interface_gap(thirds, 6) <= 1e-12);
    CHECK_THROWS_WITH_AS(volspline::spline::multipatch_from_gpc_spline(spline, 0), doctest::Contains("split must be in 1..4"), Error);
  }
  SUBCASE("a T with Type-1 ill-points (clamped faces) and rotated frames") {
    GpcSplineOptions o;
    o.intervals.assign(5, {3, 3, 3});
    GpcSpline spline(t_shape_domain(), o);
    random_gpc_points(spline, 12);
    const BsplineMultipatch m = volspline::spline::multipatch_from_gpc_spline(spline);
    CHECK(multipatch_error(m, spline, 100, 7) <= 1e-12);
    CHECK(interface_gap(m, 8) <= 1e-12);
    CHECK(volspline::spline::multipatch_topology_is_vertex_based(m));
  }
}
