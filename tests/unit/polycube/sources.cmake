# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_layout_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cube_faces_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_paths_test.cpp
)
