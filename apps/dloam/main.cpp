// dloam: LiDAR SLAM in dynamic urban environments (DLOAM). Command-line front-end.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>

#include "commands.hpp"
#include "dloam/run/process_memory.hpp"
#ifdef DLOAM_WITH_ROS
#include "dloam/ros/bag_sequence.hpp"
#endif

int main(int argc, char** argv) {
  dloam::run::reuse_freed_memory();
  CLI::App app{"dloam: real-time LiDAR SLAM that keeps moving objects out of odometry and map"};
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  dloam simulate --scenario urban --frames 200 --seed 1 --out sim/urban\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005\n"
      "  dloam eval odometry GT/poses.txt out/0005/poses.txt --lengths 5,10,20,30\n"
      "  dloam check ../shared/data/kitti-raw-0005\n"
      "  dloam thin ../shared/data/kitti-raw-0005 --out thin/0005-every2 --keep-every 2\n"
      "  dloam run vlp16.pcap --out out/vlp16\n"
      "Run `dloam COMMAND --help` for each command.");
  dloam::app::register_simulate(app);
  dloam::app::register_thin(app);
  dloam::app::register_eval(app);
  dloam::app::register_check(app);
  dloam::app::register_config(app);
  dloam::app::register_run(app);
  dloam::app::register_clean(app);
  dloam::app::register_calibrate(app);
  dloam::app::register_convert(app);
  dloam::app::register_report(app);
#ifdef DLOAM_WITH_TORCH
  dloam::app::register_train(app);
  dloam::app::register_sweep(app);
#endif
#ifdef DLOAM_WITH_ROS
  dloam::ros1::register_bag_format();  // sequences may be rosbags
#endif
  spdlog::set_default_logger(
      spdlog::stderr_color_mt("dloam"));  // errors beside the progress, not in the results
  int status = 0;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    status = app.exit(e);
  } catch (const std::exception& e) {
    // Subcommand callbacks run inside parse(); bad input surfaces here with its file name.
    spdlog::error("{}", e.what());
    status = 1;
  }
  // Results go to stdout: a full disk or a closed pipe there must not look like success.
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    if (status != 0) return status;  // already reported
    std::fprintf(stderr, "dloam: error writing to standard output: %s\n",
                 errno ? std::strerror(errno) : "I/O error");
    return 1;
  }
  return status;
}
