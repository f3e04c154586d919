// Per-scan, per-module wall-clock timing (ms) of the pipeline, for timing.csv and the report.
#pragma once

#include <array>
#include <chrono>
#include <string_view>

namespace dloam {

enum class Module {
  kDeskew,
  kSegmentation,
  kStepCheck,
  kDetection,
  kFeatures,
  kOdometry,
  kMapping,
  kTotal,
  kCount
};
inline constexpr std::array<std::string_view, static_cast<std::size_t>(Module::kCount)> kModuleNames = {
    "deskew", "segmentation", "step_check", "detection", "features", "odometry", "mapping", "total"};

struct ModuleTimes {
  std::array<double, static_cast<std::size_t>(Module::kCount)> ms{};
  double& operator[](Module m) { return ms[static_cast<std::size_t>(m)]; }
  double operator[](Module m) const { return ms[static_cast<std::size_t>(m)]; }
};

/// Adds the elapsed time to `times[m]` when it goes out of scope.
class ScopedTimer {
 public:
  ScopedTimer(ModuleTimes& times, Module m)
      : times_(times), m_(m), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    times_[m_] +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  ModuleTimes& times_;
  Module m_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dloam
