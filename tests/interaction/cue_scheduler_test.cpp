// The scheduler's rules: stop pre-empts at once, rate limits, minimum gaps, de-duplication,
// interruption, time to live, the belt's 1 Hz refresh, holds and switching off.
#include "navaid/interaction/cue_scheduler.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/hand_unit_adapter.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {
namespace {

/// Words are the id; every message lasts `seconds` unless it is "long" (4 s).
class FixedSpeech final : public SpeechRenderer {
 public:
  explicit FixedSpeech(double seconds) : seconds_(seconds) {}
  std::string text(const SpokenMessage& m) const override { return m.id; }
  double duration_s(const SpokenMessage& m, const std::string&) const override {
    return m.id == "long" ? 4.0 : seconds_;
  }

 private:
  double seconds_;
};

Cue cue(double t_s, CueKind kind, std::optional<std::string> message = std::nullopt, double direction_deg = 0.0) {
  Cue c;
  c.t = seconds_to_ns(t_s);
  c.kind = kind;
  c.priority = default_priority(kind);
  c.ttl_s = kind == CueKind::kSystem ? 10.0 : 3.0;
  if (kind == CueKind::kTurn || kind == CueKind::kVeer || kind == CueKind::kOnCourse) {
    c.direction_rad = planning::deg_to_rad(direction_deg);
  }
  if (message) c.message = SpokenMessage{MessageCategory::kAction, *message, {}};
  return c;
}

struct Timeline {
  std::vector<CueEvent> events;
  std::vector<CueEvent> of(CueChannel channel, CueOutcome outcome) const {
    std::vector<CueEvent> r;
    for (const CueEvent& e : events) {
      if (e.channel == channel && e.outcome == outcome) r.push_back(e);
    }
    return r;
  }
  std::vector<double> times(CueChannel channel, CueOutcome outcome) const {
    std::vector<double> t;
    for (const CueEvent& e : of(channel, outcome)) t.push_back(std::round(ns_to_seconds(e.t) * 1e6) / 1e6);
    return t;
  }
};

Timeline feed(CueScheduler& s, const std::vector<Cue>& cues, double until_s) {
  Timeline run;
  for (const Cue& c : cues) {
    for (CueEvent& e : s.push(c)) run.events.push_back(std::move(e));
  }
  for (CueEvent& e : s.advance(seconds_to_ns(until_s))) run.events.push_back(std::move(e));
  return run;
}

class CueSchedulerTest : public ::testing::Test {
 protected:
  BeltAdapter belt_;
  FixedSpeech speech_{0.5};
  CueScheduler scheduler_{CuePolicyConfig{}, belt_, &speech_};
};

TEST_F(CueSchedulerTest, StopInterruptsTheMessageInProgressAndReachesTheBeltAtOnce) {
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kSystem, "long"), cue(1.0, CueKind::kStop, "stop")}, 5.0);
  ASSERT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kInterrupted), std::vector<double>{1.0});
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kInterrupted)[0].cue.message->id, "long");
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSent), std::vector<double>{1.0});
  EXPECT_EQ(run.of(CueChannel::kHaptic, CueOutcome::kSent)[0].pattern->commands.size(), 5u);
}

TEST_F(CueSchedulerTest, StopDropsTheLessUrgentMessagesThatWait) {
  const Timeline run = feed(scheduler_,
                       {cue(0.0, CueKind::kSystem, "long"), cue(0.1, CueKind::kSystem, "initialized"),
                        cue(0.2, CueKind::kArrive, "arrived"), cue(1.0, CueKind::kStop, "stop")},
                       10.0);
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kPreempted).size(), 2u);
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kSpoken).size(), 2u);  // long, stop
}

TEST_F(CueSchedulerTest, StopIsSpokenAtMostOncePerSecond) {
  std::vector<Cue> cues;
  for (int i = 0; i < 30; ++i) cues.push_back(cue(0.1 * i, CueKind::kStop, "stop"));
  const Timeline run = feed(scheduler_, cues, 3.0);
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 1.0, 2.0}));
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kRateLimited).size(), 27u);
  // On the belt: sent once, then refreshed at the 1 Hz tick while it lasts.
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSent), std::vector<double>{0.0});
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kRefreshed), (std::vector<double>{1.0, 2.0, 3.0}));
}

TEST_F(CueSchedulerTest, PrepareToTurnAtMostOncePerFiveSeconds) {
  const Timeline run = feed(scheduler_,
                       {cue(0.0, CueKind::kTurn, "prepare_turn", 60), cue(3.0, CueKind::kTurn, "prepare_turn", 60),
                        cue(5.5, CueKind::kTurn, "prepare_turn", 60)},
                       6.0);
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 5.5}));
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kRateLimited).size(), 1u);
}

TEST_F(CueSchedulerTest, MessagesStartAtLeastTheMinimumGapApart) {
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kSystem, "initialized"), cue(0.6, CueKind::kSystem, "located")},
                       5.0);
  // The first ends at 0.5 s; the second waits for 2.3 s after the first started.
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 2.3}));
}

TEST_F(CueSchedulerTest, TheSameWordsAreNotRepeatedWithinTheWindowUnlessAsked) {
  Cue again = cue(4.0, CueKind::kSystem, "locating");
  again.repeat = true;
  const Timeline run = feed(scheduler_,
                       {cue(0.0, CueKind::kSystem, "locating"), cue(3.0, CueKind::kSystem, "locating"), again,
                        cue(12.5, CueKind::kSystem, "locating")},
                       15.0);
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 4.0, 12.5}));
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kDuplicate).size(), 1u);
}

TEST_F(CueSchedulerTest, AWaitingMessageExpiresWhenItsTimeToLiveRunsOut) {
  Cue late = cue(0.5, CueKind::kVeer, "veer", 20);
  late.ttl_s = 1.0;
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kSystem, "long"), late}, 6.0);
  ASSERT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kExpired), std::vector<double>{1.5});
  EXPECT_EQ(run.of(CueChannel::kSpeech, CueOutcome::kSpoken).size(), 1u);
}

TEST_F(CueSchedulerTest, ObstacleInterruptsASystemMessageButAVeerDoesNot) {
  const Timeline veer = feed(scheduler_, {cue(0.0, CueKind::kSystem, "long"), cue(1.0, CueKind::kVeer, "veer", 20)}, 1.0);
  EXPECT_TRUE(veer.of(CueChannel::kSpeech, CueOutcome::kInterrupted).empty());
  const Timeline obstacle = feed(scheduler_, {cue(1.5, CueKind::kObstacle, "obstacle")}, 2.0);
  EXPECT_EQ(obstacle.times(CueChannel::kSpeech, CueOutcome::kInterrupted), std::vector<double>{1.5});
  EXPECT_EQ(obstacle.times(CueChannel::kSpeech, CueOutcome::kSpoken), std::vector<double>{1.5});
}

TEST_F(CueSchedulerTest, TheBeltChangesAtItsTickUnlessTheCueIsMoreUrgent) {
  const Timeline run = feed(scheduler_,
                       {cue(0.0, CueKind::kVeer, std::nullopt, 20), cue(0.3, CueKind::kVeer, std::nullopt, -20),
                        cue(0.6, CueKind::kVeer, std::nullopt, -20)},
                       1.0);
  // Left veer at 0, right veer waits for the 1 Hz tick.
  const std::vector<CueEvent> sent = run.of(CueChannel::kHaptic, CueOutcome::kSent);
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_DOUBLE_EQ(ns_to_seconds(sent[0].t), 0.0);
  EXPECT_EQ(sent[0].pattern->commands.at(0).actuator, BeltAdapter::kFrontLeft);
  EXPECT_DOUBLE_EQ(ns_to_seconds(sent[1].t), 1.0);
  EXPECT_EQ(sent[1].pattern->commands.at(0).actuator, BeltAdapter::kFrontRight);
  // A turn outranks a veer: at once.
  const Timeline turn = feed(scheduler_, {cue(1.2, CueKind::kTurn, std::nullopt, 60)}, 1.2);
  ASSERT_EQ(turn.times(CueChannel::kHaptic, CueOutcome::kSent), std::vector<double>{1.2});
  EXPECT_EQ(turn.of(CueChannel::kHaptic, CueOutcome::kSent)[0].pattern->commands.at(0).actuator, BeltAdapter::kLeft);
}

TEST_F(CueSchedulerTest, AStaleDirectionIsSwitchedOff) {
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kVeer, std::nullopt, 20)}, 10.0);  // ttl 3 s
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kRefreshed), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSwitchedOff), std::vector<double>{4.0});
  EXPECT_FALSE(scheduler_.next_due());
}

TEST_F(CueSchedulerTest, ArrivalIsFeltOnce) {
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kArrive, "arrived")}, 5.0);
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSent), std::vector<double>{0.0});
  EXPECT_TRUE(run.of(CueChannel::kHaptic, CueOutcome::kRefreshed).empty());
  EXPECT_FALSE(scheduler_.next_due());
}

TEST_F(CueSchedulerTest, AfterAStopLowerCuesWaitForTheHold) {
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kStop), cue(0.2, CueKind::kVeer, std::nullopt, 20)}, 1.5);
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSent), (std::vector<double>{0.0, 1.0}));
}

TEST_F(CueSchedulerTest, CuesNotToBeFeltNeverReachTheBelt) {
  Cue veer = cue(0.0, CueKind::kVeer, "bear", 20.0);
  veer.felt = false;
  Cue stop = cue(1.0, CueKind::kStop, "stop");
  stop.felt = false;
  const Timeline run = feed(scheduler_, {veer, stop}, 5.0);
  EXPECT_TRUE(run.of(CueChannel::kHaptic, CueOutcome::kSent).empty());
  EXPECT_TRUE(run.of(CueChannel::kHaptic, CueOutcome::kRefreshed).empty());
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 1.0}));
}

TEST_F(CueSchedulerTest, StopGuidanceAndInexpressibleCuesSwitchTheBeltOff) {
  Cue clear = cue(0.5, CueKind::kSystem, "guidance_stopped");
  clear.clear_haptics = true;
  const Timeline run = feed(scheduler_, {cue(0.0, CueKind::kTurn, std::nullopt, 60), clear}, 3.0);
  ASSERT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSwitchedOff), std::vector<double>{0.5});
  EXPECT_TRUE(run.of(CueChannel::kHaptic, CueOutcome::kSwitchedOff)[0].pattern->commands.empty());
  EXPECT_TRUE(run.of(CueChannel::kHaptic, CueOutcome::kRefreshed).empty());

  Cue hand = cue(4.0, CueKind::kObjectDirection);
  hand.hand = planning::HandDirection::kUp;
  const Timeline belt = feed(scheduler_, {cue(3.5, CueKind::kOnCourse), hand}, 4.0);
  EXPECT_EQ(belt.times(CueChannel::kHaptic, CueOutcome::kSwitchedOff), std::vector<double>{4.0});
}

TEST(CueScheduler, HandDirectionsAreSpokenEveryTwoSecondsOnTheHandUnit) {
  const HandUnitAdapter hand_unit;
  const FixedSpeech speech(0.6);
  CuePolicyConfig policy;
  policy.speech_min_gap_s = 0.0;
  CueScheduler s(policy, hand_unit, &speech);
  std::vector<Cue> cues;
  for (int i = 0; i < 50; ++i) {  // 5 s of "move right" at 10 Hz
    Cue c = cue(0.1 * i, CueKind::kObjectDirection, "move_hand");
    c.hand = planning::HandDirection::kRight;
    cues.push_back(c);
  }
  const Timeline run = feed(s, cues, 5.0);
  EXPECT_EQ(run.times(CueChannel::kSpeech, CueOutcome::kSpoken), (std::vector<double>{0.0, 2.0, 4.0}));
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kSent), std::vector<double>{0.0});
  EXPECT_EQ(run.times(CueChannel::kHaptic, CueOutcome::kRefreshed), (std::vector<double>{2.0, 4.0}));
}

TEST(CueScheduler, WithoutSpeechOnlyTheDeviceActs) {
  const BeltAdapter belt;
  CueScheduler s(CuePolicyConfig{}, belt, nullptr);
  const Timeline run = feed(s, {cue(0.0, CueKind::kStop, "stop")}, 0.5);
  EXPECT_TRUE(run.of(CueChannel::kSpeech, CueOutcome::kSpoken).empty());
  EXPECT_EQ(run.of(CueChannel::kHaptic, CueOutcome::kSent).size(), 1u);
}

TEST(CueScheduler, TheSameInputGivesTheSameEvents) {
  const BeltAdapter belt;
  const FixedSpeech speech(0.7);
  std::vector<Cue> cues;
  for (int i = 0; i < 200; ++i) {
    const CueKind kinds[] = {CueKind::kVeer, CueKind::kTurn, CueKind::kOnCourse, CueKind::kStop, CueKind::kSystem};
    cues.push_back(cue(0.1 * i, kinds[(i * 7) % 5], i % 3 ? std::optional<std::string>() : std::string("m") + std::to_string(i % 4),
                       (i % 9) * 10.0 - 40.0));
  }
  const auto run_once = [&] {
    CueScheduler s(CuePolicyConfig{}, belt, &speech);
    std::vector<std::string> lines;
    for (const CueEvent& e : feed(s, cues, 30.0).events) {
      lines.push_back(std::to_string(e.t) + std::string(to_string(e.channel)) + std::string(to_string(e.outcome)));
    }
    return lines;
  };
  EXPECT_EQ(run_once(), run_once());
}

TEST(CueScheduler, PolicyConfigIsRangeChecked) {
  EXPECT_THROW(read_cue_policy_config(Config::parse("interaction: {policy: {speech_min_gap_s: -1}}")), ConfigError);
  EXPECT_EQ(read_cue_policy_config(Config::parse("interaction: {policy: {interrupt_priority: 90}}")).interrupt_priority, 90);
}

}  // namespace
}  // namespace navaid::interaction
