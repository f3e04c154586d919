# dloam's data folder (src/dloam/io/data_dir.hpp): the shipped configurations and CNN models. The
# build tree holds a copy in build/share/dloam, laid out as <prefix>/share/dloam is installed, so
# the programs of the build tree find it beside them as the installed ones do.
set(DLOAM_DATA_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/dloam")
set(DLOAM_BUILD_DATA_DIR "${CMAKE_BINARY_DIR}/share/dloam")
file(GLOB DLOAM_DATA_CONFIGS CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/config/*.yaml")
file(GLOB DLOAM_DATA_MODELS CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/models/*.pt" "${CMAKE_SOURCE_DIR}/models/*.pt.csv"
     "${CMAKE_SOURCE_DIR}/models/MODEL.md")
set(DLOAM_DATA_COPIES "")
foreach(file IN LISTS DLOAM_DATA_CONFIGS DLOAM_DATA_MODELS)
  get_filename_component(name "${file}" NAME)
  get_filename_component(folder "${file}" DIRECTORY)
  get_filename_component(folder "${folder}" NAME)  # config or models
  set(copy "${DLOAM_BUILD_DATA_DIR}/${folder}/${name}")
  add_custom_command(OUTPUT "${copy}" COMMAND ${CMAKE_COMMAND} -E copy_if_different "${file}" "${copy}"
                     DEPENDS "${file}" COMMENT "data folder: ${folder}/${name}" VERBATIM)
  list(APPEND DLOAM_DATA_COPIES "${copy}")
endforeach()
add_custom_target(dloam_data ALL DEPENDS ${DLOAM_DATA_COPIES})
