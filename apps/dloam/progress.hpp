// Progress line for long runs on stderr: a redrawn bar with rate and ETA on a terminal, a line
// every 10 % otherwise (logs, CI).
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace dloam::app {

class Progress {
 public:
  Progress(std::string label, std::size_t total)
      : label_(std::move(label)),
        total_(total),
        tty_(isatty(STDERR_FILENO) != 0),
        start_(std::chrono::steady_clock::now()) {}

  /// `done` items finished; `extra` is appended (e.g. the current speed).
  void update(std::size_t done, const std::string& extra = "") {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    const double eta = rate > 0 ? (total_ - done) / rate : 0.0;
    const int pct = total_ ? static_cast<int>(100 * done / total_) : 100;
    if (tty_) {
      constexpr int kWidth = 30;
      const int fill = total_ ? static_cast<int>(kWidth * done / total_) : kWidth;
      std::fprintf(stderr, "\r%s [%s%s] %zu/%zu %.1f/s ETA %.0fs %s\033[K", label_.c_str(),
                   std::string(static_cast<std::size_t>(fill), '#').c_str(),
                   std::string(static_cast<std::size_t>(kWidth - fill), ' ').c_str(), done, total_, rate, eta,
                   extra.c_str());
      if (done == total_) std::fprintf(stderr, "\n");
    } else if (pct >= next_pct_ || done == total_) {
      std::fprintf(stderr, "%s %3d%% (%zu/%zu) %.1f/s %s\n", label_.c_str(), pct, done, total_, rate,
                   extra.c_str());
      next_pct_ = pct / 10 * 10 + 10;
    }
    std::fflush(stderr);
  }

 private:
  std::string label_;
  std::size_t total_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  int next_pct_ = 0;
};

}  // namespace dloam::app
