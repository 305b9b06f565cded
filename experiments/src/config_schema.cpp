// Keys read in more than one place of the experiments room, and the room's union of keys.
#include "navaid/experiments/config_schema.hpp"

#include "navaid/estimation/config_schema.hpp"
#include "navaid/runtime/device_spec.hpp"
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

ConfigSchema run_schema(const runtime::DeviceSpec* device) {
  ConfigSchema s = estimation::config_schema();
  s.add(recording_run_schema()).add(mapping::mapper_config_schema()).add(runtime::mapping_stage_options_schema());
  if (device != nullptr) s.add(runtime::device_spec_schema()).add(runtime::device_schema(*device));
  return s;
}

ConfigSchema config_schema() {
  return ConfigSchema()
      .add(runtime::config_schema())
      .add(recording_run_schema())
      .add(trial_schema())
      .add(experimenter_config_schema())
      .add(reach_protocol_config_schema())
      .add(scenario_cost_map_schema());
}

}  // namespace navaid::experiments
