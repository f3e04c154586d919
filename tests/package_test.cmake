# Installs the build BUILD_DIR into WORK_DIR/prefix, then configures, builds and runs
# examples/cpp against the installed package (find_package(dloam)) on two scans of KITTI_0005,
# and imports the installed Python module when PYTHON is given. Run by CTest:
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DKITTI_0005=... [-DPYTHON=... -DPYTHON_DIR=...]
#         [-DGENERATOR=...] [-DCXX_COMPILER=...] -P package_test.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR KITTI_0005)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "package_test.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT EXISTS "${KITTI_0005}/velodyne/000000.bin")
  message("SKIPPED: ${KITTI_0005} is not there (the shared data folder)")
  return()
endif()

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
run_step("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(installed bin/dloam share/dloam/config/kitti-raw.yaml include/dloam/pipeline/pipeline.hpp)
  if(NOT EXISTS "${prefix}/${installed}")
    message(FATAL_ERROR "not installed: ${prefix}/${installed}")
  endif()
endforeach()

set(configure ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/cpp" -B "${WORK_DIR}/build" -DCMAKE_BUILD_TYPE=Release
              "-DCMAKE_PREFIX_PATH=${prefix}")
if(GENERATOR)
  list(APPEND configure -G "${GENERATOR}")
endif()
if(CXX_COMPILER)
  list(APPEND configure "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
run_step("configuring examples/cpp against ${prefix}" ${configure})
run_step("building examples/cpp" ${CMAKE_COMMAND} --build "${WORK_DIR}/build" -j2)
run_step("running the example" "${WORK_DIR}/build/dloam_example" "${KITTI_0005}" 2)
message("${step_output}")
if(NOT step_output MATCHES "scan 1: x [0-9.-]+ m")
  message(FATAL_ERROR "the example printed no pose of scan 1")
endif()

# The tool finds the installed data folder beside itself: a shipped configuration by name.
run_step("installed dloam config dump --config kitti-raw" "${prefix}/bin/dloam" config dump --config kitti-raw
         --section sensor)
if(NOT step_output MATCHES "beam_vertical_offsets_m")
  message(FATAL_ERROR "the installed dloam did not read the shipped kitti-raw configuration")
endif()

if(PYTHON AND PYTHON_DIR)
  run_step("importing the installed Python module" ${CMAKE_COMMAND} -E env "PYTHONPATH=${prefix}/${PYTHON_DIR}"
           "${PYTHON}" -c "import dloam\nprint(dloam.__file__)\nprint(dloam.data_dir())")  # no ';': run_step's ARGN is a list
  message("${step_output}")
  string(FIND "${step_output}" "${prefix}" at)
  if(at LESS 0)
    message(FATAL_ERROR "the Python module was not imported from ${prefix}")
  endif()
endif()
message("the installed package in ${prefix} builds and runs examples/cpp")
