# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/mesh_io_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_builder_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_text_scanner_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/obj_format_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/off_format_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_format_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stl_format_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_format_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_json_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vtu_writer_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volume_vtu_writer_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/glb_lines_writer_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volume_io_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vtk_written_volumes_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gzip_inflate_test.cpp
)
