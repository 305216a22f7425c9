// SPDX-License-Identifier: MIT
#include "core/param/hex_grid_untangling.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/LU>

#include "core/param/barrier_untangling.h"

namespace volspline::param {

namespace {

int node_id(const std::array<int, 3>& n, int i, int j, int k) { return i + n[0] * (j + n[1] * k); }

// Corner tetrahedron of a hex: the corner node, its three neighbours along the hex edges and the
// sign that turns each edge into the +axis direction.
struct Corner {
  std::array<int, 4> node;
  std::array<double, 3> sign;
};

std::vector<Corner> all_corners(const std::array<int, 3>& n) {
  std::vector<Corner> corners;
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i)
        for (int c = 0; c < 8; ++c) {
          Corner corner;
          const int ci = i + (c & 1), cj = j + ((c >> 1) & 1), ck = k + ((c >> 2) & 1);
          corner.node[0] = node_id(n, ci, cj, ck);
          for (int a = 0; a < 3; ++a) {
            const int o = c ^ (1 << a);
            corner.node[a + 1] = node_id(n, i + (o & 1), j + ((o >> 1) & 1), k + ((o >> 2) & 1));
            corner.sign[a] = ((c >> a) & 1) ? -1.0 : 1.0;
          }
          corners.push_back(corner);
        }
  return corners;
}

Eigen::Matrix3d corner_edges(const Corner& c, const mesh::Positions& xyz) {
  Eigen::Matrix3d e;
  for (int a = 0; a < 3; ++a) e.col(a) = c.sign[a] * (xyz.row(c.node[a + 1]) - xyz.row(c.node[0])).transpose();
  return e;
}

// The untangling energy of the corners that touch a free node, as a function of the free nodes.
// Positions are kept in one flat array (x, y, z per node) so that a corner reads 12 adjacent
// doubles; the arithmetic is that of corner_edges, so results do not depend on the layout.
class Energy {
 public:
  Energy(std::vector<Corner> corners, std::vector<int> free_nodes, mesh::Positions& xyz, double h, double theta)
      : corners_(std::move(corners)), free_(std::move(free_nodes)), xyz_(xyz), inv_h_(1.0 / h), theta_(theta) {
    var_of_.assign(xyz.rows(), -1);
    for (std::size_t v = 0; v < free_.size(); ++v) var_of_[free_[v]] = static_cast<int>(v);
    flat_.resize(3 * static_cast<std::size_t>(xyz.rows()));
    for (Eigen::Index v = 0; v < xyz.rows(); ++v)
      for (int d = 0; d < 3; ++d) flat_[3 * v + d] = xyz(v, d);
  }

  int num_variables() const { return 3 * static_cast<int>(free_.size()); }

  Eigen::VectorXd variables() const {
    Eigen::VectorXd x(num_variables());
    for (std::size_t v = 0; v < free_.size(); ++v) x.segment<3>(3 * v) = xyz_.row(free_[v]).transpose();
    return x;
  }

  void set_variables(const Eigen::VectorXd& x) {
    for (std::size_t v = 0; v < free_.size(); ++v) {
      xyz_.row(free_[v]) = x.segment<3>(3 * v).transpose();
      for (int d = 0; d < 3; ++d) flat_[3 * static_cast<std::size_t>(free_[v]) + d] = x(3 * v + d);
    }
  }

  // Smallest normalized corner determinant at the current positions.
  double min_det() const {
    double worst = std::numeric_limits<double>::infinity();
    for (const Corner& c : corners_) worst = std::min(worst, jacobian(c).determinant());
    return worst;
  }

  // Energy at x (set as the free node positions) with barrier parameter eps; gradient if asked.
  double evaluate(const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient) {
    set_variables(x);
    if (gradient) gradient->setZero(num_variables());
    double total = 0.0;
    Eigen::Matrix3d df;
    for (const Corner& c : corners_) {
      total += foldover_free_energy(jacobian(c), eps, theta_, gradient ? &df : nullptr);
      if (!gradient) continue;
      const int vc = var_of_[c.node[0]];
      for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d g = c.sign[a] * inv_h_ * df.col(a);
        const int vo = var_of_[c.node[a + 1]];
        if (vo >= 0) gradient->segment<3>(3 * vo) += g;
        if (vc >= 0) gradient->segment<3>(3 * vc) -= g;
      }
    }
    return total;
  }

 private:
  // corner_edges(c, xyz) · (1/h), from the flat positions.
  Eigen::Matrix3d jacobian(const Corner& c) const {
    Eigen::Matrix3d j;
    const double* base = flat_.data() + 3 * static_cast<std::size_t>(c.node[0]);
    for (int a = 0; a < 3; ++a) {
      const double* other = flat_.data() + 3 * static_cast<std::size_t>(c.node[a + 1]);
      for (int d = 0; d < 3; ++d) j(d, a) = c.sign[a] * (other[d] - base[d]) * inv_h_;
    }
    return j;
  }

  std::vector<Corner> corners_;
  std::vector<int> free_;
  mesh::Positions& xyz_;
  std::vector<int> var_of_;
  std::vector<double> flat_;
  double inv_h_;
  double theta_;
};

}  // namespace

HexGridUntangleReport untangle_hex_grid(const std::array<int, 3>& n, const std::vector<char>& fixed,
                                        mesh::Positions& xyz, const HexGridUntangleOptions& options) {
  assert(n[0] >= 2 && n[1] >= 2 && n[2] >= 2);
  assert(static_cast<int>(fixed.size()) == n[0] * n[1] * n[2] && xyz.rows() == n[0] * n[1] * n[2]);
  assert(options.rings >= 1 && options.max_steps >= 1 && options.max_inner >= 1);
  assert(options.volume_weight >= 0.0 && options.volume_weight < 1.0);
  HexGridUntangleReport report;
  const std::vector<Corner> corners = all_corners(n);
  auto movable = [&](const Corner& c) {
    return !fixed[c.node[0]] || !fixed[c.node[1]] || !fixed[c.node[2]] || !fixed[c.node[3]];
  };
  // Reference cell: a cube of the mean corner volume, so that det J ≈ 1 on average (the volume
  // term then asks for cells of even size).
  double mean_det = 0.0;
  for (const Corner& c : corners) mean_det += corner_edges(c, xyz).determinant() / corners.size();
  const double h = std::cbrt(std::max(mean_det, 1e-300));
  auto count_inverted = [&](std::vector<char>* seeds) {
    int count = 0;
    for (std::size_t c = 0; c < corners.size(); ++c) {
      if (!movable(corners[c]) || corner_edges(corners[c], xyz).determinant() > 0.0) continue;
      ++count;
      if (!seeds) continue;
      // All 8 nodes of the corner's hex seed the free region.
      const int hex = static_cast<int>(c / 8);
      const int i = hex % (n[0] - 1), j = (hex / (n[0] - 1)) % (n[1] - 1), k = hex / ((n[0] - 1) * (n[1] - 1));
      for (int q = 0; q < 8; ++q) (*seeds)[node_id(n, i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1))] = 1;
    }
    return count;
  };
  const int total = n[0] * n[1] * n[2];
  std::vector<char> region(total, 0);
  report.initial_inverted = report.final_inverted = count_inverted(&region);
  for (int round = 0, rings = options.rings, before = report.initial_inverted + 1;
       round < 3 && report.final_inverted > 0 && report.final_inverted < before; ++round, rings *= 2) {
    before = report.final_inverted;
    // Dilate the seeds by `rings` grid steps along each axis in turn (a Chebyshev ball).
    for (int a = 0; a < 3; ++a) {
      std::vector<char> next = region;
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i) {
            if (!region[node_id(n, i, j, k)]) continue;
            std::array<int, 3> p = {i, j, k};
            const int centre = p[a];
            for (int q = std::max(0, centre - rings); q <= std::min(n[a] - 1, centre + rings); ++q) {
              p[a] = q;
              next[node_id(n, p[0], p[1], p[2])] = 1;
            }
          }
      region.swap(next);
    }
    std::vector<int> free_nodes;
    std::vector<char> is_free(total, 0);
    for (int v = 0; v < total; ++v)
      if (region[v] && !fixed[v]) {
        free_nodes.push_back(v);
        is_free[v] = 1;
      }
    std::vector<Corner> terms;
    for (const Corner& c : corners)
      if (is_free[c.node[0]] || is_free[c.node[1]] || is_free[c.node[2]] || is_free[c.node[3]]) terms.push_back(c);
    report.free_nodes = static_cast<int>(free_nodes.size());
    if (free_nodes.empty()) break;
    Energy energy(std::move(terms), std::move(free_nodes), xyz, h, options.volume_weight);
    Eigen::VectorXd x = energy.variables();
    UntangleProblem problem;
    problem.energy = [&](const Eigen::VectorXd& v, double eps, Eigen::VectorXd* g) { return energy.evaluate(v, eps, g); };
    problem.min_det = [&](const Eigen::VectorXd& v) {
      energy.set_variables(v);
      return energy.min_det();
    };
    UntangleOptions untangle_options;
    untangle_options.max_steps = options.max_steps;
    untangle_options.max_inner = options.max_inner;
    report.iterations += untangle(problem, x, untangle_options);
    energy.set_variables(x);
    std::fill(region.begin(), region.end(), 0);
    report.final_inverted = count_inverted(&region);
  }
  return report;
}

}  // namespace volspline::param
