// SPDX-License-Identifier: MIT
#include "core/volume/field_aligned_param.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/parallel_for.h"
#include "core/linalg/csr_matrix.h"

namespace volspline::volume {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

void check_options(const FieldAlignedOptions& o, std::size_t num_voxels) {
  if (!(o.anisotropy > 0 && o.anisotropy <= 1)) throw Error("field-aligned parameterization: anisotropy must be in (0, 1]");
  if (o.grid_step < 0) throw Error("field-aligned parameterization: grid_step must be >= 0, got " + std::to_string(o.grid_step));
  if (o.max_grid_nodes < 8) throw Error("field-aligned parameterization: max_grid_nodes must be >= 8");
  if (!(o.background_weight >= 0 && o.background_weight <= 1))
    throw Error("field-aligned parameterization: background_weight must be in [0, 1]");
  if (!(o.reliability_radius >= 0 && std::isfinite(o.reliability_radius)))
    throw Error("field-aligned parameterization: reliability_radius must be >= 0");
  if (!(o.identity_weight >= 0 && std::isfinite(o.identity_weight)))
    throw Error("field-aligned parameterization: identity_weight must be >= 0");
  if (!(o.corner_snap_tol >= 0 && o.corner_snap_tol < 1))
    throw Error("field-aligned parameterization: corner_snap_tol must be in [0, 1)");
  if (!(o.corner_weight > 0 && std::isfinite(o.corner_weight)))
    throw Error("field-aligned parameterization: corner_weight must be > 0");
  if (!(o.cg_tolerance > 0)) throw Error("field-aligned parameterization: cg_tolerance must be > 0");
  if (o.cg_max_iterations < 1) throw Error("field-aligned parameterization: cg_max_iterations must be >= 1");
  if (o.threads < 1) throw Error("field-aligned parameterization: threads must be >= 1");
  if (o.corner_selection == CornerSelection::Given)
    for (std::size_t id : o.corner_voxels)
      if (id >= num_voxels)
        throw Error("field-aligned parameterization: corner voxel " + std::to_string(id) + " is outside the grid of " +
                    std::to_string(num_voxels) + " voxels");
}

// The parameterization grid: m[d] nodes along axis d, node i at voxel coordinate i * ratio[d].
struct Grid {
  std::array<int, 3> m{};
  std::array<double, 3> ratio{};  // voxels per cell along each axis
  std::array<int, 3> dims{};      // voxel dims

  std::size_t num_nodes() const { return static_cast<std::size_t>(m[0]) * m[1] * m[2]; }
  std::size_t node(int i, int j, int k) const { return i + static_cast<std::size_t>(m[0]) * (j + static_cast<std::size_t>(m[1]) * k); }
  // Identity parameter of coordinate c at node index t along axis c.
  double identity(int c, int t) const { return t * ratio[c] / (dims[c] - 1); }
  // Cell index and local coordinate of voxel coordinate v along axis d.
  void locate(int d, double v, int& cell, double& xi) const {
    const double t = v / ratio[d];
    cell = std::min(static_cast<int>(std::floor(t)), m[d] - 2);
    cell = std::max(cell, 0);
    xi = t - cell;
  }
};

Grid make_grid(const Volume& v, const FieldAlignedOptions& o) {
  Grid g;
  g.dims = {v.nx, v.ny, v.nz};
  auto nodes_for = [&](int step) {
    std::size_t total = 1;
    for (int d = 0; d < 3; ++d) total *= static_cast<std::size_t>((g.dims[d] - 1 + step - 1) / step + 1);
    return total;
  };
  int step = o.grid_step;
  if (step == 0) {
    step = 1;
    while (nodes_for(step) > static_cast<std::size_t>(o.max_grid_nodes) && step < std::max({v.nx, v.ny, v.nz})) ++step;
  }
  for (int d = 0; d < 3; ++d) {
    g.m[d] = std::max(2, (g.dims[d] - 1 + step - 1) / step + 1);
    g.ratio[d] = static_cast<double>(g.dims[d] - 1) / (g.m[d] - 1);
  }
  return g;
}

// Target frame of every voxel: the smoothed frame relabelled by the cube rotation closest to the
// identity (the map is a deformation of the identity), the identity in the background. The
// confidence is the margin of that choice over the runner-up, tr(g F) - tr(g' F) clamped to
// [0.05, 1] (2 for an axis-aligned frame, 0 at a 45-degree tie where the relabelling jumps and
// would tear the map), so ambiguous voxels follow their neighbours.
struct Targets {
  std::vector<Eigen::Matrix3d> frame;
  std::vector<double> confidence;
  std::vector<double> reliability;  // per voxel in [0, 1]: trust in the frame (0 in the background)
};

// Multi-source BFS over 26-neighbours: voxels at Chebyshev distance d ≤ max_distance from the
// seeds in front (already set to 0 in distance; unreached voxels hold −1) get distance d.
void grow_chebyshev_distance(int nx, int ny, int nz, std::vector<std::size_t> front, int max_distance,
                             std::vector<int>& distance) {
  std::vector<std::size_t> next;
  for (int d = 1; d <= max_distance && !front.empty(); ++d) {
    next.clear();
    for (std::size_t id : front) {
      const int x = static_cast<int>(id % nx), y = static_cast<int>((id / nx) % ny),
                z = static_cast<int>(id / (static_cast<std::size_t>(nx) * ny));
      for (int zz = std::max(0, z - 1); zz <= std::min(nz - 1, z + 1); ++zz)
        for (int yy = std::max(0, y - 1); yy <= std::min(ny - 1, y + 1); ++yy)
          for (int xx = std::max(0, x - 1); xx <= std::min(nx - 1, x + 1); ++xx) {
            const std::size_t other = xx + static_cast<std::size_t>(nx) * (yy + static_cast<std::size_t>(ny) * zz);
            if (distance[other] < 0) {
              distance[other] = d;
              next.push_back(other);
            }
          }
    }
    std::swap(front, next);
  }
}

// Reliability of the frames (our reading of §5.2.2: only the iso-surface constraints carry
// information; interior Hessian frames of flat materials are noise): exp(-(d / R)^2) with d the
// Chebyshev distance to the nearest constrained voxel (multi-source BFS over 26-neighbours, cut
// at 3R); 1 on every foreground voxel for R = 0; 0 on the background.
std::vector<double> frame_reliability(const MaterialClassification& classes, double radius) {
  const std::size_t n = classes.label.size();
  std::vector<double> reliability(n, 0.0);
  if (radius == 0.0) {
    for (std::size_t i = 0; i < n; ++i) reliability[i] = classes.label[i] == 0 ? 0.0 : 1.0;
    return reliability;
  }
  const int nx = classes.nx, ny = classes.ny, nz = classes.nz;
  const int cut = static_cast<int>(std::ceil(3.0 * radius));
  std::vector<int> distance(n, -1);
  std::vector<std::size_t> front;
  for (const FrameConstraint& c : classes.constraints)
    if (distance[c.voxel_id] < 0) {
      distance[c.voxel_id] = 0;
      front.push_back(c.voxel_id);
    }
  grow_chebyshev_distance(nx, ny, nz, std::move(front), cut, distance);
  for (std::size_t i = 0; i < n; ++i)
    if (classes.label[i] != 0 && distance[i] >= 0) reliability[i] = std::exp(-std::pow(distance[i] / radius, 2));
  return reliability;
}

Targets combed_targets(const FrameField& field, const MaterialClassification& classes) {
  Targets targets;
  targets.frame.resize(field.frames.size());
  targets.confidence.assign(field.frames.size(), 1.0);
  const auto& group = cube_group_rotations();
  for (std::size_t i = 0; i < field.frames.size(); ++i) {
    if (classes.label[i] == 0) {
      targets.frame[i].setIdentity();
      continue;
    }
    double best = -1e300, second = -1e300;
    int best_g = 0;
    for (int g = 0; g < 24; ++g) {
      const double score = (group[g] * field.frames[i]).trace();
      if (score > best) {
        second = best;
        best = score;
        best_g = g;
      } else if (score > second) {
        second = score;
      }
    }
    targets.frame[i] = group[best_g] * field.frames[i];
    targets.confidence[i] = std::clamp(best - second, 0.05, 1.0);
  }
  return targets;
}

// RMS angle (degrees) over foreground voxels (with reliability >= min_reliability) between the
// gradient of each coordinate of a per-voxel map and its target axis.
double alignment_rms_deg(const Volume& volume, const MaterialClassification& classes, const Targets& targets,
                         const Eigen::MatrixX3d& uvw, double min_reliability = 0.0) {
  double sum_sq = 0.0;
  std::size_t count = 0;
  const int dims[3] = {volume.nx, volume.ny, volume.nz};
  for (int z = 0; z < volume.nz; ++z)
    for (int y = 0; y < volume.ny; ++y)
      for (int x = 0; x < volume.nx; ++x) {
        const std::size_t id = volume.index(x, y, z);
        if (classes.label[id] == 0 || targets.reliability[id] < min_reliability) continue;
        Eigen::Matrix3d jac;  // column d: d uvw / d axis d (central differences, one-sided at the border)
        const int p[3] = {x, y, z};
        for (int d = 0; d < 3; ++d) {
          int lo[3] = {x, y, z}, hi[3] = {x, y, z};
          lo[d] = std::max(0, p[d] - 1);
          hi[d] = std::min(dims[d] - 1, p[d] + 1);
          jac.col(d) = (uvw.row(static_cast<Eigen::Index>(volume.index(hi[0], hi[1], hi[2]))) -
                        uvw.row(static_cast<Eigen::Index>(volume.index(lo[0], lo[1], lo[2]))))
                           .transpose() /
                       ((hi[d] - lo[d]) * volume.spacing[d]);
        }
        for (int c = 0; c < 3; ++c) {
          const Eigen::Vector3d gradient = jac.row(c).transpose();
          if (!(gradient.norm() > 0)) continue;
          const double cosine = std::clamp(gradient.normalized().dot(targets.frame[id].row(c).transpose()), -1.0, 1.0);
          const double angle = std::acos(cosine) * kRadToDeg;
          sum_sq += angle * angle;
          ++count;
        }
      }
  return count > 0 ? std::sqrt(sum_sq / static_cast<double>(count)) : 0.0;
}

// Uniform CSR pattern over the interior nodes with the 27-point stencil.
struct System {
  std::array<int, 3> interior{};  // interior nodes per axis (m - 2)
  int unknowns = 0;
  std::vector<int> row_offsets;
  std::vector<int> col_indices;
  std::vector<int> slot;  // per unknown, 27 entries: position in col_indices or -1
  std::array<std::vector<double>, 3> values;
  std::array<Eigen::VectorXd, 3> rhs;

  int unknown(const Grid& g, int i, int j, int k) const {
    if (i <= 0 || j <= 0 || k <= 0 || i >= g.m[0] - 1 || j >= g.m[1] - 1 || k >= g.m[2] - 1) return -1;
    return (i - 1) + interior[0] * ((j - 1) + interior[1] * (k - 1));
  }
};

System make_system(const Grid& g) {
  System s;
  for (int d = 0; d < 3; ++d) s.interior[d] = std::max(0, g.m[d] - 2);
  s.unknowns = s.interior[0] * s.interior[1] * s.interior[2];
  s.row_offsets.assign(1, 0);
  s.slot.assign(static_cast<std::size_t>(s.unknowns) * 27, -1);
  s.col_indices.reserve(static_cast<std::size_t>(s.unknowns) * 27);
  for (int k = 1; k < g.m[2] - 1; ++k)
    for (int j = 1; j < g.m[1] - 1; ++j)
      for (int i = 1; i < g.m[0] - 1; ++i) {
        const int row = s.unknown(g, i, j, k);
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int col = s.unknown(g, i + dx, j + dy, k + dz);
              if (col < 0) continue;
              s.slot[static_cast<std::size_t>(row) * 27 + (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)] = static_cast<int>(s.col_indices.size());
              s.col_indices.push_back(col);
            }
        s.row_offsets.push_back(static_cast<int>(s.col_indices.size()));
      }
  for (int c = 0; c < 3; ++c) {
    s.values[c].assign(s.col_indices.size(), 0.0);
    s.rhs[c] = Eigen::VectorXd::Zero(s.unknowns);
  }
  return s;
}

// Adds a local 8x8 block (cell corner order: bit 0 = +x, bit 1 = +y, bit 2 = +z) of coordinate c
// with its load vector; Dirichlet corners (the box boundary, held at the identity) move to the rhs.
void scatter(const Grid& g, System& s, int c, int ci, int cj, int ck, const double (&k)[8][8], const double (&f)[8]) {
  for (int a = 0; a < 8; ++a) {
    const int ia = ci + (a & 1), ja = cj + ((a >> 1) & 1), ka = ck + ((a >> 2) & 1);
    const int row = s.unknown(g, ia, ja, ka);
    if (row < 0) continue;
    s.rhs[c][row] += f[a];
    for (int b = 0; b < 8; ++b) {
      const int ib = ci + (b & 1), jb = cj + ((b >> 1) & 1), kb = ck + ((b >> 2) & 1);
      const int col = s.unknown(g, ib, jb, kb);
      if (col < 0) {
        const int t = c == 0 ? ib : c == 1 ? jb : kb;
        s.rhs[c][row] -= k[a][b] * g.identity(c, t);
      } else {
        const int o = (ib - ia + 1) + 3 * (jb - ja + 1) + 9 * (kb - ka + 1);
        s.values[c][s.slot[static_cast<std::size_t>(row) * 27 + o]] += k[a][b];
      }
    }
  }
}

// Per-voxel uvw by trilinear interpolation of the node values.
Eigen::MatrixX3d interpolate(const Grid& g, const std::array<Eigen::VectorXd, 3>& nodes) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  Eigen::MatrixX3d uvw(static_cast<Eigen::Index>(nx) * ny * nz, 3);
  std::vector<int> cell[3];
  std::vector<double> xi[3];
  for (int d = 0; d < 3; ++d) {
    cell[d].resize(g.dims[d]);
    xi[d].resize(g.dims[d]);
    for (int t = 0; t < g.dims[d]; ++t) g.locate(d, t, cell[d][t], xi[d][t]);
  }
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const Eigen::Index id = x + static_cast<Eigen::Index>(nx) * (y + static_cast<Eigen::Index>(ny) * z);
        for (int c = 0; c < 3; ++c) {
          double value = 0.0;
          for (int a = 0; a < 8; ++a) {
            const double wx = (a & 1) ? xi[0][x] : 1 - xi[0][x];
            const double wy = (a & 2) ? xi[1][y] : 1 - xi[1][y];
            const double wz = (a & 4) ? xi[2][z] : 1 - xi[2][z];
            value += wx * wy * wz * nodes[c][g.node(cell[0][x] + (a & 1), cell[1][y] + ((a >> 1) & 1), cell[2][z] + ((a >> 2) & 1))];
          }
          uvw(id, c) = std::clamp(value, 0.0, 1.0);
        }
      }
  return uvw;
}

Eigen::MatrixX3d identity_map(int nx, int ny, int nz) {
  Eigen::MatrixX3d uvw(static_cast<Eigen::Index>(nx) * ny * nz, 3);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const Eigen::Index id = x + static_cast<Eigen::Index>(nx) * (y + static_cast<Eigen::Index>(ny) * z);
        uvw(id, 0) = static_cast<double>(x) / (nx - 1);
        uvw(id, 1) = static_cast<double>(y) / (ny - 1);
        uvw(id, 2) = static_cast<double>(z) / (nz - 1);
      }
  return uvw;
}

}  // namespace

namespace {

// Scaled-Jacobian check; `folded`, if given, receives the flat index of the (0,0,0) voxel of
// every hex with a corner Jacobian <= 0, ascending.
double jacobian_check(int nx, int ny, int nz, const Eigen::MatrixX3d& uvw, int* inverted, std::vector<std::size_t>* folded) {
  assert(nx >= 2 && ny >= 2 && nz >= 2 && uvw.rows() == static_cast<Eigen::Index>(nx) * ny * nz);
  double min_scaled = 1.0;
  int bad = 0;
  auto at = [&](int x, int y, int z) -> Eigen::Vector3d {
    return uvw.row(x + static_cast<Eigen::Index>(nx) * (y + static_cast<Eigen::Index>(ny) * z)).transpose();
  };
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        bool is_folded = false;
        for (int corner = 0; corner < 8; ++corner) {
          const int bx = corner & 1, by = (corner >> 1) & 1, bz = (corner >> 2) & 1;
          const Eigen::Vector3d e1 = at(x + 1, y + by, z + bz) - at(x, y + by, z + bz);
          const Eigen::Vector3d e2 = at(x + bx, y + 1, z + bz) - at(x + bx, y, z + bz);
          const Eigen::Vector3d e3 = at(x + bx, y + by, z + 1) - at(x + bx, y + by, z);
          const double det = e1.dot(e2.cross(e3));
          const double lengths = e1.norm() * e2.norm() * e3.norm();
          const double scaled = lengths > 0 ? det / lengths : 0.0;
          min_scaled = std::min(min_scaled, scaled);
          if (!(det > 0)) is_folded = true;
        }
        if (is_folded) {
          ++bad;
          if (folded) folded->push_back(x + static_cast<std::size_t>(nx) * (y + static_cast<std::size_t>(ny) * z));
        }
      }
  if (inverted) *inverted = bad;
  return min_scaled;
}

// Smallest and largest uvw volume of a voxel hex (determinant of its mean edge vectors) over
// the identity map's 1 / ((nx - 1)(ny - 1)(nz - 1)).
void volume_ratio_range(int nx, int ny, int nz, const Eigen::MatrixX3d& uvw, double& lo, double& hi) {
  auto at = [&](int x, int y, int z) -> Eigen::Vector3d {
    return uvw.row(x + static_cast<Eigen::Index>(nx) * (y + static_cast<Eigen::Index>(ny) * z)).transpose();
  };
  const double identity = 1.0 / ((nx - 1.0) * (ny - 1.0) * (nz - 1.0));
  lo = std::numeric_limits<double>::infinity();
  hi = -std::numeric_limits<double>::infinity();
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        Eigen::Vector3d e[3] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
        for (int a = 0; a <= 1; ++a)
          for (int b = 0; b <= 1; ++b) {
            e[0] += at(x + 1, y + a, z + b) - at(x, y + a, z + b);
            e[1] += at(x + a, y + 1, z + b) - at(x + a, y, z + b);
            e[2] += at(x + a, y + b, z + 1) - at(x + a, y + b, z);
          }
        const double ratio = e[0].dot(e[1].cross(e[2])) / 64.0 / identity;
        lo = std::min(lo, ratio);
        hi = std::max(hi, ratio);
      }
}

// Eq. 5.7/5.10 with the gradient operator of Eq. 5.8 for the trilinear polynomial on each cell
// (an exact fit of its 8 nodes), integrated by 2x2x2 Gauss quadrature: the cubic 5^3 window
// would give 729 nonzeros per row, the cell operator 27, and the full quadrature has no
// hourglass null space. Adds the cells' terms of all three coordinates to s.
void assemble_alignment(const Volume& volume, const MaterialClassification& classes, const Targets& targets,
                        const Grid& g, const FieldAlignedOptions& options, System& s) {
  const Eigen::Vector3d h(g.ratio[0] * volume.spacing.x(), g.ratio[1] * volume.spacing.y(), g.ratio[2] * volume.spacing.z());
  // Gradient of the identity parameter per unit length: u = x / ((nx - 1) sx).
  const Eigen::Vector3d scale((volume.nx - 1) * volume.spacing.x(), (volume.ny - 1) * volume.spacing.y(),
                              (volume.nz - 1) * volume.spacing.z());
  const double gauss[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
  const double alpha = options.anisotropy;
  for (int ck = 0; ck + 1 < g.m[2]; ++ck)
    for (int cj = 0; cj + 1 < g.m[1]; ++cj)
      for (int ci = 0; ci + 1 < g.m[0]; ++ci) {
        double k[3][8][8] = {};
        double f[3][8] = {};
        for (int q = 0; q < 8; ++q) {
          const double xi[3] = {gauss[q & 1], gauss[(q >> 1) & 1], gauss[(q >> 2) & 1]};
          const int vx = static_cast<int>(std::lround((ci + xi[0]) * g.ratio[0]));
          const int vy = static_cast<int>(std::lround((cj + xi[1]) * g.ratio[1]));
          const int vz = static_cast<int>(std::lround((ck + xi[2]) * g.ratio[2]));
          const std::size_t voxel = volume.index(vx, vy, vz);
          // Eq. 5.7/5.10 where the frame is reliable, the identity frame elsewhere. The thesis
          // names no regularisation (§5.3.1 only says constraints "may cause serious
          // distortion"), so its weight is ours: the density error grows with the map's stretch
          // on every volume (tooth worst), and identity_weight 4 with background_weight 1 keeps
          // the hex volume ratio within about [0.8, 1.2]; fuel and bucky barely move between 1 and 16.
          const bool background = classes.label[voxel] == 0;
          const double reliability = targets.reliability[voxel];
          const double weight = background ? 0.0 : reliability * targets.confidence[voxel] * h.prod() / 8.0;
          const double pull = (background ? options.background_weight : options.identity_weight * (1.0 - reliability)) *
                              h.prod() / 8.0;
          if (weight == 0.0 && pull == 0.0) continue;
          Eigen::Matrix<double, 3, 8> grad;
          for (int a = 0; a < 8; ++a) {
            const double n0 = (a & 1) ? xi[0] : 1 - xi[0];
            const double n1 = (a & 2) ? xi[1] : 1 - xi[1];
            const double n2 = (a & 4) ? xi[2] : 1 - xi[2];
            grad(0, a) = ((a & 1) ? 1.0 : -1.0) / h[0] * n1 * n2;
            grad(1, a) = ((a & 2) ? 1.0 : -1.0) / h[1] * n0 * n2;
            grad(2, a) = ((a & 4) ? 1.0 : -1.0) / h[2] * n0 * n1;
          }
          for (int c = 0; c < 3; ++c) {
            const Eigen::Vector3d t = targets.frame[voxel].row(c).transpose();
            // Eq. 5.10 metric: alpha along the coordinate's own axis, 1 across it.
            const Eigen::Matrix3d metric = Eigen::Matrix3d::Identity() - (1.0 - alpha) * t * t.transpose();
            const Eigen::Matrix<double, 3, 8> mg = metric * grad;
            const Eigen::Matrix<double, 8, 8> local = grad.transpose() * mg;
            const Eigen::Matrix<double, 8, 1> load = mg.transpose() * (t / scale[c]);
            const Eigen::Matrix<double, 8, 8> plain = grad.transpose() * grad;
            const Eigen::Matrix<double, 8, 1> plain_load = grad.row(c).transpose() / scale[c];
            for (int a = 0; a < 8; ++a) {
              f[c][a] += weight * load[a] + pull * plain_load[a];
              for (int b = 0; b < 8; ++b) k[c][a][b] += weight * local(a, b) + pull * plain(a, b);
            }
          }
        }
        for (int c = 0; c < 3; ++c) scatter(g, s, c, ci, cj, ck, k[c], f[c]);
      }
}

// Node values at the identity: the boundary's for good, the interior's as the warm start.
std::array<Eigen::VectorXd, 3> identity_nodes(const Grid& g) {
  std::array<Eigen::VectorXd, 3> nodes;
  for (int c = 0; c < 3; ++c) {
    nodes[c].resize(static_cast<Eigen::Index>(g.num_nodes()));
    for (int kk = 0; kk < g.m[2]; ++kk)
      for (int jj = 0; jj < g.m[1]; ++jj)
        for (int ii = 0; ii < g.m[0]; ++ii) nodes[c][g.node(ii, jj, kk)] = g.identity(c, c == 0 ? ii : c == 1 ? jj : kk);
  }
  return nodes;
}

// Solves the three coordinates' systems from the interior node values (updated in place); adds
// the CG iterations to result and clears result.converged if a solve did not converge.
void solve_nodes(const Grid& g, const System& sys, const FieldAlignedOptions& options,
                 std::array<Eigen::VectorXd, 3>& nodes, FieldAlignedParam& result) {
  if (sys.unknowns == 0) return;
  // The three coordinates are independent systems: solved concurrently, combined in order.
  std::array<int, 3> iterations{};
  std::array<bool, 3> converged{};
  linalg::parallel_for(options.threads, 3, [&](int c) {
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_arrays(sys.unknowns, sys.unknowns, sys.row_offsets, sys.col_indices, sys.values[c]);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg(a);
    cg.set_tolerance(options.cg_tolerance).set_max_iterations(options.cg_max_iterations);
    Eigen::VectorXd x0(sys.unknowns);
    for (int kk = 1; kk < g.m[2] - 1; ++kk)
      for (int jj = 1; jj < g.m[1] - 1; ++jj)
        for (int ii = 1; ii < g.m[0] - 1; ++ii) x0[sys.unknown(g, ii, jj, kk)] = nodes[c][g.node(ii, jj, kk)];
    const Eigen::VectorXd x = cg.solve(sys.rhs[c], x0);
    iterations[c] = cg.iterations();
    converged[c] = cg.info() == linalg::SolverInfo::Success;
    for (int kk = 1; kk < g.m[2] - 1; ++kk)
      for (int jj = 1; jj < g.m[1] - 1; ++jj)
        for (int ii = 1; ii < g.m[0] - 1; ++ii) nodes[c][g.node(ii, jj, kk)] = x[sys.unknown(g, ii, jj, kk)];
  });
  for (int c = 0; c < 3; ++c) {
    result.cg_iterations += iterations[c];
    if (!converged[c]) result.converged = false;
  }
}

// The corner voxels of §5.3.1 (automatic or given), ascending, without repeats.
std::vector<std::size_t> chosen_corners(const FrameField& smoothed, const MaterialClassification& classes,
                                        const FieldAlignedOptions& options) {
  std::vector<std::size_t> corners;
  if (options.corner_selection == CornerSelection::Automatic)
    corners = detect_corners(smoothed, classes, options.corners);
  else if (options.corner_selection == CornerSelection::Given)
    corners = options.corner_voxels;
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  return corners;
}

// Corners whose parameters nearly agree on one coordinate (closer than tol in a sorted chain)
// share their mean: they land on one iso-plane.
void snap_corner_parameters(double tol, Eigen::MatrixX3d& corner_uvw) {
  const std::size_t num_corners = static_cast<std::size_t>(corner_uvw.rows());
  for (int c = 0; c < 3; ++c) {
    std::vector<std::pair<double, std::size_t>> sorted;
    for (std::size_t i = 0; i < num_corners; ++i) sorted.emplace_back(corner_uvw(static_cast<Eigen::Index>(i), c), i);
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t begin = 0; begin < sorted.size();) {
      std::size_t end = begin + 1;
      while (end < sorted.size() && sorted[end].first - sorted[end - 1].first < tol) ++end;
      double mean = 0.0;
      for (std::size_t i = begin; i < end; ++i) mean += sorted[i].first;
      mean /= static_cast<double>(end - begin);
      for (std::size_t i = begin; i < end; ++i) corner_uvw(static_cast<Eigen::Index>(sorted[i].second), c) = mean;
      begin = end;
    }
  }
}

// Corner constraints (§5.3.1 "additional constraints"), soft: a penalty of corner_weight times
// the system's mean diagonal pulls the trilinear value at each corner voxel to its parameter.
void add_corner_constraints(const Volume& volume, const Grid& g, double corner_weight,
                            const std::vector<std::size_t>& corner_voxels, const Eigen::MatrixX3d& corner_uvw, System& s) {
  for (int c = 0; c < 3; ++c) {
    double mean_diagonal = 0.0;
    for (int r = 0; r < s.unknowns; ++r) mean_diagonal += s.values[c][s.slot[static_cast<std::size_t>(r) * 27 + 13]];
    const double penalty = corner_weight * (s.unknowns > 0 ? mean_diagonal / s.unknowns : 1.0);
    for (std::size_t i = 0; i < corner_voxels.size(); ++i) {
      const std::size_t id = corner_voxels[i];
      const int pos[3] = {static_cast<int>(id % volume.nx), static_cast<int>((id / volume.nx) % volume.ny),
                          static_cast<int>(id / (static_cast<std::size_t>(volume.nx) * volume.ny))};
      int cell[3];
      double xi[3];
      for (int d = 0; d < 3; ++d) g.locate(d, pos[d], cell[d], xi[d]);
      double phi[8];
      for (int a = 0; a < 8; ++a)
        phi[a] = ((a & 1) ? xi[0] : 1 - xi[0]) * ((a & 2) ? xi[1] : 1 - xi[1]) * ((a & 4) ? xi[2] : 1 - xi[2]);
      double k[8][8];
      double f[8];
      const double target = corner_uvw(static_cast<Eigen::Index>(i), c);
      for (int a = 0; a < 8; ++a) {
        f[a] = penalty * phi[a] * target;
        for (int b = 0; b < 8; ++b) k[a][b] = penalty * phi[a] * phi[b];
      }
      scatter(g, s, c, cell[0], cell[1], cell[2], k, f);
    }
  }
}

// The fold fallback of compute_field_aligned_param on result.uvw = solution with folds.
void blend_folds_with_identity(const Volume& volume, const Eigen::MatrixX3d& solution, FieldAlignedParam& result) {
  const std::size_t n = volume.num_voxels();
  // Fold fallback, local: uvw = (1 - t) solution + t identity with t = 1 at the folded hexes'
  // voxels, falling linearly to 0 at `radius` voxels (Chebyshev); the radius doubles and new
  // folds add their own bumps until none is left; the last resort is the identity (t = 1).
  const int nx = volume.nx, ny = volume.ny, nz = volume.nz;
  const Eigen::MatrixX3d identity = identity_map(nx, ny, nz);
  std::vector<double> t(n, 0.0);
  std::vector<int> distance(n);
  std::vector<std::size_t> folded, front;
  int radius = 2;
  for (int round = 0; round < 8 && result.inverted_cells > 0; ++round, radius *= 2) {
    folded.clear();
    jacobian_check(nx, ny, nz, result.uvw, nullptr, &folded);
    std::fill(distance.begin(), distance.end(), -1);
    front.clear();
    for (std::size_t hex : folded)
      for (int corner = 0; corner < 8; ++corner) {
        const std::size_t id = hex + (corner & 1) + ((corner >> 1) & 1) * static_cast<std::size_t>(nx) +
                               ((corner >> 2) & 1) * static_cast<std::size_t>(nx) * ny;
        if (distance[id] < 0) {
          distance[id] = 0;
          front.push_back(id);
        }
      }
    grow_chebyshev_distance(nx, ny, nz, front, radius - 1, distance);
    for (std::size_t i = 0; i < n; ++i)
      if (distance[i] >= 0) t[i] = std::max(t[i], 1.0 - static_cast<double>(distance[i]) / radius);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Index r = static_cast<Eigen::Index>(i);
      result.uvw.row(r) = (1.0 - t[i]) * solution.row(r) + t[i] * identity.row(r);
    }
    result.min_jacobian = voxel_map_min_jacobian(nx, ny, nz, result.uvw, &result.inverted_cells);
  }
  if (result.inverted_cells > 0) {
    std::fill(t.begin(), t.end(), 1.0);
    result.uvw = identity;
    result.min_jacobian = voxel_map_min_jacobian(nx, ny, nz, result.uvw, &result.inverted_cells);
  }
  double sum = 0.0;
  for (double value : t) sum += value;
  result.identity_blend = sum / static_cast<double>(n);
}

}  // namespace

double voxel_map_min_jacobian(int nx, int ny, int nz, const Eigen::MatrixX3d& uvw, int* inverted) {
  return jacobian_check(nx, ny, nz, uvw, inverted, nullptr);
}

FieldAlignedParam compute_field_aligned_param(const Volume& volume, const FrameField& smoothed,
                                              const MaterialClassification& classes, const FieldAlignedOptions& options,
                                              const Progress& progress) {
  const std::size_t n = volume.num_voxels();
  check_options(options, n);
  if (volume.nx < 2 || volume.ny < 2 || volume.nz < 2)
    throw Error("field-aligned parameterization: every volume dimension must be >= 2");
  if (smoothed.nx != volume.nx || smoothed.ny != volume.ny || smoothed.nz != volume.nz || smoothed.frames.size() != n)
    throw Error("field-aligned parameterization: the frame field does not match the volume's grid");
  if (classes.nx != volume.nx || classes.ny != volume.ny || classes.nz != volume.nz || classes.label.size() != n)
    throw Error("field-aligned parameterization: the classification does not match the volume's grid");
  progress.report("parameterization", 0.0);

  FieldAlignedParam result;
  const Grid g = make_grid(volume, options);
  result.grid_nx = g.m[0];
  result.grid_ny = g.m[1];
  result.grid_nz = g.m[2];
  Targets targets = combed_targets(smoothed, classes);
  targets.reliability = frame_reliability(classes, options.reliability_radius);
  System s = make_system(g);
  assemble_alignment(volume, classes, targets, g, options, s);
  progress.report("parameterization", 0.3);

  std::array<Eigen::VectorXd, 3> nodes = identity_nodes(g);
  result.converged = true;
  solve_nodes(g, s, options, nodes, result);
  progress.report("parameterization", 0.6);

  // Corner constraints (§5.3.1 "additional constraints"): soft, at snapped parameters.
  result.corner_voxels = chosen_corners(smoothed, classes, options);
  const std::size_t num_corners = result.corner_voxels.size();
  result.corner_uvw.resize(static_cast<Eigen::Index>(num_corners), 3);
  if (num_corners > 0) {
    const Eigen::MatrixX3d before = interpolate(g, nodes);
    for (std::size_t c = 0; c < num_corners; ++c) result.corner_uvw.row(static_cast<Eigen::Index>(c)) = before.row(static_cast<Eigen::Index>(result.corner_voxels[c]));
    snap_corner_parameters(options.corner_snap_tol, result.corner_uvw);
    add_corner_constraints(volume, g, options.corner_weight, result.corner_voxels, result.corner_uvw, s);
    solve_nodes(g, s, options, nodes, result);
  }
  progress.report("parameterization", 0.9);

  // Per-voxel map, fold check, and the identity blend as the fallback.
  const Eigen::MatrixX3d solution = interpolate(g, nodes);
  result.uvw = solution;
  result.min_jacobian = voxel_map_min_jacobian(volume.nx, volume.ny, volume.nz, result.uvw, &result.inverted_cells);
  result.inverted_cells_unblended = result.inverted_cells;
  if (result.inverted_cells > 0) blend_folds_with_identity(volume, solution, result);
  const Eigen::MatrixX3d identity = identity_map(volume.nx, volume.ny, volume.nz);
  result.alignment_rms_deg = alignment_rms_deg(volume, classes, targets, result.uvw);
  result.alignment_rms_deg_identity = alignment_rms_deg(volume, classes, targets, identity);
  result.alignment_rms_deg_reliable = alignment_rms_deg(volume, classes, targets, result.uvw, 0.5);
  result.alignment_rms_deg_reliable_identity = alignment_rms_deg(volume, classes, targets, identity, 0.5);
  volume_ratio_range(volume.nx, volume.ny, volume.nz, result.uvw, result.volume_ratio_min, result.volume_ratio_max);
  progress.report("parameterization", 1.0);
  return result;
}

}  // namespace volspline::volume
