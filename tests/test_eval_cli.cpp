// `dloam eval odometry|mos` end to end on kitti-raw-0005: a file against itself, against a
// perturbed copy, bad input, JSON keys and the gnuplot PNG.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_util.hpp"
#include "dloam/io/kitti.hpp"

namespace fs = std::filesystem;
using namespace dloam;

namespace {

const std::string kData = DLOAM_KITTI_0005;

using CommandResult = test::CliRun;
CommandResult run(const std::string& args) { return test::run_dloam(args); }

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

class EvalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dloam_test_eval_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(EvalCli, OdometryOfPosesAgainstThemselvesIsZero) {
  const CommandResult r = run("eval odometry " + kData + "/poses.txt " + kData + "/poses.txt --calib " +
                              kData + "/calib.txt --lengths 5,10,20,30 --json " + path("self.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = read_json(path("self.json"));
  EXPECT_GT(j["segments"].get<int>(), 100);
  EXPECT_NEAR(j["t_rel_pct"].get<double>(), 0.0, 1e-9);
  // acos(0.5 (trace - 1)) resolves angles down to ~1.5e-8 rad in double precision.
  EXPECT_NEAR(j["r_rel_deg100m"].get<double>(), 0.0, 1e-4);
  EXPECT_NEAR(j["ate_m"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(j["ate_aligned_m"].get<double>(), 0.0, 1e-9);
  EXPECT_EQ(j["frames"].get<int>(), 100);
  EXPECT_NE(r.output.find("t_rel"), std::string::npos);
}

TEST_F(EvalCli, OdometryOfPerturbedCopyIsNonzeroAndJsonHasKeys) {
  // 2 % longer steps and a yaw drift of 0.01 deg per frame about the camera's vertical (y) axis.
  auto poses = io::read_kitti_poses(kData + "/poses.txt");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    poses[i].translation() *= 1.02;
    poses[i].linear() =
        Eigen::AngleAxisd(1e-4 * M_PI / 180.0 * 100.0 * static_cast<double>(i), Vec3::UnitY()) *
        poses[i].linear();
  }
  io::write_kitti_poses(path("perturbed.txt"), poses);
  const CommandResult r =
      run("eval odometry " + kData + "/poses.txt " + path("perturbed.txt") + " --calib " + kData +
          "/calib.txt --lengths 5,10,20,30 --json " + path("p.json") + " --plot " + path("p.png"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = read_json(path("p.json"));
  for (const char* key : {"t_rel_pct", "r_rel_deg100m", "ate_m", "ate_aligned_m", "rpe_trans_m",
                          "rpe_rot_deg", "segments", "per_length"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_GT(j["t_rel_pct"].get<double>(), 1.0);
  EXPECT_GT(j["r_rel_deg100m"].get<double>(), 1.0);
  EXPECT_GT(j["ate_m"].get<double>(), 0.3);
  EXPECT_LT(j["ate_aligned_m"].get<double>(), j["ate_m"].get<double>());
  EXPECT_GT(j["rpe_trans_m"].get<double>(), 0.0);
  EXPECT_NEAR(j["rpe_rot_deg"].get<double>(), 0.01, 0.002);  // the per-frame drift, seen in the LiDAR frame
  ASSERT_EQ(j["per_length"].size(), 4u);
  int sum = 0;
  for (const auto& e : j["per_length"]) sum += e["segments"].get<int>();
  EXPECT_EQ(sum, j["segments"].get<int>());
  // The PNG exists and starts with the PNG signature.
  std::ifstream png(path("p.png"), std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << r.output;
}

TEST_F(EvalCli, OdometryRejectsTrajectoriesOfDifferentLengths) {
  auto poses = io::read_kitti_poses(kData + "/poses.txt");
  poses.pop_back();
  io::write_kitti_poses(path("short.txt"), poses);
  const CommandResult r = run("eval odometry " + kData + "/poses.txt " + path("short.txt"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("poses.txt"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("short.txt"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("100"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("99"), std::string::npos) << r.output;
}

TEST_F(EvalCli, MosOfLabelsAgainstThemselvesIsPerfect) {
  const CommandResult r =
      run("eval mos " + kData + "/labels " + kData + "/labels --json " + path("mos.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = read_json(path("mos.json"));
  EXPECT_EQ(j["scans"].get<int>(), 100);
  EXPECT_GT(j["tp"].get<long>(), 0);
  EXPECT_EQ(j["fp"].get<long>(), 0);
  EXPECT_EQ(j["fn"].get<long>(), 0);
  EXPECT_DOUBLE_EQ(j["iou"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["precision"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["recall"].get<double>(), 1.0);
  EXPECT_GT(j["object_tp"].get<long>(), 0);
  EXPECT_EQ(j["object_fp"].get<long>() + j["object_fn"].get<long>(), 0);
  EXPECT_DOUBLE_EQ(j["object_iou"].get<double>(), 1.0);
}

TEST_F(EvalCli, MosCountsMissedMovingPointsAndNamesMissingPredictions) {
  // Ground truth: scans 0-2. Prediction: the same, with scan 0's moving points marked static.
  fs::create_directories(path("gt"));
  fs::create_directories(path("pred"));
  std::uint64_t moving_total = 0, moving_scan0 = 0;
  for (int i = 0; i < 3; ++i) {
    const std::string name = io::scan_name(static_cast<std::size_t>(i)) + ".label";
    const std::string src = kData + "/labels/" + name;
    auto labels = io::read_labels(src, fs::file_size(src) / 4);
    io::write_labels(path("gt/" + name), labels);
    for (auto& l : labels) {
      if (!semantic::is_moving(l)) continue;
      ++moving_total;
      if (i == 0) {
        ++moving_scan0;
        l = semantic::kStatic;
      }
    }
    if (i < 2) io::write_labels(path("pred/" + name), labels);
  }
  ASSERT_GT(moving_scan0, 0u);
  CommandResult r = run("eval mos " + path("gt") + " " + path("pred"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("000002.label"), std::string::npos) << r.output;

  fs::copy_file(path("gt/000002.label"), path("pred/000002.label"));
  r = run("eval mos " + path("gt") + " " + path("pred") + " --json " + path("m.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = read_json(path("m.json"));
  EXPECT_EQ(j["fn"].get<std::uint64_t>(), moving_scan0);
  EXPECT_EQ(j["fp"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(j["tp"].get<std::uint64_t>(), moving_total - moving_scan0);
  EXPECT_NEAR(j["iou"].get<double>(), double(moving_total - moving_scan0) / double(moving_total), 1e-12);
  EXPECT_GT(j["object_fn"].get<long>(), 0);
}

TEST_F(EvalCli, TumFilesGiveTheSameResultsAsKittiFiles) {
  const auto gt = io::read_kitti_poses(kData + "/poses.txt");
  auto est = gt;
  for (std::size_t i = 0; i < est.size(); ++i)
    est[i].translation() *= 1.0 + 0.001 * static_cast<double>(i % 7);
  io::write_kitti_poses(path("est.txt"), est);
  std::vector<io::StampedPose> gt_tum, est_tum;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    gt_tum.push_back({0.1 * static_cast<double>(i), gt[i]});
    est_tum.push_back({0.1 * static_cast<double>(i), est[i]});
  }
  io::write_tum_poses(path("gt.tum"), gt_tum);
  io::write_tum_poses(path("est.tum"), est_tum);
  const std::string options = " --lengths 5,10 --step 3 --json ";
  ASSERT_EQ(run("eval odometry " + kData + "/poses.txt " + path("est.txt") + options + path("k.json")).status,
            0);
  const CommandResult r = run("eval odometry " + path("gt.tum") + " " + path("est.tum") + " --format tum" +
                              options + path("t.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto k = read_json(path("k.json"));
  const auto t = read_json(path("t.json"));
  EXPECT_EQ(k["step"].get<int>(), 3);
  EXPECT_EQ(k["segments"], t["segments"]);
  EXPECT_GT(k["t_rel_pct"].get<double>(), 0.01);
  for (const char* key : {"t_rel_pct", "ate_m", "ate_aligned_m", "rpe_trans_m"}) {
    EXPECT_NEAR(k[key].get<double>(), t[key].get<double>(), 1e-6) << key;
  }
}
