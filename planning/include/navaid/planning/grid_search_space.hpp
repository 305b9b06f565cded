#pragma once
// The grid planners' search space over a cost map (eLabrador's "classical A* with cost map M_c"):
// 8-connected cells, no corner cutting, edge cost = step length x (alpha + w_c x cost of the
// cell entered). So a path's cost is alpha x its length plus w_c x the line integral of the map
// cost along it, f_c of eq. (11), and alpha x octile distance is an admissible, consistent
// heuristic. The goal policy is a template parameter: one point goal (A*), or many boundary
// targets each with its own terminal cost (Direction A*), served by the same best_first_search.
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"

namespace navaid::planning {

struct GridCostConfig {
  double length_weight = 1.0;  ///< alpha: cost per metre walked
  double cost_weight = 1.0;    ///< w_c: weight of the map cost integral f_c
  /// Cells nearer than clearance = base_clearance_m + k_sigma x sigma_xy to an obstacle (by the
  /// ESDF) are blocked. The base is 0 because mapping's cost map is already inflated by the
  /// user's uncertainty; offline maps (navaid plan) set a body radius here.
  double base_clearance_m = 0.0;
  double clearance_k_sigma = 0.0;
};

/// Keys planning.grid.length_weight in (0, 100], planning.grid.cost_weight in [0, 100],
/// planning.grid.base_clearance_m in [0, 2], planning.grid.clearance_k_sigma in [0, 10].
GridCostConfig read_grid_cost_config(const Config& config);

/// Which cells a grid search may enter: not an obstacle of the cost map and, when clearance > 0,
/// at least `clearance_m` from every obstacle (ESDF distance of the cell centre). The ESDF is
/// computed from the cost map when none is given.
class BlockedMask {
 public:
  BlockedMask(const mapping::CostMap& cost, const mapping::Esdf2d* esdf, double clearance_m);
  bool blocked(int index) const { return blocked_[static_cast<std::size_t>(index)] != 0; }
  double clearance_m() const { return clearance_m_; }

 private:
  std::vector<std::uint8_t> blocked_;
  double clearance_m_;
};

/// Cell rectangle [x0, x1) x [y0, y1) of a grid a search may use (a local window of a big map).
struct CellWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(int x, int y) const { return x >= x0 && y >= y0 && x < x1 && y < y1; }
};

/// One target of a multi-goal search and the cost of finishing there.
struct GridTarget {
  int index = 0;
  double terminal_cost = 0.0;
};

/// Goal policy: one cell, terminal cost 0; heuristic alpha x octile distance.
struct PointGoal {
  int index = 0;
};

/// Goal policy: many cells, each with a terminal cost; heuristic min over targets of
/// (alpha x octile distance + terminal cost), admissible because every edge costs >= alpha x step.
struct TargetSet {
  std::vector<GridTarget> targets;
};

template <class Goal>
class GridSearchSpace {
 public:
  using State = int;  ///< linear cell index y * width + x
  static constexpr bool kDenseKeys = true;

  GridSearchSpace(const mapping::CostMap& cost, const BlockedMask& blocked, const GridCostConfig& config,
                  CellWindow window, Goal goal);

  std::size_t key_count() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }
  std::uint64_t key(State s) const { return static_cast<std::uint64_t>(s); }
  double heuristic(State s) const;
  std::optional<double> goal_cost(State s) const;

  template <class Emit>
  void expand(State s, Emit&& emit) const {
    const int x = s % width_;
    const int y = s / width_;
    static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
    static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (!window_.contains(nx, ny)) continue;
      const int n = ny * width_ + nx;
      if (blocked_.blocked(n)) continue;
      // No corner cutting: a diagonal step needs both cells it passes between to be open.
      if (k >= 4 && (blocked_.blocked(y * width_ + nx) || blocked_.blocked(ny * width_ + x))) continue;
      const double step = k < 4 ? resolution_ : resolution_ * kSqrt2;
      emit(n, step * (config_.length_weight + config_.cost_weight * cost_.cells().data()[n]));
    }
  }

  /// alpha x octile distance between two cells [cost units].
  double octile(int a, int b) const;

 private:
  static constexpr double kSqrt2 = 1.4142135623730951;
  const mapping::CostMap& cost_;
  const BlockedMask& blocked_;
  GridCostConfig config_;
  CellWindow window_;
  Goal goal_;
  int width_;
  int height_;
  double resolution_;
  std::vector<GridTarget> sorted_targets_;  // TargetSet: by cell index, for goal_cost lookups
};

}  // namespace navaid::planning
