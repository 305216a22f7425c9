# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/volume.cpp
  ${CMAKE_CURRENT_LIST_DIR}/local_cubic_fit.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hessian_frames.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_field.cpp
  ${CMAKE_CURRENT_LIST_DIR}/kmeans.cpp
  ${CMAKE_CURRENT_LIST_DIR}/material_classification.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corner_detection.cpp
  ${CMAKE_CURRENT_LIST_DIR}/field_aligned_param.cpp
)
