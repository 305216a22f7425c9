// SPDX-License-Identifier: MIT
#include "core/polycube/level_set_split.h"

#include <cassert>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace volspline::polycube {

LevelSetSplit split_at_level(const mesh::TriangleMesh& mesh, const std::vector<double>& value,
                             const std::vector<int>& parent, double level, double snap,
                             const std::vector<char>& frozen) {
  const int n = mesh.num_vertices();
  const int m = mesh.num_faces();
  assert(static_cast<int>(value.size()) == n);
  LevelSetSplit out;
  out.value = value;
  std::vector<double>& f = out.value;

  // Snapping pass, in face order so that it is deterministic.
  std::vector<char> on(n, 0);
  for (int v = 0; v < n; ++v) on[v] = f[v] == level;
  std::vector<std::vector<int>> neighbours(n);
  for (int t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) neighbours[mesh.triangles(t, k)].push_back(mesh.triangles(t, (k + 1) % 3));
  // Each face edge lists its head as a neighbour of its tail; on a closed surface every edge
  // appears in both directions, so these are the full one-rings.
  for (int t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(t, k), b = mesh.triangles(t, (k + 1) % 3);
      if (on[a] || on[b]) continue;
      if (!((f[a] - level) * (f[b] - level) < 0.0)) continue;
      const double span = std::abs(f[b] - f[a]);
      const int near = std::abs(f[a] - level) <= std::abs(f[b] - level) ? a : b;
      if (!(std::abs(f[near] - level) < snap * span)) continue;
      if (!frozen.empty() && frozen[near]) continue;
      bool blocked = false;
      for (int u : neighbours[near]) blocked = blocked || on[u];
      if (blocked) continue;
      f[near] = level;
      on[near] = 1;
    }

  std::vector<Eigen::Vector3d> positions;
  positions.reserve(n + n / 8);
  for (int v = 0; v < n; ++v) positions.push_back(mesh.positions.row(v).transpose());
  std::unordered_map<std::int64_t, int> crossing;
  auto cross = [&](int a, int b) {
    const std::int64_t key = static_cast<std::int64_t>(std::min(a, b)) * (static_cast<std::int64_t>(n) + 1) + std::max(a, b);
    auto it = crossing.find(key);
    if (it != crossing.end()) return it->second;
    const double t = (level - f[a]) / (f[b] - f[a]);
    positions.push_back(positions[a] + t * (positions[b] - positions[a]));
    f.push_back(level);
    out.new_vertex_edge.push_back({a, b});
    out.new_vertex_t.push_back(t);
    const int id = static_cast<int>(positions.size()) - 1;
    crossing.emplace(key, id);
    return id;
  };
  std::vector<std::array<int, 3>> faces;
  faces.reserve(m + m / 8);
  out.parent_face.reserve(m + m / 8);
  auto emit = [&](int a, int b, int c, int t) {
    faces.push_back({a, b, c});
    out.parent_face.push_back(parent.empty() ? t : parent[t]);
  };
  auto side = [&](int v) { return f[v] < level ? -1 : (f[v] > level ? 1 : 0); };
  for (int t = 0; t < m; ++t) {
    const std::array<int, 3> c = {mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2)};
    const std::array<int, 3> s = {side(c[0]), side(c[1]), side(c[2])};
    const bool neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
    const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0;
    if (!(neg && pos)) {
      emit(c[0], c[1], c[2], t);
      continue;
    }
    int zero = -1;
    for (int k = 0; k < 3; ++k)
      if (s[k] == 0) zero = k;
    if (zero >= 0) {
      const int a = c[zero], b = c[(zero + 1) % 3], d = c[(zero + 2) % 3];
      const int p = cross(b, d);
      emit(a, b, p, t);
      emit(a, p, d, t);
      continue;
    }
    // The vertex alone on its side.
    int lone = 0;
    for (int k = 0; k < 3; ++k)
      if (s[k] != s[(k + 1) % 3] && s[k] != s[(k + 2) % 3]) lone = k;
    const int a = c[lone], b = c[(lone + 1) % 3], d = c[(lone + 2) % 3];
    const int p = cross(a, b), q = cross(d, a);
    emit(a, p, q, t);
    if ((positions[p] - positions[d]).squaredNorm() <= (positions[b] - positions[q]).squaredNorm()) {
      emit(p, b, d, t);
      emit(p, d, q, t);
    } else {
      emit(p, b, q, t);
      emit(b, d, q, t);
    }
  }
  out.mesh.positions.resize(static_cast<int>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) out.mesh.positions.row(static_cast<int>(v)) = positions[v].transpose();
  out.mesh.triangles.resize(static_cast<int>(faces.size()), 3);
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k) out.mesh.triangles(static_cast<int>(t), k) = faces[t][k];
  return out;
}

}  // namespace volspline::polycube
