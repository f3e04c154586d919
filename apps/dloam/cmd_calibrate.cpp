// `dloam calibrate-beams SEQUENCE_DIR`: fits the beam table of the sensor (elevation and origin
// height per beam, beam_calibration.hpp) from scans stored ring by ring (KITTI .bin), prints it as
// the YAML sensor section on stdout, and on stderr the fit per beam and how the range image
// (eq. 4-6) fits the data with the given sensor model and with the fitted one.
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/core/beam_calibration.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::app {
namespace {

struct CalibrateArgs {
  std::string dir, out;
  ConfigArgs config;
  int every = 10;
};

/// Range-image statistics of one sensor model over scans.
struct Fit {
  std::size_t in_range = 0, outside_fov = 0, lost = 0, same_row = 0, pixels = 0, empty = 0;
  std::vector<std::size_t> row_points, row_empty;

  void add(const std::vector<Vec3>& points, const std::vector<int>& ring, const std::vector<int>& row_of_ring,
           const SensorConfig& s) {
    const RangeImage img = project(points, s);
    row_points.resize(static_cast<std::size_t>(s.N_scan));
    row_empty.resize(static_cast<std::size_t>(s.N_scan));
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double r = points[i].norm();
      if (!(r >= s.min_range && r <= s.max_range)) continue;
      ++in_range;
      const int px = img.pixel_of_point(i);
      if (px < 0) {
        ++outside_fov;
        continue;
      }
      ++row_points[static_cast<std::size_t>(img.row_of_point[i])];
      lost += img.point_of_pixel[static_cast<std::size_t>(px)] != static_cast<int>(i);
      const auto k = static_cast<std::size_t>(ring[i]);
      same_row += k < row_of_ring.size() && row_of_ring[k] == img.row_of_point[i];
    }
    for (std::size_t p = 0; p < img.point_of_pixel.size(); ++p)
      if (img.point_of_pixel[p] < 0) ++row_empty[p / static_cast<std::size_t>(img.cols)];
    pixels += img.point_of_pixel.size();
  }
  void print(const char* name, std::size_t scans, int cols) const {
    auto pct = [&](std::size_t n) { return 100.0 * static_cast<double>(n) / static_cast<double>(in_range); };
    std::size_t empty_rows = 0, all_empty = 0;
    for (std::size_t e : row_empty) {
      empty_rows += e > scans * static_cast<std::size_t>(cols) / 2;
      all_empty += e;
    }
    std::fprintf(stderr,
                 "%-8s outside FOV %5.2f %%  lose their pixel %5.2f %%  row = beam of the ring %6.2f %%  "
                 "empty pixels %5.2f %%  rows more than half empty %zu\n",
                 name, pct(outside_fov), pct(lost), pct(same_row), 100.0 * all_empty / pixels, empty_rows);
    std::fprintf(stderr, "%-8s points per row (bottom first, per scan):", name);
    for (std::size_t n : row_points) std::fprintf(stderr, " %zu", n / scans);
    std::fprintf(stderr, "\n");
  }
};

void run_calibrate(const CalibrateArgs& a) {
  PipelineConfig cfg = io::config_from(a.config.preset, a.config.config_path);
  const io::Sequence seq = io::open_sequence(a.dir);
  BeamTableFit fitter(cfg.sensor);
  std::vector<std::vector<Vec3>> scans;
  for (std::size_t i = 0; i < seq.size(); i += static_cast<std::size_t>(a.every)) {
    std::vector<Vec3> points = seq.read_scan(i).xyz;
    correct_vertical_angle(points, cfg.sensor.vertical_angle_correction_deg);
    fitter.add(points, seq.scan_files[i]);
    scans.push_back(std::move(points));
  }
  const std::vector<BeamTableFit::Beam> beams = fitter.fit();
  std::fprintf(stderr, "%zu scans; per beam (bottom first): row ring elevation_deg offset_m rms_mm points\n",
               scans.size());
  std::vector<int> row_of_ring(beams.size());
  for (std::size_t k = 0; k < beams.size(); ++k) {
    const auto& b = beams[k];
    row_of_ring[static_cast<std::size_t>(b.ring)] = static_cast<int>(k);
    std::fprintf(stderr, "  %2zu %2d %8.3f %7.3f %6.2f %zu\n", k, b.ring, b.elevation_deg, b.offset_m,
                 1000.0 * b.rms_m, b.points);
  }
  const SensorConfig fitted = fitter.fitted_sensor();
  Fit before, after;
  for (const auto& points : scans) {
    const std::vector<int> ring = rings_from_point_order(points);
    before.add(points, ring, row_of_ring, cfg.sensor);
    after.add(points, ring, row_of_ring, fitted);
  }
  before.print("given", scans.size(), cfg.sensor.Horizon_SCAN);
  after.print("fitted", scans.size(), fitted.Horizon_SCAN);
  cfg.sensor = fitted;
  const std::string yaml = fmt::format("# Fitted by `dloam calibrate-beams` from {} scans of {}\n{}",
                                       scans.size(), a.dir, io::dump_config(cfg, "sensor"));
  if (a.out.empty()) {
    fmt::print("{}", yaml);
  } else {
    io::write_atomic(a.out, [&](std::ostream& os) { os << yaml; });
    std::fprintf(stderr, "wrote %s\n", a.out.c_str());
  }
}

}  // namespace

void register_calibrate(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  auto* cmd = app.add_subcommand(
      "calibrate-beams", "fit the beam table (elevation, origin height) from scans stored ring by ring");
  cmd->add_option("SEQUENCE_DIR", args->dir, "sequence folder (KITTI .bin scans)")->required();
  ConfigHelp config_help;
  config_help.config = "YAML config (or shipped name) whose sensor section is the starting model";
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--out,-o", args->out, "write the YAML sensor section here (default: stdout)");
  cmd->add_option("--every", args->every, "use every N-th scan")->check(CLI::Range(1, 1000000));
  cmd->footer(
      "Example:\n"
      "  dloam calibrate-beams ../shared/data/kitti-raw-0005 --config kitti-raw > sensor.yaml");
  cmd->callback([args] { run_calibrate(*args); });
}

}  // namespace dloam::app
