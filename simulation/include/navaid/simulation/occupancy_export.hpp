#pragma once
// Ground-truth occupancy of a World: a voxel grid (a voxel is occupied when it overlaps a
// primitive), plus writers for a 2D ROS map_server map (PGM + YAML) of a height slice and a CSV
// list of occupied voxels (format in docs/scenarios.md).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/image.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

struct OccupancyGrid3D {
  static constexpr std::uint8_t kFree = 255;  ///< cell value of a free voxel; else the class id

  Vec3 origin = Vec3::Zero();        ///< min corner of voxel (0, 0, 0) in W
  double resolution_m = 0.1;         ///< voxel edge
  Eigen::Vector3i size = Eigen::Vector3i::Zero();  ///< voxels along x, y, z
  std::vector<std::uint8_t> cells;   ///< x fastest, then y, then z

  std::size_t index(int ix, int iy, int iz) const {
    return (static_cast<std::size_t>(iz) * size.y() + iy) * size.x() + ix;
  }
  bool occupied(int ix, int iy, int iz) const { return cells[index(ix, iy, iz)] != kFree; }
  Vec3 center(int ix, int iy, int iz) const {
    return origin + resolution_m * Vec3(ix + 0.5, iy + 0.5, iz + 0.5);
  }
  std::size_t count_occupied() const;
};

/// Voxelizes `world` on the grid whose min corner is bounds.min and which covers bounds (the
/// last voxel may stick out). A voxel is occupied when the interior of a solid primitive (box,
/// cylinder, ellipsoid, extruded polygon) overlaps the voxel's interior, or a plane patch meets
/// the half-open voxel [min, max). Exact for every shape (separating axes for boxes and patches,
/// a small convex QP for ellipsoids). The cell keeps the class of the last primitive in world
/// order that occupies it. Throws navaid::Error for a resolution <= 0, empty bounds or more than
/// 2^31 voxels.
OccupancyGrid3D voxelize(const World& world, double resolution_m, const AxisAlignedBox& bounds);

/// Top-down 2D occupancy of the voxel layers whose centres lie in [z_min, z_max]: an image with
/// row 0 at the largest y (map_server convention), 0 = occupied, 254 = free.
ImageU8 occupancy_slice(const OccupancyGrid3D& grid, double z_min, double z_max);

/// Writes `<stem>.pgm` (binary P5) and `<stem>.yaml` (map_server: image, resolution, origin
/// [x, y, 0] of the lower-left pixel, negate 0, occupied_thresh 0.65, free_thresh 0.196).
/// Throws IoError when a file cannot be written.
void write_occupancy_map(const OccupancyGrid3D& grid, double z_min, double z_max, const std::string& stem);

/// CSV of the occupied voxels: '#' header lines (format, resolution, origin, size), then a
/// column line "ix,iy,iz,x,y,z,class" and one row per voxel (centre in W, class name).
void write_voxel_csv(const OccupancyGrid3D& grid, const std::string& path);

}  // namespace navaid::simulation
