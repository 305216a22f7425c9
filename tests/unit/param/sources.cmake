# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  cuboid_surface_map_test.cpp
  volumetric_grid_map_test.cpp
  surface_distance_test.cpp
  hex_grid_untangling_test.cpp
  barrier_untangling_test.cpp
  hex_padding_test.cpp
  hex_min_quality_test.cpp
  cuboid_surface_locator_test.cpp
)
