// Feature extraction (paper III.E, LeGO-LOAM style): per range-image row and sub-image, the
// sharpest non-ground points (c > c_th) become edges and the flattest ground points planes,
// ranked by the smoothness of eq. 14. Dynamic pixels give no feature; sub-images holding
// type-2 pseudo-static objects get double quotas.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/segmentation.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// III.E Feature extraction (smoothness eq. 14).
struct FeatureConfig {
  int S = 10;     ///< |S|, neighbours in the same row (half on each side)
  int N_div = 6;  ///< sub-images per row
  int N_fe = 2;   ///< sharpest edges per sub-image row (f_e)
  int N_Fe = 40;  ///< edges per sub-image row (F_e)
  int N_fp = 4;   ///< flattest ground planes per sub-image row (f_p)
  int N_Fp = 80;  ///< (unused cap kept for the paper's name; F_p takes all remaining flat points)
  double c_th =
      0.005;  ///< edge / plane threshold on c (eq. 14 is range-normalised: a 90 deg corner at
              ///< 2048 columns gives c ~ 0.009, 2 cm noise at 5 m ~ 0.004; LeGO's 0.1 is on another scale)
  bool double_pseudo_static = true;  ///< double features in sub-images with type-2 pseudo-static objects
  double plane_leaf_size = 0.2;      ///< voxel size of F_p (less-flat) downsampling
};

/// Per-pixel inputs from the dynamic-object detection (rows*cols each; empty = none).
struct FeatureMask {
  std::vector<std::uint8_t> excluded;  ///< nonzero: dynamic pixel, never a feature
  /// nonzero: pixel of a type-2 pseudo-static object (dynamic -> static); every row of the
  /// sub-image (column strip of 360 / N_div deg) holding one gets double N_fe, N_Fe, N_fp.
  std::vector<std::uint8_t> pseudo_static;
};

/// Feature points with the input index of each (f_e is a subset of F_e, f_p of F_p).
struct FeatureSet {
  std::vector<Vec3> f_e, F_e, f_p, F_p;  ///< sharp edges, edges, flat ground planes, planes
  std::vector<int> f_e_index, F_e_index, f_p_index, F_p_index;
  std::vector<std::uint8_t> F_p_ground;  ///< per F_p point: 1 when it is a ground point (f_p all are)
};

/// Selection per row and sub-image (columns u * N_div / cols), over ground and kept-cluster
/// pixels whose smoothness is usable (compute_smoothness: not occluded, not on a surface nearly
/// parallel to the beam) and not excluded by the mask:
///  - edges: non-ground, c > c_th, sharpest first: the first N_fe are f_e, up to N_Fe are F_e;
///  - f_p: ground, c < c_th, flattest first, up to N_fp;
///  - F_p: f_p plus every other non-excluded point with c < c_th (ground or not, usable or not),
///    voxel-downsampled with plane_leaf_size (one real point per voxel).
/// A picked point's +-S/2 row neighbours are suppressed (LOAM) up to the first range jump
/// > 0.3 m or column gap > 10 (another surface). All ground pixels take part (no LeGO-LOAM
/// every-5th-column ground subsampling: F_p is voxel-downsampled instead). Deterministic.
/// Throws InputError when a mask's size does not match the image.
FeatureSet extract_features(const std::vector<Vec3>& points, const SegmentationResult& seg,
                            const FeatureConfig& config, const FeatureMask* mask = nullptr);

}  // namespace dloam
