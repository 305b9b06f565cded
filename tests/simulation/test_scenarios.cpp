#include "navaid/simulation/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

// Every scenario is built once per test program (school takes ~0.5 s).
const Scenario& scenario(const std::string& name) {
  static std::map<std::string, Scenario> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, make_scenario(name)).first;
  return it->second;
}

bool same_world(const World& a, const World& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Surface& sa = a.primitives()[i].surface;
    const Surface& sb = b.primitives()[i].surface;
    if (sa.semantic != sb.semantic || sa.texture_seed != sb.texture_seed || sa.texture_scale != sb.texture_scale ||
        sa.albedo != sb.albedo)
      return false;
  }
  const TriangleMesh ma = a.triangulate(), mb = b.triangulate();
  if (ma.vertices.size() != mb.vertices.size() || ma.triangles != mb.triangles) return false;
  for (std::size_t i = 0; i < ma.vertices.size(); ++i)
    if (ma.vertices[i] != mb.vertices[i]) return false;
  return true;
}

Vec2 direction(const Vec2& a, const Vec2& b) { return (b - a).normalized(); }

TEST(Scenarios, NamesAreStableAndEveryScenarioBuilds) {
  const std::vector<std::string> expected = {"route1",     "route2",     "corridor",   "obstacle-course", "lab-walk-1",
                                             "lab-walk-2", "lab-walk-3", "lab-walk-4", "lab-walk-5",      "office1",
                                             "office2",    "pillar",     "school"};
  ASSERT_EQ(scenario_names(), expected);
  for (const std::string& name : expected) {
    SCOPED_TRACE(name);
    const Scenario& s = scenario(name);
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.description.empty());
    EXPECT_EQ(s.seed, default_scenario_seed(name));
    EXPECT_GT(s.world.size(), 5u);
    ASSERT_GE(s.path.size(), 2u);
    EXPECT_FALSE(s.extent.empty);
    EXPECT_TRUE(s.default_mount == "head" || s.default_mount == "cane" || s.default_mount == "hand");
    const bool planner = name == "office1" || name == "office2" || name == "pillar" || name == "school";
    EXPECT_EQ(s.kind, planner ? ScenarioKind::kPlannerMap : ScenarioKind::kWalk);
    for (const Vec2& p : s.path) {  // the path lies inside the documented extent
      EXPECT_GE(p.x(), s.extent.min.x());
      EXPECT_LE(p.x(), s.extent.max.x());
      EXPECT_GE(p.y(), s.extent.min.y());
      EXPECT_LE(p.y(), s.extent.max.y());
    }
    EXPECT_TRUE(std::abs(s.origin.latitude_deg) > 1.0 && std::abs(s.origin.longitude_deg) > 1.0);
  }
}

TEST(Scenarios, UnknownNameListsTheKnownOnes) {
  const auto e = testing::expect_throw<ConfigError>([] { make_scenario("route3"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "scenario");
  const std::string what = e->what();
  EXPECT_NE(what.find("route3"), std::string::npos);
  for (const std::string& name : scenario_names()) EXPECT_NE(what.find(name), std::string::npos) << name;
  EXPECT_THROW(default_scenario_seed("nope"), ConfigError);
}

TEST(Scenarios, Route1IsThirtyMetresSouthThenALeftTurnAndTwoHundredFortyEast) {
  const Scenario& s = scenario("route1");
  EXPECT_NEAR(polyline_length(s.path), 270.0, 10.0);
  ASSERT_EQ(s.path.size(), 3u);
  const Vec2 d1 = direction(s.path[0], s.path[1]), d2 = direction(s.path[1], s.path[2]);
  EXPECT_NEAR(d1.y(), -1.0, 1e-12);                       // south
  EXPECT_NEAR(d2.x(), 1.0, 1e-12);                        // east
  EXPECT_GT(d1.x() * d2.y() - d1.y() * d2.x(), 0.9);     // counter-clockwise: a left turn
  EXPECT_NEAR((s.path[1] - s.path[0]).norm(), 30.0, 3.0);
  EXPECT_NEAR((s.path[2] - s.path[1]).norm(), 240.0, 1e-9);
  EXPECT_EQ(s.default_mount, "head");
}

TEST(Scenarios, Route2IsThreeHundredMetresStraight) {
  const Scenario& s = scenario("route2");
  EXPECT_NEAR(polyline_length(s.path), 300.0, 10.0);
  const Vec2 d = direction(s.path.front(), s.path.back());
  for (const Vec2& p : s.path) EXPECT_LT(std::abs((p - s.path.front()).x() * d.y() - (p - s.path.front()).y() * d.x()), 0.5);
  // Two zebra crossings (4 stripes each) on the walking line, and no tactile paving on them.
  std::set<long> crossings;
  for (const Primitive& p : s.world.primitives()) {
    const AxisAlignedBox b = bounds_of(p.shape);
    if (p.surface.semantic == SemanticClass::kCrosswalk && b.min.y() > -2.0 && b.max.y() < 2.0)
      crossings.insert(std::lround(b.min.x()));
    if (p.surface.semantic != SemanticClass::kTactilePaving) continue;
    for (const Primitive& q : s.world.primitives())
      if (q.surface.semantic == SemanticClass::kCrosswalk) {
        const AxisAlignedBox c = bounds_of(q.shape);
        EXPECT_TRUE(b.max.x() < c.min.x() || b.min.x() > c.max.x());
      }
  }
  EXPECT_EQ(crossings.size(), 2u);
  for (long x : crossings) EXPECT_TRUE(x > s.path.front().x() && x < s.path.back().x());
}

TEST(Scenarios, RoomAndLabDimensions) {
  auto size = [](const Scenario& s) { return Vec3(s.extent.max - s.extent.min); };
  EXPECT_TRUE(size(scenario("corridor")).head<2>().isApprox(Vec2(10.0, 2.0)));
  EXPECT_NEAR(scenario("corridor").path.back().x() - scenario("corridor").path.front().x(), 10.0, 1e-9);
  EXPECT_EQ(scenario("corridor").default_mount, "cane");
  EXPECT_TRUE(size(scenario("obstacle-course")).head<2>().isApprox(Vec2(10.0, 10.0)));
  const double course = polyline_length(scenario("obstacle-course").path);
  EXPECT_TRUE(course >= 15.0 && course <= 25.0) << course;
  EXPECT_EQ(scenario("obstacle-course").path.size(), 5u);  // three turns
  for (int k = 1; k <= 5; ++k) {
    const Scenario& s = scenario("lab-walk-" + std::to_string(k));
    const double len = polyline_length(s.path);
    if (k <= 3) {
      EXPECT_TRUE(len >= 20.0 && len <= 30.0) << k << ": " << len;
    } else {
      EXPECT_TRUE(len >= 60.0 && len <= 90.0) << k << ": " << len;
    }
    EXPECT_EQ(s.default_mount, "hand");
    // Walls are finely textured for feature tracking.
    for (const Primitive& p : s.world.primitives())
      if (p.surface.semantic == SemanticClass::kWall) {
        EXPECT_LE(p.surface.texture_scale, 0.2);
      }
  }
}

TEST(Scenarios, PlannerMapExtentsAndPaths) {
  for (const char* name : {"office1", "office2", "pillar"}) {
    const Scenario& s = scenario(name);
    EXPECT_TRUE(Vec3(s.extent.max - s.extent.min).isApprox(Vec3(40.0, 40.0, 4.5))) << name;
    EXPECT_GT(polyline_length(s.path), (s.path.back() - s.path.front()).norm() - 1e-9) << name;
    EXPECT_GT(polyline_length(s.path), 20.0) << name;
  }
  const Scenario& school = scenario("school");
  EXPECT_TRUE(Vec3(school.extent.max - school.extent.min).isApprox(Vec3(250.0, 150.0, 5.0)));
  EXPECT_GT(polyline_length(school.path), 200.0);
  // The world stays inside the documented extent (walls may stick out by their half thickness).
  for (const char* name : {"office1", "pillar", "school"}) {
    const AxisAlignedBox b = scenario(name).world.bounds();
    EXPECT_TRUE((b.min.array() >= scenario(name).extent.min.array() - 0.11).all()) << name;
    EXPECT_TRUE((b.max.array() <= scenario(name).extent.max.array() + 0.11).all()) << name;
  }
}

TEST(Scenarios, PathsKeepClearanceExceptAtDeliberateObstacles) {
  for (const std::string& name : scenario_names()) {
    SCOPED_TRACE(name);
    const Scenario& s = scenario(name);
    EXPECT_GE(path_clearance(s.world, s.path, s.ground_z_m, 0.1, {}, s.deliberate_obstacles), 0.3);
    // The walker's eye/camera (up to 1.8 m) never starts inside or against a primitive.
    EXPECT_GE(horizontal_clearance(s.world, s.path.front(), s.ground_z_m, {0.2, 1.8}), 0.3);
  }
  // Route 1's low branches and the course's head-high obstacle really are in the way.
  for (const char* name : {"route1", "obstacle-course"}) {
    const Scenario& s = scenario(name);
    EXPECT_FALSE(s.deliberate_obstacles.empty()) << name;
    EXPECT_LT(path_clearance(s.world, s.path, s.ground_z_m), 0.3) << name;
  }
  EXPECT_TRUE(scenario("corridor").deliberate_obstacles.empty());
}

TEST(Scenarios, ClearanceKnownAnswers) {
  World w;
  w.add(VerticalCylinder{Vec3(0, 0, 0), 0.5, 1.0}, Surface{});
  w.add(Box{SE3(quat_from_rpy(0, 0, 0.5), Vec3(10, 0, 3.0)), Vec3(1, 1, 0.5)}, Surface{});  // above the band
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 0)), 50, 50}, Surface{});             // ground
  EXPECT_NEAR(horizontal_clearance(w, Vec2(2.0, 0.0), 0.0), 1.5, 1e-12);
  EXPECT_EQ(horizontal_clearance(w, Vec2(0.1, 0.0), 0.0), 0.0);
  EXPECT_NEAR(horizontal_clearance(w, Vec2(10.0, 0.0), 0.0), 9.5, 1e-12);  // the box is above 2 m
  EXPECT_EQ(horizontal_clearance(w, Vec2(2.0, 0.0), 0.0, {0.2, 2.0}, {0}), std::numeric_limits<double>::infinity());
  EXPECT_NEAR(path_clearance(w, {Vec2(-3, 1), Vec2(3, 1)}, 0.0), 0.5, 1e-12);
}

TEST(Scenarios, SameSeedSameWorldDifferentSeedDifferentPlannerMap) {
  for (const char* name : {"route1", "office1", "lab-walk-2"}) {
    const Scenario again = make_scenario(name);
    EXPECT_TRUE(same_world(again.world, scenario(name).world)) << name;
    EXPECT_EQ(again.path, scenario(name).path) << name;
  }
  for (const char* name : {"office1", "office2", "pillar"}) {
    ScenarioOptions o;
    o.seed = 7;
    const Scenario other = make_scenario(name, o);
    EXPECT_EQ(other.seed, 7u);
    EXPECT_FALSE(same_world(other.world, scenario(name).world)) << name;
    EXPECT_GE(path_clearance(other.world, other.path, 0.0), 0.3) << name;
  }
}

TEST(Scenarios, PeopleAndVehiclesAreSwitchable) {
  ScenarioOptions no_people;
  no_people.people = false;
  ScenarioOptions nobody = no_people;
  nobody.vehicles = false;
  const Scenario& full = scenario("route2");
  const Scenario a = make_scenario("route2", no_people), b = make_scenario("route2", nobody);
  EXPECT_TRUE(same_world(a.world, full.world));
  int people = 0, cars = 0;
  for (const MovingObject& m : full.moving) (m.kind == MovingKind::kPerson ? people : cars)++;
  EXPECT_GE(people, 3);
  EXPECT_GE(cars, 2);
  EXPECT_EQ(a.moving.size(), static_cast<std::size_t>(cars));
  EXPECT_TRUE(b.moving.empty());
  for (const char* name : {"route1", "lab-walk-1", "office1"}) EXPECT_FALSE(scenario(name).moving.empty()) << name;
}

TEST(MovingObjects, PiecewiseLinearKnownAnswers) {
  MovingObject m;
  m.path = {Vec2(0, 0), Vec2(10, 0), Vec2(10, 5)};
  m.speed_mps = 2.0;
  m.start_s = 1.0;
  EXPECT_EQ(moving_position(m, 0.0), Vec2(0, 0));
  EXPECT_TRUE(moving_position(m, 3.0).isApprox(Vec2(4, 0)));
  EXPECT_TRUE(moving_position(m, 7.0).isApprox(Vec2(10, 2)));
  EXPECT_TRUE(moving_heading(m, 7.0).isApprox(Vec2(0, 1)));
  EXPECT_EQ(moving_position(m, 100.0), Vec2(10, 5));  // stops at the end
  m.loop = true;                                       // closed: back along the diagonal to the start
  const double perimeter = 15.0 + std::hypot(10.0, 5.0);
  EXPECT_LT((moving_position(m, 5.0 + perimeter / 2.0) - Vec2(8, 0)).norm(), 1e-9);  // one lap later
  EXPECT_TRUE(moving_position(m, 1.0 + (15.0 + 0.5 * std::hypot(10.0, 5.0)) / 2.0).isApprox(Vec2(5, 2.5)));
  MovingObject bad;
  EXPECT_THROW(moving_position(bad, 0.0), Error);
  bad.path = {Vec2(0, 0)};
  bad.speed_mps = 0.0;
  EXPECT_THROW(moving_position(bad, 0.0), Error);
}

TEST(MovingObjects, WorldAtTimeHasPeopleAndCarsWhereTheyAre) {
  MovingObject person;
  person.path = {Vec2(0, 0), Vec2(10, 0)};
  MovingObject car;
  car.kind = MovingKind::kCar;
  car.path = {Vec2(0, 5), Vec2(0, 50)};
  car.radius_m = 0.9;
  car.speed_mps = 5.0;
  const World w = moving_world({person, car}, 2.0);
  ASSERT_EQ(w.size(), 4u);
  const auto& body = std::get<VerticalCylinder>(w.primitive(0).shape);
  EXPECT_TRUE(body.base_center.head<2>().isApprox(Vec2(2.4, 0)));
  EXPECT_EQ(w.primitive(0).surface.semantic, SemanticClass::kPerson);
  EXPECT_EQ(w.primitive(1).surface.semantic, SemanticClass::kPerson);
  const auto& car_body = std::get<Box>(w.primitive(2).shape);
  EXPECT_EQ(w.primitive(2).surface.semantic, SemanticClass::kCar);
  EXPECT_TRUE(car_body.T_W_O.t.head<2>().isApprox(Vec2(0, 15)));
  EXPECT_NEAR(yaw_of(car_body.T_W_O.q), M_PI / 2, 1e-12);  // long axis along the motion
  EXPECT_NEAR(car_body.half_extents.y(), 0.9, 1e-12);
}

TEST(MovingObjects, ScenarioPeopleMoveDeterministically) {
  const Scenario& s = scenario("route1");
  const Scenario again = make_scenario("route1");
  ASSERT_EQ(s.moving.size(), again.moving.size());
  for (std::size_t i = 0; i < s.moving.size(); ++i) {
    const MovingObject& m = s.moving[i];
    EXPECT_EQ(moving_position(m, 37.5), moving_position(again.moving[i], 37.5));
    const double t = m.start_s + 5.0;  // 5 s into the first segment (all are longer than 5 s)
    EXPECT_NEAR((moving_position(m, t) - moving_position(m, m.start_s)).norm(), 5.0 * m.speed_mps, 1e-9);
  }
  const World w0 = world_at(s, 0.0), w1 = world_at(s, 10.0);
  EXPECT_EQ(w0.size(), s.world.size() + moving_world(s.moving, 0.0).size());
  EXPECT_FALSE(same_world(w0, w1));
}

TEST(UrbanCanyon, OpenFieldIsZeroStreetCanyonIsKnown) {
  World open;
  open.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 0)), 500, 500}, Surface{});
  EXPECT_EQ(urban_canyon_factor(RayCaster(open), Vec3(0, 0, 1.5)), 0.0);
  // Two 40 m high walls 10 m apart, 600 m long: only the two azimuths along the street see sky at
  // every elevation used (tan 45 deg x 5 m / sin 15 deg < 38.5 m), so 22 of 24 azimuths are blocked.
  World street = open;
  for (double y : {-5.5, 5.5})
    street.add(Box{SE3(Quat::Identity(), Vec3(0, y, 20.0)), Vec3(300.0, 0.5, 20.0)}, Surface{});
  EXPECT_NEAR(urban_canyon_factor(RayCaster(std::move(street)), Vec3(0, 0, 1.5)), 22.0 / 24.0, 1e-12);
  // Route 1: the walkway between the towers is a deeper canyon than the park entrance.
  const RayCaster r1(scenario("route1").world);
  const double canyon = urban_canyon_factor(r1, Vec3(0.0, 15.0, 1.7));
  EXPECT_GT(canyon, 0.4);
  EXPECT_GT(canyon, urban_canyon_factor(r1, Vec3(250.0, 0.0, 1.7)) - 1e-12);
}

}  // namespace
}  // namespace navaid::simulation

namespace navaid::simulation {
namespace {

// The random layout families of the safety study: every seed a different layout, every one
// walkable with the clearance of the default ones, and the default layout untouched by the switch.
TEST(Scenarios, RandomLayoutsDifferBySeedAndKeepThePathClear) {
  for (const char* name : {"corridor", "obstacle-course"}) {
    SCOPED_TRACE(name);
    std::set<std::vector<double>> layouts;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      ScenarioOptions o;
      o.seed = seed;
      o.random_layout = true;
      const Scenario s = make_scenario(name, o);
      SCOPED_TRACE(seed);
      EXPECT_GE(path_clearance(s.world, s.path, s.ground_z_m, 0.1, {}, s.deliberate_obstacles), 0.3);
      EXPECT_GE(horizontal_clearance(s.world, s.path.front(), s.ground_z_m, {0.2, 1.8}), 0.3);
      std::vector<double> where;
      for (std::uint32_t id : s.placed_obstacles) {
        const AxisAlignedBox b = bounds_of(s.world.primitive(id).shape);
        where.push_back(b.min.x());
        where.push_back(b.min.y());
      }
      layouts.insert(where);
    }
    EXPECT_EQ(layouts.size(), 40u);
  }
  ScenarioOptions d;
  d.seed = 5;
  ScenarioOptions r = d;
  r.random_layout = true;
  EXPECT_NE(make_scenario("corridor", d).path, make_scenario("corridor", r).path);
  EXPECT_EQ(make_scenario("route1", d).path, make_scenario("route1", r).path);  // no random family
}

}  // namespace
}  // namespace navaid::simulation
