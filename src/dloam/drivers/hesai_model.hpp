// The Hesai models dloam decodes and their fixed facts: channel and block counts, sensor range
// limits, nominal angle tables (elevation and azimuth offset per channel, as in the vendor's
// angle-correction CSV), firing-time offsets and return-mode layouts.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dloam::drivers::hesai {

enum class Model : std::uint8_t {
  kPandar40P,
  kPandar64,
  kPandarQT64,
  kPandarQT128,  ///< QT128C2X
  kPandarXT16,
  kPandarXT32,
  kPandarXT32M,  ///< XT32M2X
};

struct ModelInfo {
  Model model;
  const char* name;    ///< as Hesai writes it: "Pandar40P", "PandarQT128", ...
  int channels;        ///< lasers
  int blocks;          ///< blocks per data packet
  double min_range_m;  ///< the sensor's own range limits
  double max_range_m;
  double step_deg_600;  ///< azimuth step between firings at 600 rpm
  /// Dual-return packets store the last return before the first one (0x3b).
  bool last_before_first;
};

const ModelInfo& model_info(Model model);
inline const char* model_name(Model model) { return model_info(model).name; }
/// Every model, in enum order.
const std::vector<Model>& all_models();
/// Parses a model name: case, '-', '_' and spaces are ignored, the "Pandar" prefix is optional and
/// the variant suffixes C2X (QT128) and 2X (XT32M) are accepted ("QT128C2X", "pandar-xt32"). False
/// when the name is not one of the models.
bool parse_model(std::string_view name, Model& model);
/// "Pandar40P, Pandar64, ..." for error messages.
std::string model_list();

/// Nominal angles of one channel (deg): the published design values of the model.
struct ChannelAngle {
  double elevation_deg;
  double azimuth_deg;
};
/// The model's nominal angle table, channel 1 first (the built-in calibration).
std::vector<ChannelAngle> nominal_angles(Model model);

/// Firing time of `channel` relative to its block's reference time (ns). `sequence` selects the
/// QT128's firing sequence (0 or 1; its channels 0-31 fire only in sequence 1, 32-63 only in
/// sequence 0); other models ignore it.
int channel_firing_offset_ns(Model model, int channel, int sequence);
/// Time of block group `group` (of `groups` in the packet) relative to the packet's timestamp (ns).
int group_firing_offset_ns(Model model, int group, int groups);

/// What a return-mode byte says about the returns of one firing.
struct ReturnLayout {
  int returns = 0;   ///< returns per firing (blocks per group); 0: unknown mode
  const char* name;  ///< "dual last+strongest"
  int first = -1;    ///< index of the first return in the group, -1 when not reported
  int last = -1;     ///< index of the last return, -1 when not reported
  /// Index of the strongest return; -2: the stronger of returns 0 and 1 (a dual mode that stores
  /// the second strongest when the other return is also the strongest); -1: not reported.
  int strongest = -1;
};
/// Layout of return-mode byte `mode` (0x33-0x3e) for `model`; returns == 0 for an unknown byte.
ReturnLayout return_layout(Model model, std::uint8_t mode);

}  // namespace dloam::drivers::hesai
