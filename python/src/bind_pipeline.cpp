// dloam.Pipeline (one scan at a time, as `dloam run` feeds it), dloam.Result, and dloam.run (a whole
// sequence into an output folder, the writer `dloam run` and dloam_node use).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <memory>

#include "bindings.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/detector_setup.hpp"
#include "dloam/run/run_sequence.hpp"
#include "numpy_util.hpp"

namespace dloam::python {

namespace {

/// The result of one scan; the per-point vectors become numpy arrays without a copy.
struct Result {
  ScanResult r;
  py::array_t<Label> labels;
  py::array_t<std::size_t> edge_features, plane_features;

  explicit Result(ScanResult&& result) : r(std::move(result)) {
    labels = to_numpy(std::move(r.labels));
    edge_features = to_numpy(std::move(r.edge_features));
    plane_features = to_numpy(std::move(r.plane_features));
    std::vector<Label>().swap(r.labels);  // frees the memory (= {} keeps the capacity)
    std::vector<std::size_t>().swap(r.edge_features);
    std::vector<std::size_t>().swap(r.plane_features);
    std::vector<std::size_t>().swap(r.map_points);
  }
};

py::dict module_times(const ModuleTimes& t) {
  py::dict out;
  for (std::size_t i = 0; i < kModuleNames.size(); ++i) out[py::str(std::string(kModuleNames[i]))] = t.ms[i];
  return out;
}

/// A Pipeline with its detector set up as every front-end does (run/detector_setup.hpp).
class PyPipeline {
 public:
  explicit PyPipeline(const Config& config) : config_(config.config) {
    std::string note;
    cnn_ = run::prepare_detector(config_, &note);
    if (!note.empty()) std::fprintf(stderr, "dloam: %s\n", note.c_str());
    pipeline_ = std::make_unique<Pipeline>(config_, cnn_);
  }

  Result process_scan(const Scan& scan) { return run_one(scan.cloud); }

  Result process(const py::handle& points, const py::handle& times, std::optional<double> stamp) {
    if (py::isinstance<Scan>(points)) return process_scan(py::cast<const Scan&>(points));
    return run_one(cloud_from_numpy(points, times, stamp));
  }

  py::array_t<double> trajectory() {
    std::vector<Pose> poses;
    {
      py::gil_scoped_release release;
      poses = pipeline_->trajectory();
    }
    return poses_to_numpy(std::move(poses));
  }

  py::array_t<double> global_map() {
    std::vector<Vec3> map;
    {
      py::gil_scoped_release release;
      map = pipeline_->global_map();
    }
    return points_to_numpy(std::move(map));
  }

  std::size_t loop_closures() { return pipeline_->loop_closures(); }
  [[nodiscard]] std::size_t scans() const { return scans_; }
  [[nodiscard]] Config config() const { return {pipeline_->config(), "the pipeline's (detector resolved)"}; }

 private:
  Result run_one(const PointCloud& cloud) {
    ScanResult r;
    {
      py::gil_scoped_release release;
      r = pipeline_->process(cloud);
    }
    r.index = scans_++;
    return Result(std::move(r));
  }

  PipelineConfig config_;
  std::shared_ptr<MovingSegmenter> cnn_;
  std::unique_ptr<Pipeline> pipeline_;
  std::size_t scans_ = 0;
};

py::object json_to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// `dloam run` from Python: the sequence through the pipeline into the output folder `out`.
py::dict run_to_folder(const std::string& path, const std::string& out, const std::optional<Config>& config,
                       std::size_t first, std::optional<std::size_t> count) {
  PipelineConfig cfg = config ? config->config : io::config_from("", "");
  const io::Sequence seq = io::open_sequence(path, io::input_options(cfg.input));
  std::string note;
  const auto cnn = run::prepare_detector(cfg, &note);
  if (!note.empty()) std::fprintf(stderr, "dloam: %s\n", note.c_str());
  run::RunOptions options;
  options.out = out;
  options.first = first;
  options.count = count;
  run::SequenceRun result;
  {
    py::gil_scoped_release release;
    result = run::run_sequence(seq, cfg, cnn, options);
  }
  const run::RunSummary& s = result.summary;
  if (!result.error.empty())
    throw InputError(result.error + " (the outputs of the " + std::to_string(s.scans) +
                     " scans before it are in " + out + ")");
  py::dict d;
  d["scans"] = s.scans;
  d["map_points"] = s.map_points;
  d["moving_points"] = s.moving_points;
  d["loop_closures"] = s.loop_closures;
  d["trajectory"] = poses_to_numpy(std::vector<Pose>(s.trajectory));
  d["metrics"] = json_to_python(s.metrics);
  d["out"] = out;
  return d;
}

}  // namespace

void bind_pipeline(py::module_& m) {
  py::class_<Result>(m, "Result", "What the pipeline found in one scan")
      .def_property_readonly(
          "pose", [](const Result& x) { return pose_to_numpy(x.r.pose); },
          "4 x 4 world pose of the sensor (real-time: odometry with the mapping corrections so far)")
      .def_property_readonly(
          "odometry_pose", [](const Result& x) { return pose_to_numpy(x.r.odometry_pose); },
          "4 x 4 odometry-only pose")
      .def_readonly("labels", &Result::labels,
                    "N uint32 per input point: 9 static, 251 moving (empty: no detector)")
      .def_readonly("edge_features", &Result::edge_features, "input point indices of the edge features")
      .def_readonly("plane_features", &Result::plane_features, "input point indices of the plane features")
      .def_property_readonly(
          "times", [](const Result& x) { return module_times(x.r.times); },
          "milliseconds per module (deskew, segmentation, ..., total)")
      .def_property_readonly("index", [](const Result& x) { return x.r.index; })
      .def_property_readonly("stamp", [](const Result& x) { return x.r.stamp; })
      .def_property_readonly("dt", [](const Result& x) { return x.r.dt; })
      .def_property_readonly("keyframe", [](const Result& x) { return x.r.keyframe; })
      .def_property_readonly("loop_closed", [](const Result& x) { return x.r.loop_closed; })
      .def_property_readonly("degenerate", [](const Result& x) { return x.r.degenerate; })
      .def_property_readonly("num_dynamic", [](const Result& x) { return x.r.num_dynamic; })
      .def_property_readonly(
          "reinitialized", [](const Result& x) { return x.r.reinitialized; },
          "the prediction did not fit the previous scan and a search replaced it")
      .def_property_readonly(
          "lost", [](const Result& x) { return x.r.lost; },
          "the step fits far worse than the recent steps: not estimated (metrics.json lists these scans)")
      .def_property_readonly(
          "detection_suspended", [](const Result& x) { return x.r.detection_suspended; },
          "T_coarse fitted too poorly to trust a speed matrix: no object was marked moving")
      .def("__repr__", [](const Result& x) {
        const Vec3 t = x.r.pose.translation();
        char text[160];
        std::snprintf(text, sizeof(text), "<dloam.Result scan %zu: x %.3f y %.3f z %.3f, %.1f ms>", x.r.index,
                      t.x(), t.y(), t.z(), x.r.times[Module::kTotal]);
        return std::string(text);
      });

  py::class_<PyPipeline>(m, "Pipeline", "The DLOAM pipeline: one process() call per scan, in order")
      .def(py::init<const Config&>(), py::arg("config"),
           "Sets up the moving-object detector as `dloam run` does (auto: the shipped CNN when it fits the "
           "sensor and dloam has LibTorch, else the geometric detector)")
      .def("process", &PyPipeline::process, py::arg("points"), py::arg("times") = py::none(),
           py::arg("stamp") = py::none(),
           "Processes the next scan: an N x 3 / N x 4 array (x, y, z[, intensity]) with optional per-point "
           "times (fractions of the sweep) and stamp (s), or a dloam.Scan as read_sequence() gives it")
      .def("trajectory", &PyPipeline::trajectory,
           "K x 4 x 4: the best estimate of every scan's sensor pose, the poses `dloam run` writes")
      .def("global_map", &PyPipeline::global_map, "N x 3: the global map (first scan's sensor frame)")
      .def_property_readonly("loop_closures", &PyPipeline::loop_closures)
      .def_property_readonly("scans", &PyPipeline::scans)
      .def_property_readonly("config", &PyPipeline::config);

  m.def("run", &run_to_folder, py::arg("sequence"), py::arg("out"), py::arg("config") = py::none(),
        py::arg("first") = 0, py::arg("count") = py::none(),
        "`dloam run` from Python: runs the sequence (anything read_sequence() opens) and writes the output "
        "folder (poses.txt, poses_tum.txt, map.ply, moving.ply, timing.csv, config.yaml, labels/, "
        "metrics.json). Returns a dict with the trajectory (sensor frame) and the metrics.");
}

}  // namespace dloam::python
