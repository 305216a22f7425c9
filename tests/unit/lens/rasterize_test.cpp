// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/lens_mesh.h"
#include "core/lens/rasterize.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline::lens;
using volspline::test::checkerboard;

TEST_CASE("identity mesh reproduces the image to within one grey level") {
  const Image img = checkerboard(64, 48, 5);
  const LensMesh g = build_grid(64, 48, 9);
  const Eigen::MatrixX2d p = g.xyz.leftCols<2>();
  const Image out = render_textured_mesh(img, p, p, g.triangles, 64, 48);
  REQUIRE(out.pixels.size() == img.pixels.size());
  for (std::size_t i = 0; i < img.pixels.size(); ++i) CHECK(std::abs(int(out.pixels[i]) - int(img.pixels[i])) <= 1);
}

TEST_CASE("every pixel is drawn exactly once on a deformed mesh: no gaps, no overdraw") {
  const LensMesh g = build_grid(40, 40, 7);
  Eigen::MatrixX2d p = g.xyz.leftCols<2>();
  // Interior vertices jitter by at most 1.4 px on 6.7 px cells: no fold, many oblique shared edges.
  for (int v = 0; v < p.rows(); ++v)
    if (p(v, 0) > 0 && p(v, 0) < 40 && p(v, 1) > 0 && p(v, 1) < 40)
      p.row(v) += Eigen::RowVector2d(1.37 * std::sin(v), 0.91 * std::cos(3.0 * v));
  const Image img = checkerboard(40, 40, 4);
  std::vector<int> count;
  render_textured_mesh(img, p, g.xyz.leftCols<2>(), g.triangles, 40, 40, &count);
  for (int c : count) CHECK(c == 1);
}

TEST_CASE("unmoved triangles reproduce the input exactly, moved ones are drawn from the texture") {
  const Image img = checkerboard(40, 40, 3);
  const LensMesh g = build_grid(40, 40, 9);
  Eigen::MatrixX2d p = g.xyz.leftCols<2>();
  // Move one interior vertex (20, 20) by a pixel: only its one-ring (within 5 px) changes.
  for (int v = 0; v < p.rows(); ++v)
    if (p(v, 0) == 20 && p(v, 1) == 20) p.row(v) += Eigen::RowVector2d(1.0, 0.5);
  std::vector<int> count;
  const Image out = render_textured_mesh(img, p, g.xyz.leftCols<2>(), g.triangles, 40, 40, &count);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      CHECK(count[y * 40 + x] == 1);
      if (std::abs(x + 0.5 - 20) > 7 || std::abs(y + 0.5 - 20) > 7) CHECK(out.at(x, y, 0) == img.at(x, y, 0));
    }
}
