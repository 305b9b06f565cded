// The navaid recording format (io/navaid_recording.cpp): recording.yaml, calibration.yaml, every
// stream CSV and the image folders, as one packed folder (fuzz_support.hpp, unpack_folder).
#include "fuzz_support.hpp"
#include "navaid/io/navaid_recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto& dir = fuzz::fresh_scratch_dir();
  fuzz::unpack_folder(fuzz::as_text(data, size), dir);
  fuzz::expect_clear_errors("read_navaid_recording", [&] { (void)io::read_navaid_recording(dir); });
  return 0;
}
