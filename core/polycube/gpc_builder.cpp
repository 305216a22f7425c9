// SPDX-License-Identifier: MIT
#include "core/polycube/gpc_builder.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>

#include "core/common/error.h"
#include "core/mesh/graph_distance.h"
#include "core/mesh/mesh_geometry.h"
#include "core/mesh/mesh_lists.h"
#include "core/mesh/mesh_report.h"
#include "core/polycube/cap_corners.h"
#include "core/polycube/cylinder_map.h"
#include "core/polycube/t_shape_layout.h"

namespace volspline::polycube {

namespace {

// choose_loop_corners: the start shifts tried, over one quarter of the loop.
constexpr int kCornerShifts = 8;
// ... and the share of the best shift's least corner angle below which the farthest-vertex start
// gives way to it.
constexpr double kCornerAngleShare = 0.5;

// One piece cut out of the decomposition mesh; a loop whose both sides belong to the piece has
// its vertices twice, once per side.
struct PieceMesh {
  mesh::TriangleMesh mesh;
  std::vector<int> surface_vertex;
  std::vector<int> surface_face;
  std::vector<std::vector<int>> boundary;  // per SolidPiece::boundary entry: vertex per loop vertex
};

PieceMesh extract_piece(const SolidDecomposition& d, const SolidPiece& piece) {
  PieceMesh out;
  const int n = d.mesh.num_vertices();
  std::vector<int> loop_of(n, -1);
  for (std::size_t l = 0; l < d.loops.size(); ++l)
    for (int v : d.loops[l].vertices) loop_of[v] = static_cast<int>(l);
  std::vector<int> sides_in_piece(d.loops.size(), 0);
  for (const LoopSide& b : piece.boundary) sides_in_piece[b.loop] |= 1 << b.side;
  // A loop with both sides in the piece: the side of each face around its vertices, by turning
  // around each loop vertex from the face left (0, below) or right (1) of a loop edge without
  // crossing one. Topological, so it holds for loops that are not level sets (tighten_cut_loops).
  std::map<int, int> face_side;
  {
    std::map<std::pair<int, int>, int> directed;  // (a, b) → the piece's face with halfedge a → b
    for (int f : piece.faces)
      for (int k = 0; k < 3; ++k) directed[{d.mesh.triangles(f, k), d.mesh.triangles(f, (k + 1) % 3)}] = f;
    for (std::size_t l = 0; l < d.loops.size(); ++l) {
      if (sides_in_piece[l] != 3) continue;
      const std::vector<int>& lv = d.loops[l].vertices;
      std::set<std::pair<int, int>> seam;
      std::vector<std::pair<int, int>> stack;
      for (std::size_t i = 0; i < lv.size(); ++i) {
        const int a = lv[i], b = lv[(i + 1) % lv.size()];
        seam.insert({std::min(a, b), std::max(a, b)});
        for (const auto& [e, side] : {std::make_pair(std::make_pair(a, b), 0), std::make_pair(std::make_pair(b, a), 1)}) {
          const auto it = directed.find(e);
          if (it != directed.end() && face_side.emplace(it->second, side).second) stack.push_back({it->second, side});
        }
      }
      while (!stack.empty()) {
        const auto [f, side] = stack.back();
        stack.pop_back();
        for (int k = 0; k < 3; ++k) {
          const int x = d.mesh.triangles(f, k), y = d.mesh.triangles(f, (k + 1) % 3);
          if (loop_of[x] != static_cast<int>(l) && loop_of[y] != static_cast<int>(l)) continue;
          if (seam.count({std::min(x, y), std::max(x, y)})) continue;
          const auto it = directed.find({y, x});
          if (it != directed.end() && face_side.emplace(it->second, side).second) stack.push_back({it->second, side});
        }
      }
    }
  }
  std::map<std::pair<int, int>, int> key_id;
  auto key_of = [&](int v, int f) {
    const int l = loop_of[v];
    if (l < 0 || sides_in_piece[l] != 3) return std::make_pair(v, -1);
    const auto it = face_side.find(f);
    assert(it != face_side.end());
    return std::make_pair(v, it->second);
  };
  std::vector<std::array<int, 3>> tris;
  for (int f : piece.faces) {
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) {
      const auto key = key_of(d.mesh.triangles(f, k), f);
      auto it = key_id.find(key);
      if (it == key_id.end()) {
        it = key_id.emplace(key, static_cast<int>(out.surface_vertex.size())).first;
        out.surface_vertex.push_back(key.first);
      }
      t[k] = it->second;
    }
    tris.push_back(t);
    out.surface_face.push_back(f);
  }
  out.mesh.positions.resize(static_cast<int>(out.surface_vertex.size()), 3);
  for (std::size_t v = 0; v < out.surface_vertex.size(); ++v)
    out.mesh.positions.row(static_cast<int>(v)) = d.mesh.positions.row(out.surface_vertex[v]);
  out.mesh.triangles = mesh::triangles_from(tris);
  for (const LoopSide& b : piece.boundary) {
    std::vector<int> ids;
    for (int v : d.loops[b.loop].vertices) {
      const int side = sides_in_piece[b.loop] == 3 ? b.side : -1;
      const auto it = key_id.find({v, side});
      ids.push_back(it == key_id.end() ? -1 : it->second);
    }
    out.boundary.push_back(std::move(ids));
  }
  return out;
}

// The piece closed by its interface discs: a sphere for a cap or a tube.
CuboidSurface close_piece(const PieceMesh& piece, const SolidPiece& sp, const std::vector<InterfaceDisc>& discs) {
  CuboidSurface s;
  std::vector<Eigen::Vector3d> positions;
  for (int v = 0; v < piece.mesh.num_vertices(); ++v) positions.push_back(piece.mesh.positions.row(v).transpose());
  s.surface_vertex = piece.surface_vertex;
  s.surface_face = piece.surface_face;
  std::vector<std::array<int, 3>> tris;
  for (int t = 0; t < piece.mesh.num_faces(); ++t)
    tris.push_back({piece.mesh.triangles(t, 0), piece.mesh.triangles(t, 1), piece.mesh.triangles(t, 2)});
  for (std::size_t b = 0; b < sp.boundary.size(); ++b) {
    const InterfaceDisc& disc = discs[sp.boundary[b].loop];
    std::vector<int> id(disc.positions.rows());
    for (int v = 0; v < disc.positions.rows(); ++v) {
      if (v < disc.num_loop_vertices) {
        id[v] = piece.boundary[b][v];
      } else {
        id[v] = static_cast<int>(positions.size());
        positions.push_back(disc.positions.row(v).transpose());
        s.surface_vertex.push_back(-1);
      }
    }
    for (int t = 0; t < disc.triangles.rows(); ++t) {
      std::array<int, 3> tri = {id[disc.triangles(t, 0)], id[disc.triangles(t, 1)], id[disc.triangles(t, 2)]};
      if (sp.boundary[b].side == 0) std::swap(tri[1], tri[2]);
      tris.push_back(tri);
      s.surface_face.push_back(-1);
    }
  }
  s.mesh.positions = mesh::positions_from(positions);
  s.mesh.triangles = mesh::triangles_from(tris);
  return s;
}

double path_length(const mesh::TriangleMesh& m, const std::vector<int>& path) {
  double total = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i)
    total += (m.positions.row(path[i]) - m.positions.row(path[i - 1])).norm();
  return total;
}

// 4 corners of a loop at quarter arc lengths (§3.3.2: every interface loop gets 4 corners shared
// by both sides), starting at the loop's vertex farthest from its centroid. Starting there puts an
// elongated loop's corners at its two ends and the middles of its long sides, where the loop runs
// straight on: a face corner of almost 180° on one side of the cut and a squeezed face on the
// other, which neither the hexes nor the spline's cells there can follow. So the start is
// also shifted by each of kCornerShifts steps of an eighth of a quarter, and the shift whose 4
// corners make the most rectangular quadrilateral (the largest least angle between the chords to
// the neighbouring corners; the first on a tie) is taken where the farthest-vertex start reaches
// under kCornerAngleShare of its least angle.
std::array<int, 4> choose_loop_corners(const mesh::TriangleMesh& m, const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  for (int v : loop) centre += m.positions.row(v);
  centre /= n;
  int start = 0;
  double far = -1.0;
  for (int i = 0; i < n; ++i) {
    const double r = (m.positions.row(loop[i]) - centre).squaredNorm();
    if (r > far) {
      far = r;
      start = i;
    }
  }
  std::vector<double> arc(n + 1, 0.0);
  for (int i = 1; i <= n; ++i)
    arc[i] = arc[i - 1] + (m.positions.row(loop[(start + i) % n]) - m.positions.row(loop[(start + i - 1) % n])).norm();
  // Corners (indices into the loop from `start`) at offset + k quarters, each the nearest vertex
  // after the previous corner.
  auto corners_at = [&](double offset) {
    std::array<int, 4> out{};
    int previous = -1;
    for (int k = 0; k < 4; ++k) {
      const double target = offset + arc[n] * k / 4.0;
      int best = previous + 1;
      for (int i = previous + 1; i < n - (3 - k); ++i)
        if (std::abs(arc[i] - target) < std::abs(arc[best] - target)) best = i;
      previous = best;
      out[k] = best;
    }
    return out;
  };
  auto least_angle = [&](const std::array<int, 4>& c) {
    double least = 1.0e30;
    for (int k = 0; k < 4; ++k) {
      const Eigen::RowVector3d p = m.positions.row(loop[(start + c[k]) % n]);
      const Eigen::RowVector3d a = m.positions.row(loop[(start + c[(k + 3) % 4]) % n]) - p;
      const Eigen::RowVector3d b = m.positions.row(loop[(start + c[(k + 1) % 4]) % n]) - p;
      const double denominator = a.norm() * b.norm();
      least = std::min(least, denominator > 0.0 ? std::acos(std::clamp(a.dot(b) / denominator, -1.0, 1.0)) : 0.0);
    }
    return least;
  };
  const std::array<int, 4> farthest = corners_at(0.0);
  std::array<int, 4> best = farthest;
  double best_angle = least_angle(farthest);
  for (int j = 1; j < kCornerShifts; ++j) {
    const std::array<int, 4> c = corners_at(arc[n] / 4.0 * j / kCornerShifts);
    const double angle = least_angle(c);
    if (angle > best_angle + 1e-9) best_angle = angle, best = c;
  }
  // The shift only where the farthest-vertex start is far from the best (under half its least
  // angle): elsewhere both are fair and a loop keeps the corners it had without the shifts.
  if (!(least_angle(farthest) < kCornerAngleShare * best_angle)) best = farthest;
  std::array<int, 4> corners;
  for (int k = 0; k < 4; ++k) corners[k] = (start + best[k]) % n;
  return corners;
}

// Corners and prescribed poly-edges of one cube face lying on a cut loop. `order` lists the 4
// loop corners (indices into the loop's corner array) in the face's corner order `cube`.
// `forward`: the face's corner order runs in loop order.
void set_loop_face(const std::vector<int>& loop_vertex_ids, const std::array<int, 4>& loop_corner_index,
                   const std::array<int, 4>& order, bool forward, const std::array<int, 4>& cube,
                   CuboidLayout& layout, std::array<std::vector<int>, num_cube_edges>& fixed) {
  const int n = static_cast<int>(loop_vertex_ids.size());
  for (int i = 0; i < 4; ++i) layout.corners[cube[i]] = loop_vertex_ids[loop_corner_index[order[i]]];
  for (int i = 0; i < 4; ++i) {
    const int from = loop_corner_index[order[i]], to = loop_corner_index[order[(i + 1) % 4]];
    std::vector<int> path;
    for (int j = from;; j = forward ? (j + 1) % n : (j + n - 1) % n) {
      path.push_back(loop_vertex_ids[j]);
      if (j == to) break;
    }
    const int e = cube_edge_between(cube[i], cube[(i + 1) % 4]);
    if (cube_edge_corners(e)[0] != cube[i]) std::reverse(path.begin(), path.end());
    fixed[e] = std::move(path);
  }
}

struct FaceOnLoop {
  int cuboid = -1;
  int face = -1;
  std::array<int, 4> cube{};  // cube corner id of loop corner k
};

struct Glue {
  int cuboid_a = -1, face_a = -1, cuboid_b = -1, face_b = -1, cut = -1;
};

// A cuboid's closed surface from some faces of a piece and closing discs (vertex cycles of the
// piece), with its corners and poly-edges given on the piece: all 12 prescribed.
CuboidSurface assemble_cuboid(const PieceMesh& pm, const TShapeCuboid& c, const std::string& part) {
  CuboidSurface s;
  std::vector<int> id(pm.mesh.num_vertices(), -1);
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<int, 3>> tris;
  auto vertex = [&](int v) {
    if (id[v] < 0) {
      id[v] = static_cast<int>(positions.size());
      positions.push_back(pm.mesh.positions.row(v).transpose());
      s.surface_vertex.push_back(pm.surface_vertex[v]);
    }
    return id[v];
  };
  for (int f : c.faces) {
    tris.push_back({vertex(pm.mesh.triangles(f, 0)), vertex(pm.mesh.triangles(f, 1)), vertex(pm.mesh.triangles(f, 2))});
    s.surface_face.push_back(pm.surface_face[f]);
  }
  for (const std::vector<int>& cycle : c.discs) {
    mesh::Positions xyz(static_cast<int>(cycle.size()), 3);
    for (std::size_t i = 0; i < cycle.size(); ++i) xyz.row(static_cast<int>(i)) = pm.mesh.positions.row(cycle[i]);
    const InterfaceDisc disc = triangulate_interface_disc(xyz);
    std::vector<int> did(disc.positions.rows());
    for (int v = 0; v < disc.positions.rows(); ++v) {
      if (v < disc.num_loop_vertices) {
        did[v] = vertex(cycle[v]);
      } else {
        did[v] = static_cast<int>(positions.size());
        positions.push_back(disc.positions.row(v).transpose());
        s.surface_vertex.push_back(-1);
      }
    }
    for (int t = 0; t < disc.triangles.rows(); ++t) {
      tris.push_back({did[disc.triangles(t, 0)], did[disc.triangles(t, 1)], did[disc.triangles(t, 2)]});
      s.surface_face.push_back(-1);
    }
  }
  s.mesh.positions = mesh::positions_from(positions);
  s.mesh.triangles = mesh::triangles_from(tris);
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(s.mesh, "gpc " + part);
  const mesh::MeshReport report = mesh::analyze_mesh(hm);
  if (!report.closed || report.genus != 0 || !report.consistently_oriented)
    throw DecompositionError("T-to-cube: " + part + " closed by its discs is not a sphere");
  std::array<std::vector<int>, num_cube_edges> fixed;
  for (int k = 0; k < num_cube_corners; ++k) s.layout.corners[k] = id[c.corners[k]];
  for (int e = 0; e < num_cube_edges; ++e)
    for (int v : c.poly_edges[e]) fixed[e].push_back(vertex(v));
  std::string why;
  if (!complete_cuboid_layout(hm, 2, fixed, s.layout, &why))
    throw DecompositionError("T-to-cube: " + part + ": " + why);
  return s;
}

void build_t_shape(SolidDecomposition& d, const SolidPiece& sp, PieceMesh& pm, int piece,
                   GpcConstruction& out, std::vector<std::array<FaceOnLoop, 2>>& on_loop, std::vector<Glue>& glues,
                   const TShapeLayoutOptions& t_shape) {
  const std::string part = "piece " + std::to_string(piece) + " (T-shape)";
  std::array<std::vector<int>, 3> loops;
  std::array<bool, 3> forward;
  std::array<std::array<int, 4>, 3> corners;
  for (int k = 0; k < 3; ++k) {
    loops[k] = pm.boundary[k];
    forward[k] = sp.boundary[k].side == 0;
    corners[k] = out.loop_corners[sp.boundary[k].loop];
  }
  const int n0 = pm.mesh.num_vertices(), m0 = pm.mesh.num_faces();
  std::vector<int> origin(m0);
  std::iota(origin.begin(), origin.end(), 0);
  std::vector<double> value(n0);
  for (int v = 0; v < n0; ++v) value[v] = d.value[pm.surface_vertex[v]];
  TShapeLayout t;
  std::string why;
  if (!lay_out_t_shape(pm.mesh, origin, value, loops, forward, corners, pm.surface_vertex, t, &why, t_shape))
    throw DecompositionError("T-to-cube: " + part + ": " + why);
  // The layout's cuts refine the decomposition mesh inside this piece: new vertices and the
  // extra parts of split faces are appended; a split face keeps its id for its first part.
  const int dn = d.mesh.num_vertices();
  const int n1 = pm.mesh.num_vertices();
  d.mesh.positions.conservativeResize(dn + (n1 - n0), 3);
  for (int v = n0; v < n1; ++v) {
    pm.surface_vertex.push_back(dn + (v - n0));
    d.mesh.positions.row(dn + (v - n0)) = pm.mesh.positions.row(v);
    d.value.push_back(value[v]);
  }
  std::vector<char> reused(m0, 0);
  std::vector<int> surface_face(pm.mesh.num_faces());
  std::vector<std::array<int, 3>> appended;
  SolidPiece& dp = d.pieces[piece];
  for (int f = 0; f < pm.mesh.num_faces(); ++f) {
    const int o = origin[f];
    int id = pm.surface_face[o];
    if (reused[o]) {
      id = d.mesh.num_faces() + static_cast<int>(appended.size());
      appended.push_back({});
      d.parent_face.push_back(d.parent_face[pm.surface_face[o]]);
      dp.faces.push_back(id);
    }
    reused[o] = 1;
    surface_face[f] = id;
  }
  const int dm = d.mesh.num_faces();
  d.mesh.triangles.conservativeResize(dm + static_cast<int>(appended.size()), 3);
  for (int f = 0; f < pm.mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) d.mesh.triangles(surface_face[f], k) = pm.surface_vertex[pm.mesh.triangles(f, k)];
  pm.surface_face = std::move(surface_face);
  const int first = static_cast<int>(out.domain.cuboids.size());
  for (int c = 0; c < 4; ++c) {
    // Assemble first: a piece mesh vertex id is not a sphere id.
    CuboidSurface s = assemble_cuboid(pm, t.cuboids[c], part + " cuboid " + std::to_string(c));
    GpcCuboid cuboid;
    cuboid.piece = piece;
    cuboid.piece_kind = static_cast<int>(PieceKind::TShape);
    out.domain.cuboids.push_back(cuboid);
    out.surfaces.push_back(std::move(s));
    for (int f = 0; f < 6; ++f) {
      const int role = t.cuboids[c].face_role[f];
      if (role >= 0 && role < 3) on_loop[sp.boundary[role].loop][sp.boundary[role].side] = FaceOnLoop{first + c, f, {}};
    }
  }
  glues.push_back(Glue{first, 0, first + 1, 5, -1});
  glues.push_back(Glue{first, 1, first + 2, 5, -1});
  glues.push_back(Glue{first, 4, first + 3, 5, -1});
  for (int e = 0; e < 2; ++e) {
    GpcIllPoint ill;
    ill.cuboids = {first, first + 1 + e, first + 3};
    for (int k = 0; k < 2; ++k) ill.xyz[k] = pm.mesh.positions.row(t.concave_edges[e][k]).transpose();
    out.domain.ill_points.push_back(ill);
  }
}


// A rotation of the cube as a corner permutation: corner c goes to rotated[c].
using CornerMap = std::array<int, num_cube_corners>;

CornerMap corner_map(const Eigen::Matrix3i& r) {
  CornerMap out{};
  for (int c = 0; c < num_cube_corners; ++c) {
    const Eigen::Vector3i x(2 * (c & 1) - 1, 2 * (c >> 1 & 1) - 1, 2 * (c >> 2 & 1) - 1);
    const Eigen::Vector3i y = r * x;
    out[c] = (y(0) > 0) | (y(1) > 0) << 1 | (y(2) > 0) << 2;
  }
  return out;
}

int mapped_face(const CornerMap& m, int face) {
  const auto corners = cube_face_corners(face);
  for (int f = 0; f < num_cube_faces; ++f) {
    const auto g = cube_face_corners(f);
    int hits = 0;
    for (int a : corners)
      for (int b : g) hits += m[a] == b;
    if (hits == 4) return f;
  }
  return -1;
}

// The same layout in the frame rotated by m (corner c becomes corner m[c]).
CuboidLayout rotated_layout(const CuboidLayout& in, const CornerMap& m) {
  CuboidLayout out = in;
  for (int c = 0; c < num_cube_corners; ++c) out.corners[m[c]] = in.corners[c];
  for (int e = 0; e < num_cube_edges; ++e) {
    const auto ends = cube_edge_corners(e);
    const int f = cube_edge_between(m[ends[0]], m[ends[1]]);
    std::vector<int> path = in.poly_edges[e];
    if (cube_edge_corners(f)[0] != m[ends[0]]) std::reverse(path.begin(), path.end());
    out.poly_edges[f] = std::move(path);
  }
  for (int& r : out.face_region) r = mapped_face(m, r);
  return out;
}

// Merges cuboid b into cuboid a across glue `g` (a cut loop between an end face, 4 or 5, of
// each): the union is one cuboid running from a's far end face to b's. Returns false (nothing
// changed) when the glued faces are not end faces or the corners do not meet by a rotation.
bool merge_end_to_end(GpcConstruction& out, std::vector<Glue>& glues, std::size_t g_index) {
  const Glue g = glues[g_index];
  if (g.cuboid_a == g.cuboid_b || g.face_a < 4 || g.face_b < 4) return false;
  const int a = g.cuboid_a, b = g.cuboid_b;
  // Frames: a runs toward the cut (cut on its face 5), b away from it (cut on its face 4).
  const CornerMap identity = corner_map(Eigen::Matrix3i::Identity());
  Eigen::Matrix3i half_turn;  // about v: u → −u, w → −w
  half_turn << -1, 0, 0, 0, 1, 0, 0, 0, -1;
  const CornerMap map_a = g.face_a == 5 ? identity : corner_map(half_turn);
  CuboidSurface sa = out.surfaces[a], sb = out.surfaces[b];
  sa.layout = rotated_layout(sa.layout, map_a);
  // b: the turn that puts the cut on face 4, then the quarter turn about w that lines its
  // corners up with a's.
  const CornerMap flip_b = g.face_b == 4 ? identity : corner_map(half_turn);
  CornerMap map_b{};
  bool found = false;
  for (int q = 0; q < 4 && !found; ++q) {
    Eigen::Matrix3i quarter = Eigen::Matrix3i::Identity();
    for (int k = 0; k < q; ++k) {
      Eigen::Matrix3i turn;
      turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
      quarter = turn * quarter;
    }
    const CornerMap qm = corner_map(quarter);
    CornerMap m{};
    for (int c = 0; c < num_cube_corners; ++c) m[c] = qm[flip_b[c]];
    const CuboidLayout lb = rotated_layout(sb.layout, m);
    bool match = true;
    for (int k = 0; k < 4; ++k) {
      const int top_a = sa.surface_vertex[sa.layout.corners[k + 4]];
      const int bottom_b = sb.surface_vertex[lb.corners[k]];
      match = match && top_a >= 0 && top_a == bottom_b;
    }
    if (match) {
      map_b = m;
      sb.layout = lb;
      found = true;
    }
  }
  if (!found) return false;

  // The merged surface: a's and b's triangles but the cut's disc (the disc triangles that touch
  // the cut's corners), vertices of the decomposition mesh shared.
  CuboidSurface merged;
  std::map<std::pair<int, int>, int> id;  // (cuboid or −1 for a surface vertex, vertex) → merged id
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<int, 3>> tris;
  auto add_vertex = [&](const CuboidSurface& s, int which, int v) {
    const int sv = s.surface_vertex[v];
    const std::pair<int, int> key = sv >= 0 ? std::make_pair(-1, sv) : std::make_pair(which, v);
    auto it = id.find(key);
    if (it != id.end()) return it->second;
    const int n = static_cast<int>(positions.size());
    id.emplace(key, n);
    positions.push_back(s.mesh.positions.row(v).transpose());
    merged.surface_vertex.push_back(sv);
    return n;
  };
  auto cut_disc = [](const CuboidSurface& s, const std::array<int, 4>& corners) {
    // Disc faces connected (through disc faces) to a disc face at one of the corners.
    const int m = s.mesh.num_faces();
    std::vector<char> in(m, 0);
    std::vector<int> stack;
    for (int f = 0; f < m; ++f)
      if (s.surface_face[f] < 0)
        for (int k = 0; k < 3; ++k)
          if (std::find(corners.begin(), corners.end(), s.mesh.triangles(f, k)) != corners.end() && !in[f]) {
            in[f] = 1;
            stack.push_back(f);
          }
    std::map<std::pair<int, int>, std::vector<int>> edge_faces;
    for (int f = 0; f < m; ++f)
      if (s.surface_face[f] < 0)
        for (int k = 0; k < 3; ++k) {
          const int x = s.mesh.triangles(f, k), y = s.mesh.triangles(f, (k + 1) % 3);
          edge_faces[{std::min(x, y), std::max(x, y)}].push_back(f);
        }
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const int x = s.mesh.triangles(f, k), y = s.mesh.triangles(f, (k + 1) % 3);
        for (int h : edge_faces[{std::min(x, y), std::max(x, y)}])
          if (!in[h]) {
            in[h] = 1;
            stack.push_back(h);
          }
      }
    }
    return in;
  };
  const std::vector<char> drop_a =
      cut_disc(sa, {sa.layout.corners[4], sa.layout.corners[5], sa.layout.corners[6], sa.layout.corners[7]});
  const std::vector<char> drop_b =
      cut_disc(sb, {sb.layout.corners[0], sb.layout.corners[1], sb.layout.corners[2], sb.layout.corners[3]});
  for (int which = 0; which < 2; ++which) {
    const CuboidSurface& s = which == 0 ? sa : sb;
    const std::vector<char>& drop = which == 0 ? drop_a : drop_b;
    for (int f = 0; f < s.mesh.num_faces(); ++f) {
      if (drop[f]) continue;
      tris.push_back({add_vertex(s, which, s.mesh.triangles(f, 0)), add_vertex(s, which, s.mesh.triangles(f, 1)),
                      add_vertex(s, which, s.mesh.triangles(f, 2))});
      merged.surface_face.push_back(s.surface_face[f]);
    }
  }
  merged.mesh.positions = mesh::positions_from(positions);
  merged.mesh.triangles = mesh::triangles_from(tris);
  // The two may also touch along the surface: then the union is no sphere (or not even a
  // manifold) and they stay apart.
  std::optional<mesh::HalfedgeMesh> built;
  try {
    built.emplace(mesh::HalfedgeMesh::build(merged.mesh, "gpc merged cuboid"));
  } catch (const Error&) {
    return false;
  }
  const mesh::HalfedgeMesh& hm = *built;
  const mesh::MeshReport report = mesh::analyze_mesh(hm);
  if (!report.closed || report.genus != 0 || !report.consistently_oriented) return false;
  // Layout: a's bottom, b's top; the bands run through the cut's corners.
  auto in_merged = [&](const CuboidSurface& s, int which, const std::vector<int>& path) {
    std::vector<int> p;
    for (int v : path) p.push_back(add_vertex(s, which, v));
    return p;
  };
  std::array<std::vector<int>, num_cube_edges> fixed;
  for (int e = 0; e < num_cube_edges; ++e) {
    const auto ends = cube_edge_corners(e);
    if (ends[0] < 4 && ends[1] < 4) {
      fixed[e] = in_merged(sa, 0, sa.layout.poly_edges[e]);
    } else if (ends[0] >= 4 && ends[1] >= 4) {
      fixed[e] = in_merged(sb, 1, sb.layout.poly_edges[e]);
    } else {
      fixed[e] = in_merged(sa, 0, sa.layout.poly_edges[e]);
      const std::vector<int> rest = in_merged(sb, 1, sb.layout.poly_edges[e]);
      fixed[e].insert(fixed[e].end(), rest.begin() + 1, rest.end());
    }
  }
  if (static_cast<int>(positions.size()) != merged.mesh.num_vertices()) return false;  // a path left the surface
  for (int c = 0; c < 4; ++c) {
    merged.layout.corners[c] = add_vertex(sa, 0, sa.layout.corners[c]);
    merged.layout.corners[c + 4] = add_vertex(sb, 1, sb.layout.corners[c + 4]);
  }
  std::string why;
  if (!complete_cuboid_layout(hm, 2, fixed, merged.layout, &why)) return false;

  // The GPC graph: b's glues move to a with their faces in the merged frame; the cut's glue goes.
  out.surfaces[a] = std::move(merged);
  GpcCuboid& ca = out.domain.cuboids[a];
  ca.piece_kind = static_cast<int>(PieceKind::Tube);
  glues.erase(glues.begin() + static_cast<long>(g_index));
  for (Glue& x : glues) {
    for (int side = 0; side < 2; ++side) {
      int& c = side == 0 ? x.cuboid_a : x.cuboid_b;
      int& f = side == 0 ? x.face_a : x.face_b;
      if (c == a) {
        f = mapped_face(map_a, f);
      } else if (c == b) {
        c = a;
        f = mapped_face(map_b, f);
      }
      if (c > b) --c;
    }
  }
  out.surfaces.erase(out.surfaces.begin() + b);
  out.domain.cuboids.erase(out.domain.cuboids.begin() + b);
  for (GpcIllPoint& p : out.domain.ill_points)
    for (int& c : p.cuboids) c = c == b ? (a > b ? a - 1 : a) : (c > b ? c - 1 : c);
  return true;
}

}  // namespace

// A poly-edge that is not a shortest path (a T-shape's seam, two bands joined across a merged
// cut) may have a chord: an edge inside a face joining two of its vertices. Tutte's theorem
// (§3.4.1's surface map) needs no such edge, else the region between chord and poly-edge maps
// onto the straight side with zero area. Each chord is split at its midpoint, in the cuboid's
// surface and in the decomposition mesh alike (a split face keeps its id for its first part).
// A mesh without chords is left as it is.
void split_poly_edge_chords(SolidDecomposition& d, GpcConstruction& out) {
  std::vector<int> face_piece;
  for (CuboidSurface& s : out.surfaces) {
    const int n = s.mesh.num_vertices(), m = s.mesh.num_faces();
    std::vector<int> on_edge(n, 0);  // bit e: the vertex lies on poly-edge e
    std::set<std::pair<int, int>> path_edges;
    for (int e = 0; e < num_cube_edges; ++e) {
      const std::vector<int>& path = s.layout.poly_edges[e];
      for (std::size_t i = 0; i < path.size(); ++i) {
        on_edge[path[i]] |= 1 << e;
        if (i > 0) path_edges.insert({std::min(path[i - 1], path[i]), std::max(path[i - 1], path[i])});
      }
    }
    mesh::EdgeMidpoints midpoint;  // ids of `s.mesh`
    for (int f = 0; f < m; ++f) {
      if (s.surface_face[f] < 0) continue;  // a disc keeps the triangulation both sides share
      for (int k = 0; k < 3; ++k) {
        const int a = s.mesh.triangles(f, k), b = s.mesh.triangles(f, (k + 1) % 3);
        const std::pair<int, int> e{std::min(a, b), std::max(a, b)};
        if ((on_edge[a] & on_edge[b]) != 0 && !path_edges.count(e) && !midpoint.count(e))
          midpoint.emplace(e, n + static_cast<int>(midpoint.size()));
      }
    }
    if (midpoint.empty()) continue;
    if (face_piece.empty()) {
      face_piece.assign(d.mesh.num_faces(), -1);
      for (std::size_t p = 0; p < d.pieces.size(); ++p)
        for (int f : d.pieces[p].faces) face_piece[f] = static_cast<int>(p);
    }
    const int dn = d.mesh.num_vertices();
    const int added = static_cast<int>(midpoint.size());
    s.mesh.positions.conservativeResize(n + added, 3);
    d.mesh.positions.conservativeResize(dn + added, 3);
    s.surface_vertex.resize(n + added);
    d.value.resize(dn + added);
    for (const auto& [e, v] : midpoint) {
      const int da = s.surface_vertex[e.first], db = s.surface_vertex[e.second], dv = dn + (v - n);
      s.mesh.positions.row(v) = 0.5 * (s.mesh.positions.row(e.first) + s.mesh.positions.row(e.second));
      d.mesh.positions.row(dv) = 0.5 * (d.mesh.positions.row(da) + d.mesh.positions.row(db));
      d.value[dv] = 0.5 * (d.value[da] + d.value[db]);
      s.surface_vertex[v] = dv;
    }
    std::vector<std::array<int, 3>> tris(m), dtris;
    for (int f = 0; f < m; ++f) tris[f] = {s.mesh.triangles(f, 0), s.mesh.triangles(f, 1), s.mesh.triangles(f, 2)};
    const int dm = d.mesh.num_faces();
    auto to_d = [&](const std::array<int, 3>& t) {
      return std::array<int, 3>{s.surface_vertex[t[0]], s.surface_vertex[t[1]], s.surface_vertex[t[2]]};
    };
    for (int f = 0; f < m; ++f) {
      if (s.surface_face[f] < 0) continue;
      const std::vector<std::array<int, 3>> parts = mesh::split_at_midpoints(tris[f], midpoint, n);
      if (parts.size() == 1) continue;
      const int df = s.surface_face[f];
      tris[f] = parts[0];
      const std::array<int, 3> first = to_d(parts[0]);
      for (int k = 0; k < 3; ++k) d.mesh.triangles(df, k) = first[k];
      for (std::size_t i = 1; i < parts.size(); ++i) {
        const int id = dm + static_cast<int>(dtris.size());
        tris.push_back(parts[i]);
        s.surface_face.push_back(id);
        s.layout.face_region.push_back(s.layout.face_region[f]);
        dtris.push_back(to_d(parts[i]));
        d.parent_face.push_back(d.parent_face[df]);
        if (face_piece[df] >= 0) d.pieces[face_piece[df]].faces.push_back(id);
        face_piece.push_back(face_piece[df]);
      }
    }
    s.mesh.triangles = mesh::triangles_from(tris);
    d.mesh.triangles.conservativeResize(dm + static_cast<int>(dtris.size()), 3);
    for (std::size_t i = 0; i < dtris.size(); ++i)
      for (int k = 0; k < 3; ++k) d.mesh.triangles(dm + static_cast<int>(i), k) = dtris[i][k];
    s.halfedges.reset();
    d.halfedges.reset();
  }
}

GpcConstruction build_gpc(SolidDecomposition& d, double bbox_diagonal, const std::vector<int>& solid_corners,
                          bool merge_cuboids, const TShapeLayoutOptions& t_shape) {
  GpcConstruction out;
  const mesh::TriangleMesh& S = d.mesh;
  for (const CutLoop& loop : d.loops) {
    mesh::Positions xyz(static_cast<int>(loop.vertices.size()), 3);
    for (std::size_t i = 0; i < loop.vertices.size(); ++i) xyz.row(static_cast<int>(i)) = S.positions.row(loop.vertices[i]);
    out.discs.push_back(triangulate_interface_disc(xyz));
    std::array<int, 4> c = choose_loop_corners(S, loop.vertices);
    std::sort(c.begin(), c.end());
    out.loop_corners.push_back(c);
  }
  std::vector<std::array<FaceOnLoop, 2>> on_loop(d.loops.size());
  std::vector<Glue> glues;
  // The cube corner order of faces 4 (w = 0) and 5 (w = 1).
  const std::array<int, 4> bottom = {0, 1, 3, 2}, top = {4, 5, 7, 6};

  for (std::size_t p = 0; p < d.pieces.size(); ++p) {
    const SolidPiece& sp = d.pieces[p];
    const std::string part = "piece " + std::to_string(p);
    if (sp.kind == PieceKind::Solid) {
      CuboidSurface s;
      s.mesh = S;
      s.surface_vertex.resize(S.num_vertices());
      std::iota(s.surface_vertex.begin(), s.surface_vertex.end(), 0);
      s.surface_face.resize(S.num_faces());
      std::iota(s.surface_face.begin(), s.surface_face.end(), 0);
      assert(!d.halfedges || (d.halfedges->num_vertices() == S.num_vertices() && d.halfedges->num_faces() == S.num_faces()));
      s.halfedges = d.halfedges ? d.halfedges
                                : std::make_shared<const mesh::HalfedgeMesh>(mesh::HalfedgeMesh::build(s.mesh, "gpc " + part));
      CuboidLayoutOptions layout_options;
      layout_options.corners = solid_corners;
      s.layout = compute_cuboid_layout(*s.halfedges, layout_options);
      out.surfaces.push_back(std::move(s));
      GpcCuboid cuboid;
      cuboid.piece = static_cast<int>(p);
      cuboid.piece_kind = 0;
      out.domain.cuboids.push_back(cuboid);
      continue;
    }
    PieceMesh pm = extract_piece(d, sp);
    if (sp.kind == PieceKind::TShape) {
      build_t_shape(d, sp, pm, static_cast<int>(p), out, on_loop, glues, t_shape);
      continue;
    }
    CuboidSurface base = close_piece(pm, sp, out.discs);
    const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(base.mesh, "gpc " + part);
    const mesh::MeshReport report = mesh::analyze_mesh(hm);
    if (!report.closed || report.genus != 0 || !report.consistently_oriented)
      throw DecompositionError("T-to-cube: " + part + " closed by its interface discs is not a sphere (genus " +
                               std::to_string(report.genus) + ")");
    const int cuboid_id = static_cast<int>(out.domain.cuboids.size());
    // Face 4 (w = 0) on the first loop: corner order along the piece's own halfedges there,
    // which is loop order when the piece lies below the loop.
    const LoopSide a = sp.boundary[0];
    const std::array<int, 4>& ca = out.loop_corners[a.loop];
    const bool a_forward = a.side == 0;
    const std::array<int, 4> order_a = a_forward ? std::array<int, 4>{0, 1, 2, 3} : std::array<int, 4>{0, 3, 2, 1};
    std::string why;
    bool done = false;
    if (sp.kind == PieceKind::Tube) {
      // Band paths straight in the tube's cylinder map (§3.3.2 step 3): edge costs are lengths in
      // (u · height, v · circumference), so they follow the tube instead of hugging its inside.
      const mesh::HalfedgeMesh open = mesh::HalfedgeMesh::build(pm.mesh, "gpc " + part);
      const CylinderMap cyl = compute_cylinder_map(open, pm.boundary[0], pm.boundary[1]);
      std::vector<double> cost = mesh::edge_lengths(hm);
      for (int e = 0; e < hm.num_edges(); ++e) {
        const auto ends = hm.edge_vertices(e);
        if (ends[0] >= open.num_vertices() || ends[1] >= open.num_vertices()) continue;
        const double du = (cyl.u[ends[1]] - cyl.u[ends[0]]) * cyl.length;
        double dv = cyl.v[ends[1]] - cyl.v[ends[0]];
        dv -= std::round(dv);
        dv *= cyl.circumference;
        cost[e] = std::sqrt(du * du + dv * dv);
      }
      const LoopSide b = sp.boundary[1];
      const std::array<int, 4>& cb = out.loop_corners[b.loop];
      // Face 5 (w = 1): corner order against the piece's halfedges on the loop.
      const bool b_forward = b.side == 1;
      double best_length = std::numeric_limits<double>::infinity();
      CuboidLayout best;
      int best_shift = -1;
      for (int shift = 0; shift < 4; ++shift) {
        CuboidLayout layout;
        std::array<std::vector<int>, num_cube_edges> fixed;
        set_loop_face(pm.boundary[0], ca, order_a, a_forward, bottom, layout, fixed);
        std::array<int, 4> order_b;
        for (int i = 0; i < 4; ++i) order_b[i] = b_forward ? (shift + i) % 4 : (shift + 4 - i) % 4;
        set_loop_face(pm.boundary[1], cb, order_b, b_forward, top, layout, fixed);
        std::string reason;
        if (!complete_cuboid_layout(hm, 2, fixed, layout, &reason, &cost)) {
          why += (why.empty() ? "" : "; ") + reason;
          continue;
        }
        double length = 0.0;
        for (int e = 8; e < 12; ++e)
          for (std::size_t i = 0; i + 1 < layout.poly_edges[e].size(); ++i)
            for (int h : hm.vertex_outgoing(layout.poly_edges[e][i]))
              if (hm.halfedge_vertex(h) == layout.poly_edges[e][i + 1]) length += cost[hm.halfedge_edge(h)];
        if (length < best_length) {
          best_length = length;
          best = layout;
          best_shift = shift;
        }
      }
      if (best_shift >= 0) {
        base.layout = best;
        done = true;
        FaceOnLoop fa{cuboid_id, 4, {}}, fb{cuboid_id, 5, {}};
        for (int i = 0; i < 4; ++i) {
          fa.cube[order_a[i]] = bottom[i];
          const int k = b_forward ? (best_shift + i) % 4 : (best_shift + 4 - i) % 4;
          fb.cube[k] = top[i];
        }
        on_loop[a.loop][a.side] = fa;
        on_loop[b.loop][b.side] = fb;
      }
    } else {
      // Cap (§3.3.2, Algorithm 2): the 4 upper corners on the shortest paths from the loop's
      // corners to the vertex farthest from the loop (the pole), at a fraction lambda of the
      // pole's height: from cap_corner_level (the end face no longer than about its width, so
      // that its harmonic map does not crowd a limb's tip into a dot) down to halfway.
      const mesh::HalfedgeMesh open = mesh::HalfedgeMesh::build(pm.mesh, "gpc " + part);
      std::vector<int> sources;
      for (int v : pm.boundary[0]) sources.push_back(v);
      const mesh::GraphDistances height = mesh::graph_distances(open, sources);
      int pole = 0;
      for (int v = 0; v < open.num_vertices(); ++v)
        if (height.distance[v] > height.distance[pole]) pole = v;
      const mesh::GraphDistances from_pole = mesh::graph_distances(open, {pole});
      const double tip = cap_corner_level(pm.mesh, height.distance, height.distance[pole]);
      // Lower levels when a layout fails there, then the fallbacks.
      std::vector<double> lambdas;
      for (double lambda = tip; lambda > 0.5 + 1e-9; lambda -= 0.05) lambdas.push_back(lambda);
      for (double lambda : {0.5, 0.35, 0.65, 0.2}) lambdas.push_back(lambda);
      for (double lambda : lambdas) {
        CuboidLayout layout;
        std::array<std::vector<int>, num_cube_edges> fixed;
        set_loop_face(pm.boundary[0], ca, order_a, a_forward, bottom, layout, fixed);
        std::array<int, 4> upper;
        for (int i = 0; i < 4; ++i) {
          const int corner = layout.corners[bottom[i]];
          std::vector<int> path = mesh::graph_path(from_pole, corner);  // pole → corner
          upper[i] = pole;
          for (auto it = path.rbegin(); it != path.rend(); ++it)
            if (height.distance[*it] >= lambda * height.distance[pole]) {
              upper[i] = *it;
              break;
            }
        }
        auto distinct = [](std::array<int, 4> c) {
          std::sort(c.begin(), c.end());
          return std::adjacent_find(c.begin(), c.end()) == c.end();
        };
        // On a limb the paths to the pole merge long before its tip: the corners then go around
        // the level's front by the angle of the loop corners about the limb's axis.
        if (!distinct(upper) && lambda > 0.5) {
          std::array<Eigen::Vector3d, 4> below;
          for (int i = 0; i < 4; ++i) below[i] = pm.mesh.positions.row(layout.corners[bottom[i]]).transpose();
          upper = front_corners(pm.mesh, height.distance, lambda * height.distance[pole],
                                pm.mesh.positions.row(pole).transpose(), below);
        }
        if (!distinct(upper)) continue;
        for (int i = 0; i < 4; ++i) layout.corners[top[i]] = upper[i];
        std::string reason;
        if (complete_cuboid_layout(hm, 2, fixed, layout, &reason)) {
          base.layout = layout;
          done = true;
          FaceOnLoop fa{cuboid_id, 4, {}};
          for (int i = 0; i < 4; ++i) fa.cube[order_a[i]] = bottom[i];
          on_loop[a.loop][a.side] = fa;
          break;
        }
        why += (why.empty() ? "" : "; ") + reason;
      }
    }
    // A cap whose corners' paths to the pole merge at every level (no layout was even tried) is
    // not refinable: a midpoint subdivision keeps the graph's shortest paths nearly as they are,
    // so they merge again, on four times the faces.
    if (!done)
      throw DecompositionError("T-to-cube: cannot lay out the cuboid of " + part + ": " +
                                   (why.empty() ? "the corners' paths to the pole meet at every level" : why),
                               !(sp.kind == PieceKind::Cap && why.empty()));
    GpcCuboid cuboid;
    cuboid.piece = static_cast<int>(p);
    cuboid.piece_kind = static_cast<int>(sp.kind);
    out.domain.cuboids.push_back(cuboid);
    out.surfaces.push_back(std::move(base));
  }

  // Interfaces: one per cut loop (side 0 → side 1), then the faces inside T-shapes.
  for (std::size_t l = 0; l < d.loops.size(); ++l)
    glues.insert(glues.begin() + static_cast<long>(l),
                 Glue{on_loop[l][0].cuboid, on_loop[l][0].face, on_loop[l][1].cuboid, on_loop[l][1].face, static_cast<int>(l)});
  // Cuboids glued end to end across a cut (arms of T-shapes, tubes, caps) become one cuboid: the
  // thesis's GPC merges them too (Table 3.1: eight 6 cuboids from 2 T-shapes). Ill-points stay
  // where the T-shapes put them.
  if (merge_cuboids)
    for (bool merged = true; merged;) {
      merged = false;
      for (std::size_t k = 0; k < glues.size() && !merged; ++k)
        if (glues[k].cut >= 0) merged = merge_end_to_end(out, glues, k);
    }
  split_poly_edge_chords(d, out);
  std::vector<std::array<std::array<int, 4>, 2>> glue_corners;
  for (const Glue& gl : glues) {
    GpcInterface g;
    g.cuboid = {gl.cuboid_a, gl.cuboid_b};
    g.face = {gl.face_a, gl.face_b};
    g.cut = gl.cut;
    const int id = static_cast<int>(out.domain.interfaces.size());
    out.domain.cuboids[g.cuboid[0]].face_interface[g.face[0]] = id;
    out.domain.cuboids[g.cuboid[1]].face_interface[g.face[1]] = id;
    // Corner correspondence by the surface vertex both cuboids put there.
    std::array<std::array<int, 4>, 2> cc;
    const auto fa = cube_face_corners(g.face[0]), fb = cube_face_corners(g.face[1]);
    const CuboidSurface& sa = out.surfaces[g.cuboid[0]];
    const CuboidSurface& sb = out.surfaces[g.cuboid[1]];
    for (int i = 0; i < 4; ++i) {
      cc[0][i] = fa[i];
      cc[1][i] = -1;
      const int v = sa.surface_vertex[sa.layout.corners[fa[i]]];
      for (int q = 0; q < 4; ++q)
        if (sb.surface_vertex[sb.layout.corners[fb[q]]] == v) cc[1][i] = fb[q];
      if (cc[1][i] < 0 || v < 0)
        throw DecompositionError("GPC graph: the corners of glued faces of cuboids " + std::to_string(g.cuboid[0]) +
                                 " and " + std::to_string(g.cuboid[1]) + " do not match");
    }
    glue_corners.push_back(cc);
    out.domain.interfaces.push_back(g);
  }
  auto transitions = [&] {
    for (std::size_t l = 0; l < out.domain.interfaces.size(); ++l) {
      GpcInterface& g = out.domain.interfaces[l];
      if (!gpc_transition_from_corners(g.face[0], out.domain.cuboids[g.cuboid[0]].size, glue_corners[l][0],
                                       g.face[1], out.domain.cuboids[g.cuboid[1]].size, glue_corners[l][1],
                                       g.transition))
        throw DecompositionError("GPC graph: interface " + std::to_string(l) +
                                 " does not glue its two cuboids by a rotation");
    }
  };
  transitions();
  // Sizes: glued axes share one length.
  const int nc = static_cast<int>(out.domain.cuboids.size());
  std::vector<int> cls(3 * nc);
  std::iota(cls.begin(), cls.end(), 0);
  std::function<int(int)> root = [&](int x) { return cls[x] == x ? x : cls[x] = root(cls[x]); };
  for (const GpcInterface& g : out.domain.interfaces)
    for (int i = 0; i < 3; ++i)
      if (i != g.face[0] / 2) {
        const int x = root(3 * g.cuboid[0] + i), y = root(3 * g.cuboid[1] + g.transition.axis[i]);
        if (x != y) cls[std::max(x, y)] = std::min(x, y);
      }
  std::vector<double> sum(3 * nc, 0.0);
  std::vector<int> members(3 * nc, 0);
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a) {
      double length = 0.0;
      for (int k = 0; k < 4; ++k) length += path_length(out.surfaces[c].mesh, out.surfaces[c].layout.poly_edges[4 * a + k]);
      sum[root(3 * c + a)] += length / 4.0;
      ++members[root(3 * c + a)];
    }
  for (int c = 0; c < nc; ++c) {
    GpcCuboid& cuboid = out.domain.cuboids[c];
    for (int a = 0; a < 3; ++a) {
      const int r = root(3 * c + a);
      cuboid.size[a] = std::max(sum[r] / members[r] / bbox_diagonal, 1e-6);
    }
    for (int k = 0; k < 8; ++k)
      cuboid.corner_xyz[k] = out.surfaces[c].mesh.positions.row(out.surfaces[c].layout.corners[k]).transpose();
  }
  transitions();
  out.domain.genus = d.genus;
  for (const SolidPiece& sp : d.pieces) {
    out.domain.caps += sp.kind == PieceKind::Cap;
    out.domain.tubes += sp.kind == PieceKind::Tube;
    out.domain.t_shapes += sp.kind == PieceKind::TShape;
  }
  return out;
}

std::vector<double> face_area_ratios(const GpcConstruction& construction) {
  std::vector<double> region, domain;
  double region_total = 0.0, domain_total = 0.0;
  for (std::size_t c = 0; c < construction.surfaces.size(); ++c) {
    const CuboidSurface& cs = construction.surfaces[c];
    const GpcCuboid& cuboid = construction.domain.cuboids[c];
    std::array<double, num_cube_faces> area{};
    for (int t = 0; t < cs.mesh.num_faces(); ++t) {
      if (cs.surface_face[t] < 0 || cs.layout.face_region[t] < 0) continue;
      const Eigen::Vector3d a = cs.mesh.positions.row(cs.mesh.triangles(t, 0)).transpose();
      const Eigen::Vector3d b = cs.mesh.positions.row(cs.mesh.triangles(t, 1)).transpose();
      const Eigen::Vector3d d = cs.mesh.positions.row(cs.mesh.triangles(t, 2)).transpose();
      area[cs.layout.face_region[t]] += 0.5 * (b - a).cross(d - a).norm();
    }
    for (int f = 0; f < num_cube_faces; ++f) {
      if (cuboid.face_interface[f] >= 0) continue;
      const double face = cuboid.size[(f / 2 + 1) % 3] * cuboid.size[(f / 2 + 2) % 3];
      region.push_back(area[f]);
      domain.push_back(face);
      region_total += area[f];
      domain_total += face;
    }
  }
  std::vector<double> ratio(region.size(), 0.0);
  for (std::size_t k = 0; k < region.size(); ++k)
    if (region_total > 0.0 && domain[k] > 0.0) ratio[k] = (region[k] / region_total) / (domain[k] / domain_total);
  return ratio;
}

}  // namespace volspline::polycube
