// Kalibr calibration YAML (io/kalibr.cpp): one file read both as a camchain and as an IMU file.
#include "fuzz_support.hpp"
#include "navaid/io/kalibr.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto file = fuzz::fresh_scratch_dir() / "kalibr.yaml";
  fuzz::write_file(file, fuzz::as_text(data, size));
  fuzz::expect_clear_errors("read_kalibr_camchain", [&] { (void)io::read_kalibr_camchain(file); });
  fuzz::expect_clear_errors("read_kalibr_imu", [&] { (void)io::read_kalibr_imu(file); });
  return 0;
}
