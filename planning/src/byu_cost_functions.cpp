#include "navaid/planning/byu_cost_functions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {

constexpr double kOneDegree = kPi / 180.0;

constexpr NameTable<ByuCostFunction, 2> kFunctionNames{{
    {ByuCostFunction::kFicf, "ficf"},
    {ByuCostFunction::kCacf, "cacf"},
}};

void check_path(const std::string& origin, const char* key, double width_m, double distance_m) {
  if (!(0.5 * width_m <= distance_m)) {
    throw ConfigError(origin, key,
                      fmt::format("the intended path's half width {:.3f} m exceeds its distance {:.3f} m "
                                  "(eq. 2.11's gamma = arccos((w/2)/d) needs w/2 <= d)",
                                  0.5 * width_m, distance_m));
  }
}

/// Calls f(bearing, range, weight) for every bin within the considered bearings that holds an
/// obstacle or (when enabled) a drop-off; range is the nearer of the two.
template <class F>
void for_each_return(const mapping::ObstacleScan& scan, const ByuCostConfig& config, F&& f) {
  const std::size_t n = scan.ranges.size();
  if (n == 0) return;
  if (!(scan.bearing_increment_rad > 0.0) && n > 1) {
    throw Error(fmt::format("obstacle scan: bin width {} rad is not positive", scan.bearing_increment_rad));
  }
  const bool drop_offs = config.drop_offs_are_obstacles && !scan.drop_off_ranges.empty();
  if (!scan.drop_off_ranges.empty() && scan.drop_off_ranges.size() != n) {
    throw Error(fmt::format("obstacle scan: {} drop-off bins for {} range bins", scan.drop_off_ranges.size(), n));
  }
  const double weight = scan.bearing_increment_rad > 0.0 ? scan.bearing_increment_rad / kOneDegree : 1.0;
  const double limit = config.max_bearing_rad + 1e-9;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    double bearing = scan.bearing(i);
    if (std::abs(bearing) > limit) continue;
    if (std::abs(bearing) < 1e-9) bearing = 0.0;  // the straight-ahead bin, whatever the rounding
    double r = std::isnan(scan.ranges[i]) ? kInf : static_cast<double>(scan.ranges[i]);
    if (drop_offs && !std::isnan(scan.drop_off_ranges[i])) r = std::min(r, static_cast<double>(scan.drop_off_ranges[i]));
    if (r == kInf) continue;  // no return in this bin
    if (r < 0.0) throw Error(fmt::format("obstacle scan: negative range {} m in bin {}", r, i));
    f(bearing, r, weight);
  }
}

}  // namespace

std::string_view to_string(ByuCostFunction function) { return enum_name(kFunctionNames, function); }

std::optional<ByuCostFunction> byu_cost_function_from_string(std::string_view name) {
  return enum_value(kFunctionNames, name);
}

namespace {
const ByuCostConfig kByuCostFunctionsDefaults;
const ConfigKey<double> kFicfWidth{"planning.byu.ficf.width_m", kByuCostFunctionsDefaults.ficf.width_m, {0.01, 10.0},
                                   "FICF: width w of the intended user path [m]"};
const ConfigKey<double> kFicfDistance{"planning.byu.ficf.distance_m", kByuCostFunctionsDefaults.ficf.distance_m, {0.05, 20.0},
                                      "FICF: distance d of the intended path (side costs only below it) [m]"};
const ConfigKey<double> kFicfForward{"planning.byu.ficf.forward_threshold", kByuCostFunctionsDefaults.ficf.thresholds.forward,
                                     {0.0, 1e6}, "FICF: forward cost threshold of a rumble"};
const ConfigKey<double> kFicfLeftRight{"planning.byu.ficf.left_right_threshold", kByuCostFunctionsDefaults.ficf.thresholds.left_right,
                                       {0.0, 1e6}, "FICF: left / right cost threshold of a rumble"};
const ConfigKey<double> kCacfWidth{"planning.byu.cacf.width_m", kByuCostFunctionsDefaults.cacf.width_m, {0.01, 10.0},
                                   "CACF: width w of the intended path (lower safety cushion) [m]"};
const ConfigKey<double> kCacfDistance{"planning.byu.cacf.distance_m", kByuCostFunctionsDefaults.cacf.distance_m, {0.05, 20.0},
                                      "CACF: distance d of the intended path [m]"};
const ConfigKey<double> kCacfCushionWidth{"planning.byu.cacf.cushion_width_m", kByuCostFunctionsDefaults.cacf.cushion_width_m,
                                          {0.01, 20.0}, "CACF: width of the upper safety cushion [m] (>= width_m)"};
const ConfigKey<double> kCacfCushionDistance{"planning.byu.cacf.cushion_distance_m", kByuCostFunctionsDefaults.cacf.cushion_distance_m,
                                             {0.05, 20.0}, "CACF: distance of the upper safety cushion [m] (>= "
                                                           "distance_m)"};
const ConfigKey<double> kCacfForward{"planning.byu.cacf.forward_threshold", kByuCostFunctionsDefaults.cacf.thresholds.forward,
                                     {0.0, 1e6}, "CACF: forward cost threshold of a rumble"};
const ConfigKey<double> kCacfLeftRight{"planning.byu.cacf.left_right_threshold", kByuCostFunctionsDefaults.cacf.thresholds.left_right,
                                       {0.0, 1e6}, "CACF: left / right cost threshold of a rumble"};
const ConfigKey<double> kMaxBearing{"planning.byu.max_bearing_deg", rad_to_deg(kByuCostFunctionsDefaults.max_bearing_rad), {1.0, 89.0},
                                    "scan bins beyond this bearing are ignored; e of eq. 2.13 [deg]"};
const ConfigKey<bool> kDropOffs{"planning.byu.drop_offs_are_obstacles", kByuCostFunctionsDefaults.drop_offs_are_obstacles,
                                "drop-offs (kerbs stepped down) count as obstacles"};
}  // namespace

ConfigSchema byu_cost_config_schema() {
  return ConfigSchema()
      .add(kFicfWidth)
      .add(kFicfDistance)
      .add(kFicfForward)
      .add(kFicfLeftRight)
      .add(kCacfWidth)
      .add(kCacfDistance)
      .add(kCacfCushionWidth)
      .add(kCacfCushionDistance)
      .add(kCacfForward)
      .add(kCacfLeftRight)
      .add(kMaxBearing)
      .add(kDropOffs);
}

ByuCostConfig read_byu_cost_config(const Config& config) {
  ByuCostConfig c;
  c.ficf.width_m = get(config, kFicfWidth);
  c.ficf.distance_m = get(config, kFicfDistance);
  c.ficf.thresholds.forward = get(config, kFicfForward);
  c.ficf.thresholds.left_right = get(config, kFicfLeftRight);
  c.cacf.width_m = get(config, kCacfWidth);
  c.cacf.distance_m = get(config, kCacfDistance);
  c.cacf.cushion_width_m = get(config, kCacfCushionWidth);
  c.cacf.cushion_distance_m = get(config, kCacfCushionDistance);
  c.cacf.thresholds.forward = get(config, kCacfForward);
  c.cacf.thresholds.left_right = get(config, kCacfLeftRight);
  c.max_bearing_rad = deg_to_rad(get(config, kMaxBearing));
  c.drop_offs_are_obstacles = get(config, kDropOffs);

  const auto origin = [&](const char* key) { return config.has(key) ? config.origin(key) : std::string("<defaults>"); };
  check_path(origin("planning.byu.ficf.width_m"), "planning.byu.ficf.width_m", c.ficf.width_m, c.ficf.distance_m);
  check_path(origin("planning.byu.cacf.width_m"), "planning.byu.cacf.width_m", c.cacf.width_m, c.cacf.distance_m);
  check_path(origin("planning.byu.cacf.cushion_width_m"), "planning.byu.cacf.cushion_width_m", c.cacf.cushion_width_m,
             c.cacf.cushion_distance_m);
  if (c.cacf.cushion_width_m < c.cacf.width_m) {
    throw ConfigError(origin("planning.byu.cacf.cushion_width_m"), "planning.byu.cacf.cushion_width_m",
                      fmt::format("the upper cushion ({} m) must be at least as wide as the intended path "
                                  "planning.byu.cacf.width_m ({} m)",
                                  c.cacf.cushion_width_m, c.cacf.width_m));
  }
  if (c.cacf.cushion_distance_m < c.cacf.distance_m) {
    throw ConfigError(origin("planning.byu.cacf.cushion_distance_m"), "planning.byu.cacf.cushion_distance_m",
                      fmt::format("the upper cushion ({} m) must reach at least as far as the intended path "
                                  "planning.byu.cacf.distance_m ({} m)",
                                  c.cacf.cushion_distance_m, c.cacf.distance_m));
  }
  return c;
}

const ByuThresholds& byu_thresholds(ByuCostFunction function, const ByuCostConfig& config) {
  return function == ByuCostFunction::kFicf ? config.ficf.thresholds : config.cacf.thresholds;
}

double intended_path_range(double bearing_rad, double width_m, double distance_m) {
  const double s = std::abs(std::sin(bearing_rad));
  if (s * distance_m <= 0.5 * width_m) return distance_m;  // the front arc (also bearing 0)
  return 0.5 * width_m / s;
}

double intended_path_gamma(double width_m, double distance_m) { return std::acos(0.5 * width_m / distance_m); }

double ficf_forward_term(double range_m) { return std::exp(4.5 - range_m) / 100.0; }

double ficf_side_term(double bearing_rad, double range_m, double width_m, double edge_rad) {
  const double closeness = (edge_rad - std::abs(bearing_rad)) / (edge_rad - std::asin(0.5 * width_m / range_m));
  return std::exp(closeness + 3.5 - range_m) / 100.0;
}

double cacf_forward_term(double range_m, double distance_m) { return (distance_m - range_m) * (distance_m - range_m); }

double cacf_side_term(double range_m, double upper_cushion_m) {
  return (upper_cushion_m - range_m) * (upper_cushion_m - range_m);
}

ByuCosts ficf_costs(const mapping::ObstacleScan& scan, const ByuCostConfig& config) {
  const FicfConfig& f = config.ficf;
  ByuCosts c;
  for_each_return(scan, config, [&](double bearing, double r, double weight) {
    const double p = intended_path_range(bearing, f.width_m, f.distance_m);
    if (r < p) {
      c.forward += weight * ficf_forward_term(r);
    } else if (r > p && r < f.distance_m) {
      // Here p < d, so p = (w/2)/|sin(bearing)| and bearing != 0.
      const double term = weight * ficf_side_term(bearing, r, f.width_m, config.max_bearing_rad);
      (bearing > 0.0 ? c.left : c.right) += term;
    }
  });
  return c;
}

ByuCosts cacf_costs(const mapping::ObstacleScan& scan, const ByuCostConfig& config) {
  const CacfConfig& f = config.cacf;
  ByuCosts c;
  for_each_return(scan, config, [&](double bearing, double r, double weight) {
    const double lower = intended_path_range(bearing, f.width_m, f.distance_m);
    const double upper = intended_path_range(bearing, f.cushion_width_m, f.cushion_distance_m);
    if (r < lower) {
      c.forward += weight * cacf_forward_term(r, f.distance_m);
    } else if (r < upper) {
      const double term = weight * cacf_side_term(r, upper);
      if (bearing > 0.0) c.left += term;
      if (bearing < 0.0) c.right += term;  // bearing 0: neither side
    }
  });
  return c;
}

ByuCosts byu_costs(const mapping::ObstacleScan& scan, ByuCostFunction function, const ByuCostConfig& config) {
  return function == ByuCostFunction::kFicf ? ficf_costs(scan, config) : cacf_costs(scan, config);
}

RumbleState rumble_state(const ByuCosts& costs, const ByuThresholds& thresholds) {
  if (!(costs.forward > thresholds.forward)) return RumbleState::kOff;
  // Sides equal up to rounding are a tie: a symmetric scene must not pick a side by the last bit of
  // a bearing (the bins' bearings are min + i * increment, not exactly symmetric).
  const double tie = 1e-9 * std::max({1.0, std::abs(costs.left), std::abs(costs.right)});
  if (std::abs(costs.left - costs.right) <= tie) return RumbleState::kBoth;
  if (costs.left < costs.right && costs.left < thresholds.left_right) return RumbleState::kLeft;
  if (costs.right < costs.left && costs.right < thresholds.left_right) return RumbleState::kRight;
  return RumbleState::kBoth;
}

GuidanceCommand byu_guidance(const mapping::ObstacleScan& scan, EstimatorMode mode, ByuCostFunction function,
                             const ByuCostConfig& config) {
  const ByuCosts costs = byu_costs(scan, function, config);
  const ByuThresholds& t = byu_thresholds(function, config);
  const RumbleState state = rumble_state(costs, t);
  GuidanceCommand cmd;
  cmd.t = scan.t;
  cmd.rumble = state;
  const std::string numbers = fmt::format("{} C_F {:.3f} (threshold {:.2f}), C_L {:.3f}, C_R {:.3f} (threshold {:.2f})",
                                          to_string(function), costs.forward, t.forward, costs.left, costs.right,
                                          t.left_right);
  switch (state) {
    case RumbleState::kOff:
      cmd.action = GuidanceAction::kGo;
      cmd.reason = GuidanceReason::kPathFound;
      cmd.detail = "the intended path is clear: " + numbers;
      break;
    case RumbleState::kLeft:
    case RumbleState::kRight:
      cmd.action = GuidanceAction::kGo;
      cmd.reason = GuidanceReason::kObstacleAhead;
      cmd.detail = fmt::format("obstacle ahead, the {} is freer: ", state == RumbleState::kLeft ? "left" : "right") + numbers;
      break;
    case RumbleState::kBoth:
      cmd.action = GuidanceAction::kStop;
      cmd.reason = GuidanceReason::kObstacleAhead;
      cmd.detail = "obstacle ahead and neither side is free: stop and search; " + numbers;
      break;
  }
  const bool unsure = mode == EstimatorMode::kInitializing || mode == EstimatorMode::kLost;
  const bool frame_from_estimate = scan.counters.ground_source == mapping::GroundSource::kPrior;
  if (unsure && frame_from_estimate) {
    cmd.confidence = 0.0;
    cmd.detail += fmt::format("; no measured ground plane and the estimator is {}: frame U is unverified",
                              navaid::to_string(mode));
    return cmd;
  }
  cmd.confidence = 1.0;
  if (unsure) cmd.detail += fmt::format("; estimator {}: the warning needs no pose", navaid::to_string(mode));
  if (state == RumbleState::kOff) {
    cmd.heading_rad = 0.0;
    cmd.lookahead_m = function == ByuCostFunction::kFicf ? config.ficf.distance_m : config.cacf.distance_m;
  }
  return cmd;
}

GuidanceCommand rumble_command(Timestamp t, RumbleState state) {
  GuidanceCommand command;
  command.t = t;
  command.action = GuidanceAction::kGo;
  command.reason = state == RumbleState::kOff ? GuidanceReason::kPathFound : GuidanceReason::kObstacleAhead;
  command.confidence = 1.0;
  command.rumble = state;
  return command;
}

}  // namespace navaid::planning
