// SPDX-License-Identifier: MIT
#include "wasm/mesh_info_binding.h"

#include <cstdint>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

val vector3(const Eigen::Vector3d& v) {
  val out = val::array();
  for (int k = 0; k < 3; ++k) out.call<void>("push", v[k]);
  return out;
}

}  // namespace

val mesh_info(const val& bytes, const std::string& name) {
  return guarded([&] {
    const std::string data = bytes_from_js(bytes, "mesh '" + name + "'");
    const io::MeshFormat format = io::mesh_format_from_path(name);
    const mesh::HalfedgeMesh halfedges = mesh::HalfedgeMesh::build(io::parse_mesh(data, format, name), name);
    const mesh::MeshReport r = mesh::analyze_mesh(halfedges);

    val out = val::object();
    out.set("ok", true);
    out.set("vertices", r.num_vertices);
    out.set("faces", r.num_faces);
    out.set("edges", r.num_edges);
    out.set("closed", r.closed);
    out.set("manifold", r.manifold);
    out.set("boundary_loops", r.num_boundary_loops);
    out.set("components", r.num_components);
    out.set("consistently_oriented", r.consistently_oriented);
    out.set("degenerate_faces", r.num_degenerate_faces);
    out.set("euler_characteristic", r.euler_characteristic);
    out.set("genus", r.genus >= 0 ? val(r.genus) : val::null());
    out.set("signed_volume", r.signed_volume);
    out.set("bbox_min", vector3(r.bbox_min));
    out.set("bbox_max", vector3(r.bbox_max));

    // The viewer draws in single precision: halve the transfer size.
    const mesh::Positions& p = halfedges.positions();
    const std::vector<float> positions(p.data(), p.data() + p.size());
    out.set("positions", float32_array(positions.data(), positions.size()));
    const mesh::Triangles& t = halfedges.triangles();
    const std::vector<std::uint32_t> triangles(t.data(), t.data() + t.size());
    out.set("triangles", uint32_array(triangles.data(), triangles.size()));
    return out;
  });
}

}  // namespace volspline::wasm
