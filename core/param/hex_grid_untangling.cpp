// SPDX-License-Identifier: MIT
#include "core/param/hex_grid_untangling.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

#include <Eigen/LU>

#include "core/param/barrier_untangling.h"
#include "core/param/foldover_kernel.h"

namespace volspline::param {

namespace {

// Least σ of the ε update, as UntangleOptions::min_sigma.
constexpr double kMinSigma = 0.5;
// Steps without a new low of the folded corner count after which the continuation stops.
constexpr int kCountStallSteps = 3;

double barrier_chi(double d, double eps) { return 0.5 * (d + std::sqrt(eps * eps + d * d)); }

int node_id(const std::array<int, 3>& n, int i, int j, int k) { return i + n[0] * (j + n[1] * k); }

// Corner tetrahedron of a hex: the corner node, its three neighbours along the hex edges and the
// sign that turns each edge into the +axis direction.
struct Corner {
  std::array<int, 4> node;
  std::array<double, 3> sign;
  int hex;    // i + (n0 − 1)·(j + (n1 − 1)·k)
  int index;  // c
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
          corner.hex = i + (n[0] - 1) * (j + (n[1] - 1) * k);
          corner.index = c;
          for (int a = 0; a < 3; ++a) {
            const int o = c ^ (1 << a);
            corner.node[a + 1] = node_id(n, i + (o & 1), j + ((o >> 1) & 1), k + ((o >> 2) & 1));
            corner.sign[a] = ((c >> a) & 1) ? -1.0 : 1.0;
          }
          corners.push_back(corner);
        }
  return corners;
}

// The 8 corners of every hex of a hex list (node q at offset (q&1, q>>1&1, q>>2&1)).
std::vector<Corner> hex_mesh_corners(const std::vector<std::array<int, 8>>& hexes) {
  std::vector<Corner> corners;
  corners.reserve(8 * hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h)
    for (int c = 0; c < 8; ++c) {
      Corner corner;
      corner.node[0] = hexes[h][c];
      corner.hex = static_cast<int>(h);
      corner.index = c;
      for (int a = 0; a < 3; ++a) {
        corner.node[a + 1] = hexes[h][c ^ (1 << a)];
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
  // hex_nodes[h]: the 8 nodes of hex h (node q at offset (q&1, q>>1&1, q>>2&1)), h = Corner::hex.
  // sliding (or null): free nodes it flags sit at the projection of their variables onto a
  // surface or curve, and their gradient is taken in the tangent space there.
  Energy(const std::vector<std::array<int, 8>>& hex_nodes, std::vector<Corner> corners, std::vector<int> free_nodes,
         mesh::Positions& xyz, double h, double theta, const SlidingNodes* sliding,
         const std::vector<double>* hex_inv_h = nullptr)
      : corners_(std::move(corners)), free_(std::move(free_nodes)), xyz_(xyz), inv_h_(1.0 / h), theta_(theta),
        sliding_nodes_(sliding), hex_inv_h_(hex_inv_h) {
    var_of_.assign(xyz.rows(), -1);
    for (std::size_t v = 0; v < free_.size(); ++v) var_of_[free_[v]] = static_cast<int>(v);
    slide_of_var_.assign(free_.size(), -1);
    if (sliding)
      for (std::size_t v = 0; v < free_.size(); ++v)
        if (sliding->slides[free_[v]]) {
          slide_of_var_[v] = static_cast<int>(sliding_.size());
          sliding_.push_back(static_cast<int>(v));
          slide_tangent_.push_back(Eigen::Matrix3d::Zero());
        }
    projected_at_.assign(sliding_.size(), 0);
    slide_input_.assign(sliding_.size(), Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
    slide_point_.assign(sliding_.size(), Eigen::Vector3d::Zero());
    flat_.resize(3 * static_cast<std::size_t>(xyz.rows()));
    for (Eigen::Index v = 0; v < xyz.rows(); ++v)
      for (int d = 0; d < 3; ++d) flat_[3 * v + d] = xyz(v, d);
    // The terms grouped by hex, in order (all_corners lists a hex's 8 corners in a row).
    for (const Corner& c : corners_) {
      if (hexes_.empty() || hexes_.back().id != c.hex) {
        Hex hex;
        hex.id = c.hex;
        hex.inv_h = hex_inv_h_ ? (*hex_inv_h_)[c.hex] : inv_h_;
        for (int q = 0; q < 8; ++q) {
          hex.node[q] = hex_nodes[c.hex][q];
          hex.var[q] = var_of_[hex.node[q]];
        }
        hexes_.push_back(hex);
      }
      hexes_.back().corners |= 1u << c.index;
    }
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
    // Sliding nodes: the variables' projection onto the surface.
    for (std::size_t s = 0; s < sliding_.size(); ++s) project(s, x);
  }

  // The energy at x if it is at most bound, otherwise a value above bound: the sum over hexes
  // (in evaluate's order, so the same bits) stops once it passes bound, every corner term being
  // positive. Sliding nodes are projected as their first hex comes, so a stopped sum spares the
  // projections of the hexes after it (their nodes keep the unprojected variables until the next
  // evaluation).
  double evaluate_below(const Eigen::VectorXd& x, double eps, double bound) {
    for (std::size_t v = 0; v < free_.size(); ++v) {
      xyz_.row(free_[v]) = x.segment<3>(3 * v).transpose();
      for (int d = 0; d < 3; ++d) flat_[3 * static_cast<std::size_t>(free_[v]) + d] = x(3 * v + d);
    }
    ++evaluation_;
    const double eps2 = eps * eps, theta = theta_;
    auto gather = [&](const Hex& hex, double (*p)[3]) {
      for (int q = 0; q < 8; ++q) {
        const int s = hex.var[q] >= 0 ? slide_of_var_[hex.var[q]] : -1;
        if (s >= 0 && projected_at_[s] != evaluation_) {
          projected_at_[s] = evaluation_;
          project(s, x);
        }
        const double* src = flat_.data() + 3 * static_cast<std::size_t>(hex.node[q]);
        p[q][0] = src[0], p[q][1] = src[1], p[q][2] = src[2];
      }
    };
    double total = 0.0;
    const std::size_t num_hexes = hexes_.size();
    std::size_t i = 0;
    // Two hexes per kernel call; the second one's projections are wasted where the first one
    // passes the bound, and the next evaluation projects every sliding node anew.
    for (; i + 1 < num_hexes; i += 2) {
      const Hex& a = hexes_[i];
      const Hex& b = hexes_[i + 1];
      double pa[8][3], pb[8][3], ea[8], eb[8];
      gather(a, pa);
      gather(b, pb);
      corner_terms2(a, b, pa, pb, eps2, theta, ea, eb, nullptr, nullptr);
      for (int c = 0; c < 8; ++c)
        if (a.corners & (1u << c)) total += ea[c];
      if (total > bound) return total;
      for (int c = 0; c < 8; ++c)
        if (b.corners & (1u << c)) total += eb[c];
      if (total > bound) return total;
    }
    if (i < num_hexes) {
      const Hex& hex = hexes_[i];
      double p[8][3], e[8];
      gather(hex, p);
      detail::hex_corner_terms(p, hex.inv_h, eps2, theta, hex.corners, e, nullptr);
      for (int c = 0; c < 8; ++c)
        if (hex.corners & (1u << c)) total += e[c];
    }
    return total;
  }

  // The sliding nodes' variables set to the points the last evaluation projected them to (the
  // same energy and gradient): HexGridUntangleOptions::settle_sliding.
  void settle(Eigen::VectorXd& x) const {
    for (int v : sliding_) x.segment<3>(3 * v) = xyz_.row(free_[v]).transpose();
  }

  // Smallest normalized corner determinant at the current positions.
  double min_det() const {
    double worst = std::numeric_limits<double>::infinity();
    for (const Corner& c : corners_) worst = std::min(worst, jacobian(c).determinant());
    return worst;
  }

  // min_det and num_inverted from one pass over the corners.
  double min_det_and_inverted(int* inverted) const {
    double worst = std::numeric_limits<double>::infinity();
    int count = 0;
    for (const Corner& c : corners_) {
      const double det = jacobian(c).determinant();
      worst = std::min(worst, det);
      count += det <= 0.0;
    }
    *inverted = count;
    return worst;
  }

  // Energy at x (set as the free node positions) with barrier parameter eps; gradient if asked.
  // Per hex (hex_corner_kernel, two hexes a call): the 12 edges are formed once, the 8 corner terms computed side
  // by side, and the 8 node gradients written once.
  double evaluate(const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient) {
    set_variables(x);
    if (gradient) gradient->setZero(num_variables());
    double* g_out = gradient ? gradient->data() : nullptr;
    const double eps2 = eps * eps, theta = theta_;
    auto gather = [&](const Hex& hex, double (*p)[3]) {
      for (int q = 0; q < 8; ++q) {
        const double* src = flat_.data() + 3 * static_cast<std::size_t>(hex.node[q]);
        p[q][0] = src[0], p[q][1] = src[1], p[q][2] = src[2];
      }
    };
    double total = 0.0;
    auto add = [&](const Hex& hex, const double* e, const double (*node_grad)[3]) {
      for (int c = 0; c < 8; ++c)
        if (hex.corners & (1u << c)) total += e[c];
      if (!g_out) return;
      for (int q = 0; q < 8; ++q) {
        if (hex.var[q] < 0) continue;
        double* dst = g_out + 3 * static_cast<std::size_t>(hex.var[q]);
        dst[0] += node_grad[q][0], dst[1] += node_grad[q][1], dst[2] += node_grad[q][2];
      }
    };
    const std::size_t num_hexes = hexes_.size();
    std::size_t i = 0;
    for (; i + 1 < num_hexes; i += 2) {
      const Hex& a = hexes_[i];
      const Hex& b = hexes_[i + 1];
      double pa[8][3], pb[8][3], ea[8], eb[8], ga[8][3], gb[8][3];
      gather(a, pa);
      gather(b, pb);
      corner_terms2(a, b, pa, pb, eps2, theta, ea, eb, g_out ? ga : nullptr, g_out ? gb : nullptr);
      add(a, ea, ga);
      add(b, eb, gb);
    }
    if (i < num_hexes) {
      const Hex& hex = hexes_[i];
      double p[8][3], e[8], node_grad[8][3];
      gather(hex, p);
      detail::hex_corner_terms(p, hex.inv_h, eps2, theta, hex.corners, e, g_out ? node_grad : nullptr);
      add(hex, e, node_grad);
    }
    if (g_out)
      for (std::size_t s = 0; s < sliding_.size(); ++s) {
        Eigen::Map<Eigen::Vector3d> g(g_out + 3 * static_cast<std::size_t>(sliding_[s]));
        g = slide_tangent_[s] * Eigen::Vector3d(g);
      }
    return total;
  }

 private:
  // Sliding node s placed at the projection of its variables in x. The projection depends on
  // the point alone, so a point projected last time (the line search's accepted trial evaluated
  // again with its gradient, a step's end and the next step's start) takes the stored result.
  void project(std::size_t s, const Eigen::VectorXd& x) {
    const int v = sliding_[s];
    const Eigen::Vector3d target = x.segment<3>(3 * v);
    if (!(target == slide_input_[s])) {
      slide_point_[s] = sliding_nodes_->project(free_[v], target, &slide_tangent_[s]);
      slide_input_[s] = target;
    }
    const Eigen::Vector3d& p = slide_point_[s];
    xyz_.row(free_[v]) = p.transpose();
    for (int d = 0; d < 3; ++d) flat_[3 * static_cast<std::size_t>(free_[v]) + d] = p(d);
  }

  // corner_edges(c, xyz) · (1/h), from the flat positions.
  Eigen::Matrix3d jacobian(const Corner& c) const {
    Eigen::Matrix3d j;
    const double scale = hex_inv_h_ ? (*hex_inv_h_)[c.hex] : inv_h_;
    const double* base = flat_.data() + 3 * static_cast<std::size_t>(c.node[0]);
    for (int a = 0; a < 3; ++a) {
      const double* other = flat_.data() + 3 * static_cast<std::size_t>(c.node[a + 1]);
      for (int d = 0; d < 3; ++d) j(d, a) = c.sign[a] * (other[d] - base[d]) * scale;
    }
    return j;
  }

  // A hex with at least one term: its 8 nodes (node q at offset (q&1, q>>1&1, q>>2&1)), their
  // variable ids (−1 if fixed) and a bit per corner term.
  struct Hex {
    int id = -1;
    double inv_h = 0.0;  // 1 / the edge of its reference cube
    std::array<int, 8> node{};
    std::array<int, 8> var{};
    unsigned corners = 0;
  };

  // Hexes a and b (their node positions pa, pb) through one two-hex kernel call.
  static void corner_terms2(const Hex& a, const Hex& b, const double (*pa)[3], const double (*pb)[3], double eps2,
                            double theta, double* ea, double* eb, double (*ga)[3], double (*gb)[3]) {
    const double(*p[2])[3] = {pa, pb};
    const double inv_h[2] = {a.inv_h, b.inv_h};
    const unsigned corners[2] = {a.corners, b.corners};
    double* const e[2] = {ea, eb};
    double(*const g[2])[3] = {ga, gb};
    detail::hex_corner_terms2(p, inv_h, eps2, theta, corners, e, g);
  }

  std::vector<Corner> corners_;
  std::vector<Hex> hexes_;
  std::vector<int> free_;
  mesh::Positions& xyz_;
  std::vector<int> var_of_;
  std::vector<int> sliding_;                   // variables of sliding nodes
  std::vector<int> slide_of_var_;              // per variable: its index in sliding_, or −1
  std::vector<std::uint64_t> projected_at_;    // per sliding node: the evaluate_below call that projected it last
  std::uint64_t evaluation_ = 0;
  std::vector<Eigen::Matrix3d> slide_tangent_;  // projector onto each one's tangent space there
  std::vector<Eigen::Vector3d> slide_input_;    // per sliding node: the point projected last (NaN: none)
  std::vector<Eigen::Vector3d> slide_point_;    // and its projection
  std::vector<double> flat_;
  double inv_h_;
  double theta_;
  const SlidingNodes* sliding_nodes_ = nullptr;
  const std::vector<double>* hex_inv_h_ = nullptr;  // per hex id, or null: inv_h_ for all
};

// One round of the ε continuation of Garanzha et al. 2021 (§3) with untangle's update and stop
// rules; the free nodes shrink after each step to those within `rings` of a hex still folded:
// most folds open in the first steps, and the remaining steps sharpen the barrier around a few.
// `region` holds the first step's free region on entry; `first_region` gets it.
// count_inverted(seeds) counts the folded movable corners (and marks their hexes' nodes in
// *seeds if not null); dilate(region, rings) grows a node set. Reports before each step as the
// fraction (round · max_steps + step) / (rounds · max_steps).
template <class CountInverted, class Dilate>
void continuation_round(const std::vector<std::array<int, 8>>& hex_nodes, const std::vector<Corner>& corners,
                        const std::vector<char>& fixed, mesh::Positions& xyz, double h,
                        const HexGridUntangleOptions& options, int rings, std::vector<char>& region,
                        std::vector<char>& is_free, std::vector<char>& first_region, HexGridUntangleReport& report,
                        const CountInverted& count_inverted, const Dilate& dilate, const SlidingNodes* sliding,
                        int round, const Progress& progress, const std::vector<double>& hex_inv_h = {}) {
  const int total = static_cast<int>(xyz.rows());
  std::unique_ptr<Energy> energy;
  UntangleProblem problem;
  problem.energy = [&](const Eigen::VectorXd& v, double eps, Eigen::VectorXd* g) { return energy->evaluate(v, eps, g); };
  problem.energy_below = [&](const Eigen::VectorXd& v, double eps, double bound) {
    return energy->evaluate_below(v, eps, bound);
  };
  if (sliding && options.settle_sliding) problem.settle = [&](Eigen::VectorXd& v) { energy->settle(v); };
  double eps = 0.0, previous_eps = 0.0, e_prev = 0.0, best_d_min = -std::numeric_limits<double>::infinity();
  int stalled = 0, best_count = std::numeric_limits<int>::max(), count_stalled = 0, count = 1;
  for (int step = 0; step < options.max_steps; ++step) {
    progress.report("grid untangling", double(round * options.max_steps + step) / (options.rounds * options.max_steps));
    if (step > 0 && count > 0) {
      std::fill(region.begin(), region.end(), 0);
      count_inverted(&region);
      dilate(region, rings);
    } else if (step > 0) {
      region = first_region;  // all unfolded: settle the whole region, as untangle would
    }
    std::vector<int> free_nodes;
    bool changed = !energy;
    for (int v = 0; v < total; ++v) {
      const char now = region[v] && !fixed[v];
      changed = changed || now != is_free[v];
      is_free[v] = now;
      if (now) free_nodes.push_back(v);
    }
    if (free_nodes.empty()) break;
    if (step == 0) {
      report.free_nodes = static_cast<int>(free_nodes.size());
      first_region = region;
    }
    if (changed) {
      auto is_term = [&](const Corner& c) {
        return is_free[c.node[0]] || is_free[c.node[1]] || is_free[c.node[2]] || is_free[c.node[3]];
      };
      std::vector<Corner> terms;
      terms.reserve(std::count_if(corners.begin(), corners.end(), is_term));
      for (const Corner& c : corners)
        if (is_term(c)) terms.push_back(c);
      energy = std::make_unique<Energy>(hex_nodes, std::move(terms), std::move(free_nodes), xyz, h, options.volume_weight,
                                        sliding, hex_inv_h.empty() ? nullptr : &hex_inv_h);
    }
    Eigen::VectorXd x = energy->variables();
    if (step == 0) {
      const double d_min = energy->min_det();
      eps = d_min > 0.0 ? 1e-8 : first_barrier_eps(d_min);
      e_prev = energy->evaluate(x, eps, nullptr);
    } else if (changed) {
      e_prev = energy->evaluate(x, previous_eps, nullptr);  // the last step's energy on the new terms
    }
    // L-BFGS preconditioned by the hex-edge Laplacian was tried: it saves few iterations
    // (bunny 480 against 570; the folds are local barrier stiffness) and costs more each.
    // The energy at x is the one L-BFGS accepted it with; a settled x is evaluated anew.
    double e = 0.0;
    report.iterations += minimize_lbfgs(problem, eps, options.max_inner, x, &e);
    if (problem.settle)
      e = energy->evaluate(x, eps, nullptr);
    else
      energy->set_variables(x);
    const double d_min = energy->min_det_and_inverted(&count);
    const double sigma = std::max(1.0 - e / e_prev, kMinSigma);
    const double mu = (1.0 - sigma) * barrier_chi(d_min, eps);
    previous_eps = eps;
    eps = d_min < mu ? 2.0 * std::sqrt(mu * (mu - d_min)) : 1e-8;
    const bool settled = std::abs(e_prev - e) <= 1e-4 * std::abs(e);
    e_prev = e;
    if (d_min > 0.0 && settled) break;
    // As untangle: a corner that cannot unfold stops the continuation once the worst
    // determinant stops rising; and once the number of folded corners has not reached a new
    // low for kCountStallSteps steps (the worst determinant of such a corner creeps up for
    // many steps while the barrier sharpens).
    stalled = d_min > best_d_min + 1e-3 ? 0 : stalled + 1;
    best_d_min = std::max(best_d_min, d_min);
    count_stalled = count < best_count ? 0 : count_stalled + 1;
    best_count = std::min(best_count, count);
    if (d_min <= 0.0 && (stalled >= 4 || count_stalled >= kCountStallSteps)) break;
  }
}

}  // namespace

HexGridUntangleReport untangle_hex_grid(const std::array<int, 3>& n, const std::vector<char>& fixed,
                                        mesh::Positions& xyz, const HexGridUntangleOptions& options,
                                        const Progress& progress) {
  assert(n[0] >= 2 && n[1] >= 2 && n[2] >= 2);
  assert(static_cast<int>(fixed.size()) == n[0] * n[1] * n[2] && xyz.rows() == n[0] * n[1] * n[2]);
  assert(options.rings >= 1 && options.max_steps >= 1 && options.max_inner >= 1);
  assert(options.volume_weight >= 0.0 && options.volume_weight < 1.0);
  HexGridUntangleReport report;
  const std::vector<Corner> corners = all_corners(n);
  std::vector<std::array<int, 8>> hex_nodes((n[0] - 1) * (n[1] - 1) * (n[2] - 1));
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i)
        for (int q = 0; q < 8; ++q)
          hex_nodes[i + (n[0] - 1) * (j + (n[1] - 1) * k)][q] = node_id(n, i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
  auto movable = [&](const Corner& c) {
    return !fixed[c.node[0]] || !fixed[c.node[1]] || !fixed[c.node[2]] || !fixed[c.node[3]];
  };
  // Reference cell: a cube of the mean corner volume, so that det J ≈ 1 on average (the volume
  // term then asks for cells of even size).
  double mean_det = 0.0;
  for (const Corner& c : corners) mean_det += corner_edges(c, xyz).determinant() / corners.size();
  const double h = std::cbrt(std::max(mean_det, 1e-300));
  // Per corner (corners[8h + c] is corner c of hex h): folded and movable, as at the last count.
  // A count recomputes only the corners of hexes with a node that moved since.
  std::vector<char> folded(corners.size(), 0);
  mesh::Positions counted;  // xyz at the last count (empty before the first)
  auto refresh_hex = [&](int hex) {
    for (int c = 0; c < 8; ++c) {
      const Corner& corner = corners[8 * static_cast<std::size_t>(hex) + c];
      folded[8 * static_cast<std::size_t>(hex) + c] =
          movable(corner) && !(corner_edges(corner, xyz).determinant() > 0.0);
    }
  };
  std::vector<int> hex_stamp(hex_nodes.size(), -1);
  int stamp = 0;
  auto count_inverted = [&](std::vector<char>* seeds) {
    if (counted.rows() != xyz.rows()) {
      for (std::size_t h = 0; h < hex_nodes.size(); ++h) refresh_hex(static_cast<int>(h));
    } else {
      ++stamp;
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i) {
            const int v = node_id(n, i, j, k);
            if (xyz(v, 0) == counted(v, 0) && xyz(v, 1) == counted(v, 1) && xyz(v, 2) == counted(v, 2)) continue;
            for (int hk = std::max(0, k - 1); hk <= std::min(n[2] - 2, k); ++hk)
              for (int hj = std::max(0, j - 1); hj <= std::min(n[1] - 2, j); ++hj)
                for (int hi = std::max(0, i - 1); hi <= std::min(n[0] - 2, i); ++hi) {
                  const int hex = hi + (n[0] - 1) * (hj + (n[1] - 1) * hk);
                  if (hex_stamp[hex] == stamp) continue;
                  hex_stamp[hex] = stamp;
                  refresh_hex(hex);
                }
          }
    }
    counted = xyz;
    int count = 0;
    for (std::size_t c = 0; c < corners.size(); ++c) {
      if (!folded[c]) continue;
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
  // Dilates the seeds by `rings` grid steps along each axis in turn (a Chebyshev ball).
  auto dilate = [&](std::vector<char>& region, int rings) {
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
  };
  std::vector<char> region(total, 0), is_free(total, 0);
  report.initial_inverted = report.final_inverted = count_inverted(&region);
  for (int round = 0, rings = options.rings, before = report.initial_inverted + 1;
       round < options.rounds && report.final_inverted > 0 && report.final_inverted < before; ++round, rings *= 2) {
    before = report.final_inverted;
    dilate(region, rings);
    // ε continuation of Garanzha et al. 2021 (§3) with untangle's update and stop rules, but the
    // free nodes shrink after each step to those within `rings` of a hex still folded: most
    // folds open in the first steps, and the remaining steps sharpen the barrier around a few.
    std::vector<char> first_region;
    continuation_round(hex_nodes, corners, fixed, xyz, h, options, rings, region, is_free, first_region, report,
                       count_inverted, dilate, nullptr, round, progress);
    std::fill(region.begin(), region.end(), 0);
    report.final_inverted = count_inverted(&region);
    // A larger region helps only folds that the region's border held: those with a movable node
    // outside the first step's region within `rings` steps of their hex (folds that appeared
    // during the round; a seed hex has its whole `rings` neighbourhood in that region).
    bool border_held = false;
    for (std::size_t c = 0; c < corners.size() && !border_held; ++c) {
      if (!movable(corners[c]) || corner_edges(corners[c], xyz).determinant() > 0.0) continue;
      const int hex = static_cast<int>(c / 8);
      const std::array<int, 3> lo = {hex % (n[0] - 1), (hex / (n[0] - 1)) % (n[1] - 1), hex / ((n[0] - 1) * (n[1] - 1))};
      for (int k = std::max(0, lo[2] - rings); k <= std::min(n[2] - 1, lo[2] + 1 + rings) && !border_held; ++k)
        for (int j = std::max(0, lo[1] - rings); j <= std::min(n[1] - 1, lo[1] + 1 + rings) && !border_held; ++j)
          for (int i = std::max(0, lo[0] - rings); i <= std::min(n[0] - 1, lo[0] + 1 + rings); ++i)
            if (!fixed[node_id(n, i, j, k)] && !first_region[node_id(n, i, j, k)]) {
              border_held = true;
              break;
            }
    }
    if (!border_held) break;
  }
  return report;
}

HexGridUntangleReport untangle_hex_mesh(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                                        mesh::Positions& xyz, const std::vector<char>& near,
                                        const HexGridUntangleOptions& options,
                                        const SlidingNodes* sliding, const Progress& progress) {
  assert(static_cast<Eigen::Index>(fixed.size()) == xyz.rows());
  assert(options.rings >= 1 && options.max_steps >= 1 && options.max_inner >= 1);
  HexGridUntangleReport report;
  const int total = static_cast<int>(xyz.rows());
  const std::vector<Corner> corners = hex_mesh_corners(hexes);
  auto movable = [&](const Corner& c) {
    return !fixed[c.node[0]] || !fixed[c.node[1]] || !fixed[c.node[2]] || !fixed[c.node[3]];
  };
  double mean_det = 0.0;
  for (const Corner& c : corners) mean_det += corner_edges(c, xyz).determinant() / corners.size();
  const double h = std::cbrt(std::max(mean_det, 1e-300));
  std::vector<double> hex_inv_h;
  if (options.reference == HexGridUntangleOptions::Reference::OwnCell) {
    hex_inv_h.resize(hexes.size());
    for (std::size_t q = 0; q < hexes.size(); ++q) {
      double length = 0.0;
      for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a)
          if (!(c >> a & 1)) length += (xyz.row(hexes[q][c | (1 << a)]) - xyz.row(hexes[q][c])).norm() / 12.0;
      hex_inv_h[q] = length > 0.0 ? 1.0 / length : 1.0 / h;
    }
  }
  // Hexes around each node, for growing regions by rings of hexes.
  std::vector<std::vector<int>> node_hexes(total);
  for (std::size_t q = 0; q < hexes.size(); ++q)
    for (int v : hexes[q]) node_hexes[v].push_back(static_cast<int>(q));
  auto dilate = [&](std::vector<char>& region, int rings) {
    for (int r = 0; r < rings; ++r) {
      std::vector<char> next = region;
      for (int v = 0; v < total; ++v)
        if (region[v])
          for (int q : node_hexes[v])
            for (int u : hexes[q]) next[u] = 1;
      region.swap(next);
    }
  };
  // Hexes with a node within `rings` of a `near` node may seed the free region.
  std::vector<char> seeding(hexes.size(), 1);
  if (!near.empty()) {
    std::vector<char> zone = near;
    dilate(zone, options.rings);
    for (std::size_t q = 0; q < hexes.size(); ++q) {
      seeding[q] = 0;
      for (int v : hexes[q]) seeding[q] = seeding[q] || zone[v];
    }
  }
  // Per corner (corners[8h + c] is corner c of hex h): folded, movable and of a seeding hex, as
  // at the last count. A count recomputes only the corners of hexes with a node that moved since
  // (the free region is a small part of the mesh).
  std::vector<char> folded(corners.size(), 0);
  mesh::Positions counted;  // xyz at the last count (empty before the first)
  std::vector<int> hex_stamp(hexes.size(), -1);
  int stamp = 0;
  auto refresh = [&](std::size_t c) {
    folded[c] = seeding[corners[c].hex] && movable(corners[c]) && !(corner_edges(corners[c], xyz).determinant() > 0.0);
  };
  auto count_inverted = [&](std::vector<char>* seeds) {
    if (counted.rows() != xyz.rows()) {
      for (std::size_t c = 0; c < corners.size(); ++c) refresh(c);
    } else {
      ++stamp;
      for (int v = 0; v < total; ++v) {
        if (xyz(v, 0) == counted(v, 0) && xyz(v, 1) == counted(v, 1) && xyz(v, 2) == counted(v, 2)) continue;
        for (int q : node_hexes[v]) {
          if (hex_stamp[q] == stamp) continue;
          hex_stamp[q] = stamp;
          for (int c = 0; c < 8; ++c) refresh(8 * static_cast<std::size_t>(q) + c);
        }
      }
    }
    counted = xyz;
    int count = 0;
    for (std::size_t c = 0; c < corners.size(); ++c) {
      if (!folded[c]) continue;
      ++count;
      if (seeds)
        for (int v : hexes[corners[c].hex]) (*seeds)[v] = 1;
    }
    return count;
  };
  std::vector<char> region(total, 0), is_free(total, 0);
  report.initial_inverted = report.final_inverted = count_inverted(&region);
  // The ε continuation of untangle_hex_grid, with regions grown over shared hexes.
  for (int round = 0, rings = options.rings, before = report.initial_inverted + 1;
       round < options.rounds && report.final_inverted > 0 && report.final_inverted < before; ++round, rings *= 2) {
    before = report.final_inverted;
    std::fill(region.begin(), region.end(), 0);
    count_inverted(&region);
    dilate(region, rings);
    std::vector<char> first_region;
    continuation_round(hexes, corners, fixed, xyz, h, options, rings, region, is_free, first_region, report,
                       count_inverted, dilate, sliding, round, progress, hex_inv_h);
    report.final_inverted = count_inverted(nullptr);
  }
  return report;
}

int improve_hex_mesh(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                     mesh::Positions& xyz, int iterations, double volume_weight, const SlidingNodes* sliding) {
  assert(static_cast<Eigen::Index>(fixed.size()) == xyz.rows() && iterations >= 1);
  const int total = static_cast<int>(xyz.rows());
  const std::vector<Corner> corners = hex_mesh_corners(hexes);
  std::vector<char> touched(total, 0);
  for (const auto& hex : hexes)
    for (int v : hex) touched[v] = 1;
  double mean_det = 0.0;
  for (const Corner& c : corners) mean_det += corner_edges(c, xyz).determinant() / corners.size();
  const double h = std::cbrt(std::max(mean_det, 1e-300));
  std::vector<int> free_nodes;
  for (int v = 0; v < total; ++v)
    if (touched[v] && !fixed[v]) free_nodes.push_back(v);
  if (free_nodes.empty()) return 0;
  std::vector<Corner> terms;
  for (const Corner& c : corners)
    if (!fixed[c.node[0]] || !fixed[c.node[1]] || !fixed[c.node[2]] || !fixed[c.node[3]]) terms.push_back(c);
  Energy energy(hexes, std::move(terms), std::move(free_nodes), xyz, h, volume_weight, sliding);
  if (energy.min_det() <= 0.0) return 0;
  UntangleProblem problem;
  problem.energy = [&](const Eigen::VectorXd& v, double eps, Eigen::VectorXd* g) { return energy.evaluate(v, eps, g); };
  problem.energy_below = [&](const Eigen::VectorXd& v, double eps, double bound) {
    return energy.evaluate_below(v, eps, bound);
  };
  Eigen::VectorXd x = energy.variables();
  const int done = minimize_lbfgs(problem, 1e-8, iterations, x);
  energy.set_variables(x);
  return done;
}

}  // namespace volspline::param
