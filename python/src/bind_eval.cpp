// The evaluators: odometry (KITTI devkit relative error, ATE, RPE) and moving-object segmentation
// (SemanticKITTI MOS IoU, object IoU), with the keys of metrics.json and `dloam eval ... --json`.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/run/metrics.hpp"
#include "numpy_util.hpp"

namespace dloam::python {

namespace {

py::object json_to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

std::vector<Label> labels_from(const py::handle& a, const char* what) {
  const auto arr = py::array_t<Label, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!arr || arr.ndim() != 1)
    throw std::invalid_argument(std::string(what) + ": expected a 1-D array of labels");
  return {arr.data(), arr.data() + arr.shape(0)};
}

py::object evaluate_odometry(const py::handle& gt, const py::handle& est, const std::vector<double>& lengths,
                             std::size_t step) {
  const std::vector<Pose> g = poses_from_numpy(gt), e = poses_from_numpy(est);
  const eval::SegmentOptions options = run::segment_options(g, lengths, step);
  eval::OdometryResult r;
  {
    py::gil_scoped_release release;
    r = eval::evaluate_odometry(g, e, options);
  }
  return json_to_python(run::odometry_json(r, options, "as given"));
}

py::object evaluate_mos(const py::sequence& gt, const py::sequence& pred, double object_threshold) {
  if (py::len(gt) != py::len(pred))
    throw InputError("evaluate_mos: " + std::to_string(py::len(gt)) + " ground-truth scans but " +
                     std::to_string(py::len(pred)) + " predicted");
  eval::MosResult result;
  for (std::size_t i = 0; i < py::len(gt); ++i)
    eval::add_scan(result, labels_from(gt[i], "gt"), labels_from(pred[i], "pred"), object_threshold);
  return json_to_python(run::mos_json(result, object_threshold));
}

}  // namespace

void bind_eval(py::module_& m) {
  m.def("evaluate_odometry", &evaluate_odometry, py::arg("gt"), py::arg("est"),
        py::arg("lengths") = std::vector<double>{}, py::arg("step") = 0,
        "Odometry error of K x 4 x 4 estimated poses against K x 4 x 4 ground truth in the same frame: "
        "KITTI devkit relative error per segment length (default 100..800 m every 10 frames, or 5..30 m "
        "every frame on paths under 200 m), ATE (as given and SE(3)-aligned), RPE. Returns a dict with "
        "the keys of metrics.json's odometry.");
  m.def("evaluate_mos", &evaluate_mos, py::arg("gt"), py::arg("pred"), py::arg("object_threshold") = 0.5,
        "Moving-object segmentation of per-scan predicted labels against ground-truth labels (lists of "
        "uint32 arrays): SemanticKITTI MOS point IoU, precision, recall and the object IoU (eq. 16).");
}

}  // namespace dloam::python
