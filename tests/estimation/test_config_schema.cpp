// The estimation room's declared keys are the keys its read functions read, with the same
// defaults.
#include <gtest/gtest.h>

#include "config_schema_check.hpp"
#include "navaid/estimation/config_schema.hpp"
#include "navaid/estimation/estimator_config.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"

namespace navaid::estimation {

TEST(EstimationConfigSchema, DeclaredKeysAreTheKeysRead) {
  navaid::testing::expect_schema_matches_reads(config_schema(), [](const Config& c) {
    read_estimator_config(c);
    read_frontend_config(c);
  });
}

TEST(EstimationConfigSchema, DefaultsFromTheSchemaReadBackAsTheStructDefaults) {
  const Config spelt = Config::parse(Config().dump(config_schema()), "<declared defaults>");
  const EstimatorConfig a = read_estimator_config(Config());
  const EstimatorConfig b = read_estimator_config(spelt);
  EXPECT_EQ(a.window_size, b.window_size);
  EXPECT_EQ(a.gps_mode, b.gps_mode);
  EXPECT_EQ(a.anchor_bearing, b.anchor_bearing);
  EXPECT_EQ(a.non_keyframe_solve, b.non_keyframe_solve);
  EXPECT_EQ(a.mag_reference_field_enu, b.mag_reference_field_enu);
  EXPECT_EQ(a.mag_soft_iron, b.mag_soft_iron);
  EXPECT_DOUBLE_EQ(a.failure.max_rotation_jump_rad, b.failure.max_rotation_jump_rad);
  EXPECT_EQ(read_frontend_config(spelt).klt_threads, FrontendConfig{}.klt_threads);
  EXPECT_NO_THROW(spelt.reject_unknown_keys(config_schema()));
}

}  // namespace navaid::estimation
