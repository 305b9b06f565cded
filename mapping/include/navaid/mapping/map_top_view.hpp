#pragma once
// A top view of a whole walk: the local window keeps only the last 10 m, so the view accumulates
// every snapshot's occupied voxels (the highest per cell under a height limit, in its class colour)
// and the walked path,
// and is written as a PNG with a legend of the classes seen.
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/mapping/map_voxel.hpp"

namespace navaid::mapping {

class MapTopView {
 public:
  /// Cells of `cell_m`; the canvas grows to whatever the walk covers.
  explicit MapTopView(double cell_m = 0.1);

  /// Paints the voxels over what is there (a cell shows the highest voxel seen in it last). Voxels
  /// above max_z_W (ceilings, tree crowns over the user's head) are left out, so that what the
  /// user walks among stays visible.
  void add_voxels(const MapVoxels& voxels, double max_z_W);
  void add_path_point(const Vec3& p_W);

  std::size_t painted_cells() const;
  /// Writes the PNG (x east to the right, y north up, path in black, a 1 m scale bar, the legend).
  /// Throws IoError when the file cannot be written or nothing was added.
  void write_png(const std::filesystem::path& file, int max_side_px = 1600) const;

 private:
  double cell_m_;
  std::map<std::pair<long, long>, SemanticClass> cells_;  ///< (ix, iy) -> class shown
  std::vector<Vec3> path_;
};

}  // namespace navaid::mapping
