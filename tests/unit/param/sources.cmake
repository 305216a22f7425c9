# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_surface_map_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volumetric_grid_map_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_distance_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_grid_untangling_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/barrier_untangling_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_padding_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_surface_locator_test.cpp
)
