// SPDX-License-Identifier: MIT
#include "core/io/mesh_io.h"

#include <cstdio>
#include <filesystem>

#include <doctest/doctest.h>

#include "core/io/file_bytes.h"
#include "tests/unit/common/test_meshes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

TEST_CASE("mesh_io: format from extension, case-insensitive") {
  CHECK(mesh_format_from_path("a/b.OBJ") == MeshFormat::Obj);
  CHECK(mesh_format_from_path("x.off") == MeshFormat::Off);
  CHECK(mesh_format_from_path("x.Ply") == MeshFormat::Ply);
  CHECK(mesh_format_from_path("x.stl") == MeshFormat::Stl);
  CHECK(mesh_format_from_path("x.gltf") == MeshFormat::Gltf);
  CHECK(mesh_format_from_path("x.glb") == MeshFormat::Glb);
  CHECK(has(error_of([] { mesh_format_from_path("dir.v2/mesh.xyz"); }), "dir.v2/mesh.xyz: unknown mesh file extension 'xyz'"));
  CHECK(has(error_of([] { mesh_format_from_path("noext"); }), "noext: unknown mesh file extension ''"));
}

TEST_CASE("mesh_io: every writable format round-trips tetrahedron and cube through files") {
  for (const auto& mesh : {volspline::test::tetrahedron(), volspline::test::cube(0.5, 0.25)}) {
    for (const char* ext : {"obj", "off", "ply", "glb"}) {
      const std::string path = (std::filesystem::temp_directory_path() / (std::string("volspline_io_test.") + ext)).string();
      write_mesh(path, mesh);
      const auto back = read_mesh(path);
      std::remove(path.c_str());
      CHECK_MESSAGE(back.positions == mesh.positions, std::string(ext));  // these values are exact in float32 too
      CHECK_MESSAGE(back.triangles == mesh.triangles, std::string(ext));
      const MeshFormat format = mesh_format_from_path(path);
      CHECK(parse_mesh(serialize_mesh(mesh, format), format, "m").triangles == mesh.triangles);
    }
  }
}

TEST_CASE("mesh_io: unwritable formats and unreadable files are errors naming the path") {
  const auto tet = volspline::test::tetrahedron();
  CHECK(has(error_of([&] { write_mesh("out.stl", tet); }), "out.stl: writing .stl is not supported"));
  CHECK(has(error_of([&] { write_mesh("out.gltf", tet); }), "out.gltf: writing .gltf is not supported"));
  CHECK(has(error_of([&] { serialize_mesh(tet, MeshFormat::Stl); }), "not supported"));
  CHECK(has(error_of([] { read_mesh("/nonexistent/dir/m.obj"); }), "/nonexistent/dir/m.obj"));
  CHECK(has(error_of([] { read_mesh("m.xyz"); }), "m.xyz: unknown mesh file extension"));
}

TEST_CASE("mesh_io: broken test files name the file") {
  const std::string dir = VOLSPLINE_SOURCE_DIR "/tests/data/meshes/";
  CHECK(has(error_of([&] { read_mesh(dir + "truncated.off"); }), dir + "truncated.off: truncated"));
  CHECK(has(error_of([&] { read_mesh(dir + "nan_coordinate.obj"); }), dir + "nan_coordinate.obj:5: NaN"));
  CHECK(has(error_of([&] { read_mesh(dir + "empty.obj"); }), dir + "empty.obj: empty file"));
  CHECK(has(error_of([&] { read_mesh(dir + "wrong_index.off"); }), dir + "wrong_index.off:8: face index 4 out of range (4 vertices)"));
  CHECK(read_mesh(dir + "nonmanifold_edge.off").num_faces() == 3);  // readable; the mesh module rejects it
}

TEST_CASE("mesh_io: every shared mesh has the V and F of SOURCES.md") {
  struct Expected {
    const char* file;
    int vertices;
    int faces;
  };
  const Expected table[] = {{"kitten.off", 10000, 20000},    {"kitten_coarse.off", 1850, 3700},
                            {"eight.off", 766, 1536},        {"bimba.off", 697, 1390},
                            {"torus.off", 1200, 2400},       {"fertility.off", 4494, 9000},
                            {"genus3.off", 6652, 13312},     {"bunny_closed.obj", 14290, 28576},
                            {"sphere.off", 482, 960},        {"cube.off", 8, 12},
                            {"dancer.off", 24998, 49996},    {"armadillo.off", 36725, 73446},
                            {"knot.obj", 1440, 2880}};
  for (const auto& row : table) {
    const auto m = read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/" + row.file);
    CHECK_MESSAGE(m.num_vertices() == row.vertices, row.file);
    CHECK_MESSAGE(m.num_faces() == row.faces, row.file);
    CHECK_MESSAGE(m.triangles.minCoeff() >= 0, row.file);
    CHECK_MESSAGE(m.triangles.maxCoeff() < m.num_vertices(), row.file);
  }
}
