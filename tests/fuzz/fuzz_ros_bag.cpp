// ROS 1 bags (io/ros_bag.cpp on Debian's rosbag_storage): the bytes as a .bag file, its topics
// listed and the bag read with its images extracted, as navaid convert does.
#include "fuzz_support.hpp"
#include "navaid/io/ros_bag.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto dir = fuzz::fresh_scratch_dir();
  const auto file = dir / "input.bag";
  fuzz::write_file(file, fuzz::as_text(data, size));
  fuzz::expect_clear_errors("list_ros_bag_topics", [&] { (void)io::list_ros_bag_topics(file); });
  io::RosBagReadOptions options;
  options.image_folder = dir / "recording";
  fuzz::expect_clear_errors("read_ros_bag", [&] { (void)io::read_ros_bag(file, options); });
  return 0;
}
