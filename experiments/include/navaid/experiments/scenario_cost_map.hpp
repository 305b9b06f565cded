#pragma once
// A simulator scenario's ground truth as a planner's cost map: the occupancy of the body's height
// band above the scenario's ground (`navaid plan --map scenario:NAME`, the Smart Cane Table I
// reproduction, the planning benchmarks).
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"

namespace navaid::experiments {

struct ScenarioCostMap {
  mapping::CostMap cost;
  std::string description;
};

/// Keys planning.map.resolution_m (default 0.1), planning.map.band_m ([low, high] above the
/// ground, default [0.2, 2.0]) and planning.occupancy.*. Throws UsageError for an unknown scenario.
ScenarioCostMap scenario_cost_map(const std::string& scenario, const Config& config);

}  // namespace navaid::experiments
