# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  local_cubic_fit_test.cpp
  hessian_frames_test.cpp
  frame_field_test.cpp
  kmeans_test.cpp
  material_classification_test.cpp
  corner_detection_test.cpp
  field_aligned_param_test.cpp
)
