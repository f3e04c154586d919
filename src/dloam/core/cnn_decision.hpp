// Object-level decision on the CNN's per-pixel output (paper III.D.3.b with III.D.3.a's cluster
// rule): a segmentation cluster is dynamic when fewer than alpha of its pixels are static
// (probability below cnn_threshold). Ground pixels the network calls moving (a car's lower rim
// merged into the ground) are rejected as in the geometric detector: no features, not mapped.
// Labels then come from point_labels() (dynamic_detector.hpp) exactly as for the geometric
// detector; every input point, including those that lost their pixel, follows its cluster. Pixels
// of no cluster are not labelled moving by their own probability (docs/results.md, detector
// parameters).
#pragma once

#include <vector>

#include "dloam/core/dynamic_detector.hpp"

namespace dloam {

/// `probability`: rows*cols moving probabilities of the current scan's range image.
DetectionResult decide_from_probability(const SegmentationResult& seg, const std::vector<float>& probability,
                                        const DetectionConfig& config);

}  // namespace dloam
