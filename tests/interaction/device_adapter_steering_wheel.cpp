// The Smart Cane's steering wheel: the PI output in milliradians (positive left), the clamp, the
// fallback to the walking direction, stop holding straight, what has no wheel pattern, the hold
// against the 10 Hz refresh, and the interaction.wheel.* keys.
#include <gtest/gtest.h>

#include <cmath>

#include "device_adapter_testing.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/steering_wheel_adapter.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

using testing::cue_of;
using testing::walking_cue;
using W = SteeringWheelAdapter;

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

Cue steering_cue(CueKind kind, double steering_rad, double direction_rad = 0.1) {
  Cue c = walking_cue(kind, direction_rad);
  c.steering_rad = steering_rad;
  return c;
}

int level_of(const std::optional<ActuatorPattern>& p) {
  EXPECT_TRUE(p);
  if (!p) return -99999;
  EXPECT_EQ(p->commands.size(), 1u);
  return p->commands.empty() ? -99999 : p->commands[0].level;
}

TEST(DeviceAdapterSteeringWheel, OneSteeringActuator) {
  const W wheel;
  EXPECT_EQ(wheel.kind(), DeviceKind::kWheel);
  ASSERT_EQ(wheel.actuator_count(), 1);
  EXPECT_EQ(wheel.actuator_name(0), "steering");
  EXPECT_THROW(wheel.actuator_name(1), std::out_of_range);
}

TEST(DeviceAdapterSteeringWheel, SteeringIsTheLevelInMilliradiansPositiveLeft) {
  const W wheel;
  for (const CueKind kind : {CueKind::kTurn, CueKind::kVeer, CueKind::kOnCourse}) {
    EXPECT_EQ(level_of(wheel.pattern(steering_cue(kind, 0.3))), 300) << to_string(kind);
    EXPECT_EQ(level_of(wheel.pattern(steering_cue(kind, -0.0123))), -12) << to_string(kind);
  }
  // The PI output wins over the walking direction (here of the other sign).
  EXPECT_EQ(level_of(wheel.pattern(steering_cue(CueKind::kVeer, 0.2, -0.4))), 200);
  const auto p = wheel.pattern(steering_cue(CueKind::kTurn, 0.3));
  EXPECT_EQ(p->commands[0].actuator, W::kSteering);
  EXPECT_EQ(p->commands[0].on_ms, 0);  // continuous
}

TEST(DeviceAdapterSteeringWheel, SteeringIsClampedToTheMaximumAngle) {
  const W wheel;  // 45 deg = 785.4 mrad
  EXPECT_EQ(level_of(wheel.pattern(steering_cue(CueKind::kTurn, 2.0))), 785);
  EXPECT_EQ(level_of(wheel.pattern(steering_cue(CueKind::kTurn, -3.0))), -785);
  SteeringWheelConfig c;
  c.max_steering_deg = 20.0;
  EXPECT_EQ(level_of(W(c).pattern(steering_cue(CueKind::kTurn, 0.5))), static_cast<int>(std::lround(20 * kRadPerDeg * 1000)));
  EXPECT_EQ(level_of(W(c).pattern(steering_cue(CueKind::kTurn, 0.2))), 200);  // inside: unchanged
}

TEST(DeviceAdapterSteeringWheel, WithoutSteeringTheDirectionIsUsedClamped) {
  const W wheel;
  EXPECT_EQ(level_of(wheel.pattern(walking_cue(CueKind::kVeer, 0.25))), 250);
  EXPECT_EQ(level_of(wheel.pattern(walking_cue(CueKind::kTurn, -120 * kRadPerDeg))), -785);
  // Neither, or not finite: nothing to steer by.
  EXPECT_FALSE(wheel.pattern(cue_of(CueKind::kTurn)));
  EXPECT_FALSE(wheel.pattern(steering_cue(CueKind::kTurn, std::nan(""))));
  EXPECT_FALSE(wheel.pattern(walking_cue(CueKind::kOnCourse, HUGE_VAL)));
}

TEST(DeviceAdapterSteeringWheel, StopHoldsTheWheelStraight) {
  const W wheel;
  const auto p = wheel.pattern(cue_of(CueKind::kStop));
  ASSERT_TRUE(p);
  ASSERT_EQ(p->commands.size(), 1u);  // a level-0 command, not "all off" (which releases the motor)
  EXPECT_EQ(p->commands[0].level, 0);
  EXPECT_GT(p->commands[0].hold_ms, 100);
}

TEST(DeviceAdapterSteeringWheel, ArrivalReleasesTheMotorOthersHaveNoPattern) {
  const W wheel;
  const auto arrive = wheel.pattern(cue_of(CueKind::kArrive));
  ASSERT_TRUE(arrive);
  EXPECT_TRUE(arrive->commands.empty());
  for (const CueKind kind : {CueKind::kObstacle, CueKind::kObjectDirection, CueKind::kSystem}) {
    EXPECT_FALSE(wheel.pattern(steering_cue(kind, 0.3))) << to_string(kind);
  }
}

TEST(DeviceAdapterSteeringWheel, HoldsExceedTheTenHertzPeriodALittle) {
  const W wheel;
  EXPECT_DOUBLE_EQ(wheel.refresh_period_s(), 0.1);
  EXPECT_EQ(wheel.pattern(steering_cue(CueKind::kTurn, 0.1))->commands[0].hold_ms, 125);
  SteeringWheelConfig c;
  c.hold_margin = 0.1;
  EXPECT_EQ(W(c).pattern(steering_cue(CueKind::kTurn, 0.1))->commands[0].hold_ms, 110);
}

TEST(DeviceAdapterSteeringWheel, FactoryReadsTheKeys) {
  const auto wheel = make_device_adapter(
      DeviceKind::kWheel, Config::parse("interaction: {wheel: {refresh_hz: 20, max_steering_deg: 30}}"));
  ASSERT_NE(dynamic_cast<const SteeringWheelAdapter*>(wheel.get()), nullptr);
  EXPECT_EQ(wheel->kind(), DeviceKind::kWheel);
  EXPECT_DOUBLE_EQ(wheel->refresh_period_s(), 0.05);
  EXPECT_EQ(level_of(wheel->pattern(steering_cue(CueKind::kTurn, -1.0))), -524);  // 30 deg = 523.6 mrad
}

TEST(DeviceAdapterSteeringWheel, OutOfRangeKeysAreRejected) {
  for (const char* yaml : {
           "interaction: {wheel: {refresh_hz: 0}}",
           "interaction: {wheel: {refresh_hz: 200}}",
           "interaction: {wheel: {hold_margin: -0.5}}",
           "interaction: {wheel: {max_steering_deg: 0}}",
           "interaction: {wheel: {max_steering_deg: 100}}",
           "interaction: {wheel: {max_steering_deg: left}}",
       }) {
    const auto e = navaid::testing::expect_throw<ConfigError>(
        [&] { make_device_adapter(DeviceKind::kWheel, Config::parse(yaml, "wheel.yaml")); }, yaml);
    if (e) {
      EXPECT_NE(std::string(e->what()).find("interaction.wheel."), std::string::npos) << e->what();
    }
  }
  SteeringWheelConfig c;
  c.max_steering_deg = 180.0;
  EXPECT_THROW(W{c}, std::invalid_argument);
}

TEST(DeviceAdapterFactory, EachKindGivesItsAdapterAndAnUnknownKindIsRefused) {
  for (const DeviceKind kind : {DeviceKind::kBelt, DeviceKind::kHand, DeviceKind::kRumble, DeviceKind::kWheel}) {
    const auto a = make_device_adapter(kind, Config());
    ASSERT_TRUE(a);
    EXPECT_EQ(a->kind(), kind);
    EXPECT_GT(a->refresh_period_s(), 0.0);
    for (int i = 0; i < a->actuator_count(); ++i) EXPECT_FALSE(a->actuator_name(i).empty());
  }
  EXPECT_THROW(make_device_adapter(static_cast<DeviceKind>(9), Config()), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
