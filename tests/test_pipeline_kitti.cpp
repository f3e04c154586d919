// End-to-end: the pipeline on the real KITTI drive (../shared/data/kitti-raw-0005, 100 HDL-64E
// scans, 39 m) against its reference trajectory, with the KITTI devkit relative error over short
// segments and the ATE. Also determinism: the same input and config give the same poses, with the
// mapping on its worker thread (real-time poses and the refined trajectory); mapping at 2 Hz.
#include <gtest/gtest.h>

#include <filesystem>

#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"

using namespace dloam;

namespace {

struct Trajectories {
  std::vector<Pose> poses;     ///< refined (Pipeline::trajectory), what `dloam run` writes
  std::vector<Pose> realtime;  ///< ScanResult::pose
  std::vector<Pose> gt;
  int mapped = 0;
};

Trajectories run_kitti(std::size_t scans, bool deskew, int every_n_scans = 1, int latency_scans = 1) {
  const io::Sequence seq = io::open_sequence(DLOAM_KITTI_0005);
  PipelineConfig cfg = io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml");
  cfg.deskew.enabled = deskew;
  cfg.mapping.every_n_scans = every_n_scans;
  cfg.mapping.latency_scans = latency_scans;
  Pipeline pipeline(cfg);
  Trajectories r;
  const auto gt = seq.lidar_poses();
  for (std::size_t i = 0; i < scans; ++i) {
    const ScanResult s = pipeline.process(seq.read_scan(i));
    r.realtime.push_back(s.pose);
    r.mapped += s.mapped;
    r.gt.push_back(gt[i]);
  }
  r.poses = pipeline.trajectory();
  return r;
}

eval::OdometryResult evaluate(const std::vector<Pose>& gt, const std::vector<Pose>& poses) {
  eval::SegmentOptions seg;
  seg.lengths = {5, 10, 20, 30};
  seg.step = 1;
  return eval::evaluate_odometry(gt, poses, seg);
}

bool have_data() { return std::filesystem::exists(std::string(DLOAM_KITTI_0005) + "/poses.txt"); }

}  // namespace

TEST(PipelineKitti, AccurateOnTheRealDrive) {
  if (!have_data()) GTEST_SKIP() << "no " << DLOAM_KITTI_0005;
  const Trajectories r = run_kitti(100, true);
  ASSERT_EQ(r.poses.size(), 100u);
  const auto m = evaluate(r.gt, r.poses);
  std::printf("kitti-raw-0005: t_rel %.3f %%, r_rel %.3f deg/100m, ATE %.3f m (aligned %.3f m)\n",
              m.relative.t_rel_pct, m.relative.r_rel_deg100m, m.ate.rmse, m.ate_aligned.rmse);
  // The accuracy target is 1.5 % / 0.2 m; the pipeline measures 0.2 % / 0.04 m, so these bounds
  // also catch a regression well before it would miss the target.
  EXPECT_LT(m.relative.t_rel_pct, 0.5);
  EXPECT_LT(m.ate.rmse, 0.1);
  EXPECT_GT(m.relative.segments.size(), 200u);
  // The real-time poses (the mapping correction arrives one scan later) stay inside the bounds too.
  const auto rt = evaluate(r.gt, r.realtime);
  std::printf("real-time poses: t_rel %.3f %%, ATE %.3f m\n", rt.relative.t_rel_pct, rt.ate.rmse);
  EXPECT_LT(rt.relative.t_rel_pct, 0.5);
  EXPECT_LT(rt.ate.rmse, 0.1);
}

TEST(PipelineKitti, MappingAt2HzOnTheWorkerThreadStaysAccurate) {
  if (!have_data()) GTEST_SKIP() << "no " << DLOAM_KITTI_0005;
  // Mapping every 5th scan (2 Hz at 10 Hz), its result integrated 5 scans later (LOAM's rates).
  const Trajectories r = run_kitti(100, true, 5, 5);
  EXPECT_EQ(r.mapped, 20);
  const auto m = evaluate(r.gt, r.poses);
  const auto rt = evaluate(r.gt, r.realtime);
  std::printf("2 Hz mapping: t_rel %.3f %%, ATE %.3f m; real-time t_rel %.3f %%, ATE %.3f m\n",
              m.relative.t_rel_pct, m.ate.rmse, rt.relative.t_rel_pct, rt.ate.rmse);
  // Measured 0.55 % / 0.07 m (refined) and 0.98 % / 0.16 m (real time): fewer scan-to-map
  // corrections than at 10 Hz (0.18 % / 0.03 m), still inside the 1.5 % / 0.2 m target.
  EXPECT_LT(m.relative.t_rel_pct, 1.0);
  EXPECT_LT(m.ate.rmse, 0.12);
  EXPECT_LT(rt.relative.t_rel_pct, 1.5);
  EXPECT_LT(rt.ate.rmse, 0.2);
}

TEST(PipelineKitti, DeterministicAndDeskewHelps) {
  if (!have_data()) GTEST_SKIP() << "no " << DLOAM_KITTI_0005;
  const Trajectories a = run_kitti(40, true);
  const Trajectories b = run_kitti(40, true);
  // Mapping runs on a worker thread: its timing must not change the result.
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    ASSERT_TRUE(a.poses[i].matrix() == b.poses[i].matrix()) << "scan " << i;
    ASSERT_TRUE(a.realtime[i].matrix() == b.realtime[i].matrix()) << "scan " << i;
  }
  const Trajectories raw = run_kitti(40, false);
  eval::SegmentOptions seg;
  seg.lengths = {5, 10};
  seg.step = 1;
  const double with = eval::evaluate_odometry(a.gt, a.poses, seg).relative.t_rel_pct;
  const double without = eval::evaluate_odometry(raw.gt, raw.poses, seg).relative.t_rel_pct;
  std::printf("first 40 scans: t_rel %.3f %% with de-skew, %.3f %% without\n", with, without);
  EXPECT_LT(with, without);
}

TEST(Pipeline, TheCnnDetectorNeedsAModel) {
  PipelineConfig cfg;
  cfg.detection.detector = Detector::kCnn;
  EXPECT_THROW(Pipeline{cfg}, std::invalid_argument);  // no segmenter given (front-ends load models/)
}

TEST(Pipeline, RefusesMoreMappingLatencyThanItsPeriod) {
  PipelineConfig cfg;
  cfg.mapping.every_n_scans = 2;
  cfg.mapping.latency_scans = 3;  // two jobs would be in flight
  EXPECT_THROW(Pipeline{cfg}, std::invalid_argument);
  cfg.mapping.latency_scans = 2;
  EXPECT_NO_THROW(Pipeline{cfg});
}
