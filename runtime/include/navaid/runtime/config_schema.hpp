#pragma once
// The configuration keys the runtime room reads (navaid/core/config_schema.hpp): device presets
// (device.*), the mapping stage's options, the four guidance stages, and what a Device reads.
#include "navaid/core/config_schema.hpp"

namespace navaid::runtime {

struct DeviceSpec;

ConfigSchema device_spec_schema();            ///< read_device_spec (device.*)
ConfigSchema mapping_stage_options_schema();  ///< read_mapping_stage_options
ConfigSchema route_guidance_stage_schema();   ///< the route guidance stage
ConfigSchema walking_path_stage_schema();     ///< the walking-path (Smart Cane) stage
ConfigSchema obstacle_rumble_stage_schema();  ///< the obstacle-rumble (BYU) stage
ConfigSchema hand_target_stage_schema();      ///< the hand-target (W-ROMA) stage
ConfigSchema guidance_stages_schema();        ///< the four guidance stages' keys

/// Keys read in more than one place, declared once.
const ConfigKey<std::vector<double>>& hand_camera_translation_key();  ///< planning.hand.t_H_C_m
const ConfigKey<std::string>& device_guidance_key();                  ///< device.guidance
const ConfigKey<std::string>& device_actuator_key();                  ///< device.actuator

/// The keys a Device of `device` reads: cues, the actuator's adapter, speech, mapping, the
/// mapping stage's options, its guidance stage.
ConfigSchema device_schema(const DeviceSpec& device);

/// Every key of the runtime room.
ConfigSchema config_schema();

}  // namespace navaid::runtime
