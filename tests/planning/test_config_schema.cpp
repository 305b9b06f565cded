// The planning room's declared keys are the keys its read functions read, with the same defaults.
#include <gtest/gtest.h>

#include "config_schema_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/byu_cost_functions.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/direction_astar.hpp"
#include "navaid/planning/foot_router.hpp"
#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/hand_guidance.hpp"
#include "navaid/planning/occupancy_cost_map.hpp"
#include "navaid/planning/route_narration.hpp"
#include "navaid/planning/route_subgoals.hpp"
#include "navaid/planning/smart_cane_guidance.hpp"
#include "navaid/planning/wpg_planner.hpp"

namespace navaid::planning {

TEST(PlanningConfigSchema, DeclaredKeysAreTheKeysRead) {
  navaid::testing::expect_schema_matches_reads(config_schema(), [](const Config& c) {
    read_direction_astar_config(c);
    read_occupancy_cost_config(c);
    read_smart_cane_guidance_config(c);
    read_byu_cost_config(c);
    read_hand_guidance_config(c);
    read_apriltag_detector_config(c);
    foot_route_config(c);
    narration_config(c);
    sub_route_config(c);
  });
}

TEST(PlanningConfigSchema, EachReadFunctionHasItsSchema) {
  using navaid::testing::expect_schema_matches_reads;
  expect_schema_matches_reads(wpg_config_schema(), [](const Config& c) { read_wpg_config(c); });
  expect_schema_matches_reads(path_guidance_config_schema(), [](const Config& c) { read_path_guidance_config(c); });
  expect_schema_matches_reads(grid_astar_config_schema(), [](const Config& c) { read_grid_astar_config(c); });
  expect_schema_matches_reads(hand_guidance_config_schema(), [](const Config& c) { read_hand_guidance_config(c); });
  expect_schema_matches_reads(smart_cane_guidance_config_schema(),
                              [](const Config& c) { read_smart_cane_guidance_config(c); });
}

TEST(PlanningConfigSchema, DefaultsFromTheSchemaReadBackAsTheStructDefaults) {
  const Config spelt = Config::parse(Config().dump(config_schema()), "<declared defaults>");
  const WpgConfig a = read_wpg_config(Config());
  const WpgConfig b = read_wpg_config(spelt);
  EXPECT_DOUBLE_EQ(a.step_length_min_m, b.step_length_min_m);
  EXPECT_DOUBLE_EQ(a.step_width_max_m, b.step_width_max_m);
  EXPECT_DOUBLE_EQ(a.max_turn_rad, b.max_turn_rad);
  EXPECT_EQ(a.grid_heuristic, b.grid_heuristic);
  EXPECT_EQ(a.limits.max_expansions, b.limits.max_expansions);
  const PathGuidanceConfig g = read_path_guidance_config(spelt);
  EXPECT_DOUBLE_EQ(g.max_heading_sigma_rad, PathGuidanceConfig{}.max_heading_sigma_rad);
  EXPECT_EQ(g.scope, PathGuidanceConfig{}.scope);
  EXPECT_EQ(foot_route_config(spelt).max_expansions, FootRouteConfig{}.max_expansions);
  EXPECT_NO_THROW(spelt.reject_unknown_keys(config_schema()));
}

TEST(PlanningConfigSchema, DynamicRangesKeepTheirMessages) {
  const Config c = Config::parse("planning: {follow: {foresight_m: 1.0, min_foresight_m: 1.5}}\n", "follow.yaml");
  try {
    read_path_guidance_config(c);
    FAIL() << "min_foresight_m above foresight_m must be rejected";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("value 1.5 is outside the allowed range [0, 1]"), std::string::npos) << e.what();
  }
}

}  // namespace navaid::planning
