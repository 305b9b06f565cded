#pragma once
// Private to navaid_io: a structural check of a ROS 1 bag (format 2.0) before rosbag_storage
// reads it. rosbag_storage trusts the lengths in a bag: a header field longer than its header
// makes ros::Header::parse read past its buffer (found by fuzz_ros_bag). The check walks every
// record, decompresses every chunk and verifies every length, typed field size and index offset
// that rosbag_storage will follow; anything off is an IoError naming the bag and the byte offset.
#include <filesystem>

namespace navaid::io::detail {

void check_ros_bag_structure(const std::filesystem::path& bag);

}  // namespace navaid::io::detail
