// SPDX-License-Identifier: MIT
#include "core/spline/node_jacobians.h"

#include <utility>

#include "core/spline/node_jacobians_avx2.h"

namespace volspline::spline::detail {

NodeJacobians::NodeJacobians(const std::vector<FreeFunction>& functions, const std::vector<int>& node_index,
                             std::array<int, 3> sizes, std::size_t num_nodes)
    : start_(num_nodes + 1, 0) {
#if defined(VOLSPLINE_AVX2_KERNELS)
  avx2_ = __builtin_cpu_supports("avx2");
#endif
  auto for_each_entry = [&](auto&& visit) {
    for (std::size_t c = 0; c < functions.size(); ++c) {
      const FreeFunction& f = functions[c];
      for (int k = 0; k < f.count[2]; ++k)
        for (int j = 0; j < f.count[1]; ++j)
          for (int i = 0; i < f.count[0]; ++i) {
            const Eigen::Vector3d g(f.slope[0][i] * f.value[1][j] * f.value[2][k],
                                    f.value[0][i] * f.slope[1][j] * f.value[2][k],
                                    f.value[0][i] * f.value[1][j] * f.slope[2][k]);
            if (g.isZero(0.0)) continue;
            const int node = f.first[0] + i + sizes[0] * (f.first[1] + j + sizes[1] * (f.first[2] + k));
            visit(node_index[node], static_cast<int>(c), g);
          }
    }
  };
  for_each_entry([&](int q, int, const Eigen::Vector3d&) { ++start_[q + 1]; });
  for (std::size_t q = 0; q < num_nodes; ++q) start_[q + 1] += start_[q];
  column_.resize(start_.back());
  gradient_.resize(3 * static_cast<std::size_t>(start_.back()));
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for_each_entry([&](int q, int c, const Eigen::Vector3d& g) {
    const int e = fill[q]++;
    column_[e] = c;
    for (int a = 0; a < 3; ++a) gradient_[3 * e + a] = static_cast<float>(g(a));
  });
}

NodeJacobians::NodeJacobians(std::vector<int> start, std::vector<int> column,
                             const std::vector<Eigen::Vector3d>& gradient)
    : start_(std::move(start)), column_(std::move(column)) {
#if defined(VOLSPLINE_AVX2_KERNELS)
  avx2_ = __builtin_cpu_supports("avx2");
#endif
  gradient_.resize(3 * gradient.size());
  for (std::size_t e = 0; e < gradient.size(); ++e)
    for (int a = 0; a < 3; ++a) gradient_[3 * e + a] = static_cast<float>(gradient[e](a));
}

void NodeJacobians::pad(const Eigen::VectorXd& x, std::vector<double>& x4) {
  x4.assign(x.size() / 3 * 4, 0.0);
  for (Eigen::Index c = 0; c < x.size() / 3; ++c)
    for (int r = 0; r < 3; ++r) x4[4 * c + r] = x(3 * c + r);
}

void NodeJacobians::unpad(const std::vector<double>& x4, Eigen::VectorXd& x) {
  for (Eigen::Index c = 0; c < x.size() / 3; ++c)
    for (int r = 0; r < 3; ++r) x(3 * c + r) = x4[4 * c + r];
}

Eigen::Matrix3d NodeJacobians::linear(const double* x4, std::size_t q) const {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
#if defined(VOLSPLINE_AVX2_KERNELS)
  if (avx2_) {
    node_rows_linear_avx2(column_.data(), gradient_.data(), start_[q], start_[q + 1], x4, m.data());
    return m;
  }
#endif
  for (int e = start_[q]; e < start_[q + 1]; ++e) {
    const float* g = gradient_.data() + 3 * e;
    const double* xc = x4 + 4 * column_[e];
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) m(r, a) += xc[r] * double(g[a]);
  }
  return m;
}

Eigen::Matrix3d scattered_linear(const int* column, const double* gradient, int begin, int end, const double* x4) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
#if defined(VOLSPLINE_AVX2_KERNELS)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) {
    scattered_linear_avx2(column, gradient, begin, end, x4, m.data());
    return m;
  }
#endif
  for (int e = begin; e < end; ++e) {
    const double* g = gradient + 3 * e;
    const double* xc = x4 + 4 * column[e];
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) m(r, a) += xc[r] * g[a];
  }
  return m;
}

void NodeJacobians::transform(std::size_t q, const Eigen::Matrix3d& s) {
  for (int e = start_[q]; e < start_[q + 1]; ++e) {
    float* g = gradient_.data() + 3 * e;
    const Eigen::Vector3d t = s.transpose() * Eigen::Vector3d(g[0], g[1], g[2]);
    for (int a = 0; a < 3; ++a) g[a] = static_cast<float>(t(a));
  }
}

void NodeJacobians::add_gradient(const Eigen::Matrix3d& d, std::size_t q, double* gradient4) const {
#if defined(VOLSPLINE_AVX2_KERNELS)
  if (avx2_) return node_rows_add_gradient_avx2(column_.data(), gradient_.data(), start_[q], start_[q + 1], d.data(), gradient4);
#endif
  for (int e = start_[q]; e < start_[q + 1]; ++e) {
    const float* g = gradient_.data() + 3 * e;
    Eigen::Map<Eigen::Vector3d>(gradient4 + 4 * column_[e]) +=
        d.col(0) * double(g[0]) + d.col(1) * double(g[1]) + d.col(2) * double(g[2]);
  }
}

}  // namespace volspline::spline::detail
