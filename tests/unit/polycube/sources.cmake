# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  cuboid_layout_test.cpp
  gpc_test.cpp
  cut_tightening_test.cpp
  cube_faces_test.cpp
  cap_corners_test.cpp
  surface_paths_test.cpp
  t_shape_layout_test.cpp
)
