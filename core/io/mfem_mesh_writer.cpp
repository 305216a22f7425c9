// SPDX-License-Identifier: MIT
#include "core/io/mfem_mesh_writer.h"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "core/io/number_text.h"

namespace volspline::io {

namespace {

// Union–find over (patch, axis) with the direction of each member relative to its root.
struct SignedUnionFind {
  std::vector<int> parent;
  std::vector<int> sign;  // direction relative to parent
  explicit SignedUnionFind(int n) : parent(n), sign(n, 1) {
    for (int i = 0; i < n; ++i) parent[i] = i;
  }
  std::pair<int, int> find(int a) {
    int s = 1;
    while (parent[a] != a) {
      s *= sign[a];
      a = parent[a];
    }
    return {a, s};
  }
  // b runs in direction s relative to a.
  void unite(int a, int b, int s) {
    const auto [ra, sa] = find(a);
    const auto [rb, sb] = find(b);
    if (ra == rb) return;
    parent[rb] = ra;
    sign[rb] = sa * s * sb;
  }
};

void append_line(std::string& out, std::initializer_list<long long> values) {
  bool first = true;
  for (const long long v : values) {
    if (!first) out += ' ';
    first = false;
    append_number(out, v);
  }
  out += '\n';
}

}  // namespace

std::string serialize_mfem_mesh(const spline::BsplineMultipatch& multipatch) {
  const int P = int(multipatch.patches.size());
  // MFEM's hex corner k is our corner (c&1, c>>1&1, c>>2&1) = kCorner[k].
  constexpr int kCorner[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  SignedUnionFind classes(3 * P);
  for (const spline::MultipatchInterface& in : multipatch.interfaces)
    for (int i = 0; i < 3; ++i)
      if (i != in.side[0] / 2) classes.unite(3 * in.patch[0] + i, 3 * in.patch[1] + in.axis[i], in.sign[i]);
  std::map<int, int> class_id;
  for (int k = 0; k < 3 * P; ++k) class_id.emplace(classes.find(k).first, int(class_id.size()));

  std::string out = "MFEM NURBS mesh v1.0\n\n# volspline: one patch per cuboid box, cubic, polynomial (weights 1)\n\ndimension\n3\n\nelements\n";
  append_number(out, (long long)P);
  out += '\n';
  for (int p = 0; p < P; ++p) {
    out += "1 5";
    for (int k = 0; k < 8; ++k) {
      out += ' ';
      append_number(out, (long long)multipatch.corner_vertex[p][kCorner[k]]);
    }
    out += '\n';
  }
  out += "\nboundary\n";
  append_number(out, (long long)multipatch.boundary.size());
  out += '\n';
  for (const spline::MultipatchBoundary& b : multipatch.boundary) {
    const int a = b.side / 2, t1 = (a + 1) % 3, t2 = (a + 2) % 3, at = (b.side % 2) << a;
    const std::array<int, 8>& v = multipatch.corner_vertex[b.patch];
    append_line(out, {1, 3, v[at], v[at | 1 << t1], v[at | 1 << t1 | 1 << t2], v[at | 1 << t2]});
  }
  // Every edge once (vertex pairs are unique by the precondition), pointing the way its knot
  // vector class runs.
  std::map<std::pair<int, int>, std::pair<int, bool>> edges;  // sorted ends -> class, forward
  for (int p = 0; p < P; ++p)
    for (int a = 0; a < 3; ++a) {
      const auto [root, s] = classes.find(3 * p + a);
      for (int e = 0; e < 4; ++e) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int c0 = (e & 1) << b | (e >> 1) << c, c1 = c0 | 1 << a;
        int v0 = multipatch.corner_vertex[p][c0], v1 = multipatch.corner_vertex[p][c1];
        if (s < 0) std::swap(v0, v1);
        edges.emplace(std::minmax(v0, v1), std::make_pair(class_id.at(root), v0 < v1));
      }
    }
  out += "\nedges\n";
  append_number(out, (long long)edges.size());
  out += '\n';
  for (const auto& [ends, info] : edges) {
    const auto [lo, hi] = ends;
    if (info.second)
      append_line(out, {info.first, lo, hi});
    else
      append_line(out, {info.first, hi, lo});
  }
  out += "\nvertices\n";
  append_number(out, (long long)multipatch.num_vertices);
  out += "\n\npatches\n";
  for (int p = 0; p < P; ++p) {
    const spline::BsplineVolume& volume = multipatch.patches[p];
    out += "\n# patch ";
    append_number(out, (long long)p);
    out += ": cuboid ";
    append_number(out, (long long)multipatch.cuboid[p]);
    out += "\nknotvectors\n3\n";
    for (int a = 0; a < 3; ++a) {
      out += "3 ";
      append_number(out, (long long)volume.num_control(a));
      for (const double k : volume.knots(a)) {
        out += ' ';
        append_number(out, k);
      }
      out += '\n';
    }
    out += "\ndimension\n";
    append_number(out, (long long)volume.dimension());
    out += "\n\ncontrolpoints\n";
    const Eigen::MatrixXd& Q = volume.control_points();
    for (Eigen::Index i = 0; i < Q.rows(); ++i) {
      for (Eigen::Index d = 0; d < Q.cols(); ++d) {
        append_number(out, Q(i, d));
        out += ' ';
      }
      out += "1\n";
    }
  }
  return out;
}

}  // namespace volspline::io
