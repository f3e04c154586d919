// libFuzzer harness: Hesai angle-correction CSV files, and the check against each model.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "dloam/drivers/hesai_calibration.hpp"
#include "dloam/drivers/hesai_model.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dloam::fuzz::expect_input_error_or_success([&] {
    const auto calibration = dloam::drivers::hesai::parse_calibration(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.csv");
    for (const auto model : dloam::drivers::hesai::all_models())
      dloam::fuzz::expect_input_error_or_success(
          [&] { dloam::drivers::hesai::check_calibration(calibration, model); });
  });
  return 0;
}
