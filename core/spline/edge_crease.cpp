// SPDX-License-Identifier: MIT
#include "core/spline/edge_crease.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <map>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/spline/bezier_extraction.h"

namespace volspline::spline {

namespace {

// One cuboid edge of a cell: along axis t, axes a = (t + 1) % 3 and b = (t + 2) % 3 at their
// low (false) or high (true) ends.
struct CellEdge {
  int t = 0;
  bool high_a = false, high_b = false;
  int a() const { return (t + 1) % 3; }
  int b() const { return (t + 2) % 3; }
};

// True if knot vector r is a bd-control-point's on that end (quadruple end knot: B ≠ 0 on the face).
bool on_face(const LocalKnots& r, double end, bool high) { return high ? r[1] == end : r[3] == end; }

// The edge's sample points in uvw: `count` points from the cell's low to high end along t.
std::vector<Eigen::Vector3d> edge_samples(const TSpline& spline, int cell, const CellEdge& edge, int count) {
  const std::array<int, 3> k = spline.cell_index(cell);
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  const double t0 = spline.knot_lines(edge.t)[k[edge.t]], t1 = spline.knot_lines(edge.t)[k[edge.t] + 1];
  std::vector<Eigen::Vector3d> out;
  for (int j = 0; j < count; ++j) {
    Eigen::Vector3d p;
    p(edge.t) = j + 1 == count ? t1 : t0 + (t1 - t0) * j / (count - 1);
    p(edge.a()) = edge.high_a ? hi(edge.a()) : lo(edge.a());
    p(edge.b()) = edge.high_b ? hi(edge.b()) : lo(edge.b());
    out.push_back(p);
  }
  return out;
}

// At one edge point: J, and per moving function its w·∂B/∂(axis) for axis a (row in face b) or
// b (row in face a); the edge functions (B ≠ 0 on the edge) stay and set J_t.
struct EdgePoint {
  Eigen::Matrix3d jacobian;
  std::vector<std::pair<int, double>> row_a, row_b;  // (function, w·∂B/∂a) and (function, w·∂B/∂b)
};

EdgePoint edge_point(const TSpline& spline, const Eigen::Vector3d& p, const CellEdge& edge) {
  EdgePoint out;
  out.jacobian = spline.jacobian(p);
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::vector<int> ids;
  std::vector<double> values;
  for (int side = 0; side < 2; ++side) {
    const int axis = side == 0 ? edge.a() : edge.b();
    const bool high = side == 0 ? edge.high_a : edge.high_b;
    std::array<int, 3> order = {0, 0, 0};
    order[axis] = 1;
    spline.basis_at(p, order, ids, values);
    for (std::size_t q = 0; q < ids.size(); ++q) {
      const int f = ids[q];
      if (values[q] == 0.0 || on_face(spline.knots()[f][axis], high ? hi(axis) : lo(axis), high)) continue;
      (side == 0 ? out.row_a : out.row_b).emplace_back(f, spline.weights()(f) * values[q]);
    }
  }
  return out;
}

double scaled_det(const Eigen::Matrix3d& j) {
  const double scale = j.col(0).norm() * j.col(1).norm() * j.col(2).norm();
  return scale > 0 ? j.determinant() / scale : -1.0;
}

// The edges of `cell` between two exposed faces of the domain box.
std::vector<CellEdge> exposed_edges(const TSpline& spline, int cell, polycube::CubeFaceSet exposed) {
  const std::array<int, 3> k = spline.cell_index(cell);
  std::array<int, 3> end{};  // per axis: bit 0 low face touched, bit 1 high face
  for (int a = 0; a < 3; ++a) {
    if (k[a] == 0 && exposed.contains(2 * a)) end[a] |= 1;
    if (k[a] + 2 == static_cast<int>(spline.knot_lines(a).size()) && exposed.contains(2 * a + 1)) end[a] |= 2;
  }
  std::vector<CellEdge> out;
  for (int t = 0; t < 3; ++t)
    for (int ea = 0; ea < 2; ++ea)
      for (int eb = 0; eb < 2; ++eb) {
        CellEdge e{t, ea == 1, eb == 1};
        if ((end[e.a()] >> ea & 1) && (end[e.b()] >> eb & 1)) out.push_back(e);
      }
  return out;
}

// Largest cosine between the two faces' directions across the edge (±J_a in face b, ±J_b in
// face a, without their parts along the edge, signed to point at the edge) above which a cuboid
// edge is no near-flat crease: a smooth surface's faces meet at a flat angle along an edge
// (opposite directions: −1); a cube's edge has 0.
constexpr double kFlatCosine = -0.3;

// True if the faces meet at a near-flat angle at the middle of the cell's edge: a crease the tilt
// is for. At a cell's corner three edges share det J's corner value; only the near-flat ones may
// have caused it.
bool near_flat(const TSpline& spline, int cell, const CellEdge& edge) {
  const Eigen::Matrix3d j = spline.jacobian(edge_samples(spline, cell, edge, 3)[1]);
  const double tt = j.col(edge.t).squaredNorm();
  if (!(tt > 0)) return false;
  // The directions across the edge: J_a and J_b without their part along the edge.
  const Eigen::Vector3d pa = j.col(edge.a()) - j.col(edge.a()).dot(j.col(edge.t)) / tt * j.col(edge.t);
  const Eigen::Vector3d pb = j.col(edge.b()) - j.col(edge.b()).dot(j.col(edge.t)) / tt * j.col(edge.t);
  const double sign = edge.high_a == edge.high_b ? 1.0 : -1.0;  // J_a, J_b point at the high end
  const double norms = pa.norm() * pb.norm();
  return norms > 0 && sign * pa.dot(pb) < kFlatCosine * norms;
}

// Tilts the rows next to one edge of one cell (see convex_edge_creases); returns the largest move,
// 0 if none. moved: set for every moved function.
double tilt_edge(TSpline& spline, int cell, const CellEdge& edge, double margin, int samples,
                 std::vector<char>& moved) {
  const std::vector<Eigen::Vector3d> points = edge_samples(spline, cell, edge, samples);
  std::vector<EdgePoint> at;
  for (const Eigen::Vector3d& p : points) at.push_back(edge_point(spline, p, edge));
  // Gradient of Σ_j det J_j with respect to each moving point: w·∂B times the cofactor column
  // of J (∂ det / ∂J_a = J_b × J_t with (t, a, b) cyclic, likewise for b).
  std::map<int, Eigen::Vector3d> gradient;
  for (const EdgePoint& e : at) {
    const Eigen::Matrix3d& j = e.jacobian;
    const Eigen::Vector3d cof_a = j.col(edge.b()).cross(j.col(edge.t)), cof_b = j.col(edge.t).cross(j.col(edge.a()));
    for (const auto& [f, g] : e.row_a) gradient.try_emplace(f, Eigen::Vector3d::Zero()).first->second += g * cof_a;
    for (const auto& [f, g] : e.row_b) gradient.try_emplace(f, Eigen::Vector3d::Zero()).first->second += g * cof_b;
  }
  double largest = 0.0;
  for (const auto& [f, g] : gradient) largest = std::max(largest, g.norm());
  if (!(largest > 0.0)) return 0.0;
  // Unit step: the largest move is 1 model unit. J_j(c) = J_j + c·(dA_j e_aᵀ + dB_j e_bᵀ).
  std::vector<Eigen::Vector3d> da(at.size(), Eigen::Vector3d::Zero()), db(at.size(), Eigen::Vector3d::Zero());
  for (std::size_t j = 0; j < at.size(); ++j) {
    for (const auto& [f, g] : at[j].row_a) da[j] += g * gradient[f] / largest;
    for (const auto& [f, g] : at[j].row_b) db[j] += g * gradient[f] / largest;
  }
  auto reaches = [&](double c) {
    for (std::size_t j = 0; j < at.size(); ++j) {
      Eigen::Matrix3d m = at[j].jacobian;
      m.col(edge.a()) += c * da[j];
      m.col(edge.b()) += c * db[j];
      if (scaled_det(m) < margin) return false;
    }
    return true;
  };
  // Length of the cell's edge in model units: the scale of the search.
  const std::array<int, 3> k = spline.cell_index(cell);
  const double width = spline.knot_lines(edge.t)[k[edge.t] + 1] - spline.knot_lines(edge.t)[k[edge.t]];
  const double length = at[at.size() / 2].jacobian.col(edge.t).norm() * width;
  if (reaches(0.0) || !(length > 0.0)) return 0.0;
  // A tilt by the margin needs moves of about margin·length; a crease that needs more than a
  // quarter of the edge length is no near-flat one and is left as it is.
  double lo = 0.0, hi = 1e-6 * margin * length;
  while (!reaches(hi)) {
    lo = hi;
    hi *= 2.0;
    if (hi > 0.25 * length) return 0.0;
  }
  for (int step = 0; step < 40; ++step) {
    const double mid = 0.5 * (lo + hi);
    (reaches(mid) ? hi : lo) = mid;
  }
  Eigen::MatrixXd p = spline.points();
  for (const auto& [f, g] : gradient) {
    p.row(f) += (hi * g / largest).transpose();
    moved[f] = 1;
  }
  spline.set_points(std::move(p));
  return hi;
}

}  // namespace

double edge_lower_bound_rel(const TSpline& spline, int cell, int t, bool high_a, bool high_b) {
  assert(spline.dimension() == 3);
  const BezierCell bezier = extract_bezier_cell(spline, cell);
  double c[kJacobianCoefficients];
  double column_bound = 0.0;
  jacobian_determinant_bernstein(bezier, c, &column_bound);
  const int a = (t + 1) % 3, b = (t + 2) % 3;
  const int stride[3] = {1, 9, 81};
  double lowest = c[(high_a ? 8 : 0) * stride[a] + (high_b ? 8 : 0) * stride[b]];
  for (int i = 1; i <= 8; ++i)
    lowest = std::min(lowest, c[i * stride[t] + (high_a ? 8 : 0) * stride[a] + (high_b ? 8 : 0) * stride[b]]);
  return column_bound > 0 ? lowest / column_bound : -1.0;
}

EdgeCreaseResult convex_edge_creases(TSpline& spline, const std::vector<UncertifiedCell>& cells,
                                     const EdgeCreaseOptions& options, const JacobianCertificateOptions& certificate) {
  if (spline.dimension() != 3)
    throw Error("edge creases: the spline has dimension " + std::to_string(spline.dimension()) +
                ", expected 3 (geometry)");
  if (!(options.margin > 0.0 && options.margin <= 0.1)) throw Error("edge creases: margin must be in (0, 0.1]");
  if (options.tries < 1 || options.tries > 16) throw Error("edge creases: tries must be in [1, 16]");
  if (options.edge_samples < 2 || options.edge_samples > 64)
    throw Error("edge creases: edge_samples must be in [2, 64]");
  EdgeCreaseResult result;
  std::vector<char> moved(spline.num_functions(), 0);
  const double tau = certificate.rounding_rel;
  auto certified = [&](int cell) {
    return certify_bezier_cell(extract_bezier_cell(spline, cell), certificate).status == JacobianCellStatus::Certified;
  };
  for (const UncertifiedCell& u : cells) {
    for (const CellEdge& edge : exposed_edges(spline, u.cell, options.exposed_faces)) {
      // On the edge: det J's coefficients there are negative. Next to it: the cell's lowest det J
      // lies within half the cell of the edge, where a convex crease lifts det J too.
      if (!near_flat(spline, u.cell, edge)) continue;
      const double on_edge = edge_lower_bound_rel(spline, u.cell, edge.t, edge.high_a, edge.high_b);
      const Eigen::Vector3d& s = u.bound.lowest_corner_s;
      const bool next_to = std::abs(s(edge.a()) - edge.high_a) <= 0.5 && std::abs(s(edge.b()) - edge.high_b) <= 0.5;
      if (on_edge >= -tau && !next_to) continue;
      if (certified(u.cell)) continue;  // an earlier edge's tilt certified it
      const Eigen::MatrixXd before = spline.points();
      const std::vector<char> moved_before = moved;
      double margin = options.margin, largest = 0.0;
      bool done = false;
      for (int attempt = 0; attempt < options.tries && !done; ++attempt, margin *= 2.0) {
        largest = std::max(largest, tilt_edge(spline, u.cell, edge, std::min(margin, 0.1), options.edge_samples, moved));
        done = certified(u.cell);
        // Once det J on the edge is certified, what is left of the fold is no crease's.
        if (on_edge < -tau && edge_lower_bound_rel(spline, u.cell, edge.t, edge.high_a, edge.high_b) >= -tau) break;
      }
      // A tilt that neither certifies the cell nor lifts det J on the edge is undone.
      if (!done && (on_edge >= -tau || edge_lower_bound_rel(spline, u.cell, edge.t, edge.high_a, edge.high_b) <= on_edge)) {
        spline.set_points(before);
        moved = moved_before;
        continue;
      }
      ++result.edges;
      result.fixed += done;
      result.max_displacement = std::max(result.max_displacement, largest);
    }
  }
  for (int f = 0; f < spline.num_functions(); ++f)
    if (moved[f]) result.moved.push_back(f);
  return result;
}

}  // namespace volspline::spline
