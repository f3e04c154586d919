// dloam.read_sequence and dloam.Sequence / dloam.Scan: every input `dloam run` reads (KITTI and
// SemanticKITTI folders, PCD folders, pcap captures, ROS 2 bags, ROS 1 bags when built with ROS),
// and the pose-file helpers.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "numpy_util.hpp"

namespace dloam::python {

namespace {

struct Sequence {
  std::shared_ptr<const io::Sequence> seq;

  [[nodiscard]] std::size_t size() const { return seq->size(); }

  [[nodiscard]] Scan scan(long i) const {
    const long n = static_cast<long>(seq->size());
    if (i < 0) i += n;
    if (i < 0 || i >= n) throw py::index_error("scan " + std::to_string(i) + " of " + std::to_string(n));
    const auto k = static_cast<std::size_t>(i);
    Scan s;
    {
      py::gil_scoped_release release;
      s.cloud = seq->read_scan(k);
      if (seq->has_labels()) s.labels = seq->read_scan_labels(k, s.cloud.size());
    }
    s.index = k;
    s.name = seq->scan_files[k];
    return s;
  }
};

Sequence open(const std::string& path, const std::optional<Config>& config,
              const std::optional<std::string>& topic, const std::optional<std::string>& calibration,
              const std::optional<std::string>& metadata) {
  InputConfig input = config ? config->config.input : InputConfig{};
  if (topic) input.topic = *topic;
  if (calibration) input.calibration = *calibration;
  if (metadata) input.metadata = *metadata;
  Sequence s;
  py::gil_scoped_release release;
  s.seq = std::make_shared<const io::Sequence>(io::open_sequence(path, io::input_options(input)));
  return s;
}

py::object optional_pose(const std::optional<Pose>& p) {
  return p ? py::object(pose_to_numpy(*p)) : py::none();
}

}  // namespace

void bind_io(py::module_& m) {
  py::class_<Scan>(m, "Scan", "One scan: its points, per-point times, stamp and ground truth")
      .def_property_readonly(
          "points", [](const Scan& s) { return cloud_points(s.cloud); }, "N x 4 float32: x, y, z, intensity")
      .def_property_readonly(
          "times", [](const Scan& s) { return cloud_times(s.cloud); },
          "N float32 per-point times (fractions of the sweep), or None")
      .def_property_readonly(
          "xyz", [](const Scan& s) { return points_to_numpy(std::vector<Vec3>(s.cloud.xyz)); },
          "N x 3 float64 coordinates as dloam reads them")
      .def_property_readonly(
          "stamp", [](const Scan& s) { return s.cloud.stamp; }, "the scan's time (s), or None")
      .def_property_readonly(
          "labels",
          [](const Scan& s) -> py::object {
            if (!s.labels) return py::none();
            return to_numpy(std::vector<Label>(*s.labels));
          },
          "N uint32 ground-truth SemanticKITTI labels, or None")
      .def_property_readonly(
          "pose", [](const Scan& s) { return optional_pose(s.pose); },
          "4 x 4 ground-truth sensor pose (simulated scans), or None")
      .def_readonly("index", &Scan::index)
      .def_readonly("name", &Scan::name, "the file (or recording message) of the scan")
      .def("__len__", [](const Scan& s) { return s.cloud.size(); })
      .def("__repr__", [](const Scan& s) {
        return "<dloam.Scan " + std::to_string(s.index) + ": " + std::to_string(s.cloud.size()) + " points>";
      });

  py::class_<Sequence>(m, "Sequence", "A sequence folder or recording; scans are read when indexed")
      .def("__len__", &Sequence::size)
      .def("__getitem__", &Sequence::scan, py::arg("index"))
      .def_property_readonly("path", [](const Sequence& s) { return s.seq->dir; })
      .def_property_readonly("files", [](const Sequence& s) { return s.seq->scan_files; })
      .def_property_readonly(
          "poses",
          [](const Sequence& s) -> py::object {
            if (!s.seq->has_poses()) return py::none();
            return poses_to_numpy(s.seq->lidar_poses());
          },
          "K x 4 x 4 ground-truth poses in the sensor frame (poses.txt through calib.txt's Tr), or None")
      .def_property_readonly(
          "calib_tr",
          [](const Sequence& s) -> py::object {
            if (!s.seq->calib || !s.seq->calib->has_Tr) return py::none();
            return pose_to_numpy(s.seq->calib->Tr);
          },
          "4 x 4 KITTI Tr (LiDAR -> camera 0) of calib.txt, or None")
      .def_property_readonly(
          "stamps",
          [](const Sequence& s) -> py::object {
            if (s.seq->times.empty()) return py::none();
            return to_numpy(std::vector<double>(s.seq->times));
          },
          "the scans' times (s: times.txt or the recording's stamps), or None")
      .def_property_readonly("has_labels", [](const Sequence& s) { return s.seq->has_labels(); })
      .def_property_readonly(
          "source",
          [](const Sequence& s) { return s.seq->source ? s.seq->source->describe() : std::string(); },
          "a recording's description (empty for folders)")
      .def("__repr__", [](const Sequence& s) {
        return "<dloam.Sequence " + s.seq->dir + ": " + std::to_string(s.seq->size()) + " scans>";
      });

  m.def("read_sequence", &open, py::arg("path"), py::arg("config") = py::none(),
        py::arg("topic") = py::none(), py::arg("calibration") = py::none(), py::arg("metadata") = py::none(),
        "Opens anything `dloam run` reads: a KITTI / SemanticKITTI folder, a folder of PCD files, a pcap "
        "capture, a ROS 2 bag (.db3, .mcap) or a ROS 1 bag. `config`'s input section (topic, calibration, "
        "metadata, returns, ...) says how recordings are read; the keyword arguments override it. Iterate "
        "it, or index it (negative indices count from the end).");

  m.def(
      "read_kitti_poses", [](const std::string& path) { return poses_to_numpy(io::read_kitti_poses(path)); },
      py::arg("path"), "A KITTI poses file (poses.txt, as `dloam run` writes) as K x 4 x 4");
  m.def(
      "write_kitti_poses",
      [](const std::string& path, const py::handle& poses) {
        io::write_kitti_poses(path, poses_from_numpy(poses));
      },
      py::arg("path"), py::arg("poses"), "Writes K x 4 x 4 poses as a KITTI poses file");
  m.def(
      "lidar_to_camera",
      [](const py::handle& poses, const py::handle& tr) {
        return poses_to_numpy(io::lidar_to_camera(poses_from_numpy(poses), pose_from_numpy(tr)));
      },
      py::arg("poses"), py::arg("tr"), "Sensor-frame poses in the KITTI camera frame (Tr P Tr^-1)");
  m.def(
      "camera_to_lidar",
      [](const py::handle& poses, const py::handle& tr) {
        return poses_to_numpy(io::camera_to_lidar(poses_from_numpy(poses), pose_from_numpy(tr)));
      },
      py::arg("poses"), py::arg("tr"), "KITTI camera-frame poses in the sensor frame (Tr^-1 P Tr)");
}

}  // namespace dloam::python
