// SPDX-License-Identifier: MIT
#include "core/spline/bezier_extraction.h"

#include <cassert>

namespace volspline::spline {

namespace {

// b_i = Σ_{a ≤ i} C(i, a)/C(3, a)·c_a: the power basis s^a in cubic Bernstein form.
constexpr double kPowerToBernstein[4][4] = {
    {1.0, 0.0, 0.0, 0.0},
    {1.0, 1.0 / 3.0, 0.0, 0.0},
    {1.0, 2.0 / 3.0, 1.0 / 3.0, 0.0},
    {1.0, 1.0, 1.0, 1.0},
};

}  // namespace

void power_to_bernstein(const double* power, int channels, double* bernstein) {
  assert(channels >= 1 && channels <= 4);
  // power index ((4a + b)·4 + c)·ch: convert w (c), then v (b), then u (a), writing (i + 4j + 16k)·ch.
  double t1[64 * 4], t2[64 * 4];
  for (int ab = 0; ab < 16; ++ab)
    for (int k = 0; k < 4; ++k)
      for (int ch = 0; ch < channels; ++ch) {
        double s = 0.0;
        for (int c = 0; c <= k; ++c) s += kPowerToBernstein[k][c] * power[(ab * 4 + c) * channels + ch];
        t1[(ab * 4 + k) * channels + ch] = s;  // (a, b, k)
      }
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        for (int ch = 0; ch < channels; ++ch) {
          double s = 0.0;
          for (int b = 0; b <= j; ++b) s += kPowerToBernstein[j][b] * t1[((4 * a + b) * 4 + k) * channels + ch];
          t2[((4 * a + j) * 4 + k) * channels + ch] = s;  // (a, j, k)
        }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        for (int ch = 0; ch < channels; ++ch) {
          double s = 0.0;
          for (int a = 0; a <= i; ++a) s += kPowerToBernstein[i][a] * t2[((4 * a + j) * 4 + k) * channels + ch];
          bernstein[(i + 4 * j + 16 * k) * channels + ch] = s;
        }
}

BezierCell extract_bezier_cell(const TSpline& spline, int cell) {
  assert(cell >= 0 && cell < spline.num_cells());
  BezierCell out;
  out.cell = cell;
  out.dimension = spline.dimension();
  const std::array<int, 3> k = spline.cell_index(cell);
  for (int a = 0; a < 3; ++a) {
    out.uvw_min[a] = spline.knot_lines(a)[k[a]];
    out.uvw_max[a] = spline.knot_lines(a)[k[a] + 1];
  }
  double numerator[64 * 4], denominator[64];
  spline.cell_power_form(cell, numerator, denominator);
  power_to_bernstein(numerator, out.dimension, out.points.data());
  power_to_bernstein(denominator, 1, out.weights.data());
  return out;
}

std::vector<BezierCell> extract_bezier_cells(const TSpline& spline) {
  std::vector<BezierCell> cells(spline.num_cells());
  for (int c = 0; c < spline.num_cells(); ++c) cells[c] = extract_bezier_cell(spline, c);
  return cells;
}

void cubic_bernstein(double t, double* value, double* derivative) {
  const double r = 1.0 - t;
  value[0] = r * r * r;
  value[1] = 3.0 * t * r * r;
  value[2] = 3.0 * t * t * r;
  value[3] = t * t * t;
  if (derivative) {
    derivative[0] = -3.0 * r * r;
    derivative[1] = 3.0 * r * (r - 2.0 * t);
    derivative[2] = 3.0 * t * (2.0 * r - t);
    derivative[3] = 3.0 * t * t;
  }
}

void evaluate_bezier_cell(const BezierCell& cell, const Eigen::Vector3d& s, double* value, double* jacobian) {
  const int dim = cell.dimension;
  double b[3][4], db[3][4];
  for (int a = 0; a < 3; ++a) cubic_bernstein(s[a], b[a], db[a]);
  for (int d = 0; d < dim; ++d) value[d] = 0.0;
  if (jacobian)
    for (int d = 0; d < 3 * dim; ++d) jacobian[d] = 0.0;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const double* p = cell.points.data() + (i + 4 * j + 16 * k) * dim;
        const double basis = b[0][i] * b[1][j] * b[2][k];
        for (int d = 0; d < dim; ++d) value[d] += basis * p[d];
        if (!jacobian) continue;
        const double g[3] = {db[0][i] * b[1][j] * b[2][k], b[0][i] * db[1][j] * b[2][k], b[0][i] * b[1][j] * db[2][k]};
        for (int a = 0; a < 3; ++a)
          for (int d = 0; d < dim; ++d) jacobian[d + dim * a] += g[a] * p[d];
      }
  if (jacobian)
    for (int a = 0; a < 3; ++a) {
      const double inverse_width = 1.0 / (cell.uvw_max[a] - cell.uvw_min[a]);
      for (int d = 0; d < dim; ++d) jacobian[d + dim * a] *= inverse_width;
    }
}

}  // namespace volspline::spline
