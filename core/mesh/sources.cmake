# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/halfedge_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_report.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_geometry.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_lists.cpp
  ${CMAKE_CURRENT_LIST_DIR}/edge_weights.cpp
  ${CMAKE_CURRENT_LIST_DIR}/laplacian.cpp
  ${CMAKE_CURRENT_LIST_DIR}/graph_distance.cpp
  ${CMAKE_CURRENT_LIST_DIR}/min_cut.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_creases.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_quality.cpp
  ${CMAKE_CURRENT_LIST_DIR}/unit_box.cpp
)
