// HandMotion: the hand-held rig's reported velocity and acceleration are those of the path it
// moves through while the body walks and turns (so the IMU it drives is consistent), and the hand
// stays within its reach.
#include <gtest/gtest.h>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/hand_motion.hpp"
#include "navaid/simulation/person_motion.hpp"

namespace navaid::simulation {
namespace {

TEST(HandMotion, ComposedVelocityAndAccelerationMatchTheMotion) {
  PersonMotionConfig c;
  c.mount_height_m = 1.2;
  c.bob_amplitude_m = 0.0;
  PersonMotion body(c, Vec2(0, 0), 0.2, 3);
  HandMotion hand(HandMotionConfig{});
  const double dt = 0.001;
  for (int k = 0; k < 8000; ++k) {
    MotionCommand cmd;
    cmd.speed_mps = k < 2000 ? 0.6 : 0.0;
    cmd.heading_rad = k < 1000 ? 0.2 : 1.4;  // a turn while the hand reaches out and up
    if (k == 500) hand.move_to(Vec3(0.7, 0.3, 0.2));
    if (k == 2500) hand.move_to(Vec3(0.2, -0.4, -0.5));
    const KinematicState before = hand.compose(body.state(), body.heading(), body.yaw_rate(), body.yaw_acceleration());
    body.step(cmd, dt);
    hand.step(dt);
    const KinematicState after = hand.compose(body.state(), body.heading(), body.yaw_rate(), body.yaw_acceleration());
    if (k < 10) continue;
    const Vec3 v_num = (after.T_W_B.t - before.T_W_B.t) / dt;
    ASSERT_LT((v_num - 0.5 * (before.v_W + after.v_W)).norm(), 2e-3) << "step " << k;
    const Vec3 a_num = (after.v_W - before.v_W) / dt;
    ASSERT_LT((a_num - after.a_W).norm(), 0.05) << "step " << k;
  }
  EXPECT_LT((hand.offset() - Vec3(0.2, -0.4, -0.5)).norm(), 1e-3);
}

TEST(HandMotion, StaysWithinReachAndMovesAtItsSpeed) {
  HandMotionConfig cfg;
  HandMotion hand(cfg);
  hand.move_to(Vec3(5.0, -5.0, 5.0));
  EXPECT_EQ(hand.target(), Vec3(cfg.max_offset_m.x(), cfg.min_offset_m.y(), cfg.max_offset_m.z()));
  double fastest = 0;
  for (int k = 0; k < 5000; ++k) {
    hand.step(0.002);
    fastest = std::max(fastest, hand.velocity().norm());
  }
  EXPECT_TRUE(hand.at_limit(0, 1.0));
  EXPECT_TRUE(hand.at_limit(1, -1.0));
  EXPECT_FALSE(hand.at_limit(1, 1.0));
  EXPECT_LE(fastest, cfg.speed_mps * 1.05);
  EXPECT_GT(fastest, cfg.speed_mps * 0.9);
}

TEST(HandMotion, BadReachIsAClearError) {
  Config c = Config::parse("{}", "<test>", {"user.hand.rest_offset_m=[0.9,0,0]"});
  EXPECT_THROW(read_hand_motion_config(c), ConfigError);
  Config ok = Config::parse("{}", "<test>", {"user.hand.speed_mps=0.4"});
  EXPECT_DOUBLE_EQ(read_hand_motion_config(ok).speed_mps, 0.4);
}

}  // namespace
}  // namespace navaid::simulation
