# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/halfedge_mesh_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_report_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/unit_box_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_geometry_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/edge_weights_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/laplacian_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/graph_distance_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_quality_test.cpp
)
