// Row sequences, smoothness (eq. 14) and LOAM's occluded / parallel-beam rules.
#include "dloam/core/smoothness.hpp"

#include <algorithm>
#include <cmath>

namespace dloam {

namespace {

// One circular row of n >= 2 * half + 2 points: r[-half - 1 .. n + half] (padded circularly),
// gap[k] = 1 when no usable pixel lies within max_gap columns after point k.
void smooth_row(const double* r, const std::vector<std::uint8_t>& gap, int n, int half,
                const SmoothnessRules& rules, float* c, std::uint8_t* ok) {
  auto wrap = [n](int k) { return k < 0 ? k + n : (k >= n ? k - n : k); };
  auto eq14 = [&](int k, double sum) {
    return static_cast<float>(std::abs(sum - 2 * half * r[k]) / (2 * half * r[k]));
  };
  // Eq. 14 with a sliding sum of the 2 * half + 1 ranges centred on k.
  double window = 0.0;
  for (int d = -half; d <= half; ++d) window += r[d];
  for (int k = 0; k < n; ++k) {
    c[k] = eq14(k, window - r[k]);
    ok[k] = 1;
    window += r[k + half + 1] - r[k - half];
  }
  // Windows reaching over a gap: the empty side counts as a depth jump to twice the range, so
  // the last point before empty space is a silhouette edge like the near side of a jump.
  auto across_gap = [&](int k) {
    double sum = 0.0;
    for (int dir : {-1, 1}) {
      bool cut = false;
      for (int d = 1; d <= half; ++d) {
        cut = cut || gap[static_cast<std::size_t>(wrap(dir > 0 ? k + d - 1 : k - d))];
        sum += cut ? 2.0 * r[k] : r[k + dir * d];
      }
    }
    return eq14(k, sum);
  };
  for (int k = 0; k < n; ++k)
    if (gap[static_cast<std::size_t>(k)])
      for (int d = -half + 1; d <= half; ++d) c[wrap(k + d)] = across_gap(wrap(k + d));

  for (int k = 0; k < n; ++k) {
    const double jump = r[k + 1] - r[k];
    const bool gap_before = gap[static_cast<std::size_t>(wrap(k - 1))],
               gap_after = gap[static_cast<std::size_t>(k)];
    if (!gap_after && std::abs(jump) > rules.occlusion_jump) {
      // The far side of the jump and up to `half` points behind it (not past a gap) are occluded.
      if (jump < 0)
        for (int d = 0; d <= half && (d == 0 || !gap[static_cast<std::size_t>(wrap(k - d))]); ++d)
          ok[wrap(k - d)] = 0;
      else
        for (int d = 1; d <= half + 1 && (d == 1 || !gap[static_cast<std::size_t>(wrap(k + d - 1))]); ++d)
          ok[wrap(k + d)] = 0;
    }
    const double prev = std::abs(r[k - 1] - r[k]), next = std::abs(jump);
    if (!gap_before && !gap_after && prev > rules.parallel_ratio * r[k] && next > rules.parallel_ratio * r[k])
      ok[k] = 0;
  }
}

}  // namespace

RowSequences compute_smoothness(const SegmentationResult& seg, int S, const SmoothnessRules& rules) {
  const RangeImage& img = seg.image;
  RowSequences q;
  q.row_start.assign(static_cast<std::size_t>(img.rows) + 1, 0);
  q.pixel.reserve(img.range.size());
  q.col.reserve(img.range.size());
  q.range.reserve(img.range.size());
  for (int v = 0; v < img.rows; ++v) {
    q.row_start[static_cast<std::size_t>(v)] = static_cast<int>(q.pixel.size());
    for (int u = 0; u < img.cols; ++u) {
      const int px = img.pixel(v, u);
      if (seg.pixel_label[static_cast<std::size_t>(px)] == kOutlierLabel) continue;  // empty or outlier
      q.pixel.push_back(px);
      q.col.push_back(u);
      q.range.push_back(img.range[static_cast<std::size_t>(px)]);
    }
  }
  q.row_start.back() = static_cast<int>(q.pixel.size());
  q.c.assign(q.size(), -1.0f);
  q.usable.assign(q.size(), 0);

  const int half = std::max(1, S / 2);
  std::vector<double> ext;  // one row's ranges, padded circularly by half + 1 on each side
  std::vector<std::uint8_t> gap;
  for (int v = 0; v < img.rows; ++v) {
    const int b = q.row_start[static_cast<std::size_t>(v)],
              n = q.row_start[static_cast<std::size_t>(v) + 1] - b;
    if (n < 2 * half + 2) continue;
    const int pad = half + 1;
    ext.resize(static_cast<std::size_t>(n + 2 * pad));
    const float* range = q.range.data() + b;
    const int* col = q.col.data() + b;
    for (int j = -pad; j < n + pad; ++j)
      ext[static_cast<std::size_t>(j + pad)] = range[j < 0 ? j + n : (j >= n ? j - n : j)];
    gap.resize(static_cast<std::size_t>(n));
    for (int k = 0; k + 1 < n; ++k)
      gap[static_cast<std::size_t>(k)] = col[k + 1] - col[k] > rules.occlusion_max_gap;
    gap[static_cast<std::size_t>(n - 1)] = col[0] + img.cols - col[n - 1] > rules.occlusion_max_gap;  // wrap
    smooth_row(ext.data() + pad, gap, n, half, rules, q.c.data() + b, q.usable.data() + b);
  }
  return q;
}

}  // namespace dloam
