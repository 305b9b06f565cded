#include "navaid/runtime/mapping_stage.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "navaid/io/image_io.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/runtime/config_schema.hpp"

namespace navaid::runtime {

namespace {

const ConfigKey<bool> kObstaclesEnabled{"mapping.obstacles.enabled", false,
                                        "run the BYU obstacle pipeline (mapping.obstacles.*) on every mapped frame"};
const ConfigKey<double> kObstaclePriorHeight{"mapping.obstacles.prior_camera_height_m",
                                             MappingStageOptions{}.obstacle_prior_camera_height_m, {0.05, 5.0},
                                             "the obstacle pipeline's prior camera height above the ground [m]"};

}  // namespace

ConfigSchema mapping_stage_options_schema() {
  return ConfigSchema()
      .add(kObstaclesEnabled)
      .add(kObstaclePriorHeight)
      .add(mapping::obstacle_pipeline_config_schema())
      .add(mapping::segmentation_link_config_schema());
}

void read_obstacle_options(const Config& config, MappingStageOptions& options) {
  if (!get(config, kObstaclesEnabled)) return;
  options.obstacles = mapping::read_obstacle_pipeline_config(config);
  options.obstacle_prior_camera_height_m = get(config, kObstaclePriorHeight);
}

MappingStageOptions read_mapping_stage_options(const Config& config) {
  MappingStageOptions options;
  read_obstacle_options(config, options);
  options.network = mapping::read_segmentation_link_config(config);
  return options;
}

interaction::GuidanceTimelineEntry network_event(const mapping::NetworkChange& c) {
  return interaction::SystemEvent{c.t,
                                  c.kind == mapping::NetworkChangeKind::kLost ? interaction::SystemEventKind::kNetworkLost
                                                                              : interaction::SystemEventKind::kNetworkRestored,
                                  {}};
}

MappingStage::MappingStage(const mapping::MapperConfig& config, const CameraCalibration& camera,
                           const MappingStageOptions& options)
    : config_(config), camera_(camera), options_(options), mapper_(config, camera) {
  if (options.obstacles) obstacles_.emplace(*options.obstacles);
  if (options.network) link_.emplace(*options.network, options.network_start);
}

MappedFrame MappingStage::add(const RgbdFrame& unloaded, const StateEstimate& estimate) {
  MappedFrame out;
  RgbdFrame frame = unloaded;
  frame.intensity_path.clear();  // the map needs depth, labels and confidence only
  if (link_) {
    // The server's labels do not reach the edge: this frame maps geometry only.
    if (!link_->labels_available(frame.t) && (!frame.labels_path.empty() || frame.labels)) {
      frame.labels_path.clear();
      frame.confidence_path.clear();
      frame.labels.reset();
      frame.label_confidence.reset();
      out.labels_dropped = true;
    }
    out.network_changes = link_->take_changes();
    for (const auto& c : out.network_changes)
      spdlog::info("segmentation server {} at {:.3f} s", mapping::network_change_name(c.kind),
                   static_cast<double>(c.t - options_.network_start) * 1e-9);
  }
  io::load_frame_images(frame);
  out.result = mapper_.process(frame, estimate);
  if (out.labels_dropped && out.result.outcome == mapping::FrameOutcome::kMapped) ++geometry_only_;
  if (obstacles_ && !frame.depth.empty()) out.scan = scan_obstacles(frame, estimate);
  return out;
}

mapping::ObstacleScan MappingStage::scan_obstacles(const RgbdFrame& frame, const StateEstimate& estimate) {
  // Prior T_U_C: the estimate's attitude without its yaw (U looks where the camera looks), the
  // camera prior_camera_height_m over the ground; the pipeline refines it from the ground plane.
  const Mat3 R_W_C = estimate.T_W_B.rotation() * camera_.T_B_C.rotation();
  const Vec3 forward = R_W_C.col(2);
  const Mat3 R_W_U = Eigen::AngleAxisd(std::atan2(forward.y(), forward.x()), Vec3::UnitZ()).toRotationMatrix();
  const SE3 T_U_C_prior(Mat3(R_W_U.transpose() * R_W_C), Vec3(0, 0, options_.obstacle_prior_camera_height_m));
  last_scan_ = obstacles_->process(mapping::camera_points_from_depth(frame, camera_, options_.obstacle_pixel_stride),
                                   T_U_C_prior, frame.t);
  return *last_scan_;
}

}  // namespace navaid::runtime
