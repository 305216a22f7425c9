// SPDX-License-Identifier: MIT
// Small synthetic meshes with known topology and geometry, shared by the tests of every module:
// tetrahedron, cubes, torus (genus 1), flat grid, Möbius strip, voxel solids (two-hole slab, genus 2).
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "core/mesh/mesh_lists.h"
#include "core/mesh/triangle_mesh.h"

namespace volspline::test {


inline mesh::TriangleMesh make_mesh(const std::vector<double>& xyz, const std::vector<int>& faces) {
  mesh::TriangleMesh mesh;
  mesh.positions.resize(static_cast<int>(xyz.size()) / 3, 3);
  for (int i = 0; i < static_cast<int>(xyz.size()); ++i) mesh.positions(i / 3, i % 3) = xyz[i];
  mesh.triangles.resize(static_cast<int>(faces.size()) / 3, 3);
  for (int i = 0; i < static_cast<int>(faces.size()); ++i) mesh.triangles(i / 3, i % 3) = faces[i];
  return mesh;
}

/// The mesh of a point list and vertex id triples into it.
inline mesh::TriangleMesh mesh_of(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& tris) {
  return {mesh::positions_from(points), mesh::triangles_from(tris)};
}

/// Corner tetrahedron, outward normals: V 4, E 6, F 4.
inline mesh::TriangleMesh tetrahedron() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

/// Unit cube [0,1]^3 as 12 outward triangles (the triangulation of shared/data/meshes/cube.off).
inline mesh::TriangleMesh unit_cube() {
  return make_mesh({0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 1, 0, 0, 1, 0, 1, 1, 1, 0, 1, 1, 1},
                   {2, 3, 7, 2, 0, 1, 3, 1, 5, 7, 5, 4, 1, 0, 4, 0, 2, 6,
                    7, 6, 2, 1, 3, 2, 5, 7, 3, 4, 6, 7, 4, 5, 1, 6, 4, 0});
}

/// Axis-aligned cube [offset, offset + size]^3 (vertex v has corner bits x = v&1, y = v>>1&1,
/// z = v>>2&1), 12 outward triangles. The default size 1/3 makes text output keep all 17 digits.
inline mesh::TriangleMesh cube(double offset = 0.1, double size = 1.0 / 3.0) {
  mesh::TriangleMesh m;
  m.positions.resize(8, 3);
  for (int v = 0; v < 8; ++v)
    m.positions.row(v) << offset + (v & 1) * size, offset + ((v >> 1) & 1) * size, offset + ((v >> 2) & 1) * size;
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5,
      3, 7, 5;
  return m;
}

/// Flat (nx+1)×(ny+1) vertex grid on [0,nx]×[0,ny] in z = 0, normals +z; vertex (i, j) has id
/// j*(nx+1)+i; each cell split along its (i,j)-(i+1,j+1) diagonal. Interior vertices are moved
/// by a deterministic jitter of up to `jitter` in x and y.
inline mesh::TriangleMesh flat_grid(int nx, int ny, double jitter = 0.0) {
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

/// Torus (genus 1) of revolution around z (major radius R, minor r), nu×nv vertices, each quad
/// (i, j)–(i+1, j+1) split into two triangles, outward normals.
inline mesh::TriangleMesh torus(int nu, int nv, double major = 1.0, double minor = 0.3) {
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
inline mesh::TriangleMesh two_tetrahedra() {
  mesh::TriangleMesh one = tetrahedron();
  mesh::TriangleMesh both;
  both.positions.resize(8, 3);
  both.positions << one.positions, one.positions.rowwise() + Eigen::RowVector3d(5, 0, 0);
  both.triangles.resize(8, 3);
  both.triangles << one.triangles, one.triangles.array() + 4;
  return both;
}

/// Möbius strip: n quads around a circle with a half twist, 2n vertices (non-orientable).
inline mesh::TriangleMesh mobius_strip(int n) {
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

/// The boundary of the voxels (x, y, z) in [0, nx)×[0, ny)×[0, nz) where cell(x, y, z) holds, each
/// voxel face split into k × k quads, two triangles each; outward oriented; voxel size 1.
inline mesh::TriangleMesh voxel_solid(int nx, int ny, int nz, int k, const std::function<bool(int, int, int)>& cell) {
  auto filled = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return false;
    return cell(x, y, z);
  };
  std::map<std::array<long, 3>, int> ids;
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::array<int, 3>> tris;
  auto vertex = [&](const std::array<long, 3>& q) {
    auto it = ids.find(q);
    if (it != ids.end()) return it->second;
    pts.emplace_back(double(q[0]) / k, double(q[1]) / k, double(q[2]) / k);
    return ids[q] = static_cast<int>(pts.size()) - 1;
  };
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z) {
        if (!filled(x, y, z)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int dir : {-1, 1}) {
            std::array<int, 3> nb = {x, y, z};
            nb[axis] += dir;
            if (filled(nb[0], nb[1], nb[2])) continue;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int a = 0; a < k; ++a)
              for (int b = 0; b < k; ++b) {
                std::array<std::array<long, 3>, 4> c;
                for (int q = 0; q < 4; ++q) {
                  std::array<long, 3> p = {long(x) * k, long(y) * k, long(z) * k};
                  p[axis] += dir > 0 ? k : 0;
                  p[u] += a + ((q == 1 || q == 2) ? 1 : 0);
                  p[v] += b + ((q >= 2) ? 1 : 0);
                  c[q] = p;
                }
                int i0 = vertex(c[0]), i1 = vertex(c[1]), i2 = vertex(c[2]), i3 = vertex(c[3]);
                if (dir < 0) std::swap(i1, i3);
                tris.push_back({i0, i1, i2});
                tris.push_back({i0, i2, i3});
              }
          }
      }
  return mesh_of(pts, tris);
}

/// The two-hole slab: 7×3×2 voxels with the cells (1, 1, z) and (5, 1, z) removed (genus 2).
inline mesh::TriangleMesh two_hole_slab(int k) {
  return voxel_solid(7, 3, 2, k, [](int x, int y, int) { return !(y == 1 && (x == 1 || x == 5)); });
}

/// A cube's wireframe of square bars: 3×3×3 voxels without those on the three centre lines
/// (genus 5; symmetric about its diagonals), each voxel face split k × k.
inline mesh::TriangleMesh cube_frame(int k) {
  return voxel_solid(3, 3, 3, k, [](int x, int y, int z) { return (x == 1) + (y == 1) + (z == 1) < 2; });
}

}  // namespace volspline::test
