// SPDX-License-Identifier: MIT
#include "core/spline/gpc_spline.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "core/common/error.h"
#include "core/spline/knot_insertion.h"

namespace volspline::spline {

namespace {

using polycube::GpcDomain;
using polycube::GpcTransition;

std::string str(int i) { return std::to_string(i); }

// The neighbour across face f of cuboid c: its cuboid and face, and the transition from c's
// local coordinates to its own (Eq. 3.4); cuboid −1 on the solid's surface.
struct Link {
  int cuboid = -1;
  int face = -1;
  int interface_id = -1;
  GpcTransition to;
};

Link link_of(const GpcDomain& domain, int c, int f) {
  Link out;
  const int i = domain.cuboids[c].face_interface[f];
  if (i < 0) return out;
  const polycube::GpcInterface& in = domain.interfaces[i];
  out.interface_id = i;
  if (in.cuboid[0] == c && in.face[0] == f) {
    out.cuboid = in.cuboid[1];
    out.face = in.face[1];
    out.to = in.transition;
  } else {
    out.cuboid = in.cuboid[0];
    out.face = in.face[0];
    out.to = in.transition.inverse();
  }
  return out;
}

bool same_transition(const GpcTransition& a, const GpcTransition& b, double tol) {
  for (int i = 0; i < 3; ++i)
    if (a.axis[i] != b.axis[i] || a.sign[i] != b.sign[i]) return false;
  return (a.translation - b.translation).cwiseAbs().maxCoeff() <= tol;
}

// The face of the neighbour that a transition `to` maps face f of the source cuboid onto, for a
// face f whose axis is tangent to the glued face: the tangent extents of two glued faces
// coincide, so the low end maps to the low end iff the axis keeps its sign.
int image_face(const GpcTransition& to, int f) {
  const int a = f / 2, e = f % 2;
  return 2 * to.axis[a] + (to.sign[a] > 0 ? e : 1 - e);
}

Eigen::Vector3d size_of(const GpcDomain& domain, int c) {
  const auto& s = domain.cuboids[c].size;
  return {s[0], s[1], s[2]};
}

void validate_domain(const GpcDomain& domain, double tol) {
  const int nc = static_cast<int>(domain.cuboids.size());
  const int ni = static_cast<int>(domain.interfaces.size());
  if (nc == 0) throw Error("GpcSpline: the domain has no cuboid");
  for (int c = 0; c < nc; ++c) {
    for (int a = 0; a < 3; ++a) {
      const double s = domain.cuboids[c].size[a];
      if (!std::isfinite(s) || !(s > 0.0))
        throw Error("GpcSpline: cuboid " + str(c) + " has size " + std::to_string(s) + " along axis " + str(a) +
                    " (must be finite and positive)");
    }
    for (int f = 0; f < 6; ++f) {
      const int i = domain.cuboids[c].face_interface[f];
      if (i < -1 || i >= ni)
        throw Error("GpcSpline: cuboid " + str(c) + " face " + str(f) + " names interface " + str(i) + " of " + str(ni));
      if (i < 0) continue;
      const auto& in = domain.interfaces[i];
      if (!((in.cuboid[0] == c && in.face[0] == f) || (in.cuboid[1] == c && in.face[1] == f)))
        throw Error("GpcSpline: cuboid " + str(c) + " face " + str(f) + " names interface " + str(i) +
                    ", which does not hold that face");
    }
  }
  for (int i = 0; i < ni; ++i) {
    const auto& in = domain.interfaces[i];
    for (int s = 0; s < 2; ++s) {
      if (in.cuboid[s] < 0 || in.cuboid[s] >= nc || in.face[s] < 0 || in.face[s] > 5)
        throw Error("GpcSpline: interface " + str(i) + " names cuboid " + str(in.cuboid[s]) + " face " +
                    str(in.face[s]) + " (out of range)");
      if (domain.cuboids[in.cuboid[s]].face_interface[in.face[s]] != i)
        throw Error("GpcSpline: interface " + str(i) + " glues cuboid " + str(in.cuboid[s]) + " face " +
                    str(in.face[s]) + ", whose face_interface is not " + str(i));
    }
    if (in.cuboid[0] == in.cuboid[1] && in.face[0] == in.face[1])
      throw Error("GpcSpline: interface " + str(i) + " glues a face to itself");
    // Eq. 3.4: the transition maps face 0 onto face 1, the first cuboid's interior outside the
    // second (its inward normal onto the second's outward normal).
    const int fa = in.face[0], fb = in.face[1];
    const Eigen::Vector3d sa = size_of(domain, in.cuboid[0]), sb = size_of(domain, in.cuboid[1]);
    const GpcTransition& t = in.transition;
    bool ok = t.axis[fa / 2] == fb / 2 && t.sign[fa / 2] * (fa % 2 == 0 ? 1 : -1) == (fb % 2 == 0 ? -1 : 1);
    std::array<int, 3> seen{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      if (t.axis[k] >= 0 && t.axis[k] < 3 && std::abs(t.sign[k]) == 1) ++seen[t.axis[k]];
    ok = ok && seen[0] == 1 && seen[1] == 1 && seen[2] == 1;
    for (int corner = 0; ok && corner < 8; ++corner) {
      Eigen::Vector3d p((corner & 1) * sa(0), ((corner >> 1) & 1) * sa(1), ((corner >> 2) & 1) * sa(2));
      if (((corner >> (fa / 2)) & 1) != fa % 2) continue;
      const Eigen::Vector3d q = t.apply(p);
      for (int a = 0; a < 3; ++a) {
        const double target = a == fb / 2 ? (fb % 2) * sb(a) : (std::abs(q(a)) <= tol ? 0.0 : sb(a));
        if (std::abs(q(a) - target) > tol) ok = false;
      }
    }
    if (!ok)
      throw Error("GpcSpline: the transition of interface " + str(i) + " does not map cuboid " + str(in.cuboid[0]) +
                  " face " + str(fa) + " onto cuboid " + str(in.cuboid[1]) + " face " + str(fb));
  }
}

using KnotLines = std::vector<std::array<std::vector<double>, 3>>;

void check_counts(const GpcDomain& domain, const std::vector<std::array<int, 3>>& intervals) {
  const int nc = static_cast<int>(domain.cuboids.size());
  if (static_cast<int>(intervals.size()) != nc)
    throw Error("GpcSpline: intervals has " + str(static_cast<int>(intervals.size())) + " entries for " + str(nc) +
                " cuboids");
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a)
      if (intervals[c][a] < 1)
        throw Error("GpcSpline: intervals of cuboid " + str(c) + " axis " + str(a) + " is " + str(intervals[c][a]) +
                    " (must be >= 1)");
}

// Each list runs from 0 to the size, increasing by more than tol; ends within tol snap onto 0 and size.
void check_line_lists(const GpcDomain& domain, KnotLines& lines, double tol) {
  const int nc = static_cast<int>(domain.cuboids.size());
  if (static_cast<int>(lines.size()) != nc)
    throw Error("GpcSpline: knot_lines has " + str(static_cast<int>(lines.size())) + " entries for " + str(nc) +
                " cuboids");
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a) {
      std::vector<double>& l = lines[c][a];
      const double size = domain.cuboids[c].size[a];
      const std::string where = "GpcSpline: knot_lines of cuboid " + str(c) + " axis " + str(a);
      if (l.size() < 2) throw Error(where + " hold fewer than 2 lines");
      if (l.size() > 4097) throw Error(where + " hold more than 4097 lines");
      for (double x : l)
        if (!std::isfinite(x)) throw Error(where + " hold a value that is not finite");
      if (std::abs(l.front()) > tol || std::abs(l.back() - size) > tol)
        throw Error(where + " must start at 0 and end at the size " + std::to_string(size));
      l.front() = 0.0;
      l.back() = size;
      for (std::size_t k = 1; k < l.size(); ++k)
        if (!(l[k] - l[k - 1] > tol)) throw Error(where + " must increase (by more than 1e-9 of the largest size)");
    }
}

// The image of knot line x of the source cuboid's tangent axis a under transition `to`.
double line_image(const GpcTransition& to, int a, double x) { return to.sign[a] * x + to.translation(to.axis[a]); }

// The knot lines of the two sides of every glued face must agree along its tangent axes (§4.4.1
// step 1: the two components share their knot intervals on the merged face).
void check_lines(const GpcDomain& domain, const KnotLines& lines, double tol) {
  for (int i = 0; i < static_cast<int>(domain.interfaces.size()); ++i) {
    const auto& in = domain.interfaces[i];
    const int ca = in.cuboid[0], cb = in.cuboid[1];
    for (int t = 0; t < 3; ++t) {
      if (t == in.face[0] / 2) continue;
      const int tb = in.transition.axis[t];
      const std::vector<double>& la = lines[ca][t];
      const std::vector<double>& lb = lines[cb][tb];
      bool same = la.size() == lb.size() && std::abs(domain.cuboids[ca].size[t] - domain.cuboids[cb].size[tb]) <= tol;
      for (std::size_t k = 0; same && k < la.size(); ++k) {
        const std::size_t kb = in.transition.sign[t] > 0 ? k : la.size() - 1 - k;
        same = std::abs(line_image(in.transition, t, la[k]) - lb[kb]) <= 4.0 * tol;  // sizes agree to tol
      }
      if (!same)
        throw Error("GpcSpline: interface " + str(i) + " glues cuboid " + str(ca) + " axis " + str(t) + " (" +
                    str(static_cast<int>(la.size()) - 1) + " intervals) to cuboid " + str(cb) + " axis " + str(tb) +
                    " (" + str(static_cast<int>(lb.size()) - 1) + " intervals): the knot lines of the two sides differ");
    }
  }
}

KnotLines uniform_lines(const GpcDomain& domain, const std::vector<std::array<int, 3>>& intervals) {
  KnotLines out(domain.cuboids.size());
  for (std::size_t c = 0; c < out.size(); ++c)
    for (int a = 0; a < 3; ++a) {
      const int n = intervals[c][a];
      const double size = domain.cuboids[c].size[a];
      for (int k = 0; k <= n; ++k) out[c][a].push_back(k == n ? size : size * k / n);
    }
  return out;
}

// The continuity rule, with the join of every interface (Continued or Clamped).
class JoinRule {
 public:
  JoinRule(const GpcDomain& domain, std::vector<GpcFaceJoin>& join, double tol)
      : domain_(domain), join_(join), tol_(tol) {}

  bool continued(int c, int f) const {
    const int i = domain_.cuboids[c].face_interface[f];
    return i >= 0 && join_[i] == GpcFaceJoin::Continued;
  }

  // Whether the two sides of glued face (c, f), T: c → d, see the same thing at end e of c's
  // tangent axis t: both clamped (Surface or Clamped), or both continued into two cuboids glued
  // to each other across the image of the face, with the four transitions around the edge
  // closing up (a regular edge: 4 cuboids around it).
  bool same_at_edge(int c, int f, const Link& across, int t, int e) const {
    const GpcTransition& to = across.to;
    const int fc = 2 * t + e, fd = image_face(to, fc);
    const bool kc = continued(c, fc), kd = continued(across.cuboid, fd);
    if (!kc && !kd) return true;
    if (kc != kd) return false;
    const Link nc = link_of(domain_, c, fc), nd = link_of(domain_, across.cuboid, fd);
    const Link diagonal = link_of(domain_, nc.cuboid, image_face(nc.to, f));
    if (diagonal.cuboid != nd.cuboid || diagonal.face != image_face(nd.to, across.face)) return false;
    return same_transition(diagonal.to.after(nc.to), nd.to.after(to), tol_);
  }

  // One pass over the interfaces; returns true if some join changed.
  bool pass() {
    bool changed = false;
    for (int i = 0; i < static_cast<int>(domain_.interfaces.size()); ++i) {
      const auto& in = domain_.interfaces[i];
      const int c = in.cuboid[0], f = in.face[0];
      const Link across = link_of(domain_, c, f);
      for (int t = 0; t < 3; ++t) {
        if (t == f / 2) continue;
        for (int e = 0; e < 2; ++e) {
          if (same_at_edge(c, f, across, t, e)) continue;
          if (join_[i] == GpcFaceJoin::Continued) {
            join_[i] = GpcFaceJoin::Clamped;
            changed = true;
          }
          // A clamped face needs the same face basis on both sides: its tangent knot vectors
          // must agree, so a tangent face that continues on one side only is clamped too.
          changed = clamp(c, 2 * t + e) || changed;
          changed = clamp(across.cuboid, image_face(across.to, 2 * t + e)) || changed;
        }
      }
    }
    return changed;
  }

  bool clamp(int c, int f) {
    if (!continued(c, f)) return false;
    join_[domain_.cuboids[c].face_interface[f]] = GpcFaceJoin::Clamped;
    return true;
  }

 private:
  const GpcDomain& domain_;
  std::vector<GpcFaceJoin>& join_;
  double tol_;
};

// A cuboid's local functions are the tensor products of its three chain knot vectors (u fastest):
// the grid index of local function l, and its knots.
// Indices are 64-bit: a fine level of the hierarchy can have more local functions than an int
// holds, of which only the few near its splits are ever visited.
std::array<int, 3> local_index3(const std::array<std::vector<double>, 3>& knots, long long l) {
  const long long m0 = static_cast<long long>(knots[0].size()) - 4, m1 = static_cast<long long>(knots[1].size()) - 4;
  return {static_cast<int>(l % m0), static_cast<int>((l / m0) % m1), static_cast<int>(l / (m0 * m1))};
}
BlendingKnots local_blending(const std::array<std::vector<double>, 3>& knots, long long l) {
  const std::array<int, 3> j = local_index3(knots, l);
  BlendingKnots out;
  for (int a = 0; a < 3; ++a)
    for (int q = 0; q < 5; ++q) out[a][q] = knots[a][j[a] + q];
  return out;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(static_cast<std::size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Knot vectors, local functions and their identification for one set of joins.
class Assembly {
 public:
  Assembly(const GpcDomain& domain, const KnotLines& lines, const std::vector<GpcFaceJoin>& join, double tol)
      : domain_(domain), lines_(lines), join_(join), tol_(tol) {
    const int nc = static_cast<int>(domain.cuboids.size());
    knots_.resize(nc);
    offsets_.assign(nc + 1, 0);
    for (int c = 0; c < nc; ++c) {
      for (int a = 0; a < 3; ++a) knots_[c][a] = chain_knots(c, a);
      offsets_[c + 1] = offsets_[c] + count(c);
    }
  }

  long long count(int c) const {
    return static_cast<long long>(knots_[c][0].size() - 4) * static_cast<long long>(knots_[c][1].size() - 4) *
           static_cast<long long>(knots_[c][2].size() - 4);
  }
  long long total() const { return offsets_.back(); }
  const std::array<std::vector<double>, 3>& knots(int c) const { return knots_[c]; }
  long long offset(int c) const { return offsets_[c]; }
  std::array<int, 3> index3(int c, long long l) const { return local_index3(knots_[c], l); }
  long long index1(int c, const std::array<int, 3>& j) const {
    const long long m0 = static_cast<long long>(knots_[c][0].size()) - 4,
                    m1 = static_cast<long long>(knots_[c][1].size()) - 4;
    return j[0] + m0 * (j[1] + m1 * j[2]);
  }
  BlendingKnots blending(int c, long long l) const { return local_blending(knots_[c], l); }

  // The local function of the neighbour across glued face f of cuboid c that local function l
  // of c is one global function with: a copy across a Continued face it crosses, the other
  // side's face function across a Clamped face. Returns 1 with it in `out`, 0 if there is none
  // (l does not cross the Continued face, is zero on the Clamped one), −1 if l has no match (a
  // configuration the continuity rule did not foresee).
  int match(int c, int f, long long l, long long& out) const {
    const int i = domain_.cuboids[c].face_interface[f];
    const Link across = link_of(domain_, c, f);
    const int a = f / 2, d = across.cuboid, g = across.face;
    const BlendingKnots k = blending(c, l);
    const std::array<int, 3> j = index3(c, l);
    std::array<int, 3> jd{};
    if (join_[i] == GpcFaceJoin::Continued) {
      const double size = domain_.cuboids[c].size[a];
      const bool crosses = f % 2 == 0 ? k[a][0] < 0.0 : k[a][4] > size;
      if (!crosses) return 0;
      for (int b = 0; b < 3; ++b)
        if ((jd[across.to.axis[b]] = find_start(d, across.to, b, k[b])) < 0) return -1;
    } else {
      const int m = static_cast<int>(knots_[c][a].size()) - 4;
      if (j[a] != (f % 2 == 0 ? 0 : m - 1)) return 0;  // zero on the face
      for (int b = 0; b < 3; ++b) {
        if (b == a) continue;
        if ((jd[across.to.axis[b]] = find_start(d, across.to, b, k[b])) < 0) return -1;
      }
      const int md = static_cast<int>(knots_[d][g / 2].size()) - 4;
      jd[g / 2] = g % 2 == 0 ? 0 : md - 1;
    }
    out = index1(d, jd);
    return 1;
  }

  // Identifies copies of one function (across Continued faces) and the two sides' face functions
  // (across Clamped faces) over every local function (total() must fit an int). Returns −1 on
  // success, else the interface whose functions did not match.
  int identify(UnionFind& uf) const {
    for (int i = 0; i < static_cast<int>(domain_.interfaces.size()); ++i)
      for (int s = 0; s < 2; ++s) {
        const int c = domain_.interfaces[i].cuboid[s], f = domain_.interfaces[i].face[s];
        const int d = domain_.interfaces[i].cuboid[1 - s];
        for (long long l = 0; l < count(c); ++l) {
          long long ld = 0;
          const int r = match(c, f, l, ld);
          if (r < 0) return i;
          if (r > 0) uf.unite(static_cast<int>(offset(c) + l), static_cast<int>(offset(d) + ld));
        }
      }
    return -1;
  }

 private:
  bool continued(int c, int f) const {
    const int i = domain_.cuboids[c].face_interface[f];
    return i >= 0 && join_[i] == GpcFaceJoin::Continued;
  }

  // The 3 knots beyond end e of cuboid c's axis a, outward, in c's coordinates: the knot lines of
  // the cuboids met by walking through Continued faces (Eq. 3.4 composed along the way), the
  // face's coordinate repeated where the walk ends on a Surface or Clamped face (4-fold end
  // knots). A cuboid glued to itself is walked through again: a periodic knot vector.
  std::array<double, 3> extension(int c, int a, int e) const {
    std::array<double, 3> out{};
    int filled = 0, x = c, ax = a, ee = e;
    GpcTransition to_c;  // x's coordinates → c's
    while (filled < 3) {
      const int f = 2 * ax + ee;
      if (!continued(x, f)) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p(ax) = ee * domain_.cuboids[x].size[ax];
        const double end = x == c ? p(ax) : to_c.apply(p)(a);
        while (filled < 3) out[filled++] = end;
        break;
      }
      const Link l = link_of(domain_, x, f);
      const GpcTransition y_to_c = to_c.after(l.to.inverse());
      const int ay = l.face / 2, ey = l.face % 2;
      const std::vector<double>& ly = lines_[l.cuboid][ay];
      const int n = static_cast<int>(ly.size()) - 1;
      assert(y_to_c.axis[ay] == a);
      for (int k = 1; k <= n && filled < 3; ++k) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p(ay) = ey == 0 ? ly[k] : ly[n - k];
        out[filled++] = y_to_c.apply(p)(a);
      }
      x = l.cuboid;
      ax = ay;
      ee = 1 - ey;
      to_c = y_to_c;
    }
    return out;
  }

  std::vector<double> chain_knots(int c, int a) const {
    const std::vector<double>& own = lines_[c][a];
    const std::array<double, 3> lo = extension(c, a, 0), hi = extension(c, a, 1);
    std::vector<double> out;
    out.reserve(own.size() + 6);
    for (int q = 2; q >= 0; --q) out.push_back(lo[q]);
    out.insert(out.end(), own.begin(), own.end());
    for (int q = 0; q < 3; ++q) out.push_back(hi[q]);
    for (std::size_t q = 1; q < out.size(); ++q)
      if (!(out[q] >= out[q - 1]))
        throw Error("GpcSpline: the knots of cuboid " + str(c) + " axis " + str(a) +
                    " decrease where they continue into a neighbour (inconsistent transitions)");
    return out;
  }

  // Start index in cuboid d's knot vector (along the image of axis b) of the image of knot
  // vector r of the source cuboid's axis b under `to`, −1 if it is not one of d's functions.
  int find_start(int d, const GpcTransition& to, int b, const LocalKnots& r) const {
    const int target = to.axis[b];
    const double t = to.translation(target);
    LocalKnots image;
    for (int q = 0; q < 5; ++q) image[q] = to.sign[b] > 0 ? r[q] + t : -r[4 - q] + t;
    const std::vector<double>& knots = knots_[d][target];
    const int m = static_cast<int>(knots.size()) - 4;
    int j = static_cast<int>(std::lower_bound(knots.begin(), knots.end(), image[0] - tol_) - knots.begin());
    for (; j < m && knots[j] <= image[0] + tol_; ++j) {
      bool same = true;
      for (int q = 0; q < 5 && same; ++q) same = std::abs(knots[j + q] - image[q]) <= tol_;
      if (same) return j;
    }
    return -1;
  }

  const GpcDomain& domain_;
  const KnotLines& lines_;
  const std::vector<GpcFaceJoin>& join_;
  double tol_;
  std::vector<std::array<std::vector<double>, 3>> knots_;
  std::vector<long long> offsets_;
};

// One level of a hierarchical GPC-spline: the B-spline over the GPC on its knot lines with the
// fixed joins, its functions made on demand. A deep level's dense basis (every local function of
// every cuboid, identified across the faces by union–find) grows 8× per level while the splits
// visit only a few of its functions, so a function is identified from its local function by a
// walk over the faces it reaches instead. Its id is the smallest global local index
// (Assembly::offset(c) + l) over its pieces: ids order like the dense basis's first-appearance
// ids (cuboid, then local function).
class SparseLevel {
 public:
  SparseLevel(const GpcDomain& domain, KnotLines lines, const std::vector<GpcFaceJoin>& join, double tol, int level)
      : domain_(domain), lines_(std::move(lines)), assembly_(domain, lines_, join, tol), level_(level) {}
  SparseLevel(const SparseLevel&) = delete;
  SparseLevel& operator=(const SparseLevel&) = delete;

  const Assembly& assembly() const { return assembly_; }
  BlendingKnots blending(int c, long long l) const { return assembly_.blending(c, l); }

  // Local function of cuboid c with knots k (to tol), −1 if none.
  long long local_of(int c, const BlendingKnots& k, double tol) const {
    std::array<int, 3> j{};
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& v = assembly_.knots(c)[a];
      const int m = static_cast<int>(v.size()) - 4;
      j[a] = -1;
      int s = static_cast<int>(std::lower_bound(v.begin(), v.end(), k[a][0] - tol) - v.begin());
      for (; s < m && v[s] <= k[a][0] + tol && j[a] < 0; ++s) {
        bool same = true;
        for (int q = 0; q < 5 && same; ++q) same = std::abs(v[s + q] - k[a][q]) <= tol;
        if (same) j[a] = s;
      }
      if (j[a] < 0) return -1;
    }
    return assembly_.index1(c, j);
  }

  // Id of the global function that local function l of cuboid c is a piece of.
  long long id_of(int c, long long l) {
    const long long g = assembly_.offset(c) + l;
    auto it = id_.find(g);
    if (it != id_.end()) return it->second;
    // The pieces: the local functions reached through Assembly::match, sorted by global index.
    std::vector<std::pair<int, long long>> pieces{{c, l}};
    for (std::size_t next = 0; next < pieces.size(); ++next) {
      const auto [x, lx] = pieces[next];
      for (int f = 0; f < 6; ++f) {
        if (domain_.cuboids[x].face_interface[f] < 0) continue;
        long long ly = 0;
        const int r = assembly_.match(x, f, lx, ly);
        if (r < 0)
          throw Error("GpcSpline: the level-" + str(level_) + " functions do not match across interface " +
                      str(domain_.cuboids[x].face_interface[f]));
        const int y = link_of(domain_, x, f).cuboid;
        if (r > 0 && std::find(pieces.begin(), pieces.end(), std::make_pair(y, ly)) == pieces.end())
          pieces.emplace_back(y, ly);
      }
    }
    std::sort(pieces.begin(), pieces.end());
    const long long id = assembly_.offset(pieces.front().first) + pieces.front().second;
    for (const auto& [x, lx] : pieces) id_.emplace(assembly_.offset(x) + lx, id);
    pieces_.emplace(id, std::move(pieces));
    return id;
  }

  // The local functions (cuboid, local index) that function id (from id_of) is made of, sorted.
  const std::vector<std::pair<int, long long>>& pieces(long long id) const { return pieces_.at(id); }

 private:
  const GpcDomain& domain_;
  KnotLines lines_;
  Assembly assembly_;
  int level_;
  std::unordered_map<long long, long long> id_;  // global local index → function id
  std::unordered_map<long long, std::vector<std::pair<int, long long>>> pieces_;
};

// Children of a cubic B-spline with local knots r when the midpoint of every non-empty interval
// is inserted (Eq. 4.8 repeated): N_r = Σ coefficient · N_child, children with r0 < r4 only.
std::vector<std::pair<LocalKnots, double>> midpoint_children(const LocalKnots& r, double tol) {
  std::vector<std::pair<LocalKnots, double>> list{{r, 1.0}};
  for (int q = 0; q < 4; ++q) {
    if (!(r[q + 1] - r[q] > tol)) continue;
    const double m = 0.5 * (r[q] + r[q + 1]);
    std::vector<std::pair<LocalKnots, double>> next;
    auto add = [&](const LocalKnots& k, double coefficient) {
      if (!(coefficient > 0.0) || !(k[4] - k[0] > tol)) return;
      for (auto& [known, c] : next) {
        bool same = true;
        for (int i = 0; i < 5 && same; ++i) same = std::abs(known[i] - k[i]) <= tol;
        if (same) {
          c += coefficient;
          return;
        }
      }
      next.emplace_back(k, coefficient);
    };
    for (const auto& [k, c] : list) {
      if (!(k[0] < m && m < k[4])) {
        add(k, c);
        continue;
      }
      const KnotInsertion ins = insert_knot(k, m);
      add(ins.first, c * ins.first_coefficient);
      add(ins.second, c * ins.second_coefficient);
    }
    list = std::move(next);
  }
  return list;
}

// The levels of a hierarchical GPC-spline and the refinement relation between them (see
// GpcSpline's class comment): level ℓ's lines cut every base interval into 2^ℓ parts.
class Hierarchy {
 public:
  using Key = std::pair<int, long long>;  // (level, SparseLevel id)

  Hierarchy(const GpcDomain& domain, const KnotLines& base, const std::vector<GpcFaceJoin>& join, double tol)
      : domain_(domain), base_(base), join_(join), tol_(tol) {}

  SparseLevel& level(int l) {
    while (static_cast<int>(levels_.size()) <= l) build(static_cast<int>(levels_.size()));
    return *levels_[l];
  }

  // B_key = Σ coefficient · B_child over the children one level finer.
  const std::vector<std::pair<long long, double>>& children(const Key& key) {
    auto it = children_.find(key);
    if (it != children_.end()) return it->second;
    const int l = key.first;
    if (l + 1 > GpcSpline::kMaxLevel)
      throw Error("GpcSpline: refinement below level " + str(GpcSpline::kMaxLevel) + " (the deepest allowed)");
    SparseLevel& fine = level(l + 1);
    const SparseLevel& coarse = level(l);
    std::vector<std::pair<long long, double>> out;
    for (const auto& [c, local] : coarse.pieces(key.second)) {
      const BlendingKnots k = coarse.blending(c, local);
      const Eigen::Vector3d size = size_of(domain_, c);
      std::array<std::vector<std::pair<LocalKnots, double>>, 3> one;
      for (int a = 0; a < 3; ++a) one[a] = midpoint_children(k[a], tol_);
      for (const auto& [k2, c2] : one[2])
        for (const auto& [k1, c1] : one[1])
          for (const auto& [k0, c0] : one[0]) {
            const BlendingKnots child{k0, k1, k2};
            bool meets = true;
            for (int a = 0; a < 3 && meets; ++a) meets = child[a][0] < size(a) - tol_ && child[a][4] > tol_;
            if (!meets) continue;
            const long long lc = fine.local_of(c, child, 4.0 * tol_);
            if (lc < 0)
              throw Error("GpcSpline: a child of a level-" + str(l) + " function in cuboid " + str(c) +
                          " is not a level-" + str(l + 1) + " function (inconsistent knot lines)");
            const long long j = fine.id_of(c, lc);
            const double coefficient = c0 * c1 * c2;
            auto at = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.first == j; });
            if (at == out.end()) {
              out.emplace_back(j, coefficient);
            } else if (std::abs(at->second - coefficient) > 1e-9) {
              throw Error("GpcSpline: the pieces of a level-" + str(l) + " function refine differently (cuboid " +
                          str(c) + ")");
            }
          }
    }
    std::sort(out.begin(), out.end());
    return children_.emplace(key, std::move(out)).first->second;
  }

 private:
  void build(int l) {
    const int parts = 1 << l;
    KnotLines lines(base_.size());
    for (std::size_t c = 0; c < base_.size(); ++c)
      for (int a = 0; a < 3; ++a) {
        const std::vector<double>& b = base_[c][a];
        for (std::size_t k = 0; k + 1 < b.size(); ++k)
          for (int q = 0; q < parts; ++q) lines[c][a].push_back(b[k] + (b[k + 1] - b[k]) * q / parts);
        lines[c][a].push_back(b.back());
      }
    levels_.push_back(std::make_unique<SparseLevel>(domain_, std::move(lines), join_, tol_, l));
  }

  const GpcDomain& domain_;
  KnotLines base_;
  std::vector<GpcFaceJoin> join_;
  double tol_;
  std::vector<std::unique_ptr<SparseLevel>> levels_;
  std::map<Key, std::vector<std::pair<long long, double>>> children_;
};

}  // namespace

namespace detail {
// The Hierarchy with its own copy of the domain it refers to, shared between splines.
struct GpcHierarchy {
  GpcHierarchy(const GpcDomain& d, const KnotLines& base, const std::vector<GpcFaceJoin>& join, double tol)
      : domain(d), levels(domain, base, join, tol) {}
  const GpcDomain domain;
  Hierarchy levels;
};
}  // namespace detail

namespace {

// One refinement step on the active functions (key → weight): the listed ones and the closure
// replaced by their children. `from` (n×... old order) receives, per new function in key order,
// the old functions it draws on with their factors (weights: Σ factors; points: Σ factor·p / w).
struct StepRecord {
  std::vector<std::vector<std::pair<int, double>>> from;
  std::vector<int> split;  // old indices split, closure included, increasing
};

StepRecord refine_step(Hierarchy& h, std::map<Hierarchy::Key, double>& active, const std::vector<int>& split_ids,
                       long max_functions) {
  std::vector<Hierarchy::Key> order;
  order.reserve(active.size());
  for (const auto& e : active) order.push_back(e.first);
  const int n = static_cast<int>(order.size());
  std::vector<char> split(n, 0);
  for (int i : split_ids) {
    if (i < 0 || i >= n) throw Error("GpcSpline: splits name function " + str(i) + " of " + str(n));
    split[i] = 1;
  }
  std::map<Hierarchy::Key, std::vector<std::pair<int, double>>> next;
  for (;;) {
    next.clear();
    for (int i = 0; i < n; ++i) {
      const double w = active[order[i]];
      if (!split[i]) {
        next[order[i]].emplace_back(i, w);
        continue;
      }
      for (const auto& [j, coefficient] : h.children(order[i]))
        next[{order[i].first + 1, j}].emplace_back(i, w * coefficient);
      if (max_functions > 0 && static_cast<long>(next.size()) > max_functions)
        throw Error("GpcSpline: a split step gives more than the " + std::to_string(max_functions) +
                    " functions allowed");
    }
    // Closure: an unsplit function whose children are all present is split as well.
    bool grew = false;
    for (int i = 0; i < n; ++i) {
      if (split[i] || order[i].first >= GpcSpline::kMaxLevel) continue;
      if (!next.count({order[i].first + 1, h.children(order[i]).front().first})) continue;
      bool all = true;
      for (const auto& [j, coefficient] : h.children(order[i]))
        if (!next.count({order[i].first + 1, j})) {
          all = false;
          break;
        }
      if (all) split[i] = 1, grew = true;
    }
    if (!grew) break;
  }
  StepRecord record;
  active.clear();
  for (auto& [key, sources] : next) {
    double w = 0.0;
    for (const auto& s : sources) w += s.second;
    active[key] = w;
    record.from.push_back(std::move(sources));
  }
  for (int i = 0; i < n; ++i)
    if (split[i]) record.split.push_back(i);
  return record;
}

double length_tolerance(const GpcDomain& domain) {
  double largest = 0.0;
  for (const auto& c : domain.cuboids)
    for (double s : c.size)
      if (std::isfinite(s)) largest = std::max(largest, s);
  return 1e-9 * largest;
}

}  // namespace

GpcSpline::GpcSpline(const polycube::GpcDomain& domain, const GpcSplineOptions& options)
    : domain_(domain), dimension_(options.dimension), clamped_option_(options.clamped_interfaces) {
  if (dimension_ < 1 || dimension_ > 4)
    throw Error("GpcSpline: dimension is " + str(dimension_) + " (must be 1..4)");
  const double tol = length_tolerance(domain_);
  validate_domain(domain_, tol);
  if (options.knot_lines.empty()) {
    check_counts(domain_, options.intervals);
    lines_ = uniform_lines(domain_, options.intervals);
  } else {
    lines_ = options.knot_lines;
    check_line_lists(domain_, lines_, tol);
  }
  check_lines(domain_, lines_, tol);
  intervals_.resize(lines_.size());
  for (std::size_t c = 0; c < lines_.size(); ++c)
    for (int a = 0; a < 3; ++a) intervals_[c][a] = static_cast<int>(lines_[c][a].size()) - 1;
  const int ni = static_cast<int>(domain_.interfaces.size());
  interface_join_.assign(ni, GpcFaceJoin::Continued);
  for (int i : options.clamped_interfaces) {
    if (i < 0 || i >= ni)
      throw Error("GpcSpline: clamped_interfaces names interface " + str(i) + " of " + str(ni));
    interface_join_[i] = GpcFaceJoin::Clamped;
  }
  // Continuity rule (§3.5, §4.4): every glued face starts Continued (C², the knot vectors run on
  // through the transition, Eq. 3.4) and is turned Clamped (C⁰, the two-cube merging of §4.4.1
  // with shared face control points) until the rule of JoinRule::same_at_edge holds on every face.
  // At a Type-1 ill-point the thesis (§4.4.2) adds extra bd-control-points and re-weights them by
  // knot insertion into an auxiliary grid (Table 4.2) but leaves open how the knot vectors of the
  // functions around the concave edge continue, and those weights (re-derived in the unit test)
  // sum to 1 − B_aux, short of 1 inside the solid next to the edge; we clamp the faces touching it
  // instead (C⁰ there, the continuity the thesis claims at ill-points), which keeps its measures
  // exact: Σ w_i B_i ≡ 1 (Eq. 4.3) and no function beyond the solid's boundary (§4.3.1). A
  // configuration the rule does not foresee (functions that fail to match across a face) clamps
  // that face too, and the rule runs again: joins only ever turn Clamped, so this ends.
  JoinRule rule(domain_, interface_join_, tol);
  for (;;) {
    while (rule.pass()) {
    }
    const Assembly assembly(domain_, lines_, interface_join_, tol);
    if (assembly.total() > std::numeric_limits<int>::max())
      throw Error("GpcSpline: the knot lines give more than 2^31 local functions");
    UnionFind uf(static_cast<int>(assembly.total()));
    const int failed = assembly.identify(uf);
    if (failed >= 0) {
      bool changed = false;
      if (interface_join_[failed] == GpcFaceJoin::Continued) {
        interface_join_[failed] = GpcFaceJoin::Clamped;
        changed = true;
      } else {
        for (int s = 0; s < 2; ++s)
          for (int f = 0; f < 6; ++f)
            if (f / 2 != domain_.interfaces[failed].face[s] / 2)
              changed = rule.clamp(domain_.interfaces[failed].cuboid[s], f) || changed;
      }
      if (!changed)
        throw Error("GpcSpline: the face functions of the two sides of interface " + str(failed) +
                    " do not match (unsupported gluing)");
      continue;
    }
    const int nc = num_cuboids();
    if (!options.splits.empty()) {
      build_hierarchy(options.splits, options.max_functions, tol);
      break;
    }
    // Global ids in order of first appearance (cuboid, then local function).
    std::vector<int> id_of_root(static_cast<std::size_t>(assembly.total()), -1);
    patch_ids_.assign(nc, {});
    patches_.clear();
    patches_.reserve(nc);
    num_functions_ = 0;
    std::vector<char> anchored;
    for (int c = 0; c < nc; ++c) {
      const int m = static_cast<int>(assembly.count(c));
      std::vector<BlendingKnots> knots(static_cast<std::size_t>(m));
      patch_ids_[c].resize(m);
      const Eigen::Vector3d size = size_of(domain_, c);
      for (int l = 0; l < m; ++l) {
        knots[l] = assembly.blending(c, l);
        int& id = id_of_root[uf.find(static_cast<int>(assembly.offset(c)) + l)];
        if (id < 0) {
          id = num_functions_++;
          anchors_.push_back({});
          anchored.push_back(0);
        }
        patch_ids_[c][l] = id;
        if (anchored[id]) continue;
        Eigen::Vector3d greville;
        for (int a = 0; a < 3; ++a) greville(a) = (knots[l][a][1] + knots[l][a][2] + knots[l][a][3]) / 3.0;
        const bool inside = (greville.array() >= -tol).all() && (greville.array() <= size.array() + tol).all();
        if (inside || anchors_[id].cuboid < 0) {
          anchors_[id] = {c, greville.cwiseMax(Eigen::Vector3d::Zero()).cwiseMin(size)};
          anchored[id] = inside;
        }
      }
      patches_.emplace_back(std::move(knots), Eigen::VectorXd::Ones(m), Eigen::MatrixXd::Zero(m, dimension_));
    }
    points_ = Eigen::MatrixXd::Zero(num_functions_, dimension_);
    level_of_.assign(num_functions_, 0);
    level_id_.resize(num_functions_);
    std::iota(level_id_.begin(), level_id_.end(), 0);
    break;
  }
}

void GpcSpline::build_hierarchy(const std::vector<std::vector<int>>& steps, long max_functions, double tol) {
  hierarchy_ = std::make_shared<detail::GpcHierarchy>(domain_, lines_, interface_join_, tol);
  Hierarchy& h = hierarchy_->levels;
  active_.clear();
  SparseLevel& level0 = h.level(0);
  for (int c = 0; c < num_cuboids(); ++c)
    for (long long l = 0; l < level0.assembly().count(c); ++l) active_[{0, level0.id_of(c, l)}] = 1.0;
  splits_.clear();
  for (const std::vector<int>& step : steps) {
    StepRecord record = refine_step(h, active_, step, max_functions);
    splits_.push_back(std::move(record.split));
    last_step_from_ = std::move(record.from);
  }
  build_patches(tol);
}

GpcSpline::GpcSpline(const GpcSpline& from, const std::vector<int>& split)
    : domain_(from.domain_),
      dimension_(from.dimension_),
      intervals_(from.intervals_),
      lines_(from.lines_),
      interface_join_(from.interface_join_),
      splits_(from.splits_),
      clamped_option_(from.clamped_option_),
      hierarchy_(from.hierarchy_),
      active_(from.active_) {
  StepRecord record = refine_step(hierarchy_->levels, active_, split, 0);
  splits_.push_back(std::move(record.split));
  last_step_from_ = std::move(record.from);
  build_patches(length_tolerance(domain_));
}

void GpcSpline::build_patches(double tol) {
  const int nc = num_cuboids();
  Hierarchy& h = hierarchy_->levels;
  num_functions_ = static_cast<int>(active_.size());
  level_of_.clear();
  level_id_.clear();
  std::vector<double> weight;
  for (const auto& [key, w] : active_) {
    level_of_.push_back(key.first);
    level_id_.push_back(key.second);
    weight.push_back(w);
  }
  // Per cuboid: the pieces of every function, in function order (Greville anchors as above).
  patch_ids_.assign(nc, {});
  patches_.clear();
  patches_.reserve(nc);
  anchors_.assign(num_functions_, {});
  std::vector<char> anchored(num_functions_, 0);
  std::vector<std::vector<BlendingKnots>> knots(nc);
  std::vector<std::vector<double>> weights(nc);
  for (int k = 0; k < num_functions_; ++k) {
    const SparseLevel& basis = h.level(level_of_[k]);
    for (const auto& [c, local] : basis.pieces(level_id_[k])) {
      const BlendingKnots b = basis.blending(c, local);
      knots[c].push_back(b);
      weights[c].push_back(weight[k]);
      patch_ids_[c].push_back(k);
      if (anchored[k]) continue;
      const Eigen::Vector3d size = size_of(domain_, c);
      Eigen::Vector3d greville;
      for (int a = 0; a < 3; ++a) greville(a) = (b[a][1] + b[a][2] + b[a][3]) / 3.0;
      const bool inside = (greville.array() >= -tol).all() && (greville.array() <= size.array() + tol).all();
      if (inside || anchors_[k].cuboid < 0) {
        anchors_[k] = {c, greville.cwiseMax(Eigen::Vector3d::Zero()).cwiseMin(size)};
        anchored[k] = inside;
      }
    }
  }
  for (int c = 0; c < nc; ++c) {
    const Eigen::Index m = static_cast<Eigen::Index>(knots[c].size());
    patches_.emplace_back(std::move(knots[c]), Eigen::Map<const Eigen::VectorXd>(weights[c].data(), m),
                          Eigen::MatrixXd::Zero(m, dimension_));
  }
  points_ = Eigen::MatrixXd::Zero(num_functions_, dimension_);
}

int GpcSpline::max_level() const {
  return level_of_.empty() ? 0 : *std::max_element(level_of_.begin(), level_of_.end());
}

GpcSpline GpcSpline::refined(const std::vector<int>& split) const {
  auto build = [&] {
    if (hierarchy_) return GpcSpline(*this, split);
    GpcSplineOptions o;
    o.knot_lines = lines_;
    o.clamped_interfaces = clamped_option_;
    o.dimension = dimension_;
    o.splits = {split};
    return GpcSpline(domain_, o);
  };
  GpcSpline out = build();
  // F unchanged: each new point is the weighted mean of the points it draws on (Eq. 4.9).
  Eigen::MatrixXd points(out.num_functions_, dimension_);
  for (int k = 0; k < out.num_functions_; ++k) {
    Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(dimension_);
    double w = 0.0;
    for (const auto& [old, factor] : out.last_step_from_[k]) {
      sum += factor * points_.row(old);
      w += factor;
    }
    points.row(k) = sum / w;
  }
  out.set_points(std::move(points));
  return out;
}

GpcFaceJoin GpcSpline::face_join(int cuboid, int face) const {
  const int i = domain_.cuboids[cuboid].face_interface[face];
  return i < 0 ? GpcFaceJoin::Surface : interface_join_[i];
}

int GpcSpline::num_continued_interfaces() const {
  return static_cast<int>(std::count(interface_join_.begin(), interface_join_.end(), GpcFaceJoin::Continued));
}

bool GpcSpline::uniform_knots() const {
  for (std::size_t c = 0; c < lines_.size(); ++c)
    for (int a = 0; a < 3; ++a) {
      const int n = intervals_[c][a];
      const double size = domain_.cuboids[c].size[a];
      for (int k = 0; k <= n; ++k)
        if (lines_[c][a][k] != (k == n ? size : size * k / n)) return false;
    }
  return true;
}

polycube::CubeFaceSet GpcSpline::exposed_faces(int cuboid) const {
  polycube::CubeFaceSet out;
  for (int f = 0; f < 6; ++f)
    if (face_join(cuboid, f) == GpcFaceJoin::Surface) out = out.with(f);
  return out;
}

void GpcSpline::set_points(Eigen::MatrixXd points) {
  if (points.rows() != num_functions_ || points.cols() != dimension_)
    throw Error("GpcSpline::set_points: points are " + str(static_cast<int>(points.rows())) + "x" +
                str(static_cast<int>(points.cols())) + ", expected " + str(num_functions_) + "x" + str(dimension_));
  if (!points.allFinite()) throw Error("GpcSpline::set_points: a control point is not finite");
  for (int c = 0; c < num_cuboids(); ++c) {
    const std::vector<int>& ids = patch_ids_[c];
    Eigen::MatrixXd local(static_cast<Eigen::Index>(ids.size()), dimension_);
    for (std::size_t l = 0; l < ids.size(); ++l) local.row(static_cast<Eigen::Index>(l)) = points.row(ids[l]);
    patches_[c].set_points(std::move(local));
  }
  points_ = std::move(points);
}

namespace {

// Kept out of line so that the box check of every evaluation stays small.
[[noreturn]] __attribute__((noinline, cold)) void throw_outside_cuboid(const Eigen::Vector3d& uvw, int cuboid) {
  throw Error("GpcSpline: uvw (" + std::to_string(uvw(0)) + ", " + std::to_string(uvw(1)) + ", " +
              std::to_string(uvw(2)) + ") is outside cuboid " + std::to_string(cuboid));
}

}  // namespace

inline Eigen::Vector3d GpcSpline::checked(int cuboid, const Eigen::Vector3d& uvw) const {
  assert(cuboid >= 0 && cuboid < num_cuboids());
  const auto& size = domain_.cuboids[cuboid].size;
  Eigen::Vector3d out;
  for (int a = 0; a < 3; ++a) {
    const double slack = 1e-9 * size[a];
    if (!std::isfinite(uvw(a)) || uvw(a) < -slack || uvw(a) > size[a] + slack) throw_outside_cuboid(uvw, cuboid);
    out(a) = std::clamp(uvw(a), 0.0, size[a]);
  }
  return out;
}

void GpcSpline::evaluate_with_jacobian(int cuboid, const Eigen::Vector3d& uvw, double* value, double* jacobian) const {
  patches_[cuboid].evaluate_with_jacobian(checked(cuboid, uvw), TSplineForm::SemiStandard, value, jacobian);
}

void GpcSpline::evaluate_to(int cuboid, const Eigen::Vector3d& uvw, double* value) const {
  patches_[cuboid].evaluate_to(checked(cuboid, uvw), TSplineForm::SemiStandard, value);
}

Eigen::VectorXd GpcSpline::evaluate(int cuboid, const Eigen::Vector3d& uvw) const {
  return patches_[cuboid].evaluate(checked(cuboid, uvw));
}

Eigen::MatrixXd GpcSpline::evaluate_batch(const std::vector<int>& cuboids, const Eigen::MatrixX3d& uvw,
                                          Eigen::MatrixXd* jacobians) const {
  Eigen::MatrixXd values;
  evaluate_batch(cuboids, uvw, values, jacobians);
  return values;
}

// Rows grouped by cuboid (stable counting sort), then each cuboid's rows in chunks through its
// patch's cell-sorted batch (TSpline::evaluate_batch): chunks of a size that keeps the local
// copies in L2 while a cell of the patch still holds several of the chunk's rows.
void GpcSpline::evaluate_batch(const std::vector<int>& cuboids, const Eigen::MatrixX3d& uvw, Eigen::MatrixXd& values,
                               Eigen::MatrixXd* jacobians) const {
  const Eigen::Index m = uvw.rows();
  if (Eigen::Index(cuboids.size()) != m) {
    throw Error("GpcSpline: " + std::to_string(cuboids.size()) + " cuboid ids for " + std::to_string(m) + " rows");
  }
  std::vector<Eigen::Index> start(num_cuboids() + 1, 0);
  for (Eigen::Index i = 0; i < m; ++i) {
    const int c = cuboids[size_t(i)];
    if (c < 0 || c >= num_cuboids()) {
      throw Error("row " + std::to_string(i) + ": GpcSpline: cuboid " + std::to_string(c) + " is not in 0.." +
                  std::to_string(num_cuboids() - 1));
    }
    ++start[c + 1];
  }
  for (int c = 0; c < num_cuboids(); ++c) start[c + 1] += start[c];
  std::vector<Eigen::Index> rows(static_cast<size_t>(m));
  std::vector<Eigen::Index> fill(start.begin(), start.end() - 1);
  for (Eigen::Index i = 0; i < m; ++i) rows[size_t(fill[cuboids[size_t(i)]]++)] = i;
  values.resize(m, dimension_);
  if (jacobians) jacobians->resize(m, 3 * dimension_);
  constexpr Eigen::Index kChunk = 32768;
  Eigen::MatrixX3d local;
  Eigen::MatrixXd local_values, local_jacobians;
  for (int c = 0; c < num_cuboids(); ++c) {
    for (Eigen::Index begin = start[c]; begin < start[c + 1]; begin += kChunk) {
      const Eigen::Index n = std::min(kChunk, start[c + 1] - begin);
      local.resize(n, 3);
      for (Eigen::Index r = 0; r < n; ++r) {
        const Eigen::Index row = rows[size_t(begin + r)];
        try {
          local.row(r) = checked(c, uvw.row(row).transpose()).transpose();
        } catch (const Error& e) {
          throw Error("row " + std::to_string(row) + ": " + e.what());
        }
      }
      if (jacobians) {
        patches_[c].evaluate_batch_with_jacobian(local, TSplineForm::SemiStandard, local_values, local_jacobians);
      } else {
        patches_[c].evaluate_batch(local, TSplineForm::SemiStandard, local_values);
      }
      for (Eigen::Index r = 0; r < n; ++r) {
        const Eigen::Index row = rows[size_t(begin + r)];
        values.row(row) = local_values.row(r);
        if (jacobians) jacobians->row(row) = local_jacobians.row(r);
      }
    }
  }
}

Eigen::MatrixXd GpcSpline::jacobian(int cuboid, const Eigen::Vector3d& uvw) const {
  return patches_[cuboid].jacobian(checked(cuboid, uvw));
}

Eigen::VectorXd GpcSpline::derivative(int cuboid, const Eigen::Vector3d& uvw, const std::array<int, 3>& order) const {
  return patches_[cuboid].derivative(checked(cuboid, uvw), order);
}

double GpcSpline::weight_sum(int cuboid, const Eigen::Vector3d& uvw) const {
  return patches_[cuboid].weight_sum(checked(cuboid, uvw));
}

int GpcSpline::cell_of(int cuboid, const Eigen::Vector3d& uvw) const {
  return patches_[cuboid].cell_of(checked(cuboid, uvw));
}

void GpcSpline::basis_at(int cuboid, const Eigen::Vector3d& uvw, const std::array<int, 3>& order,
                         std::vector<int>& function_ids, std::vector<double>& values) const {
  const TSpline& patch = patches_[cuboid];
  std::vector<int> local;
  std::vector<double> local_values;
  patch.basis_at(checked(cuboid, uvw), order, local, local_values);
  std::vector<std::pair<int, double>> pairs(local.size());
  for (std::size_t k = 0; k < local.size(); ++k)
    pairs[k] = {patch_ids_[cuboid][local[k]], patch.weights()(local[k]) * local_values[k]};
  // Sorted by id, then by local order (stable): sums of a repeated id in a fixed order.
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  function_ids.clear();
  values.clear();
  for (const auto& [id, v] : pairs) {
    if (!function_ids.empty() && function_ids.back() == id) {
      values.back() += v;
    } else {
      function_ids.push_back(id);
      values.push_back(v);
    }
  }
}

std::vector<std::array<int, 3>> gpc_uniform_intervals(const polycube::GpcDomain& domain, double knot_spacing,
                                                      const std::vector<std::array<double, 3>>* lengths) {
  if (!std::isfinite(knot_spacing) || !(knot_spacing > 0.0))
    throw Error("gpc_uniform_intervals: knot_spacing is " + std::to_string(knot_spacing) + " (must be > 0)");
  const int nc = static_cast<int>(domain.cuboids.size());
  if (lengths && static_cast<int>(lengths->size()) != nc)
    throw Error("gpc_uniform_intervals: " + str(static_cast<int>(lengths->size())) + " length triples for " + str(nc) +
                " cuboids");
  UnionFind uf(3 * nc);
  for (int i = 0; i < static_cast<int>(domain.interfaces.size()); ++i) {
    const auto& in = domain.interfaces[i];
    if (in.cuboid[0] < 0 || in.cuboid[0] >= nc || in.cuboid[1] < 0 || in.cuboid[1] >= nc || in.face[0] < 0 ||
        in.face[0] > 5)
      throw Error("gpc_uniform_intervals: interface " + str(i) + " names a cuboid or face out of range");
    for (int t = 0; t < 3; ++t) {
      if (t == in.face[0] / 2) continue;
      const int tb = in.transition.axis[t];
      if (tb < 0 || tb > 2) throw Error("gpc_uniform_intervals: interface " + str(i) + " has an invalid transition");
      const double sa = domain.cuboids[in.cuboid[0]].size[t], sb = domain.cuboids[in.cuboid[1]].size[tb];
      if (!(std::abs(sa - sb) <= 1e-9 * std::max(std::abs(sa), std::abs(sb))))
        throw Error("gpc_uniform_intervals: interface " + str(i) + " glues cuboid " + str(in.cuboid[0]) + " axis " +
                    str(t) + " (size " + std::to_string(sa) + ") to cuboid " + str(in.cuboid[1]) + " axis " + str(tb) +
                    " (size " + std::to_string(sb) + ")");
      uf.unite(3 * in.cuboid[0] + t, 3 * in.cuboid[1] + tb);
    }
  }
  // Glued axes share one count: the mean of their lengths over the spacing (the sizes of glued
  // axes are equal, so without lengths this is ceil(size/spacing)).
  std::vector<double> sum(static_cast<std::size_t>(3 * nc), 0.0);
  std::vector<int> members(static_cast<std::size_t>(3 * nc), 0);
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a) {
      const double length = lengths ? (*lengths)[c][a] : domain.cuboids[c].size[a];
      if (!(length >= 0.0) || !std::isfinite(length))
        throw Error("gpc_uniform_intervals: the length of cuboid " + str(c) + " axis " + str(a) + " is not finite and >= 0");
      sum[uf.find(3 * c + a)] += length;
      ++members[uf.find(3 * c + a)];
    }
  std::vector<int> count(static_cast<std::size_t>(3 * nc), 1);
  for (std::size_t k = 0; k < count.size(); ++k)
    if (members[k] > 0) {
      const double n = std::ceil(sum[k] / members[k] / knot_spacing * (1.0 - 1e-12));
      count[k] = n > 1.0 ? static_cast<int>(std::min(n, 1e6)) : 1;
    }
  std::vector<std::array<int, 3>> out(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a) out[c][a] = count[uf.find(3 * c + a)];
  return out;
}


std::vector<std::array<std::vector<double>, 3>> gpc_uniform_knot_lines(const polycube::GpcDomain& domain,
                                                                       const std::vector<std::array<int, 3>>& intervals) {
  check_counts(domain, intervals);
  return uniform_lines(domain, intervals);
}

int gpc_insert_knot_line(const polycube::GpcDomain& domain, std::vector<std::array<std::vector<double>, 3>>& lines,
                         int cuboid, int axis, double x) {
  const int nc = static_cast<int>(domain.cuboids.size());
  if (static_cast<int>(lines.size()) != nc)
    throw Error("gpc_insert_knot_line: knot lines for " + str(static_cast<int>(lines.size())) + " cuboids, the domain has " +
                str(nc));
  if (cuboid < 0 || cuboid >= nc || axis < 0 || axis > 2)
    throw Error("gpc_insert_knot_line: cuboid " + str(cuboid) + " axis " + str(axis) + " out of range");
  if (!(x > 0.0 && x < domain.cuboids[cuboid].size[axis]))
    throw Error("gpc_insert_knot_line: the line " + std::to_string(x) + " is not inside cuboid " + str(cuboid) +
                " axis " + str(axis));
  const double tol = length_tolerance(domain);
  int inserted = 0;
  // Closure over the gluing of tangent axes: every line lands in every axis of its class.
  std::vector<std::tuple<int, int, double>> queue{{cuboid, axis, x}};
  while (!queue.empty()) {
    const auto [c, a, v] = queue.back();
    queue.pop_back();
    std::vector<double>& l = lines[c][a];
    if (l.size() < 2) throw Error("gpc_insert_knot_line: cuboid " + str(c) + " axis " + str(a) + " has fewer than 2 lines");
    const auto at = std::lower_bound(l.begin(), l.end(), v);
    if ((at != l.end() && *at - v <= tol) || (at != l.begin() && v - *(at - 1) <= tol)) continue;
    l.insert(at, v);
    ++inserted;
    for (const polycube::GpcInterface& in : domain.interfaces)
      for (int s = 0; s < 2; ++s) {
        if (in.cuboid[s] != c || in.face[s] / 2 == a) continue;
        const GpcTransition to = s == 0 ? in.transition : in.transition.inverse();
        queue.emplace_back(in.cuboid[1 - s], to.axis[a], line_image(to, a, v));
      }
  }
  return inserted;
}

}  // namespace volspline::spline
