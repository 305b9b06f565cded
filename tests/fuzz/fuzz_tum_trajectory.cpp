// TUM trajectory files (io/tum_trajectory.cpp): "t x y z qx qy qz qw" lines, read as poses and as
// a ground-truth recording.
#include "fuzz_support.hpp"
#include "navaid/io/tum_trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto file = fuzz::fresh_scratch_dir() / "trajectory.txt";
  fuzz::write_file(file, fuzz::as_text(data, size));
  fuzz::expect_clear_errors("read_tum_trajectory", [&] { (void)io::read_tum_trajectory(file); });
  fuzz::expect_clear_errors("read_tum_trajectory_recording",
                            [&] { (void)io::read_tum_trajectory_recording(file); });
  return 0;
}
