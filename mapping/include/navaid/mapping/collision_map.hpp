#pragma once
// Collision map M_t, eLabrador eq. (9):
//   p(g) = (1 / sum_h p(g,h)) sum_h p(s) p(m) p(g,h),
// the expectation of p(s) p(m) over the pillar's voxels weighted by their occupancy p(g,h), where
// p(s) is the semantic collision probability of the voxel's class (Table II) and p(m) = 1 when the
// voxel's height relative to the camera, m = h_voxel - h_camera, lies in [-2 m, 0 m], else 0.
//
// The sums run over the pillar's occupied voxels (p >= occupied_threshold): free voxels carry no
// class, and counting them would let empty air inside the walking band raise p(g).
//
// Table II's numbers did not survive in the seed text (only its caption), so the defaults below are
// navaid's own, one per class of core/semantic_classes.hpp, with the reason in the table's
// comments (collision_map.cpp) and in docs/mapping.md ("2D map layers").
#include <array>

#include "navaid/core/config.hpp"
#include "navaid/core/semantic_classes.hpp"
#include "navaid/mapping/grid_layer.hpp"
#include "navaid/mapping/map_voxel.hpp"

namespace navaid::mapping {

/// p(s) per class, indexed by class id.
using SemanticCollisionTable = std::array<double, kNumSemanticClasses>;

/// navaid's Table II (see collision_map.cpp for the reason per class).
const SemanticCollisionTable& default_semantic_collision_table();

struct CollisionConfig {
  double occupied_threshold = 0.5;      ///< voxels with p >= this enter eq. (9)
  double min_relative_height_m = -2.0;  ///< p(m) = 1 for min <= m <= max (eLabrador: -2 m .. 0 m)
  double max_relative_height_m = 0.0;
  SemanticCollisionTable semantic_probability = default_semantic_collision_table();
};

/// Keys mapping.collision.occupied_threshold in [0.01, 1], mapping.collision.min_relative_height_m
/// and max_relative_height_m in [-10, 10] (min <= max), and
/// mapping.collision.semantic_probability.<class-name> in [0, 1] for any subset of the classes
/// (the others keep their default). An unknown class name raises ConfigError naming the key.
CollisionConfig read_collision_config(const Config& config);

/// p(m): 1 when min <= m <= max (both edges included), else 0.
double geometric_collision_probability(double relative_height_m, const CollisionConfig& config);

/// Cell value: p(g) in [0, 1]; NaN where the pillar holds no occupied voxel (unknown).
class CollisionMap : public GridLayer<float> {
 public:
  explicit CollisionMap(const GridGeometry& geometry);
  static bool is_known(float p);
};

CollisionMap build_collision_map(const MapVoxels& voxels, const GridGeometry& geometry, double camera_height_W,
                                 const CollisionConfig& config);

}  // namespace navaid::mapping
