# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/bspline_basis.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bspline_volume.cpp
  ${CMAKE_CURRENT_LIST_DIR}/knot_insertion.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline.cpp
  ${CMAKE_CURRENT_LIST_DIR}/boundary_tessellation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline_refinement.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tspline_fitting.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hierarchical_refinement.cpp
  ${CMAKE_CURRENT_LIST_DIR}/hierarchical_fitting.cpp
  ${CMAKE_CURRENT_LIST_DIR}/density_fitting.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scattered_density_fitting.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sparsified_cholesky.cpp
  ${CMAKE_CURRENT_LIST_DIR}/component_solve.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobian_repair.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_untangling.cpp
  ${CMAKE_CURRENT_LIST_DIR}/grouped_gram.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bezier_extraction.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobian_certificate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/node_jacobians.cpp
  ${CMAKE_CURRENT_LIST_DIR}/node_jacobians_avx2.cpp
  ${CMAKE_CURRENT_LIST_DIR}/untangle_energy.cpp
  ${CMAKE_CURRENT_LIST_DIR}/untangle_pass.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_spline.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_spline_fitting.cpp
)
