// libFuzzer harness: PCD files: header parsing, DATA ascii and binary, no-return points, per-point times.
#include <cstddef>
#include <cstdint>

#include "dloam/io/kitti.hpp"
#include "dloam/io/pcd.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input = dloam::fuzz::bytes(data, size);
  dloam::fuzz::expect_input_error_or_success([&] {
    dloam::io::ScanInfo info;
    const dloam::PointCloud cloud = dloam::io::parse_pcd(input, "fuzz.pcd", &info);
    if (cloud.empty() || (!info.kept.empty() && info.kept.size() != cloud.size())) __builtin_trap();
  });
  return 0;
}
