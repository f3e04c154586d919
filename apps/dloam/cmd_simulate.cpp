// `dloam simulate`: renders a dynamic-scene sequence with the rolling-shutter LiDAR simulator
// (src/dloam/sim) and writes it in the SemanticKITTI layout: velodyne/*.bin, labels/*.label,
// poses.txt (camera frame, relative to the first scan, mid-sweep poses), calib.txt (KITTI
// odometry's Tr), times.txt, and scenario.json describing the parameters and the objects. With
// --keep-every / --drop only some of the simulated sweeps are written (renumbered), with their
// true start times in times.txt.
#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/thin.hpp"
#include "dloam/sim/scenario.hpp"
#include "dloam/sim/simulator.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct SimulateArgs {
  std::string scenario = "urban", out, platform = "car";
  ConfigArgs config;  ///< the YAML whose sensor section is simulated (over the preset); empty: the preset
  sim::ScenarioParams params;
  double noise = 0.02, dropout = 0.01;
  bool overwrite = false;
  io::ThinOptions thin;
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

json describe(const SimulateArgs& a, const sim::Simulator& sim, const Pose& first,
              const std::vector<std::size_t>& kept) {
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
    if (!x.role.empty()) actors.back()["role"] = x.role;
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
  json d = {
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
        {"config", a.config.config_path},
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
  // Keys of the newer options only when used: default runs describe themselves as before.
  const sim::ScenarioParams& p = a.params;
  if (p.platform != sim::Platform::Car) d["platform"] = sim::to_string(p.platform);
  if (p.swerve) d["swerve"] = true;
  if (p.brake) d["brake"] = true;
  if (p.kind == sim::ScenarioKind::Spin) d["spin_rate_deg_s"] = p.spin_rate_deg;
  if (p.cleaning_actors) d["leave_after_scans"] = p.leave_after_frames();
  if (e.body.enabled || p.brake) {
    // The ego's actual track (lateral offsets included) and speed, at 10 Hz.
    json track = json::array();
    for (int i = 0; i <= static_cast<int>(std::lround(duration * 10.0)); ++i) {
      const sim::Vec2 q = e.position(0.1 * i);
      track.push_back({0.1 * i, q.x(), q.y(), e.profile.speed(0.1 * i)});
    }
    d["ego_track_t_x_y_v"] = track;
  }
  if (kept.size() != static_cast<std::size_t>(p.frames)) {
    d["simulated_frames"] = p.frames;
    d["kept_frames"] = kept;
    d["keep_every"] = a.thin.keep_every;
    d["drop"] = a.thin.drop;
    d["drop_seed"] = a.thin.seed;
  }
  return d;
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
  a.params.platform = sim::parse_platform(a.platform);
  std::vector<std::size_t> kept;
  try {
    kept = io::select_scans(static_cast<std::size_t>(a.params.frames), a.thin);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("simulate: ") + e.what());
  }
  sim::LidarOptions lidar;
  lidar.sensor = io::config_from(a.config.preset, a.config.config_path)
                     .sensor;  // the preset, then the file's sensor keys
  lidar.range_noise = a.noise;
  lidar.dropout = a.dropout;
  lidar.seed = a.params.seed;
  a.params.max_range = lidar.sensor.max_range;
  sim::Simulator simulator(sim::make_world(a.params), lidar);
  prepare_output(a);

  const int n = static_cast<int>(kept.size());
  std::vector<Pose> poses;
  std::vector<double> times;
  std::size_t points = 0, moving = 0;
  Progress progress("simulate", static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const sim::SimFrame f = simulator.frame(static_cast<int>(kept[static_cast<std::size_t>(k)]));
    const std::string name = io::scan_name(static_cast<std::size_t>(k));
    io::write_kitti_bin((fs::path(a.out) / "velodyne" / (name + ".bin")).string(), f.scan.cloud);
    io::write_labels((fs::path(a.out) / "labels" / (name + ".label")).string(), f.scan.labels);
    poses.push_back(f.pose);
    times.push_back(f.stamp);
    points += f.scan.cloud.size();
    for (Label l : f.scan.labels) moving += semantic::is_moving(l);
    progress.update(static_cast<std::size_t>(k + 1), fmt::format("{} pts", f.scan.cloud.size()));
  }
  const Pose first = poses.front();
  for (auto& p : poses) p = first.inverse() * p;  // KITTI: relative to the first scan
  const io::Calib calib = kitti_calib();
  io::write_kitti_poses((fs::path(a.out) / "poses.txt").string(), io::lidar_to_camera(poses, calib.Tr));
  io::write_calib((fs::path(a.out) / "calib.txt").string(), calib);
  io::write_times((fs::path(a.out) / "times.txt").string(), times);
  io::write_atomic((fs::path(a.out) / "scenario.json").string(),
                   [&](std::ostream& out) { out << describe(a, simulator, first, kept).dump(1) << '\n'; });
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
                  "urban (pedestrians, stop-and-go), highway (fast traffic), loop, spin (turning on the "
                  "spot in the street), tunnel or open-field (a street, then a long tunnel / open "
                  "ground, then a street)")
      ->check(CLI::IsMember({"urban", "highway", "loop", "spin", "tunnel", "open-field"}, CLI::ignore_case))
      ->capture_default_str();
  cmd->add_option("--platform", args->platform,
                  "car; handheld (a person walking the urban street with the sensor at 1.5 m: stops, "
                  "turns on the spot and looks around up to 180 deg/s, tilts) or legged (a trotting "
                  "quadruped, sensor at 0.5 m, turns up to 90 deg/s)")
      ->check(CLI::IsMember({"car", "handheld", "legged"}, CLI::ignore_case))
      ->capture_default_str();
  cmd->add_flag("--swerve", args->params.swerve,
                "Car: lane-change swerves (lateral acceleration up to 8 m/s^2, yaw rate up to 30 deg/s)");
  cmd->add_flag("--brake", args->params.brake,
                "Car: hard braking at 8 m/s^2 to standstill, then accelerating again at 3 m/s^2");
  cmd->add_option("--spin-rate", args->params.spin_rate_deg,
                  "spin: yaw rate in deg/s (> 0 counter-clockwise), constant at every instant")
      ->check(CLI::Range(-720.0, 720.0))
      ->capture_default_str();
  cmd->add_flag("--cleaning-actors", args->params.cleaning_actors,
                "urban: add a pedestrian standing for the first half then walking away, one walking in "
                "and standing, and a parked car that drives off after --leave-after scans");
  cmd->add_option("--leave-after", args->params.leave_after,
                  "Scans the scripted parked car stands before it drives off (default: a third of --frames)")
      ->check(CLI::Range(0, 20000));
  cmd->add_option("--keep-every", args->thin.keep_every,
                  "Write only every N-th simulated scan (true start times in times.txt)")
      ->check(CLI::Range(1, 20000))
      ->capture_default_str();
  cmd->add_option("--drop", args->thin.drop, "Drop each (kept) scan with this probability")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  cmd->add_option("--drop-seed", args->thin.seed, "Seed of the --drop draws")->capture_default_str();
  cmd->add_option("--frames", args->params.frames, "Number of scans simulated (10 Hz)")
      ->check(CLI::Range(1, 20000))
      ->capture_default_str();
  cmd->add_option("--seed", args->params.seed, "Random seed; the same seed gives the same files")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output sequence folder")->required();
  ConfigHelp config_help;
  config_help.preset = "Sensor: {presets}";
  config_help.preset_default = "HDL-64E";
  config_help.config =
      "YAML config (or shipped name) whose sensor section is simulated over --preset: your own beam table, "
      "beam origin heights, range limits (e.g. kitti-raw)";
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--density", args->params.density, "Static scene density (trees, poles, parked cars), 0-5")
      ->check(CLI::Range(0.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--traffic", args->params.traffic, "Amount of moving road users relative to default, 0-10")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--speed", args->params.ego_speed,
                  "Ego speed in m/s (default: urban 7, loop 9, highway 25, tunnel and open-field 10; "
                  "mean walking speed: handheld 1.25, legged 1.5)")
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
      "  dloam simulate --scenario urban --frames 100 --config kitti-raw --out sim/kitti-like\n"
      "  dloam simulate --scenario urban --frames 50 --preset VLP-16 --speed 15 --noise 0 --out sim/fast\n"
      "  dloam simulate --scenario urban --platform handheld --frames 300 --out sim/handheld\n"
      "  dloam simulate --scenario highway --swerve --brake --frames 300 --out sim/highway-events\n"
      "  dloam simulate --scenario spin --spin-rate 90 --traffic 0 --frames 40 --out sim/spin\n"
      "  dloam simulate --scenario tunnel --frames 600 --out sim/tunnel\n"
      "  dloam simulate --scenario urban --cleaning-actors --leave-after 30 --frames 100 --out sim/cleaning\n"
      "  dloam simulate --scenario urban --frames 200 --keep-every 3 --drop 0.1 --out sim/urban-thin");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
