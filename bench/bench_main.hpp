// main() of every benchmark: the process memory policy of the dloam tool (run/process_memory.hpp),
// so that a benchmark measures what `dloam` does, then Google Benchmark's own main.
#pragma once

#include <benchmark/benchmark.h>

#include "dloam/run/process_memory.hpp"

#define DLOAM_BENCHMARK_MAIN()                                        \
  int main(int argc, char** argv) {                                   \
    dloam::run::reuse_freed_memory();                                 \
    benchmark::Initialize(&argc, argv);                               \
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1; \
    benchmark::RunSpecifiedBenchmarks();                              \
    benchmark::Shutdown();                                            \
    return 0;                                                         \
  }
