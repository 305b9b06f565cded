// eLabrador evaluation routes (seed elabrador-wearable-outdoor-navigation, Sec. V-A, Fig. 6).
#include <cmath>

#include "scenarios/families.hpp"
#include "scenarios/street_layouts.hpp"

namespace navaid::simulation::scenarios {

namespace {

using C = SemanticClass;

// Buildings along y = y_front (facing the street) between x0 and x1, extending away from the
// street (direction `side`: +1 north, -1 south), with random widths, gaps, depths and heights.
void building_row(SceneBuilder& b, double x0, double x1, double y_front, double side, double h_min, double h_max) {
  Rng& r = b.rng();
  double x = x0;
  while (x < x1 - 6.0) {
    const double w = std::min(r.uniform(12.0, 26.0), x1 - x);
    const double depth = r.uniform(10.0, 16.0), h = r.uniform(h_min, h_max);
    const double y_a = y_front, y_b = y_front + side * depth;
    b.box(Vec3(x, std::min(y_a, y_b), 0.0), Vec3(x + w, std::max(y_a, y_b), h), C::kBuilding, 0.4);
    x += w + r.uniform(3.0, 8.0);
  }
}

// Street trees in pits along a line; a share of them has a low branch reaching `branch_dir`.
void tree_line(SceneBuilder& b, const Vec2& from, const Vec2& to, double spacing, double low_share, const Vec2& branch_dir,
               Scenario& s) {
  Rng& r = b.rng();
  const double len = (to - from).norm();
  const Vec2 dir = (to - from) / len;
  for (double d = 0.0; d <= len; d += spacing) {
    const Vec2 p = from + (d + r.uniform(-0.8, 0.8)) * dir;
    std::vector<Vec2> branches;
    if (r.chance(low_share)) branches.push_back(r.uniform(1.3, 1.7) * branch_dir);
    b.tree(p, 0.0, r.uniform(2.6, 3.2), r.uniform(2.0, 2.6), branches, &s.deliberate_obstacles);
  }
}

}  // namespace

// Route 1: start at the residential gate (0, 32), walk south to the main street, turn left (east)
// and walk 240 m along its north sidewalk to the park landmark at x = 240.
void build_route1(Scenario& s, Rng& rng) {
  SceneBuilder b(s.world, rng);
  s.kind = ScenarioKind::kWalk;
  s.default_mount = "head";
  s.origin = {30.274100, 120.155100, 15.0};
  s.ground_z_m = 0.0;
  s.path = {Vec2(0.0, 32.0), Vec2(0.0, 0.0), Vec2(240.0, 0.0)};
  s.extent.extend(Vec3(-30.0, -40.0, -0.16));
  s.extent.extend(Vec3(270.0, 60.0, 32.0));

  const double road_z = -0.15;
  b.horizontal_patch(Vec2(-30.0, -40.0), Vec2(270.0, 60.0), road_z - 0.01, C::kTerrain, 0.5);
  b.horizontal_patch(Vec2(-30.0, -9.5), Vec2(270.0, -1.5), road_z, C::kRoad, 0.3);   // main street
  b.horizontal_patch(Vec2(-9.5, -1.5), Vec2(-1.5, 60.0), road_z, C::kRoad, 0.3);    // side street
  b.sidewalk(Vec2(-1.5, -1.5), Vec2(250.0, 1.5), 0.0, 0.15);                          // main sidewalk
  b.sidewalk(Vec2(-1.5, 1.5), Vec2(1.5, 36.0), 0.0, 0.15);                            // walkway south from the gate
  b.sidewalk(Vec2(-30.0, -14.5), Vec2(270.0, -9.5), 0.0, 0.15);                       // south sidewalk
  b.curb(Vec2(-1.5, -1.5), Vec2(250.0, -1.5), road_z, 0.0);
  b.curb(Vec2(-1.5, -1.5), Vec2(-1.5, 36.0), road_z, 0.0);
  b.curb(Vec2(-30.0, -9.5), Vec2(270.0, -9.5), road_z, 0.0);
  b.horizontal_patch(Vec2(1.5, 1.5), Vec2(236.0, 4.5), 0.0, C::kTerrain, 0.3);        // verge north of the sidewalk
  b.horizontal_patch(Vec2(1.5, 4.5), Vec2(4.5, 36.0), 0.0, C::kTerrain, 0.3);

  // Residential gate at the start: compound fence with an opening and a small name board.
  b.box(Vec3(1.8, 36.0, 0.0), Vec3(30.0, 36.3, 2.0), C::kFence, 0.1);
  b.box(Vec3(-9.5, 36.0, 0.0), Vec3(-1.8, 36.3, 2.0), C::kFence, 0.1);
  b.landmark(Vec2(0.0, 37.0), 0.0, 3.0, M_PI / 2);

  // Tall residential towers beside the walkway and across the side street (a street canyon),
  // then a row of mixed buildings along the main street and across it.
  b.box(Vec3(6.0, 8.0, 0.0), Vec3(20.0, 20.0, 30.0), C::kBuilding, 0.4);
  b.box(Vec3(6.0, 23.0, 0.0), Vec3(20.0, 34.0, 27.0), C::kBuilding, 0.4);
  b.box(Vec3(-26.0, 4.0, 0.0), Vec3(-12.0, 20.0, 24.0), C::kBuilding, 0.4);
  b.box(Vec3(-26.0, 23.0, 0.0), Vec3(-12.0, 38.0, 28.0), C::kBuilding, 0.4);
  building_row(b, 24.0, 230.0, 6.0, 1.0, 6.0, 24.0);
  building_row(b, -28.0, 262.0, -17.0, -1.0, 6.0, 24.0);

  // Street trees in pits beside the curb (0.95 m from the path); about a quarter of them have a
  // low branch reaching over the walking line: the deliberate head-height obstacles of Fig. 6-B.
  tree_line(b, Vec2(6.0, -0.95), Vec2(232.0, -0.95), 8.0, 0.25, Vec2(0.0, 1.0), s);
  tree_line(b, Vec2(-0.95, 6.0), Vec2(-0.95, 30.0), 8.0, 0.25, Vec2(1.0, 0.0), s);

  // Lamp poles (some with signs) at the curb, benches on the verge side.
  for (double x = 15.0; x < 235.0; x += 30.0) b.pole(Vec2(x, -1.25), 0.0, 5.0, rng.chance(0.4), 0.0);
  for (double x = 34.0; x < 230.0; x += 45.0) b.bench(Vec2(x, 1.15), 0.0, 0.0);
  for (double x = 10.0; x < 250.0; x += rng.uniform(18.0, 40.0)) b.car(Vec2(x, -2.6), road_z, 0.0);

  // Tactile paving along the walking line in 10 m pieces, sometimes missing (always at the turn).
  for (double y = 36.0; y > 6.0; y -= 10.0)
    if (rng.chance(0.8)) b.tactile_strip(Vec2(0.0, y), Vec2(0.0, std::max(y - 10.0, 6.0)), 0.0);
  for (double x = 6.0; x < 250.0; x += 10.0)
    if (rng.chance(0.8)) b.tactile_strip(Vec2(x, 0.0), Vec2(std::min(x + 10.0, 250.0), 0.0), 0.0);

  // The wayside park and its landmark slogan board ("Honoring the Pioneers of Science"), which the
  // walker faces at the end of the route.
  b.horizontal_patch(Vec2(236.0, 1.5), Vec2(270.0, 40.0), 0.0, C::kTerrain, 0.3);
  b.landmark(Vec2(240.0, 3.6), 0.0, 3.0, M_PI / 2);
  for (int i = 0; i < 12; ++i) {
    const double y = rng.uniform(8.0, 38.0);  // y before x (random_draws.hpp: the order of record)
    b.tree(Vec2(rng.uniform(240.0, 268.0), y), 0.0, 3.0, 2.4);
  }

  // People on the sidewalks and crossing the street; traffic on both lanes.
  auto person = [&](std::vector<Vec2> path, double speed, double start) {
    s.moving.push_back(looping_person(std::move(path), speed, start, rng.uniform(1.55, 1.85)));
  };
  person({Vec2(200.0, 0.55), Vec2(20.0, 0.55)}, 1.3, 0.0);
  person({Vec2(30.0, -0.4), Vec2(230.0, -0.4)}, 1.0, 10.0);
  person({Vec2(0.7, 30.0), Vec2(0.7, 3.0)}, 1.2, 5.0);
  person({Vec2(120.0, 1.0), Vec2(120.0, -13.0)}, 1.1, 20.0);
  for (double y : {-4.0, -7.5})
    s.moving.push_back(looping_car(
        y < -5.0 ? std::vector<Vec2>{Vec2(265.0, y), Vec2(-25.0, y)} : std::vector<Vec2>{Vec2(-25.0, y), Vec2(265.0, y)},
        8.0, 0.0));
}

// Route 2: from the Cultural Activities Center (0, 0) 300 m straight east to the residential
// entrance ("Kexing Unit"), crossing two T-junctions without tactile paving and passing a
// bus-stop pavilion through a narrow passage.
void build_route2(Scenario& s, Rng& rng) {
  SceneBuilder b(s.world, rng);
  s.kind = ScenarioKind::kWalk;
  s.default_mount = "head";
  s.origin = {30.270500, 120.161800, 14.0};
  s.ground_z_m = 0.0;
  s.path = {Vec2(0.0, 0.0), Vec2(300.0, 0.0)};
  s.extent.extend(Vec3(-30.0, -35.0, -0.13));
  s.extent.extend(Vec3(330.0, 60.0, 30.0));

  const double road_z = -0.12;  // the low step at each sidewalk end
  const double junctions[] = {88.0, 188.0};  // west edge of each 8 m side street
  b.horizontal_patch(Vec2(-30.0, -35.0), Vec2(330.0, 60.0), road_z - 0.01, C::kTerrain, 0.5);
  b.horizontal_patch(Vec2(-30.0, -10.0), Vec2(330.0, -2.0), road_z, C::kRoad, 0.3);
  double x = -10.0;
  for (double j : junctions) {
    b.horizontal_patch(Vec2(j, -2.0), Vec2(j + 8.0, 60.0), road_z, C::kRoad, 0.3);
    b.sidewalk(Vec2(x, -2.0), Vec2(j, 2.0), 0.0, 0.12);
    b.curb(Vec2(x, -2.0), Vec2(j, -2.0), road_z, 0.0);
    b.curb(Vec2(j, -2.0), Vec2(j, 2.0), road_z, 0.0);  // the step down
    if (x > -10.0) b.curb(Vec2(x, -2.0), Vec2(x, 2.0), road_z, 0.0);  // the step up
    for (double y : {-1.5, -0.5, 0.5, 1.5})  // zebra stripes, no tactile paving at the crossing
      b.horizontal_patch(Vec2(j + 0.3, y - 0.25), Vec2(j + 7.7, y + 0.25), road_z + 0.005, C::kCrosswalk, 0.5);
    x = j + 8.0;
  }
  b.sidewalk(Vec2(x, -2.0), Vec2(320.0, 2.0), 0.0, 0.12);
  b.curb(Vec2(x, -2.0), Vec2(320.0, -2.0), road_z, 0.0);
  b.curb(Vec2(x, -2.0), Vec2(x, 2.0), road_z, 0.0);
  b.sidewalk(Vec2(-30.0, -15.0), Vec2(330.0, -10.0), 0.0, 0.12);
  b.curb(Vec2(-30.0, -10.0), Vec2(330.0, -10.0), road_z, 0.0);
  // Tactile paving along the walking line, stopping 4 m before each junction.
  b.tactile_strip(Vec2(2.0, 0.0), Vec2(84.0, 0.0), 0.0);
  b.tactile_strip(Vec2(100.0, 0.0), Vec2(184.0, 0.0), 0.0);
  b.tactile_strip(Vec2(200.0, 0.0), Vec2(296.0, 0.0), 0.0);

  // The Cultural Activities Center behind the start, buildings along both sides.
  b.box(Vec3(-25.0, 6.0, 0.0), Vec3(15.0, 30.0, 14.0), C::kBuilding, 0.4);
  building_row(b, 20.0, 86.0, 6.0, 1.0, 8.0, 26.0);
  building_row(b, 100.0, 186.0, 6.0, 1.0, 8.0, 26.0);
  building_row(b, 200.0, 228.0, 6.0, 1.0, 8.0, 26.0);
  building_row(b, -28.0, 328.0, -18.0, -1.0, 8.0, 26.0);

  // Trees and poles at the curb, kept clear of the junctions and the bus stop.
  for (double tx = 8.0; tx < 296.0; tx += 9.0) {
    const bool near_junction = (tx > 84.0 && tx < 100.0) || (tx > 184.0 && tx < 200.0);
    if (near_junction || (tx > 226.0 && tx < 256.0)) continue;
    // Drawn last argument first (random_draws.hpp: the order of record).
    const double crown_radius = rng.uniform(1.8, 2.4);
    const double crown_bottom_z = rng.uniform(2.7, 3.3);
    b.tree(Vec2(tx + rng.uniform(-0.5, 0.5), -1.35), 0.0, crown_bottom_z, crown_radius);
  }
  for (double px = 20.0; px < 296.0; px += 36.0)
    if (!((px > 84.0 && px < 100.0) || (px > 184.0 && px < 200.0) || (px > 226.0 && px < 256.0)))
      b.pole(Vec2(px, -1.6), 0.0, 5.0, rng.chance(0.5), 0.0);

  // Bus-stop pavilion on the curb side and a hedge opposite: a 1.2 m passage (path 0.6 m from both).
  b.bus_stop(236.0, 246.0, -0.6, -1.9, 0.0);
  b.box(Vec3(230.0, 0.6, 0.0), Vec3(252.0, 1.4, 1.2), C::kVegetation, 0.1);
  MovingObject waiting;
  waiting.path = {Vec2(243.0, -1.4)};
  waiting.height_m = 1.65;
  s.moving.push_back(waiting);

  // Entrance of the residential community: fence with a gate and the name board ("Kexing Unit").
  b.box(Vec3(256.0, 3.0, 0.0), Vec3(296.5, 3.3, 1.8), C::kFence, 0.1);
  b.box(Vec3(303.5, 3.0, 0.0), Vec3(320.0, 3.3, 1.8), C::kFence, 0.1);
  b.landmark(Vec2(300.0, 4.2), 0.0, 4.0, M_PI / 2);
  b.box(Vec3(262.0, 12.0, 0.0), Vec3(290.0, 30.0, 24.0), C::kBuilding, 0.4);
  b.box(Vec3(306.0, 12.0, 0.0), Vec3(326.0, 34.0, 21.0), C::kBuilding, 0.4);

  // Pedestrians crossing the junctions on the crosswalks and walking along; cars turning through
  // the junctions (they cross the crosswalks) and traffic on the main road.
  auto person = [&](std::vector<Vec2> path, double speed, double start) {
    s.moving.push_back(looping_person(std::move(path), speed, start, rng.uniform(1.55, 1.85)));
  };
  for (double j : junctions) {
    person({Vec2(j + 14.0, 0.8), Vec2(j - 6.0, 0.8)}, 1.1, 0.1 * j);
    person({Vec2(j + 1.0, 30.0), Vec2(j + 1.0, -14.0)}, 1.2, 0.05 * j);
  }
  person({Vec2(280.0, -0.9), Vec2(120.0, -0.9)}, 1.25, 0.0);
  auto car = [&](std::vector<Vec2> path, double speed, double start) {
    s.moving.push_back(looping_car(std::move(path), speed, start));
  };
  car({Vec2(junctions[0] + 4.0, 50.0), Vec2(junctions[0] + 4.0, -4.5)}, 5.0, 0.0);
  car({Vec2(junctions[1] + 4.0, -4.5), Vec2(junctions[1] + 4.0, 50.0)}, 5.0, 6.0);
  car({Vec2(-25.0, -4.5), Vec2(325.0, -4.5)}, 9.0, 0.0);
  car({Vec2(325.0, -8.0), Vec2(-25.0, -8.0)}, 9.0, 3.0);
}

// Street layouts (centre lines of the slabs and road patches built above; the test
// OsmExport.LayoutsLieOnTheWorldsSurfaces checks them against the worlds).
StreetMap route1_streets() {
  StreetMap m;
  m.sidewalks = {{Vec2(0.0, 36.0), Vec2(0.0, 0.0)},        // walkway south from the gate, x in [-1.5, 1.5]
                 {Vec2(0.0, 0.0), Vec2(250.0, 0.0)},       // north sidewalk of the main street, y in [-1.5, 1.5]
                 {Vec2(-30.0, -12.0), Vec2(270.0, -12.0)}};  // south sidewalk, y in [-14.5, -9.5] (no crossing to it)
  StreetRoad main{{Vec2(-30.0, -5.5), Vec2(270.0, -5.5)}, "Route 1 Main Street", "residential",
                  {{"sidewalk", "separate"}, {"foot", "use_sidepath"}}};
  // Drawn south to north: the gate walkway runs along its right (east) side.
  StreetRoad side{{Vec2(-5.5, -5.5), Vec2(-5.5, 60.0)}, "Route 1 Side Street", "residential",
                  {{"sidewalk:right", "separate"}, {"sidewalk:left", "no"}}};
  m.roads = {main, side};
  m.landmarks = {{Vec2(240.0, 3.6), "Honoring the Pioneers of Science",
                  {{"amenity", "notice_board"}, {"tourism", "information"}, {"information", "board"}}}};
  m.goal_landmark = 0;
  return m;
}

StreetMap route2_streets() {
  StreetMap m;
  m.sidewalks = {{Vec2(-10.0, 0.0), Vec2(88.0, 0.0)},
                 {Vec2(96.0, 0.0), Vec2(188.0, 0.0)},
                 {Vec2(196.0, 0.0), Vec2(320.0, 0.0)},          // north sidewalk, y in [-2, 2], cut by the junctions
                 {Vec2(-30.0, -12.5), Vec2(330.0, -12.5)}};      // south sidewalk, y in [-15, -10] (no crossing to it)
  // Zebra crossings over the side streets: no signals, no tactile paving, the 0.12 m low step
  // (road_z in build_route2) at each sidewalk end.
  for (double j : {88.0, 188.0})
    m.crossings.push_back({Vec2(j, 0.0), Vec2(j + 8.0, 0.0), CrossingControl::kUncontrolled, false, "zebra", 0.12});
  m.roads = {{{Vec2(-30.0, -6.0), Vec2(330.0, -6.0)}, "Route 2 Main Road", "residential",
              {{"sidewalk", "separate"}, {"foot", "use_sidepath"}}},
             {{Vec2(92.0, -6.0), Vec2(92.0, 60.0)}, "Route 2 First Side Street", "residential", {{"sidewalk", "no"}}},
             {{Vec2(192.0, -6.0), Vec2(192.0, 60.0)}, "Route 2 Second Side Street", "residential", {{"sidewalk", "no"}}}};
  m.landmarks = {{Vec2(0.0, 6.5), "Cultural Activities Center", {{"amenity", "community_centre"}}},
                 {Vec2(241.0, -1.25), "", {{"highway", "bus_stop"}, {"amenity", "shelter"}, {"shelter_type", "public_transport"}}},
                 {Vec2(300.0, 4.2), "Kexing Unit",
                  {{"amenity", "notice_board"}, {"tourism", "information"}, {"information", "board"}}}};
  m.goal_landmark = 2;
  return m;
}

}  // namespace navaid::simulation::scenarios
