#include "dloam/run/run_sequence.hpp"

#include <algorithm>
#include <cstdio>

#include "dloam/core/preprocess.hpp"
#include "dloam/core/range_image.hpp"

namespace dloam::run {

/// The scan without the points the ground truth labels moving: what a perfect detector would
/// leave. `kept`: input index of each remaining point.
PointCloud without_moving(const PointCloud& cloud, const std::vector<Label>& gt,
                          std::vector<std::size_t>& kept) {
  PointCloud out;
  out.stamp = cloud.stamp;
  kept.clear();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (semantic::is_moving(gt[i])) continue;
    kept.push_back(i);
    out.xyz.push_back(cloud.xyz[i]);
    if (cloud.has_intensity()) out.intensity.push_back(cloud.intensity[i]);
    if (cloud.has_time()) out.time.push_back(cloud.time[i]);
  }
  return out;
}

/// A result of the reduced scan in the input's point indices; the dropped points are moving.
void restore_indices(ScanResult& r, const std::vector<std::size_t>& kept, std::size_t input_size) {
  for (auto* idx : {&r.edge_features, &r.plane_features, &r.map_points})
    for (std::size_t& i : *idx) i = kept[i];
  if (r.labels.empty()) return;
  std::vector<Label> labels(input_size, semantic::kMovingGeneric);
  for (std::size_t j = 0; j < kept.size(); ++j) labels[kept[j]] = r.labels[j];
  r.labels = std::move(labels);
}

void check_sensor_fits(const PointCloud& cloud, const SensorConfig& sensor, const std::string& file) {
  std::size_t inside = 0, in_range = 0;
  std::vector<Vec3> points = cloud.xyz;
  correct_vertical_angle(points, sensor.vertical_angle_correction_deg);
  const BeamLookup beams(sensor);  // the rows of the range image, beam origin heights included
  for (const auto& p : points) {
    const double r = p.norm();
    if (r < sensor.min_range || r > sensor.max_range) continue;
    ++in_range;
    inside += beams.row(p) >= 0;
  }
  if (in_range > 0 && inside < 0.9 * static_cast<double>(in_range)) {
    char what[320];
    std::snprintf(
        what, sizeof(what),
        ": only %.0f%% of the points lie inside the vertical field of view of the sensor model '%s' "
        "(%d beams, %.1f .. %.1f deg): wrong --preset or sensor config? (`dloam check` estimates it)",
        100.0 * static_cast<double>(inside) / static_cast<double>(in_range), sensor.preset.c_str(),
        sensor.N_scan, sensor.beam_elevation_deg(0), sensor.beam_elevation_deg(sensor.N_scan - 1));
    throw InputError(file + what);
  }
}

SequenceRun run_sequence(const io::Sequence& seq, const PipelineConfig& config,
                         std::shared_ptr<MovingSegmenter> cnn, const RunOptions& options) {
  const std::size_t first = options.first;
  if (first >= seq.size())
    throw InputError(seq.dir + ": first scan " + std::to_string(first) + " but the sequence has " +
                     std::to_string(seq.size()) + " scans");
  if (options.drop_labelled_moving && !seq.has_labels())
    throw InputError(seq.dir +
                     ": dropping the labelled moving points needs ground-truth labels (labels/*.label)");
  const std::size_t last = options.count ? std::min(seq.size(), first + *options.count) : seq.size();

  OutputOptions output;
  output.dir = options.out;
  if (seq.calib && seq.calib->has_Tr) output.camera_Tr = seq.calib->Tr;
  output.lengths = options.lengths;
  RunOutputs outputs(output, config);
  Pipeline pipeline(config, std::move(cnn));
  std::vector<Pose> poses;
  SequenceRun run;
  for (std::size_t i = first; i < last; ++i) {
    if (options.stop && options.stop->load()) {
      run.stopped = true;
      break;
    }
    const PointCloud cloud = seq.read_scan(i);
    if (i == first) check_sensor_fits(cloud, config.sensor, seq.scan_files[i]);
    const std::vector<Label> gt =
        seq.has_labels() ? seq.read_scan_labels(i, cloud.size()) : std::vector<Label>{};
    std::vector<std::size_t> kept;
    ScanResult r = pipeline.process(options.drop_labelled_moving ? without_moving(cloud, gt, kept) : cloud);
    if (options.drop_labelled_moving) restore_indices(r, kept, cloud.size());
    r.index = i;
    outputs.add(r, cloud, seq.has_labels() ? &gt : nullptr);
    poses.push_back(r.pose);
    if (outputs.scans() % 50 == 0) outputs.write_poses(poses);  // an interrupted run keeps its poses
    if (options.on_scan) options.on_scan(outputs.scans(), last - first, r);
  }
  std::optional<std::vector<Pose>> gt;
  if (seq.has_poses()) {
    const auto gt_all = seq.lidar_poses();
    gt.emplace(gt_all.begin() + static_cast<long>(first),
               gt_all.begin() + static_cast<long>(first + outputs.scans()));
  }
  run.summary = outputs.finish(pipeline, gt ? &*gt : nullptr);
  return run;
}

}  // namespace dloam::run
