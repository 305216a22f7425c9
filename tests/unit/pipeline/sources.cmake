# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/lens_job_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_session_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh2spline_job_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh2spline_measures_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vol2spline_job_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_outputs_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_mesh2spline_test.cpp
)
