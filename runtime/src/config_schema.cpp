// Keys read in more than one place of the runtime room, what a Device reads, and the room's union.
#include "navaid/runtime/config_schema.hpp"

#include "navaid/interaction/config_schema.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/runtime/device_spec.hpp"

namespace navaid::runtime {

const ConfigKey<std::vector<double>>& hand_camera_translation_key() {
  static const ConfigKey<std::vector<double>> key{"planning.hand.t_H_C_m", std::vector<double>{0.0, 0.0, 0.0}, 3,
                                                  {-2.0, 2.0}, "the camera's position in the hand unit's frame [m]"};
  return key;
}

ConfigSchema device_schema(const DeviceSpec& device) {
  ConfigSchema s = interaction::cue_generator_config_schema();
  s.add(interaction::cue_policy_config_schema());
  s.add(interaction::device_adapter_schema(device.actuator));
  s.add(interaction::speech_config_schema());
  s.add(mapping::mapper_config_schema());
  s.add(mapping_stage_options_schema());
  switch (device.guidance) {
    case GuidanceKind::kRoute: return s.add(route_guidance_stage_schema());
    case GuidanceKind::kWalkingPath: return s.add(walking_path_stage_schema());
    case GuidanceKind::kObstacleRumble: return s.add(obstacle_rumble_stage_schema());
    case GuidanceKind::kHandTarget: return s.add(hand_target_stage_schema());
  }
  return s;
}

ConfigSchema config_schema() {
  return ConfigSchema().add(device_spec_schema()).add(mapping_stage_options_schema()).add(guidance_stages_schema());
}

}  // namespace navaid::runtime
