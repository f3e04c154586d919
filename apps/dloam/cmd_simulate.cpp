// `dloam simulate`: renders a dynamic-scene sequence with the rolling-shutter LiDAR simulator
// (src/dloam/sim) and writes it in the SemanticKITTI layout: velodyne/*.bin, labels/*.label,
// poses.txt (camera frame, relative to the first scan, mid-sweep poses), calib.txt (KITTI
// odometry's Tr), times.txt, and scenario.json describing the parameters and the objects.
#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct SimulateArgs {
  std::string scenario = "urban", out, preset = "HDL-64E";
  std::string config;  ///< YAML whose sensor section is simulated (over the preset); empty: the preset
  sim::ScenarioParams params;
  double noise = 0.02, dropout = 0.01;
  bool overwrite = false;
};

// KITTI odometry sequences 00-02: camera projections and Tr (velodyne -> rectified camera 0).
io::Calib kitti_calib() {
  io::Calib c;
  const std::vector<double> P0{718.856, 0, 607.1928, 0, 0, 718.856, 185.2157, 0, 0, 0, 1, 0};
  c.entries = {{"P0", P0}, {"P1", P0}, {"P2", P0}, {"P3", P0}};
  c.entries[1].second[3] = -386.1448;
  c.entries[2].second = {718.856,  0,          607.1928, 45.38225, 0, 718.856,
                         185.2157, -0.1130887, 0,        0,        1, 0.003779761};
  c.entries[3].second = {718.856,  0,        607.1928, -337.2877, 0, 718.856,
                         185.2157, 2.369057, 0,        0,         1, 0.004915215};
  const double tr[12] = {4.276802385584e-04,  -9.999672484946e-01, -8.084491683471e-03, -1.198459927713e-02,
                         -7.210626507497e-03, 8.081198471645e-03,  -9.999413164504e-01, -5.403984729748e-02,
                         9.999738645903e-01,  4.859485810390e-04,  -7.206933692422e-03, -2.921968648686e-01};
  Eigen::Matrix3d R;
  R << tr[0], tr[1], tr[2], tr[4], tr[5], tr[6], tr[8], tr[9], tr[10];
  c.Tr.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();  // exactly orthonormal
  c.Tr.translation() = Vec3(tr[3], tr[7], tr[11]);
  c.has_Tr = true;
  c.entries.emplace_back("Tr", std::vector<double>(tr, tr + 12));
  return c;
}

json pose_json(const Pose& p) {
  json m = json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back({p.matrix()(r, 0), p.matrix()(r, 1), p.matrix()(r, 2), p.matrix()(r, 3)});
  return m;
}

// Path points (x, y) covered between times t0 and t1, at most ~200 of them.
json path_json(const sim::Path& path, double s_begin, double s_end) {
  json pts = json::array();
  const double step = std::max(1.0, (s_end - s_begin) / 200.0);
  for (double s = s_begin; s < s_end + step; s += step) {
    const sim::PathPoint pp = path.at(std::min(s, s_end));
    pts.push_back({pp.p.x(), pp.p.y()});
  }
  return pts;
}

json describe(const SimulateArgs& a, const sim::Simulator& sim, const Pose& first) {
  const sim::World& w = sim.world();
  const double duration = a.params.frames * w.frame_period;
  json actors = json::array();
  for (const sim::Actor& x : w.actors) {
    json keys = json::array();
    for (const auto& k : x.profile.keys()) keys.push_back({k.t, k.v});
    actors.push_back({{"instance", x.instance},
                      {"kind", sim::to_string(x.kind)},
                      {"static_class", sim::static_class(x.kind)},
                      {"moving_class", sim::moving_class(x.kind)},
                      {"stop_and_go", x.stop_and_go},
                      {"dims_lwh", {x.dims.length, x.dims.width, x.dims.height}},
                      {"exists_from_s", std::max(x.t_begin, 0.0)},
                      {"exists_until_s", std::min(x.t_end, duration)},
                      {"speed_keys_t_v", keys},
                      {"path_xy", path_json(x.path, x.s0 + x.profile.distance(0.0),
                                            x.s0 + x.profile.distance(duration))}});
  }
  json statics = json::array();
  for (const sim::StaticObject& o : w.objects)
    statics.push_back({{"kind", o.kind},
                       {"instance", o.instance},
                       {"position", {o.position.x(), o.position.y(), o.position.z()}},
                       {"yaw", o.yaw},
                       {"dims_lwh", {o.dims.length, o.dims.width, o.dims.height}}});
  const auto& e = w.ego;
  const auto& s = sim.options().sensor;
  return {
      {"generator", "dloam simulate"},
      {"scenario", a.scenario},
      {"frames", a.params.frames},
      {"seed", a.params.seed},
      {"density", a.params.density},
      {"traffic", a.params.traffic},
      {"ego_speed_mps", a.params.speed()},
      {"terrain", {{"amplitude_m", w.ground.amplitude}, {"wavelength_m", w.ground.wavelength}}},
      {"sensor",
       {{"preset", s.preset},
        {"config", a.config},
        {"N_scan", s.N_scan},
        {"beam_vertical_offsets_m", s.beam_vertical_offsets_m},
        {"Horizon_SCAN", s.Horizon_SCAN},
        {"rate_hz", 10.0},
        {"min_range", s.min_range},
        {"max_range", s.max_range},
        {"mount_height_m", e.mount_height},
        {"range_noise_sigma_m", a.noise},
        {"dropout", a.dropout},
        {"rolling_shutter", true},
        {"point_time",
         "column c fires at (c + 0.5) / Horizon_SCAN of the sweep; column 0 at the rear, clockwise"}}},
      {"frames_convention",
       "poses.txt: camera frame (Tr from calib.txt), sensor pose at the middle of each sweep, relative to "
       "scan 0; world coordinates below: world = first_lidar_pose_world * lidar_pose"},
      {"first_lidar_pose_world", pose_json(first)},
      {"ego_path_xy", path_json(e.path, e.s0 + e.profile.distance(0.0), e.s0 + e.profile.distance(duration))},
      {"static_triangles", w.static_mesh.size()},
      {"actors", actors},
      {"static_objects", statics}};
}

void prepare_output(const SimulateArgs& a) {
  for (const char* sub : {"velodyne", "labels"}) {
    const fs::path dir = fs::path(a.out) / sub;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw InputError(dir.string() + ": cannot create folder (" + ec.message() + ")");
    std::vector<fs::path> old;
    for (const auto& f : fs::directory_iterator(dir))
      if (f.path().extension() == ".bin" || f.path().extension() == ".label") old.push_back(f.path());
    if (!old.empty() && !a.overwrite)
      throw InputError(dir.string() + ": already holds " + std::to_string(old.size()) +
                       " files of an earlier sequence; use --overwrite or another --out");
    for (const auto& f : old) fs::remove(f);
  }
}

void run(SimulateArgs a) {
  a.params.kind = sim::parse_scenario_kind(a.scenario);
  sim::LidarOptions lidar;
  lidar.sensor = io::config_from(a.preset, a.config).sensor;  // the preset, then the file's sensor keys
  lidar.range_noise = a.noise;
  lidar.dropout = a.dropout;
  lidar.seed = a.params.seed;
  a.params.max_range = lidar.sensor.max_range;
  sim::Simulator simulator(sim::make_world(a.params), lidar);
  prepare_output(a);

  const int n = a.params.frames;
  std::vector<Pose> poses;
  std::vector<double> times;
  std::size_t points = 0, moving = 0;
  Progress progress("simulate", static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const sim::SimFrame f = simulator.frame(i);
    const std::string name = io::scan_name(static_cast<std::size_t>(i));
    io::write_kitti_bin((fs::path(a.out) / "velodyne" / (name + ".bin")).string(), f.scan.cloud);
    io::write_labels((fs::path(a.out) / "labels" / (name + ".label")).string(), f.scan.labels);
    poses.push_back(f.pose);
    times.push_back(f.stamp);
    points += f.scan.cloud.size();
    for (Label l : f.scan.labels) moving += semantic::is_moving(l);
    progress.update(static_cast<std::size_t>(i + 1), fmt::format("{} pts", f.scan.cloud.size()));
  }
  const Pose first = poses.front();
  for (auto& p : poses) p = first.inverse() * p;  // KITTI: relative to the first scan
  const io::Calib calib = kitti_calib();
  io::write_kitti_poses((fs::path(a.out) / "poses.txt").string(), io::lidar_to_camera(poses, calib.Tr));
  io::write_calib((fs::path(a.out) / "calib.txt").string(), calib);
  io::write_times((fs::path(a.out) / "times.txt").string(), times);
  io::write_atomic((fs::path(a.out) / "scenario.json").string(),
                   [&](std::ostream& out) { out << describe(a, simulator, first).dump(1) << '\n'; });
  fmt::print("wrote {} scans to {}: {:.0f} points/scan, {:.2f} % moving, {} actors, {} static triangles\n", n,
             a.out, static_cast<double>(points) / n, 100.0 * moving / std::max<std::size_t>(points, 1),
             simulator.world().actors.size(), simulator.world().static_mesh.size());
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd =
      app.add_subcommand("simulate",
                         "Simulate a dynamic urban/highway drive with a rolling-shutter LiDAR and write a "
                         "SemanticKITTI-layout sequence with ground truth");
  cmd->add_option("--scenario", args->scenario,
                  "urban (pedestrians, stop-and-go), highway (fast traffic) or loop")
      ->check(CLI::IsMember({"urban", "highway", "loop"}, CLI::ignore_case))
      ->capture_default_str();
  cmd->add_option("--frames", args->params.frames, "Number of scans (10 Hz)")
      ->check(CLI::Range(1, 20000))
      ->capture_default_str();
  cmd->add_option("--seed", args->params.seed, "Random seed; the same seed gives the same files")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output sequence folder")->required();
  cmd->add_option("--preset", args->preset, "Sensor: " + sensor_preset_list())->capture_default_str();
  cmd->add_option("-c,--config", args->config,
                  "YAML config whose sensor section is simulated over --preset: your own beam table, "
                  "beam origin heights, range limits (e.g. config/kitti-raw.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--density", args->params.density, "Static scene density (trees, poles, parked cars), 0-5")
      ->check(CLI::Range(0.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--traffic", args->params.traffic, "Amount of moving road users relative to default, 0-10")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--speed", args->params.ego_speed,
                  "Ego speed in m/s (default: urban 7, loop 9, highway 25)")
      ->check(CLI::Range(0.0, 50.0));
  cmd->add_option("--noise", args->noise, "Range noise sigma in m")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  cmd->add_option("--dropout", args->dropout, "Probability of a lost return")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  cmd->add_option("--hills", args->params.hills,
                  "Terrain undulation amplitude in m (default: 2 city, 4 highway)")
      ->check(CLI::Range(0.0, 20.0));
  cmd->add_flag("--overwrite", args->overwrite, "Replace the scans of an earlier run in --out");
  cmd->footer(
      "Examples:\n"
      "  dloam simulate --scenario urban --frames 200 --seed 1 --out sim/urban\n"
      "  dloam simulate --scenario highway --frames 300 --traffic 2 --out sim/highway\n"
      "  dloam simulate --scenario loop --frames 1200 --preset HDL-32E --out sim/loop\n"
      "  dloam simulate --scenario urban --frames 100 --config config/kitti-raw.yaml --out sim/kitti-like\n"
      "  dloam simulate --scenario urban --frames 50 --preset VLP-16 --speed 15 --noise 0 --out sim/fast");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
