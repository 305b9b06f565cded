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

TEST(ZeroVelocityFactor, WhitensTheVelocityAndIgnoresTheBiases) {
  const ZeroVelocityFactor f(0.01);
  double speed_bias[9] = {0.02, -0.01, 0.005, 0.3, 0.3, 0.3, 1.0, 1.0, 1.0};
  const double* p[] = {speed_bias};
  double r[3];
  ASSERT_TRUE(f.Evaluate(p, r, nullptr));
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_NEAR(r[1], -1.0, 1e-12);
  EXPECT_NEAR(r[2], 0.5, 1e-12);
  std::mt19937_64 rng(7);
  const Vec3 v = random_vector(rng, 1.0), b = random_vector(rng, 0.1);
  double x[9] = {v.x(), v.y(), v.z(), b.x(), b.y(), b.z(), -b.x(), b.z(), b.y()};
  EXPECT_TRUE(jacobians_match(f, {x}, {nullptr}));
}

TEST(ZeroVelocityFactor, RejectsASigmaThatIsNotPositive) {
  EXPECT_THROW(ZeroVelocityFactor(0.0), Error);
  EXPECT_THROW(ZeroVelocityFactor(-0.01), Error);
  EXPECT_THROW(ZeroVelocityFactor(NAN), Error);
}
