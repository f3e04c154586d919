// The built-in sensor presets, as data: one row per model with its beam table (or uniform
// blocks), image width, range limits, beam origin geometry and where the numbers come from.
// sensor_preset() turns a row into a SensorConfig; the preset lists of the command-line help and
// `dloam config presets` come from the same rows.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "dloam/core/sensor.hpp"

namespace dloam {

namespace {

/// `n` evenly spaced beams from `lo` to `hi` (deg), bottom first.
struct UniformBlock {
  double lo, hi;
  int n;
};

/// One model. The beams are `elevations_deg` (bottom first) when given; otherwise `blocks`: one
/// block is the uniform model of eq. 4 (no table: Pit_bottom .. fov_top), several are expanded
/// into a table. Beam origin heights (sensor frame): beams leaving a ring of radius
/// `beam_origin_radius_m` around the axis at height `origin_height_m` reach a point at horizontal
/// distance h at z = origin_height - radius tan(e) + h tan(e), so beam k's origin height is
/// origin_height - radius tan(e_k) (Ouster: lidar_to_sensor_transform z and
/// lidar_origin_to_beam_origin_mm of the sensor's metadata). Both 0: no origin heights.
struct PresetRow {
  const char* name;
  const char* source;
  int columns;  ///< Horizon_SCAN at 10 Hz
  double min_range, max_range;
  std::vector<double> elevations_deg;
  std::vector<UniformBlock> blocks;
  double origin_height_m, beam_origin_radius_m;
};

// Sources: the files named are in the shared data folder (../shared/data/sensors, see its README
// for their provenance): nebula's Velodyne calibration YAMLs (vert_correction, radians, converted
// to degrees and rounded to 0.001 deg), nebula's Hesai angle-correction CSVs (Elevation column as
// given) and Ouster sensor metadata JSONs (beam_altitude_angles as given). The Ouster JSONs and
// most nebula files are tables of real units; the VLP-16, HDL-32E and VLP-32C files hold round
// nominal angles. Tables bottom first. The range limits of the presets other than HDL-64E,
// HDL-32E, VLP-16, OS1-64 and OS1-128 are generous round values, not from these files.
const std::vector<PresetRow>& rows() {
  static const std::vector<PresetRow> table = {
      {"HDL-64E",
       "Velodyne HDL-64E: two blocks of 32 evenly spaced beams, +2.0 .. -8.33 and -8.83 .. -24.9 deg "
       "(nominal); no origin heights",
       2048,
       2.5,
       120.0,
       {},
       {{-24.9, -8.83, 32}, {-8.33, 2.0, 32}},
       0.0,
       0.0},
      {"HDL-32E",
       "Velodyne HDL-32E: 32 beams, -30.67 .. +10.67 deg in steps of 1.33 deg (nominal, as nebula "
       "HDL32.yaml), uniform",
       1800,
       1.0,
       100.0,
       {},
       {{-30.67, 10.67, 32}},
       0.0,
       0.0},
      {"VLP-16",
       "Velodyne VLP-16: 16 beams, -15 .. +15 deg in steps of 2 deg (nominal, as nebula VLP16.yaml), uniform",
       1800,
       1.0,
       100.0,
       {},
       {{-15.0, 15.0, 16}},
       0.0,
       0.0},
      {"VLP-32C",
       "Velodyne VLP-32C: the nominal angles of nebula "
       "sensors/velodyne/nebula/calibration/VLP32.yaml; range limits are generous round values, not from the "
       "table source",
       1800,
       1.0,
       200.0,
       {-25,   -15.639, -11.31, -8.843, -7.254, -6.148, -5.333, -4.667, -4,     -3.667, -3.333,
        -3,    -2.667,  -2.333, -2,     -1.667, -1.333, -1,     -0.667, -0.333, 0,      0.333,
        0.667, 1,       1.333,  1.667,  2.333,  3.333,  4.667,  7,      10.333, 15},
       {},
       0.0,
       0.0},
      {"VLS-128",
       "Velodyne VLS-128 (Alpha Prime): nebula sensors/velodyne/nebula/calibration/VLS128.yaml; range limits "
       "are generous round values, not from the table source",
       1800,
       1.0,
       250.0,
       {-25,   -19.582, -16.042, -13.565, -11.742, -10.346, -9.244, -8.352, -7.65, -7.15, -6.85, -6.65, -6.5,
        -6.39, -6.28,   -6.17,   -6.06,   -5.95,   -5.84,   -5.73,  -5.62,  -5.51, -5.4,  -5.29, -5.18, -5.07,
        -4.96, -4.85,   -4.74,   -4.63,   -4.52,   -4.41,   -4.3,   -4.19,  -4.08, -3.97, -3.86, -3.75, -3.64,
        -3.53, -3.42,   -3.31,   -3.2,    -3.09,   -2.98,   -2.87,  -2.76,  -2.65, -2.54, -2.43, -2.32, -2.21,
        -2.1,  -1.99,   -1.88,   -1.77,   -1.66,   -1.55,   -1.44,  -1.33,  -1.22, -1.11, -1,    -0.89, -0.78,
        -0.67, -0.56,   -0.45,   -0.34,   -0.23,   -0.12,   -0.01,  0.1,    0.21,  0.32,  0.43,  0.54,  0.65,
        0.76,  0.87,    0.98,    1.09,    1.2,     1.31,    1.42,   1.53,   1.64,  1.75,  1.86,  1.97,  2.08,
        2.19,  2.3,     2.41,    2.52,    2.63,    2.74,    2.85,   2.96,   3.07,  3.18,  3.29,  3.4,   3.51,
        3.62,  3.73,    3.84,    3.95,    4.06,    4.17,    4.28,   4.39,   4.5,   4.61,  4.72,  4.83,  4.98,
        5.18,  5.43,    5.73,    6.08,    6.48,    6.98,    7.58,   8.43,   9.7,   11.75, 15},
       {},
       0.0,
       0.0},
      {"OS0-32",
       "Ouster OS0-32 (uniform): a unit's beam_altitude_angles, "
       "sensors/ouster/OS-0-32-U1_v2.2.0_1024x10.json; origin heights of the sensor frame from its "
       "lidar_to_sensor_transform z (36.18 mm) and lidar_origin_to_beam_origin_mm (27.67); range limits are "
       "generous round values, not from the table source",
       1024,
       0.5,
       100.0,
       {-45.4,  -42.38, -39.39, -36.43, -33.49, -30.58, -27.68, -24.79, -21.92, -19.06, -16.22,
        -13.38, -10.55, -7.72,  -4.9,   -2.09,  0.72,   3.55,   6.35,   9.17,   11.99,  14.81,
        17.66,  20.51,  23.37,  26.25,  29.16,  32.06,  34.98,  37.94,  40.9,   43.88},
       {},
       0.03618,
       0.02767},
      {"OS0-64",
       "Ouster OS0-64: the data sheet's 90 deg field (-45 .. +45), uniform (no unit table here); origin "
       "heights as OS0-32; range limits are generous round values, not from the table source",
       1024,
       0.5,
       100.0,
       {},
       {{-45.0, 45.0, 64}},
       0.03618,
       0.02767},
      {"OS0-128",
       "Ouster OS0-128: a unit's beam_altitude_angles, sensors/ouster/OS-0-128-U1_v2.3.0_1024x10.json; "
       "origin heights from its lidar_to_sensor_transform z (36.18 mm) and lidar_origin_to_beam_origin_mm "
       "(27.67); range limits are generous round values, not from the table source",
       1024,
       0.5,
       100.0,
       {-46.26, -45.24, -44.52, -44.09, -43.22, -42.23, -41.51, -41.08, -40.21, -39.24, -38.55, -38.11,
        -37.24, -36.29, -35.6,  -35.14, -34.29, -33.37, -32.68, -32.21, -31.36, -30.47, -29.78, -29.29,
        -28.46, -27.57, -26.9,  -26.39, -25.56, -24.7,  -24.02, -23.5,  -22.68, -21.84, -21.17, -20.62,
        -19.8,  -18.99, -18.32, -17.77, -16.95, -16.16, -15.48, -14.91, -14.1,  -13.34, -12.65, -12.07,
        -11.28, -10.51, -9.85,  -9.24,  -8.43,  -7.71,  -7.05,  -6.43,  -5.6,   -4.9,   -4.23,  -3.6,
        -2.77,  -2.09,  -1.43,  -0.77,  0.04,   0.71,   1.37,   2.06,   2.86,   3.5,    4.17,   4.87,
        5.68,   6.31,   6.99,   7.71,   8.51,   9.13,   9.81,   10.55,  11.34,  11.94,  12.62,  13.41,
        14.19,  14.76,  15.45,  16.27,  17.04,  17.6,   18.3,   19.13,  19.91,  20.46,  21.16,  22.03,
        22.79,  23.33,  24.03,  24.93,  25.7,   26.23,  26.93,  27.86,  28.62,  29.13,  29.85,  30.8,
        31.56,  32.06,  32.78,  33.74,  34.51,  35,     35.72,  36.71,  37.47,  37.95,  38.69,  39.7,
        40.46,  40.94,  41.68,  42.72,  43.47,  43.93,  44.7,   45.75},
       {},
       0.03618,
       0.02767},
      {"OS1-32",
       "Ouster OS1-32 (uniform): the data sheet's 45 deg field (-22.5 .. +22.5), uniform (no unit table "
       "here); origin heights as OS1-32-G; range limits are generous round values, not from the table source",
       1024,
       1.0,
       120.0,
       {},
       {{-22.5, 22.5, 32}},
       0.03618,
       0.015806},
      {"OS1-32-G",
       "Ouster OS1-32 gradient beam spacing: a unit's beam_altitude_angles, "
       "sensors/ouster/OS-1-32-G_v2.1.1_1024x10.json; origin heights from its lidar_to_sensor_transform z "
       "(36.18 mm) and lidar_origin_to_beam_origin_mm (15.806); range limits are generous round values, not "
       "from the table source",
       1024,
       1.0,
       120.0,
       {-15.32, -14.01, -12.66, -11.31, -9.95, -8.57, -7.17, -5.76, -5.06, -4.36, -3.65,
        -2.96,  -2.6,   -2.24,  -1.88,  -1.54, -1.17, -0.83, -0.49, -0.13, 0.23,  0.6,
        0.93,   1.29,   1.65,   2.02,   2.35,  3.41,  4.47,  7.27,  10.03, 12.75},
       {},
       0.03618,
       0.015806},
      {"OS1-64",
       "Ouster OS1-64 (first generation): the data sheet's 33.2 deg field (-16.6 .. +16.6), uniform; no "
       "origin heights",
       1024,
       1.0,
       120.0,
       {},
       {{-16.6, 16.6, 64}},
       0.0,
       0.0},
      {"OS1-128",
       "Ouster OS1-128: the data sheet's 45 deg field (-22.5 .. +22.5), uniform; no origin heights",
       1024,
       1.0,
       120.0,
       {},
       {{-22.5, 22.5, 128}},
       0.0,
       0.0},
      {"OS2-32",
       "Ouster OS2-32 (uniform): a unit's beam_altitude_angles, "
       "sensors/ouster/OS-2-32-U0_v2.0.0_1024x10.json; origin heights from its lidar_to_sensor_transform z "
       "(74.296 mm) and lidar_origin_to_beam_origin_mm (13.762); range limits are generous round values, not "
       "from the table source",
       1024,
       1.0,
       250.0,
       {-10.48, -9.82, -9.14, -8.47, -7.77, -7.08, -6.4, -5.7, -5.02, -4.32, -3.61,
        -2.92,  -2.22, -1.51, -0.83, -0.12, 0.56,  1.27, 1.96, 2.66,  3.35,  4.06,
        4.76,   5.44,  6.14,  6.83,  7.52,  8.2,   8.88, 9.56, 10.24, 10.87},
       {},
       0.074296,
       0.013762},
      {"OS2-64",
       "Ouster OS2-64: the data sheet's 22.5 deg field (-11.25 .. +11.25), uniform (no unit table here); "
       "origin heights as OS2-128; range limits are generous round values, not from the table source",
       1024,
       1.0,
       250.0,
       {},
       {{-11.25, 11.25, 64}},
       0.078296,
       0.013762},
      {"OS2-128",
       "Ouster OS2-128: a unit's beam_altitude_angles, sensors/ouster/OS-2-128-U1_v2.3.0_1024x10.json; "
       "origin heights from its lidar_to_sensor_transform z (78.296 mm) and lidar_origin_to_beam_origin_mm "
       "(13.762); range limits are generous round values, not from the table source",
       1024,
       1.0,
       250.0,
       {-11.09, -10.92, -10.75, -10.58, -10.41, -10.24, -10.07, -9.91, -9.74, -9.57, -9.4,  -9.23, -9.06,
        -8.89,  -8.72,  -8.55,  -8.38,  -8.22,  -8.04,  -7.86,  -7.69, -7.51, -7.35, -7.17, -7,    -6.84,
        -6.66,  -6.49,  -6.32,  -6.15,  -5.96,  -5.8,   -5.64,  -5.46, -5.28, -5.11, -4.94, -4.75, -4.58,
        -4.4,   -4.25,  -4.07,  -3.9,   -3.73,  -3.55,  -3.37,  -3.19, -3.02, -2.85, -2.68, -2.5,  -2.32,
        -2.16,  -1.97,  -1.81,  -1.63,  -1.45,  -1.28,  -1.11,  -0.93, -0.76, -0.58, -0.42, -0.25, -0.05,
        0.11,   0.29,   0.46,   0.63,   0.81,   0.98,   1.16,   1.32,  1.51,  1.69,  1.87,  2.03,  2.21,
        2.37,   2.55,   2.72,   2.9,    3.07,   3.24,   3.43,   3.58,  3.76,  3.95,  4.11,  4.28,  4.46,
        4.63,   4.81,   4.97,   5.14,   5.32,   5.5,    5.67,   5.83,  6.02,  6.18,  6.35,  6.53,  6.7,
        6.86,   7.03,   7.21,   7.39,   7.55,   7.74,   7.9,    8.08,  8.23,  8.41,  8.57,  8.75,  8.91,
        9.09,   9.24,   9.41,   9.57,   9.76,   9.93,   10.1,   10.24, 10.42, 10.58, 10.76},
       {},
       0.078296,
       0.013762},
      {"Pandar40P",
       "Hesai Pandar40P: the elevations of nebula sensors/hesai/nebula/calibration/Pandar40P.csv; range "
       "limits are generous round values, not from the table source",
       1800,
       0.3,
       200.0,
       {-24.985, -18.977, -14.018, -13.062, -12.094, -11.12, -10.133, -9.148, -8.147, -7.151,
        -6.149,  -5.814,  -5.479,  -5.145,  -4.808,  -4.473, -4.138,  -3.8,   -3.463, -3.128,
        -2.788,  -2.453,  -2.116,  -1.776,  -1.439,  -1.101, -0.763,  -0.425, -0.088, 0.249,
        0.587,   0.925,   1.263,   1.6,     1.94,    2.952,  4.969,   7.971,  10.944, 14.794},
       {},
       0.0,
       0.0},
      {"Pandar64",
       "Hesai Pandar64: the elevations of nebula sensors/hesai/nebula/calibration/Pandar64.csv; range limits "
       "are generous round values, not from the table source",
       1800,
       0.3,
       200.0,
       {-24.879, -18.871, -13.912, -12.956, -11.988, -11.014, -10.027, -9.042, -8.041, -7.045, -6.043,
        -5.88,   -5.708,  -5.547,  -5.373,  -5.211,  -5.039,  -4.874,  -4.702, -4.54,  -4.367, -4.203,
        -4.032,  -3.866,  -3.694,  -3.53,   -3.357,  -3.192,  -3.022,  -2.855, -2.682, -2.518, -2.347,
        -2.18,   -2.01,   -1.842,  -1.67,   -1.504,  -1.333,  -1.166,  -0.995, -0.827, -0.657, -0.49,
        -0.319,  -0.151,  0.018,   0.187,   0.355,   0.526,   0.693,   0.864,  1.031,  1.202,  1.369,
        1.54,    1.706,   1.878,   2.046,   3.058,   5.075,   8.077,   11.05,  14.9},
       {},
       0.0,
       0.0},
      {"PandarQT64",
       "Hesai PandarQT64: the elevations of nebula sensors/hesai/nebula/calibration/PandarQT64.csv; range "
       "limits are generous round values, not from the table source",
       600,
       0.1,
       60.0,
       {-52.121, -49.785, -47.577, -45.477, -43.465, -41.528, -39.653, -37.831, -36.055, -34.320, -32.619,
        -30.950, -29.308, -27.690, -26.094, -24.517, -22.964, -21.420, -19.889, -18.372, -16.865, -15.368,
        -13.880, -12.399, -10.925, -9.457,  -7.994,  -6.535,  -5.079,  -3.626,  -2.175,  -0.725,  0.725,
        2.175,   3.626,   5.079,   6.534,   7.993,   9.456,   10.923,  12.397,  13.877,  15.365,  16.861,
        18.368,  19.885,  21.415,  22.959,  24.524,  26.101,  27.697,  29.315,  30.957,  32.627,  34.328,
        36.064,  37.840,  39.662,  41.537,  43.475,  45.487,  47.587,  49.795,  52.133},
       {},
       0.0,
       0.0},
      {"PandarQT128",
       "Hesai PandarQT128: the elevations of nebula sensors/hesai/nebula/calibration/PandarQT128.csv; range "
       "limits are generous round values, not from the table source",
       900,
       0.1,
       60.0,
       {-52.62676282, -51.0280939,  -49.51495392, -48.07394795, -46.69466297, -45.36882812, -44.08974439,
        -42.85190128, -41.65069769, -40.48225401, -39.34326358, -38.23088092, -37.14263654, -36.07637316,
        -35.03019446, -34.00242585, -32.99157758, -31.99631045, -31.01543179, -30.04786472, -29.09262707,
        -28.14883195, -27.21566989, -26.29240356, -25.37835081, -24.47288318, -23.57542315, -22.68544071,
        -21.80243688, -20.92594329, -20.05553602, -19.19081372, -18.33139172, -17.47691901, -16.62705442,
        -15.78149317, -14.93993032, -14.10208035, -13.26767188, -12.43645574, -11.60818201, -10.78261371,
        -9.959523504, -9.138697037, -8.319929599, -7.503005408, -6.687807162, -5.873926875, -5.061393513,
        -4.249948322, -3.43941536,  -2.629617595, -1.820378325, -1.011522452, -0.202883525, 0.605717878,
        1.414444374,  2.223469054,  3.032962884,  3.8431104,    4.654074511,  5.466034723,  6.279180222,
        7.093696848,  7.909760474,  8.727579858,  9.54735011,   10.36927364,  11.19356846,  12.0204614,
        12.85016831,  13.68294669,  14.51903314,  15.35869922,  16.20222125,  17.04988688,  17.90200196,
        18.75890049,  19.19081372,  19.62091911,  20.05553602,  20.48842178,  20.92594329,  21.36180725,
        21.80243688,  22.24149217,  22.68544071,  23.12791172,  23.57542315,  24.02155359,  24.47288318,
        24.92293181,  25.37835081,  25.83260224,  26.29240356,  26.75116558,  27.21566989,  27.67927338,
        28.14883195,  28.61763387,  29.09262707,  29.56702472,  30.04786472,  30.52828971,  31.01543179,
        31.50236238,  31.99631045,  32.49026442,  32.99157758,  33.49313666,  34.00242585,  34.51223682,
        35.03019446,  35.54897914,  36.07637316,  37.14263654,  38.23088092,  39.34326358,  40.48225401,
        41.65069769,  42.85190128,  44.08974439,  45.36882812,  46.69466297,  48.07394795,  49.51495392,
        51.0280939,   52.62676282},
       {},
       0.0,
       0.0},
      {"PandarXT16",
       "Hesai PandarXT16: the elevations of nebula sensors/hesai/nebula/calibration/PandarXT16.csv; range "
       "limits are generous round values, not from the table source",
       2000,
       0.1,
       120.0,
       {-15, -13, -11, -9, -7, -5, -3, -1, 1, 3, 5, 7, 9, 11, 13, 15},
       {},
       0.0,
       0.0},
      {"PandarXT32",
       "Hesai PandarXT32: the elevations of nebula sensors/hesai/nebula/calibration/PandarXT32.csv; range "
       "limits are generous round values, not from the table source",
       2000,
       0.1,
       120.0,
       {-16.023602, -15.004862, -13.997372, -12.996131, -12.003641, -11.006150, -10.011159, -9.011169,
        -8.013678,  -7.013687,  -6.016196,  -5.019955,  -4.024964,  -3.028723,  -2.036232,  -1.039991,
        -0.047500,  0.944992,   1.936233,   2.929974,   3.924965,   4.922456,   5.919947,   6.919938,
        7.917429,   8.917419,   9.922410,   10.926151,  11.931141,  12.938632,  13.952372,  14.972363},
       {},
       0.0,
       0.0},
      {"PandarXT32M",
       "Hesai PandarXT32M: the elevations of nebula sensors/hesai/nebula/calibration/PandarXT32M.csv; range "
       "limits are generous round values, not from the table source",
       2000,
       0.3,
       200.0,
       {-20.720, -19.424, -18.129, -16.834, -15.537, -14.242, -12.955, -11.685, -10.386, -9.087, -7.792,
        -6.496,  -5.204,  -3.905,  -2.605,  -1.310,  -0.005,  1.299,   2.595,   3.885,   5.181,  6.475,
        7.769,   9.066,   10.362,  11.661,  12.917,  14.214,  15.512,  16.801,  18.106,  19.407},
       {},
       0.0,
       0.0},
  };
  return table;
}

std::string upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

const PresetRow* find_row(const std::string& name) {
  const std::string n = upper(name);
  for (const PresetRow& r : rows())
    if (upper(r.name) == n) return &r;
  return nullptr;
}

SensorConfig from_row(const PresetRow& r) {
  SensorConfig s;
  s.preset = r.name;
  s.Horizon_SCAN = r.columns;
  s.min_range = r.min_range;
  s.max_range = r.max_range;
  if (!r.elevations_deg.empty()) {
    s.beam_elevations_deg = r.elevations_deg;
  } else if (r.blocks.size() == 1) {
    s.N_scan = r.blocks[0].n;
    s.Pit_bottom = r.blocks[0].lo;
    s.fov_top = r.blocks[0].hi;
  } else {
    s.beam_elevations_deg.clear();
    for (const UniformBlock& b : r.blocks)
      for (int i = 0; i < b.n; ++i) s.beam_elevations_deg.push_back(b.lo + (b.hi - b.lo) * i / (b.n - 1));
  }
  if (!r.elevations_deg.empty()) {
    s.Pit_bottom = r.elevations_deg.front();
    s.fov_top = r.elevations_deg.back();
  } else if (r.blocks.size() > 1) {
    s.Pit_bottom = r.blocks.front().lo;
    s.fov_top = r.blocks.back().hi;
  }
  if (!s.beam_elevations_deg.empty()) s.N_scan = static_cast<int>(s.beam_elevations_deg.size());
  if (r.origin_height_m != 0.0 || r.beam_origin_radius_m != 0.0) {
    for (int k = 0; k < s.N_scan; ++k) {
      const double dz =
          r.origin_height_m - r.beam_origin_radius_m * std::tan(s.beam_elevation_deg(k) * M_PI / 180.0);
      s.beam_vertical_offsets_m.push_back(std::round(dz * 1e4) / 1e4);  // 0.1 mm
    }
  }
  return s;
}

}  // namespace

std::vector<SensorPresetInfo> sensor_preset_info() {
  std::vector<SensorPresetInfo> out;
  for (const PresetRow& r : rows()) {
    const SensorConfig s = from_row(r);
    out.push_back({r.name, r.source, s.N_scan, s.beam_elevation_deg(0), s.beam_elevation_deg(s.N_scan - 1),
                   s.Horizon_SCAN});
  }
  return out;
}

std::vector<std::string> sensor_preset_names() {
  std::vector<std::string> names;
  for (const PresetRow& r : rows()) names.emplace_back(r.name);
  return names;
}

std::string sensor_preset_list(const std::string& separator) {
  std::string list;
  for (const PresetRow& r : rows()) list += (list.empty() ? "" : separator) + r.name;
  return list;
}

SensorConfig sensor_preset(const std::string& name) {
  if (const PresetRow* r = find_row(name)) return from_row(*r);
  throw std::invalid_argument("unknown sensor preset '" + name + "' (known: " + sensor_preset_list() + ")");
}

}  // namespace dloam
