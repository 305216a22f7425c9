# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/csr_matrix.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobi_preconditioner.cpp
  ${CMAKE_CURRENT_LIST_DIR}/incomplete_cholesky0.cpp
  ${CMAKE_CURRENT_LIST_DIR}/conjugate_gradient.cpp
  ${CMAKE_CURRENT_LIST_DIR}/parallel_for.cpp
  ${CMAKE_CURRENT_LIST_DIR}/algebraic_multigrid.cpp
)
