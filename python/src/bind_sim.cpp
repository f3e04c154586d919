// dloam.Simulator: the ray-casting LiDAR simulator of dynamic urban scenes (`dloam simulate`),
// frame by frame, with ground-truth labels and poses.
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#ifdef DLOAM_WITH_SIM
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"
#endif

namespace dloam::python {

#ifdef DLOAM_WITH_SIM
namespace {

struct PySimulator {
  std::unique_ptr<sim::Simulator> simulator;
  int frames = 0;

  Scan frame(int i) {
    if (i < 0) i += frames;
    if (i < 0 || i >= frames)
      throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(frames));
    sim::SimFrame f;
    {
      py::gil_scoped_release release;
      f = simulator->frame(i);
    }
    Scan s;
    s.cloud = std::move(f.scan.cloud);
    s.cloud.stamp = f.stamp;
    s.labels = std::move(f.scan.labels);
    s.pose = f.pose;
    s.index = static_cast<std::size_t>(i);
    s.name = "simulated frame " + std::to_string(i);
    return s;
  }
};

PySimulator make(const std::string& scenario, int frames, std::uint64_t seed,
                 const std::optional<Config>& config, double noise, double dropout, double traffic,
                 double density, double speed) {
  sim::ScenarioParams params;
  sim::LidarOptions lidar;
  try {
    params.kind = sim::parse_scenario_kind(scenario);
    params.frames = frames;
    params.seed = seed;
    params.traffic = traffic;
    params.density = density;
    params.ego_speed = speed;
    if (config) lidar.sensor = config->config.sensor;
    params.max_range = lidar.sensor.max_range;
    lidar.range_noise = noise;
    lidar.dropout = dropout;
    lidar.seed = seed;
    params.validate();
    lidar.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("Simulator: ") + e.what());
  }
  PySimulator s;
  py::gil_scoped_release release;
  s.simulator = std::make_unique<sim::Simulator>(sim::make_world(params), lidar);
  s.frames = frames;
  return s;
}

}  // namespace
#endif

void bind_sim(py::module_& m) {
#ifdef DLOAM_WITH_SIM
  py::class_<PySimulator>(m, "Simulator",
                          "A simulated drive (as `dloam simulate`): index it for dloam.Scan frames with "
                          "ground-truth labels and sensor poses (world frame, mid-sweep)")
      .def(py::init(&make), py::arg("scenario") = "urban", py::arg("frames") = 200, py::arg("seed") = 1,
           py::arg("config") = py::none(), py::arg("noise") = 0.02, py::arg("dropout") = 0.01,
           py::arg("traffic") = 1.0, py::arg("density") = 1.0, py::arg("speed") = 0.0,
           "scenario: urban | highway | loop | spin | tunnel | open-field; config: its sensor section is "
           "simulated (default HDL-64E); speed 0: the scenario's default")
      .def("__len__", [](const PySimulator& s) { return s.frames; })
      .def("__getitem__", &PySimulator::frame, py::arg("index"))
      .def("frame", &PySimulator::frame, py::arg("index"));
  m.attr("has_simulator") = true;
#else
  m.attr("has_simulator") = false;
#endif
}

}  // namespace dloam::python
