# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/roi_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/roi_field_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_mesh_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_texture_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/flatten_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_flattener_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_measures_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/rasterize_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_io_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/roi_translation_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/baseline_lens_test.cpp
)
