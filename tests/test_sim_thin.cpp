// Thinned sequences: `dloam simulate --keep-every / --drop` writes exactly the kept scans of the
// full simulation (byte for byte) with their true times, poses and labels; `dloam thin` does the
// same to any sequence folder (the simulated one, the first scans of kitti-raw-0005, a PCD
// folder) and never writes into its input; the scan choice is shared and reproducible.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/thin.hpp"

namespace fs = std::filesystem;
using namespace dloam;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::vector<std::string> out;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

class SimThin : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dloam_test_sim_thin_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Scan k of `thinned` is scan kept[k] of `full`: scan and label bytes, pose and time lines.
  static void expect_subset(const fs::path& full, const fs::path& thinned,
                            const std::vector<std::size_t>& kept, const std::string& scan_sub,
                            const std::string& ext, bool same_pose_lines) {
    const auto times = lines_of(full / "times.txt"), thin_times = lines_of(thinned / "times.txt");
    const auto poses = lines_of(full / "poses.txt"), thin_poses = lines_of(thinned / "poses.txt");
    ASSERT_EQ(thin_times.size(), kept.size());
    ASSERT_EQ(thin_poses.size(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const std::string a = io::scan_name(kept[k]), b = io::scan_name(k);
      EXPECT_EQ(slurp(full / scan_sub / (a + ext)), slurp(thinned / scan_sub / (b + ext))) << k;
      if (fs::exists(full / "labels")) {
        EXPECT_EQ(slurp(full / "labels" / (a + ".label")), slurp(thinned / "labels" / (b + ".label"))) << k;
      }
      EXPECT_EQ(thin_times[k], times[kept[k]]) << k;
      if (same_pose_lines) {
        EXPECT_EQ(thin_poses[k], poses[kept[k]]) << k;
      }
    }
    std::size_t scans = 0;
    for (const auto& f : fs::directory_iterator(thinned / scan_sub)) scans += f.path().extension() == ext;
    EXPECT_EQ(scans, kept.size());
  }

  fs::path dir_;
};

}  // namespace

TEST(SimThinSelect, KeepEveryAndDropChooseReproducibleScans) {
  io::ThinOptions o;
  EXPECT_EQ(io::select_scans(5, o), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  o.keep_every = 3;
  EXPECT_EQ(io::select_scans(10, o), (std::vector<std::size_t>{0, 3, 6, 9}));
  o.keep_every = 1;
  o.drop = 0.3;
  o.seed = 4;
  const auto a = io::select_scans(20000, o);
  EXPECT_EQ(a, io::select_scans(20000, o));
  EXPECT_NEAR(static_cast<double>(a.size()) / 20000.0, 0.7, 0.015);
  o.seed = 5;
  EXPECT_NE(a, io::select_scans(20000, o));
  // A scan's draw does not depend on keep-every: every 2nd with drops = the even ones of the drops.
  o.keep_every = 2;
  const auto even = io::select_scans(20000, o);
  o.keep_every = 1;
  std::vector<std::size_t> expected;
  for (std::size_t i : io::select_scans(20000, o))
    if (i % 2 == 0) expected.push_back(i);
  EXPECT_EQ(even, expected);
  o.drop = 1.0;
  EXPECT_THROW(io::select_scans(10, o), std::invalid_argument);
  o.drop = 0.5;
  o.keep_every = 0;
  EXPECT_THROW(io::select_scans(10, o), std::invalid_argument);
}

TEST_F(SimThin, SimulatedKeepEveryAndDropWriteTheFullRunsScansWithTheirTrueTimes) {
  const std::string common = "simulate --scenario urban --frames 12 --seed 3 --preset VLP-16 --traffic 2";
  ASSERT_EQ(test::run_dloam(common + " --out " + path("full")).status, 0);
  const auto every = test::run_dloam(common + " --keep-every 3 --out " + path("every3"));
  ASSERT_EQ(every.status, 0) << every.output;
  expect_subset(path("full"), path("every3"), {0, 3, 6, 9}, "velodyne", ".bin", true);
  const auto times = lines_of(path("every3") + "/times.txt");
  EXPECT_DOUBLE_EQ(std::stod(times[1]), 0.3);  // true start times, not renumbered ones

  // Random drops: the scans of select_scans, poses relative to the first kept scan.
  io::ThinOptions o;
  o.drop = 0.5;
  o.seed = 11;
  const auto kept = io::select_scans(12, o);
  ASSERT_GT(kept.front(), 0u) << "seed 11 should drop scan 0 to test the re-based poses";
  ASSERT_EQ(test::run_dloam(common + " --drop 0.5 --drop-seed 11 --out " + path("drop")).status, 0);
  expect_subset(path("full"), path("drop"), kept, "velodyne", ".bin", false);
  std::ifstream js(path("drop") + "/scenario.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  EXPECT_EQ(j["kept_frames"].get<std::vector<std::size_t>>(), kept);
  const auto full_poses = io::read_kitti_poses(path("full") + "/poses.txt");
  const auto drop_poses = io::read_kitti_poses(path("drop") + "/poses.txt");
  EXPECT_TRUE(drop_poses.front().isApprox(Pose::Identity(), 1e-12));
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Pose expected = full_poses[kept.front()].inverse() * full_poses[kept[k]];
    EXPECT_TRUE(drop_poses[k].isApprox(expected, 1e-7)) << k;
  }

  // `dloam thin` of the full run gives the files of `simulate --keep-every` and `--drop`.
  ASSERT_EQ(test::run_dloam("thin " + path("full") + " --keep-every 3 --out " + path("thin3")).status, 0);
  for (const char* f : {"poses.txt", "times.txt", "calib.txt"})
    EXPECT_EQ(slurp(path("thin3") + "/" + f), slurp(path("every3") + "/" + f)) << f;
  expect_subset(path("every3"), path("thin3"), {0, 1, 2, 3}, "velodyne", ".bin", true);
  ASSERT_EQ(
      test::run_dloam("thin " + path("full") + " --drop 0.5 --seed 11 --out " + path("thin_drop")).status, 0);
  expect_subset(
      path("drop"), path("thin_drop"),
      [&] {
        std::vector<std::size_t> all(kept.size());
        for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
        return all;
      }(),
      "velodyne", ".bin", false);
  EXPECT_EQ(lines_of(path("thin_drop") + "/kept_scans.txt").size(), kept.size());
  EXPECT_EQ(test::run_dloam("check " + path("thin_drop")).status, 0);
  // Every scan dropped: an error, not an empty sequence.
  const auto none =
      test::run_dloam(common + " --keep-every 20 --drop 0.99 --drop-seed 2 --out " + path("none"));
  EXPECT_NE(none.status, 0);
  EXPECT_NE(none.output.find("no scan"), std::string::npos) << none.output;
}

TEST_F(SimThin, ThinsTheFirstScansOfKittiRaw0005WithoutTouchingThem) {
  const fs::path data = DLOAM_KITTI_0005;
  if (!fs::exists(data / "velodyne" / "000009.bin")) GTEST_SKIP() << "no " << data;
  // A copy of the first 10 scans: scans, labels, poses, times, calib.
  const fs::path in = path("kitti10");
  fs::create_directories(in / "velodyne");
  fs::create_directories(in / "labels");
  for (std::size_t i = 0; i < 10; ++i) {
    const std::string n = io::scan_name(i);
    fs::copy_file(data / "velodyne" / (n + ".bin"), in / "velodyne" / (n + ".bin"));
    fs::copy_file(data / "labels" / (n + ".label"), in / "labels" / (n + ".label"));
  }
  for (const char* f : {"poses.txt", "times.txt"}) {
    const auto lines = lines_of(data / f);
    std::ofstream out(in / f);
    for (std::size_t i = 0; i < 10; ++i) out << lines[i] << '\n';
  }
  fs::copy_file(data / "calib.txt", in / "calib.txt");
  const std::string before = slurp(in / "poses.txt") + slurp(in / "times.txt");

  const auto r = test::run_dloam("thin " + in.string() + " --out " + path("every3") + " --keep-every 3");
  ASSERT_EQ(r.status, 0) << r.output;
  expect_subset(in, path("every3"), {0, 3, 6, 9}, "velodyne", ".bin", true);
  EXPECT_EQ(slurp(path("every3") + "/calib.txt"), slurp(in / "calib.txt"));
  EXPECT_EQ(lines_of(path("every3") + "/kept_scans.txt"), (std::vector<std::string>{"0", "3", "6", "9"}));
  EXPECT_EQ(test::run_dloam("check " + path("every3")).status, 0);
  // Hard links (same file system): the same file, not a copy.
  EXPECT_TRUE(fs::equivalent(in / "velodyne" / "000006.bin", path("every3") + "/velodyne/000002.bin"));

  // Random drops with a seed; rerunning into the same folder needs --overwrite.
  io::ThinOptions o;
  o.drop = 0.4;
  o.seed = 7;
  const auto kept = io::select_scans(10, o);
  ASSERT_EQ(test::run_dloam("thin " + in.string() + " --out " + path("drop") + " --drop 0.4 --seed 7").status,
            0);
  expect_subset(in, path("drop"), kept, "velodyne", ".bin", kept.front() == 0);
  const auto again =
      test::run_dloam("thin " + in.string() + " --out " + path("drop") + " --drop 0.4 --seed 7");
  EXPECT_NE(again.status, 0);
  EXPECT_NE(again.output.find("--overwrite"), std::string::npos) << again.output;
  EXPECT_EQ(
      test::run_dloam("thin " + in.string() + " --out " + path("drop") + " --drop 0.4 --seed 7 --overwrite")
          .status,
      0);

  // Never into the input, and no silent no-op.
  const auto into =
      test::run_dloam("thin " + in.string() + " --out " + (in / "sub").string() + " --keep-every 2");
  EXPECT_NE(into.status, 0);
  EXPECT_NE(into.output.find("inside"), std::string::npos) << into.output;
  EXPECT_NE(test::run_dloam("thin " + in.string() + " --out " + path("same")).status, 0);
  EXPECT_EQ(slurp(in / "poses.txt") + slurp(in / "times.txt"), before);
  EXPECT_EQ(std::distance(fs::directory_iterator(in / "velodyne"), fs::directory_iterator{}), 10);

  // Without times.txt the kept scans get their nominal times: index / scan rate.
  fs::remove(in / "times.txt");
  ASSERT_EQ(test::run_dloam("thin " + in.string() + " --out " + path("nominal") + " --keep-every 4").status,
            0);
  const auto times = io::read_times(path("nominal") + "/times.txt");
  ASSERT_EQ(times.size(), 3u);
  EXPECT_DOUBLE_EQ(times[1], 0.4);
  EXPECT_DOUBLE_EQ(times[2], 0.8);
}

TEST_F(SimThin, ThinsAFolderOfPcdScans) {
  const fs::path in = path("pcd");
  fs::create_directories(in);
  for (int i = 0; i < 6; ++i) {
    PointCloud c;
    for (int k = 0; k < 10; ++k) {
      c.xyz.emplace_back(i, k, 1.0);
      c.intensity.push_back(0.5f);
    }
    io::write_pcd((in / (io::scan_name(static_cast<std::size_t>(i)) + ".pcd")).string(), c);
  }
  {
    std::ofstream t(in / "times.txt");
    for (int i = 0; i < 6; ++i) t << 100.0 + 0.05 * i << '\n';
    std::ofstream p(in / "poses.txt");
    for (int i = 0; i < 6; ++i) p << "1 0 0 " << i << " 0 1 0 0 0 0 1 0\n";
  }
  const auto r = test::run_dloam("thin " + in.string() + " --out " + path("out") + " --keep-every 2");
  ASSERT_EQ(r.status, 0) << r.output;
  // PCD scans directly in the folder: the same layout out (plus times, poses, kept_scans).
  expect_subset(in, path("out"), {0, 2, 4}, ".", ".pcd", true);
}
