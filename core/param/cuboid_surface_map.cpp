// SPDX-License-Identifier: MIT
#include "core/param/cuboid_surface_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "core/common/error.h"
#include "core/linalg/algebraic_multigrid.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"

namespace volspline::param {

CuboidSurfaceMap compute_cuboid_surface_map(const mesh::HalfedgeMesh& mesh,
                                            const polycube::CuboidLayout& layout,
                                            const CuboidSurfaceMapOptions& options,
                                            const Progress& progress) {
  if (!(options.tolerance > 0.0 && options.tolerance < 1.0) ||
      !(options.balance_tolerance >= options.tolerance && options.balance_tolerance < 1.0))
    throw Error("cuboid surface map: `tolerance` must be in (0, 1) and `balance_tolerance` in [`tolerance`, 1)");
  if (options.area_balance_iterations < 0 || options.area_balance_iterations > 20)
    throw Error("cuboid surface map: `area_balance_iterations` must be in [0, 20]");
  if (!(options.squeezed_below >= 0.0 && options.squeezed_below < 1.0) || options.squeezed_rounds < 0 ||
      options.squeezed_rounds > 40)
    throw Error("cuboid surface map: `squeezed_below` must be in [0, 1) and `squeezed_rounds` in [0, 40]");
  progress.report("surface map", 0.0);
  const int n = mesh.num_vertices();
  CuboidSurfaceMap map;
  map.uvw = mesh::Positions::Zero(n, 3);
  map.face_region = layout.face_region;
  std::vector<char> fixed(n, 0);

  // Poly-edges by arc length: both rectangles sharing an edge read the same parameters.
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto& path = layout.poly_edges[e];
    const int axis = e / 4;
    const int low = polycube::cube_edge_corners(e)[0];
    std::vector<double> arc(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
      arc[i] = arc[i - 1] + (mesh.vertex_position(path[i]) - mesh.vertex_position(path[i - 1])).norm();
    const double total = arc.back();
    for (std::size_t i = 0; i < path.size(); ++i) {
      Eigen::Vector3d uvw(low & 1, (low >> 1) & 1, (low >> 2) & 1);
      uvw(axis) = i + 1 == path.size() ? 1.0 : (total > 0.0 ? arc[i] / total : 0.0);
      map.uvw.row(path[i]) = uvw.transpose();
      fixed[path[i]] = 1;
    }
  }

  std::vector<double> weight;  // per halfedge, symmetric
  if (options.weights == SurfaceWeights::MeanValue) {
    // Symmetrized mean-value weights stay positive (Tutte's theorem needs only positivity) and
    // make the system SPD so the project's CG applies.
    const std::vector<double> mvc = mesh::mean_value_weights(mesh);
    weight.resize(mvc.size());
    for (int h = 0; h < mesh.num_halfedges(); ++h)
      weight[h] = 0.5 * (mvc[h] + mvc[mesh.halfedge_twin(h)]);
  } else {
    weight = mesh::edge_to_halfedge_weights(mesh, mesh::cotan_weights(mesh));
  }

  std::vector<int> vertex_face(n, -1);  // cube face of vertices inside a rectangle
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int v : mesh.face_vertices(f))
      if (!fixed[v]) vertex_face[v] = layout.face_region[f];
  std::vector<std::vector<int>> face_interior(polycube::num_cube_faces);
  std::vector<int> local(n, -1);
  for (int v = 0; v < n; ++v)
    if (vertex_face[v] >= 0) {
      local[v] = static_cast<int>(face_interior[vertex_face[v]].size());
      face_interior[vertex_face[v]].push_back(v);
    }

  // Per cube face the pattern of its interior system, built once (the area-balancing rounds
  // change only the values): per row the outgoing halfedges of its vertex and, for each, the
  // entry of the neighbour's column (−1: a fixed neighbour, which goes to the right-hand side).
  struct FaceSystem {
    std::vector<int> first;     // per row, its range of halfedges (m + 1 offsets)
    std::vector<int> halfedge;  // outgoing halfedges, in vertex_outgoing order
    std::vector<int> entry;     // per halfedge, index into a.values() or −1
    std::vector<int> diagonal;  // per row, index of the diagonal entry
    linalg::CsrMatrix a;
  };
  std::vector<FaceSystem> systems(polycube::num_cube_faces);
  for (int face = 0; face < polycube::num_cube_faces; ++face) {
    const std::vector<int>& interior = face_interior[face];
    const int m = static_cast<int>(interior.size());
    FaceSystem& system = systems[face];
    system.first.assign(1, 0);
    std::vector<int> offsets(m + 1, 0), cols;
    std::vector<int> row;
    for (int i = 0; i < m; ++i) {
      row.assign(1, i);
      for (int h : mesh.vertex_outgoing(interior[i])) {
        system.halfedge.push_back(h);
        const int j = mesh.halfedge_vertex(h);
        if (!fixed[j]) row.push_back(local[j]);
      }
      system.first.push_back(static_cast<int>(system.halfedge.size()));
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      auto entry_of = [&](int column) {
        return offsets[i] + static_cast<int>(std::lower_bound(row.begin(), row.end(), column) - row.begin());
      };
      for (int k = system.first[i]; k < system.first[i + 1]; ++k) {
        const int j = mesh.halfedge_vertex(system.halfedge[k]);
        system.entry.push_back(fixed[j] ? -1 : entry_of(local[j]));
      }
      system.diagonal.push_back(entry_of(i));
      cols.insert(cols.end(), row.begin(), row.end());
      offsets[i + 1] = static_cast<int>(cols.size());
    }
    std::vector<double> values(cols.size(), 0.0);
    system.a = linalg::CsrMatrix::from_arrays(m, m, std::move(offsets), std::move(cols), std::move(values));
  }

  const double num_solves = polycube::num_cube_faces * (options.area_balance_iterations + 1.0);
  int solves_done = 0;
  // Solves every cube face's map; max_iterations < 0: the solver's default (2 × the face's
  // unknowns). Returns false if a face's solve stopped at max_iterations short of the tolerance.
  auto solve = [&](const std::vector<double>& weight, double tolerance, int max_iterations) {
    bool converged = true;
    for (int face = 0; face < polycube::num_cube_faces; ++face) {
      progress.report("surface map", std::min(1.0, solves_done++ / num_solves));
      const std::vector<int>& interior = face_interior[face];
      const int m = static_cast<int>(interior.size());
      if (m == 0) continue;
      FaceSystem& system = systems[face];
      std::vector<double>& values = system.a.values();
      std::fill(values.begin(), values.end(), 0.0);
      Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
      Eigen::MatrixXd x0(m, 2);
      for (int i = 0; i < m; ++i) {
        const int v = interior[i];
        x0.row(i) = cube_face_coordinates(face, map.uvw.row(v).transpose()).transpose();
        double diagonal = 0.0;
        for (int k = system.first[i]; k < system.first[i + 1]; ++k) {
          const int h = system.halfedge[k];
          const double w = weight[h];
          diagonal += w;
          if (system.entry[k] < 0)
            rhs.row(i) += w * cube_face_coordinates(face, map.uvw.row(mesh.halfedge_vertex(h)).transpose()).transpose();
          else
            values[system.entry[k]] -= w;
        }
        values[system.diagonal[i]] = diagonal > 0.0 ? diagonal : 1.0;
      }
      Eigen::MatrixXd st;
      linalg::SolverInfo info = linalg::SolverInfo::Success;
      int iterations = 0;
      auto run = [&](auto& cg) {
        cg.set_tolerance(tolerance);
        cg.set_max_iterations(max_iterations);
        cg.compute(system.a);
        st = cg.solve(rhs, x0);
        info = cg.info();
        iterations = cg.iterations();
      };
      if (options.solver == SurfaceSolver::Multigrid) {
        linalg::ConjugateGradient<linalg::AlgebraicMultigrid> cg;
        run(cg);
      } else {
        linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
        run(cg);
      }
      if (info == linalg::SolverInfo::NumericalIssue)
        throw Error("mesh '" + mesh.source_name() + "': the harmonic map of cuboid face " +
                    std::to_string(face) + " has no SPD system (negative cotan weights?)");
      map.cg_iterations = std::max(map.cg_iterations, iterations);
      converged = converged && info == linalg::SolverInfo::Success;
      for (int i = 0; i < m; ++i)
        map.uvw.row(interior[i]) = cube_face_point(face, st(i, 0), st(i, 1)).transpose();
    }
    return converged;
  };
  // Warm start at the square's centre: the solution lies inside the square.
  for (int v = 0; v < n; ++v)
    if (vertex_face[v] >= 0) map.uvw.row(v) = cube_face_point(vertex_face[v], 0.5, 0.5).transpose();
  // The maps before the last only set the area-balancing weights: a looser solve is enough.
  auto round_tolerance = [&](int round) {
    return round < options.area_balance_iterations ? options.balance_tolerance : options.tolerance;
  };
  solve(weight, round_tolerance(0), -1);

  // Area balancing (after Yoshizawa, Belyaev & Seidel 2004, stretch minimization): a Tutte map
  // squeezes protrusions (ears, limbs) into tiny parameter areas that no spline cell can
  // resolve; dividing each edge weight by the local area stretch of the current map makes those
  // springs weaker, so the region takes more parameter area. Weights stay positive, so every
  // iterate is still a bijective convex-combination map.
  std::vector<double> face_area(polycube::num_cube_faces, 0.0);
  std::vector<double> surface_area(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto c = mesh.face_vertices(f);
    surface_area[f] = 0.5 * (mesh.vertex_position(c[1]) - mesh.vertex_position(c[0]))
                                .cross(mesh.vertex_position(c[2]) - mesh.vertex_position(c[0]))
                                .norm();
    face_area[layout.face_region[f]] += surface_area[f];
  }
  // Area of mesh face f in its cube face's parameters, positive if not flipped.
  auto oriented_param_area = [&](int f) {
    const int face = layout.face_region[f];
    const auto c = mesh.face_vertices(f);
    const Eigen::Vector2d p0 = cube_face_coordinates(face, map.uvw.row(c[0]).transpose());
    const Eigen::Vector2d d1 = cube_face_coordinates(face, map.uvw.row(c[1]).transpose()) - p0;
    const Eigen::Vector2d d2 = cube_face_coordinates(face, map.uvw.row(c[2]).transpose()) - p0;
    const double area = 0.5 * (d1.x() * d2.y() - d1.y() * d2.x());
    return face % 2 == 1 ? area : -area;
  };
  // Per vertex √(surface share / parameter share) within its cube face: the linear stretch.
  auto measure_stretch = [&]() {
    std::vector<double> vertex_surface(n, 0.0), vertex_param(n, 0.0);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int face = layout.face_region[f];
      const double param_area = std::abs(oriented_param_area(f));
      for (int v : mesh.face_vertices(f)) {
        vertex_surface[v] += face_area[face] > 0.0 ? surface_area[f] / face_area[face] : 0.0;
        vertex_param[v] += param_area;
      }
    }
    std::vector<double> stretch(n, 1.0);
    for (int v = 0; v < n; ++v)
      if (vertex_param[v] > 0.0 && vertex_surface[v] > 0.0) stretch[v] = std::sqrt(vertex_surface[v] / vertex_param[v]);
    return stretch;
  };
  auto reweight = [&](const std::vector<double>& stretch) {
    for (int h = 0; h < mesh.num_halfedges(); ++h) {
      const int i = mesh.halfedge_vertex(mesh.halfedge_twin(h)), j = mesh.halfedge_vertex(h);
      weight[h] /= 0.5 * (stretch[i] + stretch[j]);
    }
  };
  for (int iteration = 0; iteration < options.area_balance_iterations; ++iteration) {
    std::vector<double> stretch = measure_stretch();
    for (double& s : stretch) s = std::clamp(s, 0.2, 5.0);
    reweight(stretch);
    solve(weight, round_tolerance(iteration + 1), -1);
  }

  // Squeeze rescue (a §3.4.1 deviation, as the balancing): in a thin protrusion the stretch grows
  // ring by ring towards the tip and only the weights' gradient along it moves the map, so rounds
  // bounded by 5 open a deep squeeze slowly; rounds bounded by 20 open it in a few. They only
  // widen (stretch below 1 is left at 1): rounds that also shrink the parts with room overshoot
  // and crowd the poly-edges next to a tip. The weights then span many orders of magnitude, where
  // a relative residual of 1e-10 leaves triangles of the light region flipped: these rounds are
  // solved to 1e-14.
  constexpr double kSqueezedStretchBound = 20.0, kSqueezedTolerance = 1e-14;
  // A tip opens by about 2× per round; a round that gains less than this meets a squeeze the
  // rounds hardly move (where cuts crowd a face): it is undone and the rounds stop, so such a map
  // stays the balanced one instead of paying 1e-14 solves for a change of a few per cent.
  constexpr double kSqueezedMinGain = 1.3;
  // The multigrid-preconditioned solves of these rounds converge in 15-150 iterations; where the
  // weights' range leaves the 1e-14 residual out of reach, CG stalls and would run to twice the
  // face's unknowns (a 29k-vertex face: 59k iterations, minutes). Such a round is undone and the
  // rounds stop, as for a round that flips a triangle.
  constexpr int kSqueezedMaxIterations = 500;
  auto least_density = [&](const std::vector<double>& stretch) {
    double least = std::numeric_limits<double>::infinity();
    for (int v = 0; v < n; ++v)
      if (vertex_face[v] >= 0) least = std::min(least, 1.0 / stretch[v]);
    return least;
  };
  // Flipped or degenerate triangles of the current map, and the first of them (−1 if none).
  auto count_flipped = [&](int* first) {
    int count = 0;
    if (first) *first = -1;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      if (!(oriented_param_area(f) > 0.0)) {
        ++count;
        if (first && *first < 0) *first = f;
      }
    }
    return count;
  };
  std::vector<double> stretch = measure_stretch();
  map.least_density = least_density(stretch);
  map.unrescued_least_density = map.least_density;
  // A round is kept only if its map is bijective and gains kSqueezedMinGain: where the weights'
  // range outruns double precision, the rounds stop at the last good map instead of failing.
  for (int round = 0; round < options.squeezed_rounds && map.least_density < options.squeezed_below; ++round) {
    if (round == 0 && count_flipped(nullptr) > 0) break;
    const mesh::Positions kept = map.uvw;
    for (double& s : stretch) s = std::clamp(s, 1.0, kSqueezedStretchBound);
    reweight(stretch);
    const bool converged = solve(weight, std::min(options.tolerance, kSqueezedTolerance), kSqueezedMaxIterations);
    std::vector<double> next = measure_stretch();
    const double density = least_density(next);
    if (!converged || !(density >= kSqueezedMinGain * map.least_density) || count_flipped(nullptr) > 0) {
      map.uvw = kept;
      break;
    }
    stretch = std::move(next);
    map.least_density = density;
    map.squeeze_rounds = round + 1;
  }

  progress.report("surface map", 1.0);
  int first_flipped = -1;
  map.num_flipped = count_flipped(&first_flipped);
  if (map.num_flipped > 0)
    throw Error("mesh '" + mesh.source_name() + "': the cuboid surface map is not bijective: " +
                std::to_string(map.num_flipped) + " flipped or degenerate triangles (first: face " +
                std::to_string(first_flipped) + " on cuboid face " +
                std::to_string(layout.face_region[first_flipped]) + ")");
  return map;
}

}  // namespace volspline::param
