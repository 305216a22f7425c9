# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/csr_matrix_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/jacobi_preconditioner_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/incomplete_cholesky0_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/conjugate_gradient_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/parallel_for_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/algebraic_multigrid_test.cpp
)
