# SPDX-License-Identifier: MIT
# Assembles the static site: cmake -DWEB_DIR=.. -DSAMPLES_DIR=.. -DWASM_DIR=.. -DSITE_DIR=.. -P assemble_site.cmake
# Copies the page files of web/ (html, css, js, and the modules in tabs/ and shaders/), the ES module build of the core and the bundled
# samples, and writes samples/index.json listing them for the page's samples menu.
foreach(var WEB_DIR SAMPLES_DIR WASM_DIR SITE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "assemble_site.cmake: ${var} is not set")
  endif()
endforeach()

file(MAKE_DIRECTORY ${SITE_DIR} ${SITE_DIR}/samples)
file(GLOB page_files ${WEB_DIR}/*.html ${WEB_DIR}/*.css ${WEB_DIR}/*.js)
file(COPY ${page_files} DESTINATION ${SITE_DIR})
foreach(sub tabs shaders)
  file(GLOB module_files ${WEB_DIR}/${sub}/*.js)
  file(MAKE_DIRECTORY ${SITE_DIR}/${sub})
  file(COPY ${module_files} DESTINATION ${SITE_DIR}/${sub})
endforeach()
file(COPY ${WASM_DIR}/volspline.mjs ${WASM_DIR}/volspline.wasm DESTINATION ${SITE_DIR})

set(entries "")
foreach(kind meshes images volumes)
  file(GLOB sample_files LIST_DIRECTORIES false ${SAMPLES_DIR}/${kind}/*)
  foreach(f ${sample_files})
    get_filename_component(name ${f} NAME)
    if(name MATCHES "\\.(obj|off|ply|stl|glb|png|jpg|jpeg|raw|nrrd|nhdr|vti|nii|mha)$")
      file(COPY ${f} DESTINATION ${SITE_DIR}/samples/${kind})
      file(SIZE ${f} size)
      list(APPEND entries "  {\"kind\": \"${kind}\", \"name\": \"${name}\", \"path\": \"samples/${kind}/${name}\", \"bytes\": ${size}}")
    endif()
  endforeach()
endforeach()
list(JOIN entries ",\n" body)
file(WRITE ${SITE_DIR}/samples/index.json "[\n${body}\n]\n")
