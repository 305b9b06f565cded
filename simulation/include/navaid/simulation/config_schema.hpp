#pragma once
// The configuration keys the simulation room reads (navaid/core/config_schema.hpp).
#include "navaid/core/config_schema.hpp"

namespace navaid::simulation {

ConfigSchema scenario_options_schema();    ///< read_scenario_options
ConfigSchema simulation_config_schema();   ///< read_scenario_name + read_simulation_config
ConfigSchema user_model_schema();          ///< read_user_model (user.*)
ConfigSchema hand_motion_config_schema();  ///< read_hand_motion_config (user.hand.*)
ConfigSchema reach_model_schema();         ///< read_reach_model (user.reach.*)

/// simulation.world_seed (also read by navaid simulate --from-recording's flight room).
const ConfigKey<long long>& world_seed_key();

/// Every key of the simulation room.
ConfigSchema config_schema();

}  // namespace navaid::simulation
