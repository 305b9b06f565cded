// The simulation room's declared keys are the keys its read functions read, with the same
// defaults.
#include <gtest/gtest.h>

#include "config_schema_check.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/hand_motion.hpp"
#include "navaid/simulation/reaching_user.hpp"
#include "navaid/simulation/simulated_user.hpp"
#include "navaid/simulation/simulation_config.hpp"

namespace navaid::simulation {

TEST(SimulationConfigSchema, DeclaredKeysAreTheKeysRead) {
  const Scenario scenario = make_scenario("corridor");
  navaid::testing::expect_schema_matches_reads(config_schema(), [&](const Config& c) {
    read_simulation_config(c, scenario);
    read_user_model(c);
    read_hand_motion_config(c);
    read_reach_model(c);
  });
}

TEST(SimulationConfigSchema, DefaultsFromTheSchemaReadBackAsTheStructDefaults) {
  const Scenario scenario = make_scenario("corridor");
  const Config spelt = Config::parse(Config().dump(config_schema()), "<declared defaults>");
  const SimulationConfig a = read_simulation_config(Config(), scenario);
  const SimulationConfig b = read_simulation_config(spelt, scenario);
  EXPECT_EQ(a.mount.name, b.mount.name);  // no declared default: the scenario's
  EXPECT_EQ(a.sensor_preset, b.sensor_preset);
  EXPECT_EQ(a.camera.rate_hz, b.camera.rate_hz);
  EXPECT_EQ(a.imu.rate_hz, b.imu.rate_hz);
  EXPECT_EQ(a.gps_enabled, b.gps_enabled);
  EXPECT_EQ(a.walker.scan_amplitude_rad, b.walker.scan_amplitude_rad);
  EXPECT_EQ(a.imu_options.gyro_scale_misalignment, b.imu_options.gyro_scale_misalignment);
  EXPECT_EQ(a.mag.soft_iron, b.mag.soft_iron);
  EXPECT_TRUE(b.imu_options.shocks.empty());
  EXPECT_TRUE(b.gps.outages.empty());
  EXPECT_DOUBLE_EQ(read_reach_model(spelt).turn_rad, ReachModel{}.turn_rad);
  EXPECT_EQ(read_user_model(spelt).speed_mps, read_user_model(Config()).speed_mps);
  Config with_scenario = spelt;
  with_scenario.apply_override("scenario=corridor");
  EXPECT_NO_THROW(with_scenario.reject_unknown_keys(config_schema()));
}

}  // namespace navaid::simulation
