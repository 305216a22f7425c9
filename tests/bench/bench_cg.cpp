// SPDX-License-Identifier: MIT
// Preconditioned CG of core/linalg against Eigen's ConjugateGradient on the same systems, the
// same preconditioner and the same relative tolerance. Prints JSON (medians of 5 runs).
//
// Systems:
//  - grid: 7-point Laplacian of a 47³ interior grid with Dirichlet boundary (103823 unknowns).
//  - bunny: cotan Laplacian of bunny_closed.obj plus μ·M (lumped vertex areas) with
//    μ = 1e-3·trace(L)/trace(M), which makes it SPD (a screened Poisson / implicit-smoothing
//    matrix); cotan weights are built here so the bench does not depend on core/mesh.
// Times: CPU time of the running thread (the build machine is shared), wall time as well.
// Right-hand side: fixed pseudo-random vector in [-1, 1]. x0 = 0. tolerance 1e-10.
// Eigen: SparseMatrix<double> (column-major, as the brief asks) with Lower|Upper; the
// row-major variant is reported too since its SpMV is a gather like ours. IC: Eigen's
// IncompleteCholesky is a different algorithm (Lin–Moré, column scaling, fill by magnitude),
// measured with natural ordering (closest to ours) and with its default AMD ordering.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <nlohmann/json.hpp>

#include "core/linalg/conjugate_gradient.h"
#include "tests/unit/linalg/test_systems.h"

namespace linalg = volspline::linalg;
using nlohmann::json;
using volspline::linalg::testing::pseudo_random_vector;

namespace {

constexpr int kRuns = 5;
constexpr double kTolerance = 1e-10;

double now_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

linalg::CsrMatrix grid_laplacian(int m) {
  const auto id = [m](int i, int j, int k) { return (k * m + j) * m + i; };
  std::vector<linalg::Triplet> t;
  t.reserve(static_cast<size_t>(7) * m * m * m);
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        const int v = id(i, j, k);
        if (k > 0) t.push_back({v, id(i, j, k - 1), -1.0});
        if (j > 0) t.push_back({v, id(i, j - 1, k), -1.0});
        if (i > 0) t.push_back({v, id(i - 1, j, k), -1.0});
        t.push_back({v, v, 6.0});
        if (i + 1 < m) t.push_back({v, id(i + 1, j, k), -1.0});
        if (j + 1 < m) t.push_back({v, id(i, j + 1, k), -1.0});
        if (k + 1 < m) t.push_back({v, id(i, j, k + 1), -1.0});
      }
    }
  }
  return linalg::CsrMatrix::from_triplets(m * m * m, m * m * m, t);
}

// Minimal OBJ reader: "v x y z" and "f a b c ..." (a/b/c forms, fan-triangulated).
bool read_obj(const std::string& path, std::vector<Eigen::Vector3d>& v,
              std::vector<std::array<int, 3>>& f) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      s >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> ids;
      std::string token;
      while (s >> token) ids.push_back(std::stoi(token.substr(0, token.find('/'))) - 1);
      for (size_t k = 2; k < ids.size(); ++k) f.push_back({ids[0], ids[k - 1], ids[k]});
    }
  }
  return !v.empty() && !f.empty();
}

linalg::CsrMatrix screened_cotan_laplacian(const std::vector<Eigen::Vector3d>& v,
                                           const std::vector<std::array<int, 3>>& f) {
  std::vector<linalg::Triplet> stiffness;
  std::vector<double> mass(v.size(), 0.0);
  for (const auto& tri : f) {
    const double area = 0.5 * (v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]).norm();
    for (int c = 0; c < 3; ++c) {
      const int i = tri[c], j = tri[(c + 1) % 3], k = tri[(c + 2) % 3];
      const Eigen::Vector3d e1 = v[j] - v[i], e2 = v[k] - v[i];
      const double w = 0.5 * e1.dot(e2) / e1.cross(e2).norm();
      stiffness.push_back({j, k, -w});
      stiffness.push_back({k, j, -w});
      stiffness.push_back({j, j, w});
      stiffness.push_back({k, k, w});
      mass[i] += area / 3.0;
    }
  }
  double trace_l = 0.0, trace_m = 0.0;
  for (const auto& t : stiffness) {
    if (t.row == t.col) trace_l += t.value;
  }
  for (double m : mass) trace_m += m;
  const double mu = 1e-3 * trace_l / trace_m;
  for (size_t i = 0; i < v.size(); ++i) {
    stiffness.push_back({static_cast<int>(i), static_cast<int>(i), mu * mass[i]});
  }
  const int n = static_cast<int>(v.size());
  return linalg::CsrMatrix::from_triplets(n, n, stiffness);
}

struct Measurement {
  std::vector<double> compute, solve, compute_wall, solve_wall;
  int iterations = 0;
  double residual = 0.0;  // true relative residual ‖b − A x‖/‖b‖
  Eigen::VectorXd x;
  double compute_ms() const { return median(compute); }
  double solve_ms() const { return median(solve); }
};

json to_json(const Measurement& m) {
  return {{"compute_ms", m.compute_ms()},
          {"solve_ms", m.solve_ms()},
          {"total_ms", m.compute_ms() + m.solve_ms()},
          {"wall_total_ms", median(m.compute_wall) + median(m.solve_wall)},
          {"iterations", m.iterations},
          {"residual_rel", m.residual}};
}

// One timed compute + solve; CPU time of this thread (the machine is shared, so wall time is
// noisy), wall time reported alongside.
template <class Solver, class Matrix>
void run_once(Solver& cg, const Matrix& a, const Eigen::VectorXd& b, Measurement& m) {
  const double c0 = cpu_ms(), w0 = now_ms();
  cg.compute(a);
  const double c1 = cpu_ms(), w1 = now_ms();
  m.x = cg.solve(b);
  const double c2 = cpu_ms(), w2 = now_ms();
  m.compute.push_back(c1 - c0);
  m.solve.push_back(c2 - c1);
  m.compute_wall.push_back(w1 - w0);
  m.solve_wall.push_back(w2 - w1);
  m.iterations = static_cast<int>(cg.iterations());
}

template <class P, class EigenP>
json compare(const std::string& name, const linalg::CsrMatrix& a,
             const Eigen::SparseMatrix<double>& col_major,
             const Eigen::SparseMatrix<double, Eigen::RowMajor>& row_major,
             const Eigen::VectorXd& b) {
  using ColSolver =
      Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, EigenP>;
  using RowSolver = Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>,
                                             Eigen::Lower | Eigen::Upper, EigenP>;
  Measurement ours, eigen, eigen_row;
  // Runs are interleaved so that all three see the same machine load.
  for (int run = 0; run < kRuns; ++run) {
    linalg::ConjugateGradient<P> cg;
    cg.set_tolerance(kTolerance);
    run_once(cg, a, b, ours);
    ours.residual = cg.residual();
    ColSolver ecg;
    ecg.setTolerance(kTolerance);
    run_once(ecg, col_major, b, eigen);
    RowSolver rcg;
    rcg.setTolerance(kTolerance);
    run_once(rcg, row_major, b, eigen_row);
  }
  eigen.residual = (b - col_major * eigen.x).norm() / b.norm();
  eigen_row.residual = (b - row_major * eigen_row.x).norm() / b.norm();
  const double total = ours.compute_ms() + ours.solve_ms();
  return {{"preconditioner", name},
          {"ours", to_json(ours)},
          {"eigen", to_json(eigen)},
          {"eigen_row_major", to_json(eigen_row)},
          {"ratio_total", total / (eigen.compute_ms() + eigen.solve_ms())},
          {"ratio_solve", ours.solve_ms() / eigen.solve_ms()},
          {"ratio_total_vs_row_major", total / (eigen_row.compute_ms() + eigen_row.solve_ms())},
          {"solution_difference_rel", (ours.x - eigen.x).norm() / eigen.x.norm()}};
}

json bench_system(const std::string& name, const linalg::CsrMatrix& a) {
  const Eigen::VectorXd b = pseudo_random_vector(a.rows(), 7);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> row_major = a.to_eigen();
  const Eigen::SparseMatrix<double> col_major = row_major;
  json cases = json::array();
  cases.push_back(compare<linalg::IdentityPreconditioner, Eigen::IdentityPreconditioner>(
      "identity", a, col_major, row_major, b));
  cases.push_back(compare<linalg::JacobiPreconditioner, Eigen::DiagonalPreconditioner<double>>(
      "jacobi", a, col_major, row_major, b));
  json ic = compare<linalg::IncompleteCholesky0,
                    Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>>>(
      "ic0 (Eigen: IncompleteCholesky natural ordering)", a, col_major, row_major, b);
  using EigenIcAmd = Eigen::ConjugateGradient<Eigen::SparseMatrix<double>,
                                              Eigen::Lower | Eigen::Upper,
                                              Eigen::IncompleteCholesky<double>>;
  Measurement amd;
  for (int run = 0; run < kRuns; ++run) {
    EigenIcAmd cg;
    cg.setTolerance(kTolerance);
    run_once(cg, col_major, b, amd);
  }
  amd.residual = (b - col_major * amd.x).norm() / b.norm();
  ic["eigen_ic_amd_ordering"] = to_json(amd);
  linalg::IncompleteCholesky0 probe;
  probe.compute(a);
  ic["ic0_shift"] = probe.shift();
  cases.push_back(ic);
  return {{"system", name}, {"unknowns", a.rows()}, {"nnz", a.nnz()}, {"cases", cases}};
}

}  // namespace

int main(int argc, char** argv) {
  json systems = json::array();
  systems.push_back(bench_system("grid_laplacian_47^3", grid_laplacian(47)));

  const std::string path = argc > 1 ? argv[1]
                                    : std::string(VOLSPLINE_SHARED_DATA) +
                                          "/meshes/bunny_closed.obj";
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  if (read_obj(path, v, f)) {
    systems.push_back(bench_system("bunny_cotan_plus_1e-3_mass", screened_cotan_laplacian(v, f)));
  } else {
    std::cerr << "bench_cg: cannot read " << path << ", skipping the mesh system\n";
  }
  const json out = {{"benchmark", "bench_cg"},
                    {"tolerance_rel", kTolerance},
                    {"runs", kRuns},
                    {"statistic", "median"},
                    {"iterations_note", "ours counts x updates; Eigen counts one less"},
                    {"systems", systems}};
  std::cout << out.dump(2) << "\n";
  return 0;
}
