// ReachingUser: the hand follows the hand unit's directions; the body steps in when the arm
// cannot go on; without a device the hand's spiral sweeps the place around the remembered one.
#include <gtest/gtest.h>

#include "navaid/simulation/reaching_user.hpp"

namespace navaid::simulation {
namespace {

UserModel sure_user() {
  UserModel u = user_model_preset("typical");
  u.compliance = 1.0;
  u.reaction_delay_s = 0.5;
  u.reaction_jitter_s = 0.0;
  u.turn_error_sigma_rad = 0.0;
  u.motion.veer_sigma = 0.0;
  return u;
}

struct Walk {
  PersonMotion body;
  HandMotion hand{HandMotionConfig{}};
  ReachingUser user;
  double t = 0;
  Walk(const UserModel& u, const ReachModel& r) : body(u.motion, Vec2::Zero(), 0.0, 1), user(u, r, 2) {}
  /// Runs for `seconds`; returns the largest body speed.
  double run(double seconds, double mount_z = 1.2) {
    double fastest = 0;
    for (double end = t + seconds; t < end; t += 0.005) {
      const auto d = user.decide(t, body, hand, mount_z, false);
      body.step(d.body, 0.005);
      hand.step(0.005);
      fastest = std::max(fastest, body.speed());
    }
    return fastest;
  }
};

Instruction move(double t, const Vec3& hand_H) {
  Instruction i{t, Instruction::Kind::kMoveHand, 0};
  i.hand_H = hand_H;
  return i;
}

TEST(ReachingUser, MovesTheHandAsToldAndStepsForwardWithTheArmOut) {
  ReachModel r;
  r.direction_sigma_rad = 0.0;
  Walk w(sure_user(), r);
  const Vec3 rest = w.hand.offset();
  w.user.perceive(move(0.0, Vec3(0, -1, 0)));  // up
  EXPECT_EQ(w.run(2.0), 0.0);                  // the hand moves, the body stands
  EXPECT_NEAR(w.hand.offset().z() - rest.z(), w.hand.config().speed_mps * r.move_time_s, 0.02);
  // Forward until the arm is out, then forward steps.
  for (int k = 0; k < 4; ++k) w.user.perceive(move(w.t + 2.0 * k, Vec3(0, 0, 1)));
  const double fastest = w.run(8.0);
  EXPECT_TRUE(w.hand.at_limit(0, 1.0, 0.03));
  EXPECT_GT(fastest, 0.8 * r.step_speed_mps);
  EXPECT_GT(w.body.position().x(), 0.3);
  EXPECT_EQ(w.user.counts().walks, 1u);  // two cues moved the arm out (0.3 -> 0.75 m), the third walks
  // A side cue stops the walk and turns the person; the next forward walks on.
  w.user.perceive(move(w.t, Vec3(-1, 0, 0)));
  w.run(2.5);
  EXPECT_NEAR(w.body.heading(), r.turn_rad, 0.02);
  EXPECT_EQ(w.body.speed(), 0.0);
  w.user.perceive(move(w.t, Vec3(0, 0, 1)));
  EXPECT_GT(w.run(2.0), 0.8 * r.step_speed_mps);
  w.user.perceive(move(w.t, Vec3::Zero()));  // hold
  w.run(3.0);
  EXPECT_EQ(w.body.speed(), 0.0);
  // Backward with the hand drawn in: the object is behind, the person turns round.
  for (int k = 0; k < 5; ++k) w.user.perceive(move(w.t + 2.0 * k, Vec3(0, 0, -1)));
  w.run(14.0);
  EXPECT_NEAR(std::abs(std::remainder(w.body.heading() - r.turn_rad, 2 * M_PI)), M_PI, 0.05);
}

TEST(ReachingUser, TurnsTheBodyWhenTheHandIsAtItsSide) {
  ReachModel r;
  r.direction_sigma_rad = 0.0;
  Walk w(sure_user(), r);
  for (int k = 0; k < 3; ++k) w.user.perceive(move(2.0 * k, Vec3(1, 0, 0)));  // right, right, right
  w.run(8.0);
  EXPECT_EQ(w.user.counts().turns, 1u);
  EXPECT_NEAR(w.body.heading(), -r.turn_rad, 0.02);
  EXPECT_TRUE(w.hand.at_limit(1, -1.0));  // the arm turns with the body
}

TEST(ReachingUser, GraspsWhenToldTheTargetIsReached) {
  Walk w(sure_user(), ReachModel{});
  w.user.perceive(Instruction{0.0, Instruction::Kind::kArrived, 0});
  bool grasped = false;
  for (; w.t < 2.0; w.t += 0.005) grasped = grasped || w.user.decide(w.t, w.body, w.hand, 1.2, false).grasp;
  EXPECT_TRUE(grasped);
  EXPECT_EQ(w.user.counts().grasps, 1u);
}

TEST(ReachingUser, FromMemoryWalksThereAndSweepsTheSurroundings) {
  Walk w(sure_user(), ReachModel{});
  const Vec3 remembered(3.0, 1.0, 0.9);
  const Vec3 truth = remembered + Vec3(0.25, -0.2, 0.0);  // 32 cm from where they think
  w.user.search_from_memory(remembered);
  double closest = 1e9;
  for (; w.t < 60.0; w.t += 0.005) {
    const auto d = w.user.decide(w.t, w.body, w.hand, 1.2, false);
    w.body.step(d.body, 0.005);
    w.hand.step(0.005);
    closest = std::min(closest, (w.hand.position_W(w.body.position(), 1.2, w.body.heading()) - truth).norm());
  }
  EXPECT_LT(closest, 0.05);
  EXPECT_GE(w.user.counts().rings, 2u);
  EXPECT_LT((w.body.position() - remembered.head<2>()).norm(), 1.2);  // near it, not wandering off
}

}  // namespace
}  // namespace navaid::simulation
