# SPDX-License-Identifier: MIT
list(APPEND VOLSPLINE_CORE_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/file_bytes.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gzip_inflate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/image_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_builder.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_text_scanner.cpp
  ${CMAKE_CURRENT_LIST_DIR}/obj_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/off_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/stl_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/gltf_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/spline_json.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vtu_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/glb_lines_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/textured_glb_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volume_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volume_header_text.cpp
  ${CMAKE_CURRENT_LIST_DIR}/volume_data.cpp
  ${CMAKE_CURRENT_LIST_DIR}/raw_volume_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nrrd_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vtk_volume_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/metaimage_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vti_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/nifti_format.cpp
)
