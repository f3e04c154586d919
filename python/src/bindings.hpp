// The parts of the dloam Python module (dloam._dloam), one function per area, called once by
// module.cpp. The Python-side objects that several areas share are declared here.
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam::python {

namespace py = pybind11;

/// dloam.Config: a full pipeline configuration (the preset with a YAML file's keys over it).
struct Config {
  PipelineConfig config;
  std::string source;  ///< what it was loaded from, for messages
};

/// dloam.Scan: one scan of a sequence (or of the simulator), kept as dloam reads it so that
/// Pipeline.process(scan) sees exactly what `dloam run` sees.
struct Scan {
  PointCloud cloud;
  std::size_t index = 0;
  std::string name;                          ///< the file (or recording message) it came from
  std::optional<std::vector<Label>> labels;  ///< ground-truth labels, when the sequence has them
  std::optional<Pose> pose;                  ///< ground-truth sensor pose (simulator), when known
};

void bind_config(py::module_& m);
void bind_io(py::module_& m);
void bind_pipeline(py::module_& m);
void bind_eval(py::module_& m);
void bind_sim(py::module_& m);

}  // namespace dloam::python
