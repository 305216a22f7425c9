// SPDX-License-Identifier: MIT
#include "core/param/hex_padding.h"

#include <algorithm>
#include <cassert>

#include "core/mesh/hex_quality.h"

namespace volspline::param {

HexMesh pad_hex_mesh(const mesh::Positions& xyz, const std::vector<std::array<int, 8>>& hexes,
                     const std::vector<int>& hex_group, const std::vector<std::uint8_t>& surface_faces, double depth) {
  assert(hexes.size() == hex_group.size() && hexes.size() == surface_faces.size());
  assert(depth > 0.0 && depth < 1.0);
  const int n = static_cast<int>(xyz.rows());
  // Nodes on a surface face, and the mean centroid of every node's hexes.
  std::vector<int> copy(n, -1);
  int copies = 0;
  for (std::size_t h = 0; h < hexes.size(); ++h)
    for (int f = 0; f < 6; ++f) {
      if (!(surface_faces[h] >> f & 1)) continue;
      for (int q = 0; q < 8; ++q)
        if ((q >> (f / 2) & 1) == f % 2 && copy[hexes[h][q]] < 0) copy[hexes[h][q]] = n + copies++;
    }
  Eigen::MatrixX3d centroid = Eigen::MatrixX3d::Zero(n, 3);
  std::vector<int> count(n, 0);
  for (const auto& hex : hexes) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int v : hex) c += xyz.row(v);
    c /= 8.0;
    for (int v : hex)
      if (copy[v] >= 0) {
        centroid.row(v) += c;
        ++count[v];
      }
  }
  HexMesh out;
  out.xyz.resize(n + copies, 3);
  out.xyz.topRows(n) = xyz;
  out.on_surface.assign(n + copies, 0);
  out.copy_of.assign(n + copies, -1);
  for (int v = 0; v < n; ++v)
    if (copy[v] >= 0) {
      out.on_surface[v] = 1;
      out.copy_of[copy[v]] = v;
      out.xyz.row(copy[v]) = xyz.row(v) + depth * (centroid.row(v) / count[v] - xyz.row(v));
    }
  out.hexes.reserve(hexes.size() * 5 / 4);
  for (const auto& hex : hexes) {
    std::array<int, 8> inner = hex;
    for (int& v : inner)
      if (copy[v] >= 0) v = copy[v];
    out.hexes.push_back(inner);
  }
  out.hex_group = hex_group;
  out.padding.assign(hexes.size(), 0);
  for (std::size_t h = 0; h < hexes.size(); ++h)
    for (int f = 0; f < 6; ++f) {
      if (!(surface_faces[h] >> f & 1)) continue;
      // The padding hex continues hex h across face f: its nodes on that side are the surface
      // nodes, those on the other side their copies (the same orientation as hex h).
      const int a = f / 2, side = f % 2;
      std::array<int, 8> pad;
      for (int q = 0; q < 8; ++q) pad[q] = (q >> a & 1) == side ? hexes[h][q] : copy[hexes[h][q ^ (1 << a)]];
      out.hexes.push_back(pad);
      out.hex_group.push_back(hex_group[h]);
      out.padding.push_back(1);
    }
  return out;
}

HexMeshQuality hex_mesh_quality(const HexMesh& mesh) {
  HexMeshQuality q;
  for (const auto& hex : mesh.hexes) {
    std::array<Eigen::Vector3d, 8> x;
    for (int c = 0; c < 8; ++c) x[c] = mesh.xyz.row(hex[c]).transpose();
    const double sj = mesh::hex_scaled_jacobian(x);
    q.min_scaled_jacobian = std::min(q.min_scaled_jacobian, sj);
    if (sj <= 0.0) ++q.num_inverted;
  }
  return q;
}

}  // namespace volspline::param
