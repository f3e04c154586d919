#include "dloam/core/map_cleaner.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "dloam/core/range_image.hpp"

namespace dloam {

namespace {

/// Evidence counters of one point: views that saw through its place, views that saw it.
struct Votes {
  std::uint16_t free = 0, occupied = 0;
  void add(int e) {
    if (e > 0 && free < 65535) ++free;
    if (e < 0 && occupied < 65535) ++occupied;
  }
  [[nodiscard]] bool any() const { return free + occupied > 0; }
  [[nodiscard]] bool through() const { return free > occupied; }
};

/// The same over the map window, with each view weighted by the scans it stands for (1 in the label
/// window, map_stride beyond it): the shares are shares of the time the place was seen.
struct TimeVotes {
  std::uint16_t free_views = 0;
  std::uint32_t free = 0, occupied = 0;
  void add(int e, std::uint32_t weight) {
    if (e > 0) {
      if (free_views < 65535) ++free_views;
      free += weight;
    }
    if (e < 0) occupied += weight;
  }
  [[nodiscard]] bool any() const { return free + occupied > 0; }
};

void check_config(const MapCleanerConfig& c) {
  auto bad = [](const std::string& what) { throw InputError("map cleaner config: " + what); };
  if (c.label_window < 1) bad("label_window must be at least 1");
  if (c.map_window < c.label_window) bad("map_window must be at least label_window");
  if (c.map_stride < 1) bad("map_stride must be at least 1");
  if (c.far_point_stride < 1) bad("far_point_stride must be at least 1");
  if (!(c.margin >= 0.0) || !(c.margin_per_m >= 0.0) || !(c.occupied_tolerance > 0.0))
    bad("margin, margin_per_m must be >= 0 and occupied_tolerance > 0");
  if (c.occupied_tolerance > c.margin)
    bad("occupied_tolerance must not exceed margin (a return cannot be both near and past a point)");
  if (!(c.max_range > 0.0) || !(c.max_view_distance > 0.0))
    bad("max_range and max_view_distance must be > 0");
  if (c.neighbour_rows < 0 || c.neighbour_cols < 0) bad("neighbour_rows / neighbour_cols must be >= 0");
  if (!(c.moving_fraction > 0.0 && c.moving_fraction < 1.0) ||
      !(c.map_fraction > 0.0 && c.map_fraction < 1.0))
    bad("moving_fraction and map_fraction must be in (0, 1)");
}

}  // namespace

CleanerScan make_cleaner_scan(std::vector<Vec3> points, const SegmentationResult& seg, const Pose& pose) {
  CleanerScan s;
  s.points = std::move(points);
  s.point_label = seg.point_label;
  s.range = seg.image.range;
  s.ground_pixel.resize(seg.pixel_label.size());
  for (std::size_t p = 0; p < seg.pixel_label.size(); ++p)
    s.ground_pixel[p] = seg.pixel_label[p] == kGroundLabel;
  s.ground_normal = seg.ground_normal;
  s.ground_height = seg.ground_height;
  s.ground_valid = seg.ground_plane_valid;
  s.pose = pose;
  return s;
}

MapCleaner::MapCleaner(const SensorConfig& sensor, const MapCleanerConfig& config)
    : sensor_(sensor), config_(config) {
  check_config(config_);
  if (sensor_.N_scan <= 0 || sensor_.Horizon_SCAN <= 0) throw InputError("map cleaner: empty sensor image");
}

MapCleaner::~MapCleaner() = default;

MapCleaner::Entry& MapCleaner::entry(std::size_t index) { return window_[index - front_]; }

void MapCleaner::add(CleanerScan scan) {
  if (finished_) throw InputError("map cleaner: scan added after finish()");
  const std::size_t pixels =
      static_cast<std::size_t>(sensor_.N_scan) * static_cast<std::size_t>(sensor_.Horizon_SCAN);
  if (scan.range.size() != pixels || scan.ground_pixel.size() != pixels)
    throw InputError("map cleaner: scan " + std::to_string(added_) + ": range image of " +
                     std::to_string(scan.range.size()) + " pixels, the sensor has " + std::to_string(pixels));
  if (scan.point_label.size() != scan.points.size())
    throw InputError("map cleaner: scan " + std::to_string(added_) + ": labels and points differ in count");
  Entry e;
  e.points.reserve(scan.points.size());
  for (const Vec3& p : scan.points) e.points.push_back(p.cast<float>());
  e.point_label = std::move(scan.point_label);
  e.range = std::move(scan.range);
  e.ground_pixel = std::move(scan.ground_pixel);
  e.ground_normal = scan.ground_normal;
  e.ground_height = scan.ground_height;
  e.ground_valid = scan.ground_valid;
  e.pose = scan.pose;
  e.inverse = scan.pose.inverse();
  window_.push_back(std::move(e));
  ++added_;
  while (decided_ + static_cast<std::size_t>(config_.map_window) < added_) decide(decided_++);
  trim();
}

void MapCleaner::finish() {
  finished_ = true;
  while (decided_ < added_) decide(decided_++);
  trim();
}

bool MapCleaner::ready() const { return !out_.empty(); }

CleanedScan MapCleaner::pop() {
  if (out_.empty()) throw InputError("map cleaner: no decided scan waiting");
  CleanedScan s = std::move(out_.front());
  out_.pop_front();
  return s;
}

void MapCleaner::trim() {
  // Scans before decided_ - map_window are no viewer of any undecided scan.
  const std::size_t keep_from =
      decided_ > static_cast<std::size_t>(config_.map_window) ? decided_ - config_.map_window : 0;
  while (front_ < keep_from && !window_.empty()) {
    window_.pop_front();
    ++front_;
  }
}

void MapCleaner::decide(std::size_t j) {
  Entry& q = entry(j);
  const MapCleanerConfig& c = config_;
  const int rows = sensor_.N_scan, cols = sensor_.Horizon_SCAN;
  const BeamLookup beams(sensor_);

  // Viewers: every scan of the label window, every map_stride-th of the map window beyond it.
  struct Viewer {
    const Entry* e;
    Eigen::Matrix3f R;
    Eigen::Vector3f t;
    bool near, later;
  };
  std::vector<Viewer> viewers;
  const long lo = std::max(0L, static_cast<long>(j) - c.map_window);
  const long hi = std::min(static_cast<long>(added_) - 1, static_cast<long>(j) + c.map_window);
  for (long i = lo; i <= hi; ++i) {
    const long d = std::labs(i - static_cast<long>(j));
    if (d == 0) continue;
    const bool near = d <= c.label_window;
    if (!near && (d - c.label_window) % c.map_stride != 0) continue;
    const bool later = i > static_cast<long>(j);
    const Entry& v = entry(static_cast<std::size_t>(i));
    if ((v.pose.translation() - q.pose.translation()).norm() > c.max_view_distance) continue;
    const Pose rel = v.inverse * q.pose;  // query sensor -> viewer sensor
    viewers.push_back({&v, rel.linear().cast<float>(), rel.translation().cast<float>(), near, later});
  }

  const std::size_t n = q.points.size();
  std::vector<Votes> near_votes(n);
  std::vector<TimeVotes> all_votes(n), later_votes(n);
  const auto far_weight = static_cast<std::uint32_t>(c.map_stride);
  const double ground_h_own = q.ground_height;
  const Vec3 ground_n_own = q.ground_normal;

  // One view of q (viewer frame): +1 seen through, -1 seen occupied, 0 no evidence.
  auto evidence = [&](const Viewer& v, const Eigen::Vector3f& pf) -> int {
    const Vec3 p = pf.cast<double>();
    const double r = p.norm();
    if (r < sensor_.min_range || r > c.max_range) return 0;
    const int row = beams.row(p);
    if (row < 0) return 0;
    const int col = azimuth_column(p.x(), p.y(), cols);
    const std::vector<float>& range = v.e->range;
    const float center = range[static_cast<std::size_t>(row * cols + col)];
    if (center <= 0.0f) return 0;
    const double margin = c.margin + c.margin_per_m * r;
    const double tol = c.occupied_tolerance + c.margin_per_m * r;
    bool through = true, occupied = false;
    for (int dr = -c.neighbour_rows; dr <= c.neighbour_rows; ++dr) {
      const int rr = row + dr;
      if (rr < 0 || rr >= rows) continue;
      for (int dc = -c.neighbour_cols; dc <= c.neighbour_cols; ++dc) {
        const int cc = ((col + dc) % cols + cols) % cols;
        const float m = range[static_cast<std::size_t>(rr * cols + cc)];
        if (m <= 0.0f) continue;
        if (std::abs(m - r) < tol) occupied = true;
        if (m < r + margin) through = false;
      }
    }
    if (occupied) return -1;
    if (!through) return 0;
    if (v.e->ground_valid && v.e->ground_normal.dot(p) + v.e->ground_height < c.ground_clearance) return 0;
    return 1;
  };

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& br) {
        for (std::size_t k = br.begin(); k != br.end(); ++k) {
          const int label = q.point_label[k];
          if (label == kGroundLabel) continue;
          const Eigen::Vector3f& p = q.points[k];
          // Points at the scan's own ground plane: grazing rays of the neighbours would carve them.
          if (q.ground_valid && ground_n_own.dot(p.cast<double>()) + ground_h_own < c.ground_clearance)
            continue;
          const bool far_checked = k % static_cast<std::size_t>(c.far_point_stride) == 0;
          for (const Viewer& v : viewers) {
            if (!v.near && !far_checked) continue;
            const int e = evidence(v, v.R * p + v.t);
            if (e == 0) continue;
            all_votes[k].add(e, v.near ? 1U : far_weight);
            if (v.later) later_votes[k].add(e, v.near ? 1U : far_weight);
            if (v.near) near_votes[k].add(e);
          }
        }
      });

  // For the map a place counts as empty when some views, not most, saw through it: a parked car
  // that leaves is seen occupied until then and empty after.
  auto empty_share = [&c](const TimeVotes& v) {
    return v.free_views >= c.map_min_free && v.free >= c.map_point_fraction * (v.free + v.occupied);
  };
  // The map keeps the place as last seen: a place that every later view saw occupied holds what
  // came to stand there (seen empty before it arrived only).
  auto seen_empty = [&](std::size_t k) {
    const TimeVotes& later = later_votes[k];
    if (later.any() && later.free == 0) return false;
    return empty_share(all_votes[k]) || empty_share(later);
  };

  // Per cluster: points with evidence and points seen through more than occupied.
  int max_label = 0;
  for (int l : q.point_label) max_label = std::max(max_label, l);
  std::vector<int> near_with(static_cast<std::size_t>(max_label) + 1, 0), near_thr(near_with.size(), 0);
  std::vector<int> all_with(near_with.size(), 0), all_thr(near_with.size(), 0);
  for (std::size_t k = 0; k < n; ++k) {
    const int l = q.point_label[k];
    if (l <= 0) continue;
    const auto u = static_cast<std::size_t>(l);
    if (near_votes[k].any()) {
      ++near_with[u];
      near_thr[u] += near_votes[k].through();
    }
    // Only the points checked by every view of the map window: the others saw its near part only.
    if (all_votes[k].any() && k % static_cast<std::size_t>(c.far_point_stride) == 0) {
      ++all_with[u];
      all_thr[u] += seen_empty(k);
    }
  }
  std::vector<std::uint8_t> cluster_moving(near_with.size(), 0), cluster_ghost(near_with.size(), 0);
  CleanedScan out;
  for (std::size_t u = 1; u < near_with.size(); ++u) {
    cluster_moving[u] = near_thr[u] >= c.min_moving_points && near_thr[u] > c.moving_fraction * near_with[u];
    cluster_ghost[u] = all_thr[u] >= c.min_map_points && all_thr[u] > c.map_fraction * all_with[u];
    out.moving_clusters += cluster_moving[u];
    out.ghost_clusters += cluster_ghost[u] && !cluster_moving[u];
  }

  out.index = j;
  out.pose = q.pose;
  out.labels.assign(n, semantic::kStatic);
  out.in_map.assign(n, 1);
  out.points.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.points[k] = q.points[k].cast<double>();
    const int l = q.point_label[k];
    bool moving = false, ghost = false;
    if (l > 0) {
      moving = cluster_moving[static_cast<std::size_t>(l)] != 0;
      ghost = cluster_ghost[static_cast<std::size_t>(l)] != 0;
    } else if (l == 0) {
      // Points of no cluster: decided alone, and only on clear evidence.
      moving = near_votes[k].free >= 2 && near_votes[k].free > 2 * near_votes[k].occupied;
      ghost = seen_empty(k) && all_votes[k].free > all_votes[k].occupied;
    }
    if (moving) out.labels[k] = semantic::kMovingGeneric;
    out.in_map[k] = !(moving || ghost);
  }
  // Ground points and points of no cluster next to a removed object in the image (its wheels, its
  // lowest rows taken for ground, its edge points the segmentation left alone) stay out of the map
  // too: the places there are mapped from the other scans.
  if (c.map_ground_dilation > 0) {
    std::vector<int> pixel(n, -1);
    std::vector<std::uint8_t> removed(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols), 0);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 p = out.points[k];
      const double r = p.norm();
      if (r < sensor_.min_range || r > sensor_.max_range) continue;
      const int row = beams.row(p);
      if (row < 0) continue;
      pixel[k] = row * cols + azimuth_column(p.x(), p.y(), cols);
      if (q.point_label[k] != kGroundLabel && !out.in_map[k]) removed[static_cast<std::size_t>(pixel[k])] = 1;
    }
    const int d = c.map_ground_dilation;
    for (std::size_t k = 0; k < n; ++k) {
      if (q.point_label[k] > 0 || pixel[k] < 0) continue;
      const int row = pixel[k] / cols, col = pixel[k] % cols;
      for (int dr = -d; dr <= d && out.in_map[k]; ++dr) {
        const int rr = row + dr;
        if (rr < 0 || rr >= rows) continue;
        for (int dc = -d; dc <= d; ++dc) {
          if (removed[static_cast<std::size_t>(rr * cols + ((col + dc) % cols + cols) % cols)]) {
            out.in_map[k] = 0;
            break;
          }
        }
      }
    }
  }
  // The scan's points are no longer needed (it stays a viewer through its range image only).
  q.points = {};
  q.point_label = {};
  out_.push_back(std::move(out));
}

std::vector<CleanedScan> clean_drive(std::vector<CleanerScan> scans, const SensorConfig& sensor,
                                     const MapCleanerConfig& config) {
  MapCleaner cleaner(sensor, config);
  std::vector<CleanedScan> out;
  out.reserve(scans.size());
  for (CleanerScan& s : scans) {
    cleaner.add(std::move(s));
    while (cleaner.ready()) out.push_back(cleaner.pop());
  }
  cleaner.finish();
  while (cleaner.ready()) out.push_back(cleaner.pop());
  return out;
}

CountedVoxelMap::CountedVoxelMap(double leaf) : leaf_(leaf) {
  if (!(leaf > 0.0)) throw InputError("counted voxel map: leaf must be > 0");
}

namespace {
constexpr std::int64_t kVoxelBias = 1 << 20;  // +-1M voxels per axis (+-200 km at 0.2 m)
std::uint64_t voxel_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x + kVoxelBias) << 42) |
         (static_cast<std::uint64_t>(y + kVoxelBias) << 21) | static_cast<std::uint64_t>(z + kVoxelBias);
}
}  // namespace

void CountedVoxelMap::add(const Vec3& w) {
  const Eigen::Array3d v = (w / leaf_).array().floor();
  if (!v.isFinite().all() || (v.abs() >= static_cast<double>(kVoxelBias)).any())
    throw InputError("counted voxel map: point outside the map's extent");
  const auto x = static_cast<std::int64_t>(v.x()), y = static_cast<std::int64_t>(v.y()),
             z = static_cast<std::int64_t>(v.z());
  const auto [it, inserted] =
      index_.try_emplace(voxel_key(x, y, z), static_cast<std::uint32_t>(order_.size()));
  if (inserted) order_.emplace_back();
  Cell& cell = order_[it->second];
  // Sums relative to the voxel's corner stay exact in float however far the map reaches.
  const Vec3 local = w - v.matrix() * leaf_;
  for (int a = 0; a < 3; ++a) cell.sum[a] += static_cast<float>(local[a]);
  ++cell.count;
}

void CountedVoxelMap::extract(std::vector<Vec3>& points, std::vector<std::uint32_t>& counts) const {
  points.assign(order_.size(), Vec3::Zero());
  counts.assign(order_.size(), 0);
  for (const auto& [key, i] : index_) {
    const auto x = static_cast<std::int64_t>((key >> 42) & 0x1FFFFF) - kVoxelBias;
    const auto y = static_cast<std::int64_t>((key >> 21) & 0x1FFFFF) - kVoxelBias;
    const auto z = static_cast<std::int64_t>(key & 0x1FFFFF) - kVoxelBias;
    const Cell& cell = order_[i];
    const Vec3 corner(static_cast<double>(x) * leaf_, static_cast<double>(y) * leaf_,
                      static_cast<double>(z) * leaf_);
    points[i] = corner + Vec3(cell.sum[0], cell.sum[1], cell.sum[2]) / static_cast<double>(cell.count);
    counts[i] = cell.count;
  }
}

}  // namespace dloam
