// PersonMotion: the closed-loop walker's reported derivatives are those of the pose it moves
// through (so the IMU it drives is consistent), and it follows headings, turn rates and speeds.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/person_motion.hpp"

namespace navaid::simulation {
namespace {

double yaw_of(const SE3& T) {
  const Mat3 R = T.rotation();
  return std::atan2(R(1, 0), R(0, 0));
}

TEST(PersonMotion, ReportedVelocityAndAccelerationMatchTheMotionItMakes) {
  PersonMotionConfig c;
  c.scan_amplitude_rad = 0.3;  // a sweeping cane rig
  c.bob_amplitude_m = 0.02;
  PersonMotion body(c, Vec2(1, 2), 0.3, 7);
  const double dt = 0.001;
  // Walk off, then turn while walking: speed and turn rate change all the time.
  for (int k = 0; k < 3000; ++k) {
    MotionCommand cmd;
    cmd.speed_mps = 1.0;
    cmd.heading_rad = k < 1000 ? 0.3 : 1.5;
    const KinematicState before = body.state();
    body.step(cmd, dt);
    const KinematicState after = body.state();
    if (k < 10) continue;
    // Central differences over one step against the mean of the reported derivatives.
    const Vec3 v_num = (after.T_W_B.t - before.T_W_B.t) / dt;
    EXPECT_LT((v_num - 0.5 * (before.v_W + after.v_W)).norm(), 2e-3) << "step " << k;
    const Vec3 a_num = (after.v_W - before.v_W) / dt;
    EXPECT_LT((a_num - after.a_W).norm(), 0.05) << "step " << k;
    const double yaw_rate_num = std::remainder(yaw_of(after.T_W_B) - yaw_of(before.T_W_B), 2 * M_PI) / dt;
    EXPECT_NEAR(yaw_rate_num, 0.5 * (before.omega_B.z() + after.omega_B.z()), 2e-3) << "step " << k;
  }
  EXPECT_NEAR(body.heading(), 1.5, 0.01);
  EXPECT_NEAR(body.speed(), 1.0, 1e-9);
  EXPECT_GT(body.distance_walked(), 2.3);  // 3 s at 1 m/s less the speed-up's lag
}

TEST(PersonMotion, FollowsATurnRateAndStops) {
  PersonMotion body(PersonMotionConfig{}, Vec2::Zero(), 0.0, 1);
  MotionCommand steer;
  steer.speed_mps = 0.8;
  steer.follow_heading = false;
  steer.turn_rate_rad_s = 0.5;
  for (int k = 0; k < 400; ++k) body.step(steer, 0.005);
  EXPECT_NEAR(body.yaw_rate(), 0.5, 1e-6);
  MotionCommand stop;
  stop.speed_mps = 0;
  stop.heading_rad = body.heading();
  for (int k = 0; k < 600; ++k) body.step(stop, 0.005);
  EXPECT_EQ(body.speed(), 0.0);
  const Vec2 p = body.position();
  body.step(stop, 0.005);
  EXPECT_EQ(body.position(), p);
}

TEST(PersonMotion, ABumpIsFeltAsTheDecelerationThatStopsTheWalk) {
  // The IMU integrates a_W between its samples: across the step that ran into the wall, the
  // reported acceleration must take the walking velocity to zero, or the estimator's IMU keeps
  // walking while the camera stands.
  PersonMotion body(PersonMotionConfig{}, Vec2::Zero(), 0.4, 3);
  MotionCommand walk;
  walk.speed_mps = 1.0;
  walk.heading_rad = 0.4;
  const double dt = 0.005;
  for (int k = 0; k < 600; ++k) body.step(walk, dt);
  const Vec2 from = body.position();
  const KinematicState before = body.state();
  body.step(walk, dt);
  body.halt_at(from);
  const KinematicState hit = body.state();
  EXPECT_EQ(body.speed(), 0.0);
  EXPECT_EQ(hit.v_W.head<2>(), Vec2::Zero());
  EXPECT_LT((before.v_W.head<2>() + hit.a_W.head<2>() * dt).norm(), 0.01);  // v + a dt = 0
  MotionCommand stand;
  stand.heading_rad = body.heading();
  body.step(stand, dt);
  EXPECT_LT(body.state().a_W.head<2>().norm(), 1e-9);  // one impact, then standing
}

TEST(PersonMotion, VeerGrowsWhileWalkingIsSeededAndClearsOnANewDirection) {
  PersonMotionConfig c;
  c.veer_sigma = 0.05;
  const auto walk = [&c](std::uint64_t seed) {
    PersonMotion body(c, Vec2::Zero(), 0.0, seed);
    MotionCommand cmd;
    cmd.speed_mps = 1.0;
    for (int k = 0; k < 2000; ++k) body.step(cmd, 0.005);
    return body;
  };
  const PersonMotion a = walk(3), b = walk(3), d = walk(4);
  EXPECT_EQ(a.position(), b.position());
  EXPECT_NE(a.veer(), d.veer());
  EXPECT_GT(std::abs(a.veer()) + std::abs(d.veer()), 0.005);
  // Walking with a veer holds a heading off the one meant.
  EXPECT_NEAR(a.heading(), a.veer(), 0.05);
  PersonMotion e = a;
  MotionCommand fresh;
  fresh.speed_mps = 1.0;
  fresh.new_direction = true;
  e.step(fresh, 0.005);
  EXPECT_LT(std::abs(e.veer()), 0.01);
  // Standing still, the veer does not grow.
  PersonMotion f(c, Vec2::Zero(), 0.0, 9);
  for (int k = 0; k < 2000; ++k) f.step(MotionCommand{}, 0.005);
  EXPECT_EQ(f.veer(), 0.0);
}

TEST(PersonMotion, RejectsBadInput) {
  PersonMotionConfig c;
  c.step_length_m = 0;
  EXPECT_THROW(PersonMotion(c, Vec2::Zero(), 0, 1), ConfigError);
  PersonMotion body(PersonMotionConfig{}, Vec2::Zero(), 0, 1);
  EXPECT_THROW(body.step(MotionCommand{}, 0.0), std::invalid_argument);
  MotionCommand back;
  back.speed_mps = -1;
  EXPECT_THROW(body.step(back, 0.01), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::simulation
