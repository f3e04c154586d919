// Pseudo-static objects (paper III.E): each cluster of the current scan is associated with the
// cluster of the previous scan most of its pixels land on (through the speed matrix's pixel
// correspondence), whose previous motion label it inherits. Type 1: static -> dynamic; type 2:
// dynamic -> static (the stop-and-go objects whose new features have no match in the previous
// scan: their sub-images get double features and the odometry rejects pseudo-static features).
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/dynamic_detector.hpp"

namespace dloam {

enum class Transition : std::uint8_t { kNone = 0, kStaticToDynamic = 1, kDynamicToStatic = 2 };

struct TrackResult {
  std::vector<int> previous_cluster;        ///< per current cluster: previous cluster label, 0 = none
  std::vector<Transition> transition;       ///< per current cluster
  std::vector<std::uint8_t> pseudo_static;  ///< rows*cols: pixel of a type-2 pseudo-static object
  int type1 = 0, type2 = 0;
};

class ObjectTracker {
 public:
  /// Associates the current clusters with the previous scan's and classifies the transitions;
  /// then remembers this scan's clusters and labels for the next call. The first call has no
  /// previous scan: no transitions. Hysteresis: a cluster whose object was dynamic (in at least the
  /// last two scans) stays dynamic
  /// (det.cluster_dynamic and its pixel mask are updated) while its static fraction is below
  /// `alpha_tracked` (with at least N_min_dynamic pixels of known speed); only then does it become a type-2
  /// pseudo-static object.
  TrackResult update(const SegmentationResult& seg, const SpeedMatrix& S, DetectionResult& det,
                     double alpha_tracked);

 private:
  std::vector<int> previous_pixel_label_;
  std::vector<int> previous_age_;  ///< per previous cluster: consecutive scans dynamic (0: static)
  std::vector<int> age_;
};

}  // namespace dloam
