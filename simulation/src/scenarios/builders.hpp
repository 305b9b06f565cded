#pragma once
// Shared building blocks of the scenario families: a portable seeded random source and street /
// indoor furniture made of World primitives (private to the simulation room).
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation::scenarios {

/// Seeded random numbers that are identical on every standard library (std distributions are not).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo = 0.0, double hi = 1.0) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  }
  /// Integer in [lo, hi].
  int integer(int lo, int hi) {
    return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::mt19937_64 engine_;
};

/// Adds primitives to a world with fresh texture seeds; every helper returns primitive indices.
class SceneBuilder {
 public:
  SceneBuilder(World& world, Rng& rng) : world_(world), rng_(rng) {}
  World& world() { return world_; }
  Rng& rng() { return rng_; }

  /// A surface of class c with a new texture seed and an albedo in [0.35, 0.85].
  Surface surface(SemanticClass c, double texture_scale);

  std::uint32_t box(const Vec3& lo, const Vec3& hi, SemanticClass c, double texture_scale);
  std::uint32_t oriented_box(const Vec3& center, const Vec3& half, double yaw, SemanticClass c, double texture_scale);
  std::uint32_t horizontal_patch(const Vec2& lo, const Vec2& hi, double z, SemanticClass c, double texture_scale);
  std::uint32_t cylinder(const Vec2& xy, double z0, double radius, double height, SemanticClass c, double texture_scale);

  // Street furniture. Rectangles are axis-aligned (lo, hi corners in x-y).
  /// Raised sidewalk slab from z_top - depth to z_top.
  std::uint32_t sidewalk(const Vec2& lo, const Vec2& hi, double z_top, double depth);
  /// Curb stone along an axis-aligned edge (a -> b), 0.15 m wide, from z_bottom to z_top.
  std::uint32_t curb(const Vec2& a, const Vec2& b, double z_bottom, double z_top);
  /// Tactile paving strip (0.3 m wide) on top of a walkway along a -> b.
  std::uint32_t tactile_strip(const Vec2& a, const Vec2& b, double z);
  /// Trunk + crown (crown bottom at crown_bottom_z); low branches stick out from the trunk at
  /// heights in [1.5, 1.75] m towards each given direction by the given reach; their indices are
  /// appended to `branches` when non-null.
  void tree(const Vec2& xy, double z0, double crown_bottom_z, double crown_radius,
            const std::vector<Vec2>& branch_reach = {}, std::vector<std::uint32_t>* branches = nullptr);
  /// Pole with an optional sign board (facing along +/- `sign_normal_yaw`).
  void pole(const Vec2& xy, double z0, double height, bool with_sign, double sign_normal_yaw = 0.0);
  void bench(const Vec2& xy, double z0, double yaw);
  /// Parked car (body + cabin) centred at xy, heading yaw.
  void car(const Vec2& xy, double z0, double yaw);
  /// Standing person (body cylinder + head).
  void person(const Vec2& xy, double z0, double radius = 0.25, double height = 1.7);
  /// Bus-stop pavilion along x in [x0, x1]: back panel at y_back, roof to y_front (on the road side),
  /// posts at both ends and a bench inside.
  void bus_stop(double x0, double x1, double y_back, double y_front, double z0);
  /// Landmark sign board (class traffic-sign) on two posts, board centre at xy, facing yaw.
  void landmark(const Vec2& xy, double z0, double width, double yaw);

  // Indoor.
  void chair(const Vec2& xy, double z0, double yaw);
  /// Table top at 0.74 m with four legs.
  void table(const Vec2& center, const Vec2& half, double z0, double yaw);
  /// Axis-aligned wall a -> b (horizontal or vertical), with door openings {centre along the
  /// wall from a, width}; each opening gets a door-class lintel above 2.1 m.
  void wall(const Vec2& a, const Vec2& b, double thickness, double z0, double height,
            const std::vector<std::pair<double, double>>& doors = {}, SemanticClass c = SemanticClass::kWall,
            double texture_scale = 0.1);
  /// Target object: a box of class target-object standing on z0 at xy, turned by yaw, with the
  /// AprilTag `tag_id` of `family` (black square `tag_size_m`) printed centred on its +x face (the
  /// face whose outward normal points along yaw), upright, on a white card 2 mm in front of the
  /// face: the pattern with its one-cell white ring plus `margin_cells` more white cells around.
  /// Uses no random numbers, so adding a target leaves the rest of a scene as it was.
  TargetObject tagged_box(const std::string& name, const Vec2& xy, double z0, const Vec3& half, double yaw,
                          const std::string& family, int tag_id, double tag_size_m, int margin_cells);
  /// Floor at z0 and (when ceiling_height > 0) ceiling over the rectangle.
  void room_shell(const Vec2& lo, const Vec2& hi, double z0, double ceiling_height, double texture_scale);

 private:
  World& world_;
  Rng& rng_;
};

/// Parts of people and cars, shared by static props and moving objects.
/// A person or car walking/driving `path` in a loop, starting at start_s (scenario traffic).
MovingObject looping_person(std::vector<Vec2> path, double speed_mps, double start_s, double height_m);
MovingObject looping_car(std::vector<Vec2> path, double speed_mps, double start_s);

void add_person_shape(World& world, const Vec2& xy, double z0, double radius, double height, std::uint32_t texture_seed);
void add_car_shape(World& world, const Vec2& xy, double z0, double yaw, double half_width, double height,
                   std::uint32_t texture_seed);

}  // namespace navaid::simulation::scenarios
