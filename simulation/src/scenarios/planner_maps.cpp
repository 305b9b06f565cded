// Planner maps of the Smart Cane paper (seed smart-cane-biped-walking-path-generation, Table I,
// Fig. 10): office1, office2, pillar (40 x 40 x 4.5 m) and school indoor (250 x 150 x 5 m),
// generated from seeds, each with a collision-free start-goal polyline found by grid A*.
#include <cmath>
#include <functional>

#include "navaid/core/errors.hpp"
#include "scenarios/families.hpp"
#include "scenarios/grid_planner.hpp"

namespace navaid::simulation::scenarios {

namespace {

using C = SemanticClass;
constexpr int kMaxAttempts = 10;

struct Rect {
  Vec2 lo, hi;
  Vec2 size() const { return hi - lo; }
};

// Walls are room edges; a door lies on an edge (same axis and coordinate) and is carved out of
// every wall segment it lies on, so walls shared by two rooms get the same opening.
struct Door {
  bool along_x;   // the wall runs along x (door centre at x = along, y = at)
  double at, along, width;
};

struct OfficeLayout {
  std::vector<Rect> rooms;
  std::vector<Door> doors;
  std::vector<Rect> corridors;
};

// Splits `block` along x into rooms 4.5-8 m wide (the last one takes the rest); each room gets a
// door on its y = lo edge (door_low) or its y = hi edge.
void room_row(OfficeLayout& L, const Rect& block, bool door_low, Rng& r) {
  double x = block.lo.x();
  while (block.hi.x() - x > 1e-6) {
    double w = r.uniform(4.5, 8.0);
    if (block.hi.x() - (x + w) < 4.5) w = block.hi.x() - x;
    const Rect room{Vec2(x, block.lo.y()), Vec2(x + w, block.hi.y())};
    L.rooms.push_back(room);
    L.doors.push_back({true, door_low ? room.lo.y() : room.hi.y(), r.uniform(x + 1.2, x + w - 1.2), 1.2});
    x += w;
  }
}

void build_walls(SceneBuilder& b, const OfficeLayout& L, double height) {
  auto edge = [&](const Vec2& a, const Vec2& c) {
    const bool along_x = std::abs(c.y() - a.y()) < 1e-9;
    std::vector<std::pair<double, double>> openings;
    for (const Door& d : L.doors) {
      if (d.along_x != along_x) continue;
      const double at = along_x ? a.y() : a.x(), s0 = along_x ? a.x() : a.y(), s1 = along_x ? c.x() : c.y();
      if (std::abs(d.at - at) < 1e-6 && d.along > s0 && d.along < s1) openings.push_back({d.along - s0, d.width});
    }
    b.wall(a, c, 0.1, 0.0, height, openings, C::kWall, 0.1);
  };
  for (const Rect& r : L.rooms) {
    edge(r.lo, Vec2(r.hi.x(), r.lo.y()));
    edge(Vec2(r.lo.x(), r.hi.y()), r.hi);
    edge(r.lo, Vec2(r.lo.x(), r.hi.y()));
    edge(Vec2(r.hi.x(), r.lo.y()), r.hi);
  }
}

// Desks with chairs on a loose grid inside the room shrunk by 1.2 m (the ring along the walls and
// the doors stays free), plus a cabinet.
void furnish(SceneBuilder& b, const Rect& room) {
  Rng& r = b.rng();
  const Rect in{room.lo + Vec2(1.2, 1.2), room.hi - Vec2(1.2, 1.2)};
  for (double y = in.lo.y() + 0.5; y + 1.1 <= in.hi.y(); y += 2.2)
    for (double x = in.lo.x() + 0.75; x + 0.75 <= in.hi.x(); x += 2.0) {
      if (r.chance(0.35)) continue;
      b.table(Vec2(x, y), Vec2(0.7, 0.35), 0.0, 0.0);
      b.chair(Vec2(x + r.uniform(-0.3, 0.3), y + 0.7), 0.0, -M_PI / 2 + r.uniform(-0.4, 0.4));
    }
  if (in.size().x() > 1.0 && in.size().y() > 1.0 && r.chance(0.6)) {
    const Vec2 c(r.uniform(in.lo.x() + 0.3, in.hi.x() - 0.3), in.hi.y() - 0.25);
    b.box(Vec3(c.x() - 0.3, c.y() - 0.25, 0.0), Vec3(c.x() + 0.3, c.y() + 0.25, 1.9), C::kUnlabeled, 0.05);
  }
}

// Plant pots along corridor walls, away from doors and corridor crossings.
void corridor_pots(SceneBuilder& b, const OfficeLayout& L, const Rect& corridor, bool along_x) {
  Rng& r = b.rng();
  const double len = along_x ? corridor.size().x() : corridor.size().y();
  for (int k = 0; k < static_cast<int>(len / 8.0); ++k) {
    const double s = r.uniform(1.0, len - 1.0);
    const bool low_side = r.chance(0.5);
    const Vec2 p = along_x ? Vec2(corridor.lo.x() + s, low_side ? corridor.lo.y() + 0.35 : corridor.hi.y() - 0.35)
                           : Vec2(low_side ? corridor.lo.x() + 0.35 : corridor.hi.x() - 0.35, corridor.lo.y() + s);
    bool clear = true;
    for (const Door& d : L.doors) {
      const Vec2 dc = d.along_x ? Vec2(d.along, d.at) : Vec2(d.at, d.along);
      clear = clear && (dc - p).norm() > 2.0;
    }
    for (const Rect& o : L.corridors) {
      if (&o == &corridor) continue;
      const bool inside = p.x() > o.lo.x() - 2.0 && p.x() < o.hi.x() + 2.0 && p.y() > o.lo.y() - 2.0 && p.y() < o.hi.y() + 2.0;
      clear = clear && !inside;
    }
    if (clear) b.cylinder(p, 0.0, 0.25, 1.0, C::kVegetation, 0.05);
  }
}

void common_setup(Scenario& s, double size_x, double size_y, double height) {
  s.kind = ScenarioKind::kPlannerMap;
  s.default_mount = "cane";
  s.origin = {32.026300, 118.855600, 20.0};
  s.extent = AxisAlignedBox();
  s.extent.extend(Vec3(0.0, 0.0, 0.0));
  s.extent.extend(Vec3(size_x, size_y, height));
}

// Regenerates (continuing the same random stream) until the start-goal path exists and keeps
// 0.3 m clearance; deterministic for a seed.
void generate_until_walkable(Scenario& s, Rng& rng, double resolution,
                             const std::function<std::pair<Vec2, Vec2>(SceneBuilder&)>& build) {
  for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
    s.world = World();
    s.moving.clear();
    SceneBuilder b(s.world, rng);
    const auto [start, goal] = build(b);
    const Vec2 hi = s.extent.max.head<2>();
    const auto path = plan_grid_path(s.world, Vec2::Zero(), hi, resolution, start, goal, 0.35);
    if (path && path_clearance(s.world, *path, s.ground_z_m) >= 0.3) {
      s.path = *path;
      return;
    }
  }
  throw Error("scenario '" + s.name + "': no walkable start-goal path after " + std::to_string(kMaxAttempts) +
              " layouts (seed " + std::to_string(s.seed) + ")");
}

void outer_walls(SceneBuilder& b, double sx, double sy, double h) {
  b.wall(Vec2(-0.05, -0.05), Vec2(sx + 0.05, -0.05), 0.1, 0.0, h);
  b.wall(Vec2(-0.05, sy + 0.05), Vec2(sx + 0.05, sy + 0.05), 0.1, 0.0, h);
  b.wall(Vec2(-0.05, -0.05), Vec2(-0.05, sy + 0.05), 0.1, 0.0, h);
  b.wall(Vec2(sx + 0.05, -0.05), Vec2(sx + 0.05, sy + 0.05), 0.1, 0.0, h);
}

}  // namespace

// office1: a corridor cross (3 m wide, position by seed) with rows of rooms in the four quadrants,
// each room with a door to the east-west corridor. office2: two east-west corridors joined by two
// north-south connectors, four rows of rooms. Start in the south-west room, goal in the
// north-east room.
void build_office(Scenario& s, Rng& rng, int variant) {
  const double size = 40.0, h = 4.5;
  common_setup(s, size, size, h);
  generate_until_walkable(s, rng, 0.1, [&](SceneBuilder& b) {
    Rng& r = b.rng();
    OfficeLayout L;
    if (variant == 1) {
      const double cx = 18.5 + r.uniform(-3.0, 3.0), cy = 18.5 + r.uniform(-3.0, 3.0), w = 3.0;
      L.corridors = {Rect{Vec2(0, cy), Vec2(size, cy + w)}, Rect{Vec2(cx, 0), Vec2(cx + w, size)}};
      room_row(L, Rect{Vec2(0, 0), Vec2(cx, cy)}, false, r);
      room_row(L, Rect{Vec2(cx + w, 0), Vec2(size, cy)}, false, r);
      room_row(L, Rect{Vec2(0, cy + w), Vec2(cx, size)}, true, r);
      room_row(L, Rect{Vec2(cx + w, cy + w), Vec2(size, size)}, true, r);
    } else {
      const double a = 10.0 + r.uniform(-1.5, 1.5), bb = 27.0 + r.uniform(-1.5, 1.5), w = 2.5;
      const double c1 = 9.0 + r.uniform(-2.0, 2.0), c2 = 29.0 + r.uniform(-2.0, 2.0);
      const double mid = 0.5 * (a + w + bb);
      L.corridors = {Rect{Vec2(0, a), Vec2(size, a + w)}, Rect{Vec2(0, bb), Vec2(size, bb + w)},
                     Rect{Vec2(c1, a + w), Vec2(c1 + w, bb)}, Rect{Vec2(c2, a + w), Vec2(c2 + w, bb)}};
      room_row(L, Rect{Vec2(0, 0), Vec2(size, a)}, false, r);
      room_row(L, Rect{Vec2(0, bb + w), Vec2(size, size)}, true, r);
      for (const auto& [x0, x1] : {std::pair{0.0, c1}, std::pair{c1 + w, c2}, std::pair{c2 + w, size}}) {
        room_row(L, Rect{Vec2(x0, a + w), Vec2(x1, mid)}, true, r);
        room_row(L, Rect{Vec2(x0, mid), Vec2(x1, bb)}, false, r);
      }
    }
    b.room_shell(Vec2(0, 0), Vec2(size, size), 0.0, 0.0, 0.2);
    outer_walls(b, size, size, h);
    build_walls(b, L, h);
    for (const Rect& room : L.rooms) furnish(b, room);
    for (const Rect& c : L.corridors) corridor_pots(b, L, c, c.size().x() > c.size().y());
    // Two people walking along the corridors.
    for (const Rect& c : L.corridors) {
      if (s.moving.size() >= 2) break;
      MovingObject m;
      const Vec2 mid = 0.5 * (c.lo + c.hi);
      m.path = c.size().x() > c.size().y() ? std::vector<Vec2>{Vec2(c.lo.x() + 1.0, mid.y()), Vec2(c.hi.x() - 1.0, mid.y())}
                                           : std::vector<Vec2>{Vec2(mid.x(), c.lo.y() + 1.0), Vec2(mid.x(), c.hi.y() - 1.0)};
      m.loop = true;
      m.speed_mps = r.uniform(0.9, 1.3);
      s.moving.push_back(m);
    }
    const Rect& first = L.rooms.front();  // south-west room
    Rect goal_room = L.rooms.back();
    for (const Rect& room : L.rooms)  // the north-east room
      if (room.hi.x() >= size - 1e-6 && room.hi.y() >= size - 1e-6) goal_room = room;
    return std::pair<Vec2, Vec2>(first.lo + Vec2(0.6, 0.6), goal_room.hi - Vec2(0.6, 0.6));
  });
}

// pillar: a 40 x 40 m hall with round and square pillars on a jittered 3.2 m grid.
void build_pillar(Scenario& s, Rng& rng) {
  const double size = 40.0, h = 4.5;
  common_setup(s, size, size, h);
  // Diagonal through the pillar grid (between grid points), ~37 m apart as in Table I.
  const Vec2 start(4.1, 7.3), goal(33.3, 29.7);
  generate_until_walkable(s, rng, 0.1, [&](SceneBuilder& b) {
    Rng& r = b.rng();
    b.room_shell(Vec2(0, 0), Vec2(size, size), 0.0, 0.0, 0.2);
    outer_walls(b, size, size, h);
    for (double y = 2.5; y < size - 1.0; y += 3.2)
      for (double x = 2.5; x < size - 1.0; x += 3.2) {
        if (r.chance(0.15)) continue;
        const Vec2 p(x + r.uniform(-0.6, 0.6), y + r.uniform(-0.6, 0.6));
        if ((p - start).norm() < 1.5 || (p - goal).norm() < 1.5) continue;
        if (r.chance(0.5)) {
          b.cylinder(p, 0.0, r.uniform(0.2, 0.45), h, C::kPole, 0.1);
        } else {
          const double half = r.uniform(0.2, 0.4);
          b.oriented_box(Vec3(p.x(), p.y(), 0.5 * h), Vec3(half, half, 0.5 * h), r.uniform(0.0, M_PI / 2), C::kWall, 0.1);
        }
      }
    return std::make_pair(start, goal);
  });
}

// school indoor: 250 x 150 x 5 m; 4 m corridors on a jittered grid (4 north-south, 3 east-west)
// separate blocks that are classroom buildings (solid), courtyards (grass, trees, benches) or
// lobbies (columns, tables). Start at the south-west crossing, goal at the east end of the middle
// corridor.
void build_school(Scenario& s, Rng& rng) {
  const double sx = 250.0, sy = 150.0, h = 5.0, w = 4.0;
  common_setup(s, sx, sy, h);
  generate_until_walkable(s, rng, 0.25, [&](SceneBuilder& b) {
    Rng& r = b.rng();
    const std::vector<double> xs = {12.0 + r.uniform(-3, 3), 80.0 + r.uniform(-8, 8), 160.0 + r.uniform(-8, 8),
                                    234.0 + r.uniform(-3, 3)};
    const std::vector<double> ys = {14.0 + r.uniform(-3, 3), 73.0 + r.uniform(-8, 8), 134.0 + r.uniform(-3, 3)};
    b.room_shell(Vec2(0, 0), Vec2(sx, sy), 0.0, 0.0, 0.3);
    outer_walls(b, sx, sy, h);
    std::vector<double> bx = {0.0}, by = {0.0};
    for (double x : xs) bx.insert(bx.end(), {x, x + w});
    for (double y : ys) by.insert(by.end(), {y, y + w});
    bx.push_back(sx);
    by.push_back(sy);
    for (std::size_t j = 0; j + 1 < by.size(); j += 2)
      for (std::size_t i = 0; i + 1 < bx.size(); i += 2) {
        const Rect blk{Vec2(bx[i], by[j]), Vec2(bx[i + 1], by[j + 1])};
        if (blk.size().x() < 1.0 || blk.size().y() < 1.0) continue;
        const double kind = r.uniform();
        if (kind < 0.55 || blk.size().minCoeff() < 8.0) {  // classroom building
          b.box(Vec3(blk.lo.x(), blk.lo.y(), 0.0), Vec3(blk.hi.x(), blk.hi.y(), h), C::kBuilding, 0.4);
        } else if (kind < 0.8) {  // courtyard
          b.horizontal_patch(blk.lo, blk.hi, 0.01, C::kTerrain, 0.3);
          const int trees = static_cast<int>(blk.size().prod() / 150.0);
          for (int k = 0; k < trees; ++k)
            b.tree(Vec2(r.uniform(blk.lo.x() + 3, blk.hi.x() - 3), r.uniform(blk.lo.y() + 3, blk.hi.y() - 3)), 0.0,
                   2.5, r.uniform(1.2, 1.6));  // crown tops stay below the 5 m extent
          for (int k = 0; k < trees / 2; ++k)
            b.bench(Vec2(r.uniform(blk.lo.x() + 2, blk.hi.x() - 2), r.uniform(blk.lo.y() + 2, blk.hi.y() - 2)), 0.0,
                    r.uniform(0.0, M_PI));
        } else {  // lobby: columns on a 6 m grid and tables between them
          for (double y = blk.lo.y() + 4.0; y < blk.hi.y() - 3.0; y += 6.0)
            for (double x = blk.lo.x() + 4.0; x < blk.hi.x() - 3.0; x += 6.0) {
              b.cylinder(Vec2(x, y), 0.0, 0.35, h, C::kPole, 0.1);
              if (r.chance(0.4)) b.table(Vec2(x + 3.0, y + 3.0), Vec2(0.8, 0.5), 0.0, r.uniform(0.0, M_PI));
            }
        }
      }
    // Columns and tables inside the corridors, near their walls.
    for (double x : xs)
      for (double y = 10.0; y < sy - 10.0; y += r.uniform(15.0, 30.0))
        b.cylinder(Vec2(x + (r.chance(0.5) ? 0.5 : w - 0.5), y), 0.0, 0.25, h, C::kPole, 0.1);
    for (double y : ys)
      for (double x = 10.0; x < sx - 10.0; x += r.uniform(15.0, 30.0))
        b.table(Vec2(x, y + (r.chance(0.5) ? 0.55 : w - 0.55)), Vec2(0.6, 0.3), 0.0, 0.0);
    for (std::size_t k = 0; k < 3; ++k) {
      MovingObject m;
      m.path = {Vec2(xs[0] + 2.0, ys[k] + 2.0), Vec2(xs[3] + 2.0, ys[k] + 2.0)};
      m.loop = true;
      m.start_s = 20.0 * k;
      s.moving.push_back(m);
    }
    return std::make_pair(Vec2(xs[0] + 2.0, ys[0] + 2.0), Vec2(xs[3] + 2.0, ys[1] + 2.0));
  });
}

}  // namespace navaid::simulation::scenarios
