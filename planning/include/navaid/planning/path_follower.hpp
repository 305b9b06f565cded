#pragma once
// Path following (eLabrador Alg. 2): from the path point nearest to the user, look ahead by the
// foresight distance (2 m) along the path; if the straight line from the user to that point
// crosses an obstacle (a cell with cost > 0.9), shorten the foresight to the obstacle's distance
// and look again. The walking direction is the vector from the user to the point found.
//
// Alg. 2 steps through the path by d / map_resolution indices; we step by arc length, which is
// the same on straight 4-connected runs and right on diagonal ones (a diagonal step is r sqrt 2).
#include <cstddef>
#include <optional>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"

namespace navaid::planning {

using mapping::Vec2;

struct PathFollowerConfig {
  double foresight_m = 2.0;      ///< eLabrador: two metres
  /// Below this foresight the way ahead counts as blocked (the user must stop): one step of a
  /// walker, so a cue is never given toward a point the user would reach in one stride.
  double min_foresight_m = 0.3;
};

/// Keys planning.follow.foresight_m in (0, 20], planning.follow.min_foresight_m in [0, foresight].
PathFollowerConfig read_path_follower_config(const Config& config);

struct FollowStep {
  bool blocked = false;          ///< no collision-free point ahead at >= min_foresight_m
  std::size_t nearest_index = 0; ///< idx_near of Alg. 2
  Vec2 next_W = Vec2::Zero();    ///< p_next (the path's end when the path is shorter)
  double foresight_m = 0.0;      ///< the foresight used after shortening
  Vec2 direction_W = Vec2::Zero();  ///< p_next - p_current (zero when blocked)
  double distance_to_path_m = 0.0;  ///< |p_current - path[idx_near]|
  bool at_end = false;           ///< the look-ahead reached the path's last point
};

/// Distance [m] from `from` to the first obstacle cell the segment from -> to enters (cost >
/// the map's obstacle threshold), walking the grid cells the segment crosses; nullopt when the
/// segment is clear. Cells outside the map are not obstacles (the map does not know them).
std::optional<double> first_obstacle_along(const mapping::CostMap& cost, const Vec2& from, const Vec2& to);

/// The point `distance_m` along the path from point `index` (clamped to the path's end).
Vec2 point_along(const std::vector<Vec2>& path, std::size_t index, double distance_m, bool* at_end = nullptr);

/// One step of Alg. 2. Asserts a non-empty path.
FollowStep follow_path(const Vec2& p_current, const std::vector<Vec2>& path, const mapping::CostMap& cost,
                       const PathFollowerConfig& config);

}  // namespace navaid::planning
