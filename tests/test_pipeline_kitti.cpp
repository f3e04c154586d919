// End-to-end: the pipeline on the real KITTI drive (../shared/data/kitti-raw-0005, 100 HDL-64E
// scans, 39 m) against its reference trajectory, with the KITTI devkit relative error over short
// segments and the ATE. Also determinism: the same input and config give the same poses.
#include <gtest/gtest.h>

#include <filesystem>

#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"

using namespace dloam;

namespace {

struct Trajectories {
  std::vector<Pose> poses;
  std::vector<Pose> gt;
};

Trajectories run_kitti(std::size_t scans, bool deskew) {
  const io::Sequence seq = io::open_sequence(DLOAM_KITTI_0005);
  PipelineConfig cfg = io::load_config(std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml");
  cfg.deskew.enabled = deskew;
  Pipeline pipeline(cfg);
  Trajectories r;
  const auto gt = seq.lidar_poses();
  for (std::size_t i = 0; i < scans; ++i) {
    r.poses.push_back(pipeline.process(seq.read_scan(i)).pose);
    r.gt.push_back(gt[i]);
  }
  return r;
}

bool have_data() { return std::filesystem::exists(std::string(DLOAM_KITTI_0005) + "/poses.txt"); }

}  // namespace

TEST(PipelineKitti, AccurateOnTheRealDrive) {
  if (!have_data()) GTEST_SKIP() << "no " << DLOAM_KITTI_0005;
  const Trajectories r = run_kitti(100, true);
  eval::SegmentOptions seg;
  seg.lengths = {5, 10, 20, 30};
  seg.step = 1;
  const auto m = eval::evaluate_odometry(r.gt, r.poses, seg);
  std::printf("kitti-raw-0005: t_rel %.3f %%, r_rel %.3f deg/100m, ATE %.3f m (aligned %.3f m)\n",
              m.relative.t_rel_pct, m.relative.r_rel_deg100m, m.ate.rmse, m.ate_aligned.rmse);
  // Issue #3's acceptance is 1.5 % / 0.2 m; the pipeline measures 0.2 % / 0.04 m, so these bounds
  // also catch a regression well before it would break the acceptance.
  EXPECT_LT(m.relative.t_rel_pct, 0.5);
  EXPECT_LT(m.ate.rmse, 0.1);
  EXPECT_GT(m.relative.segments.size(), 200u);
}

TEST(PipelineKitti, DeterministicAndDeskewHelps) {
  if (!have_data()) GTEST_SKIP() << "no " << DLOAM_KITTI_0005;
  const Trajectories a = run_kitti(40, true);
  const Trajectories b = run_kitti(40, true);
  for (std::size_t i = 0; i < a.poses.size(); ++i)
    ASSERT_TRUE(a.poses[i].matrix() == b.poses[i].matrix()) << "scan " << i;
  const Trajectories raw = run_kitti(40, false);
  eval::SegmentOptions seg;
  seg.lengths = {5, 10};
  seg.step = 1;
  const double with = eval::evaluate_odometry(a.gt, a.poses, seg).relative.t_rel_pct;
  const double without = eval::evaluate_odometry(raw.gt, raw.poses, seg).relative.t_rel_pct;
  std::printf("first 40 scans: t_rel %.3f %% with de-skew, %.3f %% without\n", with, without);
  EXPECT_LT(with, without);
}

TEST(Pipeline, RefusesTheCnnDetectorUntilItExists) {
  PipelineConfig cfg;
  cfg.detection.detector = "cnn";
  EXPECT_THROW(Pipeline{cfg}, std::invalid_argument);
}
