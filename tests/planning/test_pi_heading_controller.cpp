// The Smart Cane's PI heading controller (eq. 1) with known answers, and in closed loop with a
// user who turns at the commanded rate: the heading settles on the reference without a steady
// error.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/pi_heading_controller.hpp"

namespace navaid::planning {
namespace {

TEST(PiHeading, Equation1KnownAnswers) {
  PiHeadingConfig c;
  c.kp = 0.4;
  c.ki = 0.03;
  PiHeadingController pi(c);
  EXPECT_NEAR(pi.update(0, 0.5), 0.4 * 0.5, 1e-12);  // the first step has no integral yet
  // 0.1 s later with error 0.5: integral 0.05 rad s.
  EXPECT_NEAR(pi.update(seconds_to_ns(0.1), 0.5), 0.4 * 0.5 + 0.03 * 0.05, 1e-12);
  EXPECT_NEAR(pi.update(seconds_to_ns(0.2), -0.2), 0.4 * -0.2 + 0.03 * (0.05 - 0.02), 1e-12);
  EXPECT_NEAR(pi.integral(), 0.03, 1e-12);
}

TEST(PiHeading, ErrorIsWrappedAcrossTheSeam) {
  PiHeadingController pi;
  // theta_ref = 179 deg, theta = -179 deg: the error is -2 deg, not 358 deg.
  EXPECT_NEAR(pi.update(0, deg_to_rad(179.0) - deg_to_rad(-179.0)), 0.4 * deg_to_rad(-2.0), 1e-12);
}

TEST(PiHeading, AntiWindupAndOutputLimit) {
  PiHeadingConfig c;
  c.integral_limit_rad_s = 0.5;
  c.output_limit = 0.6;
  PiHeadingController pi(c);
  for (int i = 0; i <= 100; ++i) pi.update(seconds_to_ns(0.1 * i), 1.0);  // 10 s of a 1 rad error
  EXPECT_NEAR(pi.integral(), 0.5, 1e-12);
  EXPECT_NEAR(pi.update(seconds_to_ns(10.1), 3.0), 0.6, 1e-12);
  // A gap longer than max_dt restarts the integral.
  pi.update(seconds_to_ns(20.0), 0.1);
  EXPECT_DOUBLE_EQ(pi.integral(), 0.0);
}

TEST(PiHeading, ClosedLoopSettlesWithoutSteadyError) {
  // The user turns at rate gain x v [rad/s] and drifts 0.05 rad/s to the left (a constant
  // disturbance a P controller alone would leave an error for).
  PiHeadingConfig c;
  c.kp = 0.4;
  c.ki = 0.04;
  PiHeadingController pi(c);
  double theta = 0.0;
  const double ref = 1.0;
  const double dt = 0.1;
  for (int i = 0; i < 1200; ++i) {
    const double v = pi.update(seconds_to_ns(dt * i), ref - theta);
    theta += dt * (2.0 * v + 0.05);
  }
  EXPECT_NEAR(theta, ref, 1e-3);
  // P alone keeps an offset of drift / (gain kp) = 0.05 / 0.8.
  c.ki = 0.0;
  PiHeadingController p_only(c);
  theta = 0.0;
  for (int i = 0; i < 1200; ++i) theta += dt * (2.0 * p_only.update(seconds_to_ns(dt * i), ref - theta) + 0.05);
  EXPECT_NEAR(theta - ref, 0.05 / 0.8, 1e-3);
}

TEST(PiHeading, Keys) {
  const PiHeadingConfig c = read_pi_heading_config(Config::parse("{}", "<t>", {"planning.pi.kp=0.3", "planning.pi.ki=0.02"}));
  EXPECT_DOUBLE_EQ(c.kp, 0.3);
  EXPECT_DOUBLE_EQ(c.ki, 0.02);
  EXPECT_THROW(read_pi_heading_config(Config::parse("{}", "<t>", {"planning.pi.kp=-1"})), ConfigError);
}

}  // namespace
}  // namespace navaid::planning
