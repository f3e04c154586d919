// Full validation of a sequence folder: every file read, every problem collected.
#include "dloam/io/sequence_check.hpp"

#include <algorithm>
#include <filesystem>
#include <map>

#include "dloam/io/kitti.hpp"

namespace dloam::io {

namespace {
namespace fs = std::filesystem;

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

struct Checker {
  SequenceReport& report;
  const std::function<void(const std::string&)>& on_problem;

  void problem(const std::string& message) {
    report.problems.push_back(message);
    if (on_problem) on_problem(message);
  }
  /// Runs `f`, turning an InputError into a reported problem; false if it failed.
  template <class F>
  bool attempt(F&& f) {
    try {
      f();
      return true;
    } catch (const InputError& e) {
      problem(e.what());
    }
    return false;
  }
};

constexpr std::size_t kEstimateScans = 12;

/// Point counts, time channels, and the scans kept for the sensor estimate (spread evenly).
struct ScanStats {
  std::vector<std::size_t> keep;  ///< scan indices kept for the estimate
  std::vector<std::vector<Vec3>> kept;
  std::size_t total = 0;
  explicit ScanStats(std::size_t scans) : keep(spread_scan_indices(0, scans, kEstimateScans)) {}
  void add(std::size_t index, const PointCloud& cloud, SequenceReport& r) {
    r.min_points = r.scans_ok == 0 ? cloud.size() : std::min(r.min_points, cloud.size());
    r.max_points = std::max(r.max_points, cloud.size());
    total += cloud.size();
    ++r.scans_ok;
    if (cloud.has_time()) ++r.points_with_time;
    if (std::binary_search(keep.begin(), keep.end(), index)) kept.push_back(cloud.xyz);
  }
  void finish(SequenceReport& r) const {
    if (r.scans_ok > 0) r.mean_points = static_cast<double>(total) / static_cast<double>(r.scans_ok);
  }
  /// After the times are known.
  void estimate(SequenceReport& r, const std::vector<double>& times,
                const SensorEstimationConfig& config) const {
    if (kept.empty()) {
      r.sensor_error = "no readable scan";
      return;
    }
    try {
      r.sensor = estimate_sensor_model(kept, times, config);
    } catch (const InputError& e) {
      r.sensor_error = e.what();
    }
  }
};

/// A recording (bag, capture): every scan read through its source, stamps as times.
void check_file_sequence(const std::string& path, const InputOptions& input, SequenceReport& r, Checker& c,
                         const SensorEstimationConfig& estimation) {
  Sequence seq;
  if (!c.attempt([&] { seq = open_sequence(path, input); })) return;
  r.scans = seq.size();
  r.scan_format = seq.sensor ? "decoded" : "PointCloud2";
  r.recording_sensor = seq.sensor;
  ScanStats stats(seq.size());
  for (std::size_t i = 0; i < seq.size(); ++i) c.attempt([&] { stats.add(i, seq.read_scan(i), r); });
  stats.finish(r);
  stats.estimate(r, seq.times, estimation);
  if (seq.source) r.source = seq.source->describe();
  r.has_times = !seq.times.empty();
  r.time_count = seq.times.size();
  if (r.has_times) {
    r.first_time = seq.times.front();
    r.last_time = seq.times.back();
  }
}

void check_scans_and_labels(const SequenceFiles& files, SequenceReport& r, Checker& c, ScanStats& stats) {
  std::map<std::string, std::size_t> points_of;  // scan stem -> points, readable scans only
  for (std::size_t i = 0; i < files.scan_files.size(); ++i) {
    const std::string& path = files.scan_files[i];
    c.attempt([&] {
      const PointCloud cloud = read_scan_file(path);
      points_of[stem(path)] = cloud.size();
      stats.add(i, cloud, r);
    });
  }
  stats.finish(r);

  r.has_labels = files.has_label_dir;
  if (!files.has_label_dir) return;
  r.label_files = files.label_files.size();
  if (files.label_files.size() != files.scan_files.size())
    c.problem(files.dir + "/labels: has " + std::to_string(files.label_files.size()) +
              " .label files but there are " + std::to_string(files.scan_files.size()) + " scans");
  std::map<std::string, bool> labelled;
  for (const auto& path : files.label_files) {
    labelled[stem(path)] = true;
    const auto it = points_of.find(stem(path));
    if (it == points_of.end()) {
      const bool scan_exists = std::any_of(files.scan_files.begin(), files.scan_files.end(),
                                           [&](const std::string& s) { return stem(s) == stem(path); });
      if (!scan_exists) c.problem(path + ": no scan with the same name");
      continue;  // an unreadable scan was already reported
    }
    c.attempt([&] {
      for (const Label l : read_labels(path, it->second)) {
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
    c.attempt([&] {
      calib = read_calib(files.calib_file);
      r.calib_has_Tr = calib->has_Tr;
      for (const auto& entry : calib->entries) r.calib_keys.push_back(entry.first);
    });
  }
  r.has_poses = !files.poses_file.empty();
  if (r.has_poses) {
    c.attempt([&] {
      std::vector<Pose> poses = read_kitti_poses(files.poses_file);
      r.pose_count = poses.size();
      if (poses.size() != n)
        c.problem(files.poses_file + ": has " + std::to_string(poses.size()) + " poses but there are " +
                  std::to_string(n) + " scans");
      if (calib && calib->has_Tr) poses = camera_to_lidar(poses, calib->Tr);
      for (std::size_t i = 1; i < poses.size(); ++i)
        r.path_length_m += (poses[i].translation() - poses[i - 1].translation()).norm();
    });
  }
  r.has_times = !files.times_file.empty();
  if (r.has_times) {
    c.attempt([&] {
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
}
}  // namespace

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
  SequenceReport report;
  report.dir = dir;
  Checker checker{report, on_problem};
  if (is_recording(dir) || !input.topic.empty()) {
    check_file_sequence(dir, input, report, checker, estimation);
    return report;
  }
  SequenceFiles files;
  if (!checker.attempt([&] { files = list_sequence_files(dir); })) return report;
  report.scans = files.scan_files.size();
  report.scan_format = fs::path(files.scan_files.front()).extension() == ".pcd" ? "PCD" : "KITTI .bin";
  ScanStats stats(files.scan_files.size());
  check_scans_and_labels(files, report, checker, stats);
  std::vector<double> times;
  check_text_files(files, report, checker, times);
  stats.estimate(report, times, estimation);
  return report;
}

}  // namespace dloam::io
