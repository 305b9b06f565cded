#pragma once
// The occupied leaves of an OctoMap tree as MapVoxels, for the 2D layers: how a map read from a .bt
// file (or any occupancy tree) reaches the height, collision and cost maps. Pruned leaves are
// split into max-depth voxels, so every voxel has the tree's resolution and eq. (9)'s sums count
// the volume the leaf stands for. Templated over the tree type; classes are unknown (kUnlabeled).
#include <octomap/octomap_types.h>

#include "navaid/core/geometry.hpp"
#include "navaid/mapping/map_voxel.hpp"

namespace navaid::mapping {

/// Occupied leaves of `tree` inside [min_W, max_W] (OctoMap's bbx test on voxel keys).
template <class TREE>
MapVoxels octomap_to_voxels(const TREE& tree, const Vec3& min_W, const Vec3& max_W) {
  const auto to_point = [](const Vec3& p) {
    return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  };
  const octomap::OcTreeKey lo = tree.coordToKey(to_point(min_W));
  const octomap::OcTreeKey hi = tree.coordToKey(to_point(max_W));
  const double resolution = tree.getResolution();
  const unsigned max_depth = tree.getTreeDepth();
  MapVoxels voxels;
  for (auto it = tree.begin_leafs_bbx(lo, hi), end = tree.end_leafs_bbx(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const double occupancy = it->getOccupancy();
    const unsigned cells = 1U << (max_depth - it.getDepth());
    const octomap::OcTreeKey first = it.getIndexKey();
    for (unsigned dz = 0; dz < cells; ++dz) {
      for (unsigned dy = 0; dy < cells; ++dy) {
        for (unsigned dx = 0; dx < cells; ++dx) {
          const octomap::OcTreeKey key(static_cast<octomap::key_type>(first[0] + dx),
                                       static_cast<octomap::key_type>(first[1] + dy),
                                       static_cast<octomap::key_type>(first[2] + dz));
          bool inside = true;
          for (unsigned i = 0; i < 3; ++i) inside = inside && key[i] >= lo[i] && key[i] <= hi[i];
          if (!inside) continue;
          const octomap::point3d c = tree.keyToCoord(key);
          MapVoxel v;
          v.center_W = Vec3(c.x(), c.y(), c.z());
          v.size_m = resolution;
          v.occupancy = occupancy;
          voxels.push_back(v);
        }
      }
    }
  }
  return voxels;
}

}  // namespace navaid::mapping
