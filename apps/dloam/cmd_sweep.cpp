// `dloam sweep-m`: the paper's Fig. 6 — moving-object IoU of CNN models trained with different m
// (speed images in the range image bag) next to the geometric two-frame detector, on the same
// labelled sequences, each run through the whole pipeline with its own poses. Prints a table,
// writes sweep.json and sweep.png (IoU over m, one line per sequence, the geometric detector dashed).
#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/cnn/cnn_segmenter.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "gnuplot.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

using nlohmann::json;

struct SweepArgs {
  std::vector<std::string> sequences, models, configs;
  std::string out;
};

struct Entry {
  std::string name;  ///< "geometric" or the model file
  int m = -1;        ///< -1: geometric
};

eval::MosResult score(const std::string& dir, const PipelineConfig& cfg,
                      const std::shared_ptr<MovingSegmenter>& net, const std::string& label) {
  const io::Sequence seq = io::open_sequence(dir);
  if (!seq.has_labels()) throw InputError(dir + ": no labels/ folder to score against");
  Pipeline pipeline(cfg, net);
  eval::MosResult result;
  Progress bar(label, seq.size());
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const PointCloud cloud = seq.read_scan(k);
    const ScanResult r = pipeline.process(cloud);
    eval::add_scan(result, seq.read_scan_labels(k, cloud.size()), r.labels);
    bar.update(k + 1);
  }
  return result;
}

std::string plot_script(const json& rows, const std::vector<std::string>& sequences, const std::string& png,
                        const std::string& terminal) {
  std::ostringstream s;
  s << "set terminal " << terminal << " size 900,560\nset output '" << png << "'\n";
  s << "set title 'Moving-object IoU over m (paper Fig. 6)'\nset xlabel 'm (speed images in the bag)'\n"
       "set ylabel 'moving IoU (%)'\nset grid\nset key bottom right\nset yrange [0:100]\n";
  for (std::size_t q = 0; q < sequences.size(); ++q) {
    s << "$cnn" << q << " << EOD\n";
    for (const json& r : rows)
      if (r["m"].get<int>() >= 0) s << r["m"].get<int>() << ' ' << 100 * r["iou"][q].get<double>() << '\n';
    s << "EOD\n";
  }
  // The legend names a sequence by its folder (drive) name, not its whole path.
  const auto name = [](const std::string& path) {
    std::filesystem::path p = std::filesystem::path(path).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    return p.filename().empty() ? path : p.filename().string();
  };
  s << "plot ";
  for (std::size_t q = 0; q < sequences.size(); ++q) {
    double geometric = -1;
    for (const json& r : rows)
      if (r["m"].get<int>() < 0) geometric = 100 * r["iou"][q].get<double>();
    s << (q ? ", " : "") << "$cnn" << q << " using 1:2 with linespoints lw 2 lc " << q + 1 << " title 'CNN, "
      << name(sequences[q]) << "'";
    if (geometric >= 0)
      s << ", " << geometric << " with lines dt 2 lc " << q + 1 << " title 'geometric, " << name(sequences[q])
        << "'";
  }
  s << '\n';
  return s.str();
}

void run_sweep(const SweepArgs& a) {
  std::vector<PipelineConfig> cfgs;
  for (std::size_t q = 0; q < a.sequences.size(); ++q) {
    const std::string path = a.configs.empty() ? "" : a.configs[std::min(q, a.configs.size() - 1)];
    cfgs.push_back(io::config_from("HDL-64E", path));
  }
  std::vector<Entry> entries{{"geometric", -1}};
  for (const std::string& model : a.models) entries.push_back({model, 0});
  json rows = json::array();
  for (Entry& e : entries) {
    std::shared_ptr<MovingSegmenter> net;
    if (e.m >= 0) {
      net = cnn::load_cnn_segmenter(e.name, cfgs.front().detection.threads);
      e.m = net->m();
    }
    json row{{"detector", e.m < 0 ? "geometric" : "cnn"}, {"model", e.m < 0 ? "" : e.name}, {"m", e.m}};
    for (std::size_t q = 0; q < a.sequences.size(); ++q) {
      PipelineConfig cfg = cfgs[q];
      cfg.detection.detector = e.m < 0 ? Detector::kGeometric : Detector::kCnn;
      cfg.detection.m = std::max(e.m, 0);
      const eval::MosResult r =
          score(a.sequences[q], cfg, net, e.m < 0 ? "geometric" : fmt::format("m = {}", e.m));
      row["iou"].push_back(r.points.iou());
      row["precision"].push_back(r.points.precision());
      row["recall"].push_back(r.points.recall());
      row["object_iou"].push_back(r.objects.iou());
    }
    rows.push_back(row);
  }
  fmt::print("\n{:<12} {:>3}", "detector", "m");
  for (const std::string& s : a.sequences)
    fmt::print("  | {:>36}", s.size() > 36 ? s.substr(s.size() - 36) : s);
  fmt::print("\n{:<12} {:>3}", "", "");
  for (std::size_t q = 0; q < a.sequences.size(); ++q)
    fmt::print("  | {:>8} {:>8} {:>8} {:>9}", "IoU %", "P %", "R %", "obj IoU %");
  fmt::print("\n");
  for (const json& r : rows) {
    fmt::print("{:<12} {:>3}", r["detector"].get<std::string>(),
               r["m"].get<int>() < 0 ? "-" : std::to_string(r["m"].get<int>()));
    for (std::size_t q = 0; q < a.sequences.size(); ++q)
      fmt::print("  | {:8.1f} {:8.1f} {:8.1f} {:9.1f}", 100 * r["iou"][q].get<double>(),
                 100 * r["precision"][q].get<double>(), 100 * r["recall"][q].get<double>(),
                 100 * r["object_iou"][q].get<double>());
    fmt::print("\n");
  }
  if (a.out.empty()) return;
  const json doc{{"sequences", a.sequences}, {"rows", rows}};
  io::write_atomic(a.out + "/sweep.json", [&](std::ostream& o) { o << doc.dump(2) << '\n'; });
  fmt::print("wrote {}/sweep.json\n", a.out);
  render_png(a.out + "/sweep.png", [&](const std::string& tmp, const std::string& terminal) {
    return plot_script(rows, a.sequences, tmp, terminal);
  });
}

}  // namespace

void register_sweep(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand("sweep-m",
                                 "Moving-object IoU over m: CNN models vs the geometric detector (Fig. 6)");
  cmd->footer(
      "Each model (trained with `dloam train --m M`) and the geometric detector run the whole pipeline on\n"
      "every sequence; the IoU follows the SemanticKITTI MOS protocol (as `dloam eval mos`).\n"
      "Example (models/MODEL.md):\n"
      "  dloam sweep-m ../shared/data/kitti-raw-0005 sim/urban-seed1 --config "
      "config/kitti-raw.yaml,config/default.yaml\n"
      "      --models models/mos_m0.pt,models/mos_m1.pt,models/mos_m2.pt,models/mos_m6.pt --out out/sweep");
  cmd->add_option("sequences", args->sequences, "labelled sequence folders")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--models", args->models, "CNN model files (comma-separated)")->required()->delimiter(',');
  cmd->add_option("--config,-c", args->configs,
                  "config file or shipped name per sequence (comma-separated; the last one repeats)")
      ->delimiter(',')
      ->transform(config_file_validator());
  cmd->add_option("--out,-o", args->out, "folder for sweep.json and sweep.png");
  cmd->callback([args] { run_sweep(*args); });
}

}  // namespace dloam::app
