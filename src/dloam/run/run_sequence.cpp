#include "dloam/run/run_sequence.hpp"

#include <algorithm>

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

  // The sensor model must fit the data: judged on the first scan with enough points in range,
  // before the output folder is touched (a wrong --preset leaves nothing to clean up).
  SensorFitCheck fit(config.sensor);
  for (std::size_t i = first; i < last && i < first + 10 && !fit.done(); ++i) {
    PointCloud cloud;
    try {
      cloud = seq.read_scan(i);
    } catch (const InputError&) {
      break;  // the run reports it at this scan, with the outputs of the scans before it
    }
    fit.check(cloud, seq.scan_files[i]);
  }
  if (options.before_output) options.before_output();

  OutputOptions output;
  output.dir = options.out;
  if (seq.calib && seq.calib->has_Tr) output.camera_Tr = seq.calib->Tr;
  output.lengths = options.lengths;
  RunOutputs outputs(output, config);
  Pipeline pipeline(config, std::move(cnn));
  SequenceRun run;
  for (std::size_t i = first; i < last; ++i) {
    if (options.stop && options.stop()) {
      run.stopped = true;
      break;
    }
    try {
      io::ScanInfo info;
      const PointCloud cloud = seq.read_scan(i, &info);
      fit.check(cloud, seq.scan_files[i]);  // until a scan had enough points to judge by
      const std::vector<Label> gt =
          seq.has_labels() ? seq.read_scan_labels(i, cloud.size(), &info) : std::vector<Label>{};
      std::vector<std::size_t> kept;
      ScanResult r = pipeline.process(options.drop_labelled_moving ? without_moving(cloud, gt, kept) : cloud);
      if (options.drop_labelled_moving) restore_indices(r, kept, cloud.size());
      r.index = i;
      const ScanOrigin origin{seq.output_name(i), seq.scan_files[i], &info};
      const std::string warning = outputs.add(r, cloud, seq.has_labels() ? &gt : nullptr, origin);
      if (!warning.empty() && options.on_warning) options.on_warning(warning);
      if (options.on_scan) options.on_scan(outputs.scans(), last - first, r);
    } catch (const std::exception& e) {
      run.error = e.what();
      break;
    }
    if (outputs.scans() % 50 == 0) outputs.write_poses();  // an interrupted run keeps its poses
  }
  if (!run.error.empty() && outputs.scans() == 0) {  // nothing to keep: no half-written folder
    outputs.discard();
    throw InputError(run.error);
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
