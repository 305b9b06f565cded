#pragma once
// The configuration keys the experiments room reads (navaid/core/config_schema.hpp):
// the recording run, closed-loop trials, the experimenter, reach protocol, planner maps (the
// device's keys are runtime's: navaid/runtime/config_schema.hpp).
#include "navaid/core/config_schema.hpp"
#include "navaid/runtime/config_schema.hpp"

namespace navaid::experiments {

ConfigSchema recording_run_schema();        ///< run_recording's own keys (frontend.rate_hz, mapping.enabled, ...)
ConfigSchema experimenter_config_schema();  ///< read_experimenter_config (trial.correction.*)
ConfigSchema reach_protocol_config_schema();  ///< read_reach_protocol_config (trial.reach.*)
ConfigSchema trial_schema();                ///< run_trial's own keys (trial.*)
ConfigSchema scenario_cost_map_schema();    ///< scenario_cost_map (planning.map.*)

/// Keys read in more than one place, declared once.
const ConfigKey<bool>& mapping_enabled_key();                     ///< mapping.enabled
const ConfigKey<double>& frontend_rate_key();                     ///< frontend.rate_hz

/// The keys navaid run reads: the estimator, the front end, mapping, and with a device its
/// preset's and its Device's.
ConfigSchema run_schema(const runtime::DeviceSpec* device);

/// Every key of the experiments room.
ConfigSchema config_schema();

}  // namespace navaid::experiments
