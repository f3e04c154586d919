// Parameters of the whole-drive map cleaner (dloam/core/map_cleaner.hpp), apart so that the
// pipeline's config can hold them without the cleaner itself.
#pragma once

namespace dloam {

/// The whole-drive cleaner (range-image visibility, both directions in time).
struct MapCleanerConfig {
  int label_window = 15;            ///< scans on each side whose views decide the labels
  int map_window = 60;              ///< scans on each side whose views decide what enters the map
  int map_stride = 4;               ///< beyond the label window, every N-th scan of the map window views
  double max_view_distance = 80.0;  ///< viewers farther than this from the scan (m) are skipped
  double max_range = 80.0;          ///< points farther than this from a viewer get no evidence from it (m)
  double margin = 0.3;              ///< seen through: returns farther than the point by this (m) ...
  double margin_per_m = 0.01;       ///< ... plus this per metre of the point's range
  double occupied_tolerance = 0.2;  ///< seen occupied: a return within this of the range (m, + margin_per_m)
  double ground_clearance = 0.3;    ///< no seen-through evidence this close to the viewer's ground plane (m)
  int neighbour_rows = 1;           ///< neighbourhood of the pixel: +-rows ...
  int neighbour_cols = 1;           ///< ... and +-columns
  double moving_fraction = 0.2;  ///< a cluster is moving when this fraction of its points with evidence ...
  int min_moving_points = 4;     ///< ... and at least this many are seen through more than occupied
  int map_min_free = 2;          ///< map: a point's place is empty when at least this many views ...
  double map_point_fraction = 0.25;  ///< ... and this share of the time it was seen (views weighted by
                                     ///< the scans they stand for) saw through it
  double map_fraction = 0.2;         ///< more than this fraction of its points seen empty keeps a cluster out
  int min_map_points = 4;            ///< ... with at least this many points
  int far_point_stride = 2;          ///< beyond the label window, every N-th point of a cluster is checked
  double map_leaf_size = 0.2;        ///< voxel size of the cleaned map (m), as the online map.ply
  int map_ground_dilation = 2;  ///< ground and unclustered pixels this close to a removed object stay out
  double map_max_range = 60.0;  ///< points farther from their scan stay out of the cleaned map (m)
};

}  // namespace dloam
