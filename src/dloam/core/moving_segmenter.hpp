// A learned moving-object segmenter (paper III.D.3.b): the range image bag in, one moving
// probability per pixel out. The core library does not depend on a learning library: dloam_cnn
// implements this with LibTorch and the front-ends hand it to the pipeline.
#pragma once

#include <vector>

#include "dloam/core/range_image_bag.hpp"

namespace dloam {

class MovingSegmenter {
 public:
  virtual ~MovingSegmenter() = default;
  /// Number of speed images the model expects in the bag.
  [[nodiscard]] virtual int m() const = 0;
  /// rows*cols probabilities in [0, 1] (row-major, as the range image).
  virtual std::vector<float> moving_probability(const RangeImageBag& bag) = 0;
};

}  // namespace dloam
