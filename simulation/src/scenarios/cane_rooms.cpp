// Cane evaluation rooms: the Smart Cane corridor (seed smart-cane-biped-walking-path-generation,
// Sec. V-C, Fig. 11) and the BYU augmented-cane obstacle course (seed augmented-cane, Fig. 3.1).
#include <functional>

#include "scenarios/families.hpp"

namespace navaid::simulation::scenarios {

namespace {
using C = SemanticClass;

// The corridor's three kinds of station; `side` +1 puts it against the left wall (y > 0), -1
// against the right one.
std::uint32_t low_box(SceneBuilder& b, double x, double side) {  // knee-high, on the floor
  return b.box(Vec3(x - 0.3, side > 0 ? 0.2 : -1.0, 0.0), Vec3(x + 0.3, side > 0 ? 1.0 : -0.2, 0.3), C::kUnlabeled, 0.05);
}
std::uint32_t hanging_board(SceneBuilder& b, double x, double side) {  // head-high sign
  return b.box(Vec3(x - 0.3, side > 0 ? 0.2 : -1.0, 1.3), Vec3(x + 0.3, side > 0 ? 1.0 : -0.2, 1.9), C::kTrafficSign, 0.05);
}
void board_suspension(SceneBuilder& b, double x, double side) {  // the board hangs from the ceiling
  b.cylinder(Vec2(x, 0.6 * side), 1.9, 0.01, 2.6 - 1.9, C::kPole, 0.05);
}
std::uint32_t cabinet(SceneBuilder& b, double x, double side) {  // standing, waist-high
  return b.box(Vec3(x - 0.25, side > 0 ? 0.05 : -0.55, 0.0), Vec3(x + 0.25, side > 0 ? 0.55 : -0.05, 1.2), C::kUnlabeled,
               0.05);
}

// The random corridor family: the three stations in a random order, each against a random wall,
// 2.3-2.8 m apart; the path passes each on the open side.
void build_corridor_stations_at_random(Scenario& s, SceneBuilder& b, Rng& rng) {
  std::uint32_t (*kinds[3])(SceneBuilder&, double, double) = {low_box, hanging_board, cabinet};
  for (int i = 2; i > 0; --i) std::swap(kinds[i], kinds[static_cast<int>(rng.uniform(0.0, i + 1.0 - 1e-9))]);
  double x = rng.uniform(2.0, 2.8);
  s.path = {Vec2(0.0, 0.0)};
  for (auto* kind : kinds) {
    const double side = rng.uniform(0.0, 1.0) < 0.5 ? 1.0 : -1.0;
    s.placed_obstacles.push_back(kind(b, x, side));
    if (kind == hanging_board) board_suspension(b, x, side);
    const double pass_y = -0.45 * side;
    s.path.push_back(Vec2(x - 1.5, 0.0));
    s.path.push_back(Vec2(x - 0.7, pass_y));
    s.path.push_back(Vec2(x + 0.7, pass_y));
    x += rng.uniform(2.3, 2.8);
  }
  s.path.push_back(Vec2(10.0, 0.0));
}
}  // namespace

// 10 m x 2 m corridor (x in [0, 10], y in [-1, 1]); the path weaves around a low box, a hanging
// box and a standing cabinet, keeping >= 0.4 m from each.
void build_corridor(Scenario& s, Rng& rng) {
  SceneBuilder b(s.world, rng);
  s.kind = ScenarioKind::kWalk;
  s.default_mount = "cane";
  s.origin = {32.026300, 118.855600, 20.0};
  const double h = 2.6;
  s.extent.extend(Vec3(0.0, -1.0, 0.0));
  s.extent.extend(Vec3(10.0, 1.0, h));
  b.room_shell(Vec2(0.0, -1.0), Vec2(10.0, 1.0), 0.0, h, 0.1);
  b.box(Vec3(0.0, -1.12, 0.0), Vec3(10.0, -1.0, h), C::kWall, 0.08);
  b.box(Vec3(0.0, 1.0, 0.0), Vec3(10.0, 1.12, h), C::kWall, 0.08);

  if (s.random_layout) {
    build_corridor_stations_at_random(s, b, rng);
    return;
  }
  // Obstacle stations, jittered along x by the seed.
  const double x_low = 2.5 + rng.uniform(-0.2, 0.2);
  const double x_hang = 5.5 + rng.uniform(-0.2, 0.2);
  const double x_stand = 8.0 + rng.uniform(-0.2, 0.2);
  s.placed_obstacles = {low_box(b, x_low, 1.0), hanging_board(b, x_hang, -1.0), cabinet(b, x_stand, 1.0)};
  board_suspension(b, x_hang, -1.0);
  s.path = {Vec2(0.0, 0.0),          Vec2(x_low - 1.3, 0.0),   Vec2(x_low - 0.5, -0.4), Vec2(x_low + 0.9, -0.4),
            Vec2(x_hang - 0.9, 0.4), Vec2(x_hang + 0.9, 0.4),  Vec2(x_stand - 0.7, -0.45), Vec2(x_stand + 0.7, -0.45),
            Vec2(10.0, 0.0)};
}

// BYU demonstration: 10 m x 10 m room; the user starts near the middle of the west wall facing
// east; dividers force three turns (right, left, left) to a goal area in the north-east corner.
// The head-high hanging obstacle hangs over the walking line (deliberate); the waist-high one,
// the chairs and the dividers keep >= 0.3 m from it.
void build_obstacle_course(Scenario& s, Rng& rng) {
  SceneBuilder b(s.world, rng);
  s.kind = ScenarioKind::kWalk;
  s.default_mount = "cane";
  s.origin = {40.246900, -111.649300, 1400.0};
  const double h = 2.7;
  s.extent.extend(Vec3(0.0, 0.0, 0.0));
  s.extent.extend(Vec3(10.0, 10.0, h));
  b.room_shell(Vec2(0.0, 0.0), Vec2(10.0, 10.0), 0.0, h, 0.15);
  b.wall(Vec2(0.0, -0.05), Vec2(10.0, -0.05), 0.1, 0.0, h);
  b.wall(Vec2(0.0, 10.05), Vec2(10.0, 10.05), 0.1, 0.0, h);
  b.wall(Vec2(-0.05, 0.0), Vec2(-0.05, 10.0), 0.1, 0.0, h, {{5.0, 1.0}});
  b.wall(Vec2(10.05, 0.0), Vec2(10.05, 10.0), 0.1, 0.0, h);

  // Vertical dividers (1.8 m panels).
  b.box(Vec3(4.175, 2.6, 0.0), Vec3(4.225, 10.0, 1.8), C::kWall, 0.1);
  b.box(Vec3(6.975, 2.8, 0.0), Vec3(7.025, 8.0, 1.8), C::kWall, 0.1);
  b.box(Vec3(0.0, 6.6, 0.0), Vec3(2.4, 6.65, 1.8), C::kWall, 0.1);

  // Chairs on the floor beside the walking line, slightly jittered by the seed.
  // The random family moves them further along the walking line (they stay beside it) and turns
  // them at random.
  const double along = s.random_layout ? 1.0 : 0.1;
  // Every draw on its own line, in the order of record (random_draws.hpp): a chair's yaw before
  // its position, y before x.
  const auto yaw = [&](double fixed) { return s.random_layout ? rng.uniform(-3.14159, 3.14159) : fixed; };
  const auto offset = [&](double x_lo, double x_hi, double y_lo, double y_hi) -> Vec2 {
    const double y = rng.uniform(y_lo, y_hi);
    return Vec2(rng.uniform(x_lo, x_hi), y);
  };
  const auto chair = [&](const Vec2& at, double fixed_yaw, const std::function<Vec2()>& moved) {
    const double a = yaw(fixed_yaw);
    b.chair(at + moved(), 0.0, a);
  };
  chair(Vec2(1.8, 3.0), 0.3, [&]() -> Vec2 {
    const double shift = s.random_layout ? rng.uniform(-1.0, 0.8) : 0.0;
    return offset(-0.1, 0.1, -0.1, 0.1) + Vec2(0, shift);
  });
  chair(Vec2(5.4, 0.5), 1.6, [&]() -> Vec2 { return offset(-along, along, -0.1, 0.1); });
  chair(Vec2(9.35, 4.5), 3.1, [&]() -> Vec2 { return offset(-0.1, 0.1, -along, along); });
  chair(Vec2(7.75, 5.6), -0.4, [&]() -> Vec2 { return offset(-0.1, 0.0, -0.1, 0.1); });
  chair(Vec2(5.6, 6.0), 2.0, [&]() -> Vec2 { return offset(-0.1, 0.1, -0.1, 0.1) * (s.random_layout ? 8.0 : 1.0); });

  // Hanging obstacles: head-high over the south leg (deliberate), waist-high beside the east leg.
  // Random family: the head-high one anywhere over the south leg, the waist-high one anywhere
  // beside the east leg.
  const double head_x = s.random_layout ? rng.uniform(3.8, 7.2) : 5.6;
  const double waist_y = s.random_layout ? rng.uniform(3.0, 7.6) : 6.5;
  const std::uint32_t head = s.world.add(Ellipsoid{SE3(Quat::Identity(), Vec3(head_x, 1.4, 1.7)), Vec3(0.2, 0.2, 0.2)},
                                         b.surface(C::kUnlabeled, 0.05));
  const std::uint32_t cord = b.cylinder(Vec2(head_x, 1.4), 1.9, 0.005, h - 1.9, C::kUnlabeled, 0.05);
  s.deliberate_obstacles = {head, cord};
  s.placed_obstacles = {
      s.world.add(Ellipsoid{SE3(Quat::Identity(), Vec3(9.15, waist_y, 1.0)), Vec3(0.3, 0.3, 0.25)},
                  b.surface(C::kUnlabeled, 0.05)),
      b.cylinder(Vec2(9.15, waist_y), 1.25, 0.005, h - 1.25, C::kUnlabeled, 0.05)};

  // The music source marking the goal: a speaker on a small table in the corner.
  b.table(Vec2(9.5, 9.5), Vec2(0.3, 0.3), 0.0, 0.0);
  b.box(Vec3(9.35, 9.4, 0.76), Vec3(9.65, 9.6, 1.1), C::kUnlabeled, 0.03);

  s.path = {Vec2(0.8, 5.0), Vec2(2.8, 5.0), Vec2(2.8, 1.4), Vec2(8.4, 1.4), Vec2(8.4, 8.6)};
}

}  // namespace navaid::simulation::scenarios
