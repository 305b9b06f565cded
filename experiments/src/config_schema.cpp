// Keys read in more than one place of the experiments room, and the room's union of keys.
#include "navaid/experiments/config_schema.hpp"

#include "navaid/estimation/config_schema.hpp"
#include "navaid/experiments/device_preset.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::experiments {

const ConfigKey<bool>& mapping_enabled_key() {
  static const ConfigKey<bool> key{"mapping.enabled", std::nullopt,
                                   "navaid run: map with the estimates (off by default); a device always maps "
                                   "(its presets say true)"};
  return key;
}

const ConfigKey<double>& frontend_rate_key() {
  static const ConfigKey<double> key{"frontend.rate_hz", 0.0, {0.0, 1000.0},
                                     "camera frames fed to the front end per second; 0: every frame (a trial: "
                                     "the simulated camera's rate, in [1, 200])"};
  return key;
}

const ConfigKey<std::vector<double>>& hand_camera_translation_key() {
  static const ConfigKey<std::vector<double>> key{"planning.hand.t_H_C_m", std::vector<double>{0.0, 0.0, 0.0}, 3,
                                                  {-2.0, 2.0}, "the camera's position in the hand unit's frame [m]"};
  return key;
}

ConfigSchema device_run_schema(const DeviceSpec& device) {
  ConfigSchema s = interaction::cue_generator_config_schema();
  s.add(interaction::cue_policy_config_schema());
  s.add(interaction::device_adapter_schema(device.actuator));
  s.add(interaction::speech_config_schema());
  s.add(mapping::mapper_config_schema());
  switch (device.guidance) {
    case GuidanceKind::kRoute: return s.add(route_guidance_stage_schema());
    case GuidanceKind::kWalkingPath: return s.add(walking_path_stage_schema());
    case GuidanceKind::kObstacleRumble: return s.add(obstacle_rumble_stage_schema());
    case GuidanceKind::kHandTarget: return s.add(hand_target_stage_schema());
  }
  return s;
}

ConfigSchema run_schema(const DeviceSpec* device) {
  ConfigSchema s = estimation::config_schema();
  s.add(recording_run_schema()).add(mapping::mapper_config_schema()).add(map_session_options_schema());
  if (device != nullptr) s.add(device_spec_schema()).add(device_run_schema(*device));
  return s;
}

ConfigSchema config_schema() {
  return ConfigSchema()
      .add(device_spec_schema())
      .add(recording_run_schema())
      .add(map_session_options_schema())
      .add(guidance_stages_schema())
      .add(trial_schema())
      .add(experimenter_config_schema())
      .add(reach_protocol_config_schema())
      .add(scenario_cost_map_schema());
}

}  // namespace navaid::experiments
