// KITTI odometry / SemanticKITTI sequence folders: velodyne/*.bin, labels/*.label,
// poses.txt, calib.txt (Tr), times.txt. Every reader throws dloam::InputError with the file's
// name and the problem; every writer writes atomically (temp file + rename), so an
// interrupted run never leaves a half-written file.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"
#include "dloam/drivers/scanner.hpp"

namespace dloam::io {

// Each reader has a parse_*() twin that takes the file's bytes and the name to put in errors
// (used by the readers themselves and by the fuzz harnesses).

/// float32 x y z intensity per point. Rejects: missing file, size not a multiple of 16,
/// empty scan, NaN/Inf values (the format has no no-return convention), a coordinate beyond
/// 1e6 m, and data that clearly has another record layout (5, 6 or 8 floats per point, float64).
PointCloud read_kitti_bin(const std::string& path);
PointCloud parse_kitti_bin(const std::string& bytes, const std::string& name);
void write_kitti_bin(const std::string& path, const PointCloud& cloud);

/// uint32 per point; `expected_points` must match the scan's point count.
std::vector<Label> read_labels(const std::string& path, std::size_t expected_points);
std::vector<Label> parse_labels(const std::string& bytes, const std::string& name,
                                std::size_t expected_points);
void write_labels(const std::string& path, const std::vector<Label>& labels);

/// calib.txt: `KEY: v1 v2 ...` lines; Tr (velodyne -> camera 0) as 12 row-major values, also
/// accepted under KITTI's object-detection name Tr_velo_to_cam. A key given twice is an error.
struct Calib {
  Pose Tr = Pose::Identity();
  bool has_Tr = false;
  std::vector<std::pair<std::string, std::vector<double>>> entries;  ///< every line, in order
};
Calib read_calib(const std::string& path);
Calib parse_calib(const std::string& text, const std::string& name);
void write_calib(const std::string& path, const Calib& calib);

/// KITTI poses: one 3x4 row-major matrix per line (a rotation; a translation within 1e9 m).
std::vector<Pose> read_kitti_poses(const std::string& path);
std::vector<Pose> parse_kitti_poses(const std::string& text, const std::string& name);
void write_kitti_poses(const std::string& path, const std::vector<Pose>& poses);

/// TUM poses: `t tx ty tz qx qy qz qw` per line, times strictly increasing.
struct StampedPose {
  double t = 0.0;
  Pose pose = Pose::Identity();
};
std::vector<StampedPose> read_tum_poses(const std::string& path);
std::vector<StampedPose> parse_tum_poses(const std::string& text, const std::string& name);
void write_tum_poses(const std::string& path, const std::vector<StampedPose>& poses);

/// times.txt: one time in seconds per line, strictly increasing.
std::vector<double> read_times(const std::string& path);
std::vector<double> parse_times(const std::string& text, const std::string& name);
void write_times(const std::string& path, const std::vector<double>& times);

/// KITTI poses live in the camera-0 frame. Sensor-frame pose = Tr^-1 * P * Tr.
std::vector<Pose> camera_to_lidar(const std::vector<Pose>& camera_poses, const Pose& Tr);
std::vector<Pose> lidar_to_camera(const std::vector<Pose>& lidar_poses, const Pose& Tr);

/// The scans of a sequence stored in one file (a rosbag: dloam_ros) instead of a file per scan.
struct ScanSource {
  virtual ~ScanSource() = default;
  [[nodiscard]] virtual PointCloud read(std::size_t i) const = 0;
  /// What is read and how, for `dloam check` / `dloam run` (e.g. the topic, dropped points).
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// What reading one scan dropped: the points without a return (NaN coordinates of an organised
/// PCD). `kept` holds the file index of every point read, and is empty when none was dropped.
struct ScanInfo {
  std::size_t file_points = 0;  ///< points in the file
  std::vector<std::size_t> kept;
  [[nodiscard]] std::size_t dropped() const { return kept.empty() ? 0 : file_points - kept.size(); }
};

/// A sequence folder. open_sequence() lists the files and checks that counts agree
/// (poses, times, labels vs scans); scans are read lazily with read_scan().
struct Sequence {
  std::string dir;
  std::vector<std::string> scan_files;  ///< velodyne/NNNNNN.bin, natural order (a source: one name per scan)
  std::shared_ptr<const ScanSource> source;  ///< single-file sequences (rosbag): read_scan() reads it
  std::vector<std::string> label_files;      ///< labels/NNNNNN.label, empty when absent
  std::optional<Calib> calib;
  std::vector<Pose> poses;            ///< poses.txt as stored (camera frame when calib has Tr), or empty
  std::vector<double> times;          ///< times.txt, or empty; recordings: the scans' stamps (s)
  std::vector<std::string> warnings;  ///< oddities that do not stop a run (e.g. a gap in the scan numbers)
  /// The sensor model a recording of raw packets gives (the vendor decoder's Scanner::sensor()):
  /// front-ends use it when neither a preset nor a config's sensor section is given.
  std::optional<SensorConfig> sensor;

  [[nodiscard]] std::size_t size() const { return scan_files.size(); }
  [[nodiscard]] bool has_labels() const { return !label_files.empty(); }
  [[nodiscard]] bool has_poses() const { return !poses.empty(); }
  /// A calib.txt without Tr beside poses.txt: the frame of the poses is unknown (KITTI poses are
  /// camera-frame). lidar_poses() refuses it; a caller that knows the poses are LiDAR-frame drops
  /// `calib`.
  [[nodiscard]] bool poses_frame_unknown() const { return has_poses() && calib && !calib->has_Tr; }
  /// Ground-truth poses of the LiDAR (Tr applied when calib has Tr). Throws InputError when
  /// poses_frame_unknown().
  [[nodiscard]] std::vector<Pose> lidar_poses() const;
  /// Scan i, with its stamp from `times` when the sequence has them; `info` (optional) receives
  /// what the reader dropped.
  [[nodiscard]] PointCloud read_scan(std::size_t i, ScanInfo* info = nullptr) const;
  /// The labels of scan i's points: `n_points` of them, or, with the ScanInfo of a scan that
  /// dropped points, the labels of the kept points out of the file's.
  [[nodiscard]] std::vector<Label> read_scan_labels(std::size_t i, std::size_t n_points,
                                                    const ScanInfo* info = nullptr) const;
  /// The name of scan i's per-scan outputs (labels/NAME.label): its file's stem ("000042", "7"),
  /// scan_name(i) for single-file sequences.
  [[nodiscard]] std::string output_name(std::size_t i) const;
};
/// How a recording is read (pcap captures, ROS 2 bags; `topic` also applies to ROS 1 bags).
struct InputOptions {
  std::string topic;        ///< bag topic; empty: the only PointCloud2 topic, else the only packet topic
  std::string calibration;  ///< Velodyne calibration YAML / Hesai angle CSV; empty: the model's nominal table
  std::string metadata;  ///< Ouster sensor metadata JSON; empty: the .json of the same name beside the file
  drivers::ScannerOptions scan;  ///< returns, cut azimuth, range limits
  std::uint16_t port = 0;  ///< pcap: UDP destination port of the data; 0: the port of the first data packet
};

/// Lists a sequence folder and checks that counts and names agree (poses, times, labels vs
/// scans); reads the small text files. Scans are KITTI .bin in velodyne/, or PCD files in
/// velodyne/ or directly in `dir`.
/// Recordings: a pcap / pcapng capture, a ROS 2 bag (a rosbag2 folder with metadata.yaml, a .db3
/// or .mcap file) of PointCloud2 or raw packets, a ROS 1 .bag (registered by dloam_ros).
Sequence open_sequence(const std::string& dir, const std::string& topic = {});
Sequence open_sequence(const std::string& dir, const InputOptions& input);

/// True when `path` is read as a recording (a file, or a rosbag2 folder), not a sequence folder.
bool is_recording(const std::string& path);

/// Opens a sequence stored in one file; `topic` as in open_sequence().
using FileSequenceOpener = std::function<Sequence(const std::string& path, const std::string& topic)>;
/// Registers the reader of single-file sequences with this extension (".bag": dloam_ros).
void register_sequence_format(const std::string& extension, FileSequenceOpener opener);

/// The files of a sequence folder, listed but not read (paths empty when absent). Throws when
/// `dir` is missing, cannot be listed or holds no scans. Used by open_sequence() and `dloam check`.
/// Files are in natural order (numbers by value: 2.bin before 10.bin). An entry with a scan's
/// extension that is not a regular file (FIFO, broken link, link loop) is listed, so that reading
/// it names the problem.
struct SequenceFiles {
  std::string dir;
  std::vector<std::string> scan_files;   ///< velodyne/*.bin, else velodyne/*.pcd, else *.pcd
  std::vector<std::string> label_files;  ///< labels/*.label; empty when labels/ is absent
  bool has_label_dir = false;
  std::string calib_file, poses_file, times_file;
  /// Scans named by numbers whose numbers skip values ("000004.bin then 000006.bin"), one
  /// description per gap; empty otherwise.
  std::vector<std::string> numbering_gaps;
};
SequenceFiles list_sequence_files(const std::string& dir);

/// Reads one scan by extension: .bin (KITTI) or .pcd; `info` as in Sequence::read_scan().
PointCloud read_scan_file(const std::string& path, ScanInfo* info = nullptr);

/// Natural order of names: runs of digits compare by value ("2" < "10"), the rest as text.
bool natural_less(const std::string& a, const std::string& b);

/// Path helpers: "<dir>/velodyne/000042.bin" etc.
std::string scan_name(std::size_t index);  ///< "000042"

}  // namespace dloam::io
