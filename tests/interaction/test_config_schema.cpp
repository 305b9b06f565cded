// The interaction room's declared keys are the keys its read functions read, with the same
// defaults.
#include <gtest/gtest.h>

#include "config_schema_check.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/interaction/cue_generator.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/device_link.hpp"
#include "navaid/interaction/hand_unit_adapter.hpp"
#include "navaid/interaction/route_timeline.hpp"
#include "navaid/interaction/rumble_adapter.hpp"
#include "navaid/interaction/speech_synthesizer.hpp"
#include "navaid/interaction/steering_wheel_adapter.hpp"

namespace navaid::interaction {

TEST(InteractionConfigSchema, DeclaredKeysAreTheKeysRead) {
  navaid::testing::expect_schema_matches_reads(config_schema(), [](const Config& c) {
    read_cue_generator_config(c);
    read_cue_policy_config(c);
    read_belt_config(c);
    read_hand_unit_config(c);
    read_rumble_config(c);
    read_steering_wheel_config(c);
    read_speech_config(c);
    read_link_config(c);
    read_route_timeline_config(c);
  });
}

TEST(InteractionConfigSchema, DefaultsFromTheSchemaReadBackAsTheStructDefaults) {
  const Config spelt = Config::parse(Config().dump(config_schema()), "<declared defaults>");
  EXPECT_FALSE(read_belt_config(spelt).intensity.has_value());  // no default: each cue's own intensity
  EXPECT_EQ(read_speech_config(spelt).voice, read_speech_config(Config()).voice);
  EXPECT_EQ(read_cue_generator_config(spelt).modality, CueGeneratorConfig{}.modality);
  EXPECT_DOUBLE_EQ(read_cue_generator_config(spelt).turn_rad, read_cue_generator_config(Config()).turn_rad);
  EXPECT_EQ(read_link_config(spelt).baud, LinkConfig{}.baud);
  EXPECT_NO_THROW(spelt.reject_unknown_keys(config_schema()));
}

}  // namespace navaid::interaction
