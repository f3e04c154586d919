// dloam._dloam: the Python module of dloam (pybind11). The package python/dloam re-exports it.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "dloam/core/types.hpp"
#include "dloam/io/data_dir.hpp"
#ifdef DLOAM_WITH_ROS
#include "dloam/ros/bag_sequence.hpp"
#endif

namespace py = pybind11;

PYBIND11_MODULE(_dloam, m) {
  m.doc() =
      "dloam: LiDAR SLAM for dynamic scenes (segmentation, de-skew, moving-object detection, "
      "LOAM odometry and mapping, loop closure)";
  // Bad input (a file, a key, a value) raises dloam.InputError, a ValueError naming the problem.
  py::register_exception<dloam::InputError>(m, "InputError", PyExc_ValueError);
#ifdef DLOAM_WITH_ROS
  dloam::ros1::register_bag_format();  // read_sequence() opens ROS 1 bags, as the CLI does
#endif
  m.def(
      "data_dir", [] { return dloam::io::data_dir(); },
      "The data folder (config/, models/) this dloam uses: $DLOAM_DATA_DIR, else share/dloam beside the "
      "installed (or build-tree) module");
  dloam::python::bind_config(m);
  dloam::python::bind_io(m);
  dloam::python::bind_pipeline(m);
  dloam::python::bind_eval(m);
  dloam::python::bind_sim(m);
}
