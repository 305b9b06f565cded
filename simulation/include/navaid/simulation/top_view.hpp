#pragma once
// Orthographic top-down map of a World: rays cast straight down on a pixel grid, coloured by the
// semantic class display colour of the first visible surface and shaded by its height (colour x
// (0.6 + 0.4 (z - z_lo) / (z_hi - z_lo)) over the visible heights; 1 when all are equal), with
// optional overlays (walked path, moving objects' paths, start/goal markers, scale bar).
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/image.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/semantic_classes.hpp"

namespace navaid::simulation {

struct Scenario;  // scenario.hpp

struct TopViewOptions {
  double metres_per_pixel = 0.1;            ///< > 0
  /// Mapped x-y rectangle (min, max); default: the world's bounds plus `margin_m`.
  std::optional<std::pair<Vec2, Vec2>> region;
  double margin_m = 1.0;
  /// Surfaces seen through (e.g. ceilings, so that rooms are visible).
  std::vector<SemanticClass> hidden_classes = {SemanticClass::kCeiling};
  std::vector<Vec2> path;                   ///< walked path (drawn in blue, start green, goal red)
  std::vector<std::vector<Vec2>> other_paths;  ///< e.g. moving people's paths (drawn dashed in magenta)
  bool markers = true;                      ///< start/goal discs when `path` has points
  bool scale_bar = true;                    ///< bottom-right, a round length with its label
  std::array<std::uint8_t, 3> background = {235, 235, 235};  ///< where no surface is hit
};

struct TopView {
  ImageU8 image;            ///< RGB, 3 channels
  Vec2 top_left = Vec2::Zero();  ///< W x-y of the image's top-left corner (x min, y max)
  double metres_per_pixel = 0.1;
  /// Pixel (column, row) containing the W point p (may be outside the image).
  Eigen::Vector2i pixel(const Vec2& p) const;
};

/// The map of a scenario as docs/scenarios.md shows it: its documented extent plus a 3 % margin,
/// `width_px` wide, the scenario path (or `walked` when given) and the moving objects' paths.
TopViewOptions scenario_map_options(const Scenario& scenario, double width_px, const std::vector<Vec2>* walked = nullptr);

/// Renders the top view. Throws navaid::Error for metres_per_pixel <= 0, an empty region or an
/// image larger than 8192 pixels on a side.
TopView render_top_view(const RayCaster& caster, const TopViewOptions& options = {});

}  // namespace navaid::simulation
