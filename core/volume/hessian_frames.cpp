// SPDX-License-Identifier: MIT
#include "core/volume/hessian_frames.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "core/linalg/parallel_for.h"

namespace volspline::volume {

namespace {

Eigen::Vector3d canonical_sign(const Eigen::Vector3d& v) {
  int largest = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(v[a]) > std::abs(v[largest])) largest = a;
  return v[largest] < 0 ? Eigen::Vector3d(-v) : v;
}

}  // namespace

Eigen::Matrix3d principal_frame(const Eigen::Matrix3d& tensor, Eigen::Vector3d* eigenvalues) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(tensor);
  const Eigen::Vector3d lambda = solver.eigenvalues();
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (std::abs(lambda[a]) != std::abs(lambda[b])) return std::abs(lambda[a]) > std::abs(lambda[b]);
    return lambda[a] > lambda[b];
  });
  Eigen::Matrix3d frame;
  frame.row(0) = canonical_sign(solver.eigenvectors().col(order[0]).normalized()).transpose();
  frame.row(1) = canonical_sign(solver.eigenvectors().col(order[1]).normalized()).transpose();
  frame.row(2) = frame.row(0).cross(frame.row(1)).normalized();
  if (eigenvalues) *eigenvalues = Eigen::Vector3d(lambda[order[0]], lambda[order[1]], lambda[order[2]]);
  return frame;
}

std::vector<Eigen::Matrix3d> hessian_frames(const std::vector<Eigen::Matrix3d>& hessians, int threads) {
  assert(threads >= 1);
  std::vector<Eigen::Matrix3d> frames(hessians.size());
  // Each frame depends on its own tensor only: any split gives the same frames.
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (hessians.size() + kChunk - 1) / kChunk;
  linalg::parallel_for(threads, static_cast<int>(chunks), [&](int chunk) {
    const std::size_t end = std::min(hessians.size(), (chunk + 1) * kChunk);
    for (std::size_t i = chunk * kChunk; i < end; ++i) frames[i] = principal_frame(hessians[i]);
  });
  return frames;
}

}  // namespace volspline::volume
