// SPDX-License-Identifier: MIT
// Small synthetic meshes with known topology, shared by the mesh module's tests.
#pragma once

#include <cmath>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh::test {

inline TriangleMesh make_mesh(const std::vector<double>& xyz, const std::vector<int>& faces) {
  TriangleMesh mesh;
  mesh.positions.resize(static_cast<int>(xyz.size()) / 3, 3);
  for (int i = 0; i < static_cast<int>(xyz.size()); ++i) mesh.positions(i / 3, i % 3) = xyz[i];
  mesh.triangles.resize(static_cast<int>(faces.size()) / 3, 3);
  for (int i = 0; i < static_cast<int>(faces.size()); ++i) mesh.triangles(i / 3, i % 3) = faces[i];
  return mesh;
}

/// Corner tetrahedron, outward normals: V 4, E 6, F 4.
inline TriangleMesh tetrahedron() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

/// Unit cube [0,1]^3 as 12 outward triangles (the triangulation of shared/data/meshes/cube.off).
inline TriangleMesh unit_cube() {
  return make_mesh({0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 1, 0, 0, 1, 0, 1, 1, 1, 0, 1, 1, 1},
                   {2, 3, 7, 2, 0, 1, 3, 1, 5, 7, 5, 4, 1, 0, 4, 0, 2, 6,
                    7, 6, 2, 1, 3, 2, 5, 7, 3, 4, 6, 7, 4, 5, 1, 6, 4, 0});
}

/// Flat (nx+1)×(ny+1) vertex grid on [0,nx]×[0,ny] in z = 0, normals +z; vertex (i, j) has id
/// j*(nx+1)+i; each cell split along its (i,j)-(i+1,j+1) diagonal. Interior vertices are moved
/// by a deterministic jitter of up to `jitter` in x and y.
inline TriangleMesh flat_grid(int nx, int ny, double jitter = 0.0) {
  std::vector<double> xyz;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const bool interior = i > 0 && i < nx && j > 0 && j < ny;
      const double dx = interior ? jitter * std::sin(1.7 * i + 2.3 * j) : 0.0;
      const double dy = interior ? jitter * std::cos(2.9 * i - 1.3 * j) : 0.0;
      xyz.insert(xyz.end(), {i + dx, j + dy, 0.0});
    }
  }
  std::vector<int> faces;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      faces.insert(faces.end(), {a, b, c, a, c, d});
    }
  }
  return make_mesh(xyz, faces);
}

/// Torus of revolution around z (major radius R, minor r), nu×nv vertices, outward normals.
inline TriangleMesh torus(int nu, int nv, double major = 1.0, double minor = 0.3) {
  const double pi = 3.14159265358979323846;
  std::vector<double> xyz;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      xyz.insert(xyz.end(), {(major + minor * std::cos(v)) * std::cos(u),
                             (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v)});
    }
  }
  std::vector<int> faces;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j;
      const int c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
      faces.insert(faces.end(), {a, b, c, a, c, d});
    }
  }
  return make_mesh(xyz, faces);
}

/// Two disjoint tetrahedra (the second shifted by 5 in x).
inline TriangleMesh two_tetrahedra() {
  TriangleMesh one = tetrahedron();
  TriangleMesh both;
  both.positions.resize(8, 3);
  both.positions << one.positions, one.positions.rowwise() + Eigen::RowVector3d(5, 0, 0);
  both.triangles.resize(8, 3);
  both.triangles << one.triangles, one.triangles.array() + 4;
  return both;
}

/// Möbius strip: n quads around a circle with a half twist, 2n vertices (non-orientable).
inline TriangleMesh mobius_strip(int n) {
  const double pi = 3.14159265358979323846;
  std::vector<double> xyz;
  for (int side = 0; side < 2; ++side) {
    for (int i = 0; i < n; ++i) {
      const double u = 2 * pi * i / n, s = side == 0 ? 0.3 : -0.3;
      const double radius = 1.0 + s * std::cos(u / 2);
      xyz.insert(xyz.end(), {radius * std::cos(u), radius * std::sin(u), s * std::sin(u / 2)});
    }
  }
  std::vector<int> faces;
  for (int i = 0; i < n; ++i) {
    const int top = i, bottom = n + i;
    const int next_top = i + 1 < n ? i + 1 : n;  // the twist swaps the two sides
    const int next_bottom = i + 1 < n ? n + i + 1 : 0;
    faces.insert(faces.end(), {top, bottom, next_bottom, top, next_bottom, next_top});
  }
  return make_mesh(xyz, faces);
}

}  // namespace volspline::mesh::test
