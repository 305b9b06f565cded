#pragma once
// Undulation map M_h (eLabrador Appendix A-B): a Sobel filter on the height map measures how much a
// cell stands above or below its neighbours (steps, curbs, kerbs, walls), and cells past a
// threshold are 1, the rest 0.
#include <cstdint>

#include "navaid/core/config.hpp"
#include "navaid/mapping/height_map.hpp"

namespace navaid::mapping {

struct UndulationConfig {
  /// A cell is undulating (1) when its edge degree exceeds this [m]. The edge degree is the Sobel
  /// gradient magnitude divided by 4, so that a step of height d between two cells reads d on both
  /// sides of it. 0.12 m lies above one voxel layer (0.08-0.1 m: a gentle slope quantised into
  /// one-voxel terraces must not fire) and below a kerb (0.15 m).
  double step_threshold_m = 0.12;
};

/// Key mapping.undulation.step_threshold_m in [0.01, 2].
UndulationConfig read_undulation_config(const Config& config);

/// Cell value: 1 undulating, 0 flat or unknown (no height evidence of a step).
class UndulationMap : public GridLayer<std::uint8_t> {
 public:
  explicit UndulationMap(const GridGeometry& geometry);
};

/// Sobel edge degree [m] of cell c (see UndulationConfig). An unknown neighbour (NaN height, or
/// beyond the grid) takes the centre cell's height: an unseen cell is no evidence of a step.
/// Unknown cells have degree 0.
double sobel_edge_degree(const HeightMap& heights, const Cell2& c);

UndulationMap build_undulation_map(const HeightMap& heights, const UndulationConfig& config);

}  // namespace navaid::mapping
