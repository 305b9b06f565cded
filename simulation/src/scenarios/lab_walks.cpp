// Hand-held walks in a furnished lab (seed w-roma-rgbd-vio-object-manipulation, Sec. V-A:
// three short and two long hand-held trajectories in the laboratory, Table I).
#include <cmath>

#include "navaid/core/errors.hpp"
#include "scenarios/families.hpp"

namespace navaid::simulation::scenarios {

namespace {

using C = SemanticClass;

// Lab: x in [0, 16], y in [0, 12], 3 m high; a 2.4 m corridor east of it (x in [16.1, 18.5])
// reached through two doors (y = 3 and y = 9). Walls, floor and furniture carry fine textures
// (0.05-0.15 m) so that a KLT tracker finds corners everywhere.
void build_lab(SceneBuilder& b) {
  Rng& r = b.rng();
  const double h = 3.0;
  b.room_shell(Vec2(0.0, 0.0), Vec2(16.0, 12.0), 0.0, h, 0.1);
  b.room_shell(Vec2(16.0, 0.0), Vec2(18.5, 12.0), 0.0, h, 0.12);
  b.wall(Vec2(-0.1, -0.1), Vec2(18.6, -0.1), 0.2, 0.0, h, {{3.0, 1.0}}, C::kWall, 0.08);
  b.box(Vec3(2.5, -0.2, 0.0), Vec3(3.5, -0.15, 2.1), C::kDoor, 0.05);  // closed lab door
  b.wall(Vec2(-0.1, 12.1), Vec2(18.6, 12.1), 0.2, 0.0, h, {}, C::kWall, 0.08);
  b.wall(Vec2(-0.1, -0.1), Vec2(-0.1, 12.1), 0.2, 0.0, h, {}, C::kWall, 0.1);
  b.wall(Vec2(16.05, 0.0), Vec2(16.05, 12.0), 0.1, 0.0, h, {{3.0, 1.2}, {9.0, 1.2}}, C::kWall, 0.06);
  b.wall(Vec2(18.6, -0.1), Vec2(18.6, 12.1), 0.2, 0.0, h, {}, C::kWall, 0.1);

  // Shelves (boxes) along the north and west walls, desks and chairs along the south wall.
  for (double x0 : {1.0, 9.0}) b.box(Vec3(x0, 11.4, 0.0), Vec3(x0 + 6.0, 12.0, r.uniform(1.8, 2.2)), C::kWall, 0.05);
  b.box(Vec3(0.0, 4.0, 0.0), Vec3(0.6, 10.0, 1.8), C::kWall, 0.05);
  b.table(Vec2(10.0, 0.4), Vec2(4.0, 0.4), 0.0, 0.0);
  for (double x = 7.0; x < 14.0; x += 1.5) b.chair(Vec2(x, 1.2), 0.0, -M_PI / 2 + r.uniform(-0.3, 0.3));
  // Two table islands with chairs on their long sides; the central aisle x in [7, 9] stays free.
  for (double cx : {5.5, 10.5}) {
    b.table(Vec2(cx, 6.0), Vec2(1.5, 1.5), 0.0, 0.0);
    for (double dx : {-0.8, 0.0, 0.8}) {
      b.chair(Vec2(cx + dx, 4.0), 0.0, M_PI / 2 + r.uniform(-0.3, 0.3));
      b.chair(Vec2(cx + dx, 8.0), 0.0, -M_PI / 2 + r.uniform(-0.3, 0.3));
    }
    b.box(Vec3(cx - 0.3, 5.8, 0.74), Vec3(cx + 0.2, 6.2, 1.1), C::kUnlabeled, 0.03);  // an instrument on the table
  }
  // Boxes stacked in the corridor's far end.
  b.box(Vec3(17.5, 11.0, 0.0), Vec3(18.5, 12.0, 1.2), C::kUnlabeled, 0.05);
}

std::vector<Vec2> rectangle_loop(double x0, double y0, double x1, double y1, int laps) {
  std::vector<Vec2> p{Vec2(x0, y0)};
  for (int i = 0; i < laps; ++i) {
    p.insert(p.end(), {Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1), Vec2(x0, y0)});
  }
  return p;
}

}  // namespace

void build_lab_walk(Scenario& s, Rng& rng, int index) {
  SceneBuilder b(s.world, rng);
  s.kind = ScenarioKind::kWalk;
  s.default_mount = "hand";
  s.origin = {40.819900, -73.950000, 30.0};
  s.extent.extend(Vec3(0.0, 0.0, 0.0));
  s.extent.extend(Vec3(18.5, 12.0, 3.0));
  build_lab(b);
  // Aisle lines: y = 2.2 (south), y = 9.8 (north), x = 2.5 (west), x = 8 (centre), x = 13.5 (east).
  switch (index) {
    case 1: s.path = rectangle_loop(2.5, 2.2, 8.0, 9.8, 1); break;  // 26.2 m
    case 2:  // S-shaped walk through the central aisle, 26.2 m
      s.path = {Vec2(2.5, 2.2), Vec2(8.0, 2.2), Vec2(8.0, 9.8), Vec2(13.5, 9.8), Vec2(13.5, 2.2)};
      break;
    case 3: s.path = {Vec2(2.5, 2.2), Vec2(2.5, 9.8), Vec2(13.5, 9.8), Vec2(13.5, 6.0)}; break;  // 22.4 m
    case 4: s.path = rectangle_loop(2.5, 2.2, 13.5, 9.8, 2); break;  // 74.4 m
    case 5: {  // perimeter lap, out through the first door, up the corridor, back in: ~82 m
      s.path = rectangle_loop(2.5, 2.2, 13.5, 9.8, 1);
      s.path.insert(s.path.end(), {Vec2(12.0, 2.2), Vec2(12.0, 3.0), Vec2(17.3, 3.0), Vec2(17.3, 9.0), Vec2(13.5, 9.0),
                                   Vec2(13.5, 9.8), Vec2(2.5, 9.8), Vec2(2.5, 2.2)});
      break;
    }
    default: throw Error("lab walk index must be 1..5");
  }
  // Two colleagues: one walking up and down the east aisle, one crossing the central aisle.
  MovingObject a;
  a.path = {Vec2(14.8, 1.5), Vec2(14.8, 10.8)};
  a.speed_mps = 0.9;
  a.loop = true;
  s.moving.push_back(a);
  MovingObject c;
  c.path = {Vec2(8.0, 3.0), Vec2(8.0, 9.0)};
  c.speed_mps = 1.0;
  c.start_s = 4.0;
  c.loop = true;
  c.height_m = 1.62;
  s.moving.push_back(c);
  // The object to reach for (hand guidance, Sec. IV): a 46 cm box on the south desk, tag36h11
  // id 5 (30 cm black square, on a 45 cm white card) on the face turned towards the start of the
  // walks, in view from the start until about x = 5.5 on the way east along y = 2.2. Added last
  // and without random numbers: the rest of the lab is unchanged by it.
  if (s.place_targets)
    s.targets.push_back(b.tagged_box("box-on-desk", Vec2(8.0, 0.45), 0.74, Vec3(0.2, 0.23, 0.23),
                                     std::atan2(1.75, -4.5), "36h11", 5, 0.30, 1));
}

}  // namespace navaid::simulation::scenarios
