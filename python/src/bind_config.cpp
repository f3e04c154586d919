// dloam.load_config and dloam.Config: the configuration as the CLI builds it from --preset and
// --config (a YAML file, or a configuration shipped in the data folder by name).
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <sstream>

#include "bindings.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/data_dir.hpp"

namespace dloam::python {

namespace {

/// A YAML scalar as the Python value it spells: None, bool, int, float, else str.
py::object scalar_value(const std::string& s) {
  if (s.empty() || s == "~" || s == "null") return py::none();
  if (s == "true") return py::bool_(true);
  if (s == "false") return py::bool_(false);
  char* end = nullptr;
  const long long i = std::strtoll(s.c_str(), &end, 10);
  if (end && *end == '\0') return py::int_(i);
  const double d = std::strtod(s.c_str(), &end);
  if (end && *end == '\0') return py::float_(d);
  return py::str(s);
}

py::object node_value(const YAML::Node& node) {
  if (node.IsSequence()) {
    py::list out;
    for (const auto& item : node) out.append(node_value(item));
    return std::move(out);
  }
  if (node.IsMap()) {
    py::dict out;
    for (const auto& item : node) out[py::str(item.first.as<std::string>())] = node_value(item.second);
    return std::move(out);
  }
  if (node.IsNull()) return py::none();
  // A quoted scalar stays a string ("auto", "HDL-64E", paths).
  if (node.Tag() == "!") return py::str(node.as<std::string>());
  return scalar_value(node.as<std::string>());
}

/// The value at "section.key" (or a whole section) of the full YAML dump.
py::object config_get(const Config& c, const std::string& key) {
  const YAML::Node root = YAML::Load(io::dump_config(c.config));
  YAML::Node node = YAML::Clone(root);
  std::stringstream path(key);
  std::string part;
  while (std::getline(path, part, '.')) {
    if (!node.IsMap() || !node[part]) throw py::key_error("no configuration key '" + key + "'");
    node = node[part];
  }
  return node_value(node);
}

/// Sets "section.key" to `value` (any JSON-serialisable value), as the same key of a YAML file
/// over this configuration would: checked and validated like a file.
void config_set(Config& c, const std::string& key, const py::object& value) {
  const py::object json = py::module_::import("json");
  std::string text = py::cast<std::string>(json.attr("dumps")(value));
  std::stringstream path(key);
  std::vector<std::string> parts;
  std::string part;
  while (std::getline(path, part, '.')) parts.push_back(part);
  if (parts.empty()) throw py::key_error("empty configuration key");
  for (auto it = parts.rbegin(); it != parts.rend(); ++it)
    text = "{" + py::cast<std::string>(json.attr("dumps")(*it)) + ": " + text + "}";
  c.config = io::config_from_yaml_string(text, "Config.set('" + key + "')", c.config);
}

Config load(const std::string& preset, const std::optional<std::string>& path) {
  Config c;
  const std::string file = path && !path->empty() ? io::resolve_config_file(*path) : std::string();
  c.config = io::config_from(preset, file);
  c.source = file.empty() ? "preset " + preset : file + " over preset " + preset;
  return c;
}

}  // namespace

void bind_config(py::module_& m) {
  py::class_<Config>(m, "Config", "A full dloam configuration (see `dloam config dump`)")
      .def(py::init([] { return load("HDL-64E", std::nullopt); }), "The built-in defaults (HDL-64E)")
      .def(
          "dump",
          [](const Config& c, const std::string& section) { return io::dump_config(c.config, section); },
          py::arg("section") = "", "The YAML of every key (or of one section), with a comment each")
      .def("get", &config_get, py::arg("key"), "The value of 'section.key' (or a whole section as a dict)")
      .def("set", &config_set, py::arg("key"), py::arg("value"),
           "Sets 'section.key' as a YAML file over this configuration would (checked and validated)")
      .def("__getitem__", &config_get)
      .def("__setitem__", &config_set)
      .def("copy", [](const Config& c) { return c; })
      .def_property_readonly("preset", [](const Config& c) { return c.config.sensor.preset; })
      .def_property_readonly("source", [](const Config& c) { return c.source; })
      .def("__repr__", [](const Config& c) {
        return "<dloam.Config " + c.config.sensor.preset + ", detector " +
               std::string(name_of(c.config.detection.detector)) + " (" + c.source + ")>";
      });

  m.def("load_config", &load, py::arg("preset") = "HDL-64E", py::arg("path") = py::none(),
        "The configuration of a sensor preset with the keys of a YAML file over it (as `dloam run "
        "--preset P --config FILE`); `path` may name a configuration shipped in the data folder "
        "(e.g. 'kitti-raw').");
  m.def("sensor_presets", &sensor_preset_names, "The names of the built-in sensor presets");
  m.def("shipped_configs", &io::shipped_configs, "The configurations shipped in the data folder, by name");
}

}  // namespace dloam::python
