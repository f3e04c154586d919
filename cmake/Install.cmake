# Install rules and the CMake package: `cmake --install build [--prefix P]` installs the headers,
# the libraries, the tools, the data folder (share/dloam: config/, models/) and
# lib/cmake/dloam, so that another project's find_package(dloam [COMPONENTS ...]) gives the
# dloam::<library> targets. Libraries are exported in one set per component (core: core, pipeline,
# eval; io: drivers, io; run; sim; cnn; ros), each found with its own dependencies only.
include(CMakePackageConfigHelpers)
set(DLOAM_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/dloam")

get_property(DLOAM_EXPORTED_LIBRARIES GLOBAL PROPERTY DLOAM_EXPORTED_LIBRARIES)
set(DLOAM_EXPORT_SETS "")
set(DLOAM_LIBRARY_SETS "")  # name=set pairs for the package's component lookup
foreach(entry IN LISTS DLOAM_EXPORTED_LIBRARIES)
  string(REPLACE ":" ";" parts "${entry}")
  list(GET parts 0 name)
  list(GET parts 1 export_set)
  install(TARGETS dloam_${name} EXPORT dloam-${export_set} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY src/dloam/${name}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dloam/${name}
          FILES_MATCHING PATTERN "*.hpp")
  list(APPEND DLOAM_EXPORT_SETS ${export_set})
  list(APPEND DLOAM_LIBRARY_SETS "${name}=${export_set}")
endforeach()
list(REMOVE_DUPLICATES DLOAM_EXPORT_SETS)
foreach(export_set IN LISTS DLOAM_EXPORT_SETS)
  install(EXPORT dloam-${export_set} NAMESPACE dloam:: FILE dloam-${export_set}-targets.cmake
          DESTINATION ${DLOAM_CMAKE_INSTALL_DIR})
endforeach()

configure_package_config_file(cmake/dloamConfig.cmake.in "${CMAKE_BINARY_DIR}/dloamConfig.cmake"
                              INSTALL_DESTINATION ${DLOAM_CMAKE_INSTALL_DIR} PATH_VARS DLOAM_DATA_INSTALL_DIR)
write_basic_package_version_file("${CMAKE_BINARY_DIR}/dloamConfigVersion.cmake" VERSION ${PROJECT_VERSION}
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_BINARY_DIR}/dloamConfig.cmake" "${CMAKE_BINARY_DIR}/dloamConfigVersion.cmake"
        DESTINATION ${DLOAM_CMAKE_INSTALL_DIR})

install(FILES ${DLOAM_DATA_CONFIGS} DESTINATION ${DLOAM_DATA_INSTALL_DIR}/config)
install(FILES ${DLOAM_DATA_MODELS} DESTINATION ${DLOAM_DATA_INSTALL_DIR}/models)
if(TARGET dloam)
  install(TARGETS dloam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET dloam_node)
  install(TARGETS dloam_node RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
