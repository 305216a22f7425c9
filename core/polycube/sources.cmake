# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/cap_corners.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cube_faces.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cuboid_layout.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cut_flips.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cut_tightening.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cylinder_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_builder.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_domain.cpp
  ${CMAKE_CURRENT_LIST_DIR}/interface_disc.cpp
  ${CMAKE_CURRENT_LIST_DIR}/level_set_split.cpp
  ${CMAKE_CURRENT_LIST_DIR}/morse_function.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solid_decomposition.cpp
  ${CMAKE_CURRENT_LIST_DIR}/surface_paths.cpp
  ${CMAKE_CURRENT_LIST_DIR}/t_shape_layout.cpp
  ${CMAKE_CURRENT_LIST_DIR}/disc_chords.cpp
  ${CMAKE_CURRENT_LIST_DIR}/piece_resplit.cpp
)
