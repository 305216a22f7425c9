// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/io/gpc_json.h"
#include "core/io/gpc_spline_io.h"
#include "core/spline/bspline_basis.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/knot_insertion.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::Error;
using volspline::polycube::GpcDomain;
using volspline::spline::gpc_uniform_intervals;
using volspline::spline::gpc_uniform_knot_lines;
using volspline::spline::GpcFaceJoin;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineOptions;
using namespace volspline::test;

namespace {

// A random point of cuboid c; one in four is pushed onto a face, one in sixteen onto an edge.
Eigen::Vector3d random_uvw(const GpcDomain& d, int c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 15), axis(0, 2), end(0, 1);
  const Eigen::Vector3d s = cuboid_size(d, c);
  Eigen::Vector3d h(unit(rng) * s(0), unit(rng) * s(1), unit(rng) * s(2));
  const int kind = pick(rng);
  if (kind < 4) {
    const int a = axis(rng);
    h(a) = end(rng) * s(a);
  }
  if (kind == 0) {
    const int a = (axis(rng) + 1) % 3;
    h(a) = end(rng) * s(a);
  }
  return h;
}

void random_points(GpcSpline& spline, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coeff(-1.0, 1.0);
  Eigen::MatrixXd p(spline.num_functions(), spline.dimension());
  for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = coeff(rng);
  spline.set_points(p);
}

// Largest |Σ w_i B_i − 1| at `count` random points spread over all cuboids (Eq. 4.3).
double partition_error(const GpcSpline& spline, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> cuboid(0, spline.num_cuboids() - 1);
  double worst = 0.0;
  std::vector<int> ids;
  std::vector<double> values;
  for (int s = 0; s < count; ++s) {
    const int c = cuboid(rng);
    const Eigen::Vector3d h = random_uvw(spline.domain(), c, rng);
    worst = std::max(worst, std::abs(spline.weight_sum(c, h) - 1.0));
    if (s % 64 == 0) {  // the merged global basis sums to one as well
      spline.basis_at(c, h, {0, 0, 0}, ids, values);
      double sum = 0.0;
      for (double v : values) sum += v;
      worst = std::max(worst, std::abs(sum - 1.0));
      CHECK(std::is_sorted(ids.begin(), ids.end()));
      CHECK(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    }
  }
  return worst;
}

// Point (s, t) ∈ [0,1]² of face f of cuboid c in its local coordinates.
Eigen::Vector3d face_point(const GpcDomain& d, int c, int f, double s, double t) {
  const Eigen::Vector3d size = cuboid_size(d, c);
  Eigen::Vector3d h;
  h(f / 2) = (f % 2) * size(f / 2);
  h((f / 2 + 1) % 3) = s * size((f / 2 + 1) % 3);
  h((f / 2 + 2) % 3) = t * size((f / 2 + 2) % 3);
  return h;
}

// Largest distance between the two sides' values on every glued face, at random face points and
// on the face's edges.
double interface_gap(const GpcSpline& spline, int per_face, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const GpcDomain& d = spline.domain();
  double worst = 0.0;
  for (const auto& in : d.interfaces)
    for (int k = 0; k < per_face; ++k) {
      double s = unit(rng), t = unit(rng);
      if (k % 8 == 0) s = k % 16 == 0 ? 0.0 : 1.0;
      const Eigen::Vector3d a = face_point(d, in.cuboid[0], in.face[0], s, t);
      const Eigen::Vector3d b = in.transition.apply(a);
      worst = std::max(worst, (spline.evaluate(in.cuboid[0], a) - spline.evaluate(in.cuboid[1], b)).norm());
    }
  return worst;
}

// One-sided derivatives across glued face `in` at point p of its face on side 0, along the
// outward normal of side 0 (t < 0 in cuboid 0, t > 0 in cuboid 1), from values only: 4-point
// one-sided stencils, exact for a cubic inside one knot cell. Returns the largest jump of the
// normal first and second derivatives and of the mixed normal–tangent second derivatives
// (5-point central in the tangent direction, exact for cubics too).
struct Jumps {
  double d1 = 0.0, d2 = 0.0, mixed = 0.0;
};
Jumps derivative_jumps(const GpcSpline& spline, const volspline::polycube::GpcInterface& in, const Eigen::Vector3d& p,
                       double delta) {
  const int a = in.face[0] / 2;
  const double outward = in.face[0] % 2 == 0 ? -1.0 : 1.0;
  // F at p + t·n + b·e_tangent, from the side that holds it.
  auto value = [&](double t, int tangent, double b, int side) {
    Eigen::Vector3d x = p;
    x(a) += outward * t;
    if (tangent >= 0) x(tangent) += b;
    return side == 0 ? spline.evaluate(in.cuboid[0], x) : spline.evaluate(in.cuboid[1], in.transition.apply(x));
  };
  auto normal_derivatives = [&](auto&& g, int side) {
    // side 0: t = 0, −δ, −2δ, −3δ; side 1: t = 0, δ, 2δ, 3δ.
    const double step = side == 0 ? -delta : delta;
    const Eigen::VectorXd f0 = g(0.0), f1 = g(step), f2 = g(2 * step), f3 = g(3 * step);
    const Eigen::VectorXd first = (11 * f0 - 18 * f1 + 9 * f2 - 2 * f3) / (6 * step);
    const Eigen::VectorXd second = (2 * f0 - 5 * f1 + 4 * f2 - f3) / (delta * delta);
    return std::make_pair(first, second);
  };
  Jumps out;
  const auto l = normal_derivatives([&](double t) { return value(t, -1, 0.0, 0); }, 0);
  const auto r = normal_derivatives([&](double t) { return value(t, -1, 0.0, 1); }, 1);
  out.d1 = (l.first - r.first).norm();
  out.d2 = (l.second - r.second).norm();
  for (int tangent = 0; tangent < 3; ++tangent) {
    if (tangent == a) continue;
    auto tangent_derivative = [&](int side) {
      return [&, side](double t) {
        return Eigen::VectorXd((-value(t, tangent, 2 * delta, side) + 8 * value(t, tangent, delta, side) -
                                8 * value(t, tangent, -delta, side) + value(t, tangent, -2 * delta, side)) /
                               (12 * delta));
      };
    };
    const auto ml = normal_derivatives(tangent_derivative(0), 0);
    const auto mr = normal_derivatives(tangent_derivative(1), 1);
    out.mixed = std::max(out.mixed, (ml.first - mr.first).norm());
  }
  return out;
}

// Largest jumps over points of face `in` away from the knot lines (cell centres ± a quarter cell).
Jumps max_jumps(const GpcSpline& spline, int interface_id, unsigned seed) {
  const auto& in = spline.domain().interfaces[interface_id];
  const int c = in.cuboid[0], a = in.face[0] / 2;
  const Eigen::Vector3d size = cuboid_size(spline.domain(), c);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-0.25, 0.25);
  Jumps worst;
  for (int k = 0; k < 40; ++k) {
    Eigen::Vector3d p;
    p(a) = (in.face[0] % 2) * size(a);
    for (int b = 0; b < 3; ++b) {
      if (b == a) continue;
      const int n = spline.intervals(c)[b];
      const double h = size(b) / n;
      p(b) = (std::uniform_int_distribution<int>(0, n - 1)(rng) + 0.5 + offset(rng)) * h;
    }
    const Jumps j = derivative_jumps(spline, in, p, 1e-2 * size.minCoeff() / 4);
    worst.d1 = std::max(worst.d1, j.d1);
    worst.d2 = std::max(worst.d2, j.d2);
    worst.mixed = std::max(worst.mixed, j.mixed);
  }
  return worst;
}

std::vector<std::array<int, 3>> intervals_of(const GpcDomain& d, double spacing) { return gpc_uniform_intervals(d, spacing); }

}  // namespace

TEST_CASE("gpc spline: two cuboids glued with a quarter turn are one C² B-spline") {
  const GpcDomain d = glue_boxes(two_cube_boxes());
  REQUIRE(d.interfaces.size() == 1);
  GpcSplineOptions o;
  o.intervals = {{3, 4, 3}, {4, 3, 4}};  // A's v ↔ B's w (4), A's w ↔ B's v (3); normals 3 | 4
  GpcSpline spline(d, o);
  CHECK(spline.interface_join(0) == GpcFaceJoin::Continued);
  CHECK(spline.face_join(0, 1) == GpcFaceJoin::Continued);
  CHECK(spline.face_join(0, 0) == GpcFaceJoin::Surface);
  CHECK(spline.exposed_faces(0) == volspline::polycube::CubeFaceSet::all().without(1));
  // One knot vector of 3 + 4 intervals along the glued normal: 7 + 3 functions, times 7 × 6.
  CHECK(spline.num_functions() == 10 * 7 * 6);
  // A's patch reaches 3 knots into B (where B's first knots lie), and stops at its surface faces.
  CHECK(spline.patch(0).domain_max()(0) == doctest::Approx(1.0 + 3 * 0.325).epsilon(1e-12));
  CHECK(spline.patch(0).domain_min()(0) == 0.0);
  CHECK(spline.patch(0).domain_max()(1) == 0.8);
  random_points(spline, 7);
  const double pu = partition_error(spline, 100000, 1);
  MESSAGE("two cuboids: max |sum w B - 1| = " << pu);
  CHECK(pu <= 1e-12);
  CHECK(interface_gap(spline, 400, 2) <= 1e-12);
  const auto j = max_jumps(spline, 0, 3);
  MESSAGE("continued face: jumps d1 " << j.d1 << " d2 " << j.d2 << " mixed " << j.mixed);
  CHECK(j.d1 <= 1e-9);
  CHECK(j.d2 <= 1e-6);
  CHECK(j.mixed <= 1e-6);

  // The same face forced clamped: C⁰ with the face control points shared.
  o.clamped_interfaces = {0};
  GpcSpline clamped(d, o);
  CHECK(clamped.interface_join(0) == GpcFaceJoin::Clamped);
  // (3+3) + (4+3) functions along the normal, the face column shared: 12 per tangent pair.
  CHECK(clamped.num_functions() == 12 * 7 * 6);
  CHECK(clamped.patch(0).domain_max()(0) == 1.0);
  random_points(clamped, 7);
  CHECK(partition_error(clamped, 100000, 4) <= 1e-12);
  CHECK(interface_gap(clamped, 400, 5) <= 1e-12);
  const auto jc = max_jumps(clamped, 0, 6);
  MESSAGE("clamped face: jumps d1 " << jc.d1 << " d2 " << jc.d2);
  CHECK(jc.d1 >= 1e-2);  // random control points: the normal derivative jumps
}

TEST_CASE("gpc spline: blocks of randomly rotated cuboids around regular edges and vertices are C² everywhere") {
  const GpcDomain d = glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11));
  REQUIRE(d.cuboids.size() == 8);
  REQUIRE(d.interfaces.size() == 12);
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.29);
  GpcSpline spline(d, o);
  CHECK(spline.num_continued_interfaces() == 12);
  // One tensor B-spline on the union: per global axis the two columns' intervals + 3.
  // x: ceil(1/0.29) + ceil(0.7/0.29) = 4 + 3; y: 3 + 5; z: 2 + 4.
  CHECK(spline.num_functions() == (7 + 3) * (8 + 3) * (6 + 3));
  random_points(spline, 9);
  CHECK(partition_error(spline, 100000, 10) <= 1e-12);
  CHECK(interface_gap(spline, 200, 11) <= 1e-12);
  for (int i = 0; i < 12; ++i) {
    const auto j = max_jumps(spline, i, 12 + i);
    CHECK(j.d1 <= 1e-9);
    CHECK(j.d2 <= 1e-6);
    CHECK(j.mixed <= 1e-6);
  }
}

TEST_CASE("gpc spline: batch evaluation has the bits of the one-point evaluation") {
  const GpcDomain d = glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11));
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.29);
  GpcSpline spline(d, o);
  random_points(spline, 13);
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int rows = 9000;
  std::vector<int> cuboids(rows);
  Eigen::MatrixX3d uvw(rows, 3);
  for (int i = 0; i < rows; ++i) {
    cuboids[i] = (i * 5) % spline.num_cuboids();
    for (int a = 0; a < 3; ++a) uvw(i, a) = unit(rng) * d.cuboids[cuboids[i]].size[a];
  }
  uvw(7, 1) = d.cuboids[cuboids[7]].size[1] * (1.0 + 1e-12);  // clamped onto the box
  Eigen::MatrixXd jacobians;
  const Eigen::MatrixXd values = spline.evaluate_batch(cuboids, uvw, &jacobians);
  const Eigen::MatrixXd values_only = spline.evaluate_batch(cuboids, uvw);
  int differ = 0;
  double value[3], value_j[3], jacobian[9];
  for (int i = 0; i < rows; ++i) {
    spline.evaluate_to(cuboids[i], uvw.row(i).transpose(), value);
    spline.evaluate_with_jacobian(cuboids[i], uvw.row(i).transpose(), value_j, jacobian);
    for (int k = 0; k < 3; ++k) differ += values_only(i, k) != value[k] || values(i, k) != value_j[k];
    for (int k = 0; k < 9; ++k) differ += jacobians(i, k) != jacobian[k];
  }
  CHECK(differ == 0);
  cuboids[5] = 8;
  CHECK_THROWS_WITH_AS(spline.evaluate_batch(cuboids, uvw), "row 5: GpcSpline: cuboid 8 is not in 0..7", Error);
  cuboids[5] = 0;
  uvw(6, 0) = -0.5;
  CHECK_THROWS_WITH_AS(spline.evaluate_batch(cuboids, uvw), doctest::Contains("row 6: GpcSpline: uvw (-0.500000"), Error);
  cuboids.pop_back();
  CHECK_THROWS_WITH_AS(spline.evaluate_batch(cuboids, uvw), "GpcSpline: 8999 cuboid ids for 9000 rows", Error);
}

TEST_CASE("gpc spline: a cuboid glued to itself is periodic") {
  for (bool twist : {false, true}) {
    const GpcDomain d = torus_domain(twist);
    for (int nu : {1, 2, 3, 5}) {
      GpcSplineOptions o;
      o.intervals = {{nu, 2, twist ? 2 : 1}};
      GpcSpline spline(d, o);
      CHECK(spline.interface_join(0) == GpcFaceJoin::Continued);
      // A periodic knot vector has as many functions as intervals.
      CHECK(spline.num_functions() == nu * (2 + 3) * ((twist ? 2 : 1) + 3));
      random_points(spline, 20 + nu);
      CHECK(partition_error(spline, nu == 5 ? 100000 : 20000, 21) <= 1e-12);
      CHECK(interface_gap(spline, 400, 22) <= 1e-12);
      if (nu >= 3) {
        const auto j = max_jumps(spline, 0, 23);
        CHECK(j.d1 <= 1e-9);
        CHECK(j.d2 <= 1e-6);
        CHECK(j.mixed <= 1e-6);
      }
    }
  }
}

TEST_CASE("gpc spline: a T with Type-1 ill-points is C0 on the faces touching them, C2 elsewhere") {
  const GpcDomain d = t_shape_domain();
  REQUIRE(d.cuboids.size() == 5);
  REQUIRE(d.interfaces.size() == 4);
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.5);
  GpcSpline spline(d, o);
  // Centre Z = 0, arms L = 1 (with L2 = 2 beyond), R = 3, D = 4.
  for (int i = 0; i < 4; ++i) {
    const auto& in = d.interfaces[i];
    const bool arm_to_arm = (in.cuboid[0] == 1 && in.cuboid[1] == 2) || (in.cuboid[0] == 2 && in.cuboid[1] == 1);
    CHECK(spline.interface_join(i) == (arm_to_arm ? GpcFaceJoin::Continued : GpcFaceJoin::Clamped));
  }
  for (const auto& ill : d.ill_points)
    for (int i = 0; i < 4; ++i) {
      const auto& in = d.interfaces[i];
      const auto& cs = ill.cuboids;
      const bool touches = std::count(cs.begin(), cs.end(), in.cuboid[0]) && std::count(cs.begin(), cs.end(), in.cuboid[1]);
      if (touches) CHECK(spline.interface_join(i) == GpcFaceJoin::Clamped);
    }
  random_points(spline, 30);
  const double pu = partition_error(spline, 100000, 31);
  MESSAGE("T-shape: max |sum w B - 1| = " << pu);
  CHECK(pu <= 1e-12);
  CHECK(interface_gap(spline, 400, 32) <= 1e-12);
  for (int i = 0; i < 4; ++i)
    if (spline.interface_join(i) == GpcFaceJoin::Continued) {
      const auto j = max_jumps(spline, i, 33);
      CHECK(j.d1 <= 1e-9);
      CHECK(j.d2 <= 1e-6);
    }
}

TEST_CASE("gpc spline: real GPC domains of the eight and the torus") {
  const std::string dir = VOLSPLINE_SOURCE_DIR "/tests/data/gpc/";
  for (const char* name : {"eight", "eight_no_merge", "torus"}) {
    const GpcDomain d = volspline::io::read_gpc_domain(dir + name + ".gpc.json");
    GpcSplineOptions o;
    o.intervals = intervals_of(d, 0.04);
    GpcSpline spline(d, o);
    random_points(spline, 40);
    const double pu = partition_error(spline, 100000, 41);
    const double gap = interface_gap(spline, 400, 42);
    MESSAGE(std::string(name) << ": " << d.cuboids.size() << " cuboids, " << d.interfaces.size() << " interfaces ("
                 << spline.num_continued_interfaces() << " continued), " << spline.num_functions()
                 << " functions; max |sum w B - 1| = " << pu << ", gap " << gap);
    CHECK(pu <= 1e-12);
    CHECK(gap <= 1e-12);
    for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i)
      if (spline.interface_join(i) == GpcFaceJoin::Continued) {
        const auto j = max_jumps(spline, i, 43);
        CHECK(j.d1 <= 1e-8);
        CHECK(j.d2 <= 1e-5);
      }
    if (std::string(name) == "torus") CHECK(spline.num_continued_interfaces() == 1);
    // §4.3.1: no function reaches beyond a face on the solid's surface.
    for (int c = 0; c < spline.num_cuboids(); ++c)
      for (int f = 0; f < 6; ++f)
        if (spline.face_join(c, f) == GpcFaceJoin::Surface) {
          const double bound = f % 2 == 0 ? spline.patch(c).domain_min()(f / 2) : spline.patch(c).domain_max()(f / 2);
          CHECK(bound == (f % 2) * d.cuboids[c].size[f / 2]);
        }
    // Deterministic: the same domain and options give the same functions and ids.
    const GpcSpline again(d, o);
    for (int c = 0; c < spline.num_cuboids(); ++c) {
      CHECK(again.patch_function_ids(c) == spline.patch_function_ids(c));
      CHECK(again.patch(c).knots() == spline.patch(c).knots());
    }
    // The faces at the eight's Type-1 ill-points are clamped.
    for (const auto& ill : d.ill_points)
      for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i) {
        const auto& in = d.interfaces[i];
        const auto& cs = ill.cuboids;
        if (std::count(cs.begin(), cs.end(), in.cuboid[0]) && std::count(cs.begin(), cs.end(), in.cuboid[1]) &&
            in.cut < 0)
          CHECK(spline.interface_join(i) == GpcFaceJoin::Clamped);
      }
  }
}

TEST_CASE("gpc spline: the anchors lie in their cuboids and reproduce a linear map") {
  // Greville abscissae reproduce linear functions: control points = a linear map of the global
  // coordinates at the anchors give that map exactly, across continued and clamped faces.
  const std::vector<PlacedCuboid> boxes = t_shape_boxes();
  const GpcDomain d = glue_boxes(boxes);
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.4);
  GpcSpline spline(d, o);
  const Eigen::Matrix3d m = (Eigen::Matrix3d() << 1.0, 0.3, -0.2, 0.1, 2.0, 0.5, -0.4, 0.2, 1.5).finished();
  Eigen::MatrixXd p(spline.num_functions(), 3);
  for (int i = 0; i < spline.num_functions(); ++i) {
    const auto& anchor = spline.anchor(i);
    REQUIRE(anchor.cuboid >= 0);
    const Eigen::Vector3d s = cuboid_size(d, anchor.cuboid);
    CHECK((anchor.uvw.array() >= 0.0).all());
    CHECK((anchor.uvw.array() <= s.array()).all());
    p.row(i) = (m * boxes[anchor.cuboid].placement.apply(anchor.uvw)).transpose();
  }
  spline.set_points(p);
  std::mt19937_64 rng(50);
  double worst = 0.0, jac = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const int c = k % spline.num_cuboids();
    const Eigen::Vector3d h = random_uvw(d, c, rng);
    worst = std::max(worst, (spline.evaluate(c, h) - m * boxes[c].placement.apply(h)).norm());
    // ∂F/∂uvw = m · (the placement's rotation).
    Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 3; ++a) r(boxes[c].placement.axis[a], a) = boxes[c].placement.sign[a];
    jac = std::max(jac, (spline.jacobian(c, h) - m * r).cwiseAbs().maxCoeff());
  }
  CHECK(worst <= 1e-12);
  CHECK(jac <= 1e-11);
}

TEST_CASE("gpc spline: bad input throws with a message") {
  const GpcDomain d = glue_boxes(two_cube_boxes());
  GpcSplineOptions o;
  o.intervals = {{3, 4, 3}, {4, 4, 4}};
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("knot lines of the two sides differ"), Error);
  o.intervals = {{3, 4, 3}};
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("intervals has 1 entries for 2 cuboids"), Error);
  o.intervals = {{0, 4, 3}, {4, 3, 4}};
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("must be >= 1"), Error);
  o.intervals = {{3, 4, 3}, {4, 3, 4}};
  o.clamped_interfaces = {1};
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("clamped_interfaces names interface 1"), Error);
  o.clamped_interfaces = {};
  o.dimension = 5;
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("dimension"), Error);
  o.dimension = 3;
  GpcDomain broken = d;
  broken.cuboids[1].face_interface[0] = -1;
  CHECK_THROWS_WITH_AS(GpcSpline(broken, o), doctest::Contains("whose face_interface is not 0"), Error);
  broken = d;
  broken.interfaces[0].transition.translation(0) += 0.1;
  CHECK_THROWS_WITH_AS(GpcSpline(broken, o), doctest::Contains("does not map cuboid 0 face 1"), Error);
  broken = d;
  broken.cuboids[0].size[2] = -1.0;
  CHECK_THROWS_WITH_AS(GpcSpline(broken, o), doctest::Contains("cuboid 0 has size"), Error);

  GpcSpline spline(d, o);
  CHECK_THROWS_WITH_AS(spline.evaluate(0, Eigen::Vector3d(1.1, 0.0, 0.0)), doctest::Contains("outside cuboid 0"), Error);
  CHECK_THROWS_AS(spline.weight_sum(1, Eigen::Vector3d(0.0, std::nan(""), 0.0)), Error);
  CHECK_NOTHROW(spline.evaluate(0, Eigen::Vector3d(1.0 + 1e-12, 0.8, -1e-12)));  // rounding of a transition
  CHECK_THROWS_WITH_AS(spline.set_points(Eigen::MatrixXd::Zero(3, 3)), doctest::Contains("expected"), Error);
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(spline.num_functions(), 3);
  p(0, 0) = std::nan("");
  CHECK_THROWS_WITH_AS(spline.set_points(p), doctest::Contains("not finite"), Error);
  CHECK_THROWS_WITH_AS(gpc_uniform_intervals(d, 0.0), doctest::Contains("knot_spacing"), Error);
  broken = d;
  broken.cuboids[1].size[1] = 0.7;
  CHECK_THROWS_WITH_AS(gpc_uniform_intervals(broken, 0.1), doctest::Contains("interface 0 glues cuboid 0 axis 2"),
                       Error);
}

TEST_CASE("gpc spline: knot lines inserted through the gluing keep a C² partition of unity") {
  // The twisted tube (a quarter turn: v → w, w → size − v): a line lands in both tangent axes
  // and, through the turn, mirrored: v and w each get 0.1 and 0.3 − 0.1.
  {
    const GpcDomain d = torus_domain(true);
    auto lines = volspline::spline::gpc_uniform_knot_lines(d, {{4, 2, 2}});
    CHECK(volspline::spline::gpc_insert_knot_line(d, lines, 0, 1, 0.1) == 4);
    CHECK(volspline::spline::gpc_insert_knot_line(d, lines, 0, 2, 0.2) == 0);  // already there
    for (int a : {1, 2}) {
      REQUIRE(lines[0][a].size() == 5);
      CHECK(lines[0][a][1] == doctest::Approx(0.1).epsilon(1e-15));
      CHECK(lines[0][a][3] == doctest::Approx(0.2).epsilon(1e-15));
    }
    GpcSplineOptions o;
    o.knot_lines = lines;
    GpcSpline spline(d, o);
    CHECK_FALSE(spline.uniform_knots());
    CHECK(spline.intervals(0) == std::array<int, 3>{4, 4, 4});
    CHECK(spline.num_functions() == 4 * 7 * 7);  // periodic u: as many functions as intervals
    random_points(spline, 61);
    CHECK(partition_error(spline, 20000, 62) <= 1e-12);
    CHECK(interface_gap(spline, 400, 63) <= 1e-12);
    const auto j = max_jumps(spline, 0, 64);
    CHECK(j.d1 <= 1e-9);
    CHECK(j.d2 <= 1e-6);
  }
  // Two cubes and a block of rotated cuboids: midpoints of random intervals, anywhere.
  const std::vector<GpcDomain> domains = {glue_boxes(two_cube_boxes()),
                                          glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11))};
  for (const GpcDomain& d : domains) {
    auto lines = volspline::spline::gpc_uniform_knot_lines(d, intervals_of(d, 0.3));
    std::mt19937_64 rng(70);
    for (int k = 0; k < 8; ++k) {
      const int c = std::uniform_int_distribution<int>(0, static_cast<int>(d.cuboids.size()) - 1)(rng);
      const int a = std::uniform_int_distribution<int>(0, 2)(rng);
      const auto& l = lines[c][a];
      const int i = std::uniform_int_distribution<int>(0, static_cast<int>(l.size()) - 2)(rng);
      CHECK(volspline::spline::gpc_insert_knot_line(d, lines, c, a, 0.5 * (l[i] + l[i + 1])) >= 1);
    }
    GpcSplineOptions o;
    o.knot_lines = lines;
    GpcSpline spline(d, o);
    CHECK(spline.num_continued_interfaces() == static_cast<int>(d.interfaces.size()));
    random_points(spline, 71);
    CHECK(partition_error(spline, 100000, 72) <= 1e-12);
    CHECK(interface_gap(spline, 200, 73) <= 1e-12);
    for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i) {
      const auto j = max_jumps(spline, i, 74 + i);
      CHECK(j.d1 <= 1e-9);
      CHECK(j.d2 <= 1e-6);
    }
    // The file holds the lines: write → read → write is byte-identical; uniform knots write none.
    const std::string text = volspline::io::serialize_gpc_spline_json(spline);
    CHECK(text.find("\"knot_lines\"") != std::string::npos);
    CHECK(volspline::io::serialize_gpc_spline_json(volspline::io::parse_gpc_spline_json(text, "t")) == text);
    GpcSplineOptions uniform;
    uniform.intervals = intervals_of(d, 0.3);
    CHECK(volspline::io::serialize_gpc_spline_json(GpcSpline(d, uniform)).find("knot_lines") == std::string::npos);
  }
}

TEST_CASE("gpc spline: bad knot lines throw with a message") {
  const GpcDomain d = glue_boxes(two_cube_boxes());
  auto lines = volspline::spline::gpc_uniform_knot_lines(d, {{3, 4, 3}, {4, 3, 4}});
  GpcSplineOptions o;
  o.knot_lines = lines;
  o.knot_lines[0][1].insert(o.knot_lines[0][1].begin() + 1, 0.05);  // one side only
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("knot lines of the two sides differ"), Error);
  o.knot_lines = lines;
  std::swap(o.knot_lines[0][0][1], o.knot_lines[0][0][2]);
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("must increase"), Error);
  o.knot_lines = lines;
  o.knot_lines[1][2].back() = 2.0;
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("must start at 0 and end at the size"), Error);
  o.knot_lines.pop_back();
  CHECK_THROWS_WITH_AS(GpcSpline(d, o), doctest::Contains("knot_lines has 1 entries for 2 cuboids"), Error);
  CHECK_THROWS_WITH_AS(volspline::spline::gpc_insert_knot_line(d, lines, 0, 0, 0.0), doctest::Contains("not inside"),
                       Error);
  CHECK_THROWS_WITH_AS(volspline::spline::gpc_insert_knot_line(d, lines, 2, 0, 0.5), doctest::Contains("out of range"),
                       Error);
}

TEST_CASE("gpc spline: knot insertion re-derives Table 4.2's Type-1 weights, which leave Σ w B short of 1 inside") {
  // §4.4.2 around a Type-1 ill-point (the cross-section of a concave edge: three quadrants of a
  // standard grid are the solid, x < 0, y < 0 is outside): an auxiliary control point completes
  // the grid, bd-knots make x = 0 and y = 0 triple, and every refined function's weight is the
  // sum of the refinement coefficients of the original unit-weight functions except the
  // auxiliary one: w = 1 − α_x α_y with α the auxiliary function's coefficient per axis.
  using volspline::spline::insert_knot;
  using volspline::spline::LocalKnots;
  const LocalKnots aux = {-3.0, -2.0, -1.0, 0.0, 1.0};  // centred on −1, the missing corner
  std::vector<std::pair<LocalKnots, double>> parts = {{aux, 1.0}};
  for (int round = 0; round < 2; ++round) {  // 0 twice more: multiplicity 3
    std::vector<std::pair<LocalKnots, double>> next;
    for (const auto& [r, c] : parts) {
      if (!(r[0] < 0.0 && r[4] > 0.0)) {  // 0 is an end knot: nothing to split
        next.push_back({r, c});
        continue;
      }
      const auto k = insert_knot(r, 0.0);
      if (k.first_coefficient > 0.0) next.push_back({k.first, c * k.first_coefficient});
      if (k.second_coefficient > 0.0) next.push_back({k.second, c * k.second_coefficient});
    }
    parts = next;
  }
  auto alpha = [&](const LocalKnots& r) {
    double sum = 0.0;
    for (const auto& [q, c] : parts)
      if (q == r) sum += c;
    return sum;
  };
  // The three refined functions nearest the central point along an axis: ending at the triple
  // knot, the C⁰ one through it, starting at it.
  const std::array<LocalKnots, 3> near = {{{-2.0, -1.0, 0.0, 0.0, 0.0}, {-1.0, 0.0, 0.0, 0.0, 1.0}, {0.0, 0.0, 0.0, 1.0, 2.0}}};
  const std::array<double, 3> a = {alpha(near[0]), alpha(near[1]), alpha(near[2])};
  CHECK(a[0] == doctest::Approx(1.0 / 3.0).epsilon(1e-15));
  CHECK(a[1] == doctest::Approx(1.0 / 6.0).epsilon(1e-15));
  CHECK(a[2] == 0.0);
  // Table 4.2, Type-1 row: 8/9, 17/18, 35/36 and 1 (the third axis, along the edge, adds factors 1).
  const double table[3][3] = {{8.0 / 9, 17.0 / 18, 1.0}, {17.0 / 18, 35.0 / 36, 1.0}, {1.0, 1.0, 1.0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) CHECK(1.0 - a[i] * a[j] == doctest::Approx(table[i][j]).epsilon(1e-15));
  // The refined functions with these weights sum to 1 − B_aux, and B_aux does not vanish in the
  // solid (x > 0 or y > 0 next to the edge): Σ w B falls short of 1 there. GpcSpline clamps the
  // faces at a Type-1 ill-point instead (weights 1, Σ B ≡ 1; the T-shape case above).
  const double deficit = volspline::spline::cubic_basis(aux, 0.5) * volspline::spline::cubic_basis(aux, -0.5);
  MESSAGE("Type-1 weights: Σ w B = 1 − " << deficit << " at (0.5, −0.5), inside the solid");
  CHECK(deficit > 1e-3);
}

TEST_CASE("gpc spline: poly-cube blocks with concave edges and corners (Type-1 to Type-4 points) stay exact") {
  // A 2×2×2 block of randomly rotated cuboids with some removed: one (a concave corner where
  // three concave edges meet), a column (a concave edge through the block), three around one
  // (a tripod: three concave edges at the inner corner), two on a diagonal layer.
  const std::vector<PlacedCuboid> all = block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 13);
  const std::vector<std::vector<int>> removed = {{7}, {3, 7}, {3, 5, 6, 7}, {6, 7}, {1, 7}};
  for (const std::vector<int>& gone : removed) {
    std::vector<PlacedCuboid> boxes;
    for (int b = 0; b < 8; ++b)
      if (std::find(gone.begin(), gone.end(), b) == gone.end()) boxes.push_back(all[b]);
    const GpcDomain d = glue_boxes(boxes);
    GpcSplineOptions o;
    o.intervals = intervals_of(d, 0.2);
    GpcSpline spline(d, o);
    CAPTURE(gone.size());
    CHECK(spline.num_continued_interfaces() < static_cast<int>(d.interfaces.size()));  // clamped at the ill-points
    random_points(spline, 80);
    CHECK(partition_error(spline, 50000, 81) <= 1e-12);
    CHECK(interface_gap(spline, 200, 82) <= 1e-12);
    for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i)
      if (spline.interface_join(i) == GpcFaceJoin::Continued) CHECK(max_jumps(spline, i, 83 + i).d1 <= 1e-9);
    // Linear maps are reproduced (control points at the anchors' global positions): no function
    // reaches a region the solid does not cover.
    place_at_anchors(spline, boxes);
    std::mt19937_64 rng(84);
    double worst = 0.0;
    for (int k = 0; k < 3000; ++k) {
      const int c = k % spline.num_cuboids();
      const Eigen::Vector3d h = random_uvw(d, c, rng);
      worst = std::max(worst, (spline.evaluate(c, h) - boxes[c].placement.apply(h)).norm());
    }
    CHECK(worst <= 1e-12);
  }
}

TEST_CASE("gpc spline: hierarchical splits keep F and a C² partition of unity across every kind of gluing") {
  // A twisted closed tube, a block of rotated cuboids (regular edges and vertices) and a T with
  // Type-1 ill-points (clamped faces): split a random fifth of the functions, then some of their
  // children, and compare with the spline before.
  const std::vector<std::pair<GpcDomain, double>> cases = {
      {torus_domain(true), 0.25},
      {glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11)), 0.5},
      {t_shape_domain(), 0.5}};
  unsigned seed = 200;
  for (const auto& [d, spacing] : cases) {
    GpcSplineOptions o;
    o.intervals = intervals_of(d, spacing);
    GpcSpline base(d, o);
    random_points(base, seed++);
    std::mt19937_64 rng(seed++);
    std::vector<int> split;
    for (int i = 0; i < base.num_functions(); ++i)
      if (rng() % 5 == 0) split.push_back(i);
    const GpcSpline once = base.refined(split);
    std::vector<int> again;
    for (int i = 0; i < once.num_functions(); ++i)
      if (once.function_level(i) == 1 && rng() % 3 == 0) again.push_back(i);
    const GpcSpline twice = once.refined(again);
    MESSAGE("functions " << base.num_functions() << " -> " << once.num_functions() << " -> " << twice.num_functions());
    CHECK(once.num_functions() > base.num_functions());
    CHECK(twice.num_functions() > once.num_functions());
    CHECK(twice.max_level() == 2);
    REQUIRE(twice.splits().size() == 2);
    // F is the same function (Eq. 4.9) and the weights still sum to 1 (Eq. 4.3).
    double worst = 0.0;
    std::mt19937_64 points_rng(seed++);
    for (int k = 0; k < 20000; ++k) {
      const int c = static_cast<int>(points_rng() % d.cuboids.size());
      const Eigen::Vector3d uvw = random_uvw(d, c, points_rng);
      worst = std::max(worst, (twice.evaluate(c, uvw) - base.evaluate(c, uvw)).cwiseAbs().maxCoeff());
    }
    CHECK(worst <= 1e-12);
    // The lattice evaluation (measures, untangling) agrees with point evaluation on the patches.
    double lattice_worst = 0.0;
    for (int c = 0; c < twice.num_cuboids(); ++c) {
      std::array<std::vector<double>, 3> coords;
      for (int a = 0; a < 3; ++a)
        for (int q = 0; q < 7; ++q) coords[a].push_back(cuboid_size(d, c)(a) * (q + 0.5) / 7.0);
      twice.patch(c).evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double* value, const double* jac) {
        double v[3], jj[9];
        twice.evaluate_with_jacobian(c, Eigen::Vector3d(coords[0][i], coords[1][j], coords[2][k]), v, jj);
        for (int q = 0; q < 3; ++q) lattice_worst = std::max(lattice_worst, std::abs(v[q] - value[q]));
        for (int q = 0; q < 9; ++q) lattice_worst = std::max(lattice_worst, std::abs(jj[q] - jac[q]) / 100.0);
      });
    }
    CHECK(lattice_worst <= 1e-11);
    // New points: the refined basis itself is single-valued and C² across continued faces.
    GpcSpline fresh = twice;
    random_points(fresh, seed++);
    CHECK(partition_error(fresh, 50000, seed++) <= 1e-12);
    CHECK(interface_gap(fresh, 300, seed++) <= 1e-12);
    for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i)
      if (fresh.interface_join(i) == GpcFaceJoin::Continued) {
        const auto j = max_jumps(fresh, i, seed++);
        CHECK(j.d1 <= 1e-9);
        CHECK(j.d2 <= 1e-6);
      }
    // The splits replay: the same functions from the options alone (refined() goes on from the
    // levels of the spline it refines), and with the same points the same bits.
    GpcSplineOptions replay;
    replay.knot_lines = gpc_uniform_knot_lines(d, o.intervals);
    replay.splits = twice.splits();
    GpcSpline again_built(d, replay);
    REQUIRE(again_built.num_functions() == twice.num_functions());
    for (int c = 0; c < twice.num_cuboids(); ++c) {
      CHECK(again_built.patch(c).weights() == twice.patch(c).weights());
      CHECK(again_built.patch(c).knots() == twice.patch(c).knots());
      CHECK(again_built.patch_function_ids(c) == twice.patch_function_ids(c));
    }
    for (int i = 0; i < twice.num_functions(); ++i) {
      CHECK(again_built.anchor(i).cuboid == twice.anchor(i).cuboid);
      CHECK(again_built.anchor(i).uvw == twice.anchor(i).uvw);
      CHECK(again_built.function_level(i) == twice.function_level(i));
    }
    again_built.set_points(twice.points());
    std::mt19937_64 bits_rng(seed++);
    for (int k = 0; k < 200; ++k) {
      const int c = static_cast<int>(bits_rng() % d.cuboids.size());
      const Eigen::Vector3d uvw = random_uvw(d, c, bits_rng);
      CHECK(again_built.evaluate(c, uvw) == twice.evaluate(c, uvw));
    }
  }
}

TEST_CASE("gpc spline: splits down to the deepest level next to an interface stay local") {
  // The T with 6 knot intervals per axis: level 6 holds (6·64 + 3)³ local functions per cuboid,
  // 2.9·10⁸ over the five, of which the splits visit a few hundred. Split the function largest
  // at a point of a glued face (clamped next to an ill-point, continued between the arms) level
  // by level down to kMaxLevel.
  const GpcDomain d = t_shape_domain();
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 1.0 / 6.0);
  REQUIRE(o.intervals[0] == std::array<int, 3>{6, 6, 6});
  GpcSpline base(d, o);
  random_points(base, 400);
  unsigned seed = 401;
  for (int i = 0; i < static_cast<int>(d.interfaces.size()); ++i) {
    const auto& in = d.interfaces[i];
    const bool arm_to_arm = std::min(in.cuboid[0], in.cuboid[1]) == 1 && std::max(in.cuboid[0], in.cuboid[1]) == 2;
    if (i > 0 && !arm_to_arm) continue;
    REQUIRE(base.interface_join(i) == (arm_to_arm ? GpcFaceJoin::Continued : GpcFaceJoin::Clamped));
    const Eigen::Vector3d target = face_point(d, in.cuboid[0], in.face[0], 0.37, 0.61);
    GpcSpline spline = base;
    REQUIRE(split_down_at(spline, in.cuboid[0], target, GpcSpline::kMaxLevel));
    CAPTURE(i);
    CHECK(spline.max_level() == GpcSpline::kMaxLevel);
    CHECK(spline.num_functions() < base.num_functions() + 1000);
    // F is the same function (Eq. 4.9), Σ w B = 1 (Eq. 4.3) and the sides agree, in the finest
    // cells around the target and anywhere.
    const double finest = 1.0 / (6 * 64);
    std::mt19937_64 rng(seed++);
    std::uniform_real_distribution<double> near(-3.0 * finest, 3.0 * finest);
    GpcSpline fresh = spline;
    random_points(fresh, seed++);
    double worst = 0.0, partition = 0.0, gap = 0.0;
    const int a = in.face[0] / 2;
    for (int k = 0; k < 4000; ++k) {
      Eigen::Vector3d p = target;
      for (int b = 0; b < 3; ++b) p(b) += near(rng);
      p(a) = target(a) - (in.face[0] % 2 == 0 ? -1.0 : 1.0) * std::abs(p(a) - target(a));  // inside cuboid[0]
      const int c = in.cuboid[0];
      worst = std::max(worst, (spline.evaluate(c, p) - base.evaluate(c, p)).cwiseAbs().maxCoeff());
      partition = std::max(partition, std::abs(fresh.weight_sum(c, p) - 1.0));
      Eigen::Vector3d on_face = p;
      on_face(a) = target(a);
      gap = std::max(gap, (fresh.evaluate(c, on_face) - fresh.evaluate(in.cuboid[1], in.transition.apply(on_face))).norm());
    }
    CHECK(worst <= 1e-12);
    CHECK(partition <= 1e-12);
    CHECK(gap <= 1e-12);
    CHECK(partition_error(fresh, 5000, seed++) <= 1e-12);
    // The same functions from the options alone.
    GpcSplineOptions replay = o;
    replay.splits = spline.splits();
    CHECK(GpcSpline(d, replay).num_functions() == spline.num_functions());
    // No level below kMaxLevel.
    std::vector<int> ids;
    std::vector<double> values;
    spline.basis_at(in.cuboid[0], target, {0, 0, 0}, ids, values);
    std::vector<int> deepest;
    for (int id : ids)
      if (spline.function_level(id) == GpcSpline::kMaxLevel) deepest.push_back(id);
    REQUIRE(!deepest.empty());
    CHECK_THROWS_AS(spline.refined(deepest), volspline::Error);
  }
}

TEST_CASE("gpc spline: splitting every function is the uniform level with halved knot intervals") {
  const GpcDomain d = torus_domain(true);
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.25);
  GpcSpline base(d, o);
  random_points(base, 300);
  std::vector<int> all(base.num_functions());
  std::iota(all.begin(), all.end(), 0);
  const GpcSpline fine = base.refined(all);
  GpcSplineOptions halved;
  halved.intervals = o.intervals;
  for (auto& triple : halved.intervals)
    for (int& n : triple) n *= 2;
  const GpcSpline uniform(d, halved);
  CHECK(fine.num_functions() == uniform.num_functions());
  for (int c = 0; c < fine.num_cuboids(); ++c) {
    const Eigen::VectorXd& w = fine.patch(c).weights();
    CHECK((w.array() - 1.0).abs().maxCoeff() <= 1e-12);  // a standard B-spline again
  }
  // Splitting only some functions never splits a function twice or loses one: the count of
  // functions from a split of one function is its 5×5×5 children minus what was there.
  GpcSplineOptions finer;
  finer.intervals = intervals_of(d, 0.07);
  const GpcSpline many(d, finer);
  int centre = 0;
  for (int i = 1; i < many.num_functions(); ++i)
    if ((many.anchor(i).uvw - Eigen::Vector3d(0.5, 0.15, 0.15)).norm() <
        (many.anchor(centre).uvw - Eigen::Vector3d(0.5, 0.15, 0.15)).norm())
      centre = i;
  const GpcSpline one = many.refined({centre});
  CHECK(one.num_functions() == many.num_functions() - 1 + 125);
  CHECK_THROWS_WITH_AS(base.refined({base.num_functions()}), doctest::Contains("splits name function"), Error);
}

TEST_CASE("gpc spline: a hierarchically refined spline round-trips through its JSON") {
  const GpcDomain d = t_shape_domain();
  GpcSplineOptions o;
  o.intervals = intervals_of(d, 0.5);
  GpcSpline base(d, o);
  random_points(base, 400);
  std::vector<int> split;
  for (int i = 0; i < base.num_functions(); i += 7) split.push_back(i);
  const GpcSpline refined = base.refined(split);
  const std::string text = volspline::io::serialize_gpc_spline_json(refined);
  CHECK(text.find("\"splits\"") != std::string::npos);
  const GpcSpline back = volspline::io::parse_gpc_spline_json(text, "t");
  CHECK(back.num_functions() == refined.num_functions());
  CHECK(volspline::io::serialize_gpc_spline_json(back) == text);
  for (int c = 0; c < static_cast<int>(d.cuboids.size()); ++c) {
    const Eigen::Vector3d uvw = 0.37 * cuboid_size(d, c);
    CHECK((back.evaluate(c, uvw) - base.evaluate(c, uvw)).cwiseAbs().maxCoeff() <= 1e-12);
  }
  // A split id beyond the functions of its step is refused with the file named.
  std::string bad = text;
  const auto at = bad.find_first_of("0123456789", bad.find("\"splits\""));
  REQUIRE(at != std::string::npos);
  bad.insert(at, "99999999,");
  CHECK_THROWS_WITH_AS(volspline::io::parse_gpc_spline_json(bad, "bad.json"), doctest::Contains("bad.json"), Error);
  // A step giving more functions than the file has points stops the construction there.
  GpcSplineOptions capped = o;
  capped.splits = refined.splits();
  capped.max_functions = base.num_functions();
  CHECK_THROWS_WITH_AS(GpcSpline(d, capped), doctest::Contains("functions allowed"), Error);
}
