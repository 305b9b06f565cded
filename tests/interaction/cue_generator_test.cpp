// The cue generator: eLabrador's heading thresholds with hysteresis, locating, announcements once
// per change, voice commands.
#include "navaid/interaction/cue_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/message_templates.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {
namespace {

using planning::deg_to_rad;
using planning::GuidanceAction;
using planning::GuidanceCommand;
using planning::GuidanceReason;

GuidanceCommand go(double t_s, double heading_deg, double confidence = 1.0) {
  GuidanceCommand c;
  c.t = seconds_to_ns(t_s);
  c.action = GuidanceAction::kGo;
  c.reason = GuidanceReason::kPathFound;
  c.confidence = confidence;
  c.heading_rad = deg_to_rad(heading_deg);
  return c;
}

GuidanceCommand command(double t_s, GuidanceAction action, GuidanceReason reason) {
  GuidanceCommand c;
  c.t = seconds_to_ns(t_s);
  c.action = action;
  c.reason = reason;
  c.confidence = 1.0;
  return c;
}

std::vector<std::string> said(const std::vector<Cue>& cues) {
  std::vector<std::string> ids;
  for (const Cue& c : cues) {
    if (c.message) ids.push_back(c.message->id);
  }
  return ids;
}

TEST(CueGenerator, ElabradorThresholdsWithoutHistory) {
  const CueGenerator g;
  EXPECT_EQ(g.classify(deg_to_rad(0.0), std::nullopt), HeadingClass::kOnCourse);
  EXPECT_EQ(g.classify(deg_to_rad(9.9), std::nullopt), HeadingClass::kOnCourse);
  EXPECT_EQ(g.classify(deg_to_rad(-10.1), std::nullopt), HeadingClass::kVeer);
  EXPECT_EQ(g.classify(deg_to_rad(29.9), std::nullopt), HeadingClass::kVeer);
  EXPECT_EQ(g.classify(deg_to_rad(30.1), std::nullopt), HeadingClass::kTurn);
  EXPECT_EQ(g.classify(deg_to_rad(-170.0), std::nullopt), HeadingClass::kTurn);
}

TEST(CueGenerator, HysteresisKeepsTheClassNearAThreshold) {
  const CueGenerator g;  // 3 deg
  // On course stays on course up to 13 deg; veer needs to come back below 7 deg.
  EXPECT_EQ(g.classify(deg_to_rad(12.9), HeadingClass::kOnCourse), HeadingClass::kOnCourse);
  EXPECT_EQ(g.classify(deg_to_rad(13.1), HeadingClass::kOnCourse), HeadingClass::kVeer);
  EXPECT_EQ(g.classify(deg_to_rad(7.1), HeadingClass::kVeer), HeadingClass::kVeer);
  EXPECT_EQ(g.classify(deg_to_rad(6.9), HeadingClass::kVeer), HeadingClass::kOnCourse);
  // Veer stays veer up to 33 deg; turn stays turn down to 27 deg.
  EXPECT_EQ(g.classify(deg_to_rad(32.9), HeadingClass::kVeer), HeadingClass::kVeer);
  EXPECT_EQ(g.classify(deg_to_rad(33.1), HeadingClass::kVeer), HeadingClass::kTurn);
  EXPECT_EQ(g.classify(deg_to_rad(27.1), HeadingClass::kTurn), HeadingClass::kTurn);
  EXPECT_EQ(g.classify(deg_to_rad(26.9), HeadingClass::kTurn), HeadingClass::kVeer);
  // From a turn a heading straight ahead is on course at once.
  EXPECT_EQ(g.classify(deg_to_rad(2.0), HeadingClass::kTurn), HeadingClass::kOnCourse);
}

int class_changes(CueGeneratorConfig config, double centre_deg, double noise_deg) {
  CueGenerator g(config);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, noise_deg);
  std::optional<CueKind> last;
  int changes = 0;
  for (int i = 0; i < 600; ++i) {  // a minute at 10 Hz
    const std::vector<Cue> cues = g.on_guidance(go(0.1 * i, centre_deg + noise(rng)));
    if (cues.size() != 1u) return -1;
    if (last && *last != cues[0].kind) ++changes;
    last = cues[0].kind;
  }
  return changes;
}

TEST(CueGenerator, ANoisyHeadingOnAThresholdDoesNotFlicker) {
  CueGeneratorConfig none;
  none.hysteresis_rad = 0.0;
  for (const double centre : {10.0, 30.0}) {
    const int with = class_changes(CueGeneratorConfig{}, centre, 1.0);
    const int without = class_changes(none, centre, 1.0);
    EXPECT_LE(with, 2) << centre;
    EXPECT_GT(without, 100) << centre;
  }
}

TEST(CueGenerator, DirectionKeepsItsSignAndTheSteering) {
  CueGenerator g;
  GuidanceCommand c = go(0.0, -20.0);
  c.steering_rad = -0.1;
  const std::vector<Cue> cues = g.on_guidance(c);
  ASSERT_EQ(cues.size(), 1u);
  EXPECT_EQ(cues[0].kind, CueKind::kVeer);
  EXPECT_NEAR(*cues[0].direction_rad, deg_to_rad(-20.0), 1e-12);
  EXPECT_DOUBLE_EQ(*cues[0].steering_rad, -0.1);
  EXPECT_EQ(cues[0].priority, default_priority(CueKind::kVeer));
}

TEST(CueGenerator, PrepareToTurnOnceOnEnteringATurn) {
  CueGenerator g;
  EXPECT_TRUE(said(g.on_guidance(go(0.0, 0.0))).empty());
  const std::vector<Cue> enter = g.on_guidance(go(0.1, 60.0));
  ASSERT_EQ(said(enter), std::vector<std::string>{"prepare_turn"});
  EXPECT_EQ(enter[0].message->args.at("side"), "left");
  EXPECT_TRUE(said(g.on_guidance(go(0.2, 55.0))).empty());
  EXPECT_TRUE(said(g.on_guidance(go(0.3, 0.0))).empty());
  const std::vector<Cue> right = g.on_guidance(go(0.4, -90.0));
  ASSERT_EQ(said(right), std::vector<std::string>{"prepare_turn"});
  EXPECT_EQ(right[0].message->args.at("side"), "right");
}

TEST(CueGenerator, LocatingIsSaidOnEnteringThenEveryRepeatPeriodAndLocatedOnLeaving) {
  CueGenerator g;
  const GuidanceCommand wait = command(0.0, GuidanceAction::kWait, GuidanceReason::kLocating);
  int locating = 0;
  for (int i = 0; i <= 250; ++i) {  // 25 s at 10 Hz
    GuidanceCommand c = wait;
    c.t = seconds_to_ns(0.1 * i);
    const std::vector<Cue> cues = g.on_guidance(c);
    for (const Cue& cue : cues) {
      EXPECT_FALSE(cue.direction_rad);
      if (cue.message && cue.message->id == "locating") ++locating;
    }
  }
  EXPECT_EQ(locating, 3);  // 0, 10, 20 s
  EXPECT_EQ(said(g.on_guidance(go(25.1, 0.0))), std::vector<std::string>{"located"});
}

TEST(CueGenerator, AnUnsureGoCommandGivesNoDirection) {
  CueGenerator g;
  const std::vector<Cue> cues = g.on_guidance(go(0.0, 45.0, 0.1));  // below min_confidence 0.2
  ASSERT_EQ(said(cues), std::vector<std::string>{"locating"});
  EXPECT_FALSE(cues[0].direction_rad);
  EXPECT_EQ(cues[0].kind, CueKind::kSystem);
  const std::vector<Cue> sure = g.on_guidance(go(0.1, 45.0, 0.9));
  ASSERT_FALSE(sure.empty());
  EXPECT_EQ(sure.back().kind, CueKind::kTurn);
}

TEST(CueGenerator, StopArriveAndTargetReached) {
  CueGenerator g;
  const std::vector<Cue> stop = g.on_guidance(command(0.0, GuidanceAction::kStop, GuidanceReason::kObstacleAhead));
  ASSERT_EQ(stop.size(), 1u);
  EXPECT_EQ(stop[0].kind, CueKind::kStop);
  EXPECT_EQ(stop[0].priority, 100);
  EXPECT_EQ(stop[0].message->id, "stop");
  EXPECT_EQ(stop[0].message->category, MessageCategory::kAction);
  const std::vector<Cue> arrive = g.on_guidance(command(1.0, GuidanceAction::kArrived, GuidanceReason::kPathFound));
  EXPECT_EQ(said(arrive), std::vector<std::string>{"arrived"});
  const std::vector<Cue> reached =
      g.on_guidance(command(2.0, GuidanceAction::kArrived, GuidanceReason::kTargetReached));
  EXPECT_EQ(said(reached), std::vector<std::string>{"target_reached"});
  // With the landmark to face: its clock position ("at 9 o'clock" = left), and the direction.
  GuidanceCommand facing = command(3.0, GuidanceAction::kArrived, GuidanceReason::kPathFound);
  facing.heading_rad = deg_to_rad(80.0);
  const std::vector<Cue> turn = g.on_guidance(facing);
  ASSERT_EQ(said(turn), std::vector<std::string>{"arrived_facing"});
  EXPECT_EQ(turn[0].message->args.at("clock"), "9");
  EXPECT_EQ(turn[0].kind, CueKind::kArrive);
  EXPECT_NEAR(*turn[0].direction_rad, deg_to_rad(80.0), 1e-12);
  EXPECT_EQ(render_message(*turn[0].message, "en"), "You have arrived. The destination is at 9 o'clock.");
}

TEST(CueGenerator, ClockPositionsAreThirtyDegreesClockwiseFromAhead) {
  for (const auto& [deg, hour] : std::vector<std::pair<double, int>>{
           {0, 12}, {14, 12}, {-14, 12}, {16, 11}, {-16, 1}, {90, 9}, {-90, 3}, {180, 6}, {-180, 6}, {-150, 5}, {120, 8}})
    EXPECT_EQ(clock_position(deg_to_rad(deg)), hour) << deg;
  for (int hour = 1; hour <= 12; ++hour) EXPECT_EQ(clock_position(clock_bearing(hour)), hour);
  EXPECT_NEAR(clock_bearing(9), deg_to_rad(90), 1e-12);
  EXPECT_NEAR(clock_bearing(3), deg_to_rad(-90), 1e-12);
  EXPECT_NEAR(clock_bearing(12), 0.0, 1e-12);
}

TEST(CueGenerator, HandDirectionsAndRumbleStates) {
  CueGenerator g;
  GuidanceCommand hand = command(0.0, GuidanceAction::kGo, GuidanceReason::kTargetInView);
  hand.hand = planning::HandDirection::kUpLeft;
  const std::vector<Cue> h = g.on_guidance(hand);
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0].kind, CueKind::kObjectDirection);
  EXPECT_EQ(h[0].message->id, "move_hand");
  EXPECT_EQ(h[0].message->args.at("direction"), "up-left");
  hand.hand = planning::HandDirection::kHold;
  EXPECT_FALSE(g.on_guidance(hand)[0].message);

  GuidanceCommand rumble = command(1.0, GuidanceAction::kGo, GuidanceReason::kObstacleAhead);
  rumble.rumble = planning::RumbleState::kLeft;
  const std::vector<Cue> r = g.on_guidance(rumble);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].kind, CueKind::kObstacle);
  EXPECT_EQ(*r[0].rumble, planning::RumbleState::kLeft);
  rumble.rumble = planning::RumbleState::kOff;
  EXPECT_EQ(g.on_guidance(rumble)[0].kind, CueKind::kOnCourse);
}

TEST(CueGenerator, ModeChangesAreAnnouncedOncePerChange) {
  CueGenerator g;
  std::vector<std::string> modes;
  const std::vector<std::string> sequence = {"RGBD-VIO", "RGBD-VIO", "VIO", "VIO", "VIO", "IMU-only", "IMU-only"};
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    for (const Cue& c : g.on_event({seconds_to_ns(0.1 * i), SystemEventKind::kEstimatorMode, sequence[i]})) {
      modes.push_back(c.message->args.at("mode"));
    }
  }
  EXPECT_EQ(modes, (std::vector<std::string>{"VIO", "IMU-only"}));
}

TEST(CueGenerator, NetworkAndLinkStatesAreAnnouncedOnChangeOnly) {
  CueGenerator g;
  std::vector<std::string> ids;
  for (SystemEventKind k : {SystemEventKind::kNetworkRestored, SystemEventKind::kNetworkLost,
                            SystemEventKind::kNetworkLost, SystemEventKind::kNetworkRestored,
                            SystemEventKind::kLinkLost, SystemEventKind::kLinkLost, SystemEventKind::kLinkRestored,
                            SystemEventKind::kInitialized, SystemEventKind::kInitialized}) {
    for (const std::string& id : said(g.on_event({0, k, ""}))) ids.push_back(id);
  }
  EXPECT_EQ(ids, (std::vector<std::string>{"network_lost", "network_restored", "link_lost", "link_restored",
                                           "initialized"}));
}

TEST(CueGenerator, VoiceCommands) {
  CueGenerator g;
  const auto voice = [&](double t, const std::string& v) {
    return g.on_event({seconds_to_ns(t), SystemEventKind::kVoiceCommand, v});
  };
  EXPECT_EQ(said(voice(0.0, "repeat")), std::vector<std::string>{"no_instruction"});
  g.on_event({seconds_to_ns(0.5), SystemEventKind::kRouteInstruction, "49;left;Main Street"});
  const std::vector<Cue> again = voice(1.0, "repeat");
  ASSERT_EQ(said(again), std::vector<std::string>{"route"});
  EXPECT_TRUE(again[0].repeat);
  EXPECT_EQ(again[0].message->args.at("road"), "Main Street");
  g.on_guidance(command(1.5, GuidanceAction::kStop, GuidanceReason::kObstacleAhead));
  EXPECT_EQ(said(voice(2.0, "repeat")), std::vector<std::string>{"stop"});
  EXPECT_EQ(said(voice(2.5, "where am i")), std::vector<std::string>{"route"});

  const std::vector<Cue> stopped = voice(3.0, "stop guidance");
  ASSERT_EQ(stopped.size(), 1u);
  EXPECT_TRUE(stopped[0].clear_haptics);
  EXPECT_TRUE(g.on_guidance(go(3.1, 45.0)).empty());  // guidance is silent until a new destination
  const std::vector<Cue> dest = voice(4.0, "go to bus stop");
  ASSERT_EQ(said(dest), std::vector<std::string>{"destination_set"});
  EXPECT_EQ(dest[0].message->args.at("place"), "bus stop");
  EXPECT_FALSE(g.on_guidance(go(4.1, 45.0)).empty());
  EXPECT_EQ(said(voice(5.0, "sing a song")), std::vector<std::string>{"not_understood"});
}

TEST(CueGenerator, ConfigIsRangeChecked) {
  EXPECT_THROW(read_cue_generator_config(Config::parse("interaction: {cues: {turn_deg: 8}}")), ConfigError);
  EXPECT_THROW(read_cue_generator_config(Config::parse("interaction: {cues: {turn_deg: 15, hysteresis_deg: 3}}")), ConfigError);
  EXPECT_THROW(read_cue_generator_config(Config::parse("interaction: {cues: {min_confidence: 2}}")), ConfigError);
  const CueGeneratorConfig c =
      read_cue_generator_config(Config::parse("interaction: {cues: {on_course_deg: 15, turn_deg: 40}}"));
  EXPECT_NEAR(c.on_course_rad, deg_to_rad(15.0), 1e-12);
  EXPECT_NEAR(c.turn_rad, deg_to_rad(40.0), 1e-12);
}

TEST(CueGenerator, ABadRouteInstructionIsAClearError) {
  CueGenerator g;
  EXPECT_THROW(g.on_event({0, SystemEventKind::kRouteInstruction, "49 meters left"}), Error);
}

}  // namespace
}  // namespace navaid::interaction

namespace navaid::interaction {
namespace {

CueGenerator with_modality(CueModality m) {
  CueGeneratorConfig c;
  c.modality = m;
  return CueGenerator(c);
}

TEST(CueGeneratorModality, AudioSpeaksDirectionsAndFeelsNothing) {
  CueGenerator g = with_modality(CueModality::kAudio);
  const auto on_course = g.on_guidance(go(0.0, 2.0));
  ASSERT_EQ(on_course.size(), 1u);
  EXPECT_FALSE(on_course[0].felt);
  EXPECT_FALSE(on_course[0].message) << "silence while on course";
  const auto veer = g.on_guidance(go(0.1, -20.0));
  ASSERT_EQ(veer.size(), 1u);
  EXPECT_FALSE(veer[0].felt);
  ASSERT_TRUE(veer[0].message);
  EXPECT_EQ(veer[0].message->id, "bear");
  EXPECT_EQ(veer[0].message->args.at("side"), "right");
  const auto turn = g.on_guidance(go(0.2, 60.0));
  ASSERT_TRUE(turn[0].message);
  EXPECT_EQ(turn[0].message->id, "prepare_turn");
  planning::GuidanceCommand obstacle = go(0.3, 0.0);
  obstacle.heading_rad.reset();
  obstacle.rumble = planning::RumbleState::kLeft;
  const auto o = g.on_guidance(obstacle);
  ASSERT_TRUE(o[0].message);
  EXPECT_EQ(o[0].message->id, "obstacle");
  EXPECT_EQ(o[0].message->args.at("way"), "left");
  obstacle.rumble = planning::RumbleState::kBoth;
  EXPECT_EQ(g.on_guidance(obstacle)[0].message->args.at("way"), "stop");
}

TEST(CueGeneratorModality, HapticKeepsStopAndSystemMessagesOnly) {
  CueGenerator g = with_modality(CueModality::kHaptic);
  const auto turn = g.on_guidance(go(0.0, 60.0));
  ASSERT_EQ(turn.size(), 1u);
  EXPECT_TRUE(turn[0].felt);
  EXPECT_FALSE(turn[0].message) << "no 'prepare to turn' in haptic mode";
  planning::GuidanceCommand stop = go(1.0, 0.0);
  stop.action = planning::GuidanceAction::kStop;
  stop.heading_rad.reset();
  const auto s = g.on_guidance(stop);
  ASSERT_TRUE(s[0].message);
  EXPECT_EQ(s[0].message->id, "stop");
  planning::GuidanceCommand unsure = go(2.0, 0.0);
  unsure.confidence = 0.0;
  const auto l = g.on_guidance(unsure);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_EQ(l[0].message->id, "locating") << "uncertainty is spoken whatever the modality";
}

TEST(CueGeneratorModality, EveryModalityRoundTripsThroughItsName) {
  // Every enumerator with its name (the config key's values); a dropped or misspelt entry fails.
  const std::vector<std::pair<CueModality, std::string_view>> modalities{
      {CueModality::kBoth, "both"},
      {CueModality::kHaptic, "haptic"},
      {CueModality::kAudio, "audio"},
  };
  for (const auto& [modality, name] : modalities) {
    EXPECT_EQ(to_string(modality), name);
    EXPECT_EQ(cue_modality_from_string(to_string(modality)), modality) << name;
    const Config config = Config::parse("{}", "t", {"interaction.cues.modality=" + std::string(name)});
    EXPECT_EQ(read_cue_generator_config(config).modality, modality) << name;
  }
  EXPECT_EQ(cue_modality_from_string("Audio"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<CueModality>(9)), "unknown");
}

TEST(CueGeneratorModality, BothIsTheDefaultAndTheKeyIsChecked) {
  EXPECT_EQ(read_cue_generator_config(Config::parse("{}", "t", {})).modality, CueModality::kBoth);
  EXPECT_EQ(read_cue_generator_config(Config::parse("{}", "t", {"interaction.cues.modality=audio"})).modality,
            CueModality::kAudio);
  EXPECT_THROW(read_cue_generator_config(Config::parse("{}", "t", {"interaction.cues.modality=smell"})), ConfigError);
}

}  // namespace
}  // namespace navaid::interaction
