#pragma once
// The planning stage of a full-device run: one GuidanceCommand per estimate from the estimate,
// the newest local maps and the newest obstacle scan. One interface, one class per device chain
// (device_preset.hpp's GuidanceKind), so the pipeline drives all four the same way.
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/experiments/device_preset.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/obstacle_scan.hpp"
#include "navaid/planning/guidance_command.hpp"
#include "navaid/planning/local_planner.hpp"

namespace navaid::experiments {

struct GuidanceInput {
  const RgbdFrame& frame;  ///< the estimate's frame, images not loaded
  const StateEstimate& estimate;
  const mapping::LocalMaps* maps = nullptr;            ///< null before the first mapped frame
  const mapping::ObstacleScan* obstacle_scan = nullptr;  ///< null without one
};

struct GuidanceOutput {
  planning::GuidanceCommand command;
  std::optional<planning::Plan> new_plan;  ///< a plan made in this cycle (plans.csv)
  std::string planner;                     ///< its planner's name
};

class GuidanceStage {
 public:
  virtual ~GuidanceStage() = default;
  /// One cycle. Throws navaid::Error on broken input (the pipeline names the frame).
  virtual GuidanceOutput update(const GuidanceInput& in) = 0;
  /// What the stage did, for summary.json.
  virtual nlohmann::ordered_json summary() const = 0;
};

/// What a stage is built from: the run's configuration (its keys are read here, before the
/// pipeline rejects unknown ones), the recording and its folder, the estimator's camera and the
/// run folder (the route stage writes route/ there).
struct GuidanceStageContext {
  const DeviceSpec& spec;
  const Config& config;
  const io::Recording& recording;
  const std::filesystem::path& recording_dir;
  const CameraCalibration& camera;
  const std::filesystem::path& out;
};

std::unique_ptr<GuidanceStage> make_guidance_stage(const GuidanceStageContext& context);

// The four chains (one file each).
std::unique_ptr<GuidanceStage> make_route_guidance_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_walking_path_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_obstacle_rumble_stage(const GuidanceStageContext& context);
std::unique_ptr<GuidanceStage> make_hand_target_stage(const GuidanceStageContext& context);

/// A command that gives no direction: wait, with the reason and why in words.
planning::GuidanceCommand waiting_command(Timestamp t, planning::GuidanceReason reason, std::string detail);

}  // namespace navaid::experiments
