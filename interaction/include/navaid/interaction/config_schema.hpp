#pragma once
// The configuration keys the interaction room reads (navaid/core/config_schema.hpp): one schema
// per options struct, declared beside its read function, and their union.
#include "navaid/core/config_schema.hpp"
#include "navaid/interaction/actuator_pattern.hpp"

namespace navaid::interaction {

ConfigSchema belt_config_schema();            ///< read_belt_config
ConfigSchema cue_generator_config_schema();   ///< read_cue_generator_config
ConfigSchema cue_policy_config_schema();      ///< read_cue_policy_config
ConfigSchema link_config_schema();            ///< read_link_config
ConfigSchema hand_unit_config_schema();       ///< read_hand_unit_config
ConfigSchema speech_config_schema();          ///< read_speech_config
ConfigSchema route_timeline_config_schema();  ///< read_route_timeline_config
ConfigSchema rumble_config_schema();          ///< read_rumble_config
ConfigSchema steering_wheel_config_schema();  ///< read_steering_wheel_config

/// The keys make_device_adapter(kind, config) reads for `kind`.
ConfigSchema device_adapter_schema(DeviceKind kind);

/// Every key of the interaction room.
ConfigSchema config_schema();

}  // namespace navaid::interaction
