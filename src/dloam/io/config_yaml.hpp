// YAML configuration of the pipeline: load (defaults + optional sensor preset + explicit keys),
// validate, and dump with every field and a comment per parameter. The key <-> field table is
// dloam/io/config_schema.hpp. Errors are dloam::InputError naming the file, line and key path.
#pragma once

#include <string>

#include "dloam/pipeline/config.hpp"

namespace dloam::io {

/// Sensor "presets" that are no built-in model: `custom` (a model given by its keys alone, what
/// `dloam check --write-sensor` writes; unset keys keep SensorConfig's defaults) and `auto` (the
/// model estimated from the data at the start of a run; see config_from_allowing_auto).
inline constexpr const char* kCustomSensor = "custom";
inline constexpr const char* kAutoSensor = "auto";
/// True when the sensor section still has to be estimated from the data (preset auto).
bool sensor_needs_estimate(const PipelineConfig& config);

/// Built-in defaults with the sensor section of a preset (HDL-64E when empty), `custom`, or
/// `auto` (unresolved: SensorConfig's defaults named "auto"); throws InputError for an unknown
/// preset name.
PipelineConfig default_config(const std::string& preset = "");

/// Reads a YAML file over `base`: `sensor: {preset: NAME}` first replaces the sensor section
/// by that preset, then every explicit key overrides. Unknown keys and wrong types are errors
/// naming the file and key path (e.g. "sensor.N_scna"); the result is validated.
PipelineConfig load_config(const std::string& yaml_path);
PipelineConfig load_config(const std::string& yaml_path, const PipelineConfig& base);
/// What every front-end starts from: the preset's defaults, overridden by the YAML file when
/// `yaml_path` is not empty (validated as load_config does). Throws InputError when the sensor
/// is `auto`: only the commands that read the data first can estimate it.
PipelineConfig config_from(const std::string& preset, const std::string& yaml_path);
/// As config_from, but a sensor preset `auto` (from `preset` or the file) stays unresolved:
/// sensor.preset is "auto" and the sensor fields hold the file's keys over SensorConfig's
/// defaults (vertical_angle_correction_deg is what the estimate uses).
PipelineConfig config_from_allowing_auto(const std::string& preset, const std::string& yaml_path);
/// As config_from with the sensor preset `auto` standing for `estimated`: the file's explicit
/// sensor keys still override it.
PipelineConfig config_from(const std::string& preset, const std::string& yaml_path,
                           const SensorConfig& estimated);
/// Same from YAML text; `source` names it in error messages.
PipelineConfig config_from_yaml_string(const std::string& yaml, const std::string& source = "<yaml>",
                                       const PipelineConfig& base = default_config());

/// True when the YAML file has a top-level `section` key (e.g. "sensor"); false for an empty path.
bool config_file_sets(const std::string& yaml_path, const std::string& section);

/// Range / choice / consistency checks of every field (the limits of config_schema.hpp and
/// SensorConfig::validate()); throws InputError "<source>: <key path> ...".
void validate_config(const PipelineConfig& config, const std::string& source = "config");

/// The full YAML: every field, grouped as in config.hpp, with a one-line comment each.
/// `section` = "sensor", "mapping", ...: only that group (throws InputError if unknown).
std::string dump_config(const PipelineConfig& config, const std::string& section = "");

}  // namespace dloam::io
