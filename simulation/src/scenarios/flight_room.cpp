// The room `navaid simulate --from-recording` puts around a real flight (recorded_motion.hpp).
#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"

#include "navaid/simulation/recorded_motion.hpp"
#include "scenarios/builders.hpp"

namespace navaid::simulation {

using scenarios::Rng;
using scenarios::SceneBuilder;
using C = SemanticClass;

Scenario make_flight_room(const AxisAlignedBox& flown, std::uint64_t seed, double margin_m) {
  if (flown.empty) throw Error("make_flight_room: the flown box is empty");
  Scenario s;
  s.name = "flight-room";
  s.description = "a textured room around a recorded flight";
  s.kind = ScenarioKind::kWalk;
  s.seed = seed;
  s.default_mount = "hand";
  s.origin = {47.376887, 8.541694, 408.0};
  Rng rng(seed);
  SceneBuilder b(s.world, rng);
  const Vec2 lo = flown.min.head<2>() - Vec2::Constant(margin_m), hi = flown.max.head<2>() + Vec2::Constant(margin_m);
  const double floor_z = flown.min.z() - 0.15;
  const double height = std::max(3.0, flown.max.z() + 1.0 - floor_z);
  s.ground_z_m = floor_z;
  s.extent.extend(Vec3(lo.x(), lo.y(), floor_z));
  s.extent.extend(Vec3(hi.x(), hi.y(), floor_z + height));
  b.room_shell(lo, hi, floor_z, height, 0.1);
  const double t = 0.12;
  b.box(Vec3(lo.x() - t, lo.y() - t, floor_z), Vec3(lo.x(), hi.y() + t, floor_z + height), C::kWall, 0.08);
  b.box(Vec3(hi.x(), lo.y() - t, floor_z), Vec3(hi.x() + t, hi.y() + t, floor_z + height), C::kWall, 0.08);
  b.box(Vec3(lo.x(), lo.y() - t, floor_z), Vec3(hi.x(), lo.y(), floor_z + height), C::kWall, 0.08);
  b.box(Vec3(lo.x(), hi.y(), floor_z), Vec3(hi.x(), hi.y() + t, floor_z + height), C::kWall, 0.08);
  // Furniture in the band between the walls and the flown box grown by half the margin: boxes of
  // every height (a Vicon room's mats, crates and stands), so that near and far, low and high
  // structure is seen from any attitude.
  const double band = 0.5 * margin_m;
  const auto outside_flight = [&](const Vec2& a, const Vec2& c) {
    return c.x() < flown.min.x() - band || a.x() > flown.max.x() + band || c.y() < flown.min.y() - band ||
           a.y() > flown.max.y() + band;
  };
  for (int placed = 0, tries = 0; placed < 24 && tries < 400; ++tries) {
    // Each coordinate drawn on its own line, y before x (random_draws.hpp: the order of record).
    const double half_y = rng.uniform(0.15, 0.5);
    const Vec2 half(rng.uniform(0.15, 0.5), half_y);
    const double c_y = rng.uniform(lo.y() + half.y(), hi.y() - half.y());
    const Vec2 c(rng.uniform(lo.x() + half.x(), hi.x() - half.x()), c_y);
    if (!outside_flight(c - half, c + half)) continue;
    const double top = rng.uniform(0.3, std::min(2.5, height - 0.2));
    b.box(Vec3(c.x() - half.x(), c.y() - half.y(), floor_z), Vec3(c.x() + half.x(), c.y() + half.y(), floor_z + top),
          C::kUnlabeled, 0.05);
    ++placed;
  }
  s.path = {flown.min.head<2>(), flown.max.head<2>()};
  return s;
}

}  // namespace navaid::simulation
