// `dloam thin SEQUENCE --out DIR (--keep-every N | --drop P) [--seed S]`: writes a thinned copy of
// a sequence folder (every N-th scan and/or scans dropped at random) with the kept scans' true
// times, poses and labels; scan and label files are hard-linked (or copied), the input is never
// written to.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "dloam/core/types.hpp"
#include "dloam/io/thin.hpp"

namespace dloam::app {
namespace {

struct ThinArgs {
  std::string in, out;
  io::ThinOptions options;
  double scan_rate_hz = 10.0;
  bool overwrite = false;
};

void run(const ThinArgs& a) {
  if (a.options.keep_every == 1 && a.options.drop == 0.0)
    throw InputError("thin: give --keep-every N (N > 1) or --drop P (P > 0); as given, every scan is kept");
  const io::ThinResult r = io::thin_sequence(a.in, a.out, a.options, a.scan_rate_hz, a.overwrite);
  fmt::print("kept {} of {} scans of {} in {} ({}); input indices in {}/kept_scans.txt\n", r.kept.size(),
             r.input_scans, a.in, a.out, r.hard_links ? "hard links" : "copies", a.out);
}

}  // namespace

void register_thin(CLI::App& app) {
  auto args = std::make_shared<ThinArgs>();
  auto* cmd = app.add_subcommand(
      "thin",
      "Write a thinned copy of a sequence folder: every N-th scan and/or scans dropped at random, with "
      "their true times, poses and labels");
  cmd->add_option("sequence", args->in, "Sequence folder (KITTI velodyne/*.bin or PCD layout)")->required();
  cmd->add_option("--out", args->out, "Output folder (never the input or inside it)")->required();
  cmd->add_option("--keep-every", args->options.keep_every, "Keep scans 0, N, 2N, ...")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--drop", args->options.drop, "Drop each (kept) scan with this probability")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  cmd->add_option("--seed", args->options.seed, "Seed of the --drop draws (as --drop-seed of dloam simulate)")
      ->capture_default_str();
  cmd->add_option("--scan-rate", args->scan_rate_hz,
                  "Scan rate in Hz for the nominal times (scan index / rate) when the input has no times.txt")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--overwrite", args->overwrite, "Replace the scans of an earlier run in --out");
  cmd->footer(
      "Examples:\n"
      "  dloam thin ../shared/data/kitti-raw-0005 --out thin/0005-5hz --keep-every 2\n"
      "  dloam thin sim/urban --out sim/urban-lossy --drop 0.2 --seed 3");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
