// Device presets: the four shipped files and the device.* keys.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "test_support.hpp"

namespace {

using namespace navaid;
using namespace navaid::runtime;

TEST(DevicePreset, TheFourPresetsLoad) {
  EXPECT_EQ(device_preset_names(), (std::vector<std::string>{"augmented-cane", "elabrador", "smart-cane", "w-roma"}));
  const DeviceSpec e = read_device_spec(Config::load(device_preset_file("elabrador")));
  EXPECT_EQ(e.guidance, GuidanceKind::kRoute);
  EXPECT_EQ(e.actuator, interaction::DeviceKind::kBelt);
  EXPECT_TRUE(e.needs_gps);
  EXPECT_TRUE(e.needs_depth);
  const DeviceSpec w = read_device_spec(Config::load(device_preset_file("w-roma")));
  EXPECT_EQ(w.guidance, GuidanceKind::kHandTarget);
  EXPECT_EQ(w.map_every, 0u);
  EXPECT_EQ(read_device_spec(Config::load(device_preset_file("smart-cane"))).actuator, interaction::DeviceKind::kWheel);
  EXPECT_EQ(read_device_spec(Config::load(device_preset_file("augmented-cane"))).guidance,
            GuidanceKind::kObstacleRumble);
}

TEST(DevicePreset, AnUnknownPresetListsTheOthers) {
  const auto e = navaid::testing::expect_throw<UsageError>([] { device_preset_file("white-cane"); });
  ASSERT_TRUE(e);
  EXPECT_NE(std::string(e->what()).find("augmented-cane, elabrador, smart-cane, w-roma"), std::string::npos);
}

TEST(DevicePreset, BadKeysNameTheKey) {
  const auto parse = [](const std::string& yaml) { return read_device_spec(Config::parse(yaml, "test.yaml")); };
  const std::string base = "device: {name: x, guidance: route, actuator: belt";
  EXPECT_NE(navaid::testing::error_message<ConfigError>([&] { parse(base + ", needs: [lidar]}"); }).find("device.needs"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>([&] { parse("device: {name: x, guidance: teleport, actuator: belt}"); })
                .find("device.guidance"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<ConfigError>([&] { parse(base + ", route: {to: [52.5]}}"); }).find("device.route.to"),
            std::string::npos);
}

TEST(DevicePreset, EveryGuidanceKindRoundTripsThroughItsName) {
  // Every enumerator with its name; a dropped or misspelt table entry fails.
  const std::vector<std::pair<GuidanceKind, std::string>> kinds{
      {GuidanceKind::kRoute, "route"},
      {GuidanceKind::kWalkingPath, "walking-path"},
      {GuidanceKind::kObstacleRumble, "obstacle-rumble"},
      {GuidanceKind::kHandTarget, "hand-target"},
  };
  for (const auto& [kind, name] : kinds) {
    EXPECT_EQ(to_string(kind), name);
    const std::string yaml = "device: {name: x, guidance: " + std::string(to_string(kind)) + ", actuator: belt}";
    EXPECT_EQ(read_device_spec(Config::parse(yaml, "test.yaml")).guidance, kind) << name;
  }
  EXPECT_EQ(to_string(static_cast<GuidanceKind>(9)), "?");
}

}  // namespace
