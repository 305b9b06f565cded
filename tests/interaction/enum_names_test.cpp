// interaction's enums that are read back from text: to_string and *_from_string from one table
// each (cues in the cue timeline, device kinds in presets and on the command line). SystemEventKind
// and CueModality are checked with their readers (guidance_timeline_csv_test, cue_generator_test).
#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <vector>

#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/cue.hpp"

namespace navaid::interaction {
namespace {

// Every enumerator with its name; a dropped or misspelt table entry fails.

TEST(InteractionEnumNames, EveryCueKindRoundTrips) {
  const std::vector<std::pair<CueKind, std::string_view>> kinds{
      {CueKind::kStop, "stop"},
      {CueKind::kObstacle, "obstacle"},
      {CueKind::kArrive, "arrive"},
      {CueKind::kTurn, "turn"},
      {CueKind::kVeer, "veer"},
      {CueKind::kOnCourse, "on-course"},
      {CueKind::kObjectDirection, "object-direction"},
      {CueKind::kSystem, "system"},
  };
  for (const auto& [kind, name] : kinds) {
    EXPECT_EQ(to_string(kind), name);
    EXPECT_EQ(cue_kind_from_string(to_string(kind)), kind) << name;
  }
  EXPECT_EQ(cue_kind_from_string("on_course"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<CueKind>(99)), "unknown");
}

TEST(InteractionEnumNames, EveryCueIntensityRoundTrips) {
  const std::vector<std::pair<CueIntensity, std::string_view>> intensities{
      {CueIntensity::kLow, "low"},
      {CueIntensity::kHigh, "high"},
  };
  for (const auto& [intensity, name] : intensities) {
    EXPECT_EQ(to_string(intensity), name);
    EXPECT_EQ(cue_intensity_from_string(to_string(intensity)), intensity) << name;
  }
  EXPECT_EQ(cue_intensity_from_string("medium"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<CueIntensity>(99)), "unknown");
}

TEST(InteractionEnumNames, EveryDeviceKindRoundTrips) {
  const std::vector<std::pair<DeviceKind, std::string_view>> kinds{
      {DeviceKind::kBelt, "belt"},
      {DeviceKind::kHand, "hand"},
      {DeviceKind::kRumble, "rumble"},
      {DeviceKind::kWheel, "wheel"},
  };
  for (const auto& [kind, name] : kinds) {
    EXPECT_EQ(to_string(kind), name);
    EXPECT_EQ(device_kind_from_string(to_string(kind)), kind) << name;
  }
  EXPECT_EQ(device_kind_from_string("Belt"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<DeviceKind>(0)), "unknown");
}

}  // namespace
}  // namespace navaid::interaction
