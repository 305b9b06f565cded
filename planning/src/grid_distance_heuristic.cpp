#include "navaid/planning/grid_distance_heuristic.hpp"

#include <cmath>

namespace navaid::planning {

GridDistanceHeuristic::GridDistanceHeuristic(const mapping::Esdf2d& esdf, const mapping::Vec2& goal_W,
                                             const mapping::Vec2& start_W, double cell_m, double clearance_m)
    : esdf_(esdf), origin_(esdf.geometry().origin_W()), goal_(goal_W), clearance_(clearance_m) {
  const mapping::GridGeometry& g = esdf.geometry();
  per_ = std::max(1, static_cast<int>(std::lround(cell_m / g.resolution())));
  cell_ = per_ * g.resolution();
  nx_ = (g.width() + per_ - 1) / per_;
  ny_ = (g.height() + per_ - 1) / per_;
  const std::size_t n = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  distance_.assign(n, std::numeric_limits<float>::infinity());
  settled_.assign(n, 0);
  kind_.assign(n, kUnknown);
  const mapping::Vec2 s = (start_W - origin_) / cell_;
  start_x_ = static_cast<int>(std::floor(s.x()));
  start_y_ = static_cast<int>(std::floor(s.y()));
  const mapping::Vec2 q = (goal_W - origin_) / cell_;
  const int gx = static_cast<int>(std::floor(q.x()));
  const int gy = static_cast<int>(std::floor(q.y()));
  if (gx < 0 || gy < 0 || gx >= nx_ || gy >= ny_) return;
  const int goal = gy * nx_ + gx;
  distance_[static_cast<std::size_t>(goal)] = 0.0F;
  open_.push({to_start(goal), 0.0F, goal});
  // Cells whose way to the goal is this long do not matter to a search from the start.
  f_limit_ = 4.0F * to_start(goal) + 8.0F * static_cast<float>(cell_);
}

float GridDistanceHeuristic::to_start(int cell) const {
  // Octile distance: the exact cost of the 8-connected moves in free space, so the search runs
  // along the corridor instead of flooding the ellipse that the straight distance leaves.
  const double dx = std::abs(cell % nx_ - start_x_);
  const double dy = std::abs(cell / nx_ - start_y_);
  return static_cast<float>(cell_ * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy)));
}

bool GridDistanceHeuristic::passable(int cell) {
  std::uint8_t& kind = kind_[static_cast<std::size_t>(cell)];
  if (kind == kUnknown) {
    const mapping::GridLayer<float>& field = esdf_.field();
    const int x0 = (cell % nx_) * per_;
    const int y0 = (cell / nx_) * per_;
    const int x1 = std::min(x0 + per_, field.geometry().width());
    const int y1 = std::min(y0 + per_, field.geometry().height());
    bool obstacle = false, room = false;
    for (int y = y0; y < y1 && !obstacle; ++y)
      for (int x = x0; x < x1; ++x) {
        const float d = field.at(x, y);
        if (d <= 0.0F) {
          obstacle = true;
          break;
        }
        if (d >= clearance_) room = true;
      }
    kind = room && !obstacle ? kPassable : kBlocked;
  }
  return kind == kPassable;
}

void GridDistanceHeuristic::settle_until(int cell, std::size_t budget) {
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const float straight = static_cast<float>(cell_);
  const float diagonal = static_cast<float>(cell_ * std::sqrt(2.0));
  const std::size_t stop = settled_count_ + budget;
  while (!open_.empty() && !settled_[static_cast<std::size_t>(cell)] && open_.top().f <= f_limit_ &&
         settled_count_ < stop) {
    const int i = open_.top().cell;
    open_.pop();
    if (settled_[static_cast<std::size_t>(i)]) continue;
    const float d = distance_[static_cast<std::size_t>(i)];
    settled_[static_cast<std::size_t>(i)] = 1;
    ++settled_count_;
    const int x = i % nx_;
    const int y = i / nx_;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= nx_ || ny >= ny_) continue;
      const int n = ny * nx_ + nx;
      if (settled_[static_cast<std::size_t>(n)] || !passable(n)) continue;
      // No corner cutting: a diagonal needs both cells it passes between.
      if (k >= 4 && (!passable(y * nx_ + nx) || !passable(ny * nx_ + x))) continue;
      const float nd = d + (k < 4 ? straight : diagonal);
      if (nd < distance_[static_cast<std::size_t>(n)]) {
        distance_[static_cast<std::size_t>(n)] = nd;
        open_.push({nd + to_start(n), nd, n});
      }
    }
  }
}

double GridDistanceHeuristic::coarse_distance(int cell) {
  const auto c = static_cast<std::size_t>(cell);
  // On the frontier the tentative distance is a real coarse path's length: good enough for a
  // heuristic, and no resumption (the footstep search mostly asks about cells beside the corridor).
  if (!settled_[c] && std::isfinite(distance_[c])) return distance_[c];
  settle_until(cell, first_query_ ? std::numeric_limits<std::size_t>::max() : kResumeBudget);
  first_query_ = false;
  if (settled_[c] || std::isfinite(distance_[c])) return distance_[c];
  if (open_.empty()) return std::numeric_limits<double>::infinity();  // not connected to the goal
  // Stopped at the limit or the budget: an unsettled cell's distance is at least (frontier f) -
  // (its h).
  return std::max(0.0, static_cast<double>(open_.top().f) - to_start(cell));
}

double GridDistanceHeuristic::at(const mapping::Vec2& p_W) {
  const mapping::Vec2 q = (p_W - origin_) / cell_;
  const int x = static_cast<int>(std::floor(q.x()));
  const int y = static_cast<int>(std::floor(q.y()));
  if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return std::numeric_limits<double>::infinity();
  const int cell = y * nx_ + x;
  const double straight = (p_W - goal_).norm();
  double coarse = std::numeric_limits<double>::infinity();
  if (passable(cell)) {
    coarse = coarse_distance(cell);
  } else {
    // The walker stands where the coarse grid is blocked (near a wall, in a door): the way on goes
    // through a passable neighbour.
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx;
        const int ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= nx_ || ny >= ny_) continue;
        const int n = ny * nx_ + nx;
        if (!passable(n)) continue;
        const mapping::Vec2 centre = origin_ + (mapping::Vec2(nx, ny).array() + 0.5).matrix() * cell_;
        coarse = std::min(coarse, coarse_distance(n) + (p_W - centre).norm());
      }
    if (!std::isfinite(coarse)) return straight;
  }
  if (!std::isfinite(coarse)) return coarse;
  return std::max(straight, coarse - std::sqrt(2.0) * cell_);
}

}  // namespace navaid::planning
