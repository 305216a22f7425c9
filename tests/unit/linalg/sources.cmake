# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  csr_matrix_test.cpp
  jacobi_preconditioner_test.cpp
  incomplete_cholesky0_test.cpp
  conjugate_gradient_test.cpp
  parallel_for_test.cpp
  algebraic_multigrid_test.cpp
)
