// Hesai model facts: names, counts, range limits, return-mode layouts, block timing.
#include "dloam/drivers/hesai_model.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace dloam::drivers::hesai {

namespace {

// Range limits are the sensors' specified ranges; step_deg_600 is the firing interval in azimuth
// at 10 Hz (user manuals: 0.2 deg Pandar40P/64, 0.6 QT64, 0.4 QT128, 0.18 XT family).
const ModelInfo kModels[] = {
    {Model::kPandar40P, "Pandar40P", 40, 10, 0.3, 200.0, 0.2, false},
    {Model::kPandar64, "Pandar64", 64, 6, 0.3, 200.0, 0.2, false},
    {Model::kPandarQT64, "PandarQT64", 64, 4, 0.1, 60.0, 0.6, false},
    {Model::kPandarQT128, "PandarQT128", 128, 2, 0.05, 50.0, 0.4, false},
    {Model::kPandarXT16, "PandarXT16", 16, 8, 0.05, 120.0, 0.18, true},
    {Model::kPandarXT32, "PandarXT32", 32, 8, 0.05, 120.0, 0.18, true},
    {Model::kPandarXT32M, "PandarXT32M", 32, 6, 0.5, 300.0, 0.18, false},
};

std::string squeeze(std::string_view name) {
  std::string s;
  for (const char c : name) {
    if (c == '-' || c == '_' || c == ' ') continue;
    s.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return s;
}

}  // namespace

const ModelInfo& model_info(Model model) {
  for (const ModelInfo& m : kModels)
    if (m.model == model) return m;
  throw std::invalid_argument("hesai: unknown model enum value");
}

const std::vector<Model>& all_models() {
  static const std::vector<Model> models = [] {
    std::vector<Model> v;
    for (const ModelInfo& m : kModels) v.push_back(m.model);
    return v;
  }();
  return models;
}

bool parse_model(std::string_view name, Model& model) {
  std::string s = squeeze(name);
  if (s.rfind("pandar", 0) == 0) s = s.substr(6);
  if (s == "qt128c2x") s = "qt128";
  if (s == "xt32m2x") s = "xt32m";
  if (s == "40") s = "40p";
  for (const ModelInfo& m : kModels) {
    if (squeeze(m.name).substr(6) == s) {
      model = m.model;
      return true;
    }
  }
  return false;
}

std::string model_list() {
  std::string s;
  for (const ModelInfo& m : kModels) {
    if (!s.empty()) s += ", ";
    s += m.name;
  }
  return s;
}

ReturnLayout return_layout(Model model, std::uint8_t mode) {
  const bool flipped = model_info(model).last_before_first;
  switch (mode) {
    case 0x33:
      return {1, "single first", 0, -1, -1};
    case 0x34:
      return {1, "single second", -1, -1, -1};
    case 0x37:
      return {1, "single strongest", -1, -1, 0};
    case 0x38:
      return {1, "single last", -1, 0, -1};
    case 0x39:
      return {2, "dual last+strongest", -1, 0, -2};
    case 0x3a:
      return {2, "dual first+second", 0, -1, -1};
    case 0x3b:
      return flipped ? ReturnLayout{2, "dual first+last", 1, 0, -1}
                     : ReturnLayout{2, "dual first+last", 0, 1, -1};
    case 0x3c:
      return {2, "dual first+strongest", 0, -1, -2};
    case 0x3d:
      return {3, "triple first+last+strongest", 0, 1, 2};
    case 0x3e:
      return {2, "dual strongest+second strongest", -1, -1, 0};
    default:
      return {0, "unknown", -1, -1, -1};
  }
}

int group_firing_offset_ns(Model model, int group, int groups) {
  // Start (QT64, QT128, XT) or end (Pandar40P/64) of the block's firing relative to the packet's
  // timestamp, from the user manuals' block timing; groups are one firing each.
  const int from_last = groups - 1 - group;
  switch (model) {
    case Model::kPandar40P:
      return -28580 - 55560 * from_last;
    case Model::kPandar64:
      return -42580 - 55560 * from_last;
    case Model::kPandarQT64:
      return 25710 + 500000 * group / 3;
    case Model::kPandarQT128:
      return 9000 - 111110 * from_last;
    case Model::kPandarXT16:
    case Model::kPandarXT32:
    case Model::kPandarXT32M:
      return 5632 - 50000 * from_last;
  }
  return 0;
}

}  // namespace dloam::drivers::hesai
