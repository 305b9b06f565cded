#include "scenarios/grid_planner.hpp"

#include <cmath>
#include <limits>
#include <queue>

#include <opencv2/imgproc.hpp>

#include "navaid/simulation/occupancy_export.hpp"

namespace navaid::simulation::scenarios {

std::optional<std::vector<Vec2>> plan_grid_path(const World& world, const Vec2& lo, const Vec2& hi, double resolution_m,
                                                const Vec2& start, const Vec2& goal, double clearance_m) {
  const ClearanceBand band;
  AxisAlignedBox bounds;
  bounds.extend(Vec3(lo.x(), lo.y(), band.z_min_m));
  bounds.extend(Vec3(hi.x(), hi.y(), band.z_max_m));
  const OccupancyGrid3D grid = voxelize(world, resolution_m, bounds);
  const int W = grid.size.x(), H = grid.size.y();
  cv::Mat free_space(H, W, CV_8U, cv::Scalar(255));
  for (int iz = 0; iz < grid.size.z(); ++iz)
    for (int iy = 0; iy < H; ++iy)
      for (int ix = 0; ix < W; ++ix)
        if (grid.occupied(ix, iy, iz)) free_space.at<std::uint8_t>(iy, ix) = 0;
  cv::Mat dist;
  cv::distanceTransform(free_space, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  // An obstacle may fill only part of its cell: keep a half cell diagonal (+ a bit) in reserve.
  const float need = static_cast<float>((clearance_m + 0.75 * resolution_m) / resolution_m);
  auto traversable = [&](int x, int y) { return x >= 0 && y >= 0 && x < W && y < H && dist.at<float>(y, x) >= need; };
  auto cell_of = [&](const Vec2& p) {
    return Eigen::Vector2i(static_cast<int>(std::floor((p.x() - lo.x()) / resolution_m)),
                           static_cast<int>(std::floor((p.y() - lo.y()) / resolution_m)));
  };
  auto centre = [&](int x, int y) { return Vec2(lo.x() + (x + 0.5) * resolution_m, lo.y() + (y + 0.5) * resolution_m); };
  const Eigen::Vector2i s = cell_of(start), g = cell_of(goal);
  if (!traversable(s.x(), s.y()) || !traversable(g.x(), g.y())) return std::nullopt;

  const auto idx = [&](int x, int y) { return static_cast<std::size_t>(y) * W + x; };
  std::vector<float> cost(static_cast<std::size_t>(W) * H, std::numeric_limits<float>::infinity());
  std::vector<int> parent(cost.size(), -1);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  const auto heuristic = [&](int x, int y) {
    const float dx = static_cast<float>(std::abs(x - g.x())), dy = static_cast<float>(std::abs(y - g.y()));
    return std::max(dx, dy) + (std::sqrt(2.0f) - 1.0f) * std::min(dx, dy);
  };
  cost[idx(s.x(), s.y())] = 0.0f;
  open.push({heuristic(s.x(), s.y()), static_cast<int>(idx(s.x(), s.y()))});
  bool found = false;
  while (!open.empty()) {
    const auto [f, i] = open.top();
    open.pop();
    const int x = i % W, y = i / W;
    if (x == g.x() && y == g.y()) {
      found = true;
      break;
    }
    if (f > cost[static_cast<std::size_t>(i)] + heuristic(x, y) + 1e-3f) continue;  // stale entry
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !traversable(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 && (!traversable(x + dx, y) || !traversable(x, y + dy))) continue;  // no corner cutting
        const float c = cost[static_cast<std::size_t>(i)] + ((dx != 0 && dy != 0) ? std::sqrt(2.0f) : 1.0f);
        const std::size_t j = idx(x + dx, y + dy);
        if (c < cost[j]) {
          cost[j] = c;
          parent[j] = i;
          open.push({c + heuristic(x + dx, y + dy), static_cast<int>(j)});
        }
      }
  }
  if (!found) return std::nullopt;
  std::vector<Vec2> cells;
  for (int i = static_cast<int>(idx(g.x(), g.y())); i >= 0; i = parent[static_cast<std::size_t>(i)])
    cells.push_back(centre(i % W, i / W));
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  cells.back() = goal;

  // Line-of-sight shortcuts: extend each straight piece as far as the traversable cells allow.
  const auto visible = [&](const Vec2& a, const Vec2& b) {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.25 * resolution_m))));
    for (int k = 0; k <= n; ++k) {
      const Eigen::Vector2i c = cell_of(a + (b - a) * (static_cast<double>(k) / n));
      if (!traversable(c.x(), c.y())) return false;
    }
    return true;
  };
  std::vector<Vec2> path{cells.front()};
  std::size_t i = 0;
  while (i + 1 < cells.size()) {
    std::size_t j = i + 1;
    while (j + 1 < cells.size() && visible(cells[i], cells[j + 1])) ++j;
    path.push_back(cells[j]);
    i = j;
  }
  return path;
}

}  // namespace navaid::simulation::scenarios
