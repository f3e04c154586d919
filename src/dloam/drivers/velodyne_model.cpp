#include "dloam/drivers/velodyne_model.hpp"

#include <algorithm>
#include <array>
#include <cctype>

namespace dloam::drivers {
namespace {

// Timing (user manuals): VLP-16 fires 16 lasers 2.304 us apart in a 55.296 us sequence, two
// sequences per block; the VLP-32C fires pairs of lasers 2.304 us apart in 55.296 us; the HDL-32E
// fires 32 lasers 1.152 us apart in 46.08 us and stamps the packet at its end (first firing at
// TOH - 542.592 us); the HDL-64E S2 fires one upper and one lower laser together, 0.728 us apart,
// 23.296 us per upper/lower block pair, first firing 419.30 us before the packet's stamp; the
// VLS-128 fires 16 groups of 8 lasers 2.665 us apart (plus one maintenance slot after group 8) in
// a 53.3 us sequence, the TOH being 8.7 us after the first firing.
const std::array<VelodyneModelInfo, 6> kModels = {{
    {VelodyneModel::kVLP16, "VLP-16", 16, 0.002, 100.0, 0.4, 1, 110.592, 0.0, true, 0x22},
    {VelodyneModel::kVLP32C, "VLP-32C", 32, 0.004, 200.0, 0.4, 1, 55.296, 0.0, true, 0x28},
    {VelodyneModel::kHDL32E, "HDL-32E", 32, 0.002, 100.0, 0.4, 1, 46.08, -542.592, true, 0x21},
    {VelodyneModel::kHDL64E_S2, "HDL-64E S2", 64, 0.002, 120.0, 0.9, 2, 23.296, -419.30, false, 0},
    {VelodyneModel::kHDL64E_S3, "HDL-64E S3", 64, 0.002, 120.0, 0.9, 2, 23.296, -419.30, false, 0},
    {VelodyneModel::kVLS128, "VLS-128", 128, 0.004, 245.0, 0.4, 4, 53.3, -8.7, true, 0xA1},
}};

std::string squash(const std::string& s) {
  std::string out;
  for (char c : s)
    if (std::isalnum(static_cast<unsigned char>(c)))
      out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

// VLP-16 datasheet: laser i points at -15 + i degrees (even i) or i degrees (odd i).
std::vector<double> vlp16_vert() {
  std::vector<double> v(16);
  for (int i = 0; i < 16; ++i)
    v[static_cast<std::size_t>(i)] = (i % 2 == 0) ? -15.0 + i : static_cast<double>(i);
  return v;
}

// HDL-32E manual: even lasers -30.67 .. -10.67, odd lasers -9.33 .. 10.67, 1.33 degrees apart.
const std::array<double, 32> kHdl32Vert = {-30.67, -9.33, -29.33, -8.00, -28.00, -6.67, -26.67, -5.33,
                                           -25.33, -4.00, -24.00, -2.67, -22.67, -1.33, -21.33, 0.00,
                                           -20.00, 1.33,  -18.67, 2.67,  -17.33, 4.00,  -16.00, 5.33,
                                           -14.67, 6.67,  -13.33, 8.00,  -12.00, 9.33,  -10.67, 10.67};

// VLP-32C manual: vertical angle and azimuth offset per laser.
const std::array<double, 32> kVlp32Vert = {-25.000, -1.000, -1.667, -15.639, -11.310, 0.000,  -0.667, -8.843,
                                           -7.254,  0.333,  -0.333, -6.148,  -5.333,  1.333,  0.667,  -4.000,
                                           -4.667,  1.667,  1.000,  -3.667,  -3.333,  3.333,  2.333,  -2.667,
                                           -3.000,  7.000,  4.667,  -2.333,  -2.000,  15.000, 10.333, -1.333};
const std::array<double, 32> kVlp32Rot = {-1.4, 4.2,  -1.4, 1.4,  -1.4, 1.4,  -4.2, 1.4,  -1.4, 4.2,  -1.4,
                                          1.4,  -4.2, 1.4,  -4.2, 1.4,  -1.4, 4.2,  -1.4, 4.2,  -4.2, 1.4,
                                          -1.4, 1.4,  -1.4, 1.4,  -1.4, 4.2,  -4.2, 1.4,  -1.4, 1.4};

// VLS-128 manual: vertical angle per laser; the azimuth offset repeats every 8 lasers.
const std::array<double, 128> kVls128Vert = {
    -11.742, -1.990,  3.400,  -5.290,  -0.780, 4.610,  -4.080,  1.310,  -6.500, -1.110,  4.280,  -4.410,
    0.100,   6.480,   -3.200, 2.190,   -3.860, 1.530,  -9.244,  -1.770, 2.740,  -5.950,  -0.560, 4.830,
    -2.980,  2.410,   -6.280, -0.890,  3.620,  -5.070, 0.320,   7.580,  -0.340, 5.180,   -3.640, 1.750,
    -25.000, -2.430,  2.960,  -5.730,  0.540,  9.700,  -2.760,  2.630,  -7.650, -1.550,  3.840,  -4.850,
    3.180,   -5.510,  -0.120, 5.730,   -4.300, 1.090,  -16.042, -2.210, 4.060,  -4.630,  0.760,  15.000,
    -3.420,  1.970,   -6.850, -1.330,  -5.620, -0.230, 5.430,   -3.530, 0.980,  -19.582, -2.320, 3.070,
    -4.740,  0.650,   11.750, -2.650,  1.860,  -7.150, -1.440,  3.950,  -2.100, 3.290,   -5.400, -0.010,
    4.500,   -4.190,  1.200,  -13.565, -1.220, 4.170,  -4.520,  0.870,  6.080,  -3.310,  2.080,  -6.650,
    1.420,   -10.346, -1.880, 3.510,   -6.060, -0.670, 4.720,   -3.970, 2.300,  -6.390,  -1.000, 4.390,
    -5.180,  0.210,   6.980,  -3.090,  4.980,  -3.750, 1.640,   -8.352, -2.540, 2.850,   -5.840, -0.450,
    8.430,   -2.870,  2.520,  -6.170,  -1.660, 3.730,  -4.960,  0.430};
const std::array<double, 8> kVls128Rot = {-6.354, -4.548, -2.732, -0.911, 0.911, 2.732, 4.548, 6.354};

}  // namespace

const VelodyneModelInfo& velodyne_model_info(VelodyneModel model) {
  return kModels[static_cast<std::size_t>(model)];
}

const char* velodyne_model_name(VelodyneModel model) { return velodyne_model_info(model).name; }

std::optional<VelodyneModel> parse_velodyne_model(const std::string& name) {
  const std::string s = squash(name);
  if (s == "VLP16" || s == "PUCK") return VelodyneModel::kVLP16;
  if (s == "VLP32C" || s == "VLP32" || s == "32C") return VelodyneModel::kVLP32C;
  if (s == "HDL32E" || s == "HDL32" || s == "32E") return VelodyneModel::kHDL32E;
  if (s == "HDL64ES2" || s == "HDL64S2" || s == "64ES2" || s == "HDL64ES21" || s == "64ES21")
    return VelodyneModel::kHDL64E_S2;
  if (s == "HDL64ES3" || s == "HDL64S3" || s == "64ES3") return VelodyneModel::kHDL64E_S3;
  if (s == "VLS128" || s == "VLP128" || s == "ALPHAPRIME") return VelodyneModel::kVLS128;
  return std::nullopt;
}

std::string velodyne_model_names() { return "VLP-16, VLP-32C, HDL-32E, HDL-64E S2, HDL-64E S3, VLS-128"; }

float velodyne_channel_offset_us(VelodyneModel model, int bank, int channel) {
  switch (model) {
    case VelodyneModel::kVLP16:
      // Same float operations as the manual's table: dsr * 2.304 + firing * 55.296.
      return static_cast<float>(channel % 16) * 2.304f + static_cast<float>(channel / 16) * 55.296f;
    case VelodyneModel::kVLP32C:
      return static_cast<float>(channel / 2) * 2.304f;
    case VelodyneModel::kHDL32E:
      return static_cast<float>(channel) * 1.152f;
    case VelodyneModel::kHDL64E_S2:
    case VelodyneModel::kHDL64E_S3:
      return static_cast<float>(channel) * 0.728f;
    case VelodyneModel::kVLS128: {
      const int group = velodyne_laser_of(model, bank, channel) / 8;
      return 2.665f * static_cast<float>(group + group / 8);
    }
  }
  return 0.0f;
}

int velodyne_laser_of(VelodyneModel model, int bank, int channel) {
  switch (model) {
    case VelodyneModel::kVLP16:
      return channel % 16;
    case VelodyneModel::kVLP32C:
    case VelodyneModel::kHDL32E:
      return channel;
    case VelodyneModel::kHDL64E_S2:
    case VelodyneModel::kHDL64E_S3:
    case VelodyneModel::kVLS128:
      return 32 * bank + channel;
  }
  return channel;
}

NominalAngles velodyne_nominal_angles(VelodyneModel model) {
  NominalAngles a;
  switch (model) {
    case VelodyneModel::kVLP16:
      a.vert_deg = vlp16_vert();
      a.rot_deg.assign(16, 0.0);
      break;
    case VelodyneModel::kVLP32C:
      a.vert_deg.assign(kVlp32Vert.begin(), kVlp32Vert.end());
      a.rot_deg.assign(kVlp32Rot.begin(), kVlp32Rot.end());
      break;
    case VelodyneModel::kHDL32E:
      a.vert_deg.assign(kHdl32Vert.begin(), kHdl32Vert.end());
      a.rot_deg.assign(32, 0.0);
      break;
    case VelodyneModel::kHDL64E_S2:
    case VelodyneModel::kHDL64E_S3:
      break;
    case VelodyneModel::kVLS128:
      a.vert_deg.assign(kVls128Vert.begin(), kVls128Vert.end());
      for (int i = 0; i < 128; ++i) a.rot_deg.push_back(kVls128Rot[static_cast<std::size_t>(i % 8)]);
      break;
  }
  return a;
}

}  // namespace dloam::drivers
