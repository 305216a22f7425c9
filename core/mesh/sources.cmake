# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/halfedge_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_report.cpp
)
