// SPDX-License-Identifier: MIT
#include "wasm/spline_quality_binding.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/LU>

#include "core/common/error.h"
#include "core/io/gpc_spline_io.h"
#include "core/io/mesh_io.h"
#include "core/io/spline_json.h"
#include "core/param/surface_distance.h"
#include "core/spline/gpc_boundary_tessellation.h"
#include "core/spline/gpc_jacobian_lattice.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"
#include "wasm/spline_preview.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

// det J / (|J_u| |J_v| |J_w|) at domain point x, in [−1, 1]; a collapsed direction counts as 0.
double scaled_jacobian_at(const spline::TSpline& spline, const Eigen::Vector3d& x, double* value) {
  double jacobian[9];
  spline.evaluate_with_jacobian(x, spline::TSplineForm::SemiStandard, value, jacobian);
  const Eigen::Map<const Eigen::Matrix3d> J(jacobian);
  const double scale = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
  return scale > 0 ? std::clamp(J.determinant() / scale, -1.0, 1.0) : 0.0;
}

// Per vertex of the boundary preview `xyz` (3 floats each), its distance to the mesh ÷ its bbox
// diagonal; sets boundary_distance_rel and max_distance_rel on `out`.
void set_boundary_distance(val& out, const std::vector<float>& xyz, const val& mesh_bytes, const std::string& mesh_name) {
  const mesh::TriangleMesh input = io::parse_mesh(bytes_from_js(mesh_bytes, "mesh '" + mesh_name + "'"),
                                                  io::mesh_format_from_path(mesh_name), mesh_name);
  const double diagonal = (input.positions.colwise().maxCoeff() - input.positions.colwise().minCoeff()).norm();
  if (!(diagonal > 0)) throw Error("mesh '" + mesh_name + "': its bounding box has no extent");
  const param::SurfaceDistance surface(input);
  std::vector<float> distance(xyz.size() / 3);
  double max_d = 0;
  for (std::size_t v = 0; v < distance.size(); ++v) {
    const double d = surface.distance(Eigen::Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2])) / diagonal;
    distance[v] = static_cast<float>(d);
    max_d = std::max(max_d, d);
  }
  out.set("boundary_distance_rel", float32_array(distance.data(), distance.size()));
  out.set("max_distance_rel", max_d);
}

// The quality views of a GPC spline: the lattice in every cuboid, the boundary of its surface faces.
val gpc_spline_quality(const std::string& text, const val& mesh_bytes, const std::string& mesh_name, int n, int bins,
                       int preview_samples, int preview_lines) {
  const spline::GpcSpline spline = io::parse_gpc_spline_json(text, "spline JSON");
  if (spline.dimension() != 3)
    throw Error("spline JSON: the quality views need a geometric spline (dimension 3), got dimension " +
                std::to_string(spline.dimension()));
  const spline::GpcJacobianLattice lattice = spline::sample_gpc_jacobian_lattice(spline, n);
  std::vector<double> counts(bins, 0.0);
  std::vector<float> folded;
  for (std::size_t s = 0; s < lattice.scaled_jacobian.size(); ++s) {
    const double q = lattice.scaled_jacobian[s];
    counts[std::clamp(static_cast<int>((q + 1.0) / 2.0 * bins), 0, bins - 1)] += 1;
    if (q <= 0) folded.insert(folded.end(), lattice.xyz.begin() + 3 * s, lattice.xyz.begin() + 3 * s + 3);
  }
  val out = val::object();
  out.set("ok", true);
  out.set("samples", double(lattice.scaled_jacobian.size()));
  out.set("cuboids", spline.num_cuboids());
  out.set("bins", bins);
  out.set("counts", float64_array(counts.data(), counts.size()));
  out.set("min_scaled_jacobian", lattice.min_scaled_jacobian);
  out.set("folded", float32_array(folded.data(), folded.size()));
  out.set("boundary_distance_rel", val::null());
  out.set("max_distance_rel", val::null());
  if (!mesh_bytes.isNull() && !mesh_bytes.isUndefined())
    set_boundary_distance(out, spline::tessellate_gpc_boundary(spline, preview_samples, preview_lines).surface_xyz,
                          mesh_bytes, mesh_name);
  return out;
}

}  // namespace

val spline_quality(const val& spline_json, const val& mesh_bytes, const std::string& mesh_name, const val& options) {
  return guarded([&] {
    const int n = integer_option(options, "lattice", 24, 2, 96);
    const int bins = integer_option(options, "bins", 20, 2, 200);
    const int preview_samples = integer_option(options, "preview_samples", 25, 2, 129);
    const int preview_lines = integer_option(options, "preview_lines", 9, 2, 65);
    const std::string text = bytes_from_js(spline_json, "spline JSON");
    if (io::is_gpc_spline_json(text))
      return gpc_spline_quality(text, mesh_bytes, mesh_name, n, bins, preview_samples, preview_lines);
    const spline::TSpline spline = io::parse_spline_json(text, "spline JSON");
    if (spline.dimension() != 3)
      throw Error("spline JSON: the quality views need a geometric spline (dimension 3), got dimension " +
                  std::to_string(spline.dimension()));

    std::vector<double> counts(bins, 0.0);
    std::vector<float> folded;
    double min_q = 1.0;
    const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
    double value[3];
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector3d unit((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
          const double q = scaled_jacobian_at(spline, lo + unit.cwiseProduct(hi - lo), value);
          min_q = std::min(min_q, q);
          counts[std::min(bins - 1, static_cast<int>((q + 1.0) / 2.0 * bins))] += 1;
          if (q <= 0)
            for (int d = 0; d < 3; ++d) folded.push_back(static_cast<float>(value[d]));
        }

    val out = val::object();
    out.set("ok", true);
    out.set("samples", n * n * n);
    out.set("bins", bins);
    out.set("counts", float64_array(counts.data(), counts.size()));
    out.set("min_scaled_jacobian", min_q);
    out.set("folded", float32_array(folded.data(), folded.size()));
    out.set("boundary_distance_rel", val::null());
    out.set("max_distance_rel", val::null());
    if (!mesh_bytes.isNull() && !mesh_bytes.isUndefined())
      set_boundary_distance(out, spline_preview(spline, preview_samples, preview_lines).surface_xyz, mesh_bytes, mesh_name);
    return out;
  });
}

}  // namespace volspline::wasm
