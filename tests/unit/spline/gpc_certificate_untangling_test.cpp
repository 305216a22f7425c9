// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/spline/gpc_certificate_untangling.h"
#include "core/spline/gpc_jacobian_certificate.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/gpc_spline_fitting.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::spline::certify_gpc_jacobian;
using volspline::spline::fit_gpc_spline;
using volspline::spline::GpcSamples;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineOptions;
using volspline::spline::untangle_gpc_certificate;
using namespace volspline::test;

namespace {

// A solid ring over torus_domain(false) (the tube [0,1]×[0,0.3]×[0,0.2] glued to itself along
// u): u goes round the ring (radius 1), the cross-section square goes onto a disc-like section
// of radius 0.25 by the elliptical grid map x = a·√(1 − κb²), y = b·√(1 − κa²). With κ = 1/2 the
// square's corners map onto a circle with a flat angle (det J = 0 along the tube's four long
// edges, as on any smooth surface along a cuboid edge); κ = 0.6 makes them slightly reflex, so
// the least-squares fit folds along those edges and a certified spline must crease them.
Eigen::Vector3d ring(const Eigen::Vector3d& uvw) {
  const double kPi = 3.1415926535897983846;
  const double a = 2.0 * uvw(1) / 0.3 - 1.0, b = 2.0 * uvw(2) / 0.2 - 1.0;
  const double x = a * std::sqrt(1.0 - 0.6 * b * b), y = b * std::sqrt(1.0 - 0.6 * a * a);
  const double radius = 1.0 + 0.25 * y, angle = 2.0 * kPi * uvw(0);  // (u, v, w) right-handed
  return Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle), 0.25 * x);
}

// The ring on a lattice of 48 × 7 × 7 points of the tube, its faces included.
GpcSamples ring_samples() {
  GpcSamples s;
  const int n[3] = {48, 7, 7};
  const double size[3] = {1.0, 0.3, 0.2};
  std::vector<Eigen::Vector3d> uvw;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        uvw.emplace_back(size[0] * i / n[0], size[1] * j / (n[1] - 1), size[2] * k / (n[2] - 1));
  s.cuboid.assign(uvw.size(), 0);
  s.uvw.resize(static_cast<Eigen::Index>(uvw.size()), 3);
  s.values.resize(static_cast<Eigen::Index>(uvw.size()), 3);
  for (std::size_t r = 0; r < uvw.size(); ++r) {
    s.uvw.row(static_cast<Eigen::Index>(r)) = uvw[r].transpose();
    s.values.row(static_cast<Eigen::Index>(r)) = ring(uvw[r]).transpose();
  }
  return s;
}

double max_misfit(const GpcSpline& spline, const GpcSamples& s) {
  double worst = 0.0;
  for (Eigen::Index r = 0; r < s.uvw.rows(); ++r)
    worst = std::max(worst, (spline.evaluate(0, s.uvw.row(r).transpose()) - s.values.row(r).transpose()).norm());
  return worst;
}

// The ring's least-squares fit with 8 intervals round it and 1 × 1 across (as mesh2spline's
// torus): every cell lies on the tube's four long edges, where the fit folds.
GpcSpline fitted_ring(const GpcSamples& samples) {
  GpcSplineOptions o;
  o.intervals = {{8, 1, 1}};
  GpcSpline spline(torus_domain(false), o);
  fit_gpc_spline(spline, samples);
  return spline;
}

}  // namespace

TEST_CASE("untangle_gpc_certificate: a ring with one cell across its tube ends certified, seam and surface kept") {
  // As mesh2spline's torus: 8 intervals round the ring, 1 × 1 across, so every cell lies on the
  // tube's four long edges, where the least-squares fit folds (det J < 0 proven there), and
  // every function touches the surface; those round the ring cross the seam u = 0.
  const GpcSamples samples = ring_samples();
  GpcSpline spline = fitted_ring(samples);
  const auto before = certify_gpc_jacobian(spline);
  REQUIRE(before.cells == 8);
  CHECK(before.certified_cells < 8);
  const double misfit_before = max_misfit(spline, samples);

  const auto result = untangle_gpc_certificate(spline, samples);
  const auto after = certify_gpc_jacobian(spline);
  CHECK(result.initial_uncertified == 8 - before.certified_cells);
  CHECK(result.final_uncertified == 0);
  CHECK(after.jacobian_certified_fraction == 1.0);
  CHECK(after.det_j_lower_bound_rel >= 0.0);
  // The seam: the functions crossing it moved as one control point each, so u = 0 and u = 1 are
  // still the same surface (Eq. 3.4 with the identity cross-section).
  for (int q = 0; q < 25; ++q) {
    const Eigen::Vector3d a(0.0, 0.3 * (q % 5) / 4.0, 0.2 * (q / 5) / 4.0), b(1.0, a(1), a(2));
    CHECK((spline.evaluate(0, a) - spline.evaluate(0, b)).norm() <= 1e-12);
  }
  // The data term keeps the samples where the fit had them but at the reflex corners, which the
  // crease cuts (fit 0.0038, after 0.0139, of a section radius 0.25).
  CHECK(max_misfit(spline, samples) <= misfit_before + 0.015);
}

TEST_CASE("untangle_gpc_certificate: a certified spline is left as it is") {
  const std::vector<PlacedCuboid> boxes = two_cube_boxes();
  GpcSpline spline = placed_gpc_spline(boxes, {{3, 2, 2}, {3, 2, 2}});
  const Eigen::MatrixXd points = spline.points();
  GpcSamples samples;  // none: nothing pulls
  samples.uvw.resize(0, 3);
  samples.values.resize(0, 3);
  const auto result = untangle_gpc_certificate(spline, samples);
  CHECK(result.initial_uncertified == 0);
  CHECK(result.certificate_passes == 0);
  CHECK(spline.points() == points);
}

TEST_CASE("untangle_gpc_certificate: without rounds the ring's reflex long edges are tilted convex, the seam kept") {
  // The ring above fitted with 8 × 1 × 1 intervals folds along the tube's four long edges, which
  // lie between two surface faces: the crease tilt alone (no rounds) certifies cells there.
  const GpcSamples samples = ring_samples();
  GpcSpline spline = fitted_ring(samples);
  const Eigen::MatrixXd fitted = spline.points();
  volspline::spline::SplineUntangleOptions options;
  options.certificate_rounds = 0;
  const auto result = untangle_gpc_certificate(spline, samples, options);
  // 8 cells uncertified after the fit, 2 after the tilt of 32 cell edges.
  CHECK(result.initial_uncertified == 8);
  CHECK(result.crease_edges > 0);
  CHECK(result.final_uncertified <= 2);
  CHECK(certify_gpc_jacobian(spline).uncertified.size() == static_cast<std::size_t>(result.final_uncertified));
  int moved = 0;
  for (Eigen::Index f = 0; f < fitted.rows(); ++f) moved += spline.points().row(f) != fitted.row(f);
  CHECK(moved == result.crease_functions);
  for (int q = 0; q < 25; ++q) {
    const Eigen::Vector3d a(0.0, 0.3 * (q % 5) / 4.0, 0.2 * (q / 5) / 4.0), b(1.0, a(1), a(2));
    CHECK((spline.evaluate(0, a) - spline.evaluate(0, b)).norm() <= 1e-12);
  }
}

TEST_CASE("untangle_gpc_certificate: cells left uncertified run the rounds again, the better attempt kept") {
  // One round per attempt, whose data term all but pins the fit: the ring's fit has 8 folded
  // cells, which that pass and the crease tilt cannot all certify, so the rounds run again from
  // the same start (the surface samples held like the others, then passes moving the functions
  // at their round's cells only), and the kept spline's certificate is the result's.
  const GpcSamples samples = ring_samples();
  for (const double factor : {10.0, 1.0}) {
    CAPTURE(factor);
    GpcSpline spline = fitted_ring(samples);
    volspline::spline::SplineUntangleOptions options;
    options.certificate_rounds = 1;
    options.data_weight = 1e8;
    options.surface_data_factor = factor;
    const auto result = untangle_gpc_certificate(spline, samples, options);
    const auto after = certify_gpc_jacobian(spline);
    CHECK(result.initial_uncertified == 8);
    CHECK(after.uncertified.size() == static_cast<std::size_t>(result.final_uncertified));
    CHECK(result.final_uncertified < result.initial_uncertified);
    REQUIRE(result.final_uncertified > 0);
    // One pass per attempt: three attempts with a surface factor, two without.
    CHECK(result.certificate_passes == (factor == 1.0 ? 2 : 3));
  }
}

TEST_CASE("untangle_gpc_certificate: surface samples held harder stay closer where the rounds certify") {
  // The ring's fit folds along the tube's long edges; its samples on the tube's faces are the
  // surface. Both factors certify every cell; with the surface held 10 times as hard as the
  // interior the surface samples end no farther from their targets than with every sample alike.
  const GpcSamples samples = ring_samples();
  GpcSamples surface;  // the samples on the tube's faces v, w ∈ {0, max}
  std::vector<Eigen::Index> rows;
  for (Eigen::Index r = 0; r < samples.uvw.rows(); ++r) {
    const Eigen::Vector3d p = samples.uvw.row(r).transpose();
    if (p(1) == 0.0 || p(1) == 0.3 || p(2) == 0.0 || p(2) == 0.2) rows.push_back(r);
  }
  surface.cuboid.assign(rows.size(), 0);
  surface.uvw.resize(static_cast<Eigen::Index>(rows.size()), 3);
  surface.values.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    surface.uvw.row(static_cast<Eigen::Index>(k)) = samples.uvw.row(rows[k]);
    surface.values.row(static_cast<Eigen::Index>(k)) = samples.values.row(rows[k]);
  }
  double misfit[2];
  for (int q = 0; q < 2; ++q) {
    GpcSpline spline = fitted_ring(samples);
    volspline::spline::SplineUntangleOptions options;
    options.surface_data_factor = q == 0 ? 10.0 : 1.0;
    const auto result = untangle_gpc_certificate(spline, samples, options);
    CHECK(result.final_uncertified == 0);
    misfit[q] = max_misfit(spline, surface);
  }
  // Release build: 0.0066 against 0.0100 (section radius 0.25).
  CHECK(misfit[0] < misfit[1]);
}

TEST_CASE("untangle_gpc_certificate: a ring split five levels deep at one spot ends certified, seam and surface kept") {
  // The ring's folded fit with the function largest at a point of its outer surface split level
  // by level five times: the finest split's knot lines cut every cell of the tube (one knot-line
  // grid per cuboid), so far from the spot one polynomial piece spans many grid cells and the
  // rounds' barrier cells are its parts. F is unchanged by the splits (Eq. 4.9), so the same 8
  // cells fold, now over many more grid cells.
  const GpcSamples samples = ring_samples();
  GpcSpline spline = fitted_ring(samples);
  const double misfit_before = max_misfit(spline, samples);
  REQUIRE(split_down_at(spline, 0, Eigen::Vector3d(0.53, 0.3, 0.07), 5));
  REQUIRE(spline.max_level() == 5);
  const auto before = certify_gpc_jacobian(spline);
  CHECK(before.cells > 8 * 64);
  CHECK(before.certified_cells < before.cells);
  CHECK(max_misfit(spline, samples) <= misfit_before + 1e-12);

  const auto result = untangle_gpc_certificate(spline, samples);
  CHECK(result.final_uncertified == 0);
  CHECK(certify_gpc_jacobian(spline).det_j_lower_bound_rel >= 0.0);
  for (int q = 0; q < 25; ++q) {
    const Eigen::Vector3d a(0.0, 0.3 * (q % 5) / 4.0, 0.2 * (q / 5) / 4.0), b(1.0, a(1), a(2));
    CHECK((spline.evaluate(0, a) - spline.evaluate(0, b)).norm() <= 1e-12);
  }
  CHECK(max_misfit(spline, samples) <= misfit_before + 0.015);
}

TEST_CASE("untangle_gpc_certificate: once few cells are left, a round moves only their functions") {
  // The ring with κ rising from 0.6 to 0.8 near u = 1/2 (its long edges reflex there, Gaussian
  // of width 0.06 in u), 24 × 2 × 2 intervals: the fit folds along all four long edges, every
  // cell of the tube. The first pass opens most of them; the cells left near u = 1/2 need a small
  // part of the functions held by then, so some rounds after it move only those (release build:
  // 4 passes, 2 of them local, 962 functions moved in all against 1,778 with every pass over
  // all held points).
  const double kPi = 3.1415926535897983846;
  GpcSamples samples = ring_samples();
  for (Eigen::Index r = 0; r < samples.uvw.rows(); ++r) {
    const Eigen::Vector3d uvw = samples.uvw.row(r).transpose();
    const double kappa = 0.6 + 0.2 * std::exp(-std::pow((uvw(0) - 0.5) / 0.06, 2));
    const double a = 2.0 * uvw(1) / 0.3 - 1.0, b = 2.0 * uvw(2) / 0.2 - 1.0;
    const double x = a * std::sqrt(1.0 - kappa * b * b), y = b * std::sqrt(1.0 - kappa * a * a);
    const double radius = 1.0 + 0.25 * y, angle = 2.0 * kPi * uvw(0);
    samples.values.row(r) = Eigen::RowVector3d(radius * std::cos(angle), radius * std::sin(angle), 0.25 * x);
  }
  GpcSplineOptions o;
  o.intervals = {{24, 2, 2}};
  GpcSpline spline(torus_domain(false), o);
  fit_gpc_spline(spline, samples);
  const double misfit_before = max_misfit(spline, samples);
  const auto result = untangle_gpc_certificate(spline, samples);
  CHECK(result.initial_uncertified == 96);
  CHECK(result.final_uncertified == 0);
  CHECK(certify_gpc_jacobian(spline).det_j_lower_bound_rel >= 0.0);
  REQUIRE(result.local_passes >= 1);
  REQUIRE(result.local_passes < result.certificate_passes);
  // A local pass moves at most a fifth of the functions held by then, at most of all functions.
  const int n = spline.num_functions();
  CHECK(result.free_functions <= (result.certificate_passes - result.local_passes) * n + result.local_passes * n / 5);
  for (int q = 0; q < 25; ++q) {
    const Eigen::Vector3d a(0.0, 0.3 * (q % 5) / 4.0, 0.2 * (q / 5) / 4.0), b(1.0, a(1), a(2));
    CHECK((spline.evaluate(0, a) - spline.evaluate(0, b)).norm() <= 1e-12);
  }
  // The reflex edges near u = 1/2 need the surface moved there whatever the passes (release
  // build: 0.035 against the section radius 0.25; 0.032 with every pass over all held points).
  CHECK(max_misfit(spline, samples) <= misfit_before + 0.05);
}
