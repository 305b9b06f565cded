// eLabrador's belt (§IV.C): kind + side of the walking cue to the vibrator, continuous vs
// intermittent, the two intensity modes and the user's override, our stop / obstacle / arrival
// patterns, holds against the 1 Hz refresh, and the interaction.belt.* keys.
#include <gtest/gtest.h>

#include <cmath>

#include "device_adapter_testing.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

using testing::actuators_of;
using testing::command_for;
using testing::cue_of;
using testing::walking_cue;
using B = BeltAdapter;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// The single actuator a pattern switches on, checked continuous.
int only_continuous(const ActuatorPattern& p) {
  EXPECT_EQ(p.commands.size(), 1u);
  if (p.commands.empty()) return -1;
  const ActuatorCommand& c = p.commands.front();
  EXPECT_TRUE(c.on_ms == 0 || c.off_ms == 0) << "expected a continuous command";
  return c.actuator;
}

TEST(DeviceAdapterBelt, ActuatorsRunLeftToRightWithThePapersAngles) {
  const B belt;
  EXPECT_EQ(belt.kind(), DeviceKind::kBelt);
  ASSERT_EQ(belt.actuator_count(), 5);
  EXPECT_EQ(belt.actuator_name(0), "left");         // -90 deg in eLabrador
  EXPECT_EQ(belt.actuator_name(1), "front-left");   // -45
  EXPECT_EQ(belt.actuator_name(2), "front");        // 0
  EXPECT_EQ(belt.actuator_name(3), "front-right");  // 45
  EXPECT_EQ(belt.actuator_name(4), "right");        // 90
  EXPECT_THROW(belt.actuator_name(5), std::out_of_range);
  EXPECT_THROW(belt.actuator_name(-1), std::out_of_range);
}

TEST(DeviceAdapterBelt, TurnLeftIsTheMinus90VibratorContinuously) {
  const auto p = B().pattern(walking_cue(CueKind::kTurn, 40 * kDeg));  // positive = left (ours)
  ASSERT_TRUE(p);
  EXPECT_EQ(only_continuous(*p), B::kLeft);
}

TEST(DeviceAdapterBelt, TurnRightIsThePlus90VibratorContinuously) {
  const auto p = B().pattern(walking_cue(CueKind::kTurn, -100 * kDeg));
  ASSERT_TRUE(p);
  EXPECT_EQ(only_continuous(*p), B::kRight);
}

TEST(DeviceAdapterBelt, VeerLeftIsTheMinus45VibratorContinuously) {
  const auto p = B().pattern(walking_cue(CueKind::kVeer, 15 * kDeg));
  ASSERT_TRUE(p);
  EXPECT_EQ(only_continuous(*p), B::kFrontLeft);
}

TEST(DeviceAdapterBelt, VeerRightIsThePlus45VibratorContinuously) {
  const auto p = B().pattern(walking_cue(CueKind::kVeer, -15 * kDeg));
  ASSERT_TRUE(p);
  EXPECT_EQ(only_continuous(*p), B::kFrontRight);
}

TEST(DeviceAdapterBelt, OnlyTheKindAndSignMatterNotTheAngle) {
  // Thresholds are the generator's: a "turn" of 5 deg is still the side vibrator.
  const B belt;
  EXPECT_EQ(only_continuous(*belt.pattern(walking_cue(CueKind::kTurn, 5 * kDeg))), B::kLeft);
  EXPECT_EQ(only_continuous(*belt.pattern(walking_cue(CueKind::kVeer, -170 * kDeg))), B::kFrontRight);
}

TEST(DeviceAdapterBelt, OnCourseIsTheFrontVibratorIntermittently) {
  BeltConfig c;
  c.pulse_on_ms = 150;
  c.pulse_off_ms = 350;
  const auto p = B(c).pattern(walking_cue(CueKind::kOnCourse, 2 * kDeg));
  ASSERT_TRUE(p);
  ASSERT_EQ(p->commands.size(), 1u);
  EXPECT_EQ(p->commands[0].actuator, B::kFront);
  EXPECT_EQ(p->commands[0].on_ms, 150);
  EXPECT_EQ(p->commands[0].off_ms, 350);
  // On course needs no direction.
  EXPECT_TRUE(B().pattern(cue_of(CueKind::kOnCourse)));
}

TEST(DeviceAdapterBelt, TurnOrVeerWithoutASideHasNoPattern) {
  const B belt;
  EXPECT_FALSE(belt.pattern(cue_of(CueKind::kTurn)));
  EXPECT_FALSE(belt.pattern(walking_cue(CueKind::kVeer, 0.0)));
  EXPECT_FALSE(belt.pattern(walking_cue(CueKind::kTurn, std::nan(""))));
}

TEST(DeviceAdapterBelt, IntensityModesGiveTheTwoLevels) {
  BeltConfig c;
  c.level_low = 300;
  c.level_high = 900;
  const B belt(c);
  Cue low = walking_cue(CueKind::kTurn, 1.0);
  low.intensity = CueIntensity::kLow;
  Cue high = low;
  high.intensity = CueIntensity::kHigh;
  EXPECT_EQ(belt.pattern(low)->commands.at(0).level, 300);
  EXPECT_EQ(belt.pattern(high)->commands.at(0).level, 900);
}

TEST(DeviceAdapterBelt, TheUsersIntensityPreferenceOverridesTheCues) {
  const Config config = Config::parse("interaction:\n  belt:\n    intensity: low\n    level_low: 250\n");
  const auto belt = make_device_adapter(DeviceKind::kBelt, config);
  Cue high = walking_cue(CueKind::kVeer, -0.3);
  high.intensity = CueIntensity::kHigh;
  EXPECT_EQ(belt->pattern(high)->commands.at(0).level, 250);
  const Config prefers_high = Config::parse("interaction: {belt: {intensity: high}}");
  Cue low = high;
  low.intensity = CueIntensity::kLow;
  EXPECT_EQ(make_device_adapter(DeviceKind::kBelt, prefers_high)->pattern(low)->commands.at(0).level, 1000);
}

TEST(DeviceAdapterBelt, StopPulsesAllFiveFastAtTheHighLevel) {
  BeltConfig c;
  c.intensity = CueIntensity::kLow;  // the preference does not soften a stop
  const B belt(c);
  const auto p = belt.pattern(cue_of(CueKind::kStop));
  ASSERT_TRUE(p);
  EXPECT_EQ(actuators_of(*p), (std::set<int>{0, 1, 2, 3, 4}));
  for (const ActuatorCommand& cmd : p->commands) {
    EXPECT_EQ(cmd.level, c.level_high);
    EXPECT_EQ(cmd.on_ms, c.urgent_on_ms);
    EXPECT_EQ(cmd.off_ms, c.urgent_off_ms);
    EXPECT_LT(cmd.on_ms + cmd.off_ms, c.pulse_on_ms + c.pulse_off_ms);  // faster than on-course
  }
}

TEST(DeviceAdapterBelt, ObstaclePulsesTheOpenSidesFrontVibratorOrActsLikeStop) {
  const B belt;
  Cue cue = cue_of(CueKind::kObstacle);
  cue.rumble = planning::RumbleState::kLeft;
  auto p = belt.pattern(cue);
  ASSERT_TRUE(p);
  EXPECT_EQ(actuators_of(*p), std::set<int>{B::kFrontLeft});
  EXPECT_GT(p->commands[0].on_ms, 0);
  EXPECT_GT(p->commands[0].off_ms, 0);
  cue.rumble = planning::RumbleState::kRight;
  EXPECT_EQ(actuators_of(*belt.pattern(cue)), std::set<int>{B::kFrontRight});
  const auto stop = belt.pattern(cue_of(CueKind::kStop));
  for (const auto state : {std::optional<planning::RumbleState>{planning::RumbleState::kBoth},
                           std::optional<planning::RumbleState>{planning::RumbleState::kOff},
                           std::optional<planning::RumbleState>{}}) {
    cue.rumble = state;
    p = belt.pattern(cue);
    ASSERT_TRUE(p);
    EXPECT_EQ(actuators_of(*p), actuators_of(*stop));
  }
}

TEST(DeviceAdapterBelt, ArrivalPulsesTheFrontThreeTwice) {
  BeltConfig c;
  c.arrive_on_ms = 200;
  c.arrive_off_ms = 250;
  const auto p = B(c).pattern(cue_of(CueKind::kArrive));
  ASSERT_TRUE(p);
  EXPECT_EQ(actuators_of(*p), (std::set<int>{B::kFrontLeft, B::kFront, B::kFrontRight}));
  for (const ActuatorCommand& cmd : p->commands) {
    // on 200, off 250, on 200, then the hold ends it: exactly two pulses.
    EXPECT_EQ(cmd.on_ms, 200);
    EXPECT_EQ(cmd.off_ms, 250);
    EXPECT_EQ(cmd.hold_ms, 650);
  }
}

TEST(DeviceAdapterBelt, ObjectDirectionAndSystemCuesHaveNoBeltPattern) {
  const B belt;
  Cue hand = cue_of(CueKind::kObjectDirection);
  hand.hand = planning::HandDirection::kUp;
  EXPECT_FALSE(belt.pattern(hand));
  EXPECT_FALSE(belt.pattern(cue_of(CueKind::kSystem)));
}

TEST(DeviceAdapterBelt, RefreshedHoldsExceedThePeriodALittle) {
  BeltConfig c;
  c.refresh_hz = 1.0;
  c.hold_margin = 0.2;
  const B belt(c);
  EXPECT_DOUBLE_EQ(belt.refresh_period_s(), 1.0);
  const double period_ms = belt.refresh_period_s() * 1000.0;
  for (const CueKind kind : {CueKind::kTurn, CueKind::kVeer, CueKind::kOnCourse, CueKind::kStop, CueKind::kObstacle}) {
    const auto p = belt.pattern(walking_cue(kind, 0.5));
    ASSERT_TRUE(p) << to_string(kind);
    for (const ActuatorCommand& cmd : p->commands) {
      EXPECT_EQ(cmd.hold_ms, 1200) << to_string(kind);
      EXPECT_GT(cmd.hold_ms, period_ms);
      EXPECT_LE(cmd.hold_ms, 2.0 * period_ms);  // a lost link stops within about one period
    }
  }
}

TEST(DeviceAdapterBelt, PatternsAreStampedWithTheCuesTimeAndAllOffIsEmpty) {
  const B belt;
  const auto p = belt.pattern(walking_cue(CueKind::kTurn, 1.0));
  EXPECT_EQ(p->t, 1'000'000'000);
  EXPECT_EQ(p->device, DeviceKind::kBelt);
  const ActuatorPattern off = belt.all_off(42);
  EXPECT_EQ(off.t, 42);
  EXPECT_EQ(off.device, DeviceKind::kBelt);
  EXPECT_TRUE(off.commands.empty());
}

TEST(DeviceAdapterBelt, FactoryDefaultsAreThePapersRate) {
  const auto belt = make_device_adapter(DeviceKind::kBelt, Config());
  ASSERT_NE(dynamic_cast<const BeltAdapter*>(belt.get()), nullptr);
  EXPECT_EQ(belt->kind(), DeviceKind::kBelt);
  EXPECT_DOUBLE_EQ(belt->refresh_period_s(), 1.0);
  const auto cfg = dynamic_cast<const BeltAdapter&>(*belt).config();
  EXPECT_EQ(cfg.pulse_on_ms, 200);
  EXPECT_EQ(cfg.pulse_off_ms, 300);
  EXPECT_FALSE(cfg.intensity);
  const auto fast = make_device_adapter(DeviceKind::kBelt, Config::parse("interaction: {belt: {refresh_hz: 2}}"));
  EXPECT_DOUBLE_EQ(fast->refresh_period_s(), 0.5);
}

TEST(DeviceAdapterBelt, OutOfRangeKeysAreRejected) {
  for (const char* yaml : {
           "interaction: {belt: {refresh_hz: 0}}",
           "interaction: {belt: {refresh_hz: 50}}",
           "interaction: {belt: {hold_margin: 0}}",
           "interaction: {belt: {level_low: 0}}",
           "interaction: {belt: {level_high: 1001}}",
           "interaction: {belt: {level_low: 800, level_high: 500}}",
           "interaction: {belt: {level_low: 1000, level_high: 999}}",
           "interaction: {belt: {intensity: medium}}",
           "interaction: {belt: {pulse_on_ms: 5}}",
           "interaction: {belt: {pulse_off_ms: 6000}}",
           "interaction: {belt: {urgent_on_ms: -1}}",
           "interaction: {belt: {arrive_off_ms: fast}}",
       }) {
    const auto e = navaid::testing::expect_throw<ConfigError>(
        [&] { make_device_adapter(DeviceKind::kBelt, Config::parse(yaml, "belt.yaml")); }, yaml);
    if (e) {
      EXPECT_NE(std::string(e->what()).find("interaction.belt."), std::string::npos) << e->what();
    }
  }
  // A config built in code is checked too.
  BeltConfig c;
  c.level_low = 900;
  c.level_high = 100;
  EXPECT_THROW(B{c}, std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
