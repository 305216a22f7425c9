// SPDX-License-Identifier: MIT
#include "core/polycube/interface_disc.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <unordered_map>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/mesh_lists.h"

namespace volspline::polycube {

InterfaceDisc triangulate_interface_disc(const mesh::Positions& loop_xyz) {
  const int m = static_cast<int>(loop_xyz.rows());
  assert(m >= 3);
  const double pi = 3.14159265358979323846;
  const int rings = std::clamp(static_cast<int>(std::lround(m / (2.0 * pi))), 1, 12);
  const Eigen::RowVector3d centre = loop_xyz.colwise().mean();
  // Ring r (0 = the loop, rings = the centre point) has m vertices for r < rings.
  const int total = m * rings + 1;
  InterfaceDisc disc;
  disc.num_loop_vertices = m;
  disc.positions.resize(total, 3);
  auto id = [&](int r, int i) { return r == rings ? m * rings : r * m + (i % m); };
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < m; ++i) {
      const double t = static_cast<double>(r) / rings;
      disc.positions.row(id(r, i)) = (1.0 - t) * loop_xyz.row(i) + t * centre;
    }
  disc.positions.row(total - 1) = centre;
  std::vector<std::array<int, 3>> tris;
  for (int r = 0; r + 1 < rings; ++r)
    for (int i = 0; i < m; ++i) {
      tris.push_back({id(r, i), id(r, i + 1), id(r + 1, i + 1)});
      tris.push_back({id(r, i), id(r + 1, i + 1), id(r + 1, i)});
    }
  for (int i = 0; i < m; ++i) tris.push_back({id(rings - 1, i), id(rings - 1, i + 1), id(rings, 0)});
  disc.triangles = mesh::triangles_from(tris);

  // Harmonic interior (uniform weights, loop fixed).
  const int interior = total - m;
  std::vector<std::vector<int>> nb(total);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      nb[t[k]].push_back(t[(k + 1) % 3]);
      nb[t[(k + 1) % 3]].push_back(t[k]);
    }
  std::vector<linalg::Triplet> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(interior, 3), x0(interior, 3);
  for (int v = m; v < total; ++v) {
    std::sort(nb[v].begin(), nb[v].end());
    nb[v].erase(std::unique(nb[v].begin(), nb[v].end()), nb[v].end());
    const int row = v - m;
    x0.row(row) = disc.positions.row(v);
    triplets.push_back({row, row, static_cast<double>(nb[v].size())});
    for (int u : nb[v]) {
      if (u < m)
        rhs.row(row) += disc.positions.row(u);
      else
        triplets.push_back({row, u - m, -1.0});
    }
  }
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(interior, interior, triplets);
  linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
  cg.set_tolerance(1e-10);
  cg.compute(a);
  const Eigen::MatrixXd x = cg.solve(rhs, x0);
  for (int v = m; v < total; ++v) disc.positions.row(v) = x.row(v - m);
  return disc;
}

namespace {

using Tri = std::array<Eigen::Vector3d, 3>;

// Segment pq crosses triangle t strictly inside both (Möller–Trumbore).
bool segment_crosses(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Tri& t) {
  const Eigen::Vector3d d = q - p;
  const Eigen::Vector3d e1 = t[1] - t[0], e2 = t[2] - t[0];
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  const double scale = e1.norm() * e2.norm() * d.norm();
  if (!(std::abs(det) > 1e-12 * scale)) return false;
  const Eigen::Vector3d s = p - t[0];
  const double u = s.dot(h) / det;
  if (u <= 0.0 || u >= 1.0) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  if (v <= 0.0 || u + v >= 1.0) return false;
  const double w = e2.dot(qv) / det;
  return w > 0.0 && w < 1.0;
}

bool triangles_cross(const Tri& a, const Tri& b) {
  for (int k = 0; k < 3; ++k)
    if (segment_crosses(a[k], a[(k + 1) % 3], b) || segment_crosses(b[k], b[(k + 1) % 3], a)) return true;
  return false;
}

// Solid angle of triangle abc seen from p (Van Oosterom & Strackee).
double solid_angle(const Eigen::Vector3d& p, const Tri& t) {
  const Eigen::Vector3d a = t[0] - p, b = t[1] - p, c = t[2] - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace

DiscEmbedding check_interface_discs(const mesh::TriangleMesh& surface, const std::vector<InterfaceDisc>& discs,
                                    const std::vector<std::vector<int>>& loop_ids) {
  DiscEmbedding out;
  out.crossings.assign(discs.size(), 0);
  // All triangles in one list: surface first (vertex ids as they are), then each disc (loop
  // vertices mapped to their surface ids, interior vertices to fresh ids).
  std::vector<Tri> tris;
  std::vector<std::array<int, 3>> ids;
  std::vector<int> owner;  // −1 surface, else disc index
  for (int t = 0; t < surface.num_faces(); ++t) {
    Tri tri;
    for (int k = 0; k < 3; ++k) tri[k] = surface.positions.row(surface.triangles(t, k)).transpose();
    tris.push_back(tri);
    ids.push_back({surface.triangles(t, 0), surface.triangles(t, 1), surface.triangles(t, 2)});
    owner.push_back(-1);
  }
  int next_id = surface.num_vertices();
  std::vector<int> first_disc_tri;
  for (std::size_t d = 0; d < discs.size(); ++d) {
    const InterfaceDisc& disc = discs[d];
    first_disc_tri.push_back(static_cast<int>(tris.size()));
    for (int t = 0; t < disc.triangles.rows(); ++t) {
      Tri tri;
      std::array<int, 3> vid;
      for (int k = 0; k < 3; ++k) {
        const int v = disc.triangles(t, k);
        tri[k] = disc.positions.row(v).transpose();
        vid[k] = v < disc.num_loop_vertices ? loop_ids[d][v] : next_id + v;
      }
      tris.push_back(tri);
      ids.push_back(vid);
      owner.push_back(static_cast<int>(d));
    }
    next_id += static_cast<int>(disc.positions.rows());
  }
  // Bucket grid over the discs' bounding box.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  double edge_sum = 0.0;
  int edge_count = 0;
  for (std::size_t t = first_disc_tri.empty() ? tris.size() : first_disc_tri[0]; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(tris[t][k]);
      hi = hi.cwiseMax(tris[t][k]);
      edge_sum += (tris[t][k] - tris[t][(k + 1) % 3]).norm();
      ++edge_count;
    }
  if (edge_count > 0) {
    const double cell = std::max(2.0 * edge_sum / edge_count, 1e-12 * (hi - lo).norm());
    std::array<int, 3> res;
    for (int a = 0; a < 3; ++a) res[a] = std::clamp(static_cast<int>((hi(a) - lo(a)) / cell) + 1, 1, 128);
    auto cell_range = [&](const Tri& t, std::array<int, 3>& c0, std::array<int, 3>& c1) {
      for (int a = 0; a < 3; ++a) {
        const double tmin = std::min({t[0](a), t[1](a), t[2](a)}), tmax = std::max({t[0](a), t[1](a), t[2](a)});
        const double scale = res[a] / std::max(hi(a) - lo(a), 1e-300);
        // Clamped in double first: a flat axis (hi = lo) scales by up to 1e300.
        const double f0 = std::floor((tmin - lo(a)) * scale), f1 = std::floor((tmax - lo(a)) * scale);
        if (f1 < 0.0 || f0 >= res[a]) return false;
        c0[a] = static_cast<int>(std::max(f0, 0.0));
        c1[a] = static_cast<int>(std::min(f1, static_cast<double>(res[a] - 1)));
      }
      return true;
    };
    std::unordered_map<long, std::vector<int>> buckets;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      std::array<int, 3> c0, c1;
      if (!cell_range(tris[t], c0, c1)) continue;
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x)
            buckets[(static_cast<long>(z) * res[1] + y) * res[0] + x].push_back(static_cast<int>(t));
    }
    // Plane prune: a triangle strictly on one side of disc triangle t's plane meets that plane
    // nowhere, so none of its edges crosses t and none of t's edges (in the plane) crosses it. The
    // margin (relative 1e-6 of the grid's extent, far above the crossing test's rounding) keeps
    // every pair the crossing test could count, so the counts are those of the full test.
    const double extent = (hi - lo).norm() + cell;
    std::vector<long> seen_pair_stamp(tris.size(), -1);
    for (std::size_t t = first_disc_tri[0]; t < tris.size(); ++t) {
      std::array<int, 3> c0, c1;
      if (!cell_range(tris[t], c0, c1)) continue;
      const Eigen::Vector3d e1 = tris[t][1] - tris[t][0], e2 = tris[t][2] - tris[t][0];
      const Eigen::Vector3d normal = e1.cross(e2);
      const double margin = 1e-6 * e1.norm() * e2.norm() * extent;
      auto off_plane = [&](const Tri& other) {
        const double s0 = (other[0] - tris[t][0]).dot(normal), s1 = (other[1] - tris[t][0]).dot(normal),
                     s2 = (other[2] - tris[t][0]).dot(normal);
        return (s0 > margin && s1 > margin && s2 > margin) || (s0 < -margin && s1 < -margin && s2 < -margin);
      };
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x) {
            const auto it = buckets.find((static_cast<long>(z) * res[1] + y) * res[0] + x);
            if (it == buckets.end()) continue;
            for (int s : it->second) {
              if (s == static_cast<int>(t) || seen_pair_stamp[s] == static_cast<long>(t)) continue;
              seen_pair_stamp[s] = static_cast<long>(t);
              if (owner[s] == owner[t]) continue;  // a disc against itself: embedded by construction
              if (owner[s] >= 0 && s > static_cast<int>(t)) continue;  // disc pairs once
              if (off_plane(tris[s])) continue;
              bool shared = false;
              for (int i : ids[t])
                for (int j : ids[s]) shared = shared || i == j;
              if (shared) continue;
              if (triangles_cross(tris[t], tris[s])) {
                ++out.num_intersections;
                ++out.crossings[owner[t]];
                if (out.first_problem.empty())
                  out.first_problem = "the interface disc of cut " + std::to_string(owner[t]) + " crosses " +
                                      (owner[s] < 0 ? "the surface (face " + std::to_string(s) + ")"
                                                    : "the interface disc of cut " + std::to_string(owner[s]));
              }
            }
          }
    }
  }
  for (std::size_t d = 0; d < discs.size(); ++d) {
    const Eigen::Vector3d centre = discs[d].positions.row(discs[d].positions.rows() - 1).transpose();
    double total = 0.0;
    for (int t = 0; t < surface.num_faces(); ++t) total += solid_angle(centre, tris[t]);
    const double w = total / (4.0 * 3.14159265358979323846);
    out.winding.push_back(w);
    if (w < 0.5) {
      ++out.num_outside;
      if (out.first_problem.empty())
        out.first_problem = "the interface disc of cut " + std::to_string(d) + " lies outside the solid (winding number " +
                            std::to_string(w) + ")";
    }
  }
  return out;
}

DiscEmbedding check_loop_disc(const mesh::TriangleMesh& surface, const std::vector<int>& loop) {
  assert(loop.size() >= 3);
  mesh::Positions xyz(static_cast<int>(loop.size()), 3);
  for (std::size_t i = 0; i < loop.size(); ++i) xyz.row(static_cast<int>(i)) = surface.positions.row(loop[i]);
  return check_interface_discs(surface, {triangulate_interface_disc(xyz)}, {loop});
}

}  // namespace volspline::polycube
