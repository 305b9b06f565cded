#pragma once
// Ray casting against a World's triangle mesh with Embree 3 (robust BVH; Embree stays private to
// this room, see thirdparty-notes/embree.md). The Embree device is created with one thread, so
// building and casting are single-threaded and deterministic. A RayCaster is immutable after
// construction and cast() may be called from several threads.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

struct Hit {
  double distance = 0;   ///< along the unit direction [m]
  Vec3 point;            ///< origin + distance * direction, in W
  Vec3 normal;           ///< unit geometric normal of the hit triangle (outward for closed shapes)
  std::uint32_t primitive = 0;  ///< index into World::primitives()
  std::uint32_t triangle = 0;   ///< index into mesh().triangles
  SemanticClass semantic = SemanticClass::kUnlabeled;
};

class RayCaster {
 public:
  /// Triangulates the world with `tess` and builds the BVH. The world is copied.
  explicit RayCaster(World world, const Tessellation& tess = {});
  ~RayCaster();
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  const World& world() const { return world_; }
  const TriangleMesh& mesh() const { return mesh_; }

  /// First hit with distance in [t_min, t_max] along the unit direction `dir`, nullopt if none.
  /// Distances are refined in double precision on the hit triangle's plane.
  std::optional<Hit> cast(const Vec3& origin, const Vec3& dir, double t_max = std::numeric_limits<double>::infinity(),
                          double t_min = 0.0) const;

  /// Coherent batch from one origin (e.g. all pixels of an image): hits[i] for dirs[i] (unit).
  /// `hits` is resized to dirs.size(); its storage is reused across calls.
  void cast_batch(const Vec3& origin, const std::vector<Vec3>& dirs, std::vector<std::optional<Hit>>& hits,
                  double t_max = std::numeric_limits<double>::infinity(), double t_min = 0.0) const;

 private:
  struct Impl;
  World world_;
  TriangleMesh mesh_;
  std::vector<Vec3> triangle_normals_;  // unit, from double vertices
  std::unique_ptr<Impl> impl_;

  std::optional<Hit> cast_impl(const Vec3& origin, const Vec3& dir, double t_max, double t_min, bool coherent) const;
};

}  // namespace navaid::simulation
