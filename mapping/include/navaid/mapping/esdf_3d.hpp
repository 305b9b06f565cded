#pragma once
// 3D Euclidean distance field over an OctoMap occupancy tree, for the Smart Cane's three-sphere
// collision check in 3D (hanging obstacles). dynamicEDT3D (thirdparty-notes/octomap.md) keeps a
// distance per voxel inside a bounding box and updates it incrementally from the tree's changed
// keys, so a map that grows frame by frame costs only the change.
//
// Unsigned: 0 in occupied voxels, distances saturate at max_distance_m. Templated over the tree
// type so that it serves octomap::OcTree and navaid's semantic tree alike; this header brings in
// dynamicEDT3D and OctoMap, so include it only where the 3D field is used.
#include <dynamicEDT3D/dynamicEDTOctomap.h>

#include <cassert>
#include <memory>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"

namespace navaid::mapping {

struct Esdf3dConfig {
  double max_distance_m = 2.0;        ///< distances saturate here (bounds the update's work)
  bool unknown_as_occupied = false;   ///< treat unseen voxels as obstacles (conservative)
};

/// Keys mapping.esdf3d.max_distance_m in [0.1, 20] and mapping.esdf3d.unknown_as_occupied.
Esdf3dConfig read_esdf_3d_config(const Config& config);

template <class TREE>
class Esdf3d {
 public:
  /// Field over the box [min_W, max_W] of `tree`, which must outlive this object. Turns on the
  /// tree's change detection; call update() after inserting into the tree.
  Esdf3d(TREE& tree, const Vec3& min_W, const Vec3& max_W, const Esdf3dConfig& config)
      : resolution_(tree.getResolution()),
        edt_(std::make_unique<DynamicEDTOctomapBase<TREE>>(static_cast<float>(config.max_distance_m), &tree,
                                                            point(min_W), point(max_W),
                                                            config.unknown_as_occupied)) {
    edt_->update();
  }

  /// Folds the tree's changes since the last update into the field.
  void update() { edt_->update(); }

  double resolution() const { return resolution_; }
  double max_distance_m() const { return edt_->getMaxDist(); }

  /// Distance [m] of the voxel holding p_W (0 inside obstacles); nullopt outside the box.
  std::optional<double> voxel_distance(const Vec3& p_W) const {
    const float d = edt_->getDistance(point(p_W));
    if (d == DynamicEDTOctomapBase<TREE>::distanceValue_Error) return std::nullopt;
    return static_cast<double>(d);
  }

  /// Trilinear interpolation of the voxel-centre distances; nullopt when a needed voxel lies
  /// outside the box.
  std::optional<double> distance(const Vec3& p_W) const {
    const Vec3 u = p_W / resolution_ - Vec3::Constant(0.5);
    const Vec3 base = u.array().floor().matrix();
    const Vec3 f = u - base;
    double sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3i bit((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
      const Vec3 center = (base + bit.cast<double>() + Vec3::Constant(0.5)) * resolution_;
      const std::optional<double> d = voxel_distance(center);
      if (!d) return std::nullopt;
      double w = 1.0;
      for (int i = 0; i < 3; ++i) w *= bit[i] != 0 ? f[i] : 1.0 - f[i];
      sum += w * *d;
    }
    return sum;
  }

  /// Central differences of distance() with a step of one voxel; nullopt near the box's faces.
  std::optional<Vec3> gradient(const Vec3& p_W) const {
    Vec3 g;
    for (int i = 0; i < 3; ++i) {
      const Vec3 step = Vec3::Unit(i) * resolution_;
      const std::optional<double> plus = distance(p_W + step);
      const std::optional<double> minus = distance(p_W - step);
      if (!plus || !minus) return std::nullopt;
      g[i] = (*plus - *minus) / (2.0 * resolution_);
    }
    return g;
  }

  /// Centre of the nearest occupied voxel; nullopt outside the box or beyond max_distance_m.
  std::optional<Vec3> closest_obstacle(const Vec3& p_W) const {
    float d = 0.0F;
    octomap::point3d closest;
    edt_->getDistanceAndClosestObstacle(point(p_W), d, closest);
    if (d == DynamicEDTOctomapBase<TREE>::distanceValue_Error || d >= edt_->getMaxDist()) return std::nullopt;
    return Vec3(closest.x(), closest.y(), closest.z());
  }

 private:
  static octomap::point3d point(const Vec3& p) {
    return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }

  double resolution_;
  std::unique_ptr<DynamicEDTOctomapBase<TREE>> edt_;
};

}  // namespace navaid::mapping
