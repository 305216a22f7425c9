# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  halfedge_mesh_test.cpp
  mesh_report_test.cpp
  unit_box_test.cpp
  mesh_geometry_test.cpp
  edge_weights_test.cpp
  laplacian_test.cpp
  graph_distance_test.cpp
  min_cut_test.cpp
  hex_quality_test.cpp
  surface_creases_test.cpp
)
