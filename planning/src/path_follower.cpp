#include "navaid/planning/path_follower.hpp"

#include <cassert>
#include <cmath>
#include <limits>

#include "navaid/core/errors.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {
const ConfigKey<double> kForesight{"planning.follow.foresight_m", PathFollowerConfig{}.foresight_m, {1e-3, 20.0},
                                   "path following looks this far ahead along the path [m] (eLabrador: 2)"};
const ConfigKey<double> kMinForesight{"planning.follow.min_foresight_m", PathFollowerConfig{}.min_foresight_m,
                                      {0.0, 20.0}, "below this foresight the way ahead is blocked [m] (<= foresight_m)"};
}  // namespace

ConfigSchema path_follower_config_schema() { return ConfigSchema().add(kForesight).add(kMinForesight); }

PathFollowerConfig read_path_follower_config(const Config& config) {
  PathFollowerConfig c;
  c.foresight_m = get(config, kForesight);
  c.min_foresight_m = get(config, within(kMinForesight, {0.0, c.foresight_m}));
  return c;
}

std::optional<double> first_obstacle_along(const mapping::CostMap& cost, const Vec2& from, const Vec2& to) {
  // Grid traversal (Amanatides-Woo): every cell the segment passes through, in order.
  const mapping::GridGeometry& g = cost.geometry();
  const double r = g.resolution();
  const Vec2 d = to - from;
  const double length = d.norm();
  mapping::Cell2 c = g.cell_of(from);
  const mapping::Cell2 end = g.cell_of(to);
  const auto hit = [&](const mapping::Cell2& cell) { return g.contains(cell) && cost.is_obstacle(cell); };
  if (hit(c)) return 0.0;
  if (length == 0.0) return std::nullopt;
  const Vec2 u = d / length;
  int step[2];
  double t_max[2];
  double t_delta[2];
  for (int i = 0; i < 2; ++i) {
    if (u[i] > 0.0) {
      step[i] = 1;
      t_max[i] = ((c[i] + 1 + g.origin_cell()[i]) * r - from[i]) / u[i];
      t_delta[i] = r / u[i];
    } else if (u[i] < 0.0) {
      step[i] = -1;
      t_max[i] = ((c[i] + g.origin_cell()[i]) * r - from[i]) / u[i];
      t_delta[i] = -r / u[i];
    } else {
      step[i] = 0;
      t_max[i] = std::numeric_limits<double>::infinity();
      t_delta[i] = std::numeric_limits<double>::infinity();
    }
  }
  while (c != end) {
    const int axis = t_max[0] < t_max[1] ? 0 : 1;
    const double t = t_max[axis];
    if (t > length) break;
    c[axis] += step[axis];
    t_max[axis] += t_delta[axis];
    if (hit(c)) return t;
  }
  return std::nullopt;
}

Vec2 point_along(const std::vector<Vec2>& path, std::size_t index, double distance_m, bool* at_end) {
  assert(!path.empty() && index < path.size());
  double left = distance_m;
  for (std::size_t i = index; i + 1 < path.size(); ++i) {
    const double seg = (path[i + 1] - path[i]).norm();
    if (seg >= left && seg > 0.0) {
      if (at_end != nullptr) *at_end = false;
      return path[i] + (path[i + 1] - path[i]) * (left / seg);
    }
    left -= seg;
  }
  if (at_end != nullptr) *at_end = true;
  return path.back();
}

FollowStep follow_path(const Vec2& p_current, const std::vector<Vec2>& path, const mapping::CostMap& cost,
                       const PathFollowerConfig& config) {
  assert(!path.empty());
  FollowStep s;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double d = (path[i] - p_current).squaredNorm();
    if (d < best) {
      best = d;
      s.nearest_index = i;
    }
  }
  s.distance_to_path_m = std::sqrt(best);
  double foresight = config.foresight_m;
  for (;;) {
    bool at_end = false;
    const Vec2 next = point_along(path, s.nearest_index, foresight, &at_end);
    const std::optional<double> obstacle = first_obstacle_along(cost, p_current, next);
    if (!obstacle) {
      s.next_W = next;
      s.foresight_m = foresight;
      s.direction_W = next - p_current;
      s.at_end = at_end;
      // A path's end reached within one stride is arrival, not a blocked way.
      if (s.direction_W.norm() < config.min_foresight_m && !at_end) s.blocked = true;
      return s;
    }
    // Alg. 2 line 11: d <- d_obs. Shrink strictly, so the loop ends.
    const double shorter = std::min(*obstacle, foresight - 0.5 * cost.geometry().resolution());
    if (shorter < config.min_foresight_m || shorter <= 0.0) {
      s.blocked = true;
      s.next_W = p_current;
      s.foresight_m = std::max(0.0, shorter);
      return s;
    }
    foresight = shorter;
  }
}

}  // namespace navaid::planning
