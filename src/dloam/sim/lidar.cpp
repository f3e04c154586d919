// Rolling-shutter sweep: TBB over columns, one deterministic noise stream per (seed, frame, column).
#include "dloam/sim/lidar.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace dloam::sim {

void LidarOptions::validate() const {
  sensor.validate();
  if (!(range_noise >= 0.0 && range_noise < 1.0))
    throw std::invalid_argument("lidar: range noise sigma must be in [0, 1) m");
  if (!(dropout >= 0.0 && dropout < 1.0)) throw std::invalid_argument("lidar: dropout must be in [0, 1)");
}

namespace {
struct Column {
  std::vector<Vec3> xyz;
  std::vector<float> intensity;
  std::vector<Label> labels;
  std::vector<std::uint16_t> rows;
};

float intensity_of(float reflectivity, const Vec3& normal, const Vec3& dir) {
  const double n = normal.norm();
  const double cos_inc = n > 0.0 ? std::abs(normal.dot(dir)) / n : 1.0;
  return static_cast<float>(std::clamp(reflectivity * (0.2 + 0.8 * cos_inc), 0.0, 1.0));
}
}  // namespace

Scan sweep(const World& world, const RayCaster& caster, const LidarOptions& opt, int frame) {
  const SensorConfig& s = opt.sensor;
  const int cols = s.Horizon_SCAN, rows = s.N_scan;
  // Beams in the sensor frame: origin at the beam's height (beam_vertical_offsets_m), true
  // elevation = nominal - vertical correction, so the returned points project back to their beam.
  std::vector<double> cos_el(static_cast<std::size_t>(rows)), sin_el(static_cast<std::size_t>(rows));
  std::vector<Vec3> o_local(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    const double e = (s.beam_elevation_deg(r) - s.vertical_angle_correction_deg) * M_PI / 180.0;
    cos_el[static_cast<std::size_t>(r)] = std::cos(e);
    sin_el[static_cast<std::size_t>(r)] = std::sin(e);
    o_local[static_cast<std::size_t>(r)] = Vec3(0.0, 0.0, s.beam_vertical_offset_m(r));
  }
  const float tfar = static_cast<float>(s.max_range + 6.0 * opt.range_noise);
  std::vector<Column> columns(static_cast<std::size_t>(cols));

  tbb::parallel_for(0, cols, [&](int c) {
    Column& out = columns[static_cast<std::size_t>(c)];
    const double tau = (c + 0.5) / cols;
    const double t_abs = (frame + tau) * world.frame_period;
    const Pose T = world.ego.sensor_pose(world.ground, t_abs);
    const double azimuth = M_PI - 2.0 * M_PI * tau;
    std::mt19937_64 rng(
        stream_seed(opt.seed, static_cast<std::uint64_t>(frame), static_cast<std::uint64_t>(c)));
    std::normal_distribution<double> noise(0.0, 1.0);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3> d_local(static_cast<std::size_t>(rows)), d_world(static_cast<std::size_t>(rows));
    std::vector<Vec3> o_world(static_cast<std::size_t>(rows));
    std::vector<RayCaster::Hit> hits(static_cast<std::size_t>(rows));
    for (int r = 0; r < rows; ++r) {
      const auto ru = static_cast<std::size_t>(r);
      d_local[ru] = Vec3(cos_el[ru] * std::cos(azimuth), cos_el[ru] * std::sin(azimuth), sin_el[ru]);
      d_world[ru] = T.linear() * d_local[ru];
      o_world[ru] = T * o_local[ru];
    }
    for (int r = 0; r < rows; r += RayCaster::kPacket) {
      const auto ru = static_cast<std::size_t>(r);
      const int count = std::min(RayCaster::kPacket, rows - r);
      caster.cast_packet(&o_world[ru], &d_world[ru], count, static_cast<float>(tau), 0.0f, tfar, &hits[ru]);
    }
    for (int r = 0; r < rows; ++r) {
      const auto ru = static_cast<std::size_t>(r);
      const double n = noise(rng), u = unit(rng);  // drawn for every ray: streams stay aligned
      const RayCaster::Hit& hit = hits[ru];
      if (!hit.valid() || u < opt.dropout) continue;
      const double range = hit.range + opt.range_noise * n;
      if (range < s.min_range || range > s.max_range) continue;
      Label label;
      float reflectivity;
      Vec3 normal = hit.normal.cast<double>();
      if (hit.actor < 0) {
        const Material& m = world.static_mesh.materials[hit.primitive];
        label = m.label;
        reflectivity = m.reflectivity;
      } else {
        const Actor& a = world.actors[static_cast<std::size_t>(hit.actor)];
        label = a.label(t_abs);
        reflectivity = a.mesh.materials[hit.primitive].reflectivity;
        normal = a.pose(world.ground, t_abs).linear() * normal;
      }
      out.xyz.push_back(o_local[ru] + range * d_local[ru]);
      out.intensity.push_back(intensity_of(reflectivity, normal, d_world[ru]));
      out.labels.push_back(label);
      out.rows.push_back(static_cast<std::uint16_t>(r));
    }
  });

  Scan scan;
  std::size_t total = 0;
  for (const auto& col : columns) total += col.xyz.size();
  scan.cloud.xyz.reserve(total);
  scan.cloud.intensity.reserve(total);
  scan.cloud.time.reserve(total);
  scan.labels.reserve(total);
  scan.rows.reserve(total);
  for (int c = 0; c < cols; ++c) {
    const Column& col = columns[static_cast<std::size_t>(c)];
    const float tau = static_cast<float>((c + 0.5) / cols);
    scan.cloud.xyz.insert(scan.cloud.xyz.end(), col.xyz.begin(), col.xyz.end());
    scan.cloud.intensity.insert(scan.cloud.intensity.end(), col.intensity.begin(), col.intensity.end());
    scan.cloud.time.insert(scan.cloud.time.end(), col.xyz.size(), tau);
    scan.labels.insert(scan.labels.end(), col.labels.begin(), col.labels.end());
    scan.rows.insert(scan.rows.end(), col.rows.begin(), col.rows.end());
  }
  return scan;
}

}  // namespace dloam::sim
