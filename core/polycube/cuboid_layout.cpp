// SPDX-License-Identifier: MIT
#include "core/polycube/cuboid_layout.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <set>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/mesh/mesh_geometry.h"
#include "core/polycube/surface_paths.h"

namespace volspline::polycube {

std::array<int, 2> cube_edge_corners(int edge) {
  assert(edge >= 0 && edge < num_cube_edges);
  const int axis = edge / 4;
  const int combo = edge % 4;
  const int o1 = axis == 0 ? 1 : 0;
  const int o2 = axis == 2 ? 1 : 2;
  const int low = ((combo & 1) << o1) | (((combo >> 1) & 1) << o2);
  return {low, low | (1 << axis)};
}

int cube_edge_between(int corner_a, int corner_b) {
  const int diff = corner_a ^ corner_b;
  assert(diff == 1 || diff == 2 || diff == 4);
  const int axis = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  const int low = std::min(corner_a, corner_b);
  const int o1 = axis == 0 ? 1 : 0;
  const int o2 = axis == 2 ? 1 : 2;
  return 4 * axis + ((low >> o1) & 1) + 2 * ((low >> o2) & 1);
}

std::array<int, 4> cube_face_corners(int face) {
  assert(face >= 0 && face < num_cube_faces);
  const int a = face / 2;
  const int base = (face % 2) << a;
  const int b1 = 1 << ((a + 1) % 3);
  const int b2 = 1 << ((a + 2) % 3);
  return {base, base | b1, base | b1 | b2, base | b2};
}

std::array<int, 4> cube_face_edges(int face) {
  const auto c = cube_face_corners(face);
  return {cube_edge_between(c[0], c[1]), cube_edge_between(c[1], c[2]),
          cube_edge_between(c[2], c[3]), cube_edge_between(c[3], c[0])};
}

namespace {

// Corner sets tried, best first, for each of the two corner rules before giving up.
constexpr int kCornerCandidates = 6;

using Corners = std::array<int, num_cube_corners>;

// Corner c of the unit cube, at (c&1, c>>1&1, c>>2&1).
Eigen::Vector3d corner_offset(int c) { return Eigen::Vector3d(c & 1, c >> 1 & 1, c >> 2 & 1); }

Eigen::Vector3d corner_signs(int c) {
  return Eigen::Vector3d((c & 1) ? 1.0 : -1.0, ((c >> 1) & 1) ? 1.0 : -1.0,
                         ((c >> 2) & 1) ? 1.0 : -1.0);
}

double min_pair_distance(const mesh::HalfedgeMesh& mesh, const Corners& corners) {
  double best = std::numeric_limits<double>::infinity();
  for (int a = 0; a < num_cube_corners; ++a)
    for (int b = a + 1; b < num_cube_corners; ++b)
      best = std::min(best, (mesh.vertex_position(corners[a]) -
                             mesh.vertex_position(corners[b])).norm());
  return best;
}

// The used vertices in a uniform grid of cells, each with the bounding box of its vertices, so
// that the vertex with the largest score visits only the cells whose bound reaches the best
// score found. Exact: a cell's bound is evaluated with the same floating-point expression as the
// scores on the box corner that maximizes it (rounding is monotone), so it is never below any of
// its vertices' scores, and equal scores go to the lowest vertex id, as in a scan of all vertices.
class VertexCells {
 public:
  explicit VertexCells(const mesh::HalfedgeMesh& mesh) : mesh_(mesh) {
    std::vector<int> used;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (mesh.vertex_halfedge(v) != mesh::no_id) used.push_back(v);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int v : used) {
      lo = lo.cwiseMin(mesh.vertex_position(v));
      hi = hi.cwiseMax(mesh.vertex_position(v));
    }
    // About 512 vertices per cell: the cells' bounds cost little next to the vertices scanned.
    const int r = std::clamp(static_cast<int>(std::cbrt(used.size() / 512.0)), 1, 32);
    std::vector<int> cell_of(used.size());
    std::vector<int> count(static_cast<std::size_t>(r) * r * r + 1, 0);
    for (std::size_t i = 0; i < used.size(); ++i) {
      const Eigen::Vector3d p = mesh.vertex_position(used[i]);
      int cell = 0;
      for (int a = 2; a >= 0; --a) {
        const double extent = hi(a) - lo(a);
        const int k = extent > 0.0 ? std::clamp(static_cast<int>((p(a) - lo(a)) / extent * r), 0, r - 1) : 0;
        cell = cell * r + k;
      }
      cell_of[i] = cell;
      ++count[cell + 1];
    }
    for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
    first_ = count;
    vertex_.resize(used.size());
    for (std::size_t i = 0; i < used.size(); ++i) vertex_[count[cell_of[i]]++] = used[i];  // ascending ids per cell
    const std::size_t cells = first_.size() - 1;
    lo_.assign(cells, Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()));
    hi_.assign(cells, -lo_[0]);
    for (std::size_t c = 0; c < cells; ++c)
      for (int k = first_[c]; k < first_[c + 1]; ++k) {
        lo_[c] = lo_[c].cwiseMin(mesh.vertex_position(vertex_[k]));
        hi_[c] = hi_[c].cwiseMax(mesh.vertex_position(vertex_[k]));
      }
  }

  // The vertex maximizing (x − centre)·direction.
  int max_along(const Eigen::Vector3d& centre, const Eigen::Vector3d& direction) const {
    return best([&](const Eigen::Vector3d& x) { return (x - centre).dot(direction); },
                [&](int c) {
                  Eigen::Vector3d corner;
                  for (int a = 0; a < 3; ++a) corner(a) = direction(a) >= 0.0 ? hi_[c](a) : lo_[c](a);
                  return (corner - centre).dot(direction);
                });
  }

  // The vertex nearest to target.
  int nearest_to(const Eigen::Vector3d& target) const {
    return best([&](const Eigen::Vector3d& x) { return -(x - target).squaredNorm(); },
                [&](int c) { return -(target.cwiseMax(lo_[c]).cwiseMin(hi_[c]) - target).squaredNorm(); });
  }

 private:
  template <class Score, class Bound>
  int best(const Score& score, const Bound& bound) const {
    const int cells = static_cast<int>(first_.size()) - 1;
    std::vector<double> bounds(cells, -std::numeric_limits<double>::infinity());
    int top = -1;
    for (int c = 0; c < cells; ++c) {
      if (first_[c] == first_[c + 1]) continue;
      bounds[c] = bound(c);
      if (top < 0 || bounds[c] > bounds[top]) top = c;
    }
    double best_score = -std::numeric_limits<double>::infinity();
    int best_id = -1;
    auto scan = [&](int c) {
      for (int k = first_[c]; k < first_[c + 1]; ++k) {
        const int v = vertex_[k];
        const double s = score(mesh_.vertex_position(v));
        if (best_id < 0 || s > best_score || (s == best_score && v < best_id)) {
          best_score = s;
          best_id = v;
        }
      }
    };
    if (top < 0) return -1;
    scan(top);
    for (int c = 0; c < cells; ++c)
      if (c != top && first_[c] < first_[c + 1] && bounds[c] >= best_score) scan(c);
    return best_id;
  }

  const mesh::HalfedgeMesh& mesh_;
  std::vector<int> first_;   // per cell, its range of vertex_ (cells + 1 offsets)
  std::vector<int> vertex_;  // used vertex ids, by cell, ascending within a cell
  std::vector<Eigen::Vector3d> lo_, hi_;  // per cell, the bounding box of its vertices
};

// Vertices extremal along the 8 box diagonals of `frame` (columns = axes) scaled by `extent`
// (nearest: the vertices nearest to the corners of the box of half-sides 2·extent instead);
// false if two diagonals pick the same vertex.
bool extremal_corners(const VertexCells& cells, const Eigen::Vector3d& centre, const Eigen::Matrix3d& frame,
                      const Eigen::Vector3d& extent, bool nearest, Corners& corners) {
  for (int c = 0; c < num_cube_corners; ++c) {
    const Eigen::Vector3d direction = frame * corner_signs(c).cwiseProduct(extent);
    corners[c] = nearest ? cells.nearest_to(centre + 2.0 * direction) : cells.max_along(centre, direction);
  }
  std::set<int> distinct(corners.begin(), corners.end());
  return static_cast<int>(distinct.size()) == num_cube_corners;
}

// Candidate corner sets, best first: the corners farthest apart (no slivers) first, ties in the
// order of the frames, each set once. progress: "cuboid layout" with the fraction of candidate
// frames tried.
std::vector<Corners> automatic_corners(const mesh::HalfedgeMesh& mesh, bool nearest, const Progress& progress) {
  // Area-weighted moments make the frame independent of the sampling density.
  const std::vector<double> areas = mesh::face_areas(mesh);
  std::vector<double> vertex_weight(mesh.num_vertices(), 0.0);
  double total = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int v : mesh.face_vertices(f)) vertex_weight[v] += areas[f] / 3.0;
    total += areas[f];
  }
  if (!(total > 0.0)) throw Error("mesh '" + mesh.source_name() + "': surface has zero area");
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) centre += vertex_weight[v] * mesh.vertex_position(v);
  centre /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d d = mesh.vertex_position(v) - centre;
    covariance += vertex_weight[v] * d * d.transpose();
  }
  covariance /= total;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  Eigen::Matrix3d pca;
  Eigen::Vector3d extent;
  for (int a = 0; a < 3; ++a) {
    pca.col(a) = eigen.eigenvectors().col(2 - a);
    extent(a) = std::sqrt(std::max(eigen.eigenvalues()(2 - a), 0.0));
  }
  if (pca.determinant() < 0.0) pca.col(2) = -pca.col(2);
  extent = extent.cwiseMax(1e-9 * extent.maxCoeff());

  // Candidate frames: the PCA frame, 15°-step rotations about its axes and 2×12 rotations
  // about well-spread axes (for nearly isotropic shapes, whose PCA axes are arbitrary); each
  // is refined by Procrustes fits of the box to its corners (a rotated cube then snaps onto
  // its own corners). The corners farthest apart (no slivers) win; ties keep the first.
  std::vector<Eigen::Matrix3d> frames = {pca};
  const double degree = 3.14159265358979323846 / 180.0;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 1; k < 6; ++k)
      frames.push_back(pca * Eigen::AngleAxisd(15.0 * k * degree, Eigen::Vector3d::Unit(axis)).toRotationMatrix());
  for (int i = 0; i < 12; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / 12.0;
    const double phi = i * 137.50776405 * degree;
    const Eigen::Vector3d axis(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    for (double angle : {25.0, 50.0})
      frames.push_back(pca * Eigen::AngleAxisd(angle * degree, axis).toRotationMatrix());
  }
  const VertexCells cells(mesh);
  std::vector<std::pair<double, Corners>> candidates;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    progress.report("cuboid layout", double(k) / frames.size());
    const Eigen::Matrix3d& start = frames[k];
    Corners current;
    if (!extremal_corners(cells, centre, start, extent, nearest, current)) continue;
    double score = min_pair_distance(mesh, current);
    for (int iteration = 0; iteration < 8; ++iteration) {
      Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
      for (int c = 0; c < num_cube_corners; ++c)
        h += corner_signs(c).cwiseProduct(extent) * (mesh.vertex_position(current[c]) - centre).transpose();
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
      fix(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
      const Eigen::Matrix3d frame = svd.matrixV() * fix * svd.matrixU().transpose();
      Corners next;
      if (!extremal_corners(cells, centre, frame, extent, nearest, next)) break;
      const double next_score = min_pair_distance(mesh, next);
      if (next == current || next_score <= score) break;
      current = next;
      score = next_score;
    }
    bool seen = false;
    for (const auto& candidate : candidates) seen = seen || candidate.second == current;
    if (!seen) candidates.push_back({score, current});
  }
  if (candidates.empty())
    throw Error("mesh '" + mesh.source_name() + "': cannot find 8 distinct cuboid corners");
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Corners> out;
  for (const auto& candidate : candidates) out.push_back(candidate.second);
  return out;
}

// Traces the 12 poly-edges with the loops around the ends of `long_axis`; false on failure
// (reason in *why).
bool trace_layout(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length,
                  const std::vector<double>& band_length, int long_axis,
                  const std::array<std::vector<int>, num_cube_edges>& fixed, CuboidLayout& layout,
                  std::string* why) {
  const int n = mesh.num_vertices();
  const double length_bound = straight_line_bound(mesh, length);
  const double band_bound = &band_length == &length ? length_bound : straight_line_bound(mesh, band_length);
  std::vector<char> blocked(n, 0);
  for (int c : layout.corners) blocked[c] = 1;
  for (const auto& path : fixed)
    for (int v : path) blocked[v] = 1;
  std::vector<char> on_loop(n, 0);
  std::vector<char> cut_edge(mesh.num_edges(), 0);
  for (int side = 0; side < 2; ++side) {
    const auto loop = cube_face_corners(2 * long_axis + side);
    for (int i = 0; i < 4; ++i) {
      const int ca = loop[i], cb = loop[(i + 1) % 4];
      const int e = cube_edge_between(ca, cb);
      const auto ends = cube_edge_corners(e);
      std::vector<int> path = !fixed[e].empty() ? fixed[e]
                                                : guided_path(mesh, length, length_bound, layout.corners[ends[0]],
                                                              layout.corners[ends[1]], blocked, nullptr);
      if (path.empty()) {
        *why = "no free path for cuboid edge " + std::to_string(e);
        return false;
      }
      for (int v : path) blocked[v] = on_loop[v] = 1;
      mark_path_edges(mesh, path, cut_edge);
      layout.poly_edges[e] = std::move(path);
    }
  }
  std::vector<int> component;
  const int num_regions = face_components(mesh, cut_edge, component);
  if (num_regions != 3) {
    *why = "the two end loops cut the surface into " + std::to_string(num_regions) +
           " regions instead of 3";
    return false;
  }
  // The annulus is the region touching both loops.
  std::vector<int> touches(3, 0);
  for (int side = 0; side < 2; ++side)
    for (int e : cube_face_edges(2 * long_axis + side)) {
      const auto& path = layout.poly_edges[e];
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const int edge = edge_between(mesh, path[i], path[i + 1]);
        const int h = mesh.edge_halfedge(edge);
        touches[component[mesh.halfedge_face(h)]] |= 1 << side;
        touches[component[mesh.halfedge_face(mesh.halfedge_twin(h))]] |= 1 << side;
      }
    }
  int annulus = -1;
  for (int r = 0; r < 3; ++r)
    if (touches[r] == 3) annulus = r;
  if (annulus < 0) {
    *why = "no band between the end loops";
    return false;
  }
  for (int v = 0; v < n; ++v) {
    if (on_loop[v]) continue;
    const int h = mesh.vertex_halfedge(v);
    if (h == mesh::no_id || component[mesh.halfedge_face(h)] != annulus) blocked[v] = 1;
  }
  auto in_annulus = [&](int h) {
    const int f = mesh.halfedge_face(h);
    const int g = mesh.halfedge_face(mesh.halfedge_twin(h));
    return component[f] == annulus || component[g] == annulus;
  };
  for (int k = 0; k < 4; ++k) {
    const int e = 4 * long_axis + k;
    const auto ends = cube_edge_corners(e);
    std::vector<int> path = !fixed[e].empty() ? fixed[e]
                                              : guided_path(mesh, band_length, band_bound, layout.corners[ends[0]],
                                                            layout.corners[ends[1]], blocked, in_annulus);
    if (path.empty()) {
      *why = "no free path across the band for cuboid edge " + std::to_string(e);
      return false;
    }
    for (int v : path) blocked[v] = 1;
    mark_path_edges(mesh, path, cut_edge);
    layout.poly_edges[e] = std::move(path);
  }
  // Validation: 6 disks, each bounded by the 4 poly-edges of one cube face.
  if (face_components(mesh, cut_edge, component) != num_cube_faces) {
    *why = "the poly-edges do not cut the surface into 6 regions";
    return false;
  }
  std::vector<std::set<int>> bounding(num_cube_faces);
  for (int e = 0; e < num_cube_edges; ++e) {
    const auto& path = layout.poly_edges[e];
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const int h = mesh.edge_halfedge(edge_between(mesh, path[i], path[i + 1]));
      bounding[component[mesh.halfedge_face(h)]].insert(e);
      bounding[component[mesh.halfedge_face(mesh.halfedge_twin(h))]].insert(e);
    }
  }
  std::vector<int> region_face(num_cube_faces, -1);
  std::vector<char> face_used(num_cube_faces, 0);
  for (int r = 0; r < num_cube_faces; ++r) {
    for (int f = 0; f < num_cube_faces; ++f) {
      const auto edges = cube_face_edges(f);
      if (bounding[r] == std::set<int>(edges.begin(), edges.end()) && !face_used[f]) {
        region_face[r] = f;
        face_used[f] = 1;
        break;
      }
    }
    if (region_face[r] < 0) {
      *why = "a region is not bounded by the 4 poly-edges of one cuboid face (twisted layout)";
      return false;
    }
  }
  // Orientation: along every poly-edge, from its first corner to its second, the cube face on
  // the left (outward normal) must be the region left of the path on the outward-oriented
  // surface. Extremal corners of a non-convex shape can give a mirrored layout that passes every
  // test above and whose every face map flips.
  for (int e = 0; e < num_cube_edges; ++e) {
    const auto ends = cube_edge_corners(e);
    const Eigen::Vector3d d = corner_offset(ends[1]) - corner_offset(ends[0]);
    const auto& path = layout.poly_edges[e];
    int h = mesh.edge_halfedge(edge_between(mesh, path[0], path[1]));
    if (mesh.halfedge_source(h) != path[0]) h = mesh.halfedge_twin(h);
    const int left = region_face[component[mesh.halfedge_face(h)]];
    const Eigen::Vector3d normal = (left % 2 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(left / 2);
    const Eigen::Vector3d centre = 0.5 * Eigen::Vector3d::Ones() + 0.5 * normal;
    if (normal.cross(d).dot(centre - corner_offset(ends[0])) <= 0.0) {
      *why = "the layout is mirrored against the surface's orientation";
      return false;
    }
  }
  layout.face_region.resize(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) layout.face_region[f] = region_face[component[f]];
  return true;
}

// Traces the poly-edges for the given corners, trying the band along each cube axis (longest
// first); false with the reasons if none works.
// progress: "cuboid layout" with the fraction of band axes tried.
bool layout_with_corners(const mesh::HalfedgeMesh& mesh, CuboidLayout& layout, std::string* why,
                         const Progress& progress) {
  const Eigen::Vector3d lo = mesh.positions().colwise().minCoeff();
  const Eigen::Vector3d hi = mesh.positions().colwise().maxCoeff();
  const double diagonal = (hi - lo).norm();
  layout.min_corner_distance_rel = diagonal > 0.0 ? min_pair_distance(mesh, layout.corners) / diagonal : 0.0;
  std::array<double, 3> axis_length{};
  for (int e = 0; e < num_cube_edges; ++e) {
    const auto ends = cube_edge_corners(e);
    axis_length[e / 4] += (mesh.vertex_position(layout.corners[ends[0]]) -
                           mesh.vertex_position(layout.corners[ends[1]])).norm();
  }
  std::array<int, 3> order = {0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return axis_length[a] > axis_length[b]; });
  const std::vector<double> length = mesh::edge_lengths(mesh);
  std::string reasons;
  for (int k = 0; k < 3; ++k) {
    progress.report("cuboid layout", k / 3.0);
    const int axis = order[k];
    CuboidLayout attempt = layout;
    std::string reason;
    if (trace_layout(mesh, length, length, axis, {}, attempt, &reason)) {
      layout = std::move(attempt);
      return true;
    }
    reasons += (reasons.empty() ? "" : "; ") + std::string("band along axis ") +
               std::to_string(axis) + ": " + reason;
  }
  *why = reasons;
  return false;
}

}  // namespace

bool complete_cuboid_layout(const mesh::HalfedgeMesh& mesh, int band_axis,
                            const std::array<std::vector<int>, num_cube_edges>& fixed, CuboidLayout& layout,
                            std::string* why, const std::vector<double>* band_cost) {
  const std::vector<double> length = mesh::edge_lengths(mesh);
  std::string reason;
  if (trace_layout(mesh, length, band_cost ? *band_cost : length, band_axis, fixed, layout, &reason)) return true;
  if (why) *why = reason;
  return false;
}

std::vector<CuboidLayout> candidate_cuboid_layouts(const mesh::HalfedgeMesh& mesh, int max_layouts,
                                                   const Progress& progress) {
  assert(max_layouts >= 1);
  const std::string name = "mesh '" + mesh.source_name() + "'";
  // The fraction of [lo, hi] that a step reports, as a fraction of the whole layout.
  const auto share = [&progress](double lo, double hi) {
    return Progress([&progress, lo, hi](const std::string& stage, double fraction) {
      progress.report(stage, lo + (hi - lo) * fraction);
      return true;
    });
  };
  // Extremal corners first; the box-corner choice is the fallback when their paths cannot be
  // laid out (e.g. corners on long limbs). The first try has most of the bar: it usually works.
  // The corner sets of the other frames follow, best first, up to kCornerCandidates: which
  // set lays out depends on the pose (a limb may block the first set's band in one rotation).
  std::vector<CuboidLayout> out;
  std::string reasons;
  for (bool nearest : {false, true}) {
    const double lo = nearest ? 0.9 : 0.0, hi = nearest ? 1.0 : 0.9;
    const std::vector<Corners> candidates = automatic_corners(mesh, nearest, share(lo, lo + 0.6 * (hi - lo)));
    const int tries = std::min(static_cast<int>(candidates.size()), kCornerCandidates);
    const double from = lo + 0.6 * (hi - lo), step = 0.4 * (hi - lo) / tries;
    for (int k = 0; k < tries; ++k) {
      CuboidLayout layout;
      layout.corners = candidates[k];
      bool seen = false;
      for (const CuboidLayout& other : out) seen = seen || other.corners == layout.corners;
      if (seen) continue;
      std::string why;
      if (layout_with_corners(mesh, layout, &why, share(from + k * step, from + (k + 1) * step))) {
        out.push_back(std::move(layout));
        if (static_cast<int>(out.size()) == max_layouts) {
          progress.report("cuboid layout", 1.0);
          return out;
        }
      } else if (k == 0) {
        reasons += (reasons.empty() ? "" : "; ") + why;
      }
    }
  }
  if (out.empty())
    throw Error(name + ": cannot lay out a cuboid: " + reasons + " (try other corners: `corners`)");
  progress.report("cuboid layout", 1.0);
  return out;
}

CuboidLayout compute_cuboid_layout(const mesh::HalfedgeMesh& mesh,
                                   const CuboidLayoutOptions& options, const Progress& progress) {
  const std::string name = "mesh '" + mesh.source_name() + "'";
  if (options.corners.empty()) {
    std::vector<CuboidLayout> layouts = candidate_cuboid_layouts(mesh, 1, progress);
    return std::move(layouts.front());
  }
  CuboidLayout layout;
  if (options.corners.size() != num_cube_corners)
    throw Error(name + ": expected 8 corner vertex ids, got " + std::to_string(options.corners.size()));
  std::set<int> seen;
  for (int c = 0; c < num_cube_corners; ++c) {
    const int v = options.corners[c];
    if (v < 0 || v >= mesh.num_vertices() || mesh.vertex_halfedge(v) == mesh::no_id)
      throw Error(name + ": corner " + std::to_string(c) + " is vertex " + std::to_string(v) +
                  ", not a vertex of the mesh");
    if (!seen.insert(v).second)
      throw Error(name + ": corner vertex " + std::to_string(v) + " is listed twice");
    layout.corners[c] = v;
  }
  const Eigen::Vector3d p0 = mesh.vertex_position(layout.corners[0]);
  Eigen::Matrix3d m;
  m << mesh.vertex_position(layout.corners[1]) - p0, mesh.vertex_position(layout.corners[2]) - p0,
      mesh.vertex_position(layout.corners[4]) - p0;
  if (m.determinant() <= 0.0)
    throw Error(name + ": corners are in mirrored (left-handed) order; corner c must sit at "
                "(c&1, c>>1&1, c>>2&1) of a right-handed box");
  std::string why;
  if (!layout_with_corners(mesh, layout, &why, progress))
    throw Error(name + ": cannot lay out a cuboid: " + why + " (try other corners: `corners`)");
  progress.report("cuboid layout", 1.0);
  return layout;
}

}  // namespace volspline::polycube
