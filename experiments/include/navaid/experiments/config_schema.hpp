#pragma once
// The configuration keys the experiments room reads (navaid/core/config_schema.hpp): device
// presets, the recording run, map sessions, the device's guidance stages, closed-loop trials.
#include "navaid/core/config_schema.hpp"

namespace navaid::experiments {

ConfigSchema device_spec_schema();          ///< read_device_spec (device.*)
ConfigSchema map_session_options_schema();  ///< read_map_session_options
ConfigSchema route_guidance_stage_schema();   ///< the route guidance stage
ConfigSchema walking_path_stage_schema();     ///< the walking-path (Smart Cane) stage
ConfigSchema obstacle_rumble_stage_schema();  ///< the obstacle-rumble (BYU) stage
ConfigSchema hand_target_stage_schema();      ///< the hand-target (W-ROMA) stage
ConfigSchema guidance_stages_schema();        ///< the four guidance stages' keys
ConfigSchema recording_run_schema();        ///< run_recording's own keys (frontend.rate_hz, mapping.enabled, ...)
ConfigSchema experimenter_config_schema();  ///< read_experimenter_config (trial.correction.*)
ConfigSchema reach_protocol_config_schema();  ///< read_reach_protocol_config (trial.reach.*)
ConfigSchema trial_schema();                ///< run_trial's own keys (trial.*)
ConfigSchema scenario_cost_map_schema();    ///< scenario_cost_map (planning.map.*)

/// Keys read in more than one place, declared once.
const ConfigKey<bool>& mapping_enabled_key();                     ///< mapping.enabled
const ConfigKey<double>& frontend_rate_key();                     ///< frontend.rate_hz
const ConfigKey<std::vector<double>>& hand_camera_translation_key();  ///< planning.hand.t_H_C_m
const ConfigKey<std::string>& device_guidance_key();              ///< device.guidance
const ConfigKey<std::string>& device_actuator_key();              ///< device.actuator

struct DeviceSpec;

/// The keys a DeviceRun of `device` reads: cues, the actuator's adapter, speech, mapping, its
/// guidance stage.
ConfigSchema device_run_schema(const DeviceSpec& device);
/// The keys navaid run reads: the estimator, the front end, mapping, and with a device its
/// preset's and its DeviceRun's.
ConfigSchema run_schema(const DeviceSpec* device);

/// Every key of the experiments room.
ConfigSchema config_schema();

}  // namespace navaid::experiments
