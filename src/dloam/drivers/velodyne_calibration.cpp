#include "dloam/drivers/velodyne_calibration.hpp"

#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "dloam/core/types.hpp"

namespace dloam::drivers {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

/// A number read from the file as the message shows it (shortest form; any magnitude, no cast).
std::string as_written(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

double yaml_number(const std::string& path, const YAML::Node& node, const std::string& where) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) fail(path, where + " is not a finite number");
    return v;
  } catch (const YAML::Exception&) {
    fail(path, where + " is not a number");
  }
}

VelodyneCalibration read_yaml(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    fail(path, "cannot open the calibration file");
  } catch (const YAML::Exception& e) {
    fail(path, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) fail(path, "a Velodyne calibration YAML is a map with a 'lasers' list");
  const YAML::Node lasers = root["lasers"];
  if (!lasers) fail(path, "missing key 'lasers'");
  if (!lasers.IsSequence() || lasers.size() == 0) fail(path, "'lasers' must be a non-empty list");

  VelodyneCalibration cal;
  cal.source = path;
  if (const YAML::Node r = root["distance_resolution"]) {
    cal.distance_resolution = yaml_number(path, r, "distance_resolution");
    if (!(cal.distance_resolution > 0.0)) fail(path, "distance_resolution must be > 0");
  }
  const std::size_t n = lasers.size();
  if (const YAML::Node nl = root["num_lasers"]) {
    const double v = yaml_number(path, nl, "num_lasers");
    if (v != static_cast<double>(n))
      fail(path, "num_lasers is " + as_written(v) + " but 'lasers' lists " + std::to_string(n));
  }
  cal.lasers.resize(n);
  std::vector<bool> seen(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const YAML::Node l = lasers[i];
    const std::string at = "lasers[" + std::to_string(i) + "]";
    if (!l.IsMap()) fail(path, at + " is not a map");
    auto required = [&](const char* key) {
      const YAML::Node v = l[key];
      if (!v) fail(path, at + ": missing key '" + key + "'");
      return yaml_number(path, v, at + "." + key);
    };
    auto optional = [&](const char* key, double fallback) {
      const YAML::Node v = l[key];
      return v ? yaml_number(path, v, at + "." + key) : fallback;
    };
    const double id = required("laser_id");
    if (id < 0 || id >= static_cast<double>(n) || id != std::floor(id))
      fail(path, at + ": laser_id " + std::to_string(id) + " is not in 0.." + std::to_string(n - 1));
    const auto k = static_cast<std::size_t>(id);
    if (seen[k]) fail(path, at + ": laser_id " + std::to_string(k) + " appears twice");
    seen[k] = true;
    VelodyneLaser& laser = cal.lasers[k];
    laser.laser_id = static_cast<int>(k);
    laser.rot_correction = required("rot_correction");
    laser.vert_correction = required("vert_correction");
    laser.dist_correction = required("dist_correction");
    laser.vert_offset_correction = required("vert_offset_correction");
    laser.dist_correction_x = optional("dist_correction_x", 0.0);
    laser.dist_correction_y = optional("dist_correction_y", 0.0);
    laser.horiz_offset_correction = optional("horiz_offset_correction", 0.0);
    laser.focal_distance = optional("focal_distance", 0.0);
    laser.focal_slope = optional("focal_slope", 0.0);
    laser.min_intensity = std::floor(optional("min_intensity", 0.0));
    laser.max_intensity = std::floor(optional("max_intensity", 255.0));
    if (const YAML::Node t = l["two_pt_correction_available"]) {
      try {
        laser.two_pt_correction_available = t.as<bool>();
      } catch (const YAML::Exception&) {
        fail(path, at + ".two_pt_correction_available is not a boolean");
      }
    }
  }
  return cal;
}

const tinyxml2::XMLElement* child(const std::string& path, const tinyxml2::XMLElement* parent,
                                  const char* name) {
  const tinyxml2::XMLElement* e = parent->FirstChildElement(name);
  if (!e) fail(path, std::string("missing element <") + name + "> in <" + parent->Name() + ">");
  return e;
}

double xml_number(const std::string& path, const tinyxml2::XMLElement* e, const std::string& where) {
  double v = 0.0;
  if (e->QueryDoubleText(&v) != tinyxml2::XML_SUCCESS || !std::isfinite(v))
    fail(path, where + " is not a number");
  return v;
}

/// The <item> children of a boost-serialized vector (skipping <count> and <item_version>).
std::vector<const tinyxml2::XMLElement*> items(const tinyxml2::XMLElement* list) {
  std::vector<const tinyxml2::XMLElement*> out;
  for (const auto* e = list->FirstChildElement("item"); e; e = e->NextSiblingElement("item"))
    out.push_back(e);
  return out;
}

VelodyneCalibration read_xml(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    fail(path, std::string("not readable XML: ") + (doc.ErrorStr() ? doc.ErrorStr() : "?"));
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root) fail(path, "empty XML document");
  const tinyxml2::XMLElement* db = std::string(root->Name()) == "DB" ? root : child(path, root, "DB");
  const auto points = items(child(path, db, "points_"));
  if (points.empty()) fail(path, "<points_> has no laser");

  std::vector<bool> enabled(points.size(), true);
  if (const auto* en = db->FirstChildElement("enabled_")) {
    const auto flags = items(en);
    for (std::size_t i = 0; i < flags.size() && i < enabled.size(); ++i)
      enabled[i] = xml_number(path, flags[i], "enabled_ item " + std::to_string(i)) != 0.0;
  }
  std::vector<double> min_int, max_int;
  for (const char* name : {"minIntensity_", "maxIntensity_"}) {
    std::vector<double>& dst = std::string(name) == "minIntensity_" ? min_int : max_int;
    if (const auto* e = db->FirstChildElement(name))
      for (const auto* it : items(e)) dst.push_back(xml_number(path, it, name));
  }

  VelodyneCalibration cal;
  cal.source = path;
  if (const auto* lsb = db->FirstChildElement("distLSB_"))
    cal.distance_resolution = xml_number(path, lsb, "distLSB_") / 100.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string at = "points_ item " + std::to_string(i);
    const tinyxml2::XMLElement* px = child(path, points[i], "px");
    const double id_value = xml_number(path, child(path, px, "id_"), at + " id_");
    if (id_value < 0 || id_value >= static_cast<double>(points.size()) || id_value != std::floor(id_value))
      fail(path, at + ": id_ " + as_written(id_value) + " is not in 0.." + std::to_string(points.size() - 1));
    const int id = static_cast<int>(id_value);
    if (!enabled[static_cast<std::size_t>(id)]) continue;
    auto field = [&](const char* name) { return xml_number(path, child(path, px, name), at + " " + name); };
    VelodyneLaser l;
    l.laser_id = id;
    l.rot_correction = field("rotCorrection_") * kDegToRad;
    l.vert_correction = field("vertCorrection_") * kDegToRad;
    l.dist_correction = field("distCorrection_") / 100.0;
    l.dist_correction_x = field("distCorrectionX_") / 100.0;
    l.dist_correction_y = field("distCorrectionY_") / 100.0;
    l.vert_offset_correction = field("vertOffsetCorrection_") / 100.0;
    l.horiz_offset_correction = field("horizOffsetCorrection_") / 100.0;
    l.focal_distance = field("focalDistance_") / 100.0;
    l.focal_slope = field("focalSlope_");
    const auto k = static_cast<std::size_t>(id);
    if (k < min_int.size()) l.min_intensity = min_int[k];
    if (k < max_int.size()) l.max_intensity = max_int[k];
    cal.lasers.push_back(l);
  }
  if (cal.lasers.empty()) fail(path, "no enabled laser");
  std::sort(cal.lasers.begin(), cal.lasers.end(),
            [](const VelodyneLaser& a, const VelodyneLaser& b) { return a.laser_id < b.laser_id; });
  for (std::size_t i = 0; i < cal.lasers.size(); ++i)
    if (cal.lasers[i].laser_id != static_cast<int>(i))
      fail(path, "the enabled lasers are not 0.." + std::to_string(cal.lasers.size() - 1) + " (laser " +
                     std::to_string(cal.lasers[i].laser_id) + " enabled, " + std::to_string(i) + " not)");
  return cal;
}

/// Angles a laser can have: an elevation within +-90 deg and an azimuth offset within +-180 deg.
void check_angles(const VelodyneCalibration& cal, const std::string& path, const char* unit) {
  for (const VelodyneLaser& l : cal.lasers) {
    const std::string at = "laser " + std::to_string(l.laser_id) + ": ";
    if (std::abs(l.vert_correction) > kPi / 2)
      fail(path, at + "vertical correction " + std::to_string(l.vert_correction / kDegToRad) +
                     " deg is not an elevation (the file is in " + unit + ")");
    if (std::abs(l.rot_correction) > kPi)
      fail(path, at + "rotational correction " + std::to_string(l.rot_correction / kDegToRad) +
                     " deg is not an azimuth offset (the file is in " + unit + ")");
  }
}

bool looks_like_xml(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open the calibration file");
  char c = 0;
  while (in.get(c))
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '<';
  return false;
}

}  // namespace

void assign_velodyne_rings(VelodyneCalibration& calibration) {
  std::vector<int> order(calibration.lasers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return calibration.lasers[static_cast<std::size_t>(a)].vert_correction <
           calibration.lasers[static_cast<std::size_t>(b)].vert_correction;
  });
  for (std::size_t r = 0; r < order.size(); ++r)
    calibration.lasers[static_cast<std::size_t>(order[r])].ring = static_cast<int>(r);
}

VelodyneCalibration read_velodyne_calibration(const std::string& path) {
  const bool xml = looks_like_xml(path);
  VelodyneCalibration cal = xml ? read_xml(path) : read_yaml(path);
  check_angles(cal, path, xml ? "degrees" : "radians");
  assign_velodyne_rings(cal);
  return cal;
}

VelodyneCalibration nominal_velodyne_calibration(VelodyneModel model) {
  const VelodyneModelInfo& info = velodyne_model_info(model);
  if (!info.has_nominal_table)
    throw InputError(std::string(info.name) +
                     ": no nominal angle table exists (every unit is calibrated at the factory); give its "
                     "calibration file (the ROS driver's YAML or VeloView's db.xml) as the calibration");
  const NominalAngles a = velodyne_nominal_angles(model);
  VelodyneCalibration cal;
  cal.source = std::string("nominal ") + info.name + " table";
  cal.distance_resolution = info.distance_unit_m;
  for (std::size_t i = 0; i < a.vert_deg.size(); ++i) {
    VelodyneLaser l;
    l.laser_id = static_cast<int>(i);
    l.vert_correction = a.vert_deg[i] * kDegToRad;
    l.rot_correction = a.rot_deg[i] * kDegToRad;
    cal.lasers.push_back(l);
  }
  assign_velodyne_rings(cal);
  return cal;
}

}  // namespace dloam::drivers
