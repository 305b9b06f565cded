#pragma once
// The configuration keys the planning room reads (navaid/core/config_schema.hpp): one schema per
// options struct, declared beside its read function, and their union.
#include <string_view>

#include "navaid/core/config_schema.hpp"

namespace navaid::planning {

ConfigSchema search_limits_schema();               ///< read_search_limits
ConfigSchema grid_cost_config_schema();            ///< read_grid_cost_config
ConfigSchema grid_astar_config_schema();           ///< read_grid_astar_config
ConfigSchema direction_astar_config_schema();      ///< read_direction_astar_config
ConfigSchema wpg_config_schema();                  ///< read_wpg_config
ConfigSchema occupancy_cost_config_schema();       ///< read_occupancy_cost_config
ConfigSchema path_follower_config_schema();        ///< read_path_follower_config
ConfigSchema path_guidance_config_schema();        ///< read_path_guidance_config
ConfigSchema pi_heading_config_schema();           ///< read_pi_heading_config
ConfigSchema smart_cane_guidance_config_schema();  ///< read_smart_cane_guidance_config
ConfigSchema byu_cost_config_schema();             ///< read_byu_cost_config
ConfigSchema hand_sector_config_schema();          ///< read_hand_sector_config
ConfigSchema hand_guidance_config_schema();        ///< read_hand_guidance_config
ConfigSchema apriltag_detector_config_schema();    ///< read_apriltag_detector_config
ConfigSchema foot_route_config_schema();           ///< foot_route_config
ConfigSchema narration_config_schema();            ///< narration_config
ConfigSchema sub_route_config_schema();            ///< sub_route_config

/// The keys make_local_planner(name, config) reads for the planner `name` (astar,
/// direction-astar, wpg); empty for an unknown name.
ConfigSchema local_planner_schema(std::string_view name);

/// Every key of the planning room.
ConfigSchema config_schema();

}  // namespace navaid::planning
