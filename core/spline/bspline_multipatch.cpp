// SPDX-License-Identifier: MIT
#include "core/spline/bspline_multipatch.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/common/error.h"

namespace volspline::spline {

namespace {

// Lines closer than this fraction of the box length are one line (rounding of k·size/n and of
// x ↦ size − x through a transition).
constexpr double kLineTol = 1e-9;

// Knot vector of one axis of the restricted volume (see tspline_box_to_bspline).
std::vector<double> box_knot_vector(const TSpline& spline, int axis, double lo, double hi,
                                    const std::vector<double>& extra) {
  const double tol = kLineTol * (hi - lo);
  std::map<double, int> multiplicity;
  for (const double x : spline.knot_lines(axis))
    if (x > lo + tol && x < hi - tol) multiplicity[x] = 1;
  for (const BlendingKnots& knots : spline.knots()) {
    const LocalKnots& r = knots[axis];
    for (int i = 0; i < 5;) {
      int j = i + 1;
      while (j < 5 && r[j] == r[i]) ++j;
      auto it = multiplicity.find(r[i]);
      if (it != multiplicity.end()) {
        if (j - i > 3)
          throw Error("tspline_box_to_bspline: a blending function repeats knot " + std::to_string(r[i]) +
                      " of axis " + std::to_string(axis) + " " + std::to_string(j - i) +
                      " times inside the box (a break in the spline)");
        it->second = std::max(it->second, j - i);
      }
      i = j;
    }
  }
  for (const double x : extra) {
    if (!(x > lo + tol && x < hi - tol)) continue;
    auto near = multiplicity.lower_bound(x - tol);
    if (near != multiplicity.end() && near->first <= x + tol) continue;
    multiplicity[x] = 1;
  }
  std::vector<double> knots(4, lo);
  for (const auto& [x, m] : multiplicity) knots.insert(knots.end(), m, x);
  knots.insert(knots.end(), 4, hi);
  return knots;
}

// Per control index j of knot vector K: the spline's grid interval holding a non-empty knot
// interval next to the inner knots K[j+1..j+3], and the cubic blossom's monomial factors
// (1, Σx/3, Σxy/3, xyz) of those knots in that interval's local coordinate.
struct AxisDual {
  std::vector<int> interval;
  std::vector<std::array<double, 4>> factors;
};

AxisDual axis_dual(const std::vector<double>& K, const std::vector<double>& breaks) {
  const int n = int(K.size()) - 4;
  AxisDual out;
  out.interval.resize(n);
  out.factors.resize(n);
  for (int j = 0; j < n; ++j) {
    int m = -1;
    for (const int c : {j + 1, j + 2, j, j + 3})
      if (K[c + 1] > K[c]) {
        m = c;
        break;
      }
    // A clamped vector with a non-empty domain has a non-empty interval among K[j..j+4].
    const double mid = 0.5 * (K[m] + K[m + 1]);
    int k = int(std::upper_bound(breaks.begin(), breaks.end(), mid) - breaks.begin()) - 1;
    k = std::clamp(k, 0, int(breaks.size()) - 2);
    const double b = breaks[k], h = breaks[k + 1] - breaks[k];
    const double x = (K[j + 1] - b) / h, y = (K[j + 2] - b) / h, z = (K[j + 3] - b) / h;
    out.interval[j] = k;
    out.factors[j] = {1.0, (x + y + z) / 3.0, (x * y + y * z + z * x) / 3.0, x * y * z};
  }
  return out;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Inserts x into the sorted list unless a line lies within tol; returns true if inserted.
bool insert_line(std::vector<double>& lines, double x, double tol) {
  auto it = std::lower_bound(lines.begin(), lines.end(), x - tol);
  if (it != lines.end() && *it <= x + tol) return false;
  lines.insert(it, x);
  return true;
}

}  // namespace

BsplineVolume tspline_box_to_bspline(const TSpline& spline, const Eigen::Vector3d& box_min,
                                     const Eigen::Vector3d& box_max,
                                     const std::array<std::vector<double>, 3>& extra_lines) {
  const Eigen::Vector3d dmin = spline.domain_min(), dmax = spline.domain_max();
  for (int a = 0; a < 3; ++a) {
    const double tol = kLineTol * (dmax[a] - dmin[a]);
    if (!(box_min[a] < box_max[a]) || box_min[a] < dmin[a] - tol || box_max[a] > dmax[a] + tol)
      throw Error("tspline_box_to_bspline: the box is empty or leaves the spline's domain along axis " +
                  std::to_string(a));
  }
  const int D = spline.dimension();
  std::array<std::vector<double>, 3> K;
  std::array<AxisDual, 3> dual;
  for (int a = 0; a < 3; ++a) {
    K[a] = box_knot_vector(spline, a, box_min[a], box_max[a], extra_lines[a]);
    dual[a] = axis_dual(K[a], spline.knot_lines(a));
  }
  const int n0 = int(K[0].size()) - 4, n1 = int(K[1].size()) - 4, n2 = int(K[2].size()) - 4;
  const int g0 = int(spline.knot_lines(0).size()) - 1, g1 = int(spline.knot_lines(1).size()) - 1;
  Eigen::MatrixXd points(std::size_t(n0) * n1 * n2, D);
  // De Boor–Fix: coefficient (j0, j1, j2) is F's tricubic blossom at the three inner-knot
  // triples, taken on one grid cell next to them (Eq. 4.3: each cell is one polynomial).
  std::unordered_map<int, std::vector<double>> power;
  std::vector<double> denominator(64);
  for (int j2 = 0; j2 < n2; ++j2)
    for (int j1 = 0; j1 < n1; ++j1)
      for (int j0 = 0; j0 < n0; ++j0) {
        const int cell = dual[0].interval[j0] + g0 * (dual[1].interval[j1] + g1 * dual[2].interval[j2]);
        auto it = power.find(cell);
        if (it == power.end()) {
          it = power.emplace(cell, std::vector<double>(64 * std::size_t(D))).first;
          spline.cell_power_form(cell, it->second.data(), denominator.data());
        }
        const std::vector<double>& P = it->second;
        const auto& fu = dual[0].factors[j0];
        const auto& fv = dual[1].factors[j1];
        const auto& fw = dual[2].factors[j2];
        const std::size_t row = std::size_t(j0) + std::size_t(n0) * (j1 + std::size_t(n1) * j2);
        for (int d = 0; d < D; ++d) {
          double sum = 0.0;
          for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) {
              double inner = 0.0;
              for (int c = 0; c < 4; ++c) inner += P[std::size_t((16 * a + 4 * b + c) * D + d)] * fw[c];
              sum += fu[a] * fv[b] * inner;
            }
          points(Eigen::Index(row), d) = sum;
        }
      }
  return BsplineVolume(std::move(K), std::move(points));
}

BsplineMultipatch multipatch_from_tspline(const TSpline& spline) {
  BsplineMultipatch out;
  out.patches.push_back(tspline_box_to_bspline(spline, spline.domain_min(), spline.domain_max()));
  out.cuboid = {0};
  out.box_min = {spline.domain_min()};
  out.box_max = {spline.domain_max()};
  for (int f = 0; f < 6; ++f) out.boundary.push_back({0, f});
  out.corner_vertex.push_back({0, 1, 2, 3, 4, 5, 6, 7});
  out.num_vertices = 8;
  return out;
}

BsplineMultipatch multipatch_from_gpc_spline(const GpcSpline& spline, int split) {
  if (split < 1 || split > 4) throw Error("multipatch_from_gpc_spline: split must be in 1..4, got " + std::to_string(split));
  const polycube::GpcDomain& domain = spline.domain();
  const int C = spline.num_cuboids();
  auto size = [&](int c, int a) { return domain.cuboids[c].size[a]; };
  auto split_at = [&](int c, int a, int s) { return s == split ? size(c, a) : s * size(c, a) / split; };
  // Knot lines per cuboid axis: its own, the split planes, then closed under the tangent-axis
  // gluing of every interface (x ↦ ±x + translation, Eq. 3.4) so glued sides conform.
  std::vector<std::array<std::vector<double>, 3>> lines(C);
  for (int c = 0; c < C; ++c)
    for (int a = 0; a < 3; ++a) {
      const double tol = kLineTol * size(c, a);
      for (int s = 0; s <= split; ++s) insert_line(lines[c][a], split_at(c, a, s), tol);
      for (const double x : spline.patch(c).knot_lines(a))
        if (x > tol && x < size(c, a) - tol) insert_line(lines[c][a], x, tol);
    }
  struct Relation {
    int c0, a0, c1, a1, sign;
    double shift;  // x1 = sign·x0 + shift
  };
  std::vector<Relation> relations;
  for (const polycube::GpcInterface& in : domain.interfaces) {
    const int normal = in.face[0] / 2;
    for (int i = 0; i < 3; ++i)
      if (i != normal)
        relations.push_back({in.cuboid[0], i, in.cuboid[1], in.transition.axis[i], in.transition.sign[i],
                             in.transition.translation(in.transition.axis[i])});
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (const Relation& r : relations) {
      for (const double x : std::vector<double>(lines[r.c0][r.a0]))
        changed |= insert_line(lines[r.c1][r.a1], r.sign * x + r.shift, kLineTol * size(r.c1, r.a1));
      for (const double y : std::vector<double>(lines[r.c1][r.a1]))
        changed |= insert_line(lines[r.c0][r.a0], r.sign * (y - r.shift), kLineTol * size(r.c0, r.a0));
    }
  }

  BsplineMultipatch out;
  const int per = split * split * split;
  auto patch_id = [&](int c, int s0, int s1, int s2) { return c * per + s0 + split * (s1 + split * s2); };
  for (int c = 0; c < C; ++c)
    for (int s2 = 0; s2 < split; ++s2)
      for (int s1 = 0; s1 < split; ++s1)
        for (int s0 = 0; s0 < split; ++s0) {
          const int s[3] = {s0, s1, s2};
          Eigen::Vector3d lo, hi;
          for (int a = 0; a < 3; ++a) {
            lo[a] = split_at(c, a, s[a]);
            hi[a] = split_at(c, a, s[a] + 1);
          }
          out.patches.push_back(tspline_box_to_bspline(spline.patch(c), lo, hi, lines[c]));
          out.cuboid.push_back(c);
          out.box_min.push_back(lo);
          out.box_max.push_back(hi);
        }
  // Sub-patches of one cuboid meet with the identity map.
  for (int c = 0; c < C; ++c)
    for (int s2 = 0; s2 < split; ++s2)
      for (int s1 = 0; s1 < split; ++s1)
        for (int s0 = 0; s0 < split; ++s0) {
          const int s[3] = {s0, s1, s2};
          for (int a = 0; a < 3; ++a) {
            if (s[a] + 1 == split) continue;
            int t[3] = {s0, s1, s2};
            ++t[a];
            out.interfaces.push_back({{patch_id(c, s0, s1, s2), patch_id(c, t[0], t[1], t[2])}, {2 * a + 1, 2 * a}, {0, 1, 2}, {1, 1, 1}});
          }
        }
  // Sub-patch of cuboid c on face f holding the point h of that face (c's coordinates).
  auto patch_at = [&](int c, int f, const Eigen::Vector3d& h) {
    int s[3];
    for (int a = 0; a < 3; ++a) s[a] = std::clamp(int(std::floor(h[a] / size(c, a) * split)), 0, split - 1);
    s[f / 2] = f % 2 ? split - 1 : 0;
    return patch_id(c, s[0], s[1], s[2]);
  };
  for (const polycube::GpcInterface& in : domain.interfaces) {
    const int c0 = in.cuboid[0], f0 = in.face[0], n0 = f0 / 2;
    for (int p = c0 * per; p < (c0 + 1) * per; ++p) {
      const double plane = f0 % 2 ? size(c0, n0) : 0.0;
      const double at = f0 % 2 ? out.box_max[p][n0] : out.box_min[p][n0];
      if (at != plane) continue;
      Eigen::Vector3d centre = 0.5 * (out.box_min[p] + out.box_max[p]);
      centre[n0] = plane;
      const int q = patch_at(in.cuboid[1], in.face[1], in.transition.apply(centre));
      out.interfaces.push_back({{p, q}, {f0, in.face[1]}, in.transition.axis, in.transition.sign});
    }
  }
  for (int c = 0; c < C; ++c)
    for (int f = 0; f < 6; ++f) {
      if (domain.cuboids[c].face_interface[f] >= 0) continue;
      for (int p = c * per; p < (c + 1) * per; ++p) {
        const int a = f / 2;
        const double at = f % 2 ? out.box_max[p][a] : out.box_min[p][a];
        if (at == (f % 2 ? size(c, a) : 0.0)) out.boundary.push_back({p, f});
      }
    }
  // Corner vertices: lattice points (cuboid, i0, i1, i2), i in 0..split, glued through the
  // interfaces' transitions.
  const int L = split + 1;
  auto lattice_id = [&](int c, int i0, int i1, int i2) { return ((c * L + i2) * L + i1) * L + i0; };
  UnionFind uf(C * L * L * L);
  for (const polycube::GpcInterface& in : domain.interfaces) {
    const int c0 = in.cuboid[0], c1 = in.cuboid[1], n0 = in.face[0] / 2;
    for (int i2 = 0; i2 < L; ++i2)
      for (int i1 = 0; i1 < L; ++i1)
        for (int i0 = 0; i0 < L; ++i0) {
          const int i[3] = {i0, i1, i2};
          if (i[n0] != (in.face[0] % 2 ? split : 0)) continue;
          Eigen::Vector3d h;
          for (int a = 0; a < 3; ++a) h[a] = split_at(c0, a, i[a]);
          const Eigen::Vector3d g = in.transition.apply(h);
          int j[3];
          for (int a = 0; a < 3; ++a) j[a] = std::clamp(int(std::lround(g[a] / size(c1, a) * split)), 0, split);
          uf.unite(lattice_id(c0, i0, i1, i2), lattice_id(c1, j[0], j[1], j[2]));
        }
  }
  std::vector<int> vertex_of(C * L * L * L, -1);
  for (int p = 0; p < int(out.patches.size()); ++p) {
    const int c = out.cuboid[p], local = p - c * per;
    const int s[3] = {local % split, (local / split) % split, local / (split * split)};
    std::array<int, 8> corners{};
    for (int k = 0; k < 8; ++k) {
      const int root = uf.find(lattice_id(c, s[0] + (k & 1), s[1] + (k >> 1 & 1), s[2] + (k >> 2 & 1)));
      if (vertex_of[root] < 0) vertex_of[root] = out.num_vertices++;
      corners[k] = vertex_of[root];
    }
    out.corner_vertex.push_back(corners);
  }
  return out;
}

bool multipatch_topology_is_vertex_based(const BsplineMultipatch& multipatch) {
  double extent = 0.0;
  for (const BsplineVolume& v : multipatch.patches) {
    const Eigen::MatrixXd& P = v.control_points();
    extent = std::max(extent, (P.colwise().maxCoeff() - P.colwise().minCoeff()).maxCoeff());
  }
  const double tol = 1e-9 * extent;
  std::map<std::vector<int>, Eigen::VectorXd> seen;
  auto consistent = [&](std::vector<int> key, const Eigen::VectorXd& point) {
    std::sort(key.begin(), key.end());
    auto [it, inserted] = seen.emplace(std::move(key), point);
    return inserted || (it->second - point).norm() <= tol;
  };
  for (int p = 0; p < int(multipatch.patches.size()); ++p) {
    const std::array<int, 8>& v = multipatch.corner_vertex[p];
    std::array<int, 8> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
    const BsplineVolume& volume = multipatch.patches[p];
    const Eigen::Vector3d lo = volume.domain_min(), hi = volume.domain_max();
    auto point = [&](int ku, int kv, int kw) {  // 0, 1, 2 = lower end, middle, upper end
      const int k[3] = {ku, kv, kw};
      Eigen::Vector3d h;
      for (int a = 0; a < 3; ++a) h[a] = lo[a] + 0.5 * k[a] * (hi[a] - lo[a]);
      return volume.evaluate(h);
    };
    for (int a = 0; a < 3; ++a)  // the 4 edges along axis a
      for (int e = 0; e < 4; ++e) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        int k0[3], k1[3], km[3];
        k0[a] = 0, k1[a] = 1, km[a] = 1;
        k0[b] = k1[b] = e & 1, k0[c] = k1[c] = e >> 1;
        km[b] = 2 * (e & 1), km[c] = 2 * (e >> 1);
        const int c0 = k0[0] + 2 * k0[1] + 4 * k0[2], c1 = k1[0] + 2 * k1[1] + 4 * k1[2];
        if (!consistent({v[c0], v[c1]}, point(km[0], km[1], km[2]))) return false;
      }
    for (int f = 0; f < 6; ++f) {
      const int a = f / 2;
      std::vector<int> key;
      for (int k = 0; k < 8; ++k)
        if ((k >> a & 1) == f % 2) key.push_back(v[k]);
      int km[3] = {1, 1, 1};
      km[a] = 2 * (f % 2);
      key.push_back(-1);  // faces and edges apart
      if (!consistent(key, point(km[0], km[1], km[2]))) return false;
    }
  }
  return true;
}

BsplineMultipatch vertex_based_multipatch(const GpcSpline& spline) {
  for (int split = 1; split <= 3; ++split) {
    BsplineMultipatch m = multipatch_from_gpc_spline(spline, split);
    if (multipatch_topology_is_vertex_based(m)) return m;
  }
  throw Error("vertex_based_multipatch: no split of the cuboids into at most 3^3 patches gives distinct corners, edges and faces");
}

}  // namespace volspline::spline
