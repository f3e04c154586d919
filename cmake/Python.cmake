# The Python module (pybind11 from Debian, against Debian's /usr/bin/python3). Turned off, with a
# message, when pybind11 or the Python headers are missing.
set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python of the dloam module (Debian's)")
set(PYBIND11_FINDPYTHON ON)
find_package(Python COMPONENTS Interpreter Development.Module QUIET)
if(Python_FOUND)
  find_package(pybind11 CONFIG QUIET)
endif()
if(NOT Python_FOUND OR NOT pybind11_FOUND)
  message(STATUS "dloam: pybind11 or the Python headers not found (pybind11-dev python3-dev): "
                 "building without the Python module")
  set(DLOAM_WITH_PYTHON OFF)
else()
  if(NOT DLOAM_PYTHON_INSTALL_DIR)
    set(DLOAM_PYTHON_INSTALL_DIR
        "lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/dist-packages")
  endif()
  message(STATUS "dloam: Python module for ${Python_EXECUTABLE} ${Python_VERSION}, "
                 "installed to <prefix>/${DLOAM_PYTHON_INSTALL_DIR}")
endif()
# The package in the build tree: PYTHONPATH=build/python.
set(DLOAM_PYTHON_BUILD_DIR "${CMAKE_BINARY_DIR}/python")
