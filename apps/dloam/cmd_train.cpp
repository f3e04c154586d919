// `dloam train`: trains the moving-object CNN (src/dloam/cnn) on labelled SemanticKITTI-layout
// sequences (simulated drives from `dloam simulate`, or real ones) and writes the model that
// `dloam run --detector cnn` loads. Shows progress and losses, logs the validation IoU per epoch
// (also to MODEL.csv beside the model), keeps the best epoch.
#include <fmt/core.h>

#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/cnn/trainer.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/data_dir.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

struct TrainArgs {
  std::vector<std::string> sequences;
  ConfigArgs config;
  cnn::TrainOptions options;
};

void run_train(const TrainArgs& a) {
  const PipelineConfig cfg = io::config_from(a.config.preset, a.config.config_path);
  std::vector<cnn::MosSequence> data;
  std::size_t frames = 0;
  std::vector<cnn::MosSource> sources;
  for (const std::string& spec : a.sequences) {
    sources.push_back(cnn::parse_mos_source(spec));
    for (const std::string& path : {sources.back().dir, sources.back().run_dir})
      if (!path.empty() && !std::filesystem::exists(path))
        throw InputError("training source '" + spec + "': " + path + " does not exist");
  }
  for (const cnn::MosSource& source : sources) {
    const std::string what =
        source.run_dir.empty() ? source.dir : source.dir + " (labels of " + source.run_dir + "/clean)";
    Progress bar("load " + what, 1);
    const SensorConfig sensor =
        source.config.empty()
            ? cfg.sensor
            : io::config_from(a.config.preset, io::resolve_config_file(source.config)).sensor;
    data.push_back(cnn::load_mos_sequence(source, sensor, [&](std::size_t done, std::size_t total) {
      if (done == 1) bar = Progress("load " + what, total);
      bar.update(done);
    }));
    frames += data.back().frames.size();
  }
  const cnn::TrainOptions& o = a.options;
  fmt::print(
      "dloam train: {} sequences, {} scans, m = {}, width {}, {} epochs of batch {} x {} columns -> {}\n",
      data.size(), frames, o.m, o.width, o.epochs, o.batch, o.crop_cols, o.out);
  std::unique_ptr<Progress> bar;
  cnn::TrainCallbacks cb;
  cb.on_step = [&](int epoch, std::size_t step, std::size_t steps, double loss) {
    if (step == 1) bar = std::make_unique<Progress>(fmt::format("epoch {}/{}", epoch, o.epochs), steps);
    bar->update(step, fmt::format("loss {:.4f}", loss));
  };
  cb.on_epoch = [](const cnn::EpochReport& r) {
    fmt::print("epoch {:3d}  train loss {:.4f}  val IoU {:.1f} % (P {:.1f} %, R {:.1f} %)  {:.0f} s{}\n",
               r.epoch, r.train_loss, 100 * r.val_iou, 100 * r.val_precision, 100 * r.val_recall, r.seconds,
               r.best ? "  * best, saved" : "");
    std::fflush(stdout);
  };
  cnn::train_mos_net(data, cfg.sensor, o, cb);
  fmt::print("wrote {} (best validation IoU), {}.last, {}.csv\n", o.out, o.out, o.out);
}

}  // namespace

void register_train(CLI::App& app) {
  auto args = std::make_shared<TrainArgs>();
  auto* cmd = app.add_subcommand("train", "Train the moving-object CNN on labelled sequences");
  cmd->footer(
      "Each source is DIR[,run=RUN_DIR][,weight=W]:\n"
      "  DIR       a SemanticKITTI-layout folder with velodyne/, labels/, poses.txt (+ calib.txt),\n"
      "            e.g. a simulated drive;\n"
      "  run=      labels from RUN_DIR/clean/labels and poses from RUN_DIR/poses.txt instead, i.e. a\n"
      "            real drive labelled by `dloam run DIR --clean --out RUN_DIR`, no annotation needed;\n"
      "  weight=   each of its scans is drawn W times per epoch on average (default 1);\n"
      "  config=   the YAML config (file or shipped name) of this drive's sensor, over --preset\n"
      "            (default: --config); every source must give range images of one size.\n"
      "The last --val-fraction of every sequence is held out for validation (scored with the weights).\n"
      "Examples:\n"
      "  scripts/make_training_data.sh train/sim\n"
      "  dloam train train/sim/* --out models/mos_m6.pt --m 6 --epochs 8 --seed 1\n"
      "  dloam train train/sim/* DRIVE,run=out/drive,weight=3,config=my-sensor.yaml --out my.pt\n"
      "The shipped model's recipe: models/MODEL.md (scripts/train_models.sh main).");
  cmd->add_option("sources", args->sequences, "training sources: DIR[,run=RUN_DIR][,weight=W][,config=FILE]")
      ->required();
  cmd->add_option("--out,-o", args->options.out, "model file (best epoch)")->required();
  ConfigHelp config_help;
  config_help.config = "YAML config or shipped name (its sensor model)";
  config_help.preset_default = "HDL-64E";
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--m", args->options.m, "speed images in the range image bag")
      ->check(CLI::Range(0, 12))
      ->capture_default_str();
  cmd->add_option("--width", args->options.width, "network width")
      ->check(CLI::Range(4, 64))
      ->capture_default_str();
  cmd->add_option("--epochs", args->options.epochs)->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--batch", args->options.batch)->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--crop", args->options.crop_cols, "training crop width (columns, multiple of 16)")
      ->capture_default_str();
  cmd->add_option("--lr", args->options.learning_rate)->capture_default_str();
  cmd->add_option("--val-fraction", args->options.val_fraction)
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  cmd->add_option("--seed", args->options.seed)->capture_default_str();
  cmd->add_option("--threads", args->options.threads)->check(CLI::Range(1, 64))->capture_default_str();
  cmd->callback([args] { run_train(*args); });
}

}  // namespace dloam::app
