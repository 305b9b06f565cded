#pragma once
// The 2D grid of the map layers: an axis-aligned square in W's x-y plane (W is gravity-aligned, so
// a pillar of the 3D map is one cell) around the user. The grid's origin lies on whole multiples
// of the resolution, so a window that follows the user shifts by whole cells: a cell covers the
// same patch of ground in every window, and layers never need resampling when the window scrolls.
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>

#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"

namespace navaid::mapping {

using Vec2 = Eigen::Vector2d;
using Cell2 = Eigen::Vector2i;

struct GridConfig {
  double resolution_m = 0.1;  ///< cell edge [m] (eLabrador's map resolution)
  double size_m = 10.0;       ///< window edge [m] (eLabrador: 10 m x 10 m local window)
};

/// Keys mapping.grid.resolution_m in [0.01, 1] and mapping.grid.size_m in [1, 100]; the window
/// must hold at least 3 x 3 cells (the Sobel filter's support).
GridConfig read_grid_config(const Config& config);

class GridGeometry {
 public:
  /// A width x height grid whose cell (0, 0) is the world cell `origin_cell` (world cell (i, j)
  /// spans [i r, (i + 1) r) x [j r, (j + 1) r)). Asserts resolution > 0 and a non-empty size.
  GridGeometry(const Cell2& origin_cell, int width, int height, double resolution_m);

  /// The square window of `config` centred on `center_W` (x-y), snapped to whole cells.
  static GridGeometry around(const Vec2& center_W, const GridConfig& config);

  double resolution() const { return resolution_; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t num_cells() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }
  /// World cell index of the grid's cell (0, 0).
  const Cell2& origin_cell() const { return origin_; }
  /// Lower-left corner of cell (0, 0) in W [m].
  Vec2 origin_W() const { return origin_.cast<double>() * resolution_; }

  /// World cell index that contains p_W (floor(p / r) per axis).
  Cell2 world_cell(const Vec2& p_W) const;
  /// Grid cell containing p_W; may lie outside the grid (check contains()).
  Cell2 cell_of(const Vec2& p_W) const { return world_cell(p_W) - origin_; }
  Vec2 cell_center(const Cell2& c) const { return (((c + origin_).cast<double>()).array() + 0.5).matrix() * resolution_; }
  bool contains(const Cell2& c) const { return c.x() >= 0 && c.y() >= 0 && c.x() < width_ && c.y() < height_; }
  std::size_t index(const Cell2& c) const {
    return static_cast<std::size_t>(c.y()) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(c.x());
  }
  /// Continuous grid coordinates of p_W in cells, cell centres at integers (for interpolation).
  Vec2 continuous_cell(const Vec2& p_W) const { return p_W / resolution_ - origin_.cast<double>() - Vec2(0.5, 0.5); }

  bool operator==(const GridGeometry& o) const {
    return origin_ == o.origin_ && width_ == o.width_ && height_ == o.height_ && resolution_ == o.resolution_;
  }
  bool operator!=(const GridGeometry& o) const { return !(*this == o); }

 private:
  Cell2 origin_;
  int width_;
  int height_;
  double resolution_;
};

/// Calls f(cell) for every grid cell that a voxel's x-y footprint (a square of edge size_m around
/// center_W) covers: the cells whose centres lie inside the footprint, or, when the voxel is
/// smaller than a cell and covers no centre, the one cell holding its centre. Cells outside the
/// grid are skipped.
template <class F>
void for_each_footprint_cell(const GridGeometry& g, const Vec3& center_W, double size_m, F&& f) {
  const Vec2 c = center_W.head<2>();
  const double half = 0.5 * size_m;
  const Cell2 lo = g.cell_of(c - Vec2(half, half) + Vec2::Constant(0.5 * g.resolution()));
  const Cell2 hi = g.cell_of(c + Vec2(half, half) - Vec2::Constant(0.5 * g.resolution()));
  if (lo.x() > hi.x() || lo.y() > hi.y()) {
    const Cell2 one = g.cell_of(c);
    if (g.contains(one)) f(one);
    return;
  }
  for (int y = std::max(lo.y(), 0); y <= std::min(hi.y(), g.height() - 1); ++y) {
    for (int x = std::max(lo.x(), 0); x <= std::min(hi.x(), g.width() - 1); ++x) f(Cell2(x, y));
  }
}

}  // namespace navaid::mapping
