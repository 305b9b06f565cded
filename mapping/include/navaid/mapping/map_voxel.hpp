#pragma once
// One voxel of the 3D map as the 2D layers read it: what the semantic OctoMap hands to the height,
// undulation, collision and cost maps without their including OctoMap.
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/semantic_classes.hpp"

namespace navaid::mapping {

struct MapVoxel {
  Vec3 center_W = Vec3::Zero();  ///< voxel centre in the world frame W [m]
  double size_m = 0.1;           ///< edge length [m]
  double occupancy = 0.5;        ///< p(occupied) in [0, 1]
  /// Fused class; kUnlabeled for geometry-only voxels (frames without labels).
  SemanticClass semantic = SemanticClass::kUnlabeled;
  double class_probability = 0.0;  ///< confidence of `semantic` in [0, 1]
};

using MapVoxels = std::vector<MapVoxel>;

}  // namespace navaid::mapping
