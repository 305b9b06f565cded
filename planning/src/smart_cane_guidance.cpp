#include "navaid/planning/smart_cane_guidance.hpp"

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

SmartCaneGuidanceConfig SmartCaneGuidance::default_config() {
  SmartCaneGuidanceConfig c;
  c.guidance.replan_period_s = 0.1;
  c.wpg.horizon_m = 10.0;
  c.wpg.traversal_weight = 2.0;
  c.wpg.escape_distance_m = 1.0;
  return c;
}

namespace {
const ConfigKey<std::string> kPlanner{"planning.smart_cane.planner", SmartCaneGuidanceConfig{}.planner, {"wpg", "astar"},
                                      "the Smart Cane's local planner: wpg (the paper's) or astar (its Table II "
                                      "baseline)"};
}  // namespace

ConfigSchema smart_cane_guidance_config_schema() {
  return path_guidance_config_schema()
      .add(wpg_config_schema())
      .add(pi_heading_config_schema())
      .add(kPlanner)
      .add(grid_astar_config_schema());
}

SmartCaneGuidanceConfig read_smart_cane_guidance_config(const Config& config) {
  SmartCaneGuidanceConfig c;
  c.guidance = read_path_guidance_config(config);
  if (!config.has("planning.guidance.replan_period_s")) c.guidance.replan_period_s = 0.1;
  c.wpg = read_wpg_config(config);
  if (!config.has("planning.wpg.horizon_m")) c.wpg.horizon_m = 10.0;
  if (!config.has("planning.wpg.traversal_weight")) c.wpg.traversal_weight = 2.0;
  if (!config.has("planning.wpg.escape_distance_m")) c.wpg.escape_distance_m = 1.0;
  c.pi = read_pi_heading_config(config);
  c.planner = get(config, kPlanner);
  c.astar = read_grid_astar_config(config);
  return c;
}

namespace {
std::unique_ptr<LocalPlanner> smart_cane_planner(const SmartCaneGuidanceConfig& c) {
  if (c.planner == "astar") return std::make_unique<GridAStarPlanner>(c.astar);
  if (c.planner != "wpg") throw ConfigError("", "planning.smart_cane.planner", "must be wpg or astar, not '" + c.planner + "'");
  return std::make_unique<WpgPlanner>(c.wpg);
}
}  // namespace

SmartCaneGuidance::SmartCaneGuidance(const SmartCaneGuidanceConfig& config)
    : planner_(config.planner), chain_(config.guidance, smart_cane_planner(config)), pi_(config.pi) {}

GuidanceCommand SmartCaneGuidance::update(const StateEstimate& estimate, const mapping::CostMap& cost,
                                          const mapping::Esdf2d& esdf, const Subgoal& subgoal) {
  GuidanceCommand cmd = chain_.update(estimate, cost, &esdf, subgoal);
  if (cmd.action == GuidanceAction::kGo && cmd.heading_rad) {
    // theta_ref - theta: the look-ahead direction relative to the user's heading.
    cmd.steering_rad = pi_.update(estimate.t, *cmd.heading_rad);
  } else {
    pi_.reset();
    cmd.steering_rad = 0.0;
  }
  return cmd;
}

}  // namespace navaid::planning
