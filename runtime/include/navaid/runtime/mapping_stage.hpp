#pragma once
// The mapping stage of a device: each frame with its estimate into the semantic voxel map and its
// 2D layers (mapping::Mapper), the BYU obstacle scan of the frame (mapping.obstacles.*) and the
// simulated link to the segmentation server (mapping.network.*: frames whose labels do not come
// back are mapped with geometry only). It hands back what each frame did; what is kept of it
// (timing, map files, quality) is the caller's (experiments' MapSession).
#include <optional>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/obstacle_pipeline.hpp"
#include "navaid/mapping/segmentation_link.hpp"

namespace navaid::runtime {

struct MappingStageOptions {
  /// mapping.obstacles.enabled: also run the BYU obstacle pipeline on every frame with depth (its
  /// config: the other mapping.obstacles.* keys).
  std::optional<mapping::ObstaclePipelineConfig> obstacles = std::nullopt;
  double obstacle_prior_camera_height_m = 0.8;  ///< the prior T_U_C's height (cane mount)
  int obstacle_pixel_stride = 1;                ///< the thesis uses every pixel (its voxel grid thins them)
  /// mapping.network.*: the simulated cloud segmentation server (eLabrador's edge-cloud split).
  std::optional<mapping::SegmentationLinkConfig> network = std::nullopt;
  Timestamp network_start = 0;  ///< the recording start the outages are relative to
};

/// The obstacle options of a configuration: mapping.obstacles.enabled (false) and
/// mapping.obstacles.prior_camera_height_m (0.8 m) besides the pipeline's own keys.
void read_obstacle_options(const Config& config, MappingStageOptions& options);
/// The obstacle options and mapping.network.* of `config`.
MappingStageOptions read_mapping_stage_options(const Config& config);

/// What mapping one frame did.
struct MappedFrame {
  mapping::MapperFrameResult result;
  bool labels_dropped = false;                 ///< the server's labels did not come back
  std::optional<mapping::ObstacleScan> scan;   ///< this frame's (obstacles enabled, depth present)
  std::vector<mapping::NetworkChange> network_changes;  ///< detected since the previous frame
};

/// A change of the segmentation link as the cue layer hears it (a system event).
interaction::GuidanceTimelineEntry network_event(const mapping::NetworkChange& change);

class MappingStage {
 public:
  MappingStage(const mapping::MapperConfig& config, const CameraCalibration& camera, const MappingStageOptions& options);

  /// Maps one frame of the stage's camera; images not in memory are loaded for it and freed.
  MappedFrame add(const RgbdFrame& frame, const StateEstimate& estimate);

  const mapping::Mapper& mapper() const { return mapper_; }
  const mapping::MapperConfig& config() const { return config_; }
  const MappingStageOptions& options() const { return options_; }
  /// The obstacle scan of the last frame that had one.
  const std::optional<mapping::ObstacleScan>& last_obstacle_scan() const { return last_scan_; }
  /// The segmentation link (null without mapping.network.*).
  const mapping::SegmentationLink* link() const { return link_ ? &*link_ : nullptr; }
  /// Frames mapped without labels because the link was down.
  std::size_t frames_geometry_only() const { return geometry_only_; }

 private:
  mapping::ObstacleScan scan_obstacles(const RgbdFrame& frame, const StateEstimate& estimate);

  mapping::MapperConfig config_;
  CameraCalibration camera_;
  MappingStageOptions options_;
  mapping::Mapper mapper_;
  std::optional<mapping::ObstaclePipeline> obstacles_;
  std::optional<mapping::SegmentationLink> link_;
  std::optional<mapping::ObstacleScan> last_scan_;
  std::size_t geometry_only_ = 0;
};

}  // namespace navaid::runtime
