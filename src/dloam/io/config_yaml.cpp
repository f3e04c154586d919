// Loading and validating the YAML configuration by walking the key tables of config_schema.hpp.
#include "dloam/io/config_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <type_traits>

#include "dloam/core/types.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_schema.hpp"

namespace dloam::io {

namespace {
using detail::Choices;
using detail::Range;
using detail::visit;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// The sensor section a preset name starts from: a built-in model, `custom`, or `auto` (the
/// estimated model when given, else the unresolved placeholder). Throws std::invalid_argument.
SensorConfig sensor_start(const std::string& name, const SensorConfig* estimated) {
  const std::string n = lower(name);
  if (n == kAutoSensor) {
    if (estimated) return *estimated;
    SensorConfig s;
    s.preset = kAutoSensor;
    return s;
  }
  if (n == kCustomSensor) {
    SensorConfig s;
    s.preset = kCustomSensor;
    return s;
  }
  try {
    return sensor_preset(name);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(e.what()) +
                                "; or custom (the keys alone), auto (estimated from the data)");
  }
}

/// Fills one struct from a YAML map, remembering which keys it knows.
struct Loader {
  const YAML::Node node;  // const: looking up an absent key must not add it
  std::string source, prefix;
  std::set<std::string> known;
  const SensorConfig* estimated = nullptr;  ///< what sensor preset `auto` stands for (null: unresolved)

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key_path, const std::string& what) const {
    const int line = at.Mark().line;
    throw InputError(source + (line >= 0 ? ":" + std::to_string(line + 1) : "") + ": " + key_path + ": " +
                     what);
  }

  template <class T>
  T scalar(const YAML::Node& n, const std::string& key_path, const char* expected) const {
    if (!n.IsScalar()) fail(n, key_path, std::string("expected ") + expected);
    try {
      return n.as<T>();
    } catch (const YAML::Exception&) {
      fail(n, key_path, std::string("expected ") + expected + ", got '" + n.Scalar() + "'");
    }
  }

  void read(const YAML::Node& n, bool& v, const std::string& p) const {
    v = scalar<bool>(n, p, "true or false");
  }
  void read(const YAML::Node& n, int& v, const std::string& p) const { v = scalar<int>(n, p, "an integer"); }
  void read(const YAML::Node& n, double& v, const std::string& p) const {
    v = scalar<double>(n, p, "a number");
  }
  void read(const YAML::Node& n, std::string& v, const std::string& p) const {
    v = n.IsNull() ? std::string() : scalar<std::string>(n, p, "a string");
  }
  template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
  void read(const YAML::Node& n, E& v, const std::string& p) const {
    const std::string expected = "one of " + enum_choices<E>();
    const auto name = scalar<std::string>(n, p, expected.c_str());
    const std::optional<E> value = enum_from_name<E>(name);
    if (!value) fail(n, p, "'" + name + "' must be " + expected);
    v = *value;
  }
  void read(const YAML::Node& n, std::vector<double>& v, const std::string& p) const {
    v.clear();
    if (n.IsNull()) return;
    if (!n.IsSequence()) fail(n, p, "expected a list of numbers, e.g. [-15.0, -13.0]");
    for (std::size_t i = 0; i < n.size(); ++i)
      v.push_back(scalar<double>(n[i], p + "[" + std::to_string(i) + "]", "a number"));
  }

  template <class T, class Constraint>
  void operator()(const char* key, T& field, const char* /*doc*/, const Constraint& /*limits*/) {
    known.insert(key);
    const YAML::Node n = node[key];
    if (n) read(n, field, prefix + key);
  }

  template <class S>
  void group(const char* key, S& s, const char* /*doc*/) {
    known.insert(key);
    const YAML::Node n = node[key];
    if (!n || n.IsNull()) return;
    if (!n.IsMap()) fail(n, prefix + key, "expected a map of keys");
    // A preset key (sensor.preset, motion.platform) first replaces the whole section by the
    // preset's values; the other keys then override them.
    std::string preset;
    const auto apply_preset = [&](const char* preset_key, auto make, std::string S::*name) {
      if (!n[preset_key]) return;
      read(n[preset_key], preset, prefix + key + "." + preset_key);
      try {
        s = make(preset);
      } catch (const std::invalid_argument& e) {
        fail(n[preset_key], prefix + key + "." + preset_key, e.what());
      }
      preset = s.*name;  // canonical spelling
    };
    if constexpr (std::is_same_v<S, SensorConfig>)
      apply_preset(
          "preset", [&](const std::string& name) { return sensor_start(name, estimated); },
          &SensorConfig::preset);
    if constexpr (std::is_same_v<S, MotionConfig>)
      apply_preset("platform", motion_preset, &MotionConfig::platform);
    Loader sub{n, source, prefix + key + ".", {}, estimated};
    visit(s, sub);
    sub.reject_unknown_keys();
    if constexpr (std::is_same_v<S, SensorConfig>) {
      if (!preset.empty()) s.preset = preset;
    }
    if constexpr (std::is_same_v<S, MotionConfig>) {
      if (!preset.empty()) s.platform = preset;
    }
  }

  void reject_unknown_keys() const {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) fail(kv.first, prefix + "?", "a key must be a plain name");
      const std::string key = kv.first.Scalar();
      if (!seen.insert(key).second)
        fail(kv.first, prefix + key, "given twice in the same map (YAML keys must be unique)");
      if (known.count(key)) continue;
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(kv.first, prefix + key, "unknown key (known here: " + list + ")");
    }
  }
};

/// The documents of a YAML text, counted from its markers as the YAML spec places them (column 0,
/// then a blank or the end of the line): content before the first "---" is a document, every
/// "---" starts one, content after "..." starts one. (yaml-cpp 0.7's LoadAll() never returns on
/// some inputs, e.g. ",": it is not used.)
struct Documents {
  std::size_t count = 0, second_line = 0;  ///< 1-based line where the second document starts
  bool content = false;                    ///< any line that is not blank, a comment or a marker
};
Documents count_documents(const std::string& text) {
  auto marker = [](std::string_view line, std::string_view m) {
    return line.substr(0, 3) == m &&
           (line.size() == 3 || line[3] == ' ' || line[3] == '\t' || line[3] == '\r');
  };
  Documents d;
  bool open = false;
  std::size_t start = 0, line_no = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    ++line_no;
    start = end + 1;
    const bool begins = marker(line, "---");
    const auto first = line.find_first_not_of(" \t\r");
    const bool blank = first == std::string_view::npos || line[first] == '#';
    if (marker(line, "...")) {
      open = false;
    } else if (begins || (!blank && !open && line[0] != '%')) {
      open = true;
      if (++d.count == 2) d.second_line = line_no;
    }
    if (!begins && !blank && !marker(line, "...") && line[0] != '%') d.content = true;
    if (begins && line.find_first_not_of(" \t\r", 3) != std::string_view::npos &&
        line[line.find_first_not_of(" \t\r", 3)] != '#')
      d.content = true;  // "--- {a: 1}"
    if (end == text.size()) break;
  }
  return d;
}

/// Checks every field against its Range / Choices.
struct Validator {
  std::string source, prefix;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(source + ": " + prefix + key + " " + what);
  }
  void check(const char* key, double v, const Range& r) const {
    if (!std::isfinite(v)) fail(key, "must be finite");
    const bool low = r.lo_open ? v <= r.lo : v < r.lo;
    const bool high = r.hi_open ? v >= r.hi : v > r.hi;
    if (low || high) {
      auto bound = [](double b) {
        return std::isinf(b) ? std::string(b < 0 ? "-inf" : "inf") : std::to_string(b);
      };
      fail(key, "= " + std::to_string(v) + " is outside " + (r.lo_open ? "(" : "[") + bound(r.lo) + ", " +
                    bound(r.hi) + (r.hi_open ? ")" : "]"));
    }
  }
  void operator()(const char* key, int v, const char*, const Range& r) const { check(key, v, r); }
  void operator()(const char* key, double v, const char*, const Range& r) const { check(key, v, r); }
  void operator()(const char*, bool, const char*, const Range&) const {}
  template <class E>
  void operator()(const char*, E, const char*, const detail::Named&) const {}  // valid by its type
  void operator()(const char* key, const std::vector<double>& v, const char*, const Range& r) const {
    for (double x : v) check(key, x, r);
  }
  void operator()(const char* key, const std::string& v, const char*, const Choices& choices) const {
    if (choices.empty()) return;
    std::string list;
    for (const auto& c : choices) {
      if (c == v) return;
      list += (list.empty() ? "" : " | ") + c;
    }
    fail(key, "= '" + v + "' must be one of " + list);
  }
  template <class S>
  void group(const char* key, S& s, const char*) const {
    Validator sub{source, prefix + key + "."};
    visit(s, sub);
  }
};

PipelineConfig default_config_with(const std::string& preset, const SensorConfig* estimated) {
  PipelineConfig config;
  try {
    config.sensor = sensor_start(preset.empty() ? "HDL-64E" : preset, estimated);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("preset: ") + e.what());
  }
  return config;
}

PipelineConfig load_with(const std::string& yaml, const std::string& source, const PipelineConfig& base,
                         const SensorConfig* estimated) {
  const Documents documents = count_documents(yaml);
  if (documents.count > 1)
    throw InputError(source + ":" + std::to_string(documents.second_line) +
                     ": a second YAML document (after --- or ...); a config is one document");
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": YAML error: " + e.what());
  }
  PipelineConfig config = base;
  if ((!root || root.IsNull()) && documents.content)
    throw InputError(source + ": is not a YAML map of sections (sensor, mapping, ...)");
  if (root && !root.IsNull()) {
    if (!root.IsMap()) throw InputError(source + ": expected a YAML map of sections (sensor, mapping, ...)");
    Loader loader{root, source, "", {}, estimated};
    visit(config, loader);
    loader.reject_unknown_keys();
  }
  validate_config(config, source);
  return config;
}

PipelineConfig config_with(const std::string& preset, const std::string& yaml_path,
                           const SensorConfig* estimated) {
  const PipelineConfig base = default_config_with(preset, estimated);
  return yaml_path.empty() ? base
                           : load_with(read_file(yaml_path, kMaxConfigFileBytes), yaml_path, base, estimated);
}
}  // namespace

bool sensor_needs_estimate(const PipelineConfig& config) { return config.sensor.preset == kAutoSensor; }

PipelineConfig default_config(const std::string& preset) { return default_config_with(preset, nullptr); }

PipelineConfig config_from_yaml_string(const std::string& yaml, const std::string& source,
                                       const PipelineConfig& base) {
  return load_with(yaml, source, base, nullptr);
}

PipelineConfig load_config(const std::string& yaml_path) { return load_config(yaml_path, default_config()); }

PipelineConfig load_config(const std::string& yaml_path, const PipelineConfig& base) {
  return config_from_yaml_string(read_file(yaml_path, kMaxConfigFileBytes), yaml_path, base);
}

PipelineConfig config_from_allowing_auto(const std::string& preset, const std::string& yaml_path) {
  return config_with(preset, yaml_path, nullptr);
}

PipelineConfig config_from(const std::string& preset, const std::string& yaml_path) {
  PipelineConfig config = config_with(preset, yaml_path, nullptr);
  if (sensor_needs_estimate(config))
    throw InputError((yaml_path.empty() ? std::string("--preset auto") : yaml_path + ": sensor preset auto") +
                     ": the sensor model is estimated from the data only by `dloam run` and `dloam check`; "
                     "write it to a file with `dloam check SEQUENCE --write-sensor FILE` and use that");
  return config;
}

PipelineConfig config_from(const std::string& preset, const std::string& yaml_path,
                           const SensorConfig& estimated) {
  return config_with(preset, yaml_path, &estimated);
}

bool config_file_sets(const std::string& yaml_path, const std::string& section) {
  if (yaml_path.empty()) return false;
  try {
    const YAML::Node root = YAML::Load(read_file(yaml_path, kMaxConfigFileBytes));
    return root && root.IsMap() && root[section];
  } catch (const YAML::Exception&) {
    return false;  // load_config() reports the syntax error
  }
}

void validate_config(const PipelineConfig& config, const std::string& source) {
  PipelineConfig c = config;  // visit() takes non-const references
  Validator validator{source, ""};
  visit(c, validator);
  try {
    c.sensor.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": " + e.what());
  }
  auto fail = [&](const std::string& what) { throw InputError(source + ": " + what); };
  if (c.segmentation.N_ground_rows > c.sensor.N_scan)
    fail("segmentation.N_ground_rows is larger than sensor.N_scan");
  if (c.segmentation.N_min_cluster_small > c.segmentation.N_min_cluster)
    fail("segmentation.N_min_cluster_small must not exceed N_min_cluster");
  if (c.features.S % 2 != 0) fail("features.S must be even (half of the neighbours on each side)");
  if (c.features.N_fe > c.features.N_Fe) fail("features.N_fe must not exceed N_Fe (f_e is a subset of F_e)");
  if (c.mapping.latency_scans > c.mapping.every_n_scans)
    fail("mapping.latency_scans must not exceed mapping.every_n_scans (one mapping job at a time)");
  if (c.mapping.edge_line_ratio > 0.0 && c.mapping.edge_line_ratio < 1.0)
    fail(
        "mapping.edge_line_ratio must be 0 (by the sensor) or at least 1 (a line spreads more along than "
        "across)");
  // Voxel keys are 32-bit integers per axis: a leaf of 1 mm spans +-2,100 km, room for points up to
  // 1e6 m from a sensor up to 1e6 m from the start; a smaller leaf would overflow them.
  for (const auto& [key, leaf] :
       {std::pair<const char*, double>{"features.plane_leaf_size", c.features.plane_leaf_size},
        {"mapping.edge_leaf_size", c.mapping.edge_leaf_size},
        {"mapping.plane_leaf_size", c.mapping.plane_leaf_size},
        {"mapping.map_leaf_size", c.mapping.map_leaf_size}})
    if (leaf < detail::kMinLeafSize)
      fail(std::string(key) + " = " + std::to_string(leaf) +
           " m is below 0.001 m: the voxel grid's 32-bit keys would overflow within " +
           std::to_string(2.0e9 * leaf / 1000.0) + " km of the start (and no LiDAR resolves it)");
}

}  // namespace dloam::io
