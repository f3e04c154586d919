// The whole-drive pass: moving / static per point and a ghost-free static map, decided from
// every scan's view of the others, before and after in time (range-image visibility).
//
// Each scan j is checked against the range images of its neighbours i (within `label_window` scans
// on each side, and every `map_stride`-th scan out to `map_window`): a point q of j, moved into
// i's sensor frame with the two poses, falls on a pixel of i's range image.
//  - "seen through" (free): every return of i in the pixel's neighbourhood is farther than q by
//    more than the margin (growing with range): the ray of i passed the place of q without a hit.
//    The neighbourhood minimum keeps grazing surfaces, edges and thin poles from being carved by
//    a ray that slipped past them; no return (sky, beyond max range) is no evidence; a viewer's
//    ground return says nothing about points within `ground_clearance` of its ground plane.
//  - "seen occupied": some return of the neighbourhood lies within the tolerance of q's range.
//  - otherwise (something nearer hides q) no evidence.
// Points are then decided per segmentation cluster, so whole objects flip: a cluster is moving
// when enough of its points with evidence are mostly seen through. Labels use only the views of
// the label window (a standing pedestrian or a parked car is static while it stands, as the
// SemanticKITTI MOS labels define it); the map uses every view, each weighted by the scans it
// stands for: a cluster whose place is seen through for part of the map window (a parked car that
// left, a pedestrian who walked away) stays out of the map even while it stood (no ghost). The map
// keeps the place as last seen: a place that every later view saw occupied keeps what came to
// stand there (a pedestrian who walked in and stays).
//
// Memory is bounded by the window: scans are added in time order and each scan's result is
// released once the scans `map_window` after it have been added.
#pragma once

#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

#include "dloam/core/map_cleaner_config.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// One scan as the cleaner needs it: what the segmentation made of it and its pose.
struct CleanerScan {
  std::vector<Vec3> points;      ///< sensor frame (vertical-angle corrected, de-skewed), input order
  std::vector<int> point_label;  ///< per point: -1 ground, 0 outlier / not in the image, 1.. clusters
  std::vector<float> range;      ///< the scan's range image (rows*cols, 0 where no return)
  std::vector<std::uint8_t> ground_pixel;  ///< rows*cols, 1 = ground pixel
  Vec3 ground_normal = Vec3::UnitZ();      ///< sensor frame, up
  double ground_height = 0.0;              ///< sensor height above the ground plane (m)
  bool ground_valid = false;
  Pose pose = Pose::Identity();  ///< sensor -> world
};

/// The scan from its segmentation (the range image and labels are taken from `seg`).
CleanerScan make_cleaner_scan(std::vector<Vec3> points, const SegmentationResult& seg, const Pose& pose);

/// The decision for one scan.
struct CleanedScan {
  std::size_t index = 0;             ///< order in which the scan was added (0-based)
  std::vector<Label> labels;         ///< per input point: semantic::kStatic or semantic::kMovingGeneric
  std::vector<std::uint8_t> in_map;  ///< per point: 1 = belongs to the static map
  std::vector<Vec3> points;          ///< the scan's points (sensor frame), as added
  Pose pose = Pose::Identity();
  std::size_t moving_clusters = 0, ghost_clusters = 0;  ///< clusters labelled moving / kept out of the map
};

class MapCleaner {
 public:
  /// Throws InputError when the sensor model or the config is inconsistent.
  MapCleaner(const SensorConfig& sensor, const MapCleanerConfig& config);
  ~MapCleaner();
  MapCleaner(const MapCleaner&) = delete;
  MapCleaner& operator=(const MapCleaner&) = delete;

  /// The next scan in time. Throws InputError when its image size differs from the sensor's.
  void add(CleanerScan scan);
  /// No more scans: every remaining scan is decided with the views there are.
  void finish();
  /// A decided scan is waiting (in the order added).
  [[nodiscard]] bool ready() const;
  CleanedScan pop();
  /// Scans held now (the window), for memory accounting.
  [[nodiscard]] std::size_t held() const { return window_.size(); }

 private:
  struct Entry {
    std::vector<Eigen::Vector3f> points;  ///< released once the scan is decided
    std::vector<int> point_label;
    std::vector<float> range;
    std::vector<std::uint8_t> ground_pixel;
    Vec3 ground_normal = Vec3::UnitZ();
    double ground_height = 0.0;
    bool ground_valid = false;
    Pose pose = Pose::Identity();
    Pose inverse = Pose::Identity();
  };
  void decide(std::size_t index);
  void trim();
  Entry& entry(std::size_t index);

  SensorConfig sensor_;
  MapCleanerConfig config_;
  std::deque<Entry> window_;
  std::size_t front_ = 0;  ///< index of window_.front()
  std::size_t added_ = 0, decided_ = 0;
  bool finished_ = false;
  std::deque<CleanedScan> out_;
};

/// Runs the cleaner over a whole drive held in memory (tests, small drives).
std::vector<CleanedScan> clean_drive(std::vector<CleanerScan> scans, const SensorConfig& sensor,
                                     const MapCleanerConfig& config);

/// World voxel map of static points with the number of observations per voxel: the mean of the
/// points that fell in each voxel. Memory grows with the mapped area, not with the drive's length.
class CountedVoxelMap {
 public:
  explicit CountedVoxelMap(double leaf);
  void add(const Vec3& world_point);
  /// Voxel means and counts, in the order voxels were first filled.
  void extract(std::vector<Vec3>& points, std::vector<std::uint32_t>& counts) const;
  [[nodiscard]] std::size_t size() const { return order_.size(); }

 private:
  struct Cell {
    float sum[3] = {0, 0, 0};
    std::uint32_t count = 0;
  };
  double leaf_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  std::vector<Cell> order_;
};

}  // namespace dloam
