// EuRoC / ASL folders (io/euroc.cpp): mav0/*/data.csv and sensor.yaml, as one packed folder.
#include "fuzz_support.hpp"
#include "navaid/io/euroc.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto& dir = fuzz::fresh_scratch_dir();
  fuzz::unpack_folder(fuzz::as_text(data, size), dir);
  fuzz::expect_clear_errors("read_euroc", [&] { (void)io::read_euroc(dir); });
  return 0;
}
