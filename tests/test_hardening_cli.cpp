// The command-line tool on unusual input: reused and shared output folders, SIGTERM / SIGHUP,
// degenerate and empty scans, unpadded and gapped scan names, calib.txt without Tr, numbers
// checked at parse time, a full stdout, configs that only `run` used to refuse, a FIFO as config.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/kitti.hpp"
#include "test_io_util.hpp"

using namespace dloam;
using dloam::test::TempDir;
using dloam::test::write_text;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

namespace {
const std::string kData = DLOAM_KITTI_0005;
const std::string kKittiConfig = std::string(DLOAM_SOURCE_DIR) + "/config/kitti-raw.yaml";

struct CliResult {
  int status = -1;  ///< exit code; -1 when ended by a signal (or the 300 s guard)
  std::string out, err;
};

/// Runs `dloam ARGS` through the shell with stdout and stderr captured apart; a hang ends after
/// 300 s (status -1) instead of stalling the suite.
CliResult run_cli(const std::string& args, const std::string& redirect = "") {
  TempDir tmp;
  const std::string out = tmp.file("out"), err = tmp.file("err");
  const std::string cmd = "timeout -s KILL 300 " + std::string(DLOAM_BINARY) + " " + args + " 2>" + err +
                          (redirect.empty() ? " >" + out : " " + redirect);
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(status) && WEXITSTATUS(status) != 137 ? WEXITSTATUS(status) : -1;
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::size_t lines(const std::string& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string l; std::getline(in, l);) n += !l.empty();
  return n;
}

std::size_t files_in(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return 0;
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

nlohmann::json json_of(const std::string& path) { return nlohmann::json::parse(io::read_file(path)); }

/// The first `n` scans of the real drive (links to its files) named by `name(i)`, with labels and,
/// when asked, the matching lines of poses.txt / times.txt and calib.txt.
template <class Name>
void copy_drive(const TempDir& dir, std::size_t n, Name&& name, bool text_files = true) {
  for (std::size_t i = 0; i < n; ++i) {
    fs::create_directories(dir.path / "velodyne");
    fs::create_directories(dir.path / "labels");
    fs::create_symlink(kData + "/velodyne/" + io::scan_name(i) + ".bin",
                       dir.file("velodyne/" + name(i) + ".bin"));
    fs::create_symlink(kData + "/labels/" + io::scan_name(i) + ".label",
                       dir.file("labels/" + name(i) + ".label"));
  }
  if (!text_files) return;
  std::ifstream poses(kData + "/poses.txt"), times(kData + "/times.txt");
  std::ofstream p(dir.file("poses.txt")), t(dir.file("times.txt"));
  std::string line;
  for (std::size_t i = 0; i < n && std::getline(poses, line); ++i) p << line << '\n';
  for (std::size_t i = 0; i < n && std::getline(times, line); ++i) t << line << '\n';
  fs::copy_file(kData + "/calib.txt", dir.file("calib.txt"));
}

std::string padded(std::size_t i) { return io::scan_name(i); }

#define SKIP_WITHOUT_DATA()                                                          \
  do {                                                                               \
    if (!fs::exists(kData + "/velodyne/000000.bin")) GTEST_SKIP() << "no " << kData; \
    if (!fs::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";                \
  } while (0)
}  // namespace

TEST(HardeningCli, AnOutputFolderWithAnEarlierRunIsRefusedUnlessOverwriteAndIsLocked) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 6, padded);
  const std::string seq = dir.file(""), out = dir.file("out");
  const std::string run = "run " + seq + " --config " + kKittiConfig + " --detector geometric --out " + out;
  ASSERT_EQ(run_cli(run + " --count 6").status, 0);
  ASSERT_EQ(files_in(out + "/labels"), 6u);
  const CliResult again = run_cli(run + " --count 3");
  EXPECT_NE(again.status, 0);
  EXPECT_THAT(again.err, HasSubstr("--overwrite"));
  EXPECT_THAT(again.err, HasSubstr("labels/ (6 files)"));
  EXPECT_EQ(lines(out + "/poses.txt"), 6u);  // untouched
  const CliResult over = run_cli(run + " --count 3 --overwrite");
  ASSERT_EQ(over.status, 0) << over.err;
  EXPECT_EQ(files_in(out + "/labels"), 3u);  // the earlier run's labels are gone
  EXPECT_EQ(lines(out + "/poses.txt"), 3u);
  // 6 ground truths and 3 predictions: a missing prediction, or 3 predictions without ground truth.
  EXPECT_EQ(run_cli("eval mos " + seq + "labels " + out + "/labels").status, 1);
  const CliResult extra = run_cli("eval mos " + out + "/labels " + seq + "labels");
  EXPECT_EQ(extra.status, 0);
  EXPECT_THAT(extra.err, HasSubstr("3 .label files"));

  // A second run while one holds the folder.
  const int fd = ::open((out + "/.dloam.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const CliResult locked = run_cli(run + " --count 2 --overwrite");
  ::close(fd);
  EXPECT_NE(locked.status, 0);
  EXPECT_THAT(locked.err, HasSubstr("another dloam run"));
  EXPECT_EQ(lines(out + "/poses.txt"), 3u);

  // The input folder itself is never an output folder.
  const CliResult input =
      run_cli("run " + seq + " --config " + kKittiConfig + " --count 2 --overwrite --out " + seq);
  EXPECT_NE(input.status, 0);
  EXPECT_THAT(input.err, HasSubstr("input sequence folder"));
  EXPECT_EQ(lines(seq + "/poses.txt"), 6u);
}

TEST(HardeningCli, SigtermAndSighupStopAfterTheCurrentScanWithCompleteOutputs) {
  SKIP_WITHOUT_DATA();
  for (const int sig : {SIGTERM, SIGHUP}) {
    TempDir dir;
    const std::string out = dir.file("out");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::execl(DLOAM_BINARY, DLOAM_BINARY, "run", kData.c_str(), "--config", kKittiConfig.c_str(),
              "--detector", "geometric", "--count", "80", "--out", out.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(out + "/labels/000002.label") && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    const std::size_t scans = lines(out + "/poses.txt");
    EXPECT_GE(scans, 3u);
    EXPECT_LT(scans, 80u);
    EXPECT_EQ(lines(out + "/poses_tum.txt"), scans);
    EXPECT_EQ(lines(out + "/timing.csv"), scans + 1);
    EXPECT_EQ(files_in(out + "/labels"), scans);
    EXPECT_TRUE(fs::exists(out + "/map.ply"));
    EXPECT_EQ(json_of(out + "/metrics.json")["scans"]["processed"], scans);
  }
}

TEST(HardeningCli, DegenerateScansAreFlaggedAndADriveWithoutUsablePointsIsAnError) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 8, padded, false);
  fs::remove(dir.file("velodyne/000003.bin"));
  fs::remove(dir.file("labels/000003.label"));
  PointCloud one;
  one.xyz.emplace_back(10.0, 2.0, -1.0);
  one.intensity.push_back(0.5f);
  io::write_kitti_bin(dir.file("velodyne/000003.bin"), one);
  const std::string out = dir.file("out");
  fs::remove_all(dir.path / "labels");
  const CliResult run =
      run_cli("run " + dir.file("") + " --config " + kKittiConfig + " --detector none --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("degenerate scans: 1 of 8"));
  EXPECT_THAT(run.err, HasSubstr("000003.bin: degenerate scan"));
  EXPECT_THAT(run.err, Not(HasSubstr("wrong --preset")));
  EXPECT_EQ(json_of(out + "/metrics.json")["scans"]["degenerate_scans"], nlohmann::json::array({3}));
  std::ifstream timing(out + "/timing.csv");
  const auto cells = [](const std::string& line) {
    std::vector<std::string> c;
    std::stringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) c.push_back(cell);
    return c;
  };
  std::string line;
  std::getline(timing, line);
  const auto header = cells(line);
  const auto column = std::find(header.begin(), header.end(), "degenerate") - header.begin();
  ASSERT_LT(static_cast<std::size_t>(column), header.size()) << line;
  for (int i = 0; i <= 3; ++i) std::getline(timing, line);  // scans 0-3
  EXPECT_EQ(cells(line).at(static_cast<std::size_t>(column)), "1") << line;
  const CliResult check = run_cli("check " + dir.file(""));
  EXPECT_THAT(check.err, HasSubstr("000003.bin: degenerate scan (1 point"));
  EXPECT_THAT(check.out, HasSubstr("degenerate    1 scan"));

  // A 1-point first scan is no reason to blame the sensor model.
  TempDir first;
  copy_drive(
      first, 4, [](std::size_t i) { return io::scan_name(i + 1); }, false);
  fs::remove_all(first.path / "labels");
  io::write_kitti_bin(first.file("velodyne/000000.bin"), one);
  const CliResult f = run_cli("run " + first.file("") + " --config " + kKittiConfig +
                              " --detector none --out " + first.file("out"));
  EXPECT_EQ(f.status, 0) << f.err;
  EXPECT_THAT(f.err, Not(HasSubstr("wrong --preset")));

  // Every scan all zeros.
  TempDir zeros;
  PointCloud zero;
  zero.xyz.assign(500, Vec3::Zero());
  zero.intensity.assign(500, 0.0f);
  for (int i = 0; i < 3; ++i) io::write_kitti_bin(zeros.file("velodyne/" + io::scan_name(i) + ".bin"), zero);
  const CliResult z = run_cli("run " + zeros.file("") + " --detector none --out " + zeros.file("out"));
  EXPECT_NE(z.status, 0);
  EXPECT_THAT(z.err, HasSubstr("none of the 3 scans has a point between min_range"));
}

TEST(HardeningCli, UnpaddedAndGappedScanNamesKeepTheirNamesInTheOutputs) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 11, [](std::size_t i) { return std::to_string(i); });
  const std::string out = dir.file("out");
  const CliResult run =
      run_cli("run " + dir.file("") + " --config " + kKittiConfig + " --detector geometric --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  for (int i = 0; i <= 10; ++i) EXPECT_TRUE(fs::exists(out + "/labels/" + std::to_string(i) + ".label")) << i;
  EXPECT_LT(json_of(out + "/metrics.json")["odometry"]["ate_m"].get<double>(), 0.05);
  EXPECT_EQ(run_cli("eval mos " + dir.file("labels") + " " + out + "/labels").status, 0);

  TempDir gap;
  copy_drive(gap, 8, padded, false);
  fs::remove(gap.file("velodyne/000005.bin"));
  fs::remove(gap.file("labels/000005.label"));
  const CliResult g = run_cli("run " + gap.file("") + " --config " + kKittiConfig +
                              " --detector geometric --out " + gap.file("out"));
  ASSERT_EQ(g.status, 0) << g.err;
  EXPECT_THAT(g.err, HasSubstr("skip from 000004 to 000006"));
  EXPECT_FALSE(fs::exists(gap.file("out/labels/000005.label")));
  EXPECT_TRUE(fs::exists(gap.file("out/labels/000007.label")));
  EXPECT_EQ(run_cli("eval mos " + gap.file("labels") + " " + gap.file("out/labels")).status, 0);
}

TEST(HardeningCli, CheckWithASensorRefusesScansThatRunWouldRefuse) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 2, padded);
  const CliResult vlp = run_cli("check " + dir.file("") + " --preset VLP-16");  // HDL-64E scans
  EXPECT_NE(vlp.status, 0);
  EXPECT_THAT(vlp.err, HasSubstr("vertical field of view"));
  EXPECT_EQ(run_cli("check " + dir.file("") + " --config " + kKittiConfig).status, 0);
}

TEST(HardeningCli, CameraFramePosesBesideACalibWithoutTrNeedAnExplicitFrame) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 3, padded);
  fs::remove(dir.file("calib.txt"));
  write_text(dir.file("calib.txt"), "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  const std::string run = "run " + dir.file("") + " --config " + kKittiConfig + " --detector none --out ";
  const CliResult refused = run_cli(run + dir.file("a"));
  EXPECT_NE(refused.status, 0);
  EXPECT_THAT(refused.err, HasSubstr("calib.txt: has no Tr"));
  EXPECT_THAT(refused.err, HasSubstr("--gt-frame lidar"));
  EXPECT_FALSE(fs::exists(dir.file("a/poses.txt")));
  EXPECT_EQ(run_cli(run + dir.file("b") + " --gt-frame lidar").status, 0);
}

TEST(HardeningCli, NumbersAreCheckedWhenTheCommandLineIsParsed) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  for (const char* bad : {"--first -1", "--count 0", "--count -3", "--lengths 5,-5", "--count 2x"}) {
    const CliResult r = run_cli("run " + kData + " --out " + dir.file("o") + " " + bad);
    EXPECT_NE(r.status, 0) << bad;
    EXPECT_THAT(r.err, HasSubstr(std::string(bad).substr(0, std::string(bad).find(' ')))) << bad;
    EXPECT_FALSE(fs::exists(dir.file("o"))) << bad << ": nothing runs";
  }
  // A max_range below every point: the message names the range, not the sensor preset.
  write_text(dir.file("tiny.yaml"), "sensor: {min_range: 0.0, max_range: 0.001}\n");
  const CliResult tiny = run_cli("run " + kData + " --count 2 --detector none --config " +
                                 dir.file("tiny.yaml") + " --out " + dir.file("t"));
  EXPECT_NE(tiny.status, 0);
  EXPECT_THAT(tiny.err, HasSubstr("max_range"));
  EXPECT_THAT(tiny.err, Not(HasSubstr("wrong --preset")));
}

TEST(HardeningCli, ConfigsRunRefusesAreRefusedByEveryCommand) {
  if (!fs::exists(DLOAM_BINARY)) GTEST_SKIP() << "no dloam binary";
  TempDir dir;
  write_text(dir.file("latency.yaml"), "mapping: {every_n_scans: 1, latency_scans: 3}\n");
  const CliResult dump = run_cli("config dump --config " + dir.file("latency.yaml"));
  EXPECT_NE(dump.status, 0);
  EXPECT_THAT(dump.err, HasSubstr("latency_scans"));
  write_text(dir.file("leaf.yaml"), "mapping: {map_leaf_size: 1e-5}\n");
  const CliResult leaf = run_cli("config dump --config " + dir.file("leaf.yaml"));
  EXPECT_EQ(leaf.status, 1);
  EXPECT_THAT(leaf.err, HasSubstr("mapping.map_leaf_size"));
  write_text(dir.file("dup.yaml"), "threads: 2\nthreads: 3\n");
  EXPECT_NE(run_cli("config dump --config " + dir.file("dup.yaml")).status, 0);
  // Errors go to stderr, results to stdout.
  EXPECT_THAT(dump.out, Not(HasSubstr("error")));
  EXPECT_THAT(dump.err, HasSubstr("[error]"));
  // A FIFO is refused at once instead of waiting for a writer.
  ASSERT_EQ(::mkfifo(dir.file("fifo.yaml").c_str(), 0600), 0);
  const CliResult fifo = run_cli("config dump --config " + dir.file("fifo.yaml"));
  EXPECT_NE(fifo.status, -1) << "hung";
  EXPECT_THAT(fifo.err, HasSubstr("FIFO"));
}

TEST(HardeningCli, AWorkerExceptionEndsTheRunWithAnErrorAndKeepsTheOutputs) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  // Validation refuses leaves that overflow the voxel keys before anything runs.
  write_text(dir.file("leaf.yaml"), "mapping: {map_leaf_size: 1e-5}\n");
  const CliResult leaf = run_cli("run " + kData + " --count 3 --detector none --config " +
                                 dir.file("leaf.yaml") + " --out " + dir.file("a"));
  EXPECT_EQ(leaf.status, 1);
  EXPECT_THAT(leaf.err, HasSubstr("map_leaf_size"));
  // A scan that fails to read mid-run: the outputs of the scans before it are complete.
  TempDir seq;
  copy_drive(seq, 5, padded, false);
  fs::remove(seq.file("velodyne/000003.bin"));
  write_text(seq.file("velodyne/000003.bin"), std::string(17, 'x'));
  const std::string out = seq.file("out");
  const CliResult bad =
      run_cli("run " + seq.file("") + " --config " + kKittiConfig + " --detector geometric --out " + out);
  EXPECT_EQ(bad.status, 1);
  EXPECT_THAT(bad.err, HasSubstr("000003.bin"));
  EXPECT_EQ(lines(out + "/poses.txt"), 3u);
  EXPECT_EQ(lines(out + "/timing.csv"), 4u);
  EXPECT_EQ(files_in(out + "/labels"), 3u);
}

TEST(HardeningCli, AFullStandardOutputIsAnError) {
  SKIP_WITHOUT_DATA();
  TempDir dir;
  copy_drive(dir, 2, padded);
  EXPECT_NE(run_cli("check " + dir.file(""), ">/dev/full").status, 0);
  EXPECT_NE(
      run_cli("eval odometry " + dir.file("poses.txt") + " " + dir.file("poses.txt"), ">/dev/full").status,
      0);
  EXPECT_EQ(
      run_cli("eval odometry " + dir.file("poses.txt") + " " + dir.file("poses.txt"), ">/dev/null").status,
      0);
}
