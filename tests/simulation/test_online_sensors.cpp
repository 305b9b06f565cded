// OnlineSensors: the closed loop's sensors see landmarks wherever the person goes, not only along
// the scenario's path, and the landmarks a place gets do not depend on the way the person came.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"
#include "navaid/simulation/online_sensors.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"

namespace navaid::simulation {
namespace {

struct Rig {
  Scenario scenario;
  SimulationConfig sim;
  WalkerTrajectory nominal;
};

Rig route1_rig() {
  Config config;
  config.apply_override("scenario=route1");
  config.apply_override("simulation.mode=features");
  Scenario scenario = make_scenario(read_scenario_name(config), read_scenario_options(config));
  SimulationConfig sim = read_simulation_config(config, scenario);
  WalkerConfig walker = sim.walker;
  walker.ground_z_m = scenario.ground_z_m;
  WalkerTrajectory nominal(scenario.path, walker);
  return {std::move(scenario), sim, std::move(nominal)};
}

// A pose looking along +x at `xy`, 1.7 m above the ground.
SE3 pose_at(const Rig& rig, const Vec2& xy) {
  return SE3(Quat::Identity(), Vec3(xy.x(), xy.y(), rig.scenario.ground_z_m + 1.7));
}

// The point of the scenario's extent farthest from its path, on the ground (a walk off the route).
Vec2 far_from_the_path(const Rig& rig) {
  Vec2 best = Vec2::Zero();
  double best_d = -1;
  const auto& e = rig.scenario.extent;
  for (double x = e.min.x() + 5; x < e.max.x() - 5; x += 5) {
    for (double y = e.min.y() + 5; y < e.max.y() - 5; y += 5) {
      double d = 1e9;
      for (double s = 0; s <= rig.nominal.length(); s += 4.0) d = std::min(d, (rig.nominal.path_point(s) - Vec2(x, y)).norm());
      if (d > best_d) best_d = d, best = Vec2(x, y);
    }
  }
  EXPECT_GT(best_d, 20.0) << "the test needs a place 20 m from the route";
  return best;
}

TEST(OnlineSensors, APersonOffThePlannedPathStillSeesFeatures) {
  const Rig rig = route1_rig();
  OnlineSensors sensors(rig.scenario, rig.sim, rig.nominal);
  const std::size_t along_the_path = sensors.landmarks().size();
  ASSERT_GT(along_the_path, 1000u);
  const Vec2 away = far_from_the_path(rig);
  std::size_t seen = 0;
  for (int k = 0; k < 4; ++k) {  // looking round
    const SE3 T = pose_at(rig, away) * SE3(Quat(Eigen::AngleAxisd(k * M_PI / 2, Vec3::UnitZ())), Vec3::Zero());
    seen += sensors.features(T, seconds_to_ns(0.1 * k)).features.size();
  }
  EXPECT_GT(sensors.landmarks().size(), along_the_path);  // seeded where the person is
  EXPECT_GT(seen, 20u);
}

TEST(OnlineSensors, APlaceGetsTheSameLandmarksWhicheverWayThePersonCame) {
  const Rig rig = route1_rig();
  const Vec2 away = far_from_the_path(rig);
  const Vec2 elsewhere = away + Vec2(40.0, 0.0);  // beyond the rays' 12 m of each other
  OnlineSensors direct(rig.scenario, rig.sim, rig.nominal), detour(rig.scenario, rig.sim, rig.nominal);
  direct.features(pose_at(rig, away), 0);
  detour.features(pose_at(rig, elsewhere), 0);
  detour.features(pose_at(rig, away), seconds_to_ns(0.1));
  // The landmarks near `away` (ids differ with the order of seeding; positions do not).
  const auto near = [&](const OnlineSensors& s) {
    std::vector<std::array<double, 3>> p;
    for (const Landmark& l : s.landmarks())
      if ((l.p_W.head<2>() - away).norm() < 3.0) p.push_back({l.p_W.x(), l.p_W.y(), l.p_W.z()});
    std::sort(p.begin(), p.end());
    return p;
  };
  const auto a = near(direct), b = near(detour);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace navaid::simulation
