// NMEA 0183 captures: sentences, checksums, epochs and fixes (io/nmea*.cpp) from one capture file.
#include "fuzz_support.hpp"
#include "navaid/io/nmea.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto file = fuzz::fresh_scratch_dir() / "capture.nmea";
  fuzz::write_file(file, fuzz::as_text(data, size));
  fuzz::expect_clear_errors("read_nmea_capture", [&] { (void)io::read_nmea_capture(file); });
  return 0;
}
