#pragma once
// Simulator worlds: a list of analytic primitives (plane patches, oriented boxes, vertical
// cylinders, ellipsoids, extruded polygons), each with a semantic class and a procedural texture,
// triangulated into one mesh for ray casting (ray_caster.hpp). Frame: W, z up, metres.
#include <array>
#include <cstdint>
#include <memory>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/geometry.hpp"
#include "navaid/core/image.hpp"
#include "navaid/simulation/semantic_classes.hpp"

namespace navaid::simulation {

using Vec2 = Eigen::Vector2d;

/// Appearance of a primitive: class for the label image, texture for the intensity image.
struct Surface {
  SemanticClass semantic = SemanticClass::kUnlabeled;
  std::uint32_t texture_seed = 0;  ///< different seeds give different patterns
  double texture_scale = 0.2;      ///< size of a texture cell [m], > 0
  double albedo = 0.7;             ///< mean reflectance in (0, 1]
};

/// Image texture of a plane patch (World::add with an image): a one-channel picture printed over
/// the whole rectangle, 0 = black ink, 255 = white, replacing the procedural texture (reflectance
/// = albedo x (0.05 + 0.95 v / 255)). Seen from the patch's +z side the picture is upright and
/// unmirrored: column 0 at x = -half_x, row 0 at y = +half_y. Shared, not copied, between copies
/// of a world.
using ImageTexture = std::shared_ptr<const ImageU8>;

/// Rectangle in the x-y plane of its pose, centred at the pose origin, normal = pose z axis.
struct PlanePatch {
  SE3 T_W_P;
  double half_x = 1.0, half_y = 1.0;
};

/// Oriented box: centre and orientation T_W_O, half extents along the box axes.
struct Box {
  SE3 T_W_O;
  Vec3 half_extents = Vec3::Ones();
};

/// Closed vertical cylinder standing on base_center (axis = W z).
struct VerticalCylinder {
  Vec3 base_center = Vec3::Zero();
  double radius = 0.1, height = 1.0;
};

/// Ellipsoid with centre and principal axes T_W_O and semi-axes radii.
struct Ellipsoid {
  SE3 T_W_O;
  Vec3 radii = Vec3::Ones();
};

/// Simple (non self-intersecting) polygon in W x-y, either orientation, extruded from z_min to
/// z_max (closed prism).
struct ExtrudedPolygon {
  std::vector<Vec2> polygon;
  double z_min = 0.0, z_max = 1.0;
};

using Shape = std::variant<PlanePatch, Box, VerticalCylinder, Ellipsoid, ExtrudedPolygon>;

struct Primitive {
  Shape shape;
  Surface surface;
};

/// Tessellation of curved primitives (flat ones are exact).
struct Tessellation {
  int cylinder_segments = 24;  ///< >= 3
  int ellipsoid_slices = 24;   ///< around the O z axis, >= 3
  int ellipsoid_stacks = 12;   ///< pole to pole, >= 2
};

/// Triangle mesh of a world: counter-clockwise triangles seen from outside (plane patches: from
/// the +z side of the patch), one primitive index per triangle.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> triangle_primitive;
};

struct AxisAlignedBox {
  Vec3 min = Vec3::Constant(0.0);
  Vec3 max = Vec3::Constant(0.0);
  bool empty = true;
  void extend(const Vec3& p);
  void extend(const AxisAlignedBox& b);
};

class World {
 public:
  /// Adds a primitive and returns its index. Throws navaid::Error on invalid geometry (non-positive
  /// extents, non-finite values, polygon with < 3 vertices or zero area, z_max <= z_min) or
  /// surface (texture_scale <= 0, albedo outside (0, 1]).
  std::uint32_t add(const Shape& shape, const Surface& surface);
  /// Same with an image texture (may be null: none). Throws navaid::Error when the image is empty,
  /// has more than one channel, or the shape is not a plane patch.
  std::uint32_t add(const Shape& shape, const Surface& surface, ImageTexture image);
  /// The image texture of primitive i, null when it has none.
  const ImageU8* image_texture(std::uint32_t i) const { return images_.at(i).get(); }

  const std::vector<Primitive>& primitives() const { return primitives_; }
  const Primitive& primitive(std::uint32_t i) const { return primitives_.at(i); }
  std::size_t size() const { return primitives_.size(); }
  bool empty() const { return primitives_.empty(); }

  /// Triangulation of all primitives in insertion order.
  TriangleMesh triangulate(const Tessellation& tess = {}) const;

  /// Exact bounding box of the analytic primitives.
  AxisAlignedBox bounds() const;

 private:
  std::vector<Primitive> primitives_;
  std::vector<ImageTexture> images_;  ///< one per primitive, null for none
};

/// Triangulation of one primitive appended to mesh, tagged with primitive index `index`.
void append_triangles(const Shape& shape, std::uint32_t index, const Tessellation& tess, TriangleMesh& mesh);

/// Bounding box of one primitive.
AxisAlignedBox bounds_of(const Shape& shape);

}  // namespace navaid::simulation
