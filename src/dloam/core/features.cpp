// Edge / plane feature selection per row and sub-image (paper III.E, LeGO-LOAM style).
#include "dloam/core/features.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "dloam/core/smoothness.hpp"
#include "dloam/core/voxel_grid.hpp"

namespace dloam {

namespace {

enum Flag : std::uint8_t { kGround = 1, kBlocked = 2, kPicked = 4, kEdge = 8, kFlat = 16 };

void check_mask(const std::vector<std::uint8_t>& m, std::size_t pixels, const char* name) {
  if (!m.empty() && m.size() != pixels)
    throw InputError(std::string("extract_features: FeatureMask.") + name + " has " +
                     std::to_string(m.size()) + " entries, the range image has " + std::to_string(pixels) +
                     " pixels");
}

// Picks features from one row's sub-images; indices k run over the row sequences.
struct Selector {
  const std::vector<Vec3>& points;
  const RangeImage& img;
  const RowSequences& q;
  const FeatureConfig& config;
  const SmoothnessRules& rules;
  std::vector<std::uint8_t>& flag;
  FeatureSet& out;
  int row_begin = 0, row_size = 0;
  std::vector<std::pair<float, int>> order;

  void add(std::vector<Vec3>& pts, std::vector<int>& idx, int k) {
    idx.push_back(img.point_of_pixel[static_cast<std::size_t>(q.pixel[static_cast<std::size_t>(k)])]);
    pts.push_back(points[static_cast<std::size_t>(idx.back())]);
  }

  // Marks k picked and suppresses its +-S/2 row neighbours up to a depth jump or a column gap
  // (another surface), with the occlusion rule's thresholds.
  void pick(int k) {
    flag[static_cast<std::size_t>(k)] |= kPicked;
    for (int dir : {-1, 1}) {
      int prev = k;
      for (int d = 1; d <= config.S / 2 && d < row_size; ++d) {
        const int j = row_begin + ((k - row_begin + dir * d) % row_size + row_size) % row_size;
        const auto sj = static_cast<std::size_t>(j), sp = static_cast<std::size_t>(prev);
        const int gap = std::abs(q.col[sj] - q.col[sp]);
        if (std::min(gap, img.cols - gap) > rules.occlusion_max_gap ||
            std::abs(q.range[sj] - q.range[sp]) > rules.occlusion_jump)
          break;
        flag[sj] |= kPicked;
        prev = j;
      }
    }
  }

  // Calls take(k) on `order`'s entries in ascending order until it has accepted `quota` of them.
  // Sorts lazily, a chunk at a time: only a few of a sub-image's candidates are ever needed.
  template <typename Take>
  void take_in_order(int quota, Take take) {
    std::size_t done = 0;
    while (quota > 0 && done < order.size()) {
      const std::size_t chunk = std::min(order.size(), done + static_cast<std::size_t>(4 * quota + 16));
      std::partial_sort(order.begin() + static_cast<long>(done), order.begin() + static_cast<long>(chunk),
                        order.end());
      for (; done < chunk && quota > 0; ++done)
        if (take(order[done].second)) --quota;
    }
  }

  // Sub-image [begin, end) of the row with quota multiplier `mult`.
  void select(int begin, int end, int mult) {
    // Edges: non-ground, sharpest first (ties by position: deterministic).
    order.clear();
    for (int k = begin; k < end; ++k)
      if (!(flag[static_cast<std::size_t>(k)] & (kGround | kBlocked)) &&
          q.c[static_cast<std::size_t>(k)] > config.c_th)
        order.emplace_back(-q.c[static_cast<std::size_t>(k)], k);
    int edges = 0;
    take_in_order(mult * config.N_Fe, [&](int k) {
      if (flag[static_cast<std::size_t>(k)] & kPicked) return false;
      if (edges++ < mult * config.N_fe) add(out.f_e, out.f_e_index, k);
      add(out.F_e, out.F_e_index, k);
      flag[static_cast<std::size_t>(k)] |= kEdge;
      pick(k);
      return true;
    });
    // f_p: ground, flattest first.
    order.clear();
    for (int k = begin; k < end; ++k)
      if ((flag[static_cast<std::size_t>(k)] & (kGround | kBlocked)) == kGround &&
          q.c[static_cast<std::size_t>(k)] < config.c_th)
        order.emplace_back(q.c[static_cast<std::size_t>(k)], k);
    take_in_order(mult * config.N_fp, [&](int k) {
      if (flag[static_cast<std::size_t>(k)] & kPicked) return false;
      add(out.f_p, out.f_p_index, k);
      flag[static_cast<std::size_t>(k)] |= kFlat;
      pick(k);
      return true;
    });
  }
};

}  // namespace

FeatureSet extract_features(const std::vector<Vec3>& points, const SegmentationResult& seg,
                            const FeatureConfig& config, const FeatureMask* mask) {
  const RangeImage& img = seg.image;
  const std::size_t n_pix = img.range.size();
  if (seg.pixel_label.size() != n_pix || img.row_of_point.size() != points.size())
    throw InputError("extract_features: segmentation does not match the " + std::to_string(points.size()) +
                     " input points");
  static const std::vector<std::uint8_t> kNone;
  const auto& excluded = mask ? mask->excluded : kNone;
  const auto& pseudo = mask ? mask->pseudo_static : kNone;
  check_mask(excluded, n_pix, "excluded");
  check_mask(pseudo, n_pix, "pseudo_static");

  const SmoothnessRules rules;
  const RowSequences q = compute_smoothness(seg, config.S, rules);
  std::vector<std::uint8_t> flag(q.size(), 0);
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto px = static_cast<std::size_t>(q.pixel[k]);
    if (seg.pixel_label[px] == kGroundLabel) flag[k] |= kGround;
    if (!q.usable[k] || q.c[k] < 0.0f || (!excluded.empty() && excluded[px])) flag[k] |= kBlocked;
  }
  // Sub-image s holds the columns [first_col[s], first_col[s + 1]) (u * N_div / cols == s).
  const int n_div = std::max(1, config.N_div);
  std::vector<int> first_col(static_cast<std::size_t>(n_div) + 1);
  for (int s = 0; s <= n_div; ++s)
    first_col[static_cast<std::size_t>(s)] = (s * img.cols + n_div - 1) / n_div;
  std::vector<int> quota(static_cast<std::size_t>(n_div), 1);  // 2 in sub-images with pseudo-static objects
  if (config.double_pseudo_static && !pseudo.empty())
    for (int s = 0; s < n_div; ++s)
      for (int v = 0; v < img.rows; ++v)
        for (int u = first_col[static_cast<std::size_t>(s)]; u < first_col[static_cast<std::size_t>(s) + 1];
             ++u)
          if (pseudo[static_cast<std::size_t>(img.pixel(v, u))]) quota[static_cast<std::size_t>(s)] = 2;

  FeatureSet out;
  Selector sel{points, img, q, config, rules, flag, out, 0, 0, {}};
  for (int v = 0; v < img.rows; ++v) {
    sel.row_begin = q.row_start[static_cast<std::size_t>(v)];
    const int row_end = q.row_start[static_cast<std::size_t>(v) + 1];
    sel.row_size = row_end - sel.row_begin;
    int begin = sel.row_begin;
    for (int s = 0; s < n_div; ++s) {  // the row is in column order: a sub-image is a run of it
      int end = begin;
      while (end < row_end &&
             q.col[static_cast<std::size_t>(end)] < first_col[static_cast<std::size_t>(s) + 1])
        ++end;
      sel.select(begin, end, quota[static_cast<std::size_t>(s)]);
      begin = end;
    }
  }
  // F_p: f_p plus a voxel-downsampled copy of the other flat points (usable or not).
  std::vector<int> rest;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const bool excluded_px = !excluded.empty() && excluded[static_cast<std::size_t>(q.pixel[k])];
    if (q.c[k] >= 0.0f && q.c[k] < config.c_th && !(flag[k] & (kEdge | kFlat)) && !excluded_px)
      rest.push_back(img.point_of_pixel[static_cast<std::size_t>(q.pixel[k])]);
  }
  out.F_p_index = out.f_p_index;
  const std::vector<int> kept = voxel_downsample(points, config.plane_leaf_size, &rest);
  out.F_p_index.insert(out.F_p_index.end(), kept.begin(), kept.end());
  out.F_p.reserve(out.F_p_index.size());
  out.F_p_ground.reserve(out.F_p_index.size());
  for (int i : out.F_p_index) {
    out.F_p.push_back(points[static_cast<std::size_t>(i)]);
    const int px = img.pixel_of_point(static_cast<std::size_t>(i));
    out.F_p_ground.push_back(seg.pixel_label[static_cast<std::size_t>(px)] == kGroundLabel);
  }
  return out;
}

}  // namespace dloam
