#pragma once
// 2D Euclidean signed distance field over the cost map, for planners that ask "how far is the
// nearest obstacle and which way is away from it" (the Smart Cane's walking-path search checks its
// three spheres against it).
//
// Obstacles are the cost map's cells with cost > obstacle_threshold. Signed: outside obstacles the
// value is the distance [m] from the cell centre to the nearest obstacle cell's centre; inside,
// minus the distance to the nearest free cell's centre. So a boundary obstacle cell reads -r and
// its free neighbour +r, and the bilinear interpolant crosses zero half-way, on the cell face.
// Obstacles beyond the window are not seen: near the edges the values are upper bounds.
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/distance_transform.hpp"

namespace navaid::mapping {

struct Esdf2dConfig {
  DistanceTransformBackend backend = DistanceTransformBackend::kOpenCv;  ///< the faster (measured)
};

/// Key mapping.esdf.backend: "opencv" or "dynamicedt3d".
Esdf2dConfig read_esdf_2d_config(const Config& config);

class Esdf2d {
 public:
  explicit Esdf2d(const Esdf2dConfig& config = {});

  /// Recomputes the field on the cost map's grid. A window that scrolled is a new geometry with
  /// the same cell boundaries, so values at a world point whose nearest obstacle stays inside both
  /// windows do not change; the buffers are reused while the grid size stays the same.
  void update(const CostMap& cost);

  bool empty() const { return !field_.has_value(); }
  /// The grid of the last update (asserts !empty()).
  const GridGeometry& geometry() const;
  /// Signed distance [m] at cell centres (+inf everywhere without obstacles, -inf without free
  /// cells).
  const GridLayer<float>& field() const;

  /// Bilinear interpolation of the cell-centre values; nullopt outside the grid. Within half a
  /// cell of the border the border values are held.
  std::optional<double> distance(const Vec2& p_W) const;
  /// Central differences of distance() with a step of one cell (one-sided at the border): the
  /// bilinear interpolation of the cells' central differences. Zero where the field is infinite.
  std::optional<Vec2> gradient(const Vec2& p_W) const;

 private:
  Esdf2dConfig config_;
  std::optional<GridLayer<float>> field_;
  ImageU8 obstacles_;
  ImageU8 free_;
  ImageF32 to_obstacle_;
  ImageF32 to_free_;
};

}  // namespace navaid::mapping
