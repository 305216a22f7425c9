// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/linalg/csr_matrix.h"

namespace volspline::linalg::testing {

/// 7-point Laplacian of an nx×ny×nz interior grid with Dirichlet boundary (SPD, diagonal 6).
inline CsrMatrix grid_laplacian(int nx, int ny, int nz) {
  const auto id = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  std::vector<Triplet> t;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const int v = id(i, j, k);
        t.push_back({v, v, 6.0});
        if (i > 0) t.push_back({v, id(i - 1, j, k), -1.0});
        if (i + 1 < nx) t.push_back({v, id(i + 1, j, k), -1.0});
        if (j > 0) t.push_back({v, id(i, j - 1, k), -1.0});
        if (j + 1 < ny) t.push_back({v, id(i, j + 1, k), -1.0});
        if (k > 0) t.push_back({v, id(i, j, k - 1), -1.0});
        if (k + 1 < nz) t.push_back({v, id(i, j, k + 1), -1.0});
      }
    }
  }
  const int n = nx * ny * nz;
  return CsrMatrix::from_triplets(n, n, t);
}

/// Icosphere of radius 1 after `levels` midpoint subdivisions (12, 42, 162, 642 vertices).
inline std::pair<std::vector<Eigen::Vector3d>, std::vector<std::array<int, 3>>> icosphere(
    int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0},   {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g},   {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1},   {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto mid = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const int id = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : f) {
      const int a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  return {v, f};
}

/// Cotan Laplacian (positive semi-definite convention, rows sum to 0) plus mass·(lumped
/// vertex area) on the diagonal, which makes it SPD for mass > 0.
inline CsrMatrix cotan_laplacian_plus_mass(const std::vector<Eigen::Vector3d>& v,
                                           const std::vector<std::array<int, 3>>& f,
                                           double mass) {
  std::vector<Triplet> t;
  for (const auto& tri : f) {
    const double area = 0.5 * (v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]).norm();
    for (int c = 0; c < 3; ++c) {
      const int i = tri[c], j = tri[(c + 1) % 3], k = tri[(c + 2) % 3];
      const Eigen::Vector3d e1 = v[j] - v[i], e2 = v[k] - v[i];
      const double w = 0.5 * e1.dot(e2) / e1.cross(e2).norm();  // half cot of the angle at i
      t.push_back({j, k, -w});
      t.push_back({k, j, -w});
      t.push_back({j, j, w});
      t.push_back({k, k, w});
      t.push_back({i, i, mass * area / 3.0});
    }
  }
  const int n = static_cast<int>(v.size());
  return CsrMatrix::from_triplets(n, n, t);
}

/// Deterministic values in [-1, 1) from a 64-bit LCG (portable, unlike std distributions).
inline Eigen::VectorXd pseudo_random_vector(int n, std::uint64_t seed) {
  Eigen::VectorXd x(n);
  std::uint64_t s = seed * 6364136223846793005ULL + 1442695040888963407ULL;
  for (int i = 0; i < n; ++i) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    x[i] = static_cast<double>(s >> 11) / 9007199254740992.0 * 2.0 - 1.0;
  }
  return x;
}

}  // namespace volspline::linalg::testing
