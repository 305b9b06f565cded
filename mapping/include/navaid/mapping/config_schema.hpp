#pragma once
// The configuration keys the mapping room reads (navaid/core/config_schema.hpp): one schema per
// options struct, declared beside its read_*_config function, and their union.
#include "navaid/core/config_schema.hpp"

namespace navaid::mapping {

ConfigSchema semantic_point_cloud_config_schema();  ///< read_semantic_point_cloud_config
ConfigSchema semantic_map_config_schema();          ///< read_semantic_map_config
ConfigSchema mapping_gate_config_schema();          ///< read_mapping_gate_config
ConfigSchema grid_config_schema();                  ///< read_grid_config
ConfigSchema height_map_config_schema();            ///< read_height_map_config
ConfigSchema undulation_config_schema();            ///< read_undulation_config
ConfigSchema collision_config_schema();             ///< read_collision_config
ConfigSchema cost_map_config_schema();              ///< read_cost_map_config
ConfigSchema esdf_2d_config_schema();               ///< read_esdf_2d_config
ConfigSchema esdf_3d_config_schema();               ///< read_esdf_3d_config
ConfigSchema mapper_config_schema();                ///< read_mapper_config (the above it reads, and mapping.layers)
ConfigSchema obstacle_pipeline_config_schema();     ///< read_obstacle_pipeline_config
ConfigSchema segmentation_link_config_schema();     ///< read_segmentation_link_config

/// Every key of the mapping room.
ConfigSchema config_schema();

}  // namespace navaid::mapping
