// W-ROMA's hand unit (§III, §IV, §V): each hand direction to its motor, the four diagonals to the
// pair, each command on continuously for one second with a command every two, hold / stop /
// arrival, nothing for walking cues, and the interaction.hand.* keys.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "device_adapter_testing.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/hand_unit_adapter.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

using planning::HandDirection;
using testing::actuators_of;
using testing::cue_of;
using testing::walking_cue;
using H = HandUnitAdapter;

Cue hand_cue(HandDirection d) {
  Cue c = cue_of(CueKind::kObjectDirection);
  c.hand = d;
  return c;
}

TEST(DeviceAdapterHandUnit, SixMotorsInTheDocumentedOrder) {
  const H hand;
  EXPECT_EQ(hand.kind(), DeviceKind::kHand);
  ASSERT_EQ(hand.actuator_count(), 6);
  const std::vector<std::pair<int, std::string_view>> expected{
      {H::kUp, "up"}, {H::kDown, "down"}, {H::kLeft, "left"}, {H::kRight, "right"}, {H::kForward, "forward"},
      {H::kBackward, "backward"}};
  for (const auto& [i, name] : expected) EXPECT_EQ(hand.actuator_name(i), name);
  EXPECT_THROW(hand.actuator_name(6), std::out_of_range);
}

TEST(DeviceAdapterHandUnit, EachAxisDirectionIsItsOwnMotor) {
  const H hand;
  const std::vector<std::pair<HandDirection, int>> single{
      {HandDirection::kUp, H::kUp},           {HandDirection::kDown, H::kDown},
      {HandDirection::kLeft, H::kLeft},       {HandDirection::kRight, H::kRight},
      {HandDirection::kForward, H::kForward}, {HandDirection::kBackward, H::kBackward}};
  for (const auto& [d, motor] : single) {
    const auto p = hand.pattern(hand_cue(d));
    ASSERT_TRUE(p) << planning::to_string(d);
    EXPECT_EQ(actuators_of(*p), std::set<int>{motor}) << planning::to_string(d);
  }
}

TEST(DeviceAdapterHandUnit, DiagonalsAreThePairOfTheirTwoMotors) {
  const H hand;
  const std::vector<std::pair<HandDirection, std::set<int>>> pairs{
      {HandDirection::kUpRight, {H::kUp, H::kRight}},
      {HandDirection::kUpLeft, {H::kUp, H::kLeft}},
      {HandDirection::kDownRight, {H::kDown, H::kRight}},
      {HandDirection::kDownLeft, {H::kDown, H::kLeft}}};
  for (const auto& [d, motors] : pairs) {
    const auto p = hand.pattern(hand_cue(d));
    ASSERT_TRUE(p) << planning::to_string(d);
    EXPECT_EQ(actuators_of(*p), motors) << planning::to_string(d);
  }
}

TEST(DeviceAdapterHandUnit, EachCommandIsOnContinuouslyForOneSecondEveryTwo) {
  const H hand;
  EXPECT_DOUBLE_EQ(hand.refresh_period_s(), 2.0);
  const auto p = hand.pattern(hand_cue(HandDirection::kUpLeft));
  ASSERT_TRUE(p);
  for (const ActuatorCommand& c : p->commands) {
    EXPECT_EQ(c.on_ms, 0);
    EXPECT_EQ(c.off_ms, 0);
    EXPECT_EQ(c.hold_ms, 1000);
    EXPECT_EQ(c.level, 1000);
    // The one device whose hold is shorter than its period: the pause separates commands.
    EXPECT_LT(c.hold_ms, hand.refresh_period_s() * 1000.0);
  }
}

TEST(DeviceAdapterHandUnit, HoldAndStopSwitchEverythingOff) {
  const H hand;
  const auto hold = hand.pattern(hand_cue(HandDirection::kHold));
  ASSERT_TRUE(hold);
  EXPECT_TRUE(hold->commands.empty());
  const auto stop = hand.pattern(cue_of(CueKind::kStop));
  ASSERT_TRUE(stop);
  EXPECT_TRUE(stop->commands.empty());
  EXPECT_EQ(stop->device, DeviceKind::kHand);
}

TEST(DeviceAdapterHandUnit, ArrivalIsOneShortPulseOfAllSix) {
  HandUnitConfig c;
  c.arrive_pulse_ms = 250;
  const auto p = H(c).pattern(cue_of(CueKind::kArrive));
  ASSERT_TRUE(p);
  EXPECT_EQ(actuators_of(*p), (std::set<int>{0, 1, 2, 3, 4, 5}));
  for (const ActuatorCommand& cmd : p->commands) {
    EXPECT_EQ(cmd.on_ms, 0);  // one pulse: on until the hold ends it
    EXPECT_EQ(cmd.hold_ms, 250);
  }
}

TEST(DeviceAdapterHandUnit, WalkingObstacleAndSystemCuesHaveNoHandPattern) {
  const H hand;
  for (const CueKind kind : {CueKind::kTurn, CueKind::kVeer, CueKind::kOnCourse, CueKind::kObstacle, CueKind::kSystem}) {
    EXPECT_FALSE(hand.pattern(walking_cue(kind, 0.5))) << to_string(kind);
  }
  EXPECT_FALSE(hand.pattern(cue_of(CueKind::kObjectDirection)));  // no hand direction given
}

TEST(DeviceAdapterHandUnit, FactoryReadsPeriodHoldAndLevel) {
  const auto hand = make_device_adapter(
      DeviceKind::kHand, Config::parse("interaction: {hand: {period_s: 1.5, hold_s: 0.8, level: 600}}"));
  ASSERT_NE(dynamic_cast<const HandUnitAdapter*>(hand.get()), nullptr);
  EXPECT_EQ(hand->kind(), DeviceKind::kHand);
  EXPECT_DOUBLE_EQ(hand->refresh_period_s(), 1.5);
  const auto p = hand->pattern(hand_cue(HandDirection::kForward));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->commands.at(0).hold_ms, 800);
  EXPECT_EQ(p->commands.at(0).level, 600);
}

TEST(DeviceAdapterHandUnit, OutOfRangeKeysAreRejected) {
  for (const char* yaml : {
           "interaction: {hand: {period_s: 0.1}}",
           "interaction: {hand: {period_s: 11}}",
           "interaction: {hand: {hold_s: 0}}",
           "interaction: {hand: {hold_s: 2.5}}",                // longer than the default period
           "interaction: {hand: {period_s: 1.0, hold_s: 1.2}}",
           "interaction: {hand: {level: 0}}",
           "interaction: {hand: {level: 2000}}",
           "interaction: {hand: {arrive_pulse_ms: 1}}",
           "interaction: {hand: {period_s: [2]}}",
       }) {
    const auto e = navaid::testing::expect_throw<ConfigError>(
        [&] { make_device_adapter(DeviceKind::kHand, Config::parse(yaml, "hand.yaml")); }, yaml);
    if (e) {
      EXPECT_NE(std::string(e->what()).find("interaction.hand."), std::string::npos) << e->what();
    }
  }
  HandUnitConfig c;
  c.hold_s = 3.0;
  EXPECT_THROW(H{c}, std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
