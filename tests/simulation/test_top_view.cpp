#include "navaid/simulation/top_view.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::simulation {
namespace {

std::array<std::uint8_t, 3> rgb(const TopView& v, const Vec2& p) {
  const Eigen::Vector2i px = v.pixel(p);
  return {v.image.at(px.x(), px.y(), 0), v.image.at(px.x(), px.y(), 1), v.image.at(px.x(), px.y(), 2)};
}

std::array<std::uint8_t, 3> scaled(SemanticClass c, double shade) {
  std::array<std::uint8_t, 3> out{};
  for (std::size_t i = 0; i < 3; ++i)
    out[i] = static_cast<std::uint8_t>(std::lround(shade * semantic_class_info(c).rgb[i]));
  return out;
}

// Road plane at z = 0, a car box 1.5 m high, a ceiling above everything (hidden by default).
World street_block() {
  World w;
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 0)), 10, 10}, Surface{SemanticClass::kRoad});
  w.add(Box{SE3(Quat::Identity(), Vec3(2, 3, 0.75)), Vec3(1, 1, 0.75)}, Surface{SemanticClass::kCar});
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 3.0)), 10, 10}, Surface{SemanticClass::kCeiling});
  return w;
}

TEST(TopView, ClassColoursShadedByHeight) {
  const RayCaster caster(street_block());
  TopViewOptions o;
  o.metres_per_pixel = 0.25;
  o.region = std::make_pair(Vec2(-12, -12), Vec2(12, 12));
  o.scale_bar = false;
  const TopView v = render_top_view(caster, o);
  EXPECT_EQ(v.image.width, 96);
  EXPECT_EQ(v.image.height, 96);
  EXPECT_EQ(v.image.channels, 3);
  EXPECT_EQ(rgb(v, Vec2(2, 3)), scaled(SemanticClass::kCar, 1.0));     // highest surface: full colour
  EXPECT_EQ(rgb(v, Vec2(-5, -5)), scaled(SemanticClass::kRoad, 0.6));  // lowest surface: 60 %
  EXPECT_EQ(rgb(v, Vec2(-11, 11)), o.background);                      // outside the world
  // Pixel geometry: the top-left pixel holds the region's (x min, y max) corner.
  EXPECT_EQ(v.pixel(Vec2(-12 + 0.1, 12 - 0.1)), Eigen::Vector2i(0, 0));
  EXPECT_EQ(v.pixel(Vec2(2, 3)), Eigen::Vector2i(56, 36));

  // Without hiding the ceiling, only the ceiling is seen.
  o.hidden_classes.clear();
  const TopView c = render_top_view(caster, o);
  EXPECT_EQ(rgb(c, Vec2(2, 3)), rgb(c, Vec2(-5, -5)));
  EXPECT_EQ(rgb(c, Vec2(2, 3)), scaled(SemanticClass::kCeiling, 1.0));  // one height: full colour
}

TEST(TopView, OverlaysPathMarkersAndScaleBar) {
  const RayCaster caster(street_block());
  TopViewOptions o;
  o.metres_per_pixel = 0.1;
  o.path = {Vec2(-8, -5), Vec2(-8, 8), Vec2(8, 8)};
  const TopView v = render_top_view(caster, o);  // region: world bounds + 1 m
  EXPECT_EQ(v.image.width, 220);
  const auto mid = rgb(v, Vec2(-8, 0));
  EXPECT_GT(mid[2], 200);  // blue path
  EXPECT_LT(mid[0], 60);
  const auto start = rgb(v, Vec2(-8, -5)), goal = rgb(v, Vec2(8, 8));
  EXPECT_GT(start[1], 150);  // green start
  EXPECT_LT(start[0], 30);
  EXPECT_GT(goal[0], 200);   // red goal
  EXPECT_LT(goal[1], 30);
  // Scale bar: a 2 m (20 px) black bar in the bottom-right corner on a white box.
  EXPECT_EQ(v.image.at(v.image.width - 12, v.image.height - 11, 0), 0);
  EXPECT_EQ(v.image.at(v.image.width - 12, v.image.height - 6, 0), 255);
  EXPECT_EQ(v.image.at(v.image.width - 30, v.image.height - 11, 0), 0);
  EXPECT_EQ(v.image.at(v.image.width - 31, v.image.height - 11, 0), 255);
}

TEST(TopView, ScenarioMapShowsItsSurfaces) {
  const Scenario s = make_scenario("corridor");
  const RayCaster caster(s.world);
  TopViewOptions o;
  o.metres_per_pixel = 0.05;
  const TopView v = render_top_view(caster, o);
  // The low box in the corridor sits on the left half near x = 2.5 (unlabeled: black).
  EXPECT_EQ(rgb(v, Vec2(2.5, 0.6)), scaled(SemanticClass::kUnlabeled, 1.0));
  const auto floor = rgb(v, Vec2(0.5, -0.5));
  EXPECT_EQ(floor, scaled(SemanticClass::kFloor, 0.6));
}

TEST(TopView, RejectsBadOptions) {
  const RayCaster caster(street_block());
  TopViewOptions o;
  o.metres_per_pixel = 0.0;
  EXPECT_THROW(render_top_view(caster, o), Error);
  o.metres_per_pixel = 0.001;
  EXPECT_THROW(render_top_view(caster, o), Error);  // > 8192 px
  o.metres_per_pixel = 0.1;
  o.region = std::make_pair(Vec2(1, 1), Vec2(1, 5));
  EXPECT_THROW(render_top_view(caster, o), Error);
}

}  // namespace
}  // namespace navaid::simulation
