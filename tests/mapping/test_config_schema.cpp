// The mapping room's declared keys are the keys its read functions read, with the same defaults.
#include <gtest/gtest.h>

#include "config_schema_check.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/mapping/esdf_3d.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/obstacle_pipeline.hpp"
#include "navaid/mapping/segmentation_link.hpp"

namespace navaid::mapping {

TEST(MappingConfigSchema, DeclaredKeysAreTheKeysRead) {
  navaid::testing::expect_schema_matches_reads(config_schema(), [](const Config& c) {
    read_mapper_config(c);
    read_esdf_3d_config(c);
    read_obstacle_pipeline_config(c);
    read_segmentation_link_config(c);
  });
}

TEST(MappingConfigSchema, EachReadFunctionHasItsSchema) {
  navaid::testing::expect_schema_matches_reads(mapper_config_schema(), [](const Config& c) { read_mapper_config(c); });
  navaid::testing::expect_schema_matches_reads(obstacle_pipeline_config_schema(),
                                               [](const Config& c) { read_obstacle_pipeline_config(c); });
  navaid::testing::expect_schema_matches_reads(cost_map_config_schema(), [](const Config& c) { read_cost_map_config(c); });
}

TEST(MappingConfigSchema, DefaultsFromTheSchemaReadBackAsTheStructDefaults) {
  // A config that spells out every declared default reads as an empty one.
  const Config spelt = Config::parse(Config().dump(config_schema()), "<declared defaults>");
  const MapperConfig a = read_mapper_config(Config());
  const MapperConfig b = read_mapper_config(spelt);
  EXPECT_EQ(a.cloud.pixel_stride, b.cloud.pixel_stride);
  EXPECT_EQ(a.cloud.ignored_classes, b.cloud.ignored_classes);
  EXPECT_EQ(a.map.fusion, b.map.fusion);
  EXPECT_DOUBLE_EQ(a.gate.max_sigma_yaw_rad, b.gate.max_sigma_yaw_rad);
  EXPECT_EQ(a.gate.scope, b.gate.scope);
  EXPECT_EQ(a.esdf.backend, b.esdf.backend);
  EXPECT_DOUBLE_EQ(a.cost.unknown_cost, b.cost.unknown_cost);
  EXPECT_FALSE(read_segmentation_link_config(spelt).has_value());  // outages: no default, the link stays off
  const ObstaclePipelineConfig o = read_obstacle_pipeline_config(spelt);
  EXPECT_DOUBLE_EQ(o.ransac_eps_angle_rad, ObstaclePipelineConfig{}.ransac_eps_angle_rad);
  EXPECT_DOUBLE_EQ(o.scan_bin_width_rad, ObstaclePipelineConfig{}.scan_bin_width_rad);
  EXPECT_NO_THROW(spelt.reject_unknown_keys(config_schema()));
}

}  // namespace navaid::mapping
