// SimulatedUser: instructions are acted on after the reaction delay, directions with the turn
// error, a non-compliant user ignores some, the cane makes them stop and step round, the presets
// and user.* keys load and bad ones are named.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/simulated_user.hpp"

namespace navaid::simulation {
namespace {

using K = Instruction::Kind;

UserModel exact_user() {
  UserModel m = user_model_preset("typical");
  m.reaction_jitter_s = 0;
  m.turn_error_sigma_rad = 0;
  m.compliance = 1.0;
  m.speed_sigma_mps = 0;
  m.motion.veer_sigma = 0;
  return m;
}

/// Steps user and body together for `seconds` from t0; returns the end time.
double run(SimulatedUser& user, PersonMotion& body, double t0, double seconds, std::optional<CaneTouch> cane = {}) {
  double t = t0;
  for (; t < t0 + seconds; t += 0.005) body.step(user.decide(t, body, cane), 0.005);
  return t;
}

TEST(SimulatedUser, AGuidedUserWaitsForTheFirstDirectionAndTurnsAfterTheDelay) {
  const UserModel m = exact_user();
  SimulatedUser user(m, false, Vec2(100, 0), 1);
  PersonMotion body(m.motion, Vec2::Zero(), 0.0, 1);
  double t = run(user, body, 0.0, 2.0);
  EXPECT_EQ(body.distance_walked(), 0.0);  // no direction yet: standing
  user.perceive({t, K::kGo, M_PI / 2});
  const double told = t;
  t = run(user, body, t, m.reaction_delay_s - 0.05);
  EXPECT_EQ(body.distance_walked(), 0.0);  // still reacting
  t = run(user, body, t, 4.0);
  EXPECT_NEAR(body.heading(), M_PI / 2, 0.01);
  EXPECT_NEAR(body.speed(), m.speed_mps, 1e-6);
  EXPECT_EQ(user.counts().corrections, 1u);
  user.perceive({t, K::kStop, 0});
  run(user, body, t, 3.0);
  EXPECT_EQ(body.speed(), 0.0);
  EXPECT_EQ(user.counts().stops, 1u);
  (void)told;
}

TEST(SimulatedUser, AUserToldToWalkOffWalksUntilTheFirstDirectionAndOnlyAStopHoldsThem) {
  const UserModel m = exact_user();
  SimulatedUser user(m, false, Vec2(100, 0), 3);
  user.walk_off(0.5, 0.7);
  PersonMotion body(m.motion, Vec2::Zero(), 0.5, 3);
  double t = run(user, body, 0.0, 3.0);
  EXPECT_NEAR(body.speed(), 0.7 * m.speed_mps, 1e-6);
  EXPECT_NEAR(body.heading(), 0.5, 1e-3);
  user.perceive({t, K::kWait, 0});  // "Locating, please wait.": walking off is what locates them
  t = run(user, body, t, 2.0);
  EXPECT_NEAR(body.speed(), 0.7 * m.speed_mps, 1e-6);
  user.perceive({t, K::kGo, -0.5});  // the first direction: full speed that way
  t = run(user, body, t, 3.0);
  EXPECT_NEAR(body.heading(), 0.0, 0.01);
  EXPECT_NEAR(body.speed(), m.speed_mps, 1e-6);
  SimulatedUser held(m, false, Vec2(100, 0), 4);
  held.walk_off(0.0, 0.7);
  PersonMotion still(m.motion, Vec2::Zero(), 0.0, 4);
  held.perceive({0.0, K::kStop, 0});
  run(held, still, 0.0, 3.0);
  EXPECT_LT(still.distance_walked(), 0.6);  // stopped after the reaction delay and the slowing down
  EXPECT_EQ(still.speed(), 0.0);
}

TEST(SimulatedUser, ACaneUserWalksTowardTheGoalAndStepsRoundWhatTheCaneTouches) {
  UserModel m = exact_user();
  m.cane.enabled = true;
  SimulatedUser user(m, true, Vec2(0, 10), 2);
  PersonMotion body(m.motion, Vec2::Zero(), 0.0, 2);
  double t = run(user, body, 0.0, 3.0);
  EXPECT_NEAR(body.heading(), M_PI / 2, 0.05);  // toward the goal, north
  // Something on the right of the cane's sector: stop, turn left (away), then a short detour.
  CaneTouch touch{-0.3, 1.0, false, 0};
  t = run(user, body, t, 0.1, touch);
  EXPECT_EQ(user.counts().cane_avoidances, 1u);
  t = run(user, body, t, m.cane_stop_s);
  EXPECT_GT(body.heading(), M_PI / 2 + 0.5 * m.cane_turn_rad);
  run(user, body, t, 6.0);
  EXPECT_NEAR(body.heading(), std::atan2(10 - body.position().y(), -body.position().x()), 0.05);  // back toward the goal
}

TEST(SimulatedUser, ToldWhereTheDestinationLiesOnArrivalTheyTurnToFaceItAndStay) {
  const UserModel m = exact_user();
  SimulatedUser user(m, false, Vec2(100, 0), 5);
  PersonMotion body(m.motion, Vec2::Zero(), 0.0, 5);
  user.perceive({0.0, K::kGo, 0.0});
  double t = run(user, body, 0.0, 3.0);
  // "You have arrived. The destination is at 9 o'clock." heard with the belt's arrival pulse.
  user.perceive({t, K::kArrived, M_PI / 2});
  user.perceive({t, K::kArrived, 0.0});  // the felt pulse says no direction: the turn stands
  t = run(user, body, t, 4.0);
  EXPECT_TRUE(user.arrived());
  EXPECT_EQ(body.speed(), 0.0);
  EXPECT_NEAR(body.heading(), M_PI / 2, 0.01);
  user.perceive({t, K::kGo, -M_PI / 2});  // nothing moves an arrived person
  run(user, body, t, 3.0);
  EXPECT_NEAR(body.heading(), M_PI / 2, 0.01);
}

TEST(SimulatedUser, TheExperimenterTurnsAPersonBackAndACaneUserStopsAtTheGoalTheyKnow) {
  const UserModel m = exact_user();
  // A guided person walks the way they were turned to until the device's next direction.
  SimulatedUser guided(m, false, Vec2(100, 0), 6);
  PersonMotion a(m.motion, Vec2::Zero(), 0.0, 6);
  guided.redirect(-M_PI / 2, 5.0, a);
  run(guided, a, 0.0, 4.0);
  EXPECT_NEAR(a.heading(), -M_PI / 2, 0.01);
  EXPECT_GT(a.speed(), 0.5);
  // A goal-known one walks it for the distance, then heads for their goal again; stopped there.
  SimulatedUser known(m, true, std::vector<Vec2>{Vec2(6, 0)}, 0.8, 7);
  known.stop_at_goal();
  PersonMotion b(m.motion, Vec2::Zero(), 0.0, 7);
  known.redirect(M_PI / 2, 1.0, b);
  double t = run(known, b, 0.0, 2.0);
  EXPECT_GT(b.position().y(), 0.5);  // went the experimenter's way first
  run(known, b, t, 15.0);
  EXPECT_TRUE(known.arrived());
  EXPECT_LE((b.position() - Vec2(6, 0)).norm(), 0.8);
  EXPECT_EQ(b.speed(), 0.0);
}

TEST(SimulatedUser, ComplianceDecidesHowManyDirectionsAreFollowed) {
  UserModel m = exact_user();
  m.compliance = 0.5;
  SimulatedUser user(m, false, Vec2(10, 0), 3);
  for (int k = 0; k < 400; ++k) user.perceive({0.01 * k, K::kGo, 0.3});
  for (int k = 0; k < 50; ++k) user.perceive({5.0 + 0.01 * k, K::kStop, 0});  // always heeded
  EXPECT_EQ(user.counts().instructions, 450u);
  EXPECT_NEAR(static_cast<double>(user.counts().ignored), 200.0, 40.0);
}

TEST(SimulatedUser, PresetsAndKeys) {
  for (const auto& name : user_model_names()) EXPECT_EQ(user_model_preset(name).name, name);
  EXPECT_THROW(user_model_preset("athlete"), UsageError);
  const Config c = Config::parse("{}", "<test>", {"user.model=cautious", "user.speed_mps=0.5", "user.cane.enabled=true"});
  const UserModel m = read_user_model(c);
  EXPECT_EQ(m.name, "cautious");
  EXPECT_EQ(m.speed_mps, 0.5);
  EXPECT_TRUE(m.cane.enabled);
  EXPECT_THROW(read_user_model(Config::parse("{}", "<test>", {"user.compliance=2"})), ConfigError);
  EXPECT_THROW(read_user_model(Config::parse("{}", "<test>", {"user.model=athlete"})), ConfigError);
}

}  // namespace
}  // namespace navaid::simulation
