// The BYU cane's two rumble remotes: the four states of Table 2.1, stop, what has no rumble
// pattern, the hold against the 10 Hz refresh, and the interaction.rumble.* keys.
#include <gtest/gtest.h>

#include "device_adapter_testing.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/rumble_adapter.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

using planning::RumbleState;
using testing::actuators_of;
using testing::cue_of;
using testing::walking_cue;
using R = RumbleAdapter;

std::set<int> on_for(const R& rumble, std::optional<RumbleState> state) {
  Cue c = cue_of(CueKind::kObstacle);
  c.rumble = state;
  const auto p = rumble.pattern(c);
  EXPECT_TRUE(p);
  if (!p) return {-1};
  for (const ActuatorCommand& cmd : p->commands) {
    EXPECT_EQ(cmd.level, R::kOnLevel);  // binary: on is full scale
    EXPECT_EQ(cmd.on_ms, 0);            // continuous
  }
  return actuators_of(*p);
}

TEST(DeviceAdapterRumble, TwoRemotesLeftAndRight) {
  const R rumble;
  EXPECT_EQ(rumble.kind(), DeviceKind::kRumble);
  ASSERT_EQ(rumble.actuator_count(), 2);
  EXPECT_EQ(rumble.actuator_name(R::kLeft), "left");
  EXPECT_EQ(rumble.actuator_name(R::kRight), "right");
  EXPECT_THROW(rumble.actuator_name(2), std::out_of_range);
}

TEST(DeviceAdapterRumble, Table21OffIsBothOff) { EXPECT_TRUE(on_for(R(), RumbleState::kOff).empty()); }
TEST(DeviceAdapterRumble, Table21LeftIsTheLeftRemote) {
  EXPECT_EQ(on_for(R(), RumbleState::kLeft), std::set<int>{R::kLeft});
}
TEST(DeviceAdapterRumble, Table21RightIsTheRightRemote) {
  EXPECT_EQ(on_for(R(), RumbleState::kRight), std::set<int>{R::kRight});
}
TEST(DeviceAdapterRumble, Table21BothIsBothRemotes) {
  EXPECT_EQ(on_for(R(), RumbleState::kBoth), (std::set<int>{R::kLeft, R::kRight}));
}

TEST(DeviceAdapterRumble, StopAndAnObstacleWithoutStateAreBothOn) {
  const R rumble;
  const auto stop = rumble.pattern(cue_of(CueKind::kStop));
  ASSERT_TRUE(stop);
  EXPECT_EQ(actuators_of(*stop), (std::set<int>{R::kLeft, R::kRight}));
  EXPECT_EQ(on_for(rumble, std::nullopt), (std::set<int>{R::kLeft, R::kRight}));
}

TEST(DeviceAdapterRumble, OtherCuesHaveNoRumblePattern) {
  const R rumble;
  for (const CueKind kind : {CueKind::kArrive, CueKind::kTurn, CueKind::kVeer, CueKind::kOnCourse,
                             CueKind::kObjectDirection, CueKind::kSystem}) {
    Cue c = walking_cue(kind, 0.5);
    c.rumble = RumbleState::kBoth;  // a state on a non-obstacle cue does not make it one
    EXPECT_FALSE(rumble.pattern(c)) << to_string(kind);
  }
}

TEST(DeviceAdapterRumble, HoldsExceedTheTenHertzPeriodALittle) {
  const R rumble;
  EXPECT_DOUBLE_EQ(rumble.refresh_period_s(), 0.1);
  const auto p = rumble.pattern(cue_of(CueKind::kStop));
  ASSERT_TRUE(p);
  for (const ActuatorCommand& cmd : p->commands) {
    EXPECT_EQ(cmd.hold_ms, 125);  // 100 ms x (1 + 0.25)
    EXPECT_GT(cmd.hold_ms, 100);
    EXPECT_LE(cmd.hold_ms, 200);
  }
  RumbleConfig c;
  c.refresh_hz = 20.0;
  c.hold_margin = 0.5;
  EXPECT_EQ(R(c).pattern(cue_of(CueKind::kStop))->commands.at(0).hold_ms, 75);
}

TEST(DeviceAdapterRumble, RefreshHoldRoundsUpAndRefusesNonsense) {
  EXPECT_EQ(refresh_hold_ms(0.1, 0.25), 125);
  EXPECT_EQ(refresh_hold_ms(0.001, 0.01), 2);  // 1.01 ms rounds up: still longer than the period
  EXPECT_THROW(refresh_hold_ms(0.0, 0.2), std::invalid_argument);
  EXPECT_THROW(refresh_hold_ms(1.0, -0.1), std::invalid_argument);
  EXPECT_THROW(refresh_hold_ms(60.0, 1.0), std::invalid_argument);  // 120 s does not fit the link
}

TEST(DeviceAdapterRumble, FactoryReadsTheRefreshRate) {
  const auto rumble = make_device_adapter(DeviceKind::kRumble, Config::parse("interaction: {rumble: {refresh_hz: 5}}"));
  ASSERT_NE(dynamic_cast<const RumbleAdapter*>(rumble.get()), nullptr);
  EXPECT_EQ(rumble->kind(), DeviceKind::kRumble);
  EXPECT_DOUBLE_EQ(rumble->refresh_period_s(), 0.2);
  EXPECT_EQ(rumble->all_off(7).device, DeviceKind::kRumble);
  EXPECT_TRUE(rumble->all_off(7).commands.empty());
}

TEST(DeviceAdapterRumble, OutOfRangeKeysAreRejected) {
  for (const char* yaml : {
           "interaction: {rumble: {refresh_hz: 0.5}}",
           "interaction: {rumble: {refresh_hz: 1000}}",
           "interaction: {rumble: {hold_margin: 0.001}}",
           "interaction: {rumble: {hold_margin: 3}}",
           "interaction: {rumble: {refresh_hz: .nan}}",
       }) {
    const auto e = navaid::testing::expect_throw<ConfigError>(
        [&] { make_device_adapter(DeviceKind::kRumble, Config::parse(yaml, "rumble.yaml")); }, yaml);
    if (e) {
      EXPECT_NE(std::string(e->what()).find("interaction.rumble."), std::string::npos) << e->what();
    }
  }
  RumbleConfig c;
  c.refresh_hz = 0.0;
  EXPECT_THROW(R{c}, std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
