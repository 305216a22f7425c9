# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  roi_test.cpp
  roi_field_test.cpp
  lens_mesh_test.cpp
  lens_texture_test.cpp
  flatten_test.cpp
  lens_flattener_test.cpp
  lens_measures_test.cpp
  rasterize_test.cpp
  image_io_test.cpp
  roi_translation_test.cpp
  baseline_lens_test.cpp
)
