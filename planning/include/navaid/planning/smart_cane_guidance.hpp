#pragma once
// The Smart Cane's guidance loop (seed smart-cane-biped-walking-path-generation, §III-D and
// §IV): the walking-path generator re-plans inside the 10 m sensing range at 10 Hz (the path
// guidance chain of path_guidance.hpp with a WPG planner whose horizon is the sensing range and a
// re-planning period of 0.1 s), the path is followed with the 2 m look-ahead, and the PI heading
// controller (eq. 1) turns the heading error into the steering motor's command
// (GuidanceCommand::steering_rad). The uncertainty rules are those of the chain: while the
// estimate is unsure, or the way is blocked, there is no heading and the controller is reset (no
// pull toward a direction nobody knows, and no integral carried over a stop).
//
// planning.smart_cane.planner = astar swaps the walking-path generator for the paper's A*
// baseline (Table II: grid A* on the cost map, no body model; same chain, look-ahead and PI).
#include <memory>
#include <string>

#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "navaid/planning/pi_heading_controller.hpp"
#include "navaid/planning/wpg_planner.hpp"

namespace navaid::planning {

struct SmartCaneGuidanceConfig {
  PathGuidanceConfig guidance;  ///< replan_period_s = 0.1 (10 Hz) by default here
  WpgConfig wpg;                ///< horizon_m 10 (the sensing range), traversal_weight 2, escape_distance_m 1 here
  PiHeadingConfig pi;
  std::string planner = "wpg";  ///< wpg (the paper's method) or astar (its Table II baseline)
  GridAStarConfig astar;        ///< the baseline's planning.grid.* / planning.search.* keys
};

/// Keys planning.smart_cane.planner (wpg | astar), planning.guidance.*, planning.follow.*,
/// planning.wpg.*, planning.grid.*, planning.pi.*, with the
/// defaults above (planning.guidance.replan_period_s 0.1, planning.wpg.horizon_m 10,
/// planning.wpg.traversal_weight 2: the cane camera leaves the walls beside the user unseen;
/// planning.wpg.escape_distance_m 1: a user who veered against a wall is led off it, not stopped).
SmartCaneGuidanceConfig read_smart_cane_guidance_config(const Config& config);

class SmartCaneGuidance {
 public:
  explicit SmartCaneGuidance(const SmartCaneGuidanceConfig& config = default_config());

  /// One cycle: the chain's command plus steering_rad when it says kGo. Needs the ESDF (WPG).
  GuidanceCommand update(const StateEstimate& estimate, const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                         const Subgoal& subgoal);

  const PathGuidance& chain() const { return chain_; }
  std::string_view planner() const { return planner_; }
  static SmartCaneGuidanceConfig default_config();

 private:
  std::string planner_;
  PathGuidance chain_;
  PiHeadingController pi_;
};

}  // namespace navaid::planning
