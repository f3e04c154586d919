// The moving-object CNN (LibTorch): forward shape and determinism, save / load round trip and bad
// model files, and the shipped model end to end in the pipeline on a short simulated drive whose
// seed was never used for training (models/MODEL.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "dloam/cnn/cnn_segmenter.hpp"
#include "dloam/cnn/mos_net.hpp"
#include "dloam/cnn/torch_util.hpp"
#include "dloam/cnn/trainer.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "sim_test_util.hpp"

using namespace dloam;
namespace fs = std::filesystem;

namespace {

std::string temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "dloam_test_cnn";
  fs::create_directories(dir);
  return (dir / name).string();
}

/// A tiny simulated drive in the SemanticKITTI layout (its own labels and poses).
fs::path write_tiny_drive(const std::string& name, int frames, const SensorConfig& sensor) {
  const fs::path dir = temp_path(name);
  fs::remove_all(dir);
  fs::create_directories(dir / "velodyne");
  fs::create_directories(dir / "labels");
  sim::Simulator simulator = test::make_simulator(sim::ScenarioKind::Urban, frames, 4, sensor, 3.0);
  std::vector<Pose> poses;
  for (int k = 0; k < frames; ++k) {
    const sim::SimFrame f = simulator.frame(k);
    const std::string scan = io::scan_name(static_cast<std::size_t>(k));
    io::write_kitti_bin((dir / "velodyne" / (scan + ".bin")).string(), f.scan.cloud);
    io::write_labels((dir / "labels" / (scan + ".label")).string(), f.scan.labels);
    poses.push_back(f.pose);
  }
  io::write_kitti_poses((dir / "poses.txt").string(), poses);
  return dir;
}

std::size_t moving_targets(const cnn::MosSequence& seq) {
  std::size_t n = 0;
  for (const cnn::MosFrame& f : seq.frames)
    n += static_cast<std::size_t>(std::count(f.target.begin(), f.target.end(), cnn::kTargetMoving));
  return n;
}

}  // namespace

TEST(MosNet, OutputHasOneLogitPerPixelForAnyImageSize) {
  torch::manual_seed(3);
  cnn::MosNet net(cnn::MosNetOptions{2, 8});
  net->eval();
  torch::NoGradGuard no_grad;
  for (auto [h, w] : {std::pair{64, 2048}, {16, 1800}, {32, 100}}) {
    const torch::Tensor y = cnn::forward_padded(net, torch::rand({1, 7, h, w}));
    EXPECT_EQ(y.sizes(), (std::vector<int64_t>{1, 1, h, w}));
  }
}

TEST(MosNet, ForwardIsDeterministicAndSurvivesSaveLoad) {
  torch::manual_seed(5);
  cnn::MosNet net(cnn::MosNetOptions{6, 8});
  net->eval();
  EXPECT_GT(cnn::parameter_count(net), 10000);
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::rand({1, 11, 64, 256});
  const torch::Tensor a = net->forward(x), b = net->forward(x);
  EXPECT_TRUE(torch::equal(a, b));
  const std::string path = temp_path("roundtrip.pt");
  cnn::save_mos_net(net, path);
  cnn::MosNet loaded = cnn::load_mos_net(path);
  loaded->eval();
  EXPECT_EQ(loaded->options.m, 6);
  EXPECT_EQ(loaded->options.width, 8);
  EXPECT_TRUE(torch::equal(a, loaded->forward(x)));
  // A freshly initialised network with another seed differs: the weights really were loaded.
  torch::manual_seed(6);
  cnn::MosNet other(cnn::MosNetOptions{6, 8});
  other->eval();
  EXPECT_FALSE(torch::equal(a, other->forward(x)));
}

TEST(MosNet, BadModelFilesAreNamedInTheError) {
  const std::string missing = temp_path("missing.pt");
  fs::remove(missing);
  try {
    cnn::load_mos_net(missing);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  const std::string junk = temp_path("junk.pt");
  std::ofstream(junk) << "not a model";
  EXPECT_THROW(cnn::load_mos_net(junk), InputError);
  cnn::MosNet net(cnn::MosNetOptions{2, 8});
  const std::string m2 = temp_path("m2.pt");
  cnn::save_mos_net(net, m2);
  EXPECT_THROW(cnn::load_cnn_segmenter(m2, 1, 6), InputError);  // config m = 6, model m = 2
}

TEST(MosNet, AutoUsesTheCnnOnlyForTheRangeImageSizeItWasTrainedOnAndOnACar) {
  // A model records the size of its training range images; "auto" takes the CNN only for a
  // sensor of that size, and only on a car (the model learnt from car drives; on 12 simulated
  // handheld and legged walks the geometric detector tracked more steps on 11). The shipped model
  // (64 x 2048 simulated HDL-64E drives) made a VLP-16's odometry worse than no detector: t_rel
  // 0.183 -> 0.227 %, MOS IoU 20 % on 10 traffic drives.
  cnn::MosNet net(cnn::MosNetOptions{2, 8, 64, 2048});
  const std::string path = temp_path("m2_64x2048.pt");
  cnn::save_mos_net(net, path);
  const cnn::MosNetOptions o = cnn::read_mos_net_options(path);
  EXPECT_EQ(o.m, 2);
  EXPECT_EQ(o.trained_rows, 64);
  EXPECT_EQ(o.trained_cols, 2048);

  DetectionConfig d;
  d.detector = Detector::kAuto;
  d.m = 2;
  d.model_path = path;
  std::string note;
  EXPECT_NE(cnn::prepare_detector(d, "", sensor_preset("HDL-64E"), "car", &note), nullptr);
  EXPECT_EQ(d.detector, Detector::kCnn);
  EXPECT_TRUE(note.empty()) << note;

  d.detector = Detector::kAuto;
  EXPECT_EQ(cnn::prepare_detector(d, "", sensor_preset("VLP-16"), "car", &note), nullptr);
  EXPECT_EQ(d.detector, Detector::kGeometric);
  EXPECT_NE(note.find("16 x 1800"), std::string::npos) << note;

  d.detector = Detector::kCnn;  // asked for: used, with a warning
  note.clear();
  EXPECT_NE(cnn::prepare_detector(d, "", sensor_preset("VLP-16"), "car", &note), nullptr);
  EXPECT_NE(note.find("warning"), std::string::npos) << note;

  // A model of the sensor's size, on a walk: auto takes the geometric detector and says why; cnn
  // asked for is used.
  for (const char* platform : {"handheld", "legged"}) {
    d.detector = Detector::kAuto;
    note.clear();
    EXPECT_EQ(cnn::prepare_detector(d, "", sensor_preset("HDL-64E"), platform, &note), nullptr) << platform;
    EXPECT_EQ(d.detector, Detector::kGeometric) << platform;
    EXPECT_NE(note.find(std::string("on a ") + platform + " platform"), std::string::npos) << note;
    d.detector = Detector::kCnn;
    note.clear();
    EXPECT_NE(cnn::prepare_detector(d, "", sensor_preset("HDL-64E"), platform, &note), nullptr) << platform;
    EXPECT_EQ(d.detector, Detector::kCnn) << platform;
    EXPECT_TRUE(note.empty()) << note;
    // The Pipeline handed a segmenter resolves auto the same way.
    PipelineConfig cfg;
    cfg.motion = motion_preset(platform);
    EXPECT_EQ(Pipeline(cfg, cnn::load_cnn_segmenter(path, 1, 2)).config().detection.detector,
              Detector::kGeometric);
  }
  EXPECT_EQ(Pipeline(PipelineConfig{}, cnn::load_cnn_segmenter(path, 1, 2)).config().detection.detector,
            Detector::kCnn);  // on a car (the default platform)

  // The shipped model records its training size.
  const cnn::MosNetOptions shipped =
      cnn::read_mos_net_options(cnn::resolve_model_path(DetectionConfig{}, DLOAM_MODEL_DIR));
  EXPECT_EQ(shipped.trained_rows, 64);
  EXPECT_EQ(shipped.trained_cols, 2048);
}

// The shipped model in the whole pipeline on a simulated urban drive (seed 2: not a training seed;
// scans 50-79, where cars pass; the first m scans of a run are the two-frame detector's, the CNN's
// after them are scored).
TEST(CnnPipeline, ShippedModelSegmentsMovingObjectsOfAnUnseenSimulatedDrive) {
  PipelineConfig cfg;
  cfg.detection.detector = Detector::kCnn;
  const std::string model = cnn::resolve_model_path(cfg.detection, DLOAM_MODEL_DIR);
  ASSERT_TRUE(fs::exists(model)) << model;
  constexpr int kFrames = 80;
  sim::Simulator simulator = test::make_simulator(sim::ScenarioKind::Urban, kFrames, 2, cfg.sensor);
  Pipeline pipeline(cfg, cnn::load_cnn_segmenter(model, 2, cfg.detection.m));
  eval::MosResult mos;
  for (int k = 50; k < kFrames; ++k) {
    const sim::SimFrame f = simulator.frame(k);
    const ScanResult r = pipeline.process(f.scan.cloud);
    if (k > 50 + cfg.detection.m) eval::add_scan(mos, f.scan.labels, r.labels);  // the CNN's own scans
  }
  const double iou = mos.points.iou();
  std::printf(
      "CNN on simulated urban seed 2, scans %d-79: IoU %.1f %% (P %.1f %%, R %.1f %%), objects %.1f %%\n",
      51 + cfg.detection.m, 100 * iou, 100 * mos.points.precision(), 100 * mos.points.recall(),
      100 * mos.objects.iou());
  ASSERT_GT(mos.points.tp + mos.points.fn, 1000u);
  EXPECT_GT(iou, 0.75);
}

// The CNN pipeline from the first scan of a highway drive with lanes of co-moving cars: the first
// bags lack speed images, and when the CNN decided them it found half the cars at scan 1, the
// odometry locked onto the traffic (0.23 m instead of 2.5 m per scan) and never recovered.
TEST(CnnPipeline, FirstScansOfAHighwayDriveDoNotLockOntoTraffic) {
  PipelineConfig cfg;
  cfg.detection.detector = Detector::kCnn;
  const std::string model = cnn::resolve_model_path(cfg.detection, DLOAM_MODEL_DIR);
  ASSERT_TRUE(fs::exists(model)) << model;
  // The world of `dloam simulate --scenario highway --frames 100 --seed 2 --traffic 3`.
  sim::Simulator simulator = test::make_simulator(sim::ScenarioKind::Highway, 100, 2, cfg.sensor, 3.0);
  Pipeline pipeline(cfg, cnn::load_cnn_segmenter(model, 2, cfg.detection.m));
  const auto [err, gt_rel] = test::track(pipeline, simulator, 20);
  std::printf("CNN pipeline, 20 highway scans, %.1f m: end-point error %.3f m\n", gt_rel.translation().norm(),
              err.translation().norm());
  EXPECT_GT(gt_rel.translation().norm(), 40.0);
  EXPECT_LT(err.translation().norm(), 0.01 * gt_rel.translation().norm());
}

// `dloam train`'s loop on a tiny simulated sequence written to disk in the SemanticKITTI layout:
// data preparation, every m (including 0 and 1), validation and checkpoints.
TEST(MosTrainer, TrainsAndCheckpointsOnATinySimulatedSequence) {
  const SensorConfig sensor = sensor_preset("HDL-32E");
  const fs::path dir = write_tiny_drive("tiny_seq", 8, sensor);
  const cnn::MosSequence seq = cnn::load_mos_sequence(dir.string(), sensor);
  ASSERT_EQ(seq.frames.size(), 8u);
  for (int m : {0, 1, 3}) {
    cnn::TrainOptions o;
    o.m = m;
    o.epochs = 2;
    o.batch = 2;
    o.crop_cols = 256;
    o.val_fraction = 0.25;
    o.threads = 1;
    o.out = temp_path("tiny_m" + std::to_string(m) + ".pt");
    const auto reports = cnn::train_mos_net({seq}, sensor, o);
    ASSERT_EQ(reports.size(), 2u);
    EXPECT_TRUE(std::isfinite(reports[1].train_loss));
    EXPECT_GE(reports[1].val_iou, 0.0);
    EXPECT_EQ(cnn::load_mos_net(o.out)->options.m, m);
    EXPECT_TRUE(fs::exists(o.out + ".last"));
    EXPECT_TRUE(fs::exists(o.out + ".csv"));
  }
}

TEST(MosDataset, ASourceSpecNamesItsRunFolderWeightAndSensorConfig) {
  const cnn::MosSource plain = cnn::parse_mos_source("drives/a");
  EXPECT_EQ(plain.dir, "drives/a");
  EXPECT_TRUE(plain.run_dir.empty());
  EXPECT_EQ(plain.weight, 1.0);
  const cnn::MosSource full = cnn::parse_mos_source("real/k,run=out/k,weight=2.5,config=kitti-raw");
  EXPECT_EQ(full.dir, "real/k");
  EXPECT_EQ(full.run_dir, "out/k");
  EXPECT_EQ(full.weight, 2.5);
  EXPECT_EQ(full.config, "kitti-raw");
  for (const char* bad : {",run=x", "a,run", "a,run=", "a,colour=red", "a,weight=0", "a,weight=-1",
                          "a,weight=2x", "a,weight=nan", "a,weight=1e9"}) {
    try {
      (void)cnn::parse_mos_source(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

// A real drive labelled by `dloam run --clean`: the run's clean/labels and poses.txt are trained
// on, never the folder's own labels/ (which may be the annotation that is only for scoring).
TEST(MosDataset, ARunFolderSuppliesTheLabelsAndPosesInsteadOfTheSequencesOwn) {
  const SensorConfig sensor = sensor_preset("HDL-32E");
  const fs::path dir = write_tiny_drive("drive_with_run", 4, sensor);
  const cnn::MosSequence own = cnn::load_mos_sequence(dir.string(), sensor);
  ASSERT_GT(moving_targets(own), 100u) << "the drive needs moving points for this test";

  const fs::path run = temp_path("drive_run");
  fs::remove_all(run);
  fs::create_directories(run / "clean" / "labels");
  std::vector<Pose> run_poses;
  for (int k = 0; k < 4; ++k) {
    const std::string scan = io::scan_name(static_cast<std::size_t>(k));
    const PointCloud cloud = io::read_kitti_bin((dir / "velodyne" / (scan + ".bin")).string());
    io::write_labels((run / "clean" / "labels" / (scan + ".label")).string(),
                     std::vector<Label>(cloud.size(), semantic::kStatic));
    run_poses.push_back(own.frames[static_cast<std::size_t>(k)].pose *
                        exp_se3((Vec6() << 0, 0, 0, 0.5, 0, 0).finished()));
  }
  io::write_kitti_poses((run / "poses.txt").string(), run_poses);

  cnn::MosSource source{dir.string(), run.string(), 2.0, {}};
  const cnn::MosSequence relabelled = cnn::load_mos_sequence(source, sensor);
  ASSERT_EQ(relabelled.frames.size(), 4u);
  EXPECT_EQ(moving_targets(relabelled), 0u);
  EXPECT_EQ(relabelled.weight, 2.0);
  EXPECT_NEAR((relabelled.frames[2].pose.translation() - run_poses[2].translation()).norm(), 0.0, 1e-6);

  // A missing label file, and poses of another drive, are named.
  fs::remove(run / "clean" / "labels" / (io::scan_name(3) + ".label"));
  try {
    (void)cnn::load_mos_sequence(source, sensor);
    ADD_FAILURE() << "a missing clean label file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("000003.label"), std::string::npos) << e.what();
  }
  run_poses.pop_back();
  io::write_kitti_poses((run / "poses.txt").string(), run_poses);
  try {
    (void)cnn::load_mos_sequence(source, sensor);
    ADD_FAILURE() << "a poses.txt of 3 poses for 4 scans was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("poses.txt"), std::string::npos) << e.what();
  }
}

// A source of weight w is drawn w times per epoch: the epoch's steps scale with it.
TEST(MosTrainer, ASourcesWeightScalesItsDrawsPerEpoch) {
  const SensorConfig sensor = sensor_preset("HDL-32E");
  const fs::path dir = write_tiny_drive("drive_weighted", 6, sensor);
  cnn::MosSequence seq = cnn::load_mos_sequence(dir.string(), sensor);
  cnn::TrainOptions o;
  o.m = 1;
  o.epochs = 1;
  o.batch = 1;
  o.crop_cols = 128;
  o.val_fraction = 0.0;
  o.threads = 1;
  o.out = temp_path("weighted.pt");
  // The steps of every epoch of a training with weight w.
  auto steps_with_weight = [&](double w, int epochs) {
    seq.weight = w;
    o.epochs = epochs;
    std::vector<std::size_t> steps(static_cast<std::size_t>(epochs), 0);
    cnn::TrainCallbacks cb;
    cb.on_step = [&](int epoch, std::size_t, std::size_t n, double) {
      steps[static_cast<std::size_t>(epoch - 1)] = n;
    };
    (void)cnn::train_mos_net({seq}, sensor, o, cb);
    return steps;
  };
  EXPECT_EQ(steps_with_weight(1.0, 1), std::vector<std::size_t>{6});
  EXPECT_EQ(steps_with_weight(3.0, 1), std::vector<std::size_t>{18});
  // Half the frames on average, a different draw each epoch.
  const std::vector<std::size_t> half = steps_with_weight(0.5, 16);
  const double mean = static_cast<double>(std::accumulate(half.begin(), half.end(), std::size_t{0})) / 16.0;
  EXPECT_GT(mean, 2.0);
  EXPECT_LT(mean, 4.0);
  EXPECT_GT(*std::max_element(half.begin(), half.end()), *std::min_element(half.begin(), half.end()));
  // Another range-image size than the network's is refused.
  seq.weight = 1.0;
  EXPECT_THROW((void)cnn::train_mos_net({seq}, sensor_preset("VLP-16"), o), std::invalid_argument);
}

// Folding the batch norms into the convolutions for inference gives the same logits.
TEST(MosNet, FoldingTheBatchNormsForInferenceKeepsTheOutput) {
  torch::manual_seed(5);
  cnn::MosNet net(cnn::MosNetOptions{2, 8});
  {
    torch::NoGradGuard no_grad;  // running statistics and affine parameters far from the defaults
    for (const auto& module : net->modules(false))
      if (auto* c = dynamic_cast<cnn::ConvBnImpl*>(module.get())) {
        c->bn->running_mean.uniform_(-0.5, 0.5);
        c->bn->running_var.uniform_(0.2, 3.0);
        c->bn->weight.uniform_(0.5, 1.5);
        c->bn->bias.uniform_(-0.3, 0.3);
      }
  }
  net->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::rand({1, 7, 64, 512});
  const torch::Tensor before = net->forward(x);
  net->prepare_for_inference();
  const torch::Tensor after = net->forward(x.contiguous(torch::MemoryFormat::ChannelsLast));
  EXPECT_LT((after - before).abs().max().item<float>(), 1e-3f * before.abs().max().item<float>() + 1e-4f);
  EXPECT_GT(before.abs().max().item<float>(), 0.1f);
  net->train();
  EXPECT_THROW((void)net->forward(x), std::logic_error);
}

// The network on overlapping column parts in parallel gives the full pass's logits: the overlap
// covers the receptive field, and a change beyond it does not reach a logit.
TEST(MosNet, AForwardPassInPartsEqualsTheFullPass) {
  torch::manual_seed(7);
  cnn::MosNet net(cnn::MosNetOptions{2, 8});
  net->prepare_for_inference();
  torch::NoGradGuard no_grad;
  for (const int cols : {2048, 1800, 1024}) {
    const torch::Tensor x = torch::rand({1, 7, 64, cols});
    const torch::Tensor full = cnn::forward_padded(net, x);
    for (const int parts : {2, 3}) {
      const torch::Tensor split = cnn::forward_in_parts(net, x, parts);
      ASSERT_EQ(split.sizes(), full.sizes());
      EXPECT_LT((split - full).abs().max().item<float>(), 1e-4f) << cols << " columns, " << parts << " parts";
    }
  }
  // The receptive field: a change of column 1000 moves logits within the overlap of it, not beyond.
  const torch::Tensor x = torch::rand({1, 7, 64, 2048});
  torch::Tensor y = x.clone();
  y.select(3, 1000).add_(5.0);
  const torch::Tensor diff =
      (cnn::forward_padded(net, y) - cnn::forward_padded(net, x)).abs().amax({0, 1, 2});
  EXPECT_GT(diff[1000].item<float>(), 1e-3f);
  EXPECT_LT(diff.slice(0, 0, 1000 - cnn::kPartOverlapCols).max().item<float>(), 1e-6f);
  EXPECT_LT(diff.slice(0, 1000 + cnn::kPartOverlapCols + 1).max().item<float>(), 1e-6f);
}
