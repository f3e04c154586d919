// The whole-drive cleaner on a simulated street with traffic and the map-cleaning objects (a
// pedestrian standing for the first half then walking away, one walking in and standing, a parked
// car that drives off), cleaned with the true poses: labels per scan, the static map, and the
// files `dloam clean` writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "dloam/core/map_cleaner.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/eval/map_metrics.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/pipeline/config.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"

namespace dloam {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 80;
constexpr int kLeaveAfter = 30;

struct Drive {
  SensorConfig sensor;
  MapCleanerConfig config;
  std::vector<std::vector<Vec3>> points;  ///< sensor frame at mid-sweep (exactly de-skewed)
  std::vector<std::vector<Label>> gt;
  std::vector<Pose> poses;
  std::map<std::string, std::uint32_t> instance_of_role;
  std::vector<CleanedScan> cleaned;
  std::vector<Vec3> map;  ///< the static map's voxel means (world)
};

/// The urban street with the map-cleaning objects, cleaned with the true poses.
const Drive& drive() {
  static const Drive d = [] {
    Drive out;
    out.sensor = sensor_preset("HDL-64E");
    sim::ScenarioParams params;
    params.kind = sim::ScenarioKind::Urban;
    params.frames = kFrames;
    params.seed = 5;
    params.cleaning_actors = true;
    params.leave_after = kLeaveAfter;
    sim::LidarOptions options;
    options.sensor = out.sensor;
    options.seed = 5;
    sim::Simulator simulator(sim::make_world(params), options);
    for (const sim::Actor& a : simulator.world().actors)
      if (!a.role.empty()) out.instance_of_role[a.role] = a.instance;
    std::vector<CleanerScan> scans;
    for (int i = 0; i < kFrames; ++i) {
      const sim::SimFrame f = simulator.frame(i);
      const Pose to_mid = f.pose.inverse();
      std::vector<Vec3> pts(f.scan.cloud.size());
      for (std::size_t k = 0; k < pts.size(); ++k)
        pts[k] = to_mid * simulator.sensor_pose(i, f.scan.cloud.time[k]) * f.scan.cloud.xyz[k];
      const SegmentationResult seg = segment(pts, out.sensor, SegmentationConfig{});
      scans.push_back(make_cleaner_scan(pts, seg, f.pose));
      out.points.push_back(std::move(pts));
      out.gt.push_back(f.scan.labels);
      out.poses.push_back(f.pose);
    }
    out.cleaned = clean_drive(std::move(scans), out.sensor, out.config);
    CountedVoxelMap map(out.config.map_leaf_size);
    for (const CleanedScan& s : out.cleaned)
      for (std::size_t k = 0; k < s.points.size(); ++k)
        if (s.in_map[k] && s.points[k].norm() <= out.config.map_max_range) map.add(s.pose * s.points[k]);
    std::vector<std::uint32_t> counts;
    map.extract(out.map, counts);
    return out;
  }();
  return d;
}

/// Share of the world points of `role`'s object in scans [first, last) whose GT says
/// moving == `moving`, that the cleaner labels moving; the number of such points in `n`.
double moving_share(const Drive& d, const std::string& role, bool moving, int first, int last,
                    std::size_t& n) {
  const std::uint32_t id = d.instance_of_role.at(role);
  std::size_t hits = 0;
  n = 0;
  for (int i = first; i < last; ++i)
    for (std::size_t k = 0; k < d.gt[i].size(); ++k) {
      const Label g = d.gt[i][k];
      if (semantic::instance_of(g) != id || semantic::is_moving(g) != moving) continue;
      ++n;
      hits += semantic::is_moving(d.cleaned[i].labels[k]);
    }
  return n ? static_cast<double>(hits) / static_cast<double>(n) : 0.0;
}

/// Share of the world points of `role`'s object (GT static, scans [first, last)) with a map point
/// within `radius`; with `above_road`, the points within `radius` of the object's lowest point
/// (its wheels or feet on the road, next to the road mapped under it) are left out.
double in_map_share(const Drive& d, const std::string& role, int first, int last, double radius,
                    std::size_t& n, bool above_road = false) {
  const std::uint32_t id = d.instance_of_role.at(role);
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = first; i < last; ++i)
    for (std::size_t k = 0; k < d.gt[i].size(); ++k)
      if (semantic::instance_of(d.gt[i][k]) == id && !semantic::is_moving(d.gt[i][k]))
        lowest = std::min(lowest, (d.poses[i] * d.points[i][k]).z());
  std::size_t hits = 0;
  n = 0;
  for (int i = first; i < last; ++i)
    for (std::size_t k = 0; k < d.gt[i].size(); ++k) {
      const Label g = d.gt[i][k];
      if (semantic::instance_of(g) != id || semantic::is_moving(g)) continue;
      const Vec3 w = d.poses[i] * d.points[i][k];
      if (above_road && w.z() < lowest + radius) continue;
      ++n;
      for (const Vec3& m : d.map)
        if ((m - w).squaredNorm() < radius * radius) {
          ++hits;
          break;
        }
    }
  return n ? static_cast<double>(hits) / static_cast<double>(n) : 0.0;
}

TEST(Clean, LabelsMovingObjectsPerScan) {
  const Drive& d = drive();
  ASSERT_EQ(d.cleaned.size(), static_cast<std::size_t>(kFrames));
  eval::MosConfusion c;
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_EQ(d.cleaned[i].index, static_cast<std::size_t>(i));
    ASSERT_EQ(d.cleaned[i].labels.size(), d.gt[i].size());
    c += eval::point_confusion(d.gt[i], d.cleaned[i].labels);
  }
  ASSERT_GT(c.tp + c.fn, 1000u) << "the drive should have moving points";
  EXPECT_GT(c.iou(), 0.8) << "TP " << c.tp << " FP " << c.fp << " FN " << c.fn;
}

TEST(Clean, StandingPedestrianIsStaticOnlyWhileItStands) {
  const Drive& d = drive();
  const int half = kFrames / 2;
  std::size_t n_stand = 0, n_walk = 0;
  // Standing: static up to the views of its last second before it walks off.
  const double stand = moving_share(d, "stand_then_walk", false, 0, half - d.config.label_window, n_stand);
  const double walk = moving_share(d, "stand_then_walk", true, half + 10, kFrames, n_walk);
  ASSERT_GT(n_stand, 50u) << "the standing pedestrian must be seen";
  ASSERT_GT(n_walk, 50u) << "the walking pedestrian must be seen";
  EXPECT_LT(stand, 0.2) << "standing pedestrian labelled moving";
  EXPECT_GT(walk, 0.7) << "walking pedestrian labelled static";
  // The other one walks in and stands to the end: in the map where it stands, moving while it walks.
  std::size_t n_in = 0, n_in_walk = 0;
  const double in_map = in_map_share(d, "walk_then_stand", half + 5, kFrames, 0.3, n_in);
  const double walk_in = moving_share(d, "walk_then_stand", true, 0, half - 5, n_in_walk);
  ASSERT_GT(n_in, 50u);
  ASSERT_GT(n_in_walk, 50u);
  EXPECT_GT(in_map, 0.5) << "the pedestrian standing to the end of the drive belongs to its map";
  EXPECT_GT(walk_in, 0.7);
}

TEST(Clean, StaticMapKeepsWallsDropsTraffic) {
  const Drive& d = drive();
  eval::MapAccuracyEvaluator evaluator(eval::MapAccuracyConfig{0.2, 0.2, d.config.map_max_range});
  for (int i = 0; i < kFrames; ++i) evaluator.add_scan(d.points[i], d.gt[i], d.poses[i]);
  const eval::MapAccuracy r = evaluator.evaluate(d.map);
  ASSERT_GT(r.dynamic_voxels, 500u);
  EXPECT_GT(r.sa(), 0.95) << r.static_kept << " of " << r.static_voxels;
  EXPECT_GT(r.da(), 0.9) << r.dynamic_kept << " of " << r.dynamic_voxels;
}

// The place of the parked car is seen empty by the scans after it drove off: none of it stays in the
// map. Its points within the match radius of the road are left out of the share: the road under
// the car is rightly mapped (from the scans after it left) and lies within 0.2 m of its wheels.
TEST(Clean, ParkedCarThatLeavesLeavesNoGhost) {
  const Drive& d = drive();
  std::size_t n = 0;
  const double ghost = in_map_share(d, "leaving_car", 0, kLeaveAfter, 0.2, n, true);
  ASSERT_GT(n, 200u) << "the parked car must be seen before it leaves";
  EXPECT_LT(ghost, 0.05) << "the parked car's place stays in the map after it left";
  // While it stands it is static in the labels (the views of the scans before it moves).
  std::size_t n_parked = 0;
  EXPECT_LT(moving_share(d, "leaving_car", false, 0, kLeaveAfter - d.config.label_window, n_parked), 0.2);
}

TEST(Clean, CliWritesLabelsMapAndMetrics) {
  const fs::path dir = fs::temp_directory_path() / "dloam_test_clean";
  fs::remove_all(dir);
  const std::string seq = (dir / "seq").string(), run = (dir / "run").string();
  const auto sim =
      test::run_dloam("simulate --scenario urban --frames 12 --preset VLP-16 --seed 2 --out " + seq);
  ASSERT_EQ(sim.status, 0) << sim.output;
  fs::create_directories(run);
  fs::copy_file(seq + "/poses.txt", run + "/poses.txt");  // the true poses stand for a run's
  std::ofstream(run + "/config.yaml")
      << "sensor:\n  preset: VLP-16\nclean:\n  label_window: 6\n  map_window: 12\n";
  const auto clean = test::run_dloam("clean " + seq + " " + run);
  ASSERT_EQ(clean.status, 0) << clean.output;
  for (int i = 0; i < 12; ++i) {
    const PointCloud cloud = io::read_kitti_bin(seq + "/velodyne/" + io::scan_name(i) + ".bin");
    const std::string file = run + "/clean/labels/" + io::scan_name(i) + ".label";
    ASSERT_EQ(fs::file_size(file), cloud.size() * sizeof(Label)) << file;
    for (Label l : io::read_labels(file, cloud.size()))
      ASSERT_TRUE(l == semantic::kStatic || l == semantic::kMovingGeneric) << file << ": " << l;
  }
  const io::PlyCloud map = io::read_ply(run + "/clean/map.ply");
  EXPECT_GT(map.cloud.size(), 1000u);
  const auto metrics = nlohmann::json::parse(std::ifstream(run + "/clean/metrics.json"));
  ASSERT_TRUE(metrics.contains("mos")) << metrics.dump();
  EXPECT_EQ(metrics["mos"]["scans"].get<int>(), 12);
  EXPECT_EQ(metrics["map_points"].get<std::size_t>(), map.cloud.size());
  // The same scoring as `dloam eval mos` over the written labels.
  const auto mos = test::run_dloam("eval mos " + seq + "/labels " + run + "/clean/labels --json " +
                                   (dir / "mos.json").string());
  ASSERT_EQ(mos.status, 0) << mos.output;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "mos.json"));
  EXPECT_EQ(j["tp"], metrics["mos"]["tp"]);
  EXPECT_EQ(j["fp"], metrics["mos"]["fp"]);
  EXPECT_EQ(j["fn"], metrics["mos"]["fn"]);
  fs::remove_all(dir);
}

TEST(Clean, RejectsBadConfigAndImageSize) {
  const SensorConfig sensor = sensor_preset("VLP-16");
  MapCleanerConfig bad;
  bad.map_window = bad.label_window - 1;
  EXPECT_THROW(MapCleaner(sensor, bad), InputError);
  MapCleaner cleaner(sensor, MapCleanerConfig{});
  CleanerScan s;
  s.range.assign(10, 0.0f);
  s.ground_pixel.assign(10, 0);
  EXPECT_THROW(cleaner.add(s), InputError);
}

}  // namespace
}  // namespace dloam
