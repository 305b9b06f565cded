#pragma once
// Reading PCL's PCD files (ascii, binary, binary_compressed) into plain Eigen points, for the
// obstacle pipeline's tests and the CLI. PCL stays inside the implementation.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace navaid::mapping {

/// The x y z fields of a PCD file. An organized cloud (a depth camera's, height > 1) keeps its
/// row-major layout: point (col, row) is points[row * width + col], with NaN where the sensor saw
/// nothing. An unorganized cloud has height 1.
struct PcdCloud {
  std::vector<Eigen::Vector3f> points;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  bool is_dense = true;  ///< as the file says: false when it may hold non-finite points

  bool organized() const { return height > 1; }
  const Eigen::Vector3f& at(std::uint32_t col, std::uint32_t row) const { return points[row * width + col]; }
};

/// Loads a PCD file through pcl::io::loadPCDFile. Throws navaid::IoError naming the file when it
/// is missing, unreadable, truncated or corrupt, or has no x, y and z fields.
PcdCloud read_pcd_cloud(const std::filesystem::path& file);

}  // namespace navaid::mapping
