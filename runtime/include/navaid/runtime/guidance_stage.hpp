#pragma once
// The planning stage of a device: one GuidanceCommand per estimate from the estimate, the newest
// local maps and the newest obstacle scan. One interface, one class per device chain
// (device_spec.hpp's GuidanceKind), so the device drives all four the same way. A stage is built
// from the configuration, the camera and the device's mission (device_mission.hpp); it reads no
// files but the frames' images and never sees ground truth.
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/obstacle_scan.hpp"
#include "navaid/planning/guidance_command.hpp"
#include "navaid/planning/local_planner.hpp"
#include "navaid/runtime/device_mission.hpp"
#include "navaid/runtime/device_spec.hpp"

namespace navaid::runtime {

struct GuidanceInput {
  const RgbdFrame& frame;  ///< the estimate's frame (images in memory, or paths loaded on demand)
  const StateEstimate& estimate;
  const mapping::LocalMaps* maps = nullptr;            ///< null before the first mapped frame
  const mapping::ObstacleScan* obstacle_scan = nullptr;  ///< null without one
};

struct GuidanceOutput {
  planning::GuidanceCommand command;
  std::optional<planning::Plan> new_plan;  ///< a plan made in this cycle
  std::string planner;                     ///< its planner's name
};

class GuidanceStage {
 public:
  virtual ~GuidanceStage() = default;
  /// One cycle. Throws navaid::Error on broken input (the device names the frame).
  virtual GuidanceOutput update(const GuidanceInput& in) = 0;
  /// What the stage did, for summaries.
  virtual nlohmann::ordered_json summary() const = 0;
};

/// What a stage is built from: the configuration (its keys are read here), the estimator's camera
/// and the device's mission. Throws Error when the mission lacks what the chain needs.
struct GuidanceStageContext {
  const DeviceSpec& spec;
  const Config& config;
  const CameraCalibration& camera;
  const DeviceMission& mission;
};

std::unique_ptr<GuidanceStage> make_guidance_stage(const GuidanceStageContext& context);

// The four chains (one file each).
std::unique_ptr<GuidanceStage> make_route_guidance_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_walking_path_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_obstacle_rumble_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_hand_target_stage(const GuidanceStageContext& context);

/// A command that gives no direction: wait, with the reason and why in words.
planning::GuidanceCommand waiting_command(Timestamp t, planning::GuidanceReason reason, std::string detail);

}  // namespace navaid::runtime
