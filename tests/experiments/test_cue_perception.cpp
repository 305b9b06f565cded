// What a simulated user feels and hears: the belt's vibrator as a direction, the wheel's pull,
// the rumble's sides, stop and arrival (with where the destination lies), the spoken "locating";
// refreshes tell nothing new except the wheel's continuous pull and the belt's forward pulse.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/experiments/cue_perception.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/rumble_adapter.hpp"
#include "navaid/interaction/steering_wheel_adapter.hpp"

namespace navaid::experiments {
namespace {

using interaction::Cue;
using interaction::CueEvent;
using interaction::CueKind;
using interaction::CueOutcome;
using K = simulation::Instruction::Kind;

CueEvent sent(const interaction::DeviceAdapter& device, Cue cue) {
  CueEvent e;
  e.cue = cue;
  e.outcome = CueOutcome::kSent;
  e.pattern = device.pattern(cue);
  return e;
}

Cue cue(CueKind kind, std::optional<double> direction = std::nullopt) {
  Cue c;
  c.kind = kind;
  c.direction_rad = direction;
  return c;
}

TEST(CuePerception, TheBeltsFiveVibratorsAreFiveDirections) {
  const interaction::BeltAdapter belt;
  const auto turn_left = perceive_cue(sent(belt, cue(CueKind::kTurn, 1.2)), 3.0);
  ASSERT_TRUE(turn_left);
  EXPECT_EQ(turn_left->kind, K::kGo);
  EXPECT_NEAR(turn_left->value, M_PI / 2, 1e-12);  // 69 deg is felt as the left vibrator's 90
  EXPECT_EQ(turn_left->t_s, 3.0);
  const auto veer_right = perceive_cue(sent(belt, cue(CueKind::kVeer, -0.3)), 0);
  ASSERT_TRUE(veer_right);
  EXPECT_NEAR(veer_right->value, -M_PI / 4, 1e-12);
  EXPECT_EQ(perceive_cue(sent(belt, cue(CueKind::kOnCourse, 0.05)), 0)->kind, K::kKeepGoing);
  EXPECT_EQ(perceive_cue(sent(belt, cue(CueKind::kStop)), 0)->kind, K::kStop);
  EXPECT_EQ(perceive_cue(sent(belt, cue(CueKind::kArrive)), 0)->kind, K::kArrived);
  CueEvent refresh = sent(belt, cue(CueKind::kTurn, 1.2));
  refresh.outcome = CueOutcome::kRefreshed;
  EXPECT_FALSE(perceive_cue(refresh, 0));  // the same pattern again
  // The front vibrator's pulse goes on: "walk forward", to a person who stopped meanwhile too.
  CueEvent pulse = sent(belt, cue(CueKind::kOnCourse, 0.0));
  pulse.outcome = CueOutcome::kRefreshed;
  ASSERT_TRUE(perceive_cue(pulse, 0));
  EXPECT_EQ(perceive_cue(pulse, 0)->kind, K::kKeepGoing);
  CueEvent off;
  off.outcome = CueOutcome::kSwitchedOff;
  EXPECT_EQ(perceive_cue(off, 0)->kind, K::kClear);
}

TEST(CuePerception, TheWheelsPullAndTheRumblesSides) {
  const interaction::SteeringWheelAdapter wheel;
  Cue steer = cue(CueKind::kVeer, 0.2);
  steer.steering_rad = 0.25;
  CueEvent e = sent(wheel, steer);
  e.outcome = CueOutcome::kRefreshed;  // read continuously
  const auto pull = perceive_cue(e, 0);
  ASSERT_TRUE(pull);
  EXPECT_EQ(pull->kind, K::kSteer);
  EXPECT_NEAR(pull->value, 0.25, 1e-3);  // milliradian resolution
  const interaction::RumbleAdapter rumble;
  for (const auto& [state, kind, value] : {std::tuple{planning::RumbleState::kLeft, K::kTurnToward, 1.0},
                                           std::tuple{planning::RumbleState::kRight, K::kTurnToward, -1.0},
                                           std::tuple{planning::RumbleState::kBoth, K::kHalt, 0.0}}) {
    Cue c = cue(CueKind::kObstacle);
    c.rumble = state;
    const auto felt = perceive_cue(sent(rumble, c), 0);
    ASSERT_TRUE(felt);
    EXPECT_EQ(felt->kind, kind);
    EXPECT_EQ(felt->value, value);
  }
}

TEST(CuePerception, WordsThatChangeWhatThePersonDoes) {
  CueEvent spoken;
  spoken.outcome = CueOutcome::kSpoken;
  spoken.channel = interaction::CueChannel::kSpeech;
  spoken.cue.message = interaction::SpokenMessage{interaction::MessageCategory::kSystem, "locating", {}};
  EXPECT_EQ(perceive_cue(spoken, 1)->kind, K::kWait);
  spoken.cue.message->id = "arrived";
  EXPECT_EQ(perceive_cue(spoken, 1)->kind, K::kArrived);
  // Where the destination lies, heard as a clock position: the middle of the hour.
  spoken.cue.message = interaction::SpokenMessage{interaction::MessageCategory::kRoute, "arrived_facing", {{"clock", "9"}}};
  const auto facing = perceive_cue(spoken, 1);
  ASSERT_TRUE(facing);
  EXPECT_EQ(facing->kind, K::kArrived);
  EXPECT_NEAR(facing->value, M_PI / 2, 1e-12);
  spoken.cue.message->args["clock"] = "4";
  EXPECT_NEAR(perceive_cue(spoken, 1)->value, -2 * M_PI / 3, 1e-12);
  spoken.cue.message->id = "network_lost";
  EXPECT_FALSE(perceive_cue(spoken, 1));
}

}  // namespace
}  // namespace navaid::experiments
