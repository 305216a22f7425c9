# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/local_cubic_fit_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hessian_frames_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_field_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/kmeans_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/material_classification_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corner_detection_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/field_aligned_param_test.cpp
)
