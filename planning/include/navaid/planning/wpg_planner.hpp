#pragma once
// The Smart Cane's walking-path generator (WPG, seed smart-cane-biped-walking-path-generation,
// §IV, Alg. 1): a best-first search whose edges are footsteps. From a node (the CoM at a
// touchdown, its velocity, the standing foot, the next foot), every LFPC input (a_l, a_w, dtheta)
// of a small grid is simulated for one step (lipm.hpp); the step is kept when its three spheres
// clear the obstacles by the ESDF (CheckSafe: the CoM along the step, the previous gait point and
// the upcoming one), and nodes are pruned to the cheapest per (prune cell, heading bin) (Prune).
// Edge cost, eq. 9-10:
//     c(n_i, n_{i+1}) = D(n_i, n_{i+1}) + sigma |dtheta| + risk_{i+1},
//     risk_{i+1} = w_o (d_max - d_obstacle) when d_obstacle < d_max, else 0,
// D the CoM displacement, dtheta the turn between the two steps' walking directions, d_obstacle
// the ESDF at the new CoM. The heuristic is the straight distance to the goal times
// heuristic_weight (1 = admissible; the paper wants "a reasonable path rather than an optimal
// one", and a weight above 1 is what makes footstep search fast on long maps: measured in
// docs/planning.md).
//
// Goals (Alg. 1's NearEnd / ReachHorizon): a point goal is reached within goal_tolerance_m of the
// CoM; with horizon_m > 0 (re-planning inside the sensing range) a node horizon_m from the start
// also ends the search, its terminal cost the straight distance left to the goal, or, for a
// directional subgoal, beta (1 - cos) of its bearing from the start against the direction (as
// Direction A*). Without a horizon a directional subgoal is an error.
#include "navaid/planning/lipm.hpp"
#include "navaid/planning/local_planner.hpp"

namespace navaid::planning {

struct WpgConfig {
  LipmParams lipm;
  double lfpc_gain = 0.4;              ///< b
  double step_length_min_m = 0.4, step_length_max_m = 0.6;  ///< a_l range
  int step_lengths = 3;                ///< a_l values, evenly spaced over the range
  double step_width_min_m = 0.1, step_width_max_m = 0.2;    ///< a_w range
  int step_widths = 1;                 ///< a_w values (1: the middle of the range)
  double max_turn_rad = 0.5235987756;  ///< |dtheta| <= 30 deg
  int turns_per_side = 2;              ///< dtheta in {0, +-max/n, ..., +-max}
  int com_samples = 3;                 ///< CoM positions checked along each step

  double com_radius_m = 0.3;           ///< the CoM sphere (the body; shoulders 0.45-0.5 m wide)
  double foot_radius_m = 0.1;          ///< the two gait-point spheres
  double clearance_k_sigma = 1.0;      ///< every sphere grows by k sigma_xy of the estimate

  double turn_weight = 0.5;            ///< sigma of eq. 9 [cost per rad]
  double risk_weight = 1.0;            ///< w_o of eq. 10
  double risk_distance_m = 0.6;        ///< d_max of eq. 10 (not in the paper: 0.3 m beyond the body)
  /// Not in the paper (its LiDAR sees the walls around the user): each step also costs
  /// traversal_weight x its displacement x the cost-map value at the new CoM, so that a camera's
  /// unseen cells (cost mapping.cost.unknown_cost) are walked only where seen ground offers no way.
  /// 0 = eq. 9-10 alone (planning on complete maps, Table I); the Smart Cane's guidance uses 2.
  double traversal_weight = 0.0;
  /// Not in the paper: a user who already stands closer to an obstacle than the body sphere (a
  /// veer, a bump) would be "start blocked" and told to stop for good. With escape_distance_m > 0
  /// the search leaves such a start: within this distance of it the CoM needs only the start's own
  /// clearance and the gait points are not checked (from rest the push-off foot lands behind the
  /// CoM, in the wall being left); beyond it, the full spheres again. A start inside an
  /// obstacle (clearance below escape_min_clearance_m) stays blocked. 0 = the paper's CheckSafe;
  /// the Smart Cane's guidance uses 1 m.
  double escape_distance_m = 0.0;
  double escape_min_clearance_m = 0.05;
  /// A start at least this fast (PlanningProblem::start_speed_mps) is a walk in progress: the search
  /// starts from that walking state, whose steps turn at most max_turn_rad each, and only when it
  /// finds no way does it plan from rest (stop, turn on the spot). Re-planning at 10 Hz from rest
  /// made every cycle free to turn the user round at the cost of sigma |turn|, and the plans of
  /// successive cycles flipped between ways (measured in closed loop: docs/simulated-users.md).
  double walking_start_speed_mps = 0.2;

  bool grid_heuristic = true;          ///< coarse-grid distance (grid_distance_heuristic.hpp), else straight
  double heuristic_cell_m = 0.5;       ///< its coarse cell
  double heuristic_weight = 1.2;
  double prune_cell_m = 0.25;          ///< Prune(): one node per cell of this size ...
  int heading_bins = 12;               ///< ... and heading bin (30 deg)
  double goal_tolerance_m = 0.5;       ///< NearEnd(): about one step
  double horizon_m = 0.0;              ///< ReachHorizon(): 0 = plan to the goal; 10 in re-planning
  double direction_beta = 5.0;         ///< directional subgoals: weight of 1 - cos
  SearchLimits limits;
};

/// Keys planning.wpg.*: gravity, com_height_m, support_time_s, lfpc_gain (must satisfy eq. 8 for
/// the model: a ConfigError says the interval otherwise), step_length_m [min, max], step_lengths,
/// step_width_m [min, max], step_widths, max_turn_deg, turns_per_side, com_samples, com_radius_m,
/// foot_radius_m, clearance_k_sigma, turn_weight, risk_weight, risk_distance_m, traversal_weight, escape_distance_m,
/// escape_min_clearance_m, walking_start_speed_mps, heuristic (grid |
/// euclidean), heuristic_cell_m, heuristic_weight,
/// prune_cell_m, heading_bins, goal_tolerance_m, horizon_m, direction_beta; plus planning.search.*.
WpgConfig read_wpg_config(const Config& config);

/// Eq. 9-10 for one step: CoM displacement, turn and the ESDF distance at the new CoM; plus
/// traversal_weight x displacement x cell_cost (the cost map at the new CoM, 0 when not known).
double wpg_edge_cost(const WpgConfig& c, double displacement_m, double turn_rad, double obstacle_distance_m,
                     double cell_cost = 0.0);

/// The LFPC inputs of one expansion relative to walking direction 0 (dtheta = direction_rad).
std::vector<LfpcInput> wpg_inputs(const WpgConfig& c);

class WpgPlanner : public LocalPlanner {
 public:
  explicit WpgPlanner(const WpgConfig& config = {});
  std::string_view name() const override { return "wpg"; }
  /// Needs problem.esdf (CheckSafe reads it) and a point goal, or a directional subgoal with
  /// horizon_m > 0; throws navaid::Error otherwise. Plan: path_W the CoM at every touchdown
  /// (start first), yaw_rad the walking direction there, footsteps_W the gait points.
  Plan plan(const PlanningProblem& problem) const override;
  const WpgConfig& config() const { return config_; }

 private:
  WpgConfig config_;
  std::vector<LfpcInput> inputs_;
  LipmStepTable table_;
};

}  // namespace navaid::planning
