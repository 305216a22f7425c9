// SPDX-License-Identifier: MIT
#include "core/lens/lens_texture.h"

#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "core/common/error.h"

namespace volspline::lens {

Eigen::MatrixX2d harmonic_texture(const LensMesh& lens) {
  const int n = static_cast<int>(lens.xyz.rows());
  Eigen::MatrixX2d uv = lens.xyz.leftCols<2>();
  std::vector<int> unknown(n, -1);
  int num_unknowns = 0;
  for (int v = 0; v < n; ++v)
    if (lens.in_roi[v]) unknown[v] = num_unknowns++;
  if (num_unknowns == 0) return uv;

  // Mean-value weights: w_ij = (tan(α/2) + tan(β/2)) / |v_j − v_i| with α, β the 3D angles at v_i
  // of the two triangles sharing edge ij, accumulated triangle by triangle.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(std::size_t(num_unknowns) * 14);
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(num_unknowns, 2);
  for (int t = 0; t < lens.triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int i = lens.triangles(t, c);
      if (unknown[i] < 0) continue;
      const int j = lens.triangles(t, (c + 1) % 3), k = lens.triangles(t, (c + 2) % 3);
      const Eigen::Vector3d a = lens.xyz.row(j) - lens.xyz.row(i), b = lens.xyz.row(k) - lens.xyz.row(i);
      const double la = a.norm(), lb = b.norm();
      const double sin_ab = a.cross(b).norm(), cos_ab = a.dot(b);
      const double tan_half = (la * lb - cos_ab) / sin_ab;  // tan(θ/2) = (1 − cos θ)/sin θ
      for (const auto& [other, length] : {std::pair<int, double>{j, la}, std::pair<int, double>{k, lb}}) {
        const double w = tan_half / length;
        triplets.emplace_back(unknown[i], unknown[i], w);
        if (unknown[other] >= 0)
          triplets.emplace_back(unknown[i], unknown[other], -w);
        else
          rhs.row(unknown[i]) += w * uv.row(other);
      }
    }
  Eigen::SparseMatrix<double> A(num_unknowns, num_unknowns);
  A.setFromTriplets(triplets.begin(), triplets.end());

  Eigen::MatrixX2d guess(num_unknowns, 2);
  for (int v = 0; v < n; ++v)
    if (unknown[v] >= 0) guess.row(unknown[v]) = uv.row(v);

  // Mean-value weights are not symmetric: BiCGSTAB with an incomplete LU on the ROI-interior
  // unknowns only (everything else is Dirichlet, §6.3.2), started from the planar positions.
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::IncompleteLUT<double>> solver;
  solver.preconditioner().setFillfactor(8);
  solver.setTolerance(1e-9);
  solver.setMaxIterations(4 * num_unknowns + 100);
  solver.compute(A);
  for (int col = 0; col < 2; ++col) {
    const Eigen::VectorXd x = solver.solveWithGuess(rhs.col(col), guess.col(col));
    if (solver.info() != Eigen::Success || !x.allFinite())
      throw Error("lens texturing: harmonic solve failed (degenerate lens mesh)");
    for (int v = 0; v < n; ++v)
      if (unknown[v] >= 0) uv(v, col) = x(unknown[v]);
  }
  return uv;
}

}  // namespace volspline::lens
