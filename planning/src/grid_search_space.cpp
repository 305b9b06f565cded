#include "navaid/planning/grid_search_space.hpp"

#include "navaid/planning/config_schema.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>

namespace navaid::planning {

namespace {
const GridCostConfig kGridSearchSpaceDefaults;
const ConfigKey<double> kLengthWeight{"planning.grid.length_weight", kGridSearchSpaceDefaults.length_weight, {1e-6, 100.0},
                                      "alpha: grid search cost per metre walked"};
const ConfigKey<double> kCostWeight{"planning.grid.cost_weight", kGridSearchSpaceDefaults.cost_weight, {0.0, 100.0},
                                    "w_c: weight of the map cost integral in the grid search"};
const ConfigKey<double> kBaseClearance{"planning.grid.base_clearance_m", kGridSearchSpaceDefaults.base_clearance_m, {0.0, 2.0},
                                       "cells nearer than this (plus k sigma) to an obstacle are blocked [m]"};
const ConfigKey<double> kGridSearchSpaceClearanceKSigma{"planning.grid.clearance_k_sigma", kGridSearchSpaceDefaults.clearance_k_sigma, {0.0, 10.0},
                                         "the grid clearance grows by this times the horizontal position sigma"};
}  // namespace

ConfigSchema grid_cost_config_schema() {
  return ConfigSchema().add(kLengthWeight).add(kCostWeight).add(kBaseClearance).add(kGridSearchSpaceClearanceKSigma);
}

GridCostConfig read_grid_cost_config(const Config& config) {
  GridCostConfig c;
  c.length_weight = get(config, kLengthWeight);
  c.cost_weight = get(config, kCostWeight);
  c.base_clearance_m = get(config, kBaseClearance);
  c.clearance_k_sigma = get(config, kGridSearchSpaceClearanceKSigma);
  return c;
}

BlockedMask::BlockedMask(const mapping::CostMap& cost, const mapping::Esdf2d* esdf, double clearance_m)
    : blocked_(cost.geometry().num_cells(), 0), clearance_m_(clearance_m) {
  const mapping::GridGeometry& g = cost.geometry();
  const float* c = cost.cells().data();
  const auto threshold = static_cast<float>(cost.obstacle_threshold());
  for (std::size_t i = 0; i < blocked_.size(); ++i) blocked_[i] = c[i] > threshold ? 1 : 0;
  if (clearance_m <= 0.0) return;
  mapping::Esdf2d own;
  if (esdf == nullptr || esdf->empty() || esdf->geometry() != g) {
    own.update(cost);
    esdf = &own;
  }
  const float* d = esdf->field().cells().data();
  for (std::size_t i = 0; i < blocked_.size(); ++i) {
    if (d[i] < clearance_m) blocked_[i] = 1;
  }
}

template <class Goal>
GridSearchSpace<Goal>::GridSearchSpace(const mapping::CostMap& cost, const BlockedMask& blocked,
                                       const GridCostConfig& config, CellWindow window, Goal goal)
    : cost_(cost),
      blocked_(blocked),
      config_(config),
      window_(window),
      goal_(std::move(goal)),
      width_(cost.geometry().width()),
      height_(cost.geometry().height()),
      resolution_(cost.geometry().resolution()) {
  assert(window_.x0 >= 0 && window_.y0 >= 0 && window_.x1 <= width_ && window_.y1 <= height_);
  if constexpr (std::is_same_v<Goal, TargetSet>) {
    sorted_targets_ = goal_.targets;
    std::sort(sorted_targets_.begin(), sorted_targets_.end(),
              [](const GridTarget& a, const GridTarget& b) { return a.index < b.index; });
  }
}

template <class Goal>
double GridSearchSpace<Goal>::octile(int a, int b) const {
  const int dx = std::abs(a % width_ - b % width_);
  const int dy = std::abs(a / width_ - b / width_);
  const int lo = std::min(dx, dy);
  const int hi = std::max(dx, dy);
  return config_.length_weight * resolution_ * ((hi - lo) + kSqrt2 * lo);
}

template <class Goal>
double GridSearchSpace<Goal>::heuristic(State s) const {
  if constexpr (std::is_same_v<Goal, PointGoal>) {
    return octile(s, goal_.index);
  } else {
    double best = std::numeric_limits<double>::infinity();
    for (const GridTarget& t : goal_.targets) best = std::min(best, octile(s, t.index) + t.terminal_cost);
    return best;
  }
}

template <class Goal>
std::optional<double> GridSearchSpace<Goal>::goal_cost(State s) const {
  if constexpr (std::is_same_v<Goal, PointGoal>) {
    if (s == goal_.index) return 0.0;
    return std::nullopt;
  } else {
    const auto it = std::lower_bound(sorted_targets_.begin(), sorted_targets_.end(), s,
                                     [](const GridTarget& t, int index) { return t.index < index; });
    if (it != sorted_targets_.end() && it->index == s) return it->terminal_cost;
    return std::nullopt;
  }
}

template class GridSearchSpace<PointGoal>;
template class GridSearchSpace<TargetSet>;

}  // namespace navaid::planning
