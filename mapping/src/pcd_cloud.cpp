#include "navaid/mapping/pcd_cloud.hpp"

#include <algorithm>
#include <exception>
#include <string>
#include <system_error>

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "navaid/core/errors.hpp"

namespace navaid::mapping {
namespace {

bool has_field(const pcl::PCLPointCloud2& c, const std::string& name) {
  return std::any_of(c.fields.begin(), c.fields.end(), [&](const pcl::PCLPointField& f) { return f.name == name; });
}

}  // namespace

PcdCloud read_pcd_cloud(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw IoError(name, "no such PCD file");
  pcl::PCLPointCloud2 blob;
  int status = -1;
  try {
    // PCL 1.13's reader dereferences past the end when the header declares no fields or no points
    // (garbage, an empty file): check the header first.
    pcl::PCDReader reader;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0, data_type = 0;
    unsigned int data_index = 0;
    if (reader.readHeader(name, blob, origin, orientation, version, data_type, data_index) < 0 || blob.fields.empty())
      throw IoError(name, "not a PCD file (no FIELDS in the header)");
    if (static_cast<std::size_t>(blob.width) * blob.height == 0) throw IoError(name, "PCD file holds no points");
    status = reader.read(name, blob);
  } catch (const IoError&) {
    throw;
  } catch (const pcl::PCLException& e) {
    throw IoError(name, std::string("corrupt PCD file: ") + e.what());
  } catch (const std::exception& e) {
    throw IoError(name, std::string("corrupt PCD file: ") + e.what());
  }
  if (status < 0) throw IoError(name, "corrupt or truncated PCD file (PCL's reader failed, code " + std::to_string(status) + ")");
  for (const char* axis : {"x", "y", "z"})
    if (!has_field(blob, axis)) throw IoError(name, std::string("PCD file has no '") + axis + "' field");
  if (static_cast<std::size_t>(blob.width) * blob.height * blob.point_step != blob.data.size())
    throw IoError(name, "PCD data size does not match WIDTH x HEIGHT points");

  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(blob, xyz);
  PcdCloud out;
  out.width = xyz.width;
  out.height = xyz.height;
  out.is_dense = xyz.is_dense;
  out.points.reserve(xyz.size());
  for (const pcl::PointXYZ& p : xyz) out.points.emplace_back(p.x, p.y, p.z);
  return out;
}

}  // namespace navaid::mapping
