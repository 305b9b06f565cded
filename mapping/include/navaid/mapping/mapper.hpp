#pragma once
// The mapping layer's entry point: RGB-D frame + the estimator's StateEstimate in, the semantic
// voxel map updated (or the frame skipped, counted, when it has no depth, the estimator is not
// localised, or it is too unsure of the pose). Reads only core types (DESIGN.md §3).
#include <cstddef>
#include <optional>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/collision_map.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/mapping/grid_geometry.hpp"
#include "navaid/mapping/height_map.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "navaid/mapping/semantic_map.hpp"
#include "navaid/mapping/semantic_point_cloud.hpp"
#include "navaid/mapping/undulation_map.hpp"

namespace navaid::mapping {

struct MapperConfig {
  SemanticPointCloudConfig cloud;
  SemanticMapConfig map;
  MappingGateConfig gate;
  /// Build the 2D layers and the 2D ESDF after every mapped frame (what the planners read).
  bool layers = true;
  GridConfig grid;
  HeightMapConfig height;
  UndulationConfig undulation;
  CollisionConfig collision;
  CostMapConfig cost;
  Esdf2dConfig esdf;
};

/// The 2D maps of the window around the user after the last mapped frame (eLabrador eq. 8-10).
struct LocalMaps {
  HeightMap height;
  UndulationMap undulation;
  CollisionMap collision;
  CostMap cost;  ///< inflated by k sigma_xy of the frame's estimate
  Esdf2d esdf;   ///< over the cost map's obstacles
};

/// All mapping.* keys of the layers: cloud, map, gate, grid, height, undulation, collision, cost,
/// esdf, and mapping.layers (true).
MapperConfig read_mapper_config(const Config& config);

enum class FrameOutcome { kMapped, kNoDepth, kNotLocalised, kTooUncertain };

struct MapperFrameResult {
  FrameOutcome outcome = FrameOutcome::kMapped;
  PoseUncertainty uncertainty;  ///< the estimate's own (absolute)
  /// What the gate and the inflation acted on (MappingGateConfig::scope): the absolute one, or its
  /// gain over the window.
  PoseUncertainty gated;
  std::size_t points = 0;  ///< points of the frame's cloud (0 when skipped)
  InsertStats insert;
  double cloud_ms = 0.0;   ///< back-projection
  double insert_ms = 0.0;  ///< ray casting + fusion (+ maintenance on its frames)
  double layers_ms = 0.0;  ///< height, undulation, collision and cost maps
  double esdf_ms = 0.0;    ///< the 2D ESDF
};

struct MapperCounters {
  std::size_t frames = 0;
  std::size_t mapped = 0;
  std::size_t no_depth = 0;
  std::size_t not_localised = 0;  ///< estimator initializing or lost: never mapped
  std::size_t too_uncertain = 0;  ///< sigma_xy or sigma_yaw over the gate
  std::size_t points = 0;
};

class Mapper {
 public:
  Mapper(const MapperConfig& config, const CameraCalibration& camera);

  /// Maps one frame (its images loaded; a frame without depth is skipped) at the estimate's pose.
  /// The window follows the estimate. Throws navaid::Error on a bad covariance or a malformed frame.
  MapperFrameResult process(const RgbdFrame& frame, const StateEstimate& estimate);

  const SemanticMap& map() const { return map_; }
  SemanticMap& map() { return map_; }
  const MapperCounters& counters() const { return counters_; }
  const MapperConfig& config() const { return config_; }
  /// Uncertainty the last estimate was gated on (and the 2D maps inflated by).
  const PoseUncertainty& last_uncertainty() const { return last_uncertainty_; }
  /// The 2D maps after the last mapped frame; null before the first or with layers off.
  const LocalMaps* local_maps() const { return local_maps_ ? &*local_maps_ : nullptr; }

 private:
  MapperConfig config_;
  CameraCalibration camera_;
  SemanticMap map_;
  MapperCounters counters_;
  PoseUncertainty last_uncertainty_;
  UncertaintyWindow uncertainty_window_;
  std::optional<LocalMaps> local_maps_;
};

}  // namespace navaid::mapping
