# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/roi.cpp
  ${CMAKE_CURRENT_LIST_DIR}/roi_field.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_texture.cpp
  ${CMAKE_CURRENT_LIST_DIR}/flatten.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_flattener.cpp
  ${CMAKE_CURRENT_LIST_DIR}/baseline_lens.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_measures.cpp
  ${CMAKE_CURRENT_LIST_DIR}/rasterize.cpp
  ${CMAKE_CURRENT_LIST_DIR}/roi_translation.cpp
)
