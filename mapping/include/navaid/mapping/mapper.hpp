#pragma once
// The mapping layer's entry point: RGB-D frame + the estimator's StateEstimate in, the semantic
// voxel map updated (or the frame skipped, counted, when it has no depth, the estimator is not
// localised, or it is too unsure of the pose). Reads only core types (DESIGN.md §3).
#include <cstddef>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "navaid/mapping/semantic_map.hpp"
#include "navaid/mapping/semantic_point_cloud.hpp"

namespace navaid::mapping {

struct MapperConfig {
  SemanticPointCloudConfig cloud;
  SemanticMapConfig map;
  MappingGateConfig gate;
};

/// All mapping.cloud.*, mapping.map.* and mapping.gate.* keys.
MapperConfig read_mapper_config(const Config& config);

enum class FrameOutcome { kMapped, kNoDepth, kNotLocalised, kTooUncertain };

struct MapperFrameResult {
  FrameOutcome outcome = FrameOutcome::kMapped;
  PoseUncertainty uncertainty;
  std::size_t points = 0;  ///< points of the frame's cloud (0 when skipped)
  InsertStats insert;
  double cloud_ms = 0.0;   ///< back-projection
  double insert_ms = 0.0;  ///< ray casting + fusion (+ maintenance on its frames)
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
  /// Uncertainty of the last estimate processed (for the 2D maps' inflation).
  const PoseUncertainty& last_uncertainty() const { return last_uncertainty_; }

 private:
  MapperConfig config_;
  CameraCalibration camera_;
  SemanticMap map_;
  MapperCounters counters_;
  PoseUncertainty last_uncertainty_;
};

}  // namespace navaid::mapping
