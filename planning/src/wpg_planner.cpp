#include "navaid/planning/wpg_planner.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/grid_distance_heuristic.hpp"

namespace navaid::planning {

namespace {

using Clock = std::chrono::steady_clock;

std::vector<double> spaced(double lo, double hi, int n) {
  if (n == 1) return {0.5 * (lo + hi)};
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1));
  return v;
}

// A search node: the walker at a touchdown, or the user standing at the start (who may turn on
// the spot before the first step: the paper's start state (x, y, theta)_o is a standing user).
struct WpgNode {
  WalkerState walker;
  bool standing = false;
};

// The footstep search space of Alg. 1 for best_first_search.
class WpgSpace {
 public:
  using State = WpgNode;

  WpgSpace(const WpgConfig& c, const std::vector<LfpcInput>& inputs, const LipmStepTable& table,
           const mapping::Esdf2d& esdf, const mapping::CostMap& cost, double margin_m, const Vec2& start,
           std::optional<double> escape_clearance, std::optional<Vec2> goal,
           std::optional<double> direction, GridDistanceHeuristic* grid)
      : c_(c),
        inputs_(inputs),
        table_(table),
        esdf_(esdf),
        cost_(cost),
        margin_(margin_m),
        start_(start),
        escape_clearance_(escape_clearance),
        goal_(goal),
        direction_(direction),
        grid_(grid),
        origin_(esdf.geometry().origin_W()),
        heading_bin_(2.0 * kPi / c.heading_bins) {}

  std::uint64_t key(const State& n) const {
    if (n.standing) return ~std::uint64_t{0};
    const WalkerState& s = n.walker;
    const Vec2 q = (s.com - origin_) / c_.prune_cell_m;
    const auto ix = static_cast<std::uint64_t>(std::max(0.0, std::floor(q.x())));
    const auto iy = static_cast<std::uint64_t>(std::max(0.0, std::floor(q.y())));
    const double a = wrap_angle(s.direction_rad) + kPi;  // [0, 2 pi]
    const auto ib = static_cast<std::uint64_t>(std::floor(a / heading_bin_)) % static_cast<std::uint64_t>(c_.heading_bins);
    return (ix << 40) | (iy << 16) | ib;
  }

  double heuristic(const State& n) const {
    const Vec2& p = n.walker.com;
    if (goal_) return c_.heuristic_weight * (grid_ != nullptr ? grid_->at(p) : (p - *goal_).norm());
    return c_.heuristic_weight * std::max(0.0, c_.horizon_m - (p - start_).norm());
  }

  std::optional<double> goal_cost(const State& n) const {
    const WalkerState& s = n.walker;
    if (goal_ && (s.com - *goal_).norm() <= c_.goal_tolerance_m) return (s.com - *goal_).norm();
    if (!at_horizon(s)) return std::nullopt;
    if (goal_) return (s.com - *goal_).norm();
    const Vec2 d = s.com - start_;
    return c_.direction_beta * (1.0 - std::cos(std::atan2(d.y(), d.x()) - *direction_));
  }

  template <class Emit>
  void expand(const State& n, Emit&& emit) const {
    const WalkerState& s = n.walker;
    if (at_horizon(s)) return;  // beyond the sensing range: a terminal node
    if (n.standing) {
      // Turn on the spot to any heading bin (cost sigma |turn|), then step off from rest.
      for (int k = 0; k < c_.heading_bins; ++k) {
        const double turn = wrap_angle(static_cast<double>(k) * heading_bin_);
        WalkerState turned = s;
        turned.direction_rad = wrap_angle(s.direction_rad + turn);
        turned.velocity = Vec2::Zero();
        for (const LfpcInput& relative : inputs_) {
          if (relative.direction_rad != 0.0) continue;
          step(turned, relative, c_.turn_weight * std::abs(turn), emit);
        }
      }
      return;
    }
    for (const LfpcInput& relative : inputs_) step(s, relative, 0.0, emit);
  }

 private:
  template <class Emit>
  void step(const WalkerState& s, const LfpcInput& relative, double extra_cost, Emit& emit) const {
    LfpcInput u = relative;
    u.direction_rad = wrap_angle(s.direction_rad + relative.direction_rad);
    const WalkerState next = lfpc_step(table_, c_.lfpc_gain, s, u, &samples_);
    // CheckSafe: the upcoming gait point (next.support_foot) and the CoM path. The previous gait
    // point (s.support_foot) was this check's upcoming one one step earlier (the start's is
    // checked before the search), so it is not looked up again.
    if (!clear(next.support_foot, foot_clearance(next.support_foot))) return;
    double d_com = 0.0;
    for (const Vec2& p : samples_) {
      const std::optional<double> d = esdf_.distance(p);
      if (!d || *d < com_clearance(p)) return;
      d_com = *d;  // the last sample is the new node's CoM
    }
    emit(WpgNode{next, false}, extra_cost + wpg_edge_cost(c_, (next.com - s.com).norm(), std::abs(relative.direction_rad),
                                                        d_com - margin_, cell_cost(next.com)));
  }

  double cell_cost(const Vec2& p) const {
    if (c_.traversal_weight == 0.0) return 0.0;
    return static_cast<double>(cost_.value_at(p).value_or(0.0f));
  }

  bool clear(const Vec2& p, double clearance) const {
    const std::optional<double> d = esdf_.distance(p);
    return d && *d >= clearance;
  }

  bool escaping(const Vec2& p) const { return escape_clearance_ && (p - start_).norm() < c_.escape_distance_m; }
  double com_clearance(const Vec2& p) const {
    return escaping(p) ? *escape_clearance_ : c_.com_radius_m + margin_;
  }
  // Within the escape the gait points are not checked: from rest the LFPC puts the push-off foot
  // behind the CoM, i.e. into the wall the user stands against, whichever way they would leave.
  double foot_clearance(const Vec2& p) const {
    return escaping(p) ? -std::numeric_limits<double>::infinity() : c_.foot_radius_m + margin_;
  }

  bool at_horizon(const WalkerState& s) const {
    return c_.horizon_m > 0.0 && (s.com - start_).norm() >= c_.horizon_m;
  }

  const WpgConfig& c_;
  const std::vector<LfpcInput>& inputs_;
  const LipmStepTable& table_;
  const mapping::Esdf2d& esdf_;
  const mapping::CostMap& cost_;
  double margin_;
  Vec2 start_;
  std::optional<double> escape_clearance_;  // set when the start lies inside the body sphere's clearance
  std::optional<Vec2> goal_;
  std::optional<double> direction_;
  GridDistanceHeuristic* grid_;  // resumes its Dijkstra on queries
  Vec2 origin_;
  double heading_bin_;
  mutable std::vector<Vec2> samples_;
};

Plan endpoint_failure(GuidanceReason reason, std::string detail) {
  Plan p;
  p.reason = reason;
  p.detail = std::move(detail);
  return p;
}

}  // namespace

double wpg_edge_cost(const WpgConfig& c, double displacement_m, double turn_rad, double obstacle_distance_m,
                     double cell_cost) {
  const double risk =
      obstacle_distance_m < c.risk_distance_m ? c.risk_weight * (c.risk_distance_m - obstacle_distance_m) : 0.0;
  return displacement_m + c.turn_weight * std::abs(turn_rad) + risk + c.traversal_weight * displacement_m * cell_cost;
}

std::vector<LfpcInput> wpg_inputs(const WpgConfig& c) {
  std::vector<LfpcInput> inputs;
  std::vector<double> turns{0.0};
  for (int k = 1; k <= c.turns_per_side; ++k) {
    const double t = c.max_turn_rad * static_cast<double>(k) / static_cast<double>(c.turns_per_side);
    turns.push_back(t);
    turns.push_back(-t);
  }
  for (const double a_l : spaced(c.step_length_min_m, c.step_length_max_m, c.step_lengths))
    for (const double a_w : spaced(c.step_width_min_m, c.step_width_max_m, c.step_widths))
      for (const double t : turns) inputs.push_back(LfpcInput{a_l, a_w, t});
  return inputs;
}

namespace {
const WpgConfig kWpgPlannerDefaults;
const ConfigKey<double> kGravity{"planning.wpg.gravity", kWpgPlannerDefaults.lipm.gravity, {0.1, 100.0}, "LIPM gravity [m/s^2]"};
const ConfigKey<double> kComHeight{"planning.wpg.com_height_m", kWpgPlannerDefaults.lipm.com_height_m, {0.1, 3.0},
                                   "LIPM height of the centre of mass [m]"};
const ConfigKey<double> kSupportTime{"planning.wpg.support_time_s", kWpgPlannerDefaults.lipm.support_time_s, {0.05, 2.0},
                                     "LIPM support time of one step [s]"};
const ConfigKey<double> kLfpcGain{"planning.wpg.lfpc_gain", kWpgPlannerDefaults.lfpc_gain, {0.0, 10.0},
                                  "b: LFPC gain (must keep eq. 8 stable for the LIPM)"};
const ConfigKey<std::vector<double>> kStepLength{"planning.wpg.step_length_m",
                                                 std::vector<double>{kWpgPlannerDefaults.step_length_min_m,
                                                                     kWpgPlannerDefaults.step_length_max_m},
                                                 2, {0.05, 2.0}, "[min, max] range of the step length a_l [m]"};
const ConfigKey<std::vector<double>> kStepWidth{"planning.wpg.step_width_m",
                                                std::vector<double>{kWpgPlannerDefaults.step_width_min_m, kWpgPlannerDefaults.step_width_max_m},
                                                2, {0.0, 1.0}, "[min, max] range of the step width a_w [m]"};
const ConfigKey<int> kStepLengths{"planning.wpg.step_lengths", kWpgPlannerDefaults.step_lengths, 1, 20,
                                  "step lengths tried, evenly spaced over the range"};
const ConfigKey<int> kStepWidths{"planning.wpg.step_widths", kWpgPlannerDefaults.step_widths, 1, 20,
                                 "step widths tried (1: the middle of the range)"};
const ConfigKey<double> kMaxTurn{"planning.wpg.max_turn_deg", rad_to_deg(kWpgPlannerDefaults.max_turn_rad), {0.0, 90.0},
                                 "largest turn of one step [deg]"};
const ConfigKey<int> kTurnsPerSide{"planning.wpg.turns_per_side", kWpgPlannerDefaults.turns_per_side, 0, 20,
                                   "turns tried on each side, evenly spaced up to max_turn_deg"};
const ConfigKey<int> kComSamples{"planning.wpg.com_samples", kWpgPlannerDefaults.com_samples, 1, 50,
                                 "CoM positions checked along each step"};
const ConfigKey<double> kComRadius{"planning.wpg.com_radius_m", kWpgPlannerDefaults.com_radius_m, {0.0, 2.0},
                                   "radius of the CoM sphere (the body) [m]"};
const ConfigKey<double> kFootRadius{"planning.wpg.foot_radius_m", kWpgPlannerDefaults.foot_radius_m, {0.0, 1.0},
                                    "radius of the two gait-point spheres [m]"};
const ConfigKey<double> kWpgPlannerClearanceKSigma{"planning.wpg.clearance_k_sigma", kWpgPlannerDefaults.clearance_k_sigma, {0.0, 10.0},
                                         "every sphere grows by this times the estimate's sigma_xy"};
const ConfigKey<double> kTurnWeight{"planning.wpg.turn_weight", kWpgPlannerDefaults.turn_weight, {0.0, 100.0},
                                    "sigma of eq. 9 [cost per rad]"};
const ConfigKey<double> kRiskWeight{"planning.wpg.risk_weight", kWpgPlannerDefaults.risk_weight, {0.0, 100.0}, "w_o of eq. 10"};
const ConfigKey<double> kRiskDistance{"planning.wpg.risk_distance_m", kWpgPlannerDefaults.risk_distance_m, {0.0, 10.0},
                                      "d_max of eq. 10 [m]"};
const ConfigKey<double> kTraversalWeight{"planning.wpg.traversal_weight", kWpgPlannerDefaults.traversal_weight, {0.0, 100.0},
                                         "weight of the cost-map value under each step (the Smart Cane's guidance: 2 "
                                         "when absent)"};
const ConfigKey<double> kEscapeDistance{"planning.wpg.escape_distance_m", kWpgPlannerDefaults.escape_distance_m, {0.0, 10.0},
                                        "a start nearer an obstacle than the body may leave within this distance [m] "
                                        "(the Smart Cane's guidance: 1 when absent)"};
const ConfigKey<double> kEscapeMinClearance{"planning.wpg.escape_min_clearance_m", kWpgPlannerDefaults.escape_min_clearance_m,
                                            {0.0, 2.0}, "a start with less clearance than this stays blocked [m]"};
const ConfigKey<double> kWalkingStartSpeed{"planning.wpg.walking_start_speed_mps", kWpgPlannerDefaults.walking_start_speed_mps,
                                           {0.0, 10.0}, "a start at least this fast is planned as a walk in progress "
                                                        "[m/s]"};
const ConfigKey<std::string> kHeuristic{"planning.wpg.heuristic", std::string("grid"), {"grid", "euclidean"},
                                        "search heuristic: coarse-grid distance or straight line"};
const ConfigKey<double> kHeuristicCell{"planning.wpg.heuristic_cell_m", kWpgPlannerDefaults.heuristic_cell_m, {0.01, 10.0},
                                       "cell of the coarse-grid heuristic [m]"};
const ConfigKey<double> kHeuristicWeight{"planning.wpg.heuristic_weight", kWpgPlannerDefaults.heuristic_weight, {1.0, 10.0},
                                         "weight of the heuristic"};
const ConfigKey<double> kPruneCell{"planning.wpg.prune_cell_m", kWpgPlannerDefaults.prune_cell_m, {0.01, 5.0},
                                   "Prune(): one node per cell of this size and heading bin [m]"};
const ConfigKey<int> kHeadingBins{"planning.wpg.heading_bins", kWpgPlannerDefaults.heading_bins, 1, 360,
                                  "Prune(): heading bins of a full turn"};
const ConfigKey<double> kGoalTolerance{"planning.wpg.goal_tolerance_m", kWpgPlannerDefaults.goal_tolerance_m, {0.01, 10.0},
                                       "NearEnd(): the goal is reached within this [m]"};
const ConfigKey<double> kHorizon{"planning.wpg.horizon_m", kWpgPlannerDefaults.horizon_m, {0.0, 1000.0},
                                 "ReachHorizon(): plan this far; 0 = to the goal (the Smart Cane's guidance: 10 when "
                                 "absent)"};
const ConfigKey<double> kDirectionBeta{"planning.wpg.direction_beta", kWpgPlannerDefaults.direction_beta, {0.0, 1e4},
                                       "directional subgoals: weight of 1 - cos"};
}  // namespace

ConfigSchema wpg_config_schema() {
  return ConfigSchema()
      .add(kGravity)
      .add(kComHeight)
      .add(kSupportTime)
      .add(kLfpcGain)
      .add(kStepLength)
      .add(kStepWidth)
      .add(kStepLengths)
      .add(kStepWidths)
      .add(kMaxTurn)
      .add(kTurnsPerSide)
      .add(kComSamples)
      .add(kComRadius)
      .add(kFootRadius)
      .add(kWpgPlannerClearanceKSigma)
      .add(kTurnWeight)
      .add(kRiskWeight)
      .add(kRiskDistance)
      .add(kTraversalWeight)
      .add(kEscapeDistance)
      .add(kEscapeMinClearance)
      .add(kWalkingStartSpeed)
      .add(kHeuristic)
      .add(kHeuristicCell)
      .add(kHeuristicWeight)
      .add(kPruneCell)
      .add(kHeadingBins)
      .add(kGoalTolerance)
      .add(kHorizon)
      .add(kDirectionBeta)
      .add(search_limits_schema());
}

WpgConfig read_wpg_config(const Config& config) {
  WpgConfig c;
  c.lipm.gravity = get(config, kGravity);
  c.lipm.com_height_m = get(config, kComHeight);
  c.lipm.support_time_s = get(config, kSupportTime);
  c.lfpc_gain = get(config, kLfpcGain);
  const GainInterval stable = lfpc_stable_gains(c.lipm);
  if (!stable.contains(c.lfpc_gain)) {
    throw ConfigError("", "planning.wpg.lfpc_gain",
                      fmt::format("b = {} makes the LFPC unstable for this LIPM: eq. 8 needs {:.3f} < b < {:.3f}",
                                  c.lfpc_gain, stable.low, stable.high));
  }
  if (config.has(kStepLength.name)) {
    const std::vector<double> r = get(config, kStepLength);
    if (r[0] > r[1]) throw ConfigError("", "planning.wpg.step_length_m", "needs [min, max] with min <= max");
    c.step_length_min_m = r[0];
    c.step_length_max_m = r[1];
  }
  if (config.has(kStepWidth.name)) {
    const std::vector<double> r = get(config, kStepWidth);
    if (r[0] > r[1]) throw ConfigError("", "planning.wpg.step_width_m", "needs [min, max] with min <= max");
    c.step_width_min_m = r[0];
    c.step_width_max_m = r[1];
  }
  c.step_lengths = get(config, kStepLengths);
  c.step_widths = get(config, kStepWidths);
  c.max_turn_rad = deg_to_rad(get(config, kMaxTurn));
  c.turns_per_side = get(config, kTurnsPerSide);
  c.com_samples = get(config, kComSamples);
  c.com_radius_m = get(config, kComRadius);
  c.foot_radius_m = get(config, kFootRadius);
  c.clearance_k_sigma = get(config, kWpgPlannerClearanceKSigma);
  c.turn_weight = get(config, kTurnWeight);
  c.risk_weight = get(config, kRiskWeight);
  c.risk_distance_m = get(config, kRiskDistance);
  c.traversal_weight = get(config, kTraversalWeight);
  c.escape_distance_m = get(config, kEscapeDistance);
  c.escape_min_clearance_m = get(config, kEscapeMinClearance);
  c.walking_start_speed_mps = get(config, kWalkingStartSpeed);
  c.grid_heuristic = get(config, kHeuristic) == "grid";
  c.heuristic_cell_m = get(config, kHeuristicCell);
  c.heuristic_weight = get(config, kHeuristicWeight);
  c.prune_cell_m = get(config, kPruneCell);
  c.heading_bins = get(config, kHeadingBins);
  c.goal_tolerance_m = get(config, kGoalTolerance);
  c.horizon_m = get(config, kHorizon);
  c.direction_beta = get(config, kDirectionBeta);
  c.limits = read_search_limits(config);
  return c;
}

WpgPlanner::WpgPlanner(const WpgConfig& config)
    : config_(config), inputs_(wpg_inputs(config)), table_(lipm_step_table(config.lipm, config.com_samples)) {}

Plan WpgPlanner::plan(const PlanningProblem& problem) const {
  if (problem.cost == nullptr) throw Error("wpg: the planning problem has no cost map");
  if (problem.esdf == nullptr || problem.esdf->empty()) throw Error("wpg: needs the ESDF of the map (CheckSafe)");
  if (!problem.goal_W && !problem.goal_direction_rad) throw Error("wpg: needs a point goal or a direction");
  if (!problem.goal_W && config_.horizon_m <= 0.0) {
    throw Error("wpg: a directional subgoal needs planning.wpg.horizon_m > 0 (the re-planning range)");
  }
  const mapping::Esdf2d& esdf = *problem.esdf;
  const double margin = config_.clearance_k_sigma * std::max(0.0, problem.sigma_xy_m);
  const Vec2 start = problem.start.position;
  const double yaw = problem.start.yaw_rad;

  // The user stands at the start, the left foot beside the CoM, the right one steps first.
  WalkerState s0;
  s0.com = start;
  s0.direction_rad = wrap_angle(yaw);
  const Vec2 left(-std::sin(yaw), std::cos(yaw));
  s0.support_foot = start + 0.5 * (config_.step_width_min_m + config_.step_width_max_m) * left;
  s0.next = Foot::kRight;

  const auto where = [&](const char* what, const Vec2& p) -> std::optional<Plan> {
    const std::optional<double> d = esdf.distance(p);
    const bool is_start = std::string_view(what) == "start";
    if (!p.allFinite() || !d) {
      return endpoint_failure(GuidanceReason::kOffMap, fmt::format("{} ({:.2f}, {:.2f}) is off the map", what, p.x(), p.y()));
    }
    if (*d < config_.com_radius_m + margin) {
      return endpoint_failure(is_start ? GuidanceReason::kStartBlocked : GuidanceReason::kGoalBlocked,
                              *d <= 0.0 ? fmt::format("{} ({:.2f}, {:.2f}) lies in an obstacle", what, p.x(), p.y())
                                        : fmt::format("{} ({:.2f}, {:.2f}) is {:.2f} m from an obstacle, closer than "
                                                      "the body sphere's {:.2f} m",
                                                      what, p.x(), p.y(), *d, config_.com_radius_m + margin));
    }
    return std::nullopt;
  };
  // Escape (see WpgConfig::escape_distance_m): a start inside the body sphere's clearance but not
  // in an obstacle keeps its own clearance for the first steps.
  std::optional<double> escape_clearance;
  if (const std::optional<double> d = esdf.distance(start);
      config_.escape_distance_m > 0.0 && start.allFinite() && d && *d < config_.com_radius_m + margin &&
      *d >= config_.escape_min_clearance_m) {
    escape_clearance = *d - 1e-6;
  }
  if (!escape_clearance) {
    if (std::optional<Plan> f = where("start", start)) return *f;
  }
  if (const std::optional<double> d = esdf.distance(s0.support_foot);
      !escape_clearance && (!d || *d < config_.foot_radius_m + margin)) {
    return endpoint_failure(GuidanceReason::kStartBlocked,
                            fmt::format("the standing foot at ({:.2f}, {:.2f}) is within {:.2f} m of an obstacle",
                                        s0.support_foot.x(), s0.support_foot.y(), config_.foot_radius_m + margin));
  }
  if (problem.goal_W) {
    if (std::optional<Plan> f = where("goal", *problem.goal_W)) return *f;
  }

  const Clock::time_point t0 = Clock::now();
  std::optional<GridDistanceHeuristic> grid;
  if (problem.goal_W && config_.grid_heuristic) {
    grid.emplace(esdf, *problem.goal_W, start, config_.heuristic_cell_m, config_.com_radius_m + margin);
  }
  const WpgSpace space(config_, inputs_, table_, esdf, *problem.cost, margin, start, escape_clearance, problem.goal_W,
                       problem.goal_W ? std::nullopt : problem.goal_direction_rad, grid ? &*grid : nullptr);
  // A walk in progress goes on from its walking state; from rest only when that finds no way.
  SearchResult<WpgNode> r;
  std::size_t expanded_walking = 0;
  if (problem.start_speed_mps >= config_.walking_start_speed_mps && config_.walking_start_speed_mps > 0) {
    WalkerState walking = s0;
    walking.velocity = problem.start_speed_mps * Vec2(std::cos(yaw), std::sin(yaw));
    r = best_first_search(space, WpgNode{walking, false}, config_.limits);
    expanded_walking = r.expanded;
  }
  if (!r.found()) {
    r = best_first_search(space, WpgNode{s0, true}, config_.limits);
    r.expanded += expanded_walking;
  }
  r.time_s = std::chrono::duration<double>(Clock::now() - t0).count();  // the heuristic's Dijkstra included
  Plan p = plan_outcome(r.status, r.expanded, r.time_s);
  if (!r.found()) return p;
  for (const WpgNode& n : r.path) {
    const WalkerState& w = n.walker;
    p.path_W.push_back(w.com);
    p.yaw_rad.push_back(w.direction_rad);
    p.footsteps_W.push_back(w.support_foot);
  }
  p.length_m = polyline_length(p.path_W);
  p.cost = r.cost;
  return p;
}

}  // namespace navaid::planning
