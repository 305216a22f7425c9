# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_surface_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_surface_locator.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volumetric_grid_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_volumetric_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_distance.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_grid_untangling.cpp
  ${CMAKE_CURRENT_LIST_DIR}/barrier_untangling.cpp
  ${CMAKE_CURRENT_LIST_DIR}/foldover_batch_avx2.cpp
  ${CMAKE_CURRENT_LIST_DIR}/foldover_batch_avx512.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_padding.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hex_min_quality.cpp
)
