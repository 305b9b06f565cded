// ContactMonitor: the body's parts and the swept cane against known obstacles; a contact counts
// once when it begins; the cane finds what reaches the ground and misses what hangs at head height.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/body_contacts.hpp"

namespace navaid::simulation {
namespace {

Surface surface(SemanticClass c) {
  Surface s;
  s.semantic = c;
  return s;
}

// A low box (0.3 m) at x = 3 and a sign board hanging at 1.3-1.9 m at x = 6, both across y = 0.
World obstacles() {
  World w;
  w.add(Box{SE3(Quat::Identity(), Vec3(3.0, 0, 0.15)), Vec3(0.2, 0.4, 0.15)}, surface(SemanticClass::kTable));
  w.add(Box{SE3(Quat::Identity(), Vec3(6.0, 0, 1.6)), Vec3(0.05, 0.4, 0.3)}, surface(SemanticClass::kTrafficSign));
  return w;
}

TEST(BodyContacts, PartsAndHeightsOfTheObstaclesWalkedInto) {
  const World w = obstacles();
  ContactMonitor monitor(w, 0.0, BodyModel{}, CaneModel{});
  std::vector<Contact> all;
  for (double x = 0; x < 8; x += 0.02)
    for (const auto& c : monitor.update(x, Vec2(x, 0), 0.0, World{})) all.push_back(c);
  ASSERT_EQ(all.size(), 2u);  // each counted once, however long the body stays against it
  EXPECT_EQ(all[0].part, BodyPart::kLegs);
  EXPECT_EQ(all[0].primitive, 0u);
  EXPECT_NEAR(all[0].height_m, 0.5 * (0.15 + 0.3), 1e-9);
  EXPECT_NEAR(all[0].where_W.x(), 3.0 - 0.2 - 0.22, 0.03);  // the body's edge meets the box's face
  EXPECT_EQ(all[1].part, BodyPart::kHead);  // the board spans torso and head: named by the highest
  EXPECT_EQ(all[1].semantic, SemanticClass::kTrafficSign);
  EXPECT_NEAR(all[1].height_m, 0.5 * (1.5 + 1.75), 1e-9);
}

TEST(BodyContacts, TheCaneFindsTheLowBoxAheadButNotTheHangingSign) {
  const World w = obstacles();
  CaneModel cane;
  cane.enabled = true;
  ContactMonitor monitor(w, 0.0, BodyModel{}, cane);
  std::vector<Contact> cane_contacts;
  std::optional<double> first_touch_x;
  for (double x = 0; x < 8; x += 0.02) {
    for (const auto& c : monitor.update(x, Vec2(x, 0), 0.0, World{}))
      if (c.part == BodyPart::kCane) cane_contacts.push_back(c);
    if (monitor.cane_touch() && !first_touch_x) first_touch_x = x;
  }
  ASSERT_EQ(cane_contacts.size(), 1u);
  EXPECT_EQ(cane_contacts[0].primitive, 0u);
  ASSERT_TRUE(first_touch_x);
  EXPECT_NEAR(*first_touch_x, 3.0 - 0.2 - 1.2 - 0.03, 0.03);  // the tip's reach ahead
  EXPECT_GT(cane_contacts[0].where_W.x(), 2.7);                  // where the tip met it
}

TEST(BodyContacts, MovingPeopleAndTheWayAhead) {
  const World w = obstacles();
  ContactMonitor monitor(w, 0.0, BodyModel{}, CaneModel{});
  MovingObject person;
  person.path = {Vec2(1.0, 0.0)};
  const World moving = moving_world({person}, 0.0);
  const auto touches = monitor.update(0.0, Vec2(0.6, 0), 0.0, moving);
  ASSERT_FALSE(touches.empty());
  EXPECT_TRUE(touches.front().moving);
  EXPECT_EQ(touches.front().semantic, SemanticClass::kPerson);
  // Guidance straight on from x = 2.2 walks into the box within 0.7 m; to the side it does not.
  EXPECT_EQ(monitor.blocked_along(Vec2(2.2, 0), 0.0, 0.7), std::optional<std::uint32_t>(0u));
  EXPECT_FALSE(monitor.blocked_along(Vec2(2.2, 0), M_PI / 2, 0.7));
  EXPECT_FALSE(monitor.blocked_along(Vec2(1.0, 0), 0.0, 0.7));
}

TEST(BodyContacts, AStepIntoAnObstacleIsABumpAStepAwayIsNot) {
  World w;
  w.add(Box{SE3(Quat::Identity(), Vec3(0, -1.06, 1.3)), Vec3(10, 0.06, 1.3)}, surface(SemanticClass::kWall));
  ContactMonitor monitor(w, 0.0, BodyModel{}, CaneModel{});
  // Walking south-east toward the wall (its face at y = -1): free until the body is within its
  // radius less the 3 cm give.
  const double heading = -M_PI / 4;
  const Vec2 dir(std::cos(heading), std::sin(heading));
  Vec2 p(2.0, 0.0);
  std::optional<CaneTouch> bump;
  for (int k = 0; k < 400 && !bump; ++k) {
    bump = monitor.bump(p, p + 0.005 * dir, heading);
    if (!bump) p += 0.005 * dir;
  }
  ASSERT_TRUE(bump.has_value());
  EXPECT_NEAR(p.y(), -1.0 + 0.22 - 0.03, 0.01);
  EXPECT_NEAR(bump->bearing_rad, -M_PI / 4, 0.02);  // the wall lies to the south: 45 deg right
  EXPECT_EQ(bump->primitive, 0u);
  // Stepping back or along the wall is free.
  EXPECT_FALSE(monitor.bump(p, p - 0.005 * dir, heading).has_value());
  EXPECT_FALSE(monitor.bump(p, p + Vec2(0.005, 0), 0.0).has_value());
}

TEST(BodyContacts, BadModelsAreNamed) {
  BodyModel b;
  b.head_bottom_m = 2.0;
  const World w;
  EXPECT_THROW(ContactMonitor(w, 0.0, b, CaneModel{}), ConfigError);
  CaneModel c;
  c.enabled = true;
  c.length_m = 5;
  EXPECT_THROW(ContactMonitor(w, 0.0, BodyModel{}, c), ConfigError);
}

}  // namespace
}  // namespace navaid::simulation
