# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cube_faces.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_layout.cpp
)
