// TUM RGB-D folders (io/tum_rgbd.cpp): rgb.txt, depth.txt, accelerometer.txt, groundtruth.txt.
// The folder is named like a freiburg1 sequence so that the camera is known.
#include "fuzz_support.hpp"
#include "navaid/io/tum_rgbd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto dir = fuzz::fresh_scratch_dir() / "rgbd_dataset_freiburg1_xyz";
  fuzz::unpack_folder(fuzz::as_text(data, size), dir);
  fuzz::expect_clear_errors("read_tum_rgbd", [&] { (void)io::read_tum_rgbd(dir); });
  return 0;
}
