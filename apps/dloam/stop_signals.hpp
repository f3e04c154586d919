// Graceful stop of a long command: SIGINT (Ctrl-C), SIGTERM (timeout, a scheduler, docker stop)
// and SIGHUP (a closed terminal) ask it to stop after the current item and write its outputs; a
// second signal ends the process at once with the signal's default action.
#pragma once

#include <signal.h>

#include <atomic>

namespace dloam::app {

class StopSignals {
 public:
  StopSignals() {
    received_ = 0;
    struct sigaction action {};
    action.sa_handler = &StopSignals::handle;
    sigemptyset(&action.sa_mask);
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &action, &previous_[i]);
  }
  ~StopSignals() {
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &previous_[i], nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// 0, or the first signal received.
  [[nodiscard]] int received() const { return received_.load(); }
  [[nodiscard]] static const char* name(int signal) {
    return signal == SIGINT    ? "SIGINT"
           : signal == SIGTERM ? "SIGTERM"
           : signal == SIGHUP  ? "SIGHUP"
                               : "a signal";
  }

 private:
  static constexpr int kCount = 3;
  static constexpr int kSignals[kCount] = {SIGINT, SIGTERM, SIGHUP};
  static void handle(int signal) {
    int none = 0;
    if (received_.compare_exchange_strong(none, signal)) return;
    ::signal(signal, SIG_DFL);  // the second one: stop now
    ::raise(signal);
  }
  static inline std::atomic<int> received_{0};
  struct sigaction previous_[kCount] {};
};

}  // namespace dloam::app
