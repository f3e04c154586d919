// `dloam report RUN_DIR`: the output folder of `dloam run` (or dloam_node, or the Python module's
// run()) as one self-contained HTML page (html_report.hpp).
#include <memory>
#include <string>

#include "commands.hpp"
#include "html_report.hpp"

namespace dloam::app {

void register_report(CLI::App& app) {
  struct Args {
    std::string dir, out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("report", "Write a run folder's report as one self-contained HTML page");
  cmd->add_option("RUN_DIR", args->dir, "output folder of `dloam run`")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out,-o", args->out, "HTML file (default: RUN_DIR/report.html)");
  cmd->footer(
      "The page embeds its plots (gnuplot PNGs as data URIs): the trajectory from above, coloured by its\n"
      "error when the run had ground truth; the relative error per segment length; the global map from\n"
      "above coloured by height, with the moving points; the time per scan and module; the odometry,\n"
      "MOS and run tables.\n"
      "Examples:\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005 --config kitti-raw && dloam report out/0005\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005 --config kitti-raw --report   # the same");
  cmd->callback(
      [args] { write_html_report(args->dir, args->out.empty() ? args->dir + "/report.html" : args->out); });
}

}  // namespace dloam::app
