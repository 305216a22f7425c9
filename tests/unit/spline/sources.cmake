# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/bspline_basis_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bspline_volume_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/knot_insertion_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline_refinement_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline_fitting_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hierarchical_refinement_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/density_fitting_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sparsified_cholesky_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobian_repair_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_untangling_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scattered_density_fitting_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/grouped_gram_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bezier_extraction_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobian_certificate_test.cpp
)
