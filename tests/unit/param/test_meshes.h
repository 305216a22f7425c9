// SPDX-License-Identifier: MIT
// Small closed meshes with known geometry, generated for the param, polycube and pipeline tests.
#pragma once

#include <map>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "core/mesh/triangle_mesh.h"

namespace volspline::test {

/// Surface of the cube [-1,1]³ with n×n quads (2 triangles each) per face, outward oriented.
inline mesh::TriangleMesh subdivided_cube(int n) {
  std::map<std::tuple<int, int, int>, int> ids;
  std::vector<Eigen::Vector3d> points;
  auto vertex = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto found = ids.find(key);
    if (found != ids.end()) return found->second;
    const int id = static_cast<int>(points.size());
    ids.emplace(key, id);
    points.emplace_back(2.0 * i / n - 1.0, 2.0 * j / n - 1.0, 2.0 * k / n - 1.0);
    return id;
  };
  std::vector<Eigen::Vector3i> triangles;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
      auto at = [&](int s, int t) {
        int c[3];
        c[a] = side * n;
        c[b1] = s;
        c[b2] = t;
        return vertex(c[0], c[1], c[2]);
      };
      for (int t = 0; t < n; ++t)
        for (int s = 0; s < n; ++s) {
          const int p00 = at(s, t), p10 = at(s + 1, t), p11 = at(s + 1, t + 1), p01 = at(s, t + 1);
          if (side == 1) {
            triangles.emplace_back(p00, p10, p11);
            triangles.emplace_back(p00, p11, p01);
          } else {
            triangles.emplace_back(p00, p11, p10);
            triangles.emplace_back(p00, p01, p11);
          }
        }
    }
  mesh::TriangleMesh mesh;
  mesh.positions.resize(static_cast<int>(points.size()), 3);
  for (int i = 0; i < static_cast<int>(points.size()); ++i) mesh.positions.row(i) = points[i].transpose();
  mesh.triangles.resize(static_cast<int>(triangles.size()), 3);
  for (int f = 0; f < static_cast<int>(triangles.size()); ++f) mesh.triangles.row(f) = triangles[f].transpose();
  return mesh;
}

/// Unit sphere: the subdivided cube projected onto radius 1.
inline mesh::TriangleMesh cube_sphere(int n) {
  mesh::TriangleMesh mesh = subdivided_cube(n);
  for (int i = 0; i < mesh.num_vertices(); ++i) mesh.positions.row(i).normalize();
  return mesh;
}

/// A copy rotated by `angle_rad` about `axis` (through the origin).
inline mesh::TriangleMesh rotated(const mesh::TriangleMesh& mesh, double angle_rad, const Eigen::Vector3d& axis) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  mesh::TriangleMesh out = mesh;
  for (int i = 0; i < out.num_vertices(); ++i) out.positions.row(i) = (r * mesh.positions.row(i).transpose()).transpose();
  return out;
}

/// Torus (genus 1) with radii 1 and 0.3, n×m quads split into triangles, outward oriented.
inline mesh::TriangleMesh torus(int n, int m) {
  mesh::TriangleMesh mesh;
  mesh.positions.resize(n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * 3.14159265358979323846 * i / n, v = 2 * 3.14159265358979323846 * j / m;
      mesh.positions.row(i * m + j) << (1 + 0.3 * std::cos(v)) * std::cos(u), (1 + 0.3 * std::cos(v)) * std::sin(u),
          0.3 * std::sin(v);
    }
  mesh.triangles.resize(2 * n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m, d = i * m + (j + 1) % m;
      mesh.triangles.row(2 * (i * m + j)) << a, b, c;
      mesh.triangles.row(2 * (i * m + j) + 1) << a, c, d;
    }
  return mesh;
}

}  // namespace volspline::test
