// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/baseline_lens.h"
#include "core/lens/lens_measures.h"
#include "core/lens/lens_mesh.h"

using namespace volspline::lens;

TEST_CASE("similarity maps have zero distortion and their scale as magnification") {
  const LensMesh g = build_grid(50, 50, 11);
  const Eigen::MatrixX2d tex = g.xyz.leftCols<2>();
  Eigen::Matrix2d S;
  S << 1.2, -1.6, 1.6, 1.2;  // scale 2, rotation
  const Eigen::MatrixX2d out = tex * S.transpose();
  const ShapeDistortion d = measure_distortion(out, tex, g.triangles);
  CHECK(d.max < 1e-12);
  CHECK(d.flipped_triangles == 0);
  CHECK(measure_magnification(out, tex, g.triangles, {25, 25}, 10) == doctest::Approx(2.0).epsilon(1e-12));
}

TEST_CASE("a shear is distorted, a reflection is flipped") {
  const LensMesh g = build_grid(10, 10, 3);
  const Eigen::MatrixX2d tex = g.xyz.leftCols<2>();
  Eigen::MatrixX2d shear = tex;
  shear.col(0) += 0.5 * tex.col(1);
  CHECK(measure_distortion(shear, tex, g.triangles).max > 0.01);
  Eigen::MatrixX2d mirror = tex;
  mirror.col(0) *= -1;
  const ShapeDistortion d = measure_distortion(mirror, tex, g.triangles);
  CHECK(d.flipped_triangles == g.triangles.rows());
  CHECK(d.max == 1.0);
}

TEST_CASE("baselines: fisheye and bifocal magnify the centre by the parameter, fix the outside") {
  const LensMesh g = build_grid(100, 100, 41);
  const Eigen::MatrixX2d tex = g.xyz.leftCols<2>();
  const std::vector<RadialLens> lenses = {{{50, 50}, 15, 30}};
  for (BaselineKind kind : {BaselineKind::Fisheye, BaselineKind::Bifocal, BaselineKind::Zoom}) {
    const Eigen::MatrixX2d out = baseline_positions(kind, tex, lenses, 2.0);
    // Within 1.5 px of the centre the fisheye is 2× up to a first-order term.
    CHECK(measure_magnification(out, tex, g.triangles, {50, 50}, 1.5) == doctest::Approx(2.0).epsilon(0.1));
    for (int v = 0; v < tex.rows(); ++v)
      if ((tex.row(v) - Eigen::RowVector2d(50, 50)).norm() >= 30) CHECK(out.row(v) == tex.row(v));
  }
  CHECK(measure_distortion(baseline_positions(BaselineKind::Fisheye, tex, lenses, 2.0), tex, g.triangles).flipped_triangles == 0);
}

TEST_CASE("focus mask splits the distortion: a similarity inside, a shear outside") {
  const LensMesh g = build_grid(40, 40, 11);
  const Eigen::MatrixX2d tex = g.xyz.leftCols<2>();
  Eigen::MatrixX2d out = 2.0 * tex;
  std::vector<char> focus(std::size_t(g.triangles.rows()), 0);
  for (int v = 0; v < tex.rows(); ++v)
    if (tex(v, 0) > 20) out(v, 0) += 0.8 * (tex(v, 0) - 20) + 0.5 * tex(v, 1);  // shear right of x = 20
  for (int t = 0; t < g.triangles.rows(); ++t) {
    bool left = true;
    for (int k = 0; k < 3; ++k) left = left && tex(g.triangles(t, k), 0) <= 20;
    focus[t] = left;
  }
  const ShapeDistortion d = measure_distortion(out, tex, g.triangles, focus);
  CHECK(d.focus_triangles == g.triangles.rows() / 2);
  CHECK(d.max_focus < 1e-12);  // a pure scaling in the focus
  CHECK(d.max > 0.01);
  CHECK(d.sum_focus < 1e-10);
  const ShapeDistortion whole = measure_distortion(out, tex, g.triangles);
  CHECK(whole.sum == doctest::Approx(d.sum).epsilon(1e-12));
  CHECK(whole.focus_triangles == 0);
}
