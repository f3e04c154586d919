// Full validation of a sequence folder: every file read, every problem collected.
#include "dloam/io/sequence_check.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <new>

#include "dloam/io/kitti.hpp"

namespace dloam::io {

namespace {
namespace fs = std::filesystem;

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

struct Checker {
  SequenceReport& report;
  const CheckOptions& options;

  void problem(const std::string& message) {
    report.problems.push_back(message);
    if (options.on_problem) options.on_problem(message);
  }
  void warning(const std::string& message) {
    report.warnings.push_back(message);
    if (options.on_warning) options.on_warning(message);
  }
  /// Runs `f`, turning any exception into a reported problem about `where`; false if it failed.
  template <class F>
  bool attempt(const std::string& where, F&& f) {
    try {
      f();
      return true;
    } catch (const InputError& e) {
      problem(e.what());
    } catch (const std::bad_alloc&) {
      problem(where + ": out of memory while reading it");
    } catch (const std::exception& e) {
      problem(where + ": " + e.what());
    }
    return false;
  }
};

constexpr std::size_t kEstimateScans = 12;

/// Point counts, time channels, degenerate scans, and the scans kept for the sensor estimate
/// (spread evenly).
struct ScanStats {
  std::vector<std::size_t> keep;  ///< scan indices kept for the estimate
  std::vector<std::vector<Vec3>> kept;
  std::size_t total = 0;
  PointCloud fit_scan;  ///< the first scan with enough points to judge the sensor model by
  std::string fit_name;

  explicit ScanStats(std::size_t scans) : keep(spread_scan_indices(0, scans, kEstimateScans)) {}

  void add(std::size_t index, const PointCloud& cloud, const ScanInfo& info, const std::string& name,
           Checker& c) {
    SequenceReport& r = c.report;
    r.min_points = r.scans_ok == 0 ? cloud.size() : std::min(r.min_points, cloud.size());
    r.max_points = std::max(r.max_points, cloud.size());
    total += cloud.size();
    ++r.scans_ok;
    r.dropped_points += info.dropped();
    if (cloud.has_time()) ++r.points_with_time;
    if (std::binary_search(keep.begin(), keep.end(), index)) kept.push_back(cloud.xyz);
    if (fit_name.empty() && cloud.size() >= kMinFitPoints) {
      fit_scan = cloud;
      fit_name = name;
    }
    const std::string why = degenerate_reason(cloud, c.options);
    if (!why.empty()) {
      ++r.degenerate_scans;
      c.warning(name + ": degenerate scan (" + why + "): `dloam run` keeps the predicted motion there");
    }
  }

  static std::string degenerate_reason(const PointCloud& cloud, const CheckOptions& options) {
    if (cloud.size() < kMinScanPoints)
      return std::to_string(cloud.size()) + " point" + (cloud.size() == 1 ? "" : "s") + ", fewer than " +
             std::to_string(kMinScanPoints);
    Vec3 lo = cloud.xyz.front(), hi = cloud.xyz.front();
    for (const auto& p : cloud.xyz) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if ((hi - lo).maxCoeff() < 0.1) return "all points within 0.1 m of each other";
    if (options.sensor) {
      const auto& s = *options.sensor;
      const bool any = std::any_of(cloud.xyz.begin(), cloud.xyz.end(), [&](const Vec3& p) {
        const double r = p.norm();
        return r >= s.min_range && r <= s.max_range;
      });
      if (!any)
        return "no point between min_range " + std::to_string(s.min_range) + " and max_range " +
               std::to_string(s.max_range) + " m";
    }
    return {};
  }

  /// After the times are known: the sensor estimate, then the fit of the first full scan.
  void finish(Checker& c, const std::vector<double>& times) {
    SequenceReport& r = c.report;
    if (r.scans_ok > 0) r.mean_points = static_cast<double>(total) / static_cast<double>(r.scans_ok);
    if (kept.empty()) {
      r.sensor_error = "no readable scan";
    } else {
      try {
        r.sensor = estimate_sensor_model(kept, times, c.options.estimation);
      } catch (const InputError& e) {
        r.sensor_error = e.what();
      }
    }
    if (fit_name.empty()) return;
    SensorConfig sensor;
    if (c.options.sensor) {
      sensor = *c.options.sensor;
    } else if (r.recording_sensor) {
      sensor = *r.recording_sensor;
    } else if (r.sensor) {
      sensor = sensor_preset(nearest_preset(r.sensor->sensor).preset);
    } else {
      return;
    }
    r.fit = sensor_fit(fit_scan, sensor);
    r.fit_sensor = sensor.preset;
    const std::string fit_problem = sensor_fit_problem(*r.fit, sensor, fit_name);
    if (fit_problem.empty()) return;
    if (c.options.sensor)
      c.problem(fit_problem);
    else
      c.warning(fit_problem + " (no --preset or --config given: compared with the closest preset)");
  }
};

/// A recording (bag, capture): every scan read through its source, stamps as times.
void check_file_sequence(const std::string& path, SequenceReport& r, Checker& c) {
  Sequence seq;
  if (!c.attempt(path, [&] { seq = open_sequence(path, c.options.input); })) return;
  r.scans = seq.size();
  r.scan_format = seq.sensor ? "decoded" : "PointCloud2";
  r.recording_sensor = seq.sensor;
  ScanStats stats(seq.size());
  for (std::size_t i = 0; i < seq.size(); ++i)
    c.attempt(seq.scan_files[i], [&] {
      ScanInfo info;
      const PointCloud cloud = seq.read_scan(i, &info);
      stats.add(i, cloud, info, seq.scan_files[i], c);
    });
  stats.finish(c, seq.times);
  if (seq.source) r.source = seq.source->describe();
  r.has_times = !seq.times.empty();
  r.time_count = seq.times.size();
  if (r.has_times) {
    r.first_time = seq.times.front();
    r.last_time = seq.times.back();
  }
}

void check_scans_and_labels(const SequenceFiles& files, SequenceReport& r, Checker& c, ScanStats& stats) {
  struct Read {
    std::size_t points = 0;
    ScanInfo info;
  };
  std::map<std::string, Read> read_of;  // scan stem -> what was read, readable scans only
  for (std::size_t i = 0; i < files.scan_files.size(); ++i) {
    const std::string& path = files.scan_files[i];
    c.attempt(path, [&] {
      ScanInfo info;
      const PointCloud cloud = read_scan_file(path, &info);
      stats.add(i, cloud, info, path, c);
      read_of[stem(path)] = Read{cloud.size(), std::move(info)};
    });
  }

  r.has_labels = files.has_label_dir;
  if (!files.has_label_dir) return;
  r.label_files = files.label_files.size();
  if (files.label_files.size() != files.scan_files.size())
    c.problem(files.dir + "/labels: has " + std::to_string(files.label_files.size()) +
              " .label files but there are " + std::to_string(files.scan_files.size()) + " scans");
  std::map<std::string, bool> labelled;
  for (const auto& path : files.label_files) {
    labelled[stem(path)] = true;
    const auto it = read_of.find(stem(path));
    if (it == read_of.end()) {
      const bool scan_exists = std::any_of(files.scan_files.begin(), files.scan_files.end(),
                                           [&](const std::string& s) { return stem(s) == stem(path); });
      if (!scan_exists) c.problem(path + ": no scan with the same name");
      continue;  // an unreadable scan was already reported
    }
    c.attempt(path, [&] {
      // Labels are per point of the file, no-return points included.
      for (const Label l : read_labels(path, it->second.info.file_points)) {
        if (semantic::is_ignored(l)) {
          ++r.ignored_points;
        } else {
          ++r.labelled_points;
          if (semantic::is_moving(l)) ++r.moving_points;
        }
      }
    });
  }
  for (const auto& path : files.scan_files)
    if (!labelled.count(stem(path))) c.problem(path + ": has no label file in labels/");
}

void check_text_files(const SequenceFiles& files, SequenceReport& r, Checker& c,
                      std::vector<double>& times_out) {
  const std::size_t n = files.scan_files.size();
  std::optional<Calib> calib;
  r.has_calib = !files.calib_file.empty();
  if (r.has_calib) {
    c.attempt(files.calib_file, [&] {
      calib = read_calib(files.calib_file);
      r.calib_has_Tr = calib->has_Tr;
      for (const auto& entry : calib->entries) r.calib_keys.push_back(entry.first);
    });
  }
  r.has_poses = !files.poses_file.empty();
  if (r.has_poses) {
    c.attempt(files.poses_file, [&] {
      std::vector<Pose> poses = read_kitti_poses(files.poses_file);
      r.pose_count = poses.size();
      if (poses.size() != n)
        c.problem(files.poses_file + ": has " + std::to_string(poses.size()) + " poses but there are " +
                  std::to_string(n) + " scans");
      if (calib && !calib->has_Tr && !poses.empty())
        c.problem(files.calib_file +
                  ": has no Tr (velodyne -> camera 0), so the frame of poses.txt is unknown (KITTI poses are "
                  "camera-frame poses); add Tr, or pass --gt-frame lidar to `dloam run` when poses.txt is in "
                  "the LiDAR frame");
      if (calib && calib->has_Tr) poses = camera_to_lidar(poses, calib->Tr);
      for (std::size_t i = 1; i < poses.size(); ++i)
        r.path_length_m += (poses[i].translation() - poses[i - 1].translation()).norm();
    });
  }
  r.has_times = !files.times_file.empty();
  if (r.has_times) {
    c.attempt(files.times_file, [&] {
      const auto times = read_times(files.times_file);
      times_out = times;
      r.time_count = times.size();
      if (!times.empty()) {
        r.first_time = times.front();
        r.last_time = times.back();
      }
      if (times.size() != n)
        c.problem(files.times_file + ": has " + std::to_string(times.size()) + " times but there are " +
                  std::to_string(n) + " scans");
    });
  }
  for (const auto& gap : files.numbering_gaps) {
    const std::string paired = !files.poses_file.empty() ? files.poses_file : files.times_file;
    if (paired.empty())
      c.warning(files.dir + ": " + gap);
    else
      c.problem(paired + ": pairs with the scans by line, but the " + gap +
                ": its lines cannot be matched to the scans (fill the gap or renumber the scans)");
  }
}
}  // namespace

SequenceReport check_sequence(const std::string& dir, const CheckOptions& options) {
  SequenceReport report;
  report.dir = dir;
  Checker checker{report, options};
  if (is_recording(dir) || !options.input.topic.empty()) {
    check_file_sequence(dir, report, checker);
    return report;
  }
  SequenceFiles files;
  if (!checker.attempt(dir, [&] { files = list_sequence_files(dir); })) return report;
  report.scans = files.scan_files.size();
  report.scan_format = fs::path(files.scan_files.front()).extension() == ".pcd" ? "PCD" : "KITTI .bin";
  ScanStats stats(files.scan_files.size());
  check_scans_and_labels(files, report, checker, stats);
  std::vector<double> times;
  check_text_files(files, report, checker, times);
  stats.finish(checker, times);
  return report;
}

SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem,
                              const std::string& topic, const SensorEstimationConfig& estimation) {
  InputOptions input;
  input.topic = topic;
  return check_sequence(dir, on_problem, input, estimation);
}

SequenceReport check_sequence(const std::string& dir,
                              const std::function<void(const std::string&)>& on_problem,
                              const InputOptions& input, const SensorEstimationConfig& estimation) {
  CheckOptions options;
  options.input = input;
  options.estimation = estimation;
  options.on_problem = on_problem;
  return check_sequence(dir, options);
}

}  // namespace dloam::io
