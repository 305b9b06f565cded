#pragma once
// PNG views of the 2D layers, each with a legend strip under the map (colour bar with values, or
// swatches for classes). North (+y in W) is up, +x right; cells are drawn as squares of several
// pixels so that a 10 m window is readable; unknown cells are grey. Throws IoError when the file
// cannot be written.
#include <filesystem>

#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"

namespace navaid::mapping {

void write_height_map_png(const std::filesystem::path& path, const HeightMap& map);
void write_undulation_map_png(const std::filesystem::path& path, const UndulationMap& map);
void write_collision_map_png(const std::filesystem::path& path, const CollisionMap& map);
/// Obstacles (cost > threshold) are outlined in the legend by the threshold mark.
void write_cost_map_png(const std::filesystem::path& path, const CostMap& map);
/// Signed distance on a diverging colour map, symmetric around 0.
void write_esdf_png(const std::filesystem::path& path, const Esdf2d& esdf);

}  // namespace navaid::mapping
