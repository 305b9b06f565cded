// The zero-velocity update: its residual, its Jacobian and its arguments.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/zero_velocity_factor.hpp"

using namespace navaid;
using namespace navaid::estimation;
using namespace navaid::estimation::testing;

TEST(ZeroVelocityFactor, WhitensTheVelocityAndTheGyroBiasAgainstTheStillMeanAndIgnoresTheAccelBias) {
  const ZeroVelocityFactor f(0.01, Vec3(0.002, 0.02, 0.077), Vec3(0.001, 0.002, 0.004));
  double speed_bias[9] = {0.02, -0.01, 0.005, 0.003, 0.02, 0.069, 1.0, 1.0, 1.0};
  const double* p[] = {speed_bias};
  double r[6];
  ASSERT_TRUE(f.Evaluate(p, r, nullptr));
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_NEAR(r[1], -1.0, 1e-12);
  EXPECT_NEAR(r[2], 0.5, 1e-12);
  EXPECT_NEAR(r[3], 1.0, 1e-12);
  EXPECT_NEAR(r[4], 0.0, 1e-12);
  EXPECT_NEAR(r[5], -2.0, 1e-9);
  std::mt19937_64 rng(7);
  const Vec3 v = random_vector(rng, 1.0), b = random_vector(rng, 0.1);
  double x[9] = {v.x(), v.y(), v.z(), b.x(), b.y(), b.z(), -b.x(), b.z(), b.y()};
  const ZeroVelocityFactor g(0.02, random_vector(rng, 0.1), Vec3(0.003, 0.001, 0.002));
  EXPECT_TRUE(jacobians_match(g, {x}, {nullptr}));
}

TEST(ZeroVelocityFactor, RejectsSigmasThatAreNotPositive) {
  const Vec3 s(0.001, 0.001, 0.001);
  EXPECT_THROW(ZeroVelocityFactor(0.0, Vec3::Zero(), s), Error);
  EXPECT_THROW(ZeroVelocityFactor(-0.01, Vec3::Zero(), s), Error);
  EXPECT_THROW(ZeroVelocityFactor(NAN, Vec3::Zero(), s), Error);
  EXPECT_THROW(ZeroVelocityFactor(0.01, Vec3::Zero(), Vec3(0.001, 0.0, 0.001)), Error);
  EXPECT_THROW(ZeroVelocityFactor(0.01, Vec3(NAN, 0, 0), s), Error);
}
