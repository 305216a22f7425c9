# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/gpc_job.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_outputs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_job.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lens_session.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh2spline_job.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh2spline_measures.cpp
  ${CMAKE_CURRENT_LIST_DIR}/solid_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vol2spline_job.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stage_timer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_spline_measures.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gpc_mesh2spline.cpp
)
