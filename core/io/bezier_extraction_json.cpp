// SPDX-License-Identifier: MIT
#include "core/io/bezier_extraction_json.h"

#include <array>
#include <map>
#include <vector>

#include "core/io/number_text.h"
#include "core/spline/bspline_basis.h"

namespace volspline::io {

namespace {

// One cuboid's patch and how its functions map to the global ones.
struct PatchSource {
  int cuboid = 0;
  const spline::TSpline* patch = nullptr;
  const std::vector<int>* global_ids = nullptr;  // null: identity
  Eigen::Vector3d box_min, box_max;
};

void append_list(std::string& out, const double* values, int n) {
  out += '[';
  for (int i = 0; i < n; ++i) {
    if (i) out += ',';
    append_number(out, values[i]);
  }
  out += ']';
}

// Bernstein coefficients of the piece of N_r on [b, b'] (zero outside its support): Taylor
// coefficients at b in s = (t − b)/(b' − b), then b_i = Σ_{a≤i} C(i,a)/C(3,a)·c_a.
std::array<double, 4> piece_bernstein(const spline::LocalKnots& r, double b, double b1) {
  const int j = spline::cubic_basis_interval(r, 0.5 * (b + b1), spline::RightEnd::Open);
  if (j < 0) return {0.0, 0.0, 0.0, 0.0};
  const spline::BasisDerivatives d = spline::cubic_basis_piece_derivatives(r, j, b);
  const double h = b1 - b;
  const double c0 = d.value, c1 = d.d1 * h, c2 = d.d2 * h * h / 2.0, c3 = d.d3 * h * h * h / 6.0;
  return {c0, c0 + c1 / 3.0, c0 + 2.0 * c1 / 3.0 + c2 / 3.0, c0 + c1 + c2 + c3};
}

std::string serialize(const std::vector<PatchSource>& sources, const Eigen::MatrixXd& points,
                      const Eigen::VectorXd& weights) {
  std::map<std::array<double, 4>, int> row_id;
  std::vector<std::array<double, 4>> rows;
  auto row_of = [&](const std::array<double, 4>& r) {
    auto [it, inserted] = row_id.emplace(r, int(rows.size()));
    if (inserted) rows.push_back(r);
    return it->second;
  };
  std::string cells;
  std::vector<int> functions;
  bool first_cell = true;
  for (const PatchSource& src : sources) {
    const spline::TSpline& patch = *src.patch;
    for (int cell = 0; cell < patch.num_cells(); ++cell) {
      const std::array<int, 3> k = patch.cell_index(cell);
      double lo[3], hi[3];
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        lo[a] = patch.knot_lines(a)[k[a]];
        hi[a] = patch.knot_lines(a)[k[a] + 1];
        const double tol = 1e-9 * (src.box_max[a] - src.box_min[a]);
        inside = inside && lo[a] >= src.box_min[a] - tol && hi[a] <= src.box_max[a] + tol;
      }
      if (!inside) continue;
      patch.cell_functions(cell, functions);
      cells += first_cell ? "\n" : ",\n";
      first_cell = false;
      cells += "{\"cuboid\":";
      append_number(cells, (long long)src.cuboid);
      cells += ",\"uvw_min\":";
      append_list(cells, lo, 3);
      cells += ",\"uvw_max\":";
      append_list(cells, hi, 3);
      cells += ",\"functions\":[";
      for (std::size_t f = 0; f < functions.size(); ++f) {
        if (f) cells += ',';
        append_number(cells, (long long)(src.global_ids ? (*src.global_ids)[functions[f]] : functions[f]));
      }
      cells += "],\"extraction\":[";
      for (std::size_t f = 0; f < functions.size(); ++f) {
        if (f) cells += ',';
        cells += '[';
        for (int a = 0; a < 3; ++a) {
          if (a) cells += ',';
          append_number(cells, (long long)row_of(piece_bernstein(patch.knots()[functions[f]][a], lo[a], hi[a])));
        }
        cells += ']';
      }
      cells += "]}";
    }
  }
  const int D = int(points.cols());
  std::string out = "{\"format\":\"volspline-bezier-extraction\",\"version\":1,\"form\":\"semi-standard\",";
  out += "\"degree\":[3,3,3],\"dimension\":";
  append_number(out, (long long)D);
  out += ",\n\"control_points\":[";
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (i) out += ',';
    double p[4];
    for (int d = 0; d < D; ++d) p[d] = points(i, d);
    append_list(out, p, D);
  }
  out += "],\n\"weights\":";
  append_list(out, weights.data(), int(weights.size()));
  out += ",\n\"univariate\":[";
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (r) out += ',';
    append_list(out, rows[r].data(), 4);
  }
  out += "],\n\"cells\":[" + cells + "\n]}\n";
  return out;
}

}  // namespace

std::string serialize_bezier_extraction_json(const spline::TSpline& spline) {
  return serialize({{0, &spline, nullptr, spline.domain_min(), spline.domain_max()}}, spline.points(), spline.weights());
}

std::string serialize_bezier_extraction_json(const spline::GpcSpline& spline) {
  std::vector<PatchSource> sources;
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(spline.num_functions());
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& size = spline.domain().cuboids[c].size;
    sources.push_back({c, &spline.patch(c), &spline.patch_function_ids(c), Eigen::Vector3d::Zero(),
                       Eigen::Vector3d(size[0], size[1], size[2])});
    for (int i = 0; i < spline.patch(c).num_functions(); ++i)
      weights[spline.patch_function_ids(c)[i]] = spline.patch(c).weights()[i];
  }
  return serialize(sources, spline.points(), weights);
}

}  // namespace volspline::io
