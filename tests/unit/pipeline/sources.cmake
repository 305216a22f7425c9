# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  lens_job_test.cpp
  lens_session_test.cpp
  mesh2spline_job_test.cpp
  mesh2spline_measures_test.cpp
  vol2spline_job_test.cpp
  gpc_outputs_test.cpp
  gpc_mesh2spline_test.cpp
)
