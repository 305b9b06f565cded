#pragma once
// One typed value per cell of a GridGeometry (the Voxblox layer pattern): the height, undulation,
// collision and cost maps are GridLayers of their own types, so a function that wants a cost map
// cannot be handed a height map. Cells are stored in a core Image (row y, column x), so the PNG
// writers and OpenCV code wrap them without copying.
#include <cassert>
#include <optional>

#include "navaid/core/image.hpp"
#include "navaid/mapping/grid_geometry.hpp"

namespace navaid::mapping {

template <class T>
class GridLayer {
 public:
  using Value = T;

  GridLayer(const GridGeometry& geometry, T fill)
      : geometry_(geometry), cells_(geometry.width(), geometry.height(), 1, fill) {}

  const GridGeometry& geometry() const { return geometry_; }
  const Image<T>& cells() const { return cells_; }
  Image<T>& cells() { return cells_; }

  T& at(const Cell2& c) { return cells_.at(c.x(), c.y()); }
  const T& at(const Cell2& c) const { return cells_.at(c.x(), c.y()); }
  T& at(int x, int y) { return cells_.at(x, y); }
  const T& at(int x, int y) const { return cells_.at(x, y); }

  /// Value of the cell holding p_W; nullopt outside the grid.
  std::optional<T> value_at(const Vec2& p_W) const {
    const Cell2 c = geometry_.cell_of(p_W);
    if (!geometry_.contains(c)) return std::nullopt;
    return at(c);
  }

 private:
  GridGeometry geometry_;
  Image<T> cells_;
};

}  // namespace navaid::mapping
